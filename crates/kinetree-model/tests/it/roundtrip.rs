//! Round trips through URDF and JSON export: every reference robot, the samples and the
//! example-robot-data corpus come back as the same model.

use kinetree_model::{JsonOptions, Model, RootJoint, Units, samples};
use std::path::PathBuf;

fn reference_urdfs() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/reference/urdf");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "urdf"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 7, "reference URDFs missing");
    files
}

/// URDF → URDF, URDF → JSON (SI and mm/deg), JSON → JSON: each reload equals the original.
fn check_round_trips(model: &Model, what: &str) {
    let root = model.root_joint();
    let urdf = model
        .to_urdf_string()
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    let back = Model::from_urdf_str(&urdf, root).unwrap_or_else(|e| panic!("{what}: {e}\n{urdf}"));
    // URDF has no named frames: those are the only thing allowed to go missing.
    let frames_lost = format!("{} frames vs 0", model.frames().len());
    match model.first_difference(&back, 1e-12) {
        None => {}
        Some(d) if d == frames_lost => {}
        Some(d) => panic!("{what}: URDF round trip differs: {d}"),
    }
    let json = model.to_json_string(&JsonOptions::default()).unwrap();
    let from_json = Model::from_json_str(&json, None).unwrap_or_else(|e| panic!("{what}: {e}"));
    if let Some(d) = model.first_difference(&from_json, 1e-12) {
        panic!("{what}: JSON round trip differs: {d}");
    }
    // Export again: the text is stable once the model has been through JSON.
    let json2 = from_json.to_json_string(&JsonOptions::default()).unwrap();
    let again = Model::from_json_str(&json2, None).unwrap();
    assert_eq!(from_json.first_difference(&again, 1e-12), None, "{what}");
    let mm = JsonOptions {
        units: Units::MM_DEG,
        ..JsonOptions::default()
    };
    match model.to_json_string(&mm) {
        Ok(json_mm) => {
            let from_mm = Model::from_json_str(&json_mm, None).unwrap();
            if let Some(d) = model.first_difference(&from_mm, 1e-9) {
                panic!("{what}: mm/deg JSON round trip differs: {d}");
            }
        }
        // Only mixed-unit joints with finite limits may refuse millimetres and degrees.
        Err(e) => assert!(
            e.to_string().contains("mix lengths and angles"),
            "{what}: {e}"
        ),
    }
}

#[test]
fn reference_urdfs_survive_urdf_and_json_round_trips() {
    for path in reference_urdfs() {
        for root in [RootJoint::Fixed, RootJoint::Floating] {
            let model = Model::from_urdf_file(&path, root).unwrap();
            check_round_trips(&model, &path.display().to_string());
            // URDF → JSON → Model equals the URDF model, and so does URDF → URDF → Model.
            let json = model.to_json_string(&JsonOptions::default()).unwrap();
            assert!(json.contains("\"version\": 1"));
        }
    }
}

#[test]
fn samples_survive_round_trips() {
    for model in [
        samples::pendulum(),
        samples::double_pendulum(),
        samples::planar_2r(0.4, 0.25),
        samples::six_axis(),
        samples::humanoid_like(),
    ] {
        check_round_trips(&model, model.name());
    }
}

#[test]
fn example_robot_data_survives_round_trips() {
    for path in crate::corpus::corpus() {
        let model = Model::from_urdf_file(&path, RootJoint::Fixed).unwrap();
        check_round_trips(&model, &path.display().to_string());
    }
}
