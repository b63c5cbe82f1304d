//! The seed libraries' ways at the command line: yapCAD files, joint values kept through a
//! conversion, millimetres and degrees.

mod common;

use common::kinetree;
use kinetree_test_support::assert_close;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn yapcad(name: &str) -> String {
    common::data(&format!("yapcad/{name}"))
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kinetree-seeds-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn ok(o: &Output) -> String {
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn joint<'a>(doc: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    doc["joints"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["name"] == name)
        .unwrap_or_else(|| panic!("no joint {name}"))
}

#[test]
fn convert_keeps_joint_values_and_writes_world_poses() {
    let out = temp("arm.json");
    let out_s = out.to_str().unwrap();
    ok(&kinetree(&[
        "convert",
        &yapcad("yap_arm.yapcad.json"),
        out_s,
        "--units",
        "mm-deg",
        "--world-poses",
    ]));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    // The exported values, in the file's mm and degrees.
    assert_close!(
        joint(&doc, "j_base")["position"].as_f64().unwrap(),
        30.0,
        1e-9
    );
    assert_close!(
        joint(&doc, "j_grip")["position"].as_f64().unwrap(),
        25.0,
        1e-9
    );
    // The TCP's world pose, as yapCAD exported it: (238.510, 182.020, -53.928) mm.
    let tcp = doc["links"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["name"] == "TCP")
        .unwrap();
    let xyz = &tcp["world_pose"]["xyz"];
    let expected = [
        238.510_222_698_152_66,
        182.019_581_326_063_02,
        -53.928_336_505_207_085,
    ];
    for (k, e) in expected.iter().enumerate() {
        assert_close!(xyz[k].as_f64().unwrap(), e, 1e-9, 0.0, "{xyz}");
    }
    // Export → import keeps the joint values; --positions overrides them (in --units).
    let again = temp("arm2.json");
    ok(&kinetree(&[
        "convert",
        out_s,
        again.to_str().unwrap(),
        "--positions",
        "j_elbow=-10,j_grip=5",
        "--units",
        "mm-deg",
    ]));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&again).unwrap()).unwrap();
    assert_close!(
        joint(&doc, "j_base")["position"].as_f64().unwrap(),
        30.0,
        1e-9
    );
    assert_close!(
        joint(&doc, "j_elbow")["position"].as_f64().unwrap(),
        -10.0,
        1e-9
    );
    assert_close!(
        joint(&doc, "j_grip")["position"].as_f64().unwrap(),
        5.0,
        1e-9
    );
    // Frames attached by parent_frame keep it.
    assert_eq!(joint(&doc, "j_grip")["parent_frame"], "TOOL_FLANGE");
    // URDF holds no state.
    let o = kinetree(&[
        "convert",
        out_s,
        temp("arm.urdf").to_str().unwrap(),
        "--world-poses",
    ]);
    assert!(!o.status.success());
    std::fs::remove_file(&out).unwrap();
}

#[test]
fn a_yapcad_export_is_inspected_as_it_is() {
    let text = ok(&kinetree(&[
        "inspect",
        &yapcad("yap_quickstart.yapcad.json"),
    ]));
    assert!(text.contains("LINK1"), "{text}");
    assert!(text.contains("joint1"), "{text}");
}

fn panda() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/robots/panda.urdf")
        .display()
        .to_string()
}

#[test]
fn units_mm_deg_on_ik_dynamics_and_collide() {
    // ik: the same target in m/rad and in mm/deg gives the same joints, printed in rad and deg.
    let si = ok(&kinetree(&[
        "ik",
        &panda(),
        "--frame",
        "panda_hand_tcp",
        "--target",
        "0.4,0.2,0.5,3.0,0,0",
        "--seed",
        "3",
        "--json",
    ]));
    let mm = ok(&kinetree(&[
        "ik",
        &panda(),
        "--frame",
        "panda_hand_tcp",
        "--target",
        &format!("400,200,500,{},0,0", 3.0f64.to_degrees()),
        "--seed",
        "3",
        "--json",
        "--units",
        "mm-deg",
    ]));
    let si: serde_json::Value = serde_json::from_str(si.trim()).unwrap();
    let mm: serde_json::Value = serde_json::from_str(mm.trim()).unwrap();
    assert_eq!(mm["units"]["angle"], "deg");
    for j in ["panda_joint1", "panda_joint4", "panda_finger_joint1"] {
        let (a, b) = (si["q"][j].as_f64().unwrap(), mm["q"][j].as_f64().unwrap());
        let expected = if j.contains("finger") {
            a * 1000.0
        } else {
            a.to_degrees()
        };
        assert_close!(b, expected, 1e-6, 0.0, "{j}: {b} vs {expected}");
    }
    // dynamics: q in degrees and v in deg/s give the torques of the same state in rad.
    let model = panda();
    let tau = |args: &[&str]| -> Vec<f64> {
        let mut all = vec!["dynamics", model.as_str(), "--a", "panda_joint1=0"];
        all.extend_from_slice(args);
        let text = ok(&kinetree(&all));
        text.lines()
            .skip(1)
            .take(9)
            .map(|l| l.split_whitespace().nth(1).unwrap().parse().unwrap())
            .collect()
    };
    let a = tau(&["--q", "panda_joint2=0.5,panda_joint4=-1.5"]);
    let b = tau(&[
        "--q",
        &format!(
            "panda_joint2={},panda_joint4={}",
            0.5f64.to_degrees(),
            (-1.5f64).to_degrees()
        ),
        "--units",
        "mm-deg",
    ]);
    assert_eq!(a.len(), 9);
    for (x, y) in a.iter().zip(&b) {
        assert_close!(x, y, 1e-5, 0.0, "{a:?} vs {b:?}");
    }
    // collide: the closest pair's distance printed in mm is a thousand times the one in m.
    let closest = |args: &[&str]| -> (String, f64) {
        let mut all = vec!["collide", model.as_str(), "--closest", "1"];
        all.extend_from_slice(args);
        let text = ok(&kinetree(&all));
        let mut lines = text
            .lines()
            .skip_while(|l| !l.starts_with("closest self pairs"));
        let header = lines.next().unwrap_or_default().to_string();
        let value = lines
            .next()
            .and_then(|l| l.split_whitespace().last())
            .and_then(|x| x.parse().ok())
            .unwrap_or_else(|| panic!("no closest pair in {text}"));
        (header, value)
    };
    let (m_header, m) = closest(&["--q", "panda_joint4=-1.5"]);
    let (mm_header, mm) = closest(&[
        "--q",
        &format!("panda_joint4={}", (-1.5f64).to_degrees()),
        "--units",
        "mm-deg",
    ]);
    assert!(m_header.contains("signed distance, m)"), "{m_header}");
    assert!(mm_header.contains("signed distance, mm)"), "{mm_header}");
    assert!(m.abs() > 1e-3, "{m}");
    assert_close!(mm, m * 1000.0, 1e-2, 0.0, "{mm} vs {m}");
}

#[test]
fn codegen_writes_python_that_agrees_with_compute() {
    let source = temp("fk_tcp.py");
    ok(&kinetree(&[
        "codegen",
        &panda(),
        "--frame",
        "panda_hand_tcp",
        "--lang",
        "python",
        "--name",
        "tcp",
        "--out",
        source.to_str().unwrap(),
    ]));
    let states = temp("codegen_states.json");
    std::fs::write(
        &states,
        r#"{"samples": [{"q": {"panda_joint1": 0.3, "panda_joint2": -0.4, "panda_joint4": -1.2, "panda_joint6": 1.1}}]}"#,
    )
    .unwrap();
    let computed: serde_json::Value = serde_json::from_str(&ok(&kinetree(&[
        "compute",
        &panda(),
        "--states",
        states.to_str().unwrap(),
    ])))
    .unwrap();
    let pose = &computed["samples"][0]["link_poses"]["panda_hand_tcp"];
    let script = format!(
        "import runpy\nm = runpy.run_path({:?})\nfor row in m['tcp']([0.3, -0.4, 0.0, -1.2, 0.0, 1.1, 0.0, 0.0, 0.0]):\n    print(*row)\n",
        source.display().to_string()
    );
    let out = Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    let text = ok(&out);
    let rows: Vec<Vec<f64>> = text
        .lines()
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 4, "{text}");
    for i in 0..3 {
        for j in 0..3 {
            let r = pose["rotation"][i][j].as_f64().unwrap();
            assert_close!(rows[i][j], r, 1e-12, 0.0, "R[{i}][{j}]: {text}");
        }
        let t = pose["translation"][i].as_f64().unwrap();
        assert_close!(rows[i][3], t, 1e-12, 0.0, "t[{i}]: {text}");
    }
    assert_eq!(rows[3], [0.0, 0.0, 0.0, 1.0]);
    // An unknown frame is an error naming it.
    let e = kinetree(&["codegen", &panda(), "--frame", "nope", "--lang", "c"]);
    assert!(!e.status.success());
    assert!(String::from_utf8_lossy(&e.stderr).contains("nope"));
}

#[test]
fn compute_reports_named_frames_poses() {
    let states = temp("frames_states.json");
    std::fs::write(&states, r#"{"samples": [{"name": "home"}]}"#).unwrap();
    let run = |frames: &str| -> serde_json::Value {
        let text = ok(&kinetree(&[
            "compute",
            &yapcad("yap_arm.yapcad.json"),
            "--states",
            states.to_str().unwrap(),
            "--frames",
            frames,
        ]));
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["samples"][0]["frame_poses"]
            .clone()
    };
    let all = run("all");
    let names: Vec<&String> = all.as_object().unwrap().keys().collect();
    assert_eq!(
        names,
        ["ELBOW", "MOUNT", "SHOULDER", "TOOL_FLANGE", "WRIST"],
        "{all}"
    );
    // The base's MOUNT datum sits 40 mm above the base part's origin, which is on the world's.
    let mount = &all["MOUNT"]["translation"];
    for (k, want) in [0.0, 0.0, 0.04].into_iter().enumerate() {
        assert_close!(mount[k].as_f64().unwrap(), want, 1e-12, 0.0, "{all}");
    }
    // One frame asked for by name: the same pose, and only that one.
    let one = run("SHOULDER");
    assert_eq!(one.as_object().unwrap().len(), 1);
    assert_eq!(one["SHOULDER"], all["SHOULDER"]);
    // Not asked for: no frame_poses key at all.
    let text = ok(&kinetree(&[
        "compute",
        &yapcad("yap_arm.yapcad.json"),
        "--states",
        states.to_str().unwrap(),
    ]));
    assert!(!text.contains("frame_poses"));
}

#[test]
fn compute_takes_and_prints_millimetres_and_degrees() {
    let si = temp("units_si.json");
    let mm = temp("units_mm.json");
    std::fs::write(
        &si,
        r#"{"samples": [{"q": {"panda_joint2": 0.5, "panda_joint4": -1.5, "panda_finger_joint1": 0.02}, "v": {"panda_joint1": 0.3}}]}"#,
    )
    .unwrap();
    std::fs::write(
        &mm,
        format!(
            r#"{{"samples": [{{"q": {{"panda_joint2": {}, "panda_joint4": {}, "panda_finger_joint1": 20.0}}, "v": {{"panda_joint1": {}}}}}]}}"#,
            0.5f64.to_degrees(),
            (-1.5f64).to_degrees(),
            0.3f64.to_degrees()
        ),
    )
    .unwrap();
    let run = |file: &PathBuf, units: &str| -> serde_json::Value {
        let text = ok(&kinetree(&[
            "compute",
            &panda(),
            "--states",
            file.to_str().unwrap(),
            "--units",
            units,
        ]));
        serde_json::from_str(&text).unwrap()
    };
    let (a, b) = (run(&si, "si"), run(&mm, "mm-deg"));
    assert_eq!(b["units"]["length"], "mm");
    let (a, b) = (&a["samples"][0], &b["samples"][0]);
    // The same state: translations a thousand times larger, rotations and energies equal.
    for link in ["panda_hand_tcp", "panda_leftfinger"] {
        for k in 0..3 {
            let (x, y) = (
                a["link_poses"][link]["translation"][k].as_f64().unwrap(),
                b["link_poses"][link]["translation"][k].as_f64().unwrap(),
            );
            assert_close!(y, 1000.0 * x, 1e-9, 0.0, "{link}: {x} vs {y}");
            let (r, s) = (
                a["link_poses"][link]["rotation"][k][0].as_f64().unwrap(),
                b["link_poses"][link]["rotation"][k][0].as_f64().unwrap(),
            );
            assert_close!(r, s, 1e-12);
        }
    }
    let (ka, kb) = (
        a["kinetic_energy"].as_f64().unwrap(),
        b["kinetic_energy"].as_f64().unwrap(),
    );
    assert!(ka > 0.0 && (ka - kb).abs() < 1e-12, "{ka} vs {kb}");
    let (ca, cb) = (a["com"][2].as_f64().unwrap(), b["com"][2].as_f64().unwrap());
    assert_close!(cb, 1000.0 * ca, 1e-9);
}

/// A leg whose hip and knee are composite joints (trip_kinematics' `Transformation`).
const LEG: &str = r#"{"name": "leg",
  "links": [
    {"name": "pelvis"},
    {"name": "thigh", "inertial": {"origin": {"xyz": [0.05, 0.1, -0.2]}, "mass": 1.5,
       "inertia": {"ixx": 0.03, "iyy": 0.04, "izz": 0.02}}},
    {"name": "shank", "inertial": {"origin": {"xyz": [0.05, 0.1, -0.2]}, "mass": 1.5,
       "inertia": {"ixx": 0.03, "iyy": 0.04, "izz": 0.02}}}],
  "joints": [
    {"name": "hip", "type": "composite", "parent": "pelvis", "child": "thigh",
     "origin": {"xyz": [0, 0.2, 0]},
     "factors": [{"param": "tx", "value": 0.1}, {"param": "ry", "limits": {"lower": -2, "upper": 2}},
                 {"param": "rz"}, {"param": "tz", "value": -0.05}]},
    {"name": "knee", "type": "composite", "parent": "thigh", "child": "shank",
     "factors": [{"param": "quat"}, {"param": "tz", "value": 0.3}, {"param": "ty"}]}]}"#;

#[test]
fn a_composite_joint_is_one_joint_at_the_command_line() {
    let model = temp("leg.json");
    std::fs::write(&model, LEG).unwrap();
    let model_s = model.to_str().unwrap();
    // inspect: two joints, three links, no pieces or virtual links.
    let text = ok(&kinetree(&["inspect", model_s]));
    assert!(
        text.contains("joints (2):") && text.contains("links (3):"),
        "{text}"
    );
    let hip = text
        .lines()
        .find(|l| l.trim_start().starts_with("hip "))
        .unwrap();
    assert!(
        hip.contains("composite") && hip.contains("tx=0.1 ry rz tz=-0.05"),
        "{hip}"
    );
    assert!(hip.contains("0..2"), "{hip}");
    assert!(
        !text.contains("hip#1") && !text.contains("hip.ry"),
        "{text}"
    );
    // compute: model.joints lists the composite joints with their whole blocks.
    let states = temp("leg-states.json");
    std::fs::write(
        &states,
        r#"{"samples": [{"q": {"hip": [0.3, -0.2], "knee": [0, 0, 0.6, 0.8, 0.25]}, "v": {"knee": [1, 0, 0, 0.5]}}]}"#,
    )
    .unwrap();
    let out: serde_json::Value = serde_json::from_str(&ok(&kinetree(&[
        "compute",
        model_s,
        "--states",
        states.to_str().unwrap(),
    ])))
    .unwrap();
    let joints: Vec<(String, String, u64, u64, u64, u64)> = out["model"]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| {
            let n = |k: &str| j[k].as_u64().unwrap();
            (
                j["name"].as_str().unwrap().to_string(),
                j["type"].as_str().unwrap().to_string(),
                n("idx_q"),
                n("nq"),
                n("idx_v"),
                n("nv"),
            )
        })
        .collect();
    let want = [
        ("hip", "composite", 0, 2, 0, 2),
        ("knee", "composite", 2, 5, 2, 4),
    ];
    let want: Vec<_> = want
        .iter()
        .map(|&(a, b, c, d, e, f)| (a.to_string(), b.to_string(), c, d, e, f))
        .collect();
    assert_eq!(joints, want);
    let sample = &out["samples"][0];
    let links: Vec<&String> = sample["link_poses"].as_object().unwrap().keys().collect();
    assert_eq!(links, ["pelvis", "shank", "thigh"]);
    let g = &sample["by_joint"]["gravity_torque"];
    assert_eq!(g["hip"].as_array().unwrap().len(), 2, "{g}");
    assert_eq!(g["knee"].as_array().unwrap().len(), 4, "{g}");
    // dynamics: --q names the composite joint with its values separated by `:`, and the torques
    // are printed by composite joint; they equal compute's nle at that state (a = 0).
    let text = ok(&kinetree(&[
        "dynamics",
        model_s,
        "--q",
        "hip=0.3:-0.2,knee=0:0:0.6:0.8:0.25",
        "--v",
        "knee=1:0:0:0.5",
        "--a",
        "hip=0:0",
    ]));
    let hip_tau: Vec<f64> = text
        .lines()
        .find(|l| l.trim_start().starts_with("hip "))
        .unwrap()
        .split_whitespace()
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    let nle = &sample["by_joint"]["nle"]["hip"];
    for (k, x) in hip_tau.iter().enumerate() {
        let y = nle[k].as_f64().unwrap();
        assert!((x - y).abs() < 1e-5 * (1.0 + y.abs()), "{text} vs {nle}");
    }
    // A wrong number of values names the composite joint.
    let e = kinetree(&["dynamics", model_s, "--q", "hip=0.3", "--a", "hip=0:0"]);
    assert!(!e.status.success());
    let err = String::from_utf8_lossy(&e.stderr);
    assert!(
        err.contains("'hip'") && err.contains("composite joint takes 2"),
        "{err}"
    );
    // convert: JSON to JSON keeps it one composite joint, with --positions by its name.
    let again = temp("leg-again.json");
    ok(&kinetree(&[
        "convert",
        model_s,
        again.to_str().unwrap(),
        "--positions",
        "hip=0.3:-0.2",
    ]));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&again).unwrap()).unwrap();
    assert_eq!(joint(&doc, "hip")["type"], "composite");
    assert_eq!(
        joint(&doc, "hip")["position"],
        serde_json::json!([0.3, -0.2])
    );
    assert_eq!(doc["joints"].as_array().unwrap().len(), 2);
    // To URDF: the expansion, and a note saying so.
    let urdf = temp("leg.urdf");
    let text = ok(&kinetree(&["convert", model_s, urdf.to_str().unwrap()]));
    assert!(
        text.contains(
            "composite joint 'hip' is written as its 3 elementary joints and 2 virtual links"
        ),
        "{text}"
    );
    // ik: the answer is keyed by composite joint.
    let text = ok(&kinetree(&[
        "ik",
        model_s,
        "--frame",
        "thigh",
        "--target",
        "0.1,0.2,-0.05,0,0,0",
        "--json",
    ]));
    let answer: serde_json::Value = serde_json::from_str(text.trim()).unwrap();
    let q = answer["q"].as_object().unwrap();
    assert!(
        q.contains_key("hip") && q.contains_key("knee") && !q.contains_key("hip.ry"),
        "{text}"
    );
    assert_eq!(q["hip"].as_array().unwrap().len(), 2, "{text}");
    // simulate: the final state and the trajectory are keyed by composite joint, and the viewer
    // plays that trajectory back.
    let traj = temp("leg-traj.json");
    let text = ok(&kinetree(&[
        "simulate",
        model_s,
        "--duration",
        "0.01",
        "--q",
        "hip=0.3:-0.2",
        "--out",
        traj.to_str().unwrap(),
    ]));
    let finals: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("final q:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(|l| l.split_whitespace().next().unwrap())
        .collect();
    assert_eq!(finals, ["hip", "knee"], "{text}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&traj).unwrap()).unwrap();
    let first = doc["trajectory"][0]["q"].as_object().unwrap();
    assert_eq!(first.keys().collect::<Vec<_>>(), ["hip", "knee"]);
    assert_eq!(first["hip"], serde_json::json!([0.3, -0.2]));
    let page = temp("leg-view.html");
    ok(&kinetree(&[
        "view",
        model_s,
        "--trajectory",
        traj.to_str().unwrap(),
        "--export",
        page.to_str().unwrap(),
    ]));
}

#[test]
fn compute_mm_deg_converts_every_length_and_angle_and_lists_what_stays_si() {
    let model = temp("slide-turn.json");
    std::fs::write(
        &model,
        r#"{"name": "st",
  "links": [
    {"name": "base", "collisions": [{"geometry": {"type": "box", "size": [0.1, 0.1, 0.1]}}]},
    {"name": "slider", "inertial": {"mass": 1.0, "inertia": {"ixx": 0.01, "iyy": 0.01, "izz": 0.01}}},
    {"name": "arm", "inertial": {"origin": {"xyz": [0.25, 0, 0]}, "mass": 2.0,
       "inertia": {"ixx": 0.01, "iyy": 0.05, "izz": 0.05}},
     "collisions": [{"origin": {"xyz": [0.5, 0, 0]}, "geometry": {"type": "box", "size": [0.1, 0.1, 0.1]}}]}],
  "joints": [
    {"name": "slide", "type": "prismatic", "parent": "base", "child": "slider", "axis": [1, 0, 0]},
    {"name": "turn", "type": "revolute", "parent": "slider", "child": "arm", "origin": {"xyz": [0, 0, 0.1]},
     "axis": [0, 1, 0]}],
  "frames": [{"name": "tip", "link": "arm", "origin": {"xyz": [0.5, 0, 0]}}]}"#,
    )
    .unwrap();
    let (q, v, tau) = ([0.2, 0.5], [0.1, 0.3], [1.0, 2.0]);
    let states = |mm: bool| {
        let (l, a) = if mm {
            (1000.0, 180.0 / std::f64::consts::PI)
        } else {
            (1.0, 1.0)
        };
        let path = temp(if mm { "st-mm.json" } else { "st-si.json" });
        std::fs::write(
            &path,
            format!(
                r#"{{"samples": [{{"q": {{"slide": {}, "turn": {}}}, "v": {{"slide": {}, "turn": {}}},
                    "tau": {{"slide": {}, "turn": {}}}}}]}}"#,
                q[0] * l,
                q[1] * a,
                v[0] * l,
                v[1] * a,
                tau[0],
                tau[1]
            ),
        )
        .unwrap();
        path
    };
    let run = |mm: bool| -> serde_json::Value {
        let file = states(mm);
        let text = ok(&kinetree(&[
            "compute",
            model.to_str().unwrap(),
            "--states",
            file.to_str().unwrap(),
            "--frames",
            "tip",
            "--jacobians",
            "tip",
            "--collision",
            "--units",
            if mm { "mm-deg" } else { "si" },
        ]));
        serde_json::from_str(&text).unwrap()
    };
    let (si, mm) = (run(false), run(true));
    let deg = 180.0 / std::f64::consts::PI;
    let (a, b) = (&si["samples"][0], &mm["samples"][0]);
    let close = |x: &serde_json::Value, y: &serde_json::Value, s: f64, what: &str| {
        let (x, y) = match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => (x, y),
            _ => panic!("{what}: {x} and {y} are not both numbers"),
        };
        assert!(
            (y - s * x).abs() < 1e-9 * (1.0 + y.abs()),
            "{what}: {x} × {s} vs {y}"
        );
    };
    // Positions: link and frame translations, the centre of mass, collision distances, in mm.
    for k in 0..3 {
        close(
            &a["link_poses"]["arm"]["translation"][k],
            &b["link_poses"]["arm"]["translation"][k],
            1000.0,
            "link",
        );
        close(
            &a["frame_poses"]["tip"]["translation"][k],
            &b["frame_poses"]["tip"]["translation"][k],
            1000.0,
            "frame",
        );
        close(&a["com"][k], &b["com"][k], 1000.0, "com");
    }
    let d = &a["collision"][0]["distance"];
    assert!(d.as_f64().unwrap() > 0.1, "{a}");
    close(d, &b["collision"][0]["distance"], 1000.0, "collision");
    // The Jacobian: linear rows in mm, angular rows in deg, per mm (slide) or deg (turn).
    for row in 0..6 {
        let out = if row < 3 { 1000.0 } else { deg };
        for (col, per) in [(0, 1000.0), (1, deg)] {
            let (x, y) = (
                &a["jacobians"]["tip"][row][col],
                &b["jacobians"]["tip"][row][col],
            );
            close(x, y, out / per, &format!("J[{row}][{col}]"));
        }
    }
    // The turn's angular Jacobian column is its axis, in deg/s per deg/s.
    close(
        &b["jacobians"]["tip"][4][1],
        &serde_json::json!(1.0),
        1.0,
        "J axis",
    );
    // Accelerations per coordinate: mm/s² for the slide, deg/s² for the turn.
    close(&a["aba"][0], &b["aba"][0], 1000.0, "aba slide");
    close(&a["aba"][1], &b["aba"][1], deg, "aba turn");
    close(
        &a["by_joint"]["aba"]["slide"],
        &b["by_joint"]["aba"]["slide"],
        1000.0,
        "by_joint slide",
    );
    close(
        &a["by_joint"]["aba"]["turn"],
        &b["by_joint"]["aba"]["turn"],
        deg,
        "by_joint turn",
    );
    // What stays SI is the same number, and the output says so.
    for key in ["gravity_torque", "nle"] {
        for k in 0..2 {
            close(&a[key][k], &b[key][k], 1.0, key);
        }
    }
    for key in ["kinetic_energy", "potential_energy", "total_mass"] {
        close(&a[key], &b[key], 1.0, key);
    }
    close(
        &a["mass_matrix"][1][1],
        &b["mass_matrix"][1][1],
        1.0,
        "mass_matrix",
    );
    let listed: Vec<&str> = mm["units"]["si"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap())
        .collect();
    for key in [
        "gravity_torque",
        "mass_matrix",
        "nle",
        "rnea",
        "derivatives",
        "kinetic_energy",
    ] {
        assert!(listed.contains(&key), "{listed:?}");
    }
    assert_eq!(mm["units"]["length"], "mm");
    assert!(si.get("units").is_none());
    // --help says the same.
    let help = ok(&kinetree(&["compute", "--help"]));
    assert!(
        help.contains("stay SI") && help.contains("deg/s²"),
        "{help}"
    );
}
