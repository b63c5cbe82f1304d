//! End-to-end tests of the `kinetree` binary on model files: `inspect`, `convert` and how a
//! bad file is reported. Run as a user would and read what it prints.

mod common;

use common::*;

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
fn inspect_and_compute_read_an_mjcf_model_as_mujoco_does() {
    let hopper = data("reference/mjcf/models/gym_hopper/hopper.xml");
    let o = kinetree(&["inspect", &hopper]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.starts_with("hopper (nq = 6, nv = 6)"), "{text}");
    // The torso's three joints chain through massless links at their anchors.
    for joint in ["rootx", "rootz", "rooty", "thigh_joint", "foot_joint"] {
        assert!(
            !row(section(&text, "joints"), joint).is_empty(),
            "{joint}: {text}"
        );
    }
    assert!(text.contains("actuator/motor (×3)"), "{text}");
    // MuJoCo's first reference sample: its qpos, qvel and qacc are kinetree's q, v and a (no
    // free or ball joint), and its bodies' positions and inverse dynamics come back.
    let reference: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(data("reference/mjcf/gym_hopper.json")).unwrap(),
    )
    .unwrap();
    let sample = &reference["samples"][0];
    let named = |key: &str| -> serde_json::Value {
        let values = flat(&sample[key]);
        reference["joints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| {
                (
                    j["name"].as_str().unwrap().to_string(),
                    values[j["qposadr"].as_u64().unwrap() as usize].into(),
                )
            })
            .collect::<serde_json::Map<_, _>>()
            .into()
    };
    let dir = scratch("mjcf");
    let states = dir.join("states.json");
    let request = serde_json::json!({"samples": [{"q": named("qpos"), "v": named("qvel"), "a": named("qacc")}]});
    std::fs::write(&states, request.to_string()).unwrap();
    let o = kinetree(&["compute", &hopper, "--states", states.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let xpos = flat(&sample["xpos"]);
    for (id, body) in ["world", "torso", "thigh", "leg", "foot"]
        .iter()
        .enumerate()
    {
        let p = flat(&out["samples"][0]["link_poses"][body]["translation"]);
        for k in 0..3 {
            assert!((p[k] - xpos[3 * id + k]).abs() < 1e-9, "{body}: {p:?}");
        }
    }
    let tau = &out["samples"][0]["by_joint"]["rnea"];
    let expected = flat(&sample["tau"]);
    for j in reference["joints"].as_array().unwrap() {
        let ours = tau[j["name"].as_str().unwrap()].as_f64().unwrap();
        let theirs = expected[j["dofadr"].as_u64().unwrap() as usize];
        assert!(
            (ours - theirs).abs() < 1e-9 * theirs.abs().max(1.0),
            "{j}: {ours} vs {theirs}"
        );
    }
    // MJCF bodies float by their own free joints: --floating is refused.
    refused(
        &kinetree(&["inspect", &hopper, "--floating"]),
        &["MJCF", "freejoint"],
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
    assert!(
        stderr(&out).contains(".urdf, .xml (MJCF) or .json"),
        "{}",
        stderr(&out)
    );

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
