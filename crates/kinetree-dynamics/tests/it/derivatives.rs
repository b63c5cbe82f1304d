//! The analytic derivatives: against Pinocchio 4.1's `computeRNEADerivatives`,
//! `computeGeneralizedGravityDerivatives` and `computeABADerivatives` on the reference robots,
//! against central finite differences through `integrate` on every joint kind, and identities.

use crate::common::{
    all_models, every_kind, index_map, q_of, random_state, reference_dir, rng, robots, v_of,
};
use kinetree_dynamics::kinematics::configuration::integrate;
use kinetree_dynamics::model::{Model, RootJoint};
use kinetree_dynamics::spatial::Force;
use kinetree_dynamics::spatial::glam::DVec3;
use kinetree_dynamics::{
    DerivativesData, DynamicsData, ExternalForces, FrameId, JointTerms, ReferenceFrame, aba,
    aba_derivatives, aba_derivatives_with_external_forces, crba, generalized_gravity,
    generalized_gravity_derivatives, mass_matrix_inverse, rnea, rnea_derivatives,
    rnea_derivatives_with_external_forces, rnea_with_external_forces,
};
use serde_json::Value;

/// `max |ours - reference| / max(1, max |reference|)`, the reference row-major in Pinocchio's
/// order and mapped to ours by `map`.
fn matrix_error(ours: &[f64], reference: &Value, map: &[usize]) -> f64 {
    let n = map.len();
    let mut scale: f64 = 1.0;
    let mut worst: f64 = 0.0;
    for i in 0..n {
        for j in 0..n {
            let r = reference[i][j].as_f64().unwrap();
            scale = scale.max(r.abs());
            let o = ours[map[i] * n + map[j]];
            worst = worst.max(if o.is_finite() {
                (o - r).abs()
            } else {
                f64::INFINITY
            });
        }
    }
    worst / scale
}

#[test]
fn derivatives_match_pinocchio() {
    let mut checked = 0;
    for (name, main, model) in robots() {
        let path = reference_dir()
            .join("derivatives")
            .join(format!("{name}.json"));
        let reference: Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let map = index_map(&model, &reference);
        let mut data = DerivativesData::with_joint_terms(&model, JointTerms::Ignored);
        let samples = reference["samples"].as_array().unwrap();
        assert!(!samples.is_empty());
        for (k, sample) in samples.iter().enumerate() {
            let q = q_of(&model, sample);
            let (v, a, tau) = (
                v_of(&model, sample, "v"),
                v_of(&model, sample, "a"),
                v_of(&model, sample, "tau"),
            );
            let d = rnea_derivatives(&model, &mut data, &q, &v, &a).unwrap();
            let rnea = &sample["rnea"];
            for (key, m) in [
                ("dtau_dq", d.dtau_dq),
                ("dtau_dv", d.dtau_dv),
                ("dtau_da", d.dtau_da),
            ] {
                let e = matrix_error(m, &rnea[key], &map);
                assert!(e < 1e-8, "{name} sample {k} {key}: {e:e}");
            }
            let dg = generalized_gravity_derivatives(&model, &mut data, &q).unwrap();
            let e = matrix_error(dg, &sample["gravity"]["dg_dq"], &map);
            assert!(e < 1e-8, "{name} sample {k} dg_dq: {e:e}");
            if sample["aba"].is_null() {
                continue;
            }
            let cond = main["samples"][k]["mass_matrix_cond"].as_f64().unwrap();
            let tolerance = 1e-8 * (cond / 1e3).max(1.0);
            let d = aba_derivatives(&model, &mut data, &q, &v, &tau).unwrap();
            let aba_ref = &sample["aba"];
            for (key, m) in [
                ("dddq_dq", d.dddq_dq),
                ("dddq_dv", d.dddq_dv),
                ("dddq_dtau", d.dddq_dtau),
            ] {
                let e = matrix_error(m, &aba_ref[key], &map);
                assert!(
                    e < tolerance,
                    "{name} sample {k} {key}: {e:e} (cond {cond:e})"
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 7, "{checked}");
}

/// `q ⊕ h·e_k`.
fn step(model: &Model, q: &[f64], k: usize, h: f64) -> Vec<f64> {
    let mut dv = vec![0.0; model.nv()];
    dv[k] = h;
    let mut out = vec![0.0; model.nq()];
    integrate(model, q, &dv, &mut out).unwrap();
    out
}

/// The central finite difference of `f` along column `k` of q (through `integrate`) or of the
/// vector `x` (plain), as a row-major `nv x nv` matrix.
fn fd_q(model: &Model, q: &[f64], mut f: impl FnMut(&[f64]) -> Vec<f64>) -> Vec<f64> {
    let n = model.nv();
    let h = 1e-6;
    let mut m = vec![0.0; n * n];
    for k in 0..n {
        let (p, mm) = (f(&step(model, q, k, h)), f(&step(model, q, k, -h)));
        for i in 0..n {
            m[i * n + k] = (p[i] - mm[i]) / (2.0 * h);
        }
    }
    m
}

fn fd_vec(x: &[f64], mut f: impl FnMut(&[f64]) -> Vec<f64>) -> Vec<f64> {
    let n = x.len();
    let h = 1e-6;
    let mut m = vec![0.0; n * n];
    for k in 0..n {
        let mut xp = x.to_vec();
        xp[k] += h;
        let mut xm = x.to_vec();
        xm[k] -= h;
        let (p, mm) = (f(&xp), f(&xm));
        for i in 0..n {
            m[i * n + k] = (p[i] - mm[i]) / (2.0 * h);
        }
    }
    m
}

fn close(name: &str, what: &str, ours: &[f64], fd: &[f64], tolerance: f64) {
    let scale = fd.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let worst = ours
        .iter()
        .zip(fd)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        worst / scale < tolerance,
        "{name} {what}: {:e}",
        worst / scale
    );
}

/// Wrenches of all three reference frames on the last link and, for trees, another.
fn external_forces(model: &Model) -> ExternalForces {
    let mut fext = ExternalForces::new(model);
    let nl = model.links().len();
    let push = |x: f64| {
        Force::new(
            DVec3::new(1.0, -2.0, 0.5) * x,
            DVec3::new(0.3, 0.1, -0.4) * x,
        )
    };
    fext.add(
        model,
        FrameId::Link(nl - 1),
        ReferenceFrame::Local,
        push(1.0),
    )
    .unwrap();
    fext.add(
        model,
        FrameId::Link(nl - 1),
        ReferenceFrame::World,
        push(-0.7),
    )
    .unwrap();
    fext.add(
        model,
        FrameId::Link(nl / 2),
        ReferenceFrame::LocalWorldAligned,
        push(1.3),
    )
    .unwrap();
    fext
}

#[test]
fn derivatives_match_finite_differences_on_every_joint_kind() {
    for (name, model) in all_models() {
        // Joint damping and friction on (every_kind has them); v away from 0 keeps sign(v) fixed.
        let mut data = DerivativesData::with_joint_terms(&model, JointTerms::FromModel);
        let mut dynamics = DynamicsData::with_joint_terms(&model, JointTerms::FromModel);
        let fext = external_forces(&model);
        for seed in 0..2 {
            let (q, v, a) = random_state(&model, &mut rng(100 + seed));
            let d = rnea_derivatives_with_external_forces(&model, &mut data, &q, &v, &a, &fext)
                .unwrap();
            let (dq, dv, da) = (d.dtau_dq.to_vec(), d.dtau_dv.to_vec(), d.dtau_da.to_vec());
            let mut id = |q: &[f64], v: &[f64], a: &[f64]| {
                rnea_with_external_forces(&model, &mut dynamics, q, v, a, &fext)
                    .unwrap()
                    .to_vec()
            };
            close(
                &name,
                "dtau_dq",
                &dq,
                &fd_q(&model, &q, |q| id(q, &v, &a)),
                1e-6,
            );
            close(&name, "dtau_dv", &dv, &fd_vec(&v, |v| id(&q, v, &a)), 1e-6);
            close(&name, "dtau_da", &da, &fd_vec(&a, |a| id(&q, &v, a)), 1e-6);

            let dg = generalized_gravity_derivatives(&model, &mut data, &q)
                .unwrap()
                .to_vec();
            let fd = fd_q(&model, &q, |q| {
                generalized_gravity(&model, &mut dynamics, q)
                    .unwrap()
                    .to_vec()
            });
            close(&name, "dg_dq", &dg, &fd, 1e-6);

            let tau: Vec<f64> = (0..model.nv()).map(|k| 0.3 * (k as f64).sin()).collect();
            let d = aba_derivatives_with_external_forces(&model, &mut data, &q, &v, &tau, &fext)
                .unwrap();
            let (dq, dv, dt) = (d.dddq_dq.to_vec(), d.dddq_dv.to_vec(), d.dddq_dtau.to_vec());
            let mut fd_aba = |q: &[f64], v: &[f64], t: &[f64]| {
                kinetree_dynamics::aba_with_external_forces(&model, &mut dynamics, q, v, t, &fext)
                    .unwrap()
                    .to_vec()
            };
            close(
                &name,
                "dddq_dq",
                &dq,
                &fd_q(&model, &q, |q| fd_aba(q, &v, &tau)),
                1e-5,
            );
            close(
                &name,
                "dddq_dv",
                &dv,
                &fd_vec(&v, |v| fd_aba(&q, v, &tau)),
                1e-5,
            );
            close(
                &name,
                "dddq_dtau",
                &dt,
                &fd_vec(&tau, |t| fd_aba(&q, &v, t)),
                1e-5,
            );
        }
    }
}

#[test]
fn derivative_identities() {
    for (name, model) in all_models() {
        let n = model.nv();
        let mut data = DerivativesData::new(&model);
        let mut dynamics = DynamicsData::new(&model);
        let (q, v, _) = random_state(&model, &mut rng(5));
        let tau: Vec<f64> = (0..n).map(|k| 0.2 * (k as f64).cos()).collect();
        let ddq = aba(&model, &mut dynamics, &q, &v, &tau).unwrap().to_vec();
        let m = crba(&model, &mut dynamics, &q).unwrap().to_vec();
        let minv = mass_matrix_inverse(&model, &mut dynamics, &q)
            .unwrap()
            .to_vec();
        let d = aba_derivatives(&model, &mut data, &q, &v, &tau).unwrap();
        let (ddq_d, dq, dv, dt) = (
            d.ddq.to_vec(),
            d.dddq_dq.to_vec(),
            d.dddq_dv.to_vec(),
            d.dddq_dtau.to_vec(),
        );
        close(&name, "ddq", &ddq_d, &ddq, 1e-12);
        // ∂q̈/∂τ = M⁻¹ and ∂τ/∂a = M.
        close(&name, "dddq_dtau", &dt, &minv, 1e-10);
        let d = rnea_derivatives(&model, &mut data, &q, &v, &ddq).unwrap();
        close(&name, "dtau_da", d.dtau_da, &m, 1e-12);
        // ∂q̈/∂q = -M⁻¹·∂τ/∂q and ∂q̈/∂v = -M⁻¹·∂τ/∂v at q̈ = aba(q, v, τ).
        let neg_product = |x: &[f64]| -> Vec<f64> {
            let mut out = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    out[i * n + j] = -(0..n).map(|k| minv[i * n + k] * x[k * n + j]).sum::<f64>();
                }
            }
            out
        };
        close(&name, "dddq_dq", &dq, &neg_product(d.dtau_dq), 1e-9);
        close(&name, "dddq_dv", &dv, &neg_product(d.dtau_dv), 1e-9);
        // τ of the derivatives pass is rnea's.
        let t = rnea(&model, &mut dynamics, &q, &v, &ddq).unwrap().to_vec();
        close(&name, "tau", d.tau, &t, 1e-12);
    }
}

#[test]
fn damping_enters_dtau_dv_and_friction_has_zero_derivative_at_rest() {
    let model = every_kind(RootJoint::Fixed);
    let n = model.nv();
    let mut on = DerivativesData::with_joint_terms(&model, JointTerms::FromModel);
    let mut off = DerivativesData::with_joint_terms(&model, JointTerms::Ignored);
    let (q, _, a) = random_state(&model, &mut rng(9));
    // v = 0: friction's sign(v) jumps there; its derivative is returned as zero.
    let v = vec![0.0; n];
    let d_on = rnea_derivatives(&model, &mut on, &q, &v, &a)
        .unwrap()
        .dtau_dv
        .to_vec();
    let d_off = rnea_derivatives(&model, &mut off, &q, &v, &a)
        .unwrap()
        .dtau_dv
        .to_vec();
    let mut damped = 0;
    for b in model.bodies().iter().skip(1) {
        let damping = b.joint.map_or(0.0, |j| model.joint(j).dynamics.damping);
        for k in b.idx_v..b.idx_v + b.nv {
            assert!((d_on[k * n + k] - d_off[k * n + k] - damping).abs() < 1e-12);
            damped += usize::from(damping > 0.0);
        }
    }
    assert!(damped > 0);
}
