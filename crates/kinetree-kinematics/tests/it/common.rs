//! Shared helpers: loading the reference robots and mapping their named states.

use kinetree_kinematics::model::Model;
pub(crate) use kinetree_test_support::{q_of, reference_dir, robots, v_of};
use serde_json::Value;

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
