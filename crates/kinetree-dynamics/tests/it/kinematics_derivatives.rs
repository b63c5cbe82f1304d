//! The kinematics derivatives (frame velocity, acceleration and Jacobian with respect to q, v,
//! a) against central finite differences through `integrate`, on every joint kind and the
//! reference robots, in the three reference frames.

use crate::common::{all_models, random_state, rng};
use kinetree_dynamics::kinematics::configuration::{difference, integrate};
use kinetree_dynamics::kinematics::{
    FrameId, KinematicsData, KinematicsDerivativesData, ReferenceFrame, change_reference,
    compute_frame_jacobian, difference_jacobians, forward_kinematics_with_acceleration,
    frame_acceleration_derivatives, frame_jacobian_derivatives, frame_velocity_derivatives,
    integrate_jacobians,
};
use kinetree_dynamics::model::Model;
use kinetree_dynamics::spatial::Motion;

const FRAMES: [ReferenceFrame; 3] = [
    ReferenceFrame::World,
    ReferenceFrame::Local,
    ReferenceFrame::LocalWorldAligned,
];

/// The frames to check: every link of the every-kind trees (so every joint kind is on some
/// chain), the last link of the reference robots.
fn frames(name: &str, model: &Model) -> Vec<FrameId> {
    let n = model.links().len();
    if name.starts_with("every_kind") {
        (0..n).map(FrameId::Link).collect()
    } else {
        vec![FrameId::Link(n - 1)]
    }
}

/// Velocity and acceleration of `frame` in `rf` (6 + 6 numbers).
fn motion(
    model: &Model,
    data: &mut KinematicsData,
    (q, v, a): (&[f64], &[f64], &[f64]),
    frame: FrameId,
    rf: ReferenceFrame,
) -> [f64; 12] {
    forward_kinematics_with_acceleration(model, data, q, v, a).unwrap();
    let (b, body_from_frame) = frame.body(model).unwrap();
    let world_from_frame = data.world_from_body()[b] * body_from_frame;
    let vel = body_from_frame.act_inv_motion(&data.body_velocity()[b]);
    let acc = body_from_frame.act_inv_motion(&data.body_acceleration()[b]);
    let mut out = [0.0; 12];
    out[..6].copy_from_slice(&change_reference(&world_from_frame, &vel, rf).to_array());
    out[6..].copy_from_slice(&change_reference(&world_from_frame, &acc, rf).to_array());
    out
}

fn q_plus(model: &Model, q: &[f64], k: usize, h: f64) -> Vec<f64> {
    let mut dv = vec![0.0; model.nv()];
    dv[k] = h;
    let mut out = vec![0.0; model.nq()];
    integrate(model, q, &dv, &mut out).unwrap();
    out
}

fn check(what: &str, ours: &[f64], fd: &[f64]) {
    let scale = fd.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let worst = ours
        .iter()
        .zip(fd)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(worst / scale < 1e-6, "{what}: {:e}", worst / scale);
}

#[test]
fn frame_motion_derivatives_match_finite_differences() {
    let h = 1e-6;
    for (name, model) in all_models() {
        let nv = model.nv();
        let mut kd = KinematicsDerivativesData::new(&model);
        let mut data = KinematicsData::new(&model);
        let (q, v, a) = random_state(&model, &mut rng(21));
        for (frame, rf) in frames(&name, &model)
            .into_iter()
            .flat_map(|f| FRAMES.map(|rf| (f, rf)))
        {
            let mut m = vec![vec![0.0; 6 * nv]; 6];
            let [vq, vv, dvq, daq, dav, daa] = &mut m[..] else {
                unreachable!()
            };
            frame_velocity_derivatives(&model, &mut kd, &q, &v, frame, rf, vq, vv).unwrap();
            frame_acceleration_derivatives(
                &model, &mut kd, &q, &v, &a, frame, rf, dvq, daq, dav, daa,
            )
            .unwrap();
            let mut fd = vec![vec![0.0; 6 * nv]; 5];
            for k in 0..nv {
                let (qp, qm) = (q_plus(&model, &q, k, h), q_plus(&model, &q, k, -h));
                let p = motion(&model, &mut data, (&qp, &v, &a), frame, rf);
                let n = motion(&model, &mut data, (&qm, &v, &a), frame, rf);
                let mut vp = v.clone();
                vp[k] += h;
                let mut vm = v.clone();
                vm[k] -= h;
                let pv = motion(&model, &mut data, (&q, &vp, &a), frame, rf);
                let nvv = motion(&model, &mut data, (&q, &vm, &a), frame, rf);
                let mut ap = a.clone();
                ap[k] += h;
                let mut am = a.clone();
                am[k] -= h;
                let pa = motion(&model, &mut data, (&q, &v, &ap), frame, rf);
                let na = motion(&model, &mut data, (&q, &v, &am), frame, rf);
                for r in 0..6 {
                    let d =
                        |x: &[f64; 12], y: &[f64; 12], o: usize| (x[o + r] - y[o + r]) / (2.0 * h);
                    fd[0][r * nv + k] = d(&p, &n, 0);
                    fd[1][r * nv + k] = d(&pv, &nvv, 0);
                    fd[2][r * nv + k] = d(&p, &n, 6);
                    fd[3][r * nv + k] = d(&pv, &nvv, 6);
                    fd[4][r * nv + k] = d(&pa, &na, 6);
                }
            }
            check(&format!("{name} {frame:?} {rf:?} dv/dq"), &m[0], &fd[0]);
            check(&format!("{name} {frame:?} {rf:?} dv/dv"), &m[1], &fd[1]);
            check(
                &format!("{name} {frame:?} {rf:?} dv/dq (acc)"),
                &m[2],
                &fd[0],
            );
            check(&format!("{name} {frame:?} {rf:?} da/dq"), &m[3], &fd[2]);
            check(&format!("{name} {frame:?} {rf:?} da/dv"), &m[4], &fd[3]);
            check(&format!("{name} {frame:?} {rf:?} da/da"), &m[5], &fd[4]);
        }
    }
}

#[test]
fn frame_jacobian_derivatives_match_finite_differences() {
    let h = 1e-6;
    for (name, model) in all_models() {
        let nv = model.nv();
        let mut kd = KinematicsDerivativesData::new(&model);
        let mut data = KinematicsData::new(&model);
        let (q, _, _) = random_state(&model, &mut rng(22));
        let mut jac = vec![Motion::ZERO; nv];
        let mut jacobian = |q: &[f64], frame, rf| -> Vec<f64> {
            compute_frame_jacobian(&model, &mut data, q, frame, rf, &mut jac).unwrap();
            let mut rows = vec![0.0; 6 * nv];
            for (c, col) in jac.iter().enumerate() {
                for (r, x) in col.to_array().into_iter().enumerate() {
                    rows[r * nv + c] = x;
                }
            }
            rows
        };
        for (frame, rf) in frames(&name, &model)
            .into_iter()
            .flat_map(|f| FRAMES.map(|rf| (f, rf)))
        {
            let mut hessian = vec![0.0; 6 * nv * nv];
            frame_jacobian_derivatives(&model, &mut kd, &q, frame, rf, &mut hessian).unwrap();
            let mut fd = vec![0.0; 6 * nv * nv];
            for k in 0..nv {
                let p = jacobian(&q_plus(&model, &q, k, h), frame, rf);
                let n = jacobian(&q_plus(&model, &q, k, -h), frame, rf);
                for (i, (x, y)) in p.iter().zip(&n).enumerate() {
                    fd[k * 6 * nv + i] = (x - y) / (2.0 * h);
                }
            }
            check(&format!("{name} {frame:?} {rf:?} dJ/dq"), &hessian, &fd);
        }
    }
}

#[test]
fn integrate_and_difference_jacobians_match_finite_differences() {
    let h = 1e-6;
    for (name, model) in all_models() {
        let nv = model.nv();
        let (q0, v_big, w) = random_state(&model, &mut rng(31));
        let (q_far, _, _) = random_state(&model, &mut rng(32));
        let plus = |q: &[f64], v: &[f64]| {
            let mut out = vec![0.0; model.nq()];
            integrate(&model, q, v, &mut out).unwrap();
            out
        };
        let minus = |q1: &[f64], q0: &[f64]| {
            let mut out = vec![0.0; nv];
            difference(&model, q0, q1, &mut out).unwrap();
            out
        };
        // Large motions, then small ones (the series branches of the Lie-group Jacobians).
        for scale in [1.0, 0.02] {
            let v: Vec<f64> = v_big.iter().map(|x| x * scale).collect();
            let q1 = if scale == 1.0 {
                q_far.clone()
            } else {
                plus(&q0, &w.iter().map(|x| x * scale).collect::<Vec<_>>())
            };
            let qv = plus(&q0, &v);
            let (mut iq, mut iv) = (vec![0.0; nv * nv], vec![0.0; nv * nv]);
            integrate_jacobians(&model, &q0, &v, &mut iq, &mut iv).unwrap();
            let (mut d0, mut d1) = (vec![0.0; nv * nv], vec![0.0; nv * nv]);
            difference_jacobians(&model, &q0, &q1, &mut d0, &mut d1).unwrap();
            // Central differences, column k: the four perturbed results at +h and at -h.
            let mut fd = vec![vec![0.0; nv * nv]; 4];
            for k in 0..nv {
                let at = |h: f64| -> [Vec<f64>; 4] {
                    let mut e = vec![0.0; nv];
                    e[k] = h;
                    let mut ve = v.clone();
                    ve[k] += h;
                    [
                        minus(&plus(&plus(&q0, &e), &v), &qv),
                        minus(&plus(&q0, &ve), &qv),
                        minus(&q1, &plus(&q0, &e)),
                        minus(&plus(&q1, &e), &q0),
                    ]
                };
                let (p, m) = (at(h), at(-h));
                for t in 0..4 {
                    for i in 0..nv {
                        fd[t][i * nv + k] = (p[t][i] - m[t][i]) / (2.0 * h);
                    }
                }
            }
            check(&format!("{name} x{scale} d(q+v)/dq"), &iq, &fd[0]);
            check(&format!("{name} x{scale} d(q+v)/dv"), &iv, &fd[1]);
            check(&format!("{name} x{scale} d(q1-q0)/dq0"), &d0, &fd[2]);
            check(&format!("{name} x{scale} d(q1-q0)/dq1"), &d1, &fd[3]);
        }
    }
}
