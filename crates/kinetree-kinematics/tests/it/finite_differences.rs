//! Jacobians, velocities and Jacobian derivatives against finite differences on every reference
//! robot, in all three reference frames.

use crate::common::{q_of, robots, v_of};
use kinetree_kinematics::configuration::integrate;
use kinetree_kinematics::spatial::{Motion, explog};
use kinetree_kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_joint_jacobians,
    compute_joint_jacobians_time_variation, forward_kinematics, forward_kinematics_with_velocity,
    frame_jacobian, frame_jacobian_time_variation, frame_velocity,
};

const FRAMES: [ReferenceFrame; 3] = [
    ReferenceFrame::World,
    ReferenceFrame::Local,
    ReferenceFrame::LocalWorldAligned,
];

/// The twist that moves `frame` from its pose at `q` to its pose at `q ⊕ εv`, divided by ε
/// (central difference), in the requested reference frame.
fn fd_twist(
    model: &kinetree_kinematics::model::Model,
    data: &mut KinematicsData,
    q: &[f64],
    dv: &[f64],
    frame: FrameId,
    rf: ReferenceFrame,
) -> Motion {
    let eps = 1e-6;
    let mut qp = vec![0.0; model.nq()];
    let mut qm = vec![0.0; model.nq()];
    let scaled: Vec<f64> = dv.iter().map(|x| x * eps).collect();
    let neg: Vec<f64> = dv.iter().map(|x| -x * eps).collect();
    integrate(model, q, &scaled, &mut qp).unwrap();
    integrate(model, q, &neg, &mut qm).unwrap();
    forward_kinematics(model, data, &qp).unwrap();
    let tp = *data.world_from(frame).unwrap();
    forward_kinematics(model, data, &qm).unwrap();
    let tm = *data.world_from(frame).unwrap();
    forward_kinematics(model, data, q).unwrap();
    let t0 = *data.world_from(frame).unwrap();
    // Local twist: log(T0⁻¹ T±) / ±ε, averaged.
    let local = (explog::log6(&t0.inv_mul(&tp)) - explog::log6(&t0.inv_mul(&tm))) * (0.5 / eps);
    kinetree_kinematics::change_reference(&t0, &local, rf)
}

#[test]
fn jacobian_columns_equal_finite_differences() {
    for (robot, reference, model) in robots() {
        let mut data = KinematicsData::new(&model);
        let mut jac = vec![Motion::ZERO; model.nv()];
        let sample = &reference["samples"][0];
        let q = q_of(&model, sample);
        for link in reference["jacobian_links"].as_array().unwrap() {
            let frame = FrameId::find(&model, link.as_str().unwrap()).unwrap();
            for rf in FRAMES {
                compute_joint_jacobians(&model, &mut data, &q).unwrap();
                frame_jacobian(&model, &data, frame, rf, &mut jac).unwrap();
                for k in 0..model.nv() {
                    let mut dv = vec![0.0; model.nv()];
                    dv[k] = 1.0;
                    let fd = fd_twist(&model, &mut data, &q, &dv, frame, rf);
                    assert!(
                        fd.abs_diff_eq(&jac[k], 1e-7),
                        "{robot}/{link} {rf:?} column {k}: {fd:?} vs {:?}",
                        jac[k]
                    );
                }
            }
        }
    }
}

#[test]
fn velocities_equal_jacobian_times_v() {
    for (robot, reference, model) in robots() {
        let mut data = KinematicsData::new(&model);
        let mut jac = vec![Motion::ZERO; model.nv()];
        for sample in reference["samples"].as_array().unwrap().iter().take(3) {
            let (q, v) = (q_of(&model, sample), v_of(&model, sample, "v"));
            compute_joint_jacobians(&model, &mut data, &q).unwrap();
            forward_kinematics_with_velocity(&model, &mut data, &q, &v).unwrap();
            for l in 0..model.links().len() {
                let frame = FrameId::Link(l);
                for rf in FRAMES {
                    frame_jacobian(&model, &data, frame, rf, &mut jac).unwrap();
                    let jv = jac
                        .iter()
                        .zip(&v)
                        .fold(Motion::ZERO, |acc, (c, x)| acc + *c * *x);
                    let vel = frame_velocity(&model, &data, frame, rf).unwrap();
                    // The reference quaternions are unit only to ~1e-12, so rotations are orthonormal to that.
                    assert!(
                        jv.abs_diff_eq(&vel, 1e-11),
                        "{robot}/{} {rf:?}: {:e}",
                        model.link(l).name,
                        (jv - vel)
                            .to_array()
                            .iter()
                            .fold(0.0f64, |m, x| m.max(x.abs()))
                    );
                }
            }
        }
    }
}

#[test]
fn jacobian_time_derivative_equals_finite_differences() {
    for (robot, reference, model) in robots() {
        let mut data = KinematicsData::new(&model);
        let sample = &reference["samples"][1];
        let (q, v) = (q_of(&model, sample), v_of(&model, sample, "v"));
        let eps = 1e-6;
        let mut qp = vec![0.0; model.nq()];
        let mut qm = vec![0.0; model.nq()];
        integrate(
            &model,
            &q,
            &v.iter().map(|x| x * eps).collect::<Vec<_>>(),
            &mut qp,
        )
        .unwrap();
        integrate(
            &model,
            &q,
            &v.iter().map(|x| -x * eps).collect::<Vec<_>>(),
            &mut qm,
        )
        .unwrap();
        let (mut jp, mut jm, mut dj) = (
            vec![Motion::ZERO; model.nv()],
            vec![Motion::ZERO; model.nv()],
            vec![Motion::ZERO; model.nv()],
        );
        for link in reference["jacobian_links"].as_array().unwrap() {
            let frame = FrameId::find(&model, link.as_str().unwrap()).unwrap();
            for rf in FRAMES {
                compute_joint_jacobians(&model, &mut data, &qp).unwrap();
                frame_jacobian(&model, &data, frame, rf, &mut jp).unwrap();
                compute_joint_jacobians(&model, &mut data, &qm).unwrap();
                frame_jacobian(&model, &data, frame, rf, &mut jm).unwrap();
                compute_joint_jacobians_time_variation(&model, &mut data, &q, &v).unwrap();
                frame_jacobian_time_variation(&model, &data, frame, rf, &mut dj).unwrap();
                for k in 0..model.nv() {
                    let fd = (jp[k] - jm[k]) * (0.5 / eps);
                    assert!(
                        fd.abs_diff_eq(&dj[k], 1e-7),
                        "{robot}/{link} {rf:?} column {k}: {fd:?} vs {:?}",
                        dj[k]
                    );
                }
            }
        }
    }
}
