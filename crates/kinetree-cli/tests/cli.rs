//! End-to-end tests of the `kinetree` binary: run it as a user would and read what it prints.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn kinetree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .args(args)
        .output()
        .expect("the kinetree binary runs")
}

fn panda() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/robots/panda.urdf")
        .display()
        .to_string()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The line of `text` that starts (after indentation) with `first_word`, split into words.
fn row<'a>(text: &'a str, first_word: &str) -> Vec<&'a str> {
    text.lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .find(|w| w.first() == Some(&first_word))
        .unwrap_or_else(|| panic!("no line starting with {first_word} in:\n{text}"))
}

/// The part of the report from the line starting with `header` to the next blank line.
fn section<'a>(text: &'a str, header: &str) -> &'a str {
    let start = text
        .find(&format!("\n{header}"))
        .unwrap_or_else(|| panic!("no section {header} in:\n{text}"));
    let rest = &text[start + 1..];
    rest.find("\n\n").map_or(rest, |end| &rest[..end])
}

/// A scratch folder for this test process, removed by the caller.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kinetree-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn inspect_prints_the_panda() {
    let out = kinetree(&["inspect", &panda()]);
    let text = stdout(&out);
    assert!(out.status.success(), "stderr: {}", stderr(&out));
    assert!(text.starts_with("panda (nq = 9, nv = 9)\n"), "{text}");
    assert!(text.contains("nq = 9, nv = 9; 13 links, 12 joints (9 moving), 10 bodies"));
    // The tree: the hand carries both fingers.
    assert!(
        text.contains(
            "\n                      panda_leftfinger <- panda_finger_joint1 (prismatic)\n"
        )
    );
    // Joint table: name, type, parent → child, axis, lower, upper, velocity, effort, idx_q, idx_v.
    assert_eq!(
        row(section(&text, "joints"), "panda_joint4"),
        [
            "panda_joint4",
            "revolute",
            "panda_link3",
            "→",
            "panda_link4",
            "[0,",
            "0,",
            "1]",
            "-3.0718",
            "-0.0698",
            "2.175",
            "87",
            "3",
            "3"
        ]
    );
    assert_eq!(
        row(section(&text, "joints"), "panda_finger_joint2")[5..],
        ["[0,", "-1,", "0]", "0", "0.04", "0.2", "100", "8", "8"]
    );
    assert_eq!(
        row(section(&text, "joints"), "panda_hand_joint")[1..],
        [
            "fixed",
            "panda_link8",
            "→",
            "panda_hand",
            "-",
            "-",
            "-",
            "-",
            "-",
            "-",
            "-"
        ]
    );
    // Masses: per link and in total (sum of the URDF's masses).
    assert_eq!(row(section(&text, "links"), "panda_link1")[1], "4.970684");
    assert!(text.contains("total mass: 17.451901 kg"), "{text}");
    assert!(text.contains("ignored elements (7, not modelled by kinetree)"));
    assert!(text.contains("warnings (0):\n  none\n"));
}

#[test]
fn inspect_and_compute_read_a_dh_table() {
    // A planar 2R arm as a DH table in mm/deg: links 0.3 m and 0.2 m, a tool 0.05 m further.
    let dir = scratch("dh");
    let table = dir.join("arm.dh.json");
    std::fs::write(
        &table,
        r#"{"name": "planar", "convention": "standard", "units": {"length": "mm", "angle": "deg"},
            "dh": [{"a": 300, "joint": "shoulder", "limits": {"lower": -90, "upper": 90}},
                   {"a": 200, "joint": "elbow"}],
            "tool": {"xyz": [50, 0, 0]}}"#,
    )
    .unwrap();
    let o = kinetree(&["inspect", table.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.starts_with("planar (nq = 2, nv = 2)"), "{text}");
    assert_eq!(
        row(section(&text, "joints"), "shoulder")[8..10],
        ["-1.570796", "1.570796"]
    );
    assert_eq!(row(section(&text, "frames"), "tool")[2], "[0.25,");
    // At shoulder = 90°, elbow = -90° the elbow sits at (0, 0.3, 0) and the hand points along x.
    let states = dir.join("states.json");
    std::fs::write(
        &states,
        r#"{"samples": [{"q": {"shoulder": 1.5707963267948966, "elbow": -1.5707963267948966}}]}"#,
    )
    .unwrap();
    let o = kinetree(&[
        "compute",
        table.to_str().unwrap(),
        "--states",
        states.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let elbow = flat(&out["samples"][0]["link_poses"]["link2"]["translation"]);
    assert!(
        elbow[0].abs() < 1e-12 && (elbow[1] - 0.3).abs() < 1e-12 && elbow[2].abs() < 1e-12,
        "{elbow:?}"
    );
}

#[test]
fn inspect_floating_adds_the_root_joint() {
    let out = kinetree(&["inspect", "--floating", &panda()]);
    let text = stdout(&out);
    assert!(out.status.success(), "stderr: {}", stderr(&out));
    assert!(text.starts_with("panda (nq = 16, nv = 15)\n"), "{text}");
    assert_eq!(
        row(section(&text, "joints"), "root_joint"),
        [
            "root_joint",
            "floating",
            "world",
            "→",
            "panda_link0",
            "-",
            "-",
            "-",
            "inf",
            "inf",
            "0",
            "0"
        ]
    );
    // The arm's blocks move down by the floating joint's 7/6.
    assert_eq!(
        row(section(&text, "joints"), "panda_joint1")[12..],
        ["7", "6"]
    );
}

#[test]
fn a_malformed_file_fails_with_its_name_and_no_panic() {
    let dir = scratch("malformed");
    let file = dir.join("broken_robot.urdf");
    std::fs::write(&file, "<robot name=\"broken\"><link name=\"a\">").unwrap();
    let out = kinetree(&["inspect", &file.display().to_string()]);
    std::fs::remove_dir_all(&dir).unwrap();
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "stderr: {err}");
    assert!(err.starts_with("error: cannot load "), "{err}");
    assert!(err.contains("broken_robot.urdf"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(stdout(&out).is_empty());
}

#[test]
fn an_invalid_tree_names_the_joint() {
    let dir = scratch("invalid");
    let file = dir.join("dangling.urdf");
    std::fs::write(
        &file,
        r#"<robot name="dangling"><link name="a"/>
           <joint name="j1" type="revolute"><parent link="a"/><child link="nowhere"/></joint>
           </robot>"#,
    )
    .unwrap();
    let out = kinetree(&["inspect", &file.display().to_string()]);
    std::fs::remove_dir_all(&dir).unwrap();
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "stderr: {err}");
    assert!(err.contains("dangling.urdf"), "{err}");
    assert!(err.contains("'j1'") && err.contains("'nowhere'"), "{err}");
}

#[test]
fn a_missing_file_or_unknown_format_is_an_error() {
    let out = kinetree(&["inspect", "no/such/robot.urdf"]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(err.contains("no/such/robot.urdf"), "{err}");
    // The OS message appears once, not repeated by the error chain.
    assert_eq!(err.matches("os error").count(), 1, "{err}");

    let out = kinetree(&["inspect", "robot.step"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("robot.step"), "{}", stderr(&out));
}

#[test]
fn convert_urdf_to_json_and_back_keeps_the_model() {
    let dir = scratch("convert");
    let json = dir.join("panda.json").display().to_string();
    let urdf = dir.join("panda_again.urdf").display().to_string();
    let mm = dir.join("panda_mm.json").display().to_string();

    let out = kinetree(&["convert", &panda(), &json]);
    assert!(out.status.success(), "stderr: {}", stderr(&out));
    assert_eq!(
        stdout(&out),
        format!("wrote {json} (JSON): 13 links, 12 joints, nq = 9, nv = 9\n")
    );
    let out = kinetree(&["convert", &json, &urdf]);
    assert!(out.status.success(), "stderr: {}", stderr(&out));
    let out = kinetree(&["convert", "--units", "mm-deg", &panda(), &mm]);
    assert!(out.status.success(), "stderr: {}", stderr(&out));
    let mm_text = std::fs::read_to_string(&mm).unwrap();

    let original = stdout(&kinetree(&["inspect", &panda()]));
    let reports: Vec<String> = [&json, &urdf, &mm]
        .iter()
        .map(|f| stdout(&kinetree(&["inspect", f])))
        .collect();
    std::fs::remove_dir_all(&dir).unwrap();

    assert!(mm_text.contains("\"length\": \"mm\""), "{mm_text}");
    assert!(mm_text.contains("\"angle\": \"deg\""), "{mm_text}");
    // panda_joint1's lower limit, -2.8973 rad, in degrees.
    assert!(mm_text.contains("-166.0030619832"), "{mm_text}");
    // Every format reads back to the same tree, joint table and masses.
    for report in &reports {
        assert!(report.starts_with("panda (nq = 9, nv = 9)\n"), "{report}");
        for header in ["joints", "links"] {
            assert_eq!(section(report, header), section(&original, header));
        }
    }
}

#[test]
fn convert_refuses_what_it_cannot_write() {
    let out = kinetree(&["convert", &panda(), "panda.step"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("panda.step"), "{}", stderr(&out));
    assert!(stderr(&out).contains(".urdf or .json"), "{}", stderr(&out));

    let out = kinetree(&["convert", "--units", "mm-deg", &panda(), "x.urdf"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("JSON output only"),
        "{}",
        stderr(&out)
    );

    let out = kinetree(&["convert", "missing.json", "x.urdf"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("missing.json"), "{}", stderr(&out));
}

#[test]
fn convert_notes_what_urdf_cannot_hold() {
    let dir = scratch("floating");
    let urdf = dir.join("floating.urdf").display().to_string();
    let out = kinetree(&["convert", "--floating", &panda(), &urdf]);
    let written = std::fs::read_to_string(&urdf);
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(out.status.success(), "stderr: {}", stderr(&out));
    assert!(
        stdout(&out).contains("note: the floating root joint is not written"),
        "{}",
        stdout(&out)
    );
    assert!(!written.unwrap().contains("root_joint"));
}

#[test]
fn compute_takes_every_reference_file_straight_in() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/reference");
    for robot in [
        "double_pendulum",
        "ur5",
        "kinova",
        "panda",
        "panda_collision",
        "solo12",
        "talos_reduced",
    ] {
        let states = dir.join(format!("{robot}.json"));
        let reference: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&states).unwrap()).unwrap();
        let urdf = dir.join(reference["urdf"].as_str().unwrap());
        let out = scratch(&format!("compute-{robot}")).join("result.json");
        let link = reference["jacobian_links"][0].as_str().unwrap();
        let mut args = vec![
            "compute",
            urdf.to_str().unwrap(),
            "--states",
            states.to_str().unwrap(),
        ];
        args.extend(["--jacobians", link, "--out", out.to_str().unwrap()]);
        if reference["root_joint"] != "fixed" {
            args.push("--floating");
        }
        let o = kinetree(&args);
        assert!(o.status.success(), "{robot}: {}", stderr(&o));
        let result: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(result["model"]["nv"], reference["nv"], "{robot}");
        let samples = result["samples"].as_array().unwrap();
        assert_eq!(
            samples.len(),
            reference["samples"].as_array().unwrap().len(),
            "{robot}"
        );
        // Every link pose of the last sample agrees with Pinocchio's.
        let (ours, theirs) = (
            &samples[samples.len() - 1],
            &reference["samples"][samples.len() - 1],
        );
        for (name, pose) in theirs["link_poses"].as_object().unwrap() {
            for i in 0..3 {
                let d = ours["link_poses"][name]["translation"][i].as_f64().unwrap()
                    - pose["translation"][i].as_f64().unwrap();
                assert!(d.abs() < 1e-9, "{robot}/{name}");
            }
        }
        assert_eq!(ours["jacobians"][link].as_array().unwrap().len(), 6);
        // Without any flag the dynamics are Pinocchio's (every reference URDF has <dynamics>
        // damping or friction, which Pinocchio leaves out), for every sample.
        // Our v index of each of Pinocchio's (the joint orders may differ).
        let mut ours_of = vec![0; samples[0]["rnea"].as_array().unwrap().len()];
        for j in reference["joints"].as_array().unwrap() {
            let mine = result["model"]["joints"]
                .as_array()
                .unwrap()
                .iter()
                .find(|m| m["name"] == j["name"])
                .unwrap();
            for k in 0..j["nv"].as_u64().unwrap() as usize {
                ours_of[j["idx_v"].as_u64().unwrap() as usize + k] =
                    mine["idx_v"].as_u64().unwrap() as usize + k;
            }
        }
        for (ours, theirs) in samples.iter().zip(reference["samples"].as_array().unwrap()) {
            let m = &ours["mass_matrix"];
            let permuted: Vec<Vec<f64>> = ours_of
                .iter()
                .map(|&r| ours_of.iter().map(|&c| m[r][c].as_f64().unwrap()).collect())
                .collect();
            let d = max_difference(&serde_json::json!(permuted), &theirs["mass_matrix"]);
            assert!(
                d <= 1e-9 * (1.0 + max_abs(&theirs["mass_matrix"])),
                "{robot}: M"
            );
            for key in ["rnea", "nle", "gravity_torque", "aba"] {
                let scale = 1.0 + max_abs(&theirs[key]);
                let permuted: Vec<f64> = ours_of
                    .iter()
                    .map(|&k| ours[key][k].as_f64().unwrap())
                    .collect();
                let d = max_difference(&serde_json::json!(permuted), &theirs[key]);
                let tol = if key == "aba" {
                    1e-9 * theirs["mass_matrix_cond"].as_f64().unwrap()
                } else {
                    1e-9
                };
                assert!(d <= tol * scale, "{robot}: {key} differs by {d:e}");
            }
        }
    }
}

/// Every number of a JSON value (nested arrays flattened).
fn flat(value: &serde_json::Value) -> Vec<f64> {
    match value {
        serde_json::Value::Array(a) => a.iter().flat_map(flat).collect(),
        v => vec![v.as_f64().unwrap_or(f64::NAN)],
    }
}

fn max_abs(value: &serde_json::Value) -> f64 {
    flat(value).iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// The largest difference of two equally shaped JSON arrays (NaN when shapes differ).
fn max_difference(a: &serde_json::Value, b: &serde_json::Value) -> f64 {
    let (a, b) = (flat(a), flat(b));
    if a.len() != b.len() {
        return f64::NAN;
    }
    a.iter().zip(&b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn compute_derivatives_match_pinocchio() {
    // Pinocchio 4.1's computeRNEADerivatives / computeGeneralizedGravityDerivatives /
    // computeABADerivatives on a fixed base (panda) and a floating base (solo12); the reference
    // file is the request itself (its samples wrap q, v, a, tau in "state").
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/reference");
    for robot in ["panda", "solo12"] {
        let states = dir.join(format!("derivatives/{robot}.json"));
        let reference: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&states).unwrap()).unwrap();
        let main: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(format!("{robot}.json"))).unwrap(),
        )
        .unwrap();
        let urdf = dir
            .join("derivatives")
            .join(reference["urdf"].as_str().unwrap());
        let out = scratch(&format!("derivatives-{robot}")).join("result.json");
        let mut args = vec![
            "compute",
            urdf.to_str().unwrap(),
            "--states",
            states.to_str().unwrap(),
            "--derivatives",
            "--out",
            out.to_str().unwrap(),
        ];
        if reference["root_joint"] != "fixed" {
            args.push("--floating");
        }
        let o = kinetree(&args);
        assert!(o.status.success(), "{robot}: {}", stderr(&o));
        let result: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        // Our v index of each of Pinocchio's.
        let nv = result["model"]["nv"].as_u64().unwrap() as usize;
        let mut ours_of = vec![usize::MAX; nv];
        for j in reference["joints"].as_array().unwrap() {
            let mine = result["model"]["joints"]
                .as_array()
                .unwrap()
                .iter()
                .find(|m| m["name"] == j["name"])
                .unwrap();
            for k in 0..j["nv"].as_u64().unwrap() as usize {
                ours_of[j["idx_v"].as_u64().unwrap() as usize + k] =
                    mine["idx_v"].as_u64().unwrap() as usize + k;
            }
        }
        assert!(ours_of.iter().all(|&k| k < nv), "{robot}");
        let samples = result["samples"].as_array().unwrap();
        let expected = reference["samples"].as_array().unwrap();
        assert_eq!(samples.len(), expected.len(), "{robot}");
        let mut compared = 0;
        for (i, (ours, theirs)) in samples.iter().zip(expected).enumerate() {
            let cond = main["samples"][i]["mass_matrix_cond"].as_f64().unwrap();
            for (group, keys) in [
                ("rnea", &["dtau_dq", "dtau_dv", "dtau_da"]),
                ("gravity", &["dg_dq", "dg_dq", "dg_dq"]),
                ("aba", &["dddq_dq", "dddq_dv", "dddq_dtau"]),
            ] {
                if theirs[group].is_null() {
                    assert!(ours["derivatives"][group].is_null(), "{robot} {i} {group}");
                    continue;
                }
                for key in keys {
                    let m = &ours["derivatives"][group][key];
                    let permuted: Vec<Vec<f64>> = ours_of
                        .iter()
                        .map(|&r| ours_of.iter().map(|&c| m[r][c].as_f64().unwrap()).collect())
                        .collect();
                    let reference = &theirs[group][key];
                    let d = max_difference(&serde_json::json!(permuted), reference);
                    let tol = if group == "aba" {
                        1e-8 * (cond / 1e3).max(1.0)
                    } else {
                        1e-8
                    };
                    assert!(
                        d <= tol * max_abs(reference).max(1.0),
                        "{robot} sample {i}: {group}.{key} differs by {d:e}"
                    );
                    compared += 1;
                }
            }
        }
        assert!(compared >= 7 * expected.len(), "{robot}: {compared}");
    }
    // --help names every key.
    let help = stdout(&kinetree(&["compute", "--help"]));
    for key in [
        "--derivatives",
        "derivatives",
        "dg_dq",
        "dtau_dq",
        "dtau_dv",
        "dtau_da",
        "dddq_dq",
        "dddq_dv",
        "dddq_dtau",
    ] {
        assert!(help.contains(key), "--help does not mention {key}");
    }
}

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
    assert!((tau(&[]) + 4.905).abs() < 1e-9);
    assert!((tau(&["--ignore-joint-dynamics"]) + 4.905).abs() < 1e-9);
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
    assert!((rnea(&[]) + 4.905).abs() < 1e-9);
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
fn compute_names_a_missing_joint_when_strict_and_an_unknown_joint_always() {
    let states = scratch("compute-bad").join("states.json");
    std::fs::write(&states, r#"{"samples": [{"q": {"panda_joint1": 0.1}}]}"#).unwrap();
    let o = kinetree(&[
        "compute",
        &panda(),
        "--states",
        states.to_str().unwrap(),
        "--strict",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("panda_joint2"), "{}", stderr(&o));
    std::fs::write(&states, r#"{"samples": [{"v": {"panda_joint1": 0.1}}]}"#).unwrap();
    let o = kinetree(&[
        "compute",
        &panda(),
        "--states",
        states.to_str().unwrap(),
        "--strict",
    ]);
    assert!(
        !o.status.success() && stderr(&o).contains("'q'"),
        "{}",
        stderr(&o)
    );
    std::fs::write(&states, r#"{"samples": [{"q": {"elbow": 0.1}}]}"#).unwrap();
    let o = kinetree(&["compute", &panda(), "--states", states.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("elbow"), "{}", stderr(&o));
}

/// Joints left out are neutral (q) or zero (v, a), as in the other commands; names are kept;
/// and `--help` documents every key of the output.
#[test]
fn compute_defaults_omitted_joints_keeps_names_and_documents_every_key() {
    let dir = scratch("compute-defaults");
    let states = dir.join("states.json");
    let neutral = r#"{"panda_joint1": 0.1, "panda_joint2": 0, "panda_joint3": 0, "panda_joint4": 0,
        "panda_joint5": 0, "panda_joint6": 0, "panda_joint7": 0, "panda_finger_joint1": 0,
        "panda_finger_joint2": 0}"#;
    let zero = r#"{"panda_joint1": 0, "panda_joint2": 0, "panda_joint3": 0, "panda_joint4": 0,
        "panda_joint5": 0, "panda_joint6": 0, "panda_joint7": 0, "panda_finger_joint1": 0,
        "panda_finger_joint2": 0}"#;
    std::fs::write(
        &states,
        format!(
            r#"{{"samples": [
            {{"name": "short", "q": {{"panda_joint1": 0.1}}, "v": {{"panda_joint2": 0.5}}, "a": {{}}, "tau": {{}}}},
            {{"name": {{"id": 7}}, "q": {neutral}, "v": {zero}, "a": {zero}, "tau": {zero}}},
            {{"v": {{}}}}
        ]}}"#
        ),
    )
    .unwrap();
    let o = kinetree(&[
        "compute",
        &panda(),
        "--states",
        states.to_str().unwrap(),
        "--jacobians",
        "panda_hand",
        "--collision",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let samples = out["samples"].as_array().unwrap();
    assert_eq!(samples[0]["name"], "short");
    assert_eq!(samples[1]["name"]["id"], 7);
    assert!(samples[2].get("name").is_none());
    // The short sample equals the spelled-out one where their inputs agree (q, a, tau; v differs).
    for key in [
        "link_poses",
        "jacobians",
        "mass_matrix",
        "gravity_torque",
        "com",
    ] {
        assert_eq!(samples[0][key], samples[1][key], "{key}");
    }
    assert_ne!(samples[0]["nle"], samples[1]["nle"]);
    // q left out: the neutral configuration, whose hand sits where the spelled-out sample's
    // does with joint 1 at 0 (a rotation about the base z axis by 0.1 rad).
    let hand = |s: &serde_json::Value| flat(&s["link_poses"]["panda_hand"]["translation"]);
    let (a, b) = (hand(&samples[2]), hand(&samples[1]));
    let r = (a[0] * a[0] + a[1] * a[1]).sqrt();
    assert!((r - (b[0] * b[0] + b[1] * b[1]).sqrt()).abs() < 1e-12 && (a[2] - b[2]).abs() < 1e-12);
    assert!(a[1].abs() < 1e-12 && (b[1] - r * 0.1f64.sin()).abs() < 1e-12);
    // Every key of a sample (and of the model block) is named in --help.
    let help = stdout(&kinetree(&["compute", "--help"]));
    let mut keys: Vec<&String> = samples[1].as_object().unwrap().keys().collect();
    keys.extend(out["model"].as_object().unwrap().keys());
    for key in keys {
        assert!(help.contains(key.as_str()), "--help does not mention {key}");
    }
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
        ("joint_jacobians", "jacobians"),
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
fn collide_reports_hand_computed_distances() {
    // Two unit-radius balls, a on the base and b two joints out (adjacent links are never
    // candidates): centres 3 m apart at q = 0, so the signed distance is 1 m; at slide = -1.5
    // they overlap by 0.5 m. A 0.2 m ball obstacle at x = 5 is 0.8 m from b at q = 0.
    let dir = scratch("collide");
    let urdf = dir.join("balls.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="balls">
      <link name="a"><collision><geometry><sphere radius="1"/></geometry></collision></link>
      <link name="m"/>
      <link name="b"><collision><geometry><sphere radius="1"/></geometry></collision></link>
      <joint name="slide" type="prismatic"><parent link="a"/><child link="m"/><origin xyz="3 0 0"/>
        <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="turn" type="revolute"><parent link="m"/><child link="b"/>
        <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    </robot>"#,
    )
    .unwrap();
    let scene = dir.join("scene.json");
    std::fs::write(&scene, r#"{"obstacles": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.2}, "xyz": [5, 0, 0]}]}"#).unwrap();
    let o = kinetree(&[
        "collide",
        urdf.to_str().unwrap(),
        "--obstacles",
        scene.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = format!("\n{}", stdout(&o));
    assert!(text.contains("self-collisions: 0"), "{text}");
    let closest = section(&text, "closest self pairs");
    assert!(
        (row(closest, "a_0")[2].parse::<f64>().unwrap() - 1.0).abs() < 1e-9,
        "{text}"
    );
    let world = section(&text, "closest world pairs");
    assert!(
        (row(world, "b_0")[2].parse::<f64>().unwrap() - 0.8).abs() < 1e-9,
        "{text}"
    );
    let o = kinetree(&["collide", urdf.to_str().unwrap(), "--q", "slide=-1.5"]);
    let text = format!("\n{}", stdout(&o));
    assert!(text.contains("self-collisions: 1"), "{text}");
    assert!(
        (row(section(&text, "self-collisions"), "a_0")[3]
            .parse::<f64>()
            .unwrap()
            - 0.5)
            .abs()
            < 1e-9,
        "{text}"
    );
}

#[test]
fn ik_solution_places_the_frame_where_compute_finds_it() {
    let o = kinetree(&[
        "ik",
        &panda(),
        "--frame",
        "panda_hand_tcp",
        "--target",
        "0.4,0.2,0.5,3.14159,0,0",
        "--seed",
        "3",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(report["status"], "converged", "{report}");
    assert!(report["position_error"].as_f64().unwrap() < 1e-6);
    // Independent check: forward kinematics of the answer through `kinetree compute`.
    let dir = scratch("ik");
    let states = dir.join("states.json");
    std::fs::write(
        &states,
        serde_json::json!({"samples": [{"q": report["q"]}]}).to_string(),
    )
    .unwrap();
    let o = kinetree(&["compute", &panda(), "--states", states.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let result: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    let pose = &result["samples"][0]["link_poses"]["panda_hand_tcp"];
    for (k, want) in [0.4, 0.2, 0.5].iter().enumerate() {
        assert!(
            (pose["translation"][k].as_f64().unwrap() - want).abs() < 1e-6,
            "{pose}"
        );
    }
    // roll = π about x: the tool's z axis points down.
    assert!(
        (pose["rotation"][2][2].as_f64().unwrap() + 1.0).abs() < 1e-5,
        "{pose}"
    );
    let o = kinetree(&[
        "ik",
        &panda(),
        "--frame",
        "no_such_frame",
        "--target",
        "0,0,0",
        "--position-only",
    ]);
    assert!(!o.status.success() && stderr(&o).contains("no_such_frame"));
}

#[test]
fn collide_finds_the_bundled_panda_meshes_with_no_flag() {
    let out = kinetree(&["collide", &panda()]);
    let text = stdout(&out);
    assert!(out.status.success(), "stderr: {}", stderr(&out));
    // 9 STL meshes and 8 finger boxes, none skipped.
    assert!(text.starts_with("panda: 17 shapes,"), "{text}");
    assert!(!stderr(&out).contains("skipped"), "{}", stderr(&out));
}
