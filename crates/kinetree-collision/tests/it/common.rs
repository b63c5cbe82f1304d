//! Shared helpers: the panda_collision reference and small inline robots.

use kinetree_collision::kinematics::configuration::{Space, from_named};
use kinetree_collision::kinematics::model::{Model, RootJoint};
use serde_json::Value;
use std::path::PathBuf;

pub(crate) fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data")
}

/// The panda_collision reference JSON and its model.
pub(crate) fn panda() -> (Value, Model) {
    let dir = data_dir().join("reference");
    let reference: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("panda_collision.json")).unwrap())
            .unwrap();
    let model = Model::from_urdf_file(
        dir.join(reference["urdf"].as_str().unwrap()),
        RootJoint::Fixed,
    )
    .unwrap();
    (reference, model)
}

/// Our `q` for a sample's `state.q` (keyed by joint name).
pub(crate) fn q_of(model: &Model, sample: &Value) -> Vec<f64> {
    let named = sample["state"]["q"].as_object().unwrap();
    let values = named.iter().map(|(n, x)| (n, [x.as_f64().unwrap()]));
    from_named(model, Space::Configuration, values, false).unwrap()
}

/// A robot from an inline URDF body (links and joints), fixed to the world.
pub(crate) fn urdf(body: &str) -> Model {
    Model::from_urdf_str(
        &format!("<robot name=\"t\">{body}</robot>"),
        RootJoint::Fixed,
    )
    .unwrap()
}
