//! Link poses and frame Jacobians against Pinocchio 4.1 on every public reference robot.

use crate::common::{column_map, q_of, robots};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::Motion;
use kinetree_kinematics::spatial::Se3;
use kinetree_kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, compute_joint_jacobians,
    compute_joint_jacobians_without_links, frame_jacobian,
};
use serde_json::Value;

const TOL: f64 = 1e-9;

#[test]
fn link_poses_match_pinocchio() {
    for (robot, reference, model) in robots() {
        let mut data = KinematicsData::new(&model);
        let mut worst: f64 = 0.0;
        for sample in reference["samples"].as_array().unwrap() {
            let q = q_of(&model, sample);
            kinetree_kinematics::forward_kinematics(&model, &mut data, &q).unwrap();
            for (link, pose) in sample["link_poses"].as_object().unwrap() {
                let ours = data
                    .world_from(FrameId::find(&model, link).unwrap())
                    .unwrap();
                let rows = ours.rotation_rows();
                for i in 0..3 {
                    worst = worst.max(
                        (ours.translation[i] - pose["translation"][i].as_f64().unwrap()).abs(),
                    );
                    for j in 0..3 {
                        worst = worst
                            .max((rows[i][j] - pose["rotation"][i][j].as_f64().unwrap()).abs());
                    }
                }
            }
        }
        assert!(worst < TOL, "{robot}: worst link pose error {worst:e}");
    }
}

#[test]
fn frame_jacobians_match_pinocchio() {
    for (robot, reference, model) in robots() {
        let mut data = KinematicsData::new(&model);
        let map = column_map(&model, &reference);
        let mut jac = vec![Motion::ZERO; model.nv()];
        let mut direct = vec![Motion::ZERO; model.nv()];
        let mut worst: f64 = 0.0;
        for sample in reference["samples"].as_array().unwrap() {
            let q = q_of(&model, sample);
            compute_joint_jacobians(&model, &mut data, &q).unwrap();
            worst = worst.max(worst_jacobian_error(&model, &data, sample, &map));
            // The single-frame path gives the same matrix in every reference frame.
            for link in sample["jacobians"].as_object().unwrap().keys() {
                let frame = FrameId::find(&model, link).unwrap();
                for rf in [
                    ReferenceFrame::World,
                    ReferenceFrame::Local,
                    ReferenceFrame::LocalWorldAligned,
                ] {
                    frame_jacobian(&model, &data, frame, rf, &mut jac).unwrap();
                    compute_frame_jacobian(&model, &mut data, &q, frame, rf, &mut direct).unwrap();
                    for (a, b) in jac.iter().zip(&direct) {
                        assert!(a.abs_diff_eq(b, 1e-14), "{robot}/{link} {rf:?}");
                    }
                }
            }
        }
        assert!(worst < TOL, "{robot}: worst Jacobian error {worst:e}");
    }
}

/// The largest difference between the local-world-aligned frame Jacobians read from `data`
/// (its joint Jacobians already computed at the sample's `q`) and the sample's Pinocchio ones.
fn worst_jacobian_error(
    model: &Model,
    data: &KinematicsData,
    sample: &Value,
    map: &[(usize, usize)],
) -> f64 {
    let mut jac = vec![Motion::ZERO; model.nv()];
    let mut worst: f64 = 0.0;
    for (link, expected) in sample["jacobians"].as_object().unwrap() {
        let frame = FrameId::find(model, link).unwrap();
        frame_jacobian(
            model,
            data,
            frame,
            ReferenceFrame::LocalWorldAligned,
            &mut jac,
        )
        .unwrap();
        for &(ours, theirs) in map {
            let col = jac[ours].to_array();
            for r in 0..6 {
                worst = worst.max((col[r] - expected[r][theirs].as_f64().unwrap()).abs());
            }
        }
    }
    worst
}

#[test]
fn joint_jacobians_without_links_match_pinocchio() {
    for (robot, reference, model) in robots() {
        let mut data = KinematicsData::new(&model);
        let mut full = KinematicsData::new(&model);
        let map = column_map(&model, &reference);
        let mut worst: f64 = 0.0;
        for sample in reference["samples"].as_array().unwrap() {
            let q = q_of(&model, sample);
            compute_joint_jacobians_without_links(&model, &mut data, &q).unwrap();
            worst = worst.max(worst_jacobian_error(&model, &data, sample, &map));
            // The same columns and body placements as the call that also places the links.
            compute_joint_jacobians(&model, &mut full, &q).unwrap();
            assert_eq!(data.joint_jacobians(), full.joint_jacobians(), "{robot}");
            assert_eq!(data.world_from_body(), full.world_from_body(), "{robot}");
        }
        assert!(worst < TOL, "{robot}: worst Jacobian error {worst:e}");
        // The link placements were never written: they keep their initial identity.
        assert!(
            data.world_from_link().iter().all(|x| *x == Se3::IDENTITY),
            "{robot}: link placements were written"
        );
    }
}
