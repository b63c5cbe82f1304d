//! The integrator: energy conservation, dissipation and convergence order.

use crate::common::{every_kind_with_gravity, random_state, reference_dir, rng};
use kinetree_dynamics::kinematics::configuration::difference;
use kinetree_dynamics::model::{Model, RootJoint};
use kinetree_dynamics::spatial::glam::DVec3;
use kinetree_dynamics::{
    DynamicsData, Integrator, JointTerms, centroidal_momentum, mechanical_energy, step,
};

fn double_pendulum() -> Model {
    Model::from_urdf_file(
        reference_dir().join("urdf/double_pendulum.urdf"),
        RootJoint::Fixed,
    )
    .unwrap()
}

/// RK4 at 1 kHz for 10 s with no torque: the mechanical energy drifts by less than 1e-6 of the
/// initial energy (and of the swing energy above the resting state).
///
/// The pendulum is released from rest 57° and 46° away from hanging straight down (`q = 0` is
/// upright for this URDF). Released near upright, its light second link whirls at 70+ rad/s and
/// RK4's truncation error at 1 kHz reaches a few 1e-6 (30x less at 2 kHz).
#[test]
fn double_pendulum_conserves_energy() {
    let model = double_pendulum();
    // The reference ignores the URDF's joint damping; so does this test (damping dissipates).
    let mut data = DynamicsData::with_joint_terms(&model, JointTerms::Ignored);
    let pi = std::f64::consts::PI;
    let (mut q, mut v) = (vec![pi - 1.0, 0.8], vec![0.0, 0.0]);
    let tau = [0.0; 2];
    let e0 = mechanical_energy(&model, &mut data, &q, &v).unwrap();
    let rest = mechanical_energy(&model, &mut data, &[pi, 0.0], &[0.0, 0.0]).unwrap();
    let mut drift: f64 = 0.0;
    for _ in 0..10_000 {
        step(
            &model,
            &mut data,
            Integrator::RungeKutta4,
            &mut q,
            &mut v,
            &tau,
            1e-3,
        )
        .unwrap();
        let e = mechanical_energy(&model, &mut data, &q, &v).unwrap();
        drift = drift.max((e - e0).abs());
    }
    let relative = drift / e0.abs();
    let swing = drift / (e0 - rest);
    eprintln!(
        "double pendulum, RK4 1 kHz 10 s: energy drift {drift:.2e} J, {relative:.2e} of E0 = {e0:.4} J, {swing:.2e} of the swing energy"
    );
    assert!(
        relative < 1e-6 && swing < 1e-6,
        "relative drift {relative:e} / {swing:e}"
    );
}

/// With the URDF's joint damping the energy only goes down.
#[test]
fn damped_double_pendulum_loses_energy() {
    let model = double_pendulum();
    let mut data = DynamicsData::with_joint_terms(&model, JointTerms::FromModel);
    let (mut q, mut v) = (vec![1.2, -0.7], vec![0.5, 2.0]);
    let mut e = mechanical_energy(&model, &mut data, &q, &v).unwrap();
    let e0 = e;
    for integrator in [Integrator::RungeKutta4, Integrator::SemiImplicitEuler] {
        for _ in 0..2000 {
            step(
                &model, &mut data, integrator, &mut q, &mut v, &[0.0; 2], 1e-4,
            )
            .unwrap();
            let next = mechanical_energy(&model, &mut data, &q, &v).unwrap();
            if integrator == Integrator::RungeKutta4 {
                assert!(next <= e + 1e-12, "energy rose from {e} to {next}");
            }
            e = next;
        }
    }
    assert!(e < e0 - 1e-3, "energy {e0} -> {e}");
}

/// Runs `steps` steps of `dt` from a fixed state of the floating tree with every joint kind and
/// returns the final (q, v).
fn simulate(model: &Model, integrator: Integrator, dt: f64, steps: usize) -> (Vec<f64>, Vec<f64>) {
    let mut data = DynamicsData::with_joint_terms(model, JointTerms::Ignored);
    let (mut q, mut v, _) = random_state(model, &mut rng(9));
    for x in v.iter_mut() {
        *x *= 2.0;
    }
    let tau: Vec<f64> = (0..model.nv()).map(|k| 0.3 * (k as f64).sin()).collect();
    for _ in 0..steps {
        step(model, &mut data, integrator, &mut q, &mut v, &tau, dt).unwrap();
    }
    (q, v)
}

fn state_error(model: &Model, a: &(Vec<f64>, Vec<f64>), b: &(Vec<f64>, Vec<f64>)) -> f64 {
    let mut dq = vec![0.0; model.nv()];
    difference(model, &a.0, &b.0, &mut dq).unwrap();
    let eq = dq.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let ev =
        a.1.iter()
            .zip(&b.1)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    eq.max(ev)
}

/// Halving the step divides the error by ~16 for RK4 (its fourth order holds on SO(3) and
/// SE(3) thanks to the dexp⁻¹ correction) and by ~2 for semi-implicit Euler.
#[test]
fn integrators_reach_their_order_on_the_manifold() {
    let model = every_kind_with_gravity(RootJoint::Floating, DVec3::new(0.0, 0.0, -9.81));
    let t = 0.2;
    let exact = simulate(&model, Integrator::RungeKutta4, t / 1280.0, 1280);
    let e1 = state_error(
        &model,
        &simulate(&model, Integrator::RungeKutta4, t / 20.0, 20),
        &exact,
    );
    let e2 = state_error(
        &model,
        &simulate(&model, Integrator::RungeKutta4, t / 40.0, 40),
        &exact,
    );
    let ratio = e1 / e2;
    eprintln!("RK4 error {e1:.2e} -> {e2:.2e}: ratio {ratio:.1}");
    assert!(
        ratio > 12.0 && ratio < 20.0,
        "RK4 order: error ratio {ratio}"
    );
    let e1 = state_error(
        &model,
        &simulate(&model, Integrator::SemiImplicitEuler, t / 200.0, 200),
        &exact,
    );
    let e2 = state_error(
        &model,
        &simulate(&model, Integrator::SemiImplicitEuler, t / 400.0, 400),
        &exact,
    );
    let ratio = e1 / e2;
    eprintln!("semi-implicit Euler error {e1:.2e} -> {e2:.2e}: ratio {ratio:.2}");
    assert!(
        ratio > 1.7 && ratio < 2.3,
        "Euler order: error ratio {ratio}"
    );
}

/// A floating tree without gravity or torques keeps its momentum about the centre of mass, and
/// its energy.
#[test]
fn free_floating_tree_conserves_momentum() {
    let model = every_kind_with_gravity(RootJoint::Floating, DVec3::ZERO);
    let mut data = DynamicsData::with_joint_terms(&model, JointTerms::Ignored);
    let (mut q, mut v, _) = random_state(&model, &mut rng(10));
    let tau = vec![0.0; model.nv()];
    let h0 = centroidal_momentum(&model, &mut data, &q, &v).unwrap();
    let e0 = mechanical_energy(&model, &mut data, &q, &v).unwrap();
    for _ in 0..1000 {
        step(
            &model,
            &mut data,
            Integrator::RungeKutta4,
            &mut q,
            &mut v,
            &tau,
            1e-3,
        )
        .unwrap();
    }
    let h1 = centroidal_momentum(&model, &mut data, &q, &v).unwrap();
    let e1 = mechanical_energy(&model, &mut data, &q, &v).unwrap();
    let scale = h0.linear.length() + h0.angular.length();
    assert!(
        (h1.linear - h0.linear).length() + (h1.angular - h0.angular).length() < 1e-8 * scale,
        "momentum {h0:?} -> {h1:?}"
    );
    assert!((e1 - e0).abs() < 1e-8 * e0.abs(), "energy {e0} -> {e1}");
}
