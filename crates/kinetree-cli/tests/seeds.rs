//! The seed libraries' ways at the command line: yapCAD files, joint values kept through a
//! conversion, millimetres and degrees.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn kinetree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .args(args)
        .output()
        .expect("the kinetree binary runs")
}

fn yapcad(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/yapcad")
        .join(name)
        .display()
        .to_string()
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
    assert!((joint(&doc, "j_base")["position"].as_f64().unwrap() - 30.0).abs() < 1e-9);
    assert!((joint(&doc, "j_grip")["position"].as_f64().unwrap() - 25.0).abs() < 1e-9);
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
        assert!((xyz[k].as_f64().unwrap() - e).abs() < 1e-9, "{xyz}");
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
    assert!((joint(&doc, "j_base")["position"].as_f64().unwrap() - 30.0).abs() < 1e-9);
    assert!((joint(&doc, "j_elbow")["position"].as_f64().unwrap() + 10.0).abs() < 1e-9);
    assert!((joint(&doc, "j_grip")["position"].as_f64().unwrap() - 5.0).abs() < 1e-9);
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
    let _ = std::fs::remove_dir_all(out.parent().unwrap());
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
