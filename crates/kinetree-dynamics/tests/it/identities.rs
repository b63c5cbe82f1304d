//! Identities between the algorithms on random states of every model (reference robots and a
//! tree with every joint kind), with the joints' damping, friction and armature on and off.

use crate::common::{all_models, mat_vec, random_state, relative_error, rng};
use kinetree_dynamics::kinematics::configuration::integrate;
use kinetree_dynamics::kinematics::{
    KinematicsData, compute_joint_jacobians, forward_kinematics_with_velocity, frame_jacobian,
    update_world_placements,
};
use kinetree_dynamics::model::Model;
use kinetree_dynamics::spatial::Force;
use kinetree_dynamics::spatial::glam::DVec3;
use kinetree_dynamics::spatial::{Motion, Se3};
use kinetree_dynamics::{
    DynamicsData, ExternalForces, FrameId, JointTerms, ReferenceFrame, aba,
    aba_with_external_forces, center_of_mass, center_of_mass_jacobian, center_of_mass_velocity,
    centroidal_momentum, crba, exudyn, factorize_mass_matrix, generalized_gravity,
    mass_matrix_inverse, mechanical_energy, moving_mass, nonlinear_effects, rnea,
    rnea_with_external_forces, solve_mass_matrix,
};

const SAMPLES: usize = 20;
const MODES: [JointTerms; 2] = [JointTerms::Ignored, JointTerms::FromModel];

#[test]
fn aba_inverts_rnea() {
    for (name, model) in all_models() {
        for mode in MODES {
            let mut data = DynamicsData::with_joint_terms(&model, mode);
            let mut r = rng(1);
            for _ in 0..SAMPLES {
                let (q, v, a) = random_state(&model, &mut r);
                let tau = rnea(&model, &mut data, &q, &v, &a).unwrap().to_vec();
                let ddq = aba(&model, &mut data, &q, &v, &tau).unwrap().to_vec();
                let e = relative_error(&ddq, &a, 1.0);
                assert!(e < 1e-9, "{name} {mode:?}: aba(rnea(a)) - a = {e:e}");
                // The CRBA route gives the same accelerations.
                let crb = exudyn::forward_dynamics_crb(&model, &mut data, &q, &v, Some(&tau), None)
                    .unwrap();
                let e = relative_error(crb, &a, 1.0);
                assert!(
                    e < 1e-9,
                    "{name} {mode:?}: forward_dynamics_crb error {e:e}"
                );
            }
        }
    }
}

#[test]
fn crba_and_nle_rebuild_rnea() {
    for (name, model) in all_models() {
        for mode in MODES {
            let mut data = DynamicsData::with_joint_terms(&model, mode);
            let mut r = rng(2);
            for _ in 0..SAMPLES {
                let (q, v, a) = random_state(&model, &mut r);
                let tau = rnea(&model, &mut data, &q, &v, &a).unwrap().to_vec();
                let nle = nonlinear_effects(&model, &mut data, &q, &v)
                    .unwrap()
                    .to_vec();
                let m = crba(&model, &mut data, &q).unwrap().to_vec();
                let ma = mat_vec(&m, &a);
                let rebuilt: Vec<f64> = ma.iter().zip(&nle).map(|(x, y)| x + y).collect();
                let e = relative_error(&rebuilt, &tau, 1.0);
                assert!(e < 1e-10, "{name} {mode:?}: crba·a + nle - rnea = {e:e}");
                // Gravity is rnea at rest.
                let zero = vec![0.0; model.nv()];
                let g = generalized_gravity(&model, &mut data, &q).unwrap().to_vec();
                let g2 = rnea(&model, &mut data, &q, &zero, &zero).unwrap();
                assert!(relative_error(&g, g2, 1.0) < 1e-13, "{name}: gravity");
            }
        }
    }
}

#[test]
fn mass_matrix_is_symmetric_positive_definite_and_inverts() {
    for (name, model) in all_models() {
        let nv = model.nv();
        for mode in MODES {
            let mut data = DynamicsData::with_joint_terms(&model, mode);
            let mut r = rng(3);
            for _ in 0..SAMPLES {
                let (q, v, a) = random_state(&model, &mut r);
                let m = crba(&model, &mut data, &q).unwrap().to_vec();
                for i in 0..nv {
                    assert!(m[i * nv + i] > 0.0, "{name}: diagonal");
                    for j in 0..nv {
                        assert_eq!(m[i * nv + j], m[j * nv + i], "{name}: symmetry");
                    }
                }
                // Positive definite: the tree-sparse factorization succeeds and xᵀMx > 0.
                factorize_mass_matrix(&model, &mut data, &q).unwrap();
                for x in [&v, &a] {
                    let mx = mat_vec(&m, x);
                    assert!(x.iter().zip(&mx).map(|(p, q)| p * q).sum::<f64>() > 0.0);
                }
                // Several right-hand sides at once.
                let mut b: Vec<f64> = v.iter().chain(&a).copied().collect();
                solve_mass_matrix(&model, &mut data, &mut b).unwrap();
                for (x, rhs) in [(&b[..nv], &v), (&b[nv..], &a)] {
                    let e = relative_error(&mat_vec(&m, x), rhs, 1.0);
                    assert!(e < 1e-10, "{name}: M·solve(b) - b = {e:e}");
                }
                // M⁻¹·M = I.
                let minv = mass_matrix_inverse(&model, &mut data, &q).unwrap().to_vec();
                let scale = m.iter().fold(0.0f64, |s, x| s.max(x.abs()))
                    * minv.iter().fold(0.0f64, |s, x| s.max(x.abs()));
                for i in 0..nv {
                    for j in 0..nv {
                        let p: f64 = (0..nv).map(|k| minv[i * nv + k] * m[k * nv + j]).sum();
                        let expected = if i == j { 1.0 } else { 0.0 };
                        assert!(
                            (p - expected).abs() < 1e-14 * scale.max(1.0) * nv as f64,
                            "{name}: (M⁻¹M)[{i}][{j}] = {p}"
                        );
                    }
                    for j in 0..nv {
                        assert_eq!(minv[i * nv + j], minv[j * nv + i]);
                    }
                }
            }
        }
    }
}

/// The power balance: d(T + U)/dt = q̇ᵀ·(τ - d·q̇ - μ·sign(q̇)) along the trajectory through
/// (q, v) with acceleration a, by central finite differences on the configuration manifold.
#[test]
fn energy_rate_is_the_power_of_the_torques() {
    for (name, model) in all_models() {
        for mode in MODES {
            let mut data = DynamicsData::with_joint_terms(&model, mode);
            let mut r = rng(4);
            let (mut qp, mut qm) = (vec![0.0; model.nq()], vec![0.0; model.nq()]);
            for _ in 0..SAMPLES {
                let (q, v, a) = random_state(&model, &mut r);
                let tau = rnea(&model, &mut data, &q, &v, &a).unwrap().to_vec();
                let mut power = 0.0;
                let mut scale = 0.0;
                for (k, (vk, tk)) in v.iter().zip(&tau).enumerate() {
                    let (d, mu) = dissipation(&model, k, mode);
                    let applied = tk - d * vk - mu * vk.signum();
                    power += vk * applied;
                    scale += (vk * applied).abs();
                }
                let h = 1e-5;
                let step = |sign: f64| -> Vec<f64> {
                    v.iter()
                        .zip(&a)
                        .map(|(vk, ak)| sign * h * vk + 0.5 * h * h * ak)
                        .collect()
                };
                integrate(&model, &q, &step(1.0), &mut qp).unwrap();
                integrate(&model, &q, &step(-1.0), &mut qm).unwrap();
                let vp: Vec<f64> = v.iter().zip(&a).map(|(x, y)| x + h * y).collect();
                let vm: Vec<f64> = v.iter().zip(&a).map(|(x, y)| x - h * y).collect();
                let ep = mechanical_energy(&model, &mut data, &qp, &vp).unwrap();
                let em = mechanical_energy(&model, &mut data, &qm, &vm).unwrap();
                let rate = (ep - em) / (2.0 * h);
                assert!(
                    (rate - power).abs() < 1e-6 * scale.max(1.0),
                    "{name} {mode:?}: dE/dt = {rate}, power = {power}"
                );
            }
        }
    }
}

/// Damping and friction coefficients of velocity coordinate `k` under `mode`.
fn dissipation(model: &Model, k: usize, mode: JointTerms) -> (f64, f64) {
    if mode == JointTerms::Ignored {
        return (0.0, 0.0);
    }
    for j in model.moving_joints() {
        if model.joint_v_range(j).contains(&k) {
            let d = model.joint(j).dynamics;
            return (d.damping, d.friction);
        }
    }
    unreachable!()
}

/// External wrenches enter as -Jᵀ·f with the frame Jacobian in the same reference frame, and
/// ABA undoes RNEA with them.
#[test]
fn external_forces_act_through_the_jacobian_transpose() {
    for (name, model) in all_models() {
        let nv = model.nv();
        let mut data = DynamicsData::new(&model);
        let mut kin = KinematicsData::new(&model);
        let mut fext = ExternalForces::new(&model);
        let mut jac = vec![Motion::ZERO; nv];
        let mut r = rng(5);
        let last_link = FrameId::Link(model.links().len() - 1);
        let frames = [
            (
                FrameId::Link(1.min(model.links().len() - 1)),
                ReferenceFrame::World,
            ),
            (last_link, ReferenceFrame::Local),
            (last_link, ReferenceFrame::LocalWorldAligned),
        ];
        let frames: Vec<_> = frames
            .into_iter()
            .chain(
                (!model.frames().is_empty())
                    .then_some((FrameId::Frame(0), ReferenceFrame::LocalWorldAligned)),
            )
            .collect();
        for _ in 0..5 {
            let (q, v, a) = random_state(&model, &mut r);
            let tau = rnea(&model, &mut data, &q, &v, &a).unwrap().to_vec();
            compute_joint_jacobians(&model, &mut kin, &q).unwrap();
            let mut expected = tau.clone();
            fext.clear();
            for (i, &(frame, reference)) in frames.iter().enumerate() {
                let s = 1.0 + i as f64;
                let f = Force::new(
                    DVec3::new(0.3 * s, -1.2, 0.5),
                    DVec3::new(0.1, 0.2 * s, -0.4),
                );
                fext.add(&model, frame, reference, f).unwrap();
                frame_jacobian(&model, &kin, frame, reference, &mut jac).unwrap();
                for (e, col) in expected.iter_mut().zip(&jac) {
                    *e -= col.dot(&f);
                }
            }
            let with = rnea_with_external_forces(&model, &mut data, &q, &v, &a, &fext)
                .unwrap()
                .to_vec();
            let e = relative_error(&with, &expected, 1.0);
            assert!(e < 1e-12, "{name}: rnea with external forces error {e:e}");
            let ddq = aba_with_external_forces(&model, &mut data, &q, &v, &with, &fext).unwrap();
            let e = relative_error(ddq, &a, 1.0);
            assert!(e < 1e-9, "{name}: aba with external forces error {e:e}");
            // Exudyn's ForwardDynamicsCRB with forces, and with the torques left out (zero).
            let crb =
                exudyn::forward_dynamics_crb(&model, &mut data, &q, &v, Some(&with), Some(&fext))
                    .unwrap();
            let e = relative_error(crb, &a, 1.0);
            assert!(
                e < 1e-9,
                "{name}: forward_dynamics_crb with forces error {e:e}"
            );
            let free = exudyn::forward_dynamics_crb(&model, &mut data, &q, &v, None, Some(&fext))
                .unwrap()
                .to_vec();
            let zero = vec![0.0; nv];
            let expected =
                aba_with_external_forces(&model, &mut data, &q, &v, &zero, &fext).unwrap();
            let e = relative_error(&free, expected, 1.0);
            assert!(
                e < 1e-9,
                "{name}: forward_dynamics_crb without torques error {e:e}"
            );
            // Exudyn's form: M·a + f(q, v, fext) = τ.
            let (m, f) =
                exudyn::compute_mass_matrix_and_force_terms(&model, &mut data, &q, &v, &fext)
                    .unwrap();
            let lhs: Vec<f64> = mat_vec(m, &a).iter().zip(f).map(|(x, y)| x + y).collect();
            assert!(
                relative_error(&lhs, &with, 1.0) < 1e-10,
                "{name}: exudyn force terms"
            );
        }
    }
}

#[test]
fn com_quantities_agree() {
    for (name, model) in all_models() {
        let nv = model.nv();
        let mut data = DynamicsData::new(&model);
        let mut r = rng(6);
        let mut qx = vec![0.0; model.nq()];
        let mass = moving_mass(&model);
        for _ in 0..5 {
            let (q, v, _) = random_state(&model, &mut r);
            let com = center_of_mass(&model, &mut data, &q).unwrap();
            let jac = center_of_mass_jacobian(&model, &mut data, &q)
                .unwrap()
                .to_vec();
            assert!((data.com() - com).length() < 1e-15);
            // Jacobian columns by central differences.
            let h = 1e-6;
            for k in 0..nv {
                let mut dq = vec![0.0; nv];
                dq[k] = h;
                integrate(&model, &q, &dq, &mut qx).unwrap();
                let cp = center_of_mass(&model, &mut data, &qx).unwrap();
                dq[k] = -h;
                integrate(&model, &q, &dq, &mut qx).unwrap();
                let cm = center_of_mass(&model, &mut data, &qx).unwrap();
                let fd = (cp - cm) / (2.0 * h);
                assert!(
                    (fd - jac[k]).length() < 1e-7,
                    "{name}: com jacobian column {k}"
                );
            }
            // ċ = J·v, and the linear centroidal momentum is m·ċ.
            let jv = jac
                .iter()
                .zip(&v)
                .fold(DVec3::ZERO, |s, (c, vk)| s + *c * *vk);
            let vcom = center_of_mass_velocity(&model, &mut data, &q, &v).unwrap();
            assert!(
                (jv - vcom).length() < 1e-12 * (1.0 + vcom.length()),
                "{name}: com velocity"
            );
            let h = centroidal_momentum(&model, &mut data, &q, &v).unwrap();
            assert!((h.linear - vcom * mass).length() < 1e-12 * (1.0 + h.linear.length()));
        }
    }
}

/// Largest entry of `a - b` over the rotation and translation.
fn se3_gap(a: &Se3, b: &Se3) -> f64 {
    let r = (a.rotation - b.rotation).to_cols_array();
    let t = (a.translation - b.translation).to_array();
    r.iter().chain(&t).fold(0.0, |m, x| m.max(x.abs()))
}

/// Largest entry of `a - b`.
fn motion_gap(a: &Motion, b: &Motion) -> f64 {
    (a.linear - b.linear)
        .abs()
        .max_element()
        .max((a.angular - b.angular).abs().max_element())
}

/// Asserts that `got` holds forward kinematics' `q`, local placements and (after
/// `update_world_placements`) world placements of every body and link, as `fk` does.
fn assert_same_placements(
    name: &str,
    what: &str,
    model: &Model,
    got: &mut KinematicsData,
    fk: &KinematicsData,
) {
    assert_eq!(got.q(), fk.q(), "{name} {what}: q");
    let pairs = [(
        "parent_from_body",
        got.parent_from_body(),
        fk.parent_from_body(),
    )];
    for (field, a, b) in pairs {
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            let e = se3_gap(x, y);
            assert!(e < 1e-12, "{name} {what}: {field}[{i}] differs by {e:e}");
        }
    }
    update_world_placements(model, got).unwrap();
    for (field, a, b) in [
        (
            "world_from_body",
            got.world_from_body(),
            fk.world_from_body(),
        ),
        (
            "world_from_link",
            got.world_from_link(),
            fk.world_from_link(),
        ),
    ] {
        assert_eq!(a.len(), b.len());
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            let e = se3_gap(x, y);
            assert!(e < 1e-12, "{name} {what}: {field}[{i}] differs by {e:e}");
        }
    }
}

#[test]
fn dynamics_sweeps_leave_the_placements_and_velocities_of_forward_kinematics() {
    for (name, model) in all_models() {
        let mut data = DynamicsData::new(&model);
        let mut fk = KinematicsData::new(&model);
        let mut r = rng(7);
        for _ in 0..5 {
            // RNEA: q, placements and body velocities.
            let (q, v, a) = random_state(&model, &mut r);
            rnea(&model, &mut data, &q, &v, &a).unwrap();
            forward_kinematics_with_velocity(&model, &mut fk, &q, &v).unwrap();
            for (i, (x, y)) in data
                .kinematics()
                .body_velocity()
                .iter()
                .zip(fk.body_velocity())
                .enumerate()
            {
                let e = motion_gap(x, y);
                assert!(
                    e < 1e-12,
                    "{name} rnea: body_velocity[{i}] differs by {e:e}"
                );
            }
            assert_same_placements(&name, "rnea", &model, data.kinematics_mut(), &fk);
            // Gravity alone: the velocities are zero.
            let (q, _, _) = random_state(&model, &mut r);
            generalized_gravity(&model, &mut data, &q).unwrap();
            assert!(
                data.kinematics()
                    .body_velocity()
                    .iter()
                    .all(|m| *m == Motion::ZERO),
                "{name} gravity: body velocities"
            );
            forward_kinematics_with_velocity(&model, &mut fk, &q, &vec![0.0; model.nv()]).unwrap();
            assert_same_placements(
                &name,
                "generalized_gravity",
                &model,
                data.kinematics_mut(),
                &fk,
            );
            // ABA: q and placements; the bodies' world placements before any update.
            let (q, v, tau) = random_state(&model, &mut r);
            aba(&model, &mut data, &q, &v, &tau).unwrap();
            forward_kinematics_with_velocity(&model, &mut fk, &q, &v).unwrap();
            for (i, (x, y)) in data
                .kinematics()
                .world_from_body()
                .iter()
                .zip(fk.world_from_body())
                .enumerate()
            {
                let e = se3_gap(x, y);
                assert!(
                    e < 1e-12,
                    "{name} aba: world_from_body[{i}] differs by {e:e}"
                );
            }
            assert_same_placements(&name, "aba", &model, data.kinematics_mut(), &fk);
            // CRBA: q and placements.
            let (q, _, _) = random_state(&model, &mut r);
            crba(&model, &mut data, &q).unwrap();
            forward_kinematics_with_velocity(&model, &mut fk, &q, &vec![0.0; model.nv()]).unwrap();
            assert_same_placements(&name, "crba", &model, data.kinematics_mut(), &fk);
        }
    }
}
