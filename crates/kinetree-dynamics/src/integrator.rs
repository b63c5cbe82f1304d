//! Fixed-step time integration of the equations of motion over the configuration manifold.

use crate::data::DynamicsData;
use crate::error::{DynamicsError, check_vector};
use crate::external::ExternalForces;
use crate::rnea::check_inputs;
use kinetree_kinematics::configuration::integrate;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::{JointModel, configuration};

/// A fixed-step integration scheme for [`step`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Integrator {
    /// Semi-implicit (symplectic) Euler: `v ← v + dt·q̈(q, v)`, then `q ← q ⊕ dt·v` with the new
    /// velocity. One [`aba`](crate::aba) per step, first order, good long-term energy behaviour.
    SemiImplicitEuler,
    /// The classical fourth-order Runge–Kutta method, in its Munthe-Kaas form on the
    /// configuration manifold: four [`aba`](crate::aba) per step, fourth order also for
    /// spherical, planar and floating joints.
    #[default]
    RungeKutta4,
}

/// Advances the state `(q, v)` by one time step `dt` (s) under constant joint torques `tau`
/// (zero-order hold), gravity and, with [`JointTerms::FromModel`], the joints' damping, friction
/// and armature. `q` (length `nq`) and `v` (length `nv`) are updated in place; quaternions stay
/// normalized. Allocates nothing.
///
/// Configurations move on the joints' manifolds with [`configuration::integrate`]
/// (`q ⊕ δ = q·exp(δ)` for spherical, planar and floating joints). The Runge–Kutta stages are
/// combined in the tangent space at `q` with the `dexp⁻¹` correction (Munthe-Kaas), so the
/// method keeps its fourth order on SO(3) and SE(3).
///
/// # Errors
/// [`DynamicsError::InvalidTimeStep`] unless `dt` is positive and finite;
/// [`DynamicsError::SingularMassMatrix`] as [`aba`](crate::aba); length and finiteness errors
/// for `q`, `v`, `tau` (then `q` and `v` are unchanged).
///
/// # Examples
/// ```
/// use kinetree_dynamics::{mechanical_energy, step, DynamicsData, Integrator};
/// use kinetree_dynamics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let urdf = r#"<robot name="pendulum"><link name="base"/>
///   <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
///     <inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
///   <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = DynamicsData::new(&model);
/// let (mut q, mut v) = (vec![0.0], vec![0.0]);
/// let e0 = mechanical_energy(&model, &mut data, &q, &v)?;
/// for _ in 0..1000 {
///     step(&model, &mut data, Integrator::RungeKutta4, &mut q, &mut v, &[0.0], 1e-3)?;
/// }
/// let e1 = mechanical_energy(&model, &mut data, &q, &v)?;
/// assert!((e1 - e0).abs() < 1e-9 * e0.abs().max(1.0));
/// # Ok(())
/// # }
/// ```
///
/// [`JointTerms::FromModel`]: crate::JointTerms::FromModel
#[doc(alias = "simulate")]
#[doc(alias = "integrate_dynamics")]
pub fn step(
    model: &Model,
    data: &mut DynamicsData,
    integrator: Integrator,
    q: &mut [f64],
    v: &mut [f64],
    tau: &[f64],
    dt: f64,
) -> Result<(), DynamicsError> {
    check_step(model, data, q, v, tau, dt)?;
    let result = run(model, data, integrator, q, v, tau, dt, None);
    after_step(model, data, q, v, result)
}

/// As [`step`], with wrenches applied by the environment (held constant during the step; a
/// wrench given in [`ReferenceFrame::World`](crate::ReferenceFrame::World) or
/// [`ReferenceFrame::LocalWorldAligned`](crate::ReferenceFrame::LocalWorldAligned) keeps its
/// world direction while the link moves).
///
/// # Errors
/// As [`step`]; [`DynamicsError::DataMismatch`] when `fext` belongs to another model.
#[allow(
    clippy::too_many_arguments,
    reason = "the state, inputs and step mirror `step`"
)]
pub fn step_with_external_forces(
    model: &Model,
    data: &mut DynamicsData,
    integrator: Integrator,
    q: &mut [f64],
    v: &mut [f64],
    tau: &[f64],
    dt: f64,
    fext: &ExternalForces,
) -> Result<(), DynamicsError> {
    check_step(model, data, q, v, tau, dt)?;
    fext.check_model(model)?;
    let result = run(model, data, integrator, q, v, tau, dt, Some(fext));
    after_step(model, data, q, v, result)
}

/// A step whose state stopped being finite (or whose stages failed on non-finite values) is an
/// overflow naming the first joint whose velocity or position overflowed.
fn after_step(
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    v: &[f64],
    result: Result<(), DynamicsError>,
) -> Result<(), DynamicsError> {
    match result {
        Err(e @ DynamicsError::Overflow { .. }) => return Err(e),
        // The inputs were checked finite: a non-finite stage value is an overflow.
        Err(
            DynamicsError::NonFinite { .. }
            | DynamicsError::Kinematics(kinetree_kinematics::KinematicsError::NonFinite { .. }),
        ) => {
            let dof = data.ddq.iter().position(|x| !x.is_finite()).unwrap_or(0);
            return Err(crate::error::overflow(
                model,
                data,
                "the integrator's stage state",
                dof,
                f64::NAN,
            ));
        }
        _ => {}
    }
    crate::error::check_output(model, data, "v", v)?;
    if let Some(k) = q.iter().position(|x| !x.is_finite()) {
        // q is indexed by configuration coordinates: name the body that holds index k.
        let dof = model
            .bodies()
            .iter()
            .skip(1)
            .find(|b| (b.idx_q..b.idx_q + b.nq).contains(&k))
            .map_or(0, |b| b.idx_v);
        return Err(crate::error::overflow(model, data, "q", dof, q[k]));
    }
    result
}

fn check_step(
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    dt: f64,
) -> Result<(), DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    check_vector("tau", tau, model.nv())?;
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(DynamicsError::InvalidTimeStep { dt });
    }
    Ok(())
}

#[allow(
    clippy::too_many_arguments,
    reason = "internal: the arguments of `step` plus the optional wrenches"
)]
fn run(
    model: &Model,
    data: &mut DynamicsData,
    integrator: Integrator,
    q: &mut [f64],
    v: &mut [f64],
    tau: &[f64],
    dt: f64,
    fext: Option<&ExternalForces>,
) -> Result<(), DynamicsError> {
    match integrator {
        Integrator::SemiImplicitEuler => {
            crate::aba::compute(model, data, q, v, tau, fext)?;
            for (vk, ak) in v.iter_mut().zip(&data.ddq) {
                *vk += dt * ak;
            }
            for (t, vk) in data.theta.iter_mut().zip(v.iter()) {
                *t = dt * vk;
            }
            data.q_stage.copy_from_slice(q);
            integrate(model, &data.q_stage, &data.theta, q)?;
        }
        Integrator::RungeKutta4 => rk4(model, data, q, v, tau, dt, fext)?,
    }
    Ok(())
}

/// Munthe-Kaas RK4: stage `s` evaluates at `q ⊕ θₛ`, with `θₛ = cₛ·dt·Kₛ₋₁` and
/// `Kₛ = dexp⁻¹(θₛ, vₛ)`; the step is `q ⊕ dt/6·(K₁ + 2K₂ + 2K₃ + K₄)`.
#[allow(
    clippy::too_many_arguments,
    reason = "internal: the arguments of `step` plus the optional wrenches"
)]
fn rk4(
    model: &Model,
    data: &mut DynamicsData,
    q: &mut [f64],
    v: &mut [f64],
    tau: &[f64],
    dt: f64,
    fext: Option<&ExternalForces>,
) -> Result<(), DynamicsError> {
    const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
    let nv = v.len();
    data.theta.fill(0.0);
    for s in 0..4 {
        // Stage state: q_stage = q ⊕ θ, v_stage = v + C[s]·dt·a_{s-1}.
        if s == 0 {
            data.q_stage.copy_from_slice(q);
            data.v_stage.copy_from_slice(v);
        } else {
            for k in 0..nv {
                data.theta[k] = C[s] * dt * data.k_vel[s - 1][k];
                data.v_stage[k] = v[k] + C[s] * dt * data.k_acc[s - 1][k];
            }
            integrate(model, q, &data.theta, &mut data.q_stage)?;
        }
        let q_stage = core::mem::take(&mut data.q_stage);
        let v_stage = core::mem::take(&mut data.v_stage);
        let result = crate::aba::compute(model, data, &q_stage, &v_stage, tau, fext);
        data.q_stage = q_stage;
        data.v_stage = v_stage;
        result?;
        data.k_acc[s].copy_from_slice(&data.ddq);
        // K_s = dexp⁻¹(θ_s)(v_s), per joint.
        let (k_vel, theta, v_stage) = (&mut data.k_vel[s], &data.theta, &data.v_stage);
        dexp_inv(model, data.kinematics.joint_models(), theta, v_stage, k_vel);
    }
    for k in 0..nv {
        let kv = &data.k_vel;
        let ka = &data.k_acc;
        data.theta[k] = dt / 6.0 * (kv[0][k] + 2.0 * kv[1][k] + 2.0 * kv[2][k] + kv[3][k]);
        v[k] += dt / 6.0 * (ka[0][k] + 2.0 * ka[1][k] + 2.0 * ka[2][k] + ka[3][k]);
    }
    data.q_stage.copy_from_slice(q);
    integrate(model, &data.q_stage, &data.theta, q)?;
    // Keep unit quaternions exactly unit (integrate already normalizes; this guards drift).
    configuration::normalize(model, q)?;
    Ok(())
}

/// `out = dexp⁻¹_{-θ}(ξ)` per joint ([`JointModel::dexp_inv`]), the tangent-space derivative
/// of `θ` for `q·exp(θ)` moving with body velocity `ξ`.
fn dexp_inv(
    model: &Model,
    joint_models: &[JointModel],
    theta: &[f64],
    xi: &[f64],
    out: &mut [f64],
) {
    for (b, jm) in model.bodies().iter().zip(joint_models).skip(1) {
        let r = b.idx_v..b.idx_v + b.nv;
        jm.dexp_inv(&theta[r.clone()], &xi[r.clone()], &mut out[r]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_steps_are_rejected() {
        let urdf = r#"<robot name="p"><link name="a"/><link name="b"><inertial><mass value="1"/>
            <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
            <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint></robot>"#;
        let model = Model::from_urdf_str(urdf, kinetree_kinematics::model::RootJoint::Fixed)
            .expect("valid URDF");
        let mut data = DynamicsData::new(&model);
        let (mut q, mut v) = (vec![0.0], vec![0.0]);
        for dt in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let r = step(
                &model,
                &mut data,
                Integrator::RungeKutta4,
                &mut q,
                &mut v,
                &[0.0],
                dt,
            );
            assert!(matches!(r, Err(DynamicsError::InvalidTimeStep { .. })));
        }
        let r = step(
            &model,
            &mut data,
            Integrator::SemiImplicitEuler,
            &mut q,
            &mut v,
            &[],
            1e-3,
        );
        assert!(matches!(
            r,
            Err(DynamicsError::DimensionMismatch { what: "tau", .. })
        ));
    }
}
