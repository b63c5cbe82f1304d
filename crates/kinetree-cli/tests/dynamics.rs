//! End-to-end tests of `kinetree dynamics`, `simulate` and `bench`: hand-worked torques, energy,
//! joint dynamics, limits and the benchmark's keys.

mod common;

use common::*;
use kinetree_test_support::assert_close;
use std::path::Path;

#[test]
fn joint_dynamics_are_opt_in_for_compute_and_dynamics() {
    // A damped pendulum (d = 2 N·m·s/rad, μ = 0.5 N·m) about y, its 1 kg bob 0.5 m along x. At rest
    // gravity needs τ = -4.905 N·m; at v = 1 rad/s the joint terms add d·v + μ = 2.5 N·m.
    let dir = scratch("joint-dynamics");
    let urdf = dir.join("pendulum.urdf");
    std::fs::write(&urdf, r#"<robot name="p"><link name="base"/>
      <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
        <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/>
        <dynamics damping="2" friction="0.5"/></joint>
    </robot>"#).unwrap();
    let tau = |extra: &[&str]| -> f64 {
        let mut args = vec![
            "dynamics",
            urdf.to_str().unwrap(),
            "--v",
            "hinge=1",
            "--a",
            "hinge=0",
        ];
        args.extend(extra);
        let o = kinetree(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = format!("\n{}", stdout(&o));
        row(section(&text, "tau"), "hinge")[1].parse().unwrap()
    };
    assert_close!(tau(&[]), -4.905, 1e-9);
    assert_close!(tau(&["--ignore-joint-dynamics"]), -4.905, 1e-9);
    assert!((tau(&["--joint-dynamics"]) + 4.905 - 2.5).abs() < 1e-9);
    let states = dir.join("states.json");
    std::fs::write(
        &states,
        r#"{"samples": [{"q": {"hinge": 0}, "v": {"hinge": 1}, "a": {"hinge": 0}}]}"#,
    )
    .unwrap();
    let rnea = |extra: &[&str]| -> f64 {
        let mut args = vec![
            "compute",
            urdf.to_str().unwrap(),
            "--states",
            states.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = kinetree(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let out: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
        out["samples"][0]["rnea"][0].as_f64().unwrap()
    };
    assert_close!(rnea(&[]), -4.905, 1e-9);
    assert!((rnea(&["--joint-dynamics"]) + 4.905 - 2.5).abs() < 1e-9);
}

#[test]
fn simulate_uses_joint_dynamics_by_default_and_says_so() {
    // The reference double pendulum has joint damping: by default a simulation loses energy and
    // prints that the joint terms are on; --no-joint-dynamics conserves it and says they are off.
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/reference/urdf/double_pendulum.urdf");
    let run = |extra: &[&str]| -> (String, f64) {
        let mut args = vec![
            "simulate",
            urdf.to_str().unwrap(),
            "--q",
            "joint1=0.3",
            "--v",
            "joint1=2",
            "--duration",
            "0.5",
        ];
        args.extend(extra);
        let o = kinetree(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = stdout(&o);
        let change: f64 = text
            .split("(change ")
            .nth(1)
            .and_then(|r| r.split(" J").next())
            .and_then(|x| x.trim().parse().ok())
            .unwrap_or_else(|| panic!("no energy line in {text}"));
        (text, change)
    };
    let (text, change) = run(&[]);
    assert!(
        text.contains("joint damping, friction and armature: on"),
        "{text}"
    );
    assert!(change < -1e-6, "{text}");
    let (text, change) = run(&["--no-joint-dynamics"]);
    assert!(
        text.contains("joint damping, friction and armature: off"),
        "{text}"
    );
    assert!(change.abs() < 1e-6, "{text}");
}

#[test]
fn bench_aligns_its_table_for_long_names() {
    let o = kinetree(&["bench", &panda(), "--calls", "20", "--repetitions", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    // Every timing line ends its number at the same column, the longest name included.
    let rows: Vec<&str> = text.lines().filter(|l| l.starts_with("  ")).collect();
    assert!(
        rows.iter()
            .any(|l| l.contains("joint_jacobians_without_links")),
        "{text}"
    );
    assert!(rows.len() >= 12, "{text}");
    assert!(
        rows.iter()
            .all(|l| l.chars().count() == rows[0].chars().count()),
        "{text}"
    );
}

#[test]
fn bench_prints_stable_json_keys() {
    let o = kinetree(&[
        "bench",
        &panda(),
        "--calls",
        "200",
        "--repetitions",
        "1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(v["nq"], 9);
    for key in [
        "fk",
        "fk_frames",
        "frame_jacobian",
        "joint_jacobians",
        "joint_jacobians_without_links",
        "rnea",
        "nle",
        "crba",
        "aba",
        "minv",
    ] {
        assert!(
            v["ns_per_call"][key].as_f64().is_some_and(|x| x > 0.0),
            "{key}"
        );
    }
    // The like-for-like cases again, under the names of Pinocchio's anchor benchmark.
    for (ours, theirs) in [
        ("fk_frames", "fk+frames"),
        ("joint_jacobians_without_links", "jacobians"),
        ("rnea", "rnea"),
        ("nle", "nle"),
        ("crba", "crba"),
        ("aba", "aba"),
        ("minv", "minverse"),
        ("rnea_derivatives", "rnea_derivatives"),
        ("aba_derivatives", "aba_derivatives"),
    ] {
        assert_eq!(
            v["pinocchio_ns_per_call"][theirs], v["ns_per_call"][ours],
            "{theirs}"
        );
    }
    assert_eq!(v["pinocchio_ns_per_call"].as_object().unwrap().len(), 9);
}

#[test]
fn bench_batch_times_collision_distances() {
    let run = |model: &str| {
        let o = kinetree(&[
            "bench",
            model,
            "--batch",
            "4",
            "--calls",
            "40",
            "--repetitions",
            "1",
            "--threads",
            "2",
            "--json",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_str::<serde_json::Value>(stdout(&o).trim()).unwrap()["ns_per_state"]
            .clone()
    };
    let rows = run(&data("reference/urdf/panda_collision.urdf"));
    for name in [
        "fk_matrices",
        "collision_distances",
        "rnea_derivatives",
        "aba_derivatives",
    ] {
        let row = &rows[name];
        for key in ["single", "batched", "parallel"] {
            assert!(
                row[key].as_f64().is_some_and(|x| x > 0.0),
                "{name} {key}: {row}"
            );
        }
    }
}

#[test]
fn dynamics_prints_torques_that_aba_inverts() {
    // A pendulum about y with its 1 kg bob 0.5 m along x: gravity pulls with +m·g·l = 4.905 N·m
    // about y, so holding it at rest takes τ = -4.905 N·m, and that torque gives zero acceleration.
    let dir = scratch("dynamics");
    let urdf = dir.join("pendulum.urdf");
    std::fs::write(&urdf, r#"<robot name="p"><link name="base"/>
      <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
        <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
    </robot>"#).unwrap();
    let o = kinetree(&[
        "dynamics",
        urdf.to_str().unwrap(),
        "--a",
        "hinge=0",
        "--tau",
        "hinge=-4.905",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = format!("\n{}", stdout(&o));
    let tau = section(&text, "tau");
    assert!(
        (row(tau, "hinge")[1].parse::<f64>().unwrap() + 4.905).abs() < 1e-6,
        "{text}"
    );
    let ddq = section(&text, "ddq");
    assert!(
        row(ddq, "hinge")[1].parse::<f64>().unwrap().abs() < 1e-6,
        "{text}"
    );
    // M = m·l² = 0.25 kg·m².
    assert!(text.contains("0.25000"), "{text}");
    let o = kinetree(&[
        "dynamics",
        urdf.to_str().unwrap(),
        "--q",
        "elbow=1",
        "--a",
        "hinge=0",
    ]);
    assert!(!o.status.success() && stderr(&o).contains("elbow"));
}

#[test]
fn simulate_conserves_energy_and_writes_a_plot() {
    let dir = scratch("simulate");
    let plot = dir.join("energy.svg");
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/reference/urdf/double_pendulum.urdf");
    let o = kinetree(&[
        "simulate",
        urdf.to_str().unwrap(),
        "--q",
        "joint1=0.3",
        "--duration",
        "1",
        "--dt",
        "1e-3",
        "--no-joint-dynamics",
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let relative: f64 = text
        .split("relative ")
        .nth(1)
        .and_then(|r| r.trim_end_matches([')', '\n']).split(')').next())
        .and_then(|x| x.trim().parse().ok())
        .unwrap_or_else(|| panic!("no energy line in {text}"));
    assert!(relative.abs() < 1e-6, "{text}");
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("joint1") && svg.contains("mechanical energy"));
}

#[test]
fn simulate_reports_limit_violations_and_stops_at_the_limits() {
    // A pendulum with limits [-1, 1] rad thrown from 0.9 rad at 5 rad/s passes its upper limit
    // within 0.03 s (gravity cannot stop ½·0.25·5² = 3.1 J in 0.1 rad).
    let dir = scratch("limits");
    let urdf = dir.join("pendulum.urdf");
    std::fs::write(&urdf, r#"<robot name="p"><link name="base"/>
      <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
        <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="hinge" type="revolute"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"#).unwrap();
    let run = |extra: &[&str]| -> String {
        let mut args = vec![
            "simulate",
            urdf.to_str().unwrap(),
            "--q",
            "hinge=0.9",
            "--v",
            "hinge=5",
            "--duration",
            "0.2",
        ];
        args.extend(extra);
        let o = kinetree(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    let text = run(&[]);
    assert!(
        text.contains("1 of 1 limited coordinates left their limits"),
        "{text}"
    );
    let line = row(&text, "hinge");
    assert_eq!(line[1..3], ["limits", "[-1,"], "{text}");
    let text = run(&["--joint-limits", "stop"]);
    assert!(
        text.contains("1 of 1 limited coordinates reached a stop"),
        "{text}"
    );
    let dissipated: f64 = text
        .split("reached a stop, ")
        .nth(1)
        .and_then(|r| r.split(" J").next())
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("{text}"));
    assert!(dissipated > 0.1, "{text}");
    let q: f64 = section(&format!("\n{text}"), "final q:")
        .lines()
        .find(|l| l.trim_start().starts_with("hinge"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("{text}"));
    assert!((-1.0..=1.0).contains(&q), "{text}");
    let o = kinetree(&[
        "simulate",
        urdf.to_str().unwrap(),
        "--joint-limits",
        "bounce",
    ]);
    assert!(!o.status.success() && stderr(&o).contains("bounce"));
}

#[test]
fn simulate_writes_every_joint_that_owns_coordinates_mimic_followers_included() {
    // The Panda's second finger mimics the first; loaded independent (the default) it owns its
    // coordinate, which the trajectory dropped (so `view --trajectory` played it at neutral).
    let dir = scratch("simulate_mimic");
    let out = dir.join("trajectory.json");
    let o = kinetree(&[
        "simulate",
        &panda(),
        "--duration",
        "0.01",
        "--dt",
        "1e-3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let first = &doc["trajectory"][0]["q"];
    let names: Vec<&str> = first
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    assert_eq!(names.len(), 9, "{names:?}");
    assert!(
        names.contains(&"panda_finger_joint2") && names.contains(&"panda_finger_joint1"),
        "{names:?}"
    );
}
