//! The Pinocchio reference files: where they are, the robots, and their states as our vectors.

use kinetree_kinematics::configuration::{Space, from_named};
use kinetree_kinematics::model::{Model, RootJoint};
use serde_json::Value;
use std::path::PathBuf;

/// The workspace's `tests/data` folder (robots, reference files, yapCAD exports).
#[must_use]
pub fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data")
}

/// The Pinocchio reference folder, `tests/data/reference` (its `urdf/` holds the robots).
#[must_use]
pub fn reference_dir() -> PathBuf {
    data_dir().join("reference")
}

/// Every reference robot, sorted by name: name, parsed JSON, loaded model (fixed or with a
/// floating root joint as the file's `root_joint` says). Panics unless there are exactly 7.
#[must_use]
pub fn robots() -> Vec<(String, Value, Model)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(reference_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
            let root = if v["root_joint"] == "fixed" {
                RootJoint::Fixed
            } else {
                RootJoint::Floating
            };
            let model =
                Model::from_urdf_file(reference_dir().join(v["urdf"].as_str().unwrap()), root)
                    .unwrap();
            out.push((
                path.file_stem().unwrap().to_string_lossy().into_owned(),
                v,
                model,
            ));
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(out.len(), 7);
    out
}

/// A name-keyed value of a reference state: a number, or a list for a multi-DoF joint.
#[must_use]
pub fn values(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().map(|x| x.as_f64().unwrap()).collect(),
        x => vec![x.as_f64().unwrap()],
    }
}

/// Our `q` for a sample's `state.q` (keyed by joint name).
#[must_use]
pub fn q_of(model: &Model, sample: &Value) -> Vec<f64> {
    let named = sample["state"]["q"].as_object().unwrap();
    from_named(
        model,
        Space::Configuration,
        named.iter().map(|(n, x)| (n, values(x))),
        false,
    )
    .unwrap()
}

/// Our velocity-space vector for a sample's `state.<key>` (`v`, `a` or `tau`).
#[must_use]
pub fn v_of(model: &Model, sample: &Value, key: &str) -> Vec<f64> {
    let named = sample["state"][key].as_object().unwrap();
    from_named(
        model,
        Space::Velocity,
        named.iter().map(|(n, x)| (n, values(x))),
        false,
    )
    .unwrap()
}
