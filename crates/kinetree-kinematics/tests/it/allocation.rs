//! The hot paths allocate nothing once the data exists: a counting global allocator for this
//! test binary (`kinetree-test-support`) counts allocations made by the current thread.

use crate::common::{q_of, robots, v_of};
use kinetree_kinematics::spatial::Motion;
use kinetree_kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, compute_joint_jacobians,
    compute_joint_jacobians_time_variation, compute_joint_jacobians_without_links, configuration,
    forward_kinematics, forward_kinematics_with_acceleration, frame_jacobian,
    frame_jacobian_time_variation, update_frame_placements, update_world_placements,
};
use kinetree_test_support::{CountingAllocator, allocations_during};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn hot_paths_do_not_allocate() {
    for (robot, reference, model) in robots() {
        let sample = &reference["samples"][0];
        let (q, v, a) = (
            q_of(&model, sample),
            v_of(&model, sample, "v"),
            v_of(&model, sample, "a"),
        );
        let mut data = KinematicsData::new(&model);
        let mut jac = vec![Motion::ZERO; model.nv()];
        let mut out = vec![0.0; model.nq()];
        let mut dv = vec![0.0; model.nv()];
        let mut mid = vec![0.0; model.nq()];
        let frame =
            FrameId::find(&model, reference["jacobian_links"][0].as_str().unwrap()).unwrap();
        let count = allocations_during(|| {
            for _ in 0..3 {
                forward_kinematics(&model, &mut data, &q).unwrap();
                update_frame_placements(&model, &mut data).unwrap();
                update_world_placements(&model, &mut data).unwrap();
                forward_kinematics_with_acceleration(&model, &mut data, &q, &v, &a).unwrap();
                compute_joint_jacobians(&model, &mut data, &q).unwrap();
                compute_joint_jacobians_without_links(&model, &mut data, &q).unwrap();
                frame_jacobian(
                    &model,
                    &data,
                    frame,
                    ReferenceFrame::LocalWorldAligned,
                    &mut jac,
                )
                .unwrap();
                compute_frame_jacobian(
                    &model,
                    &mut data,
                    &q,
                    frame,
                    ReferenceFrame::Local,
                    &mut jac,
                )
                .unwrap();
                compute_joint_jacobians_time_variation(&model, &mut data, &q, &v).unwrap();
                frame_jacobian_time_variation(
                    &model,
                    &data,
                    frame,
                    ReferenceFrame::World,
                    &mut jac,
                )
                .unwrap();
                configuration::integrate(&model, &q, &v, &mut out).unwrap();
                configuration::difference(&model, &q, &out, &mut dv).unwrap();
                configuration::interpolate(&model, &q, &out, 0.3, &mut mid).unwrap();
            }
        });
        assert_eq!(count, 0, "{robot}: the kinematics hot paths allocated");
    }
}
