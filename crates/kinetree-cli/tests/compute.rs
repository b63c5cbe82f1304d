//! End-to-end tests of `kinetree compute`: the reference files straight in, derivatives against
//! Pinocchio, names and defaults.

mod common;

use common::*;
use std::path::Path;

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
