//! Shared helpers: the panda_collision reference and small inline robots.

use kinetree_collision::kinematics::model::{Model, RootJoint};
pub(crate) use kinetree_test_support::{data_dir, q_of};
use serde_json::Value;

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

/// The reference's sample configurations, one `q` each.
pub(crate) fn sample_states(reference: &Value, model: &Model) -> Vec<Vec<f64>> {
    reference["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| q_of(model, s))
        .collect()
}

/// The reference's sample configurations stacked into one `N·nq` batch.
pub(crate) fn stacked_samples(reference: &Value, model: &Model) -> Vec<f64> {
    sample_states(reference, model).concat()
}

/// A robot from an inline URDF body (links and joints), fixed to the world.
pub(crate) fn urdf(body: &str) -> Model {
    Model::from_urdf_str(
        &format!("<robot name=\"t\">{body}</robot>"),
        RootJoint::Fixed,
    )
    .unwrap()
}
