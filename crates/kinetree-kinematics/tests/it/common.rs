//! Shared helpers: loading the reference robots and mapping their named states.

use kinetree_kinematics::configuration::{Space, from_named};
use kinetree_kinematics::model::{Model, RootJoint};
use serde_json::Value;
use std::path::PathBuf;

pub(crate) fn reference_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/reference")
}

/// Every reference robot: name, parsed JSON, loaded model.
pub(crate) fn robots() -> Vec<(String, Value, Model)> {
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

fn values(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().map(|x| x.as_f64().unwrap()).collect(),
        x => vec![x.as_f64().unwrap()],
    }
}

/// Our `q` for a sample's `state.q` (keyed by joint name).
pub(crate) fn q_of(model: &Model, sample: &Value) -> Vec<f64> {
    let named = sample["state"]["q"].as_object().unwrap();
    from_named(
        model,
        Space::Configuration,
        named.iter().map(|(n, x)| (n, values(x))),
        false,
    )
    .unwrap()
}

/// Our velocity-space vector for a sample's `state.<key>`.
pub(crate) fn v_of(model: &Model, sample: &Value, key: &str) -> Vec<f64> {
    let named = sample["state"][key].as_object().unwrap();
    from_named(
        model,
        Space::Velocity,
        named.iter().map(|(n, x)| (n, values(x))),
        false,
    )
    .unwrap()
}

/// Column `k` of our v order for column `pk` of Pinocchio's v order, per the reference joint table.
pub(crate) fn column_map(model: &Model, reference: &Value) -> Vec<(usize, usize)> {
    let mut map = Vec::new();
    for j in reference["joints"].as_array().unwrap() {
        let ours = model.joint_v_range(model.joint_index(j["name"].as_str().unwrap()).unwrap());
        let theirs = j["idx_v"].as_u64().unwrap() as usize;
        for (k, o) in ours.enumerate() {
            map.push((o, theirs + k));
        }
    }
    map
}
