//! Derivatives of forward dynamics.

use super::data::{AbaDerivatives, DerivativesData};
use super::rnea::sweep;
use crate::error::{DynamicsError, check_vector};
use crate::external::ExternalForces;
use crate::factor::factorize;
use crate::rnea::check_inputs;
use kinetree_kinematics::model::Model;

/// The partial derivatives of forward dynamics `q̈ = aba(q, v, τ)`: `∂q̈/∂q` (in the tangent
/// space, see the [module documentation](crate::derivatives)), `∂q̈/∂v` and `∂q̈/∂τ = M(q)⁻¹`,
/// with `q̈` itself.
///
/// From `M(q)·q̈ + b(q, v) = τ`: `∂q̈/∂x = -M⁻¹·∂τ/∂x` with `∂τ/∂x` the inverse-dynamics
/// derivatives ([`rnea_derivatives`](crate::rnea_derivatives)) at `a = q̈`. `M⁻¹` comes from the
/// tree-sparse factorization of `M` (as [`mass_matrix_inverse`](crate::mass_matrix_inverse)) and
/// the products are tree-sparse solves on whole rows; no dense inverse, no finite
/// differences. The inverse-dynamics derivatives at `q̈` stay readable in `data`
/// ([`DerivativesData::dtau_dq`], …). Allocates nothing.
///
/// # Errors
/// [`DynamicsError::DimensionMismatch`] or [`DynamicsError::NonFinite`] for a bad `q`, `v` or
/// `tau`; [`DynamicsError::SingularMassMatrix`] when `M(q)` is singular;
/// [`DynamicsError::DataMismatch`] when `data` belongs to another model.
///
/// # Examples
/// ```
/// use kinetree_dynamics::{aba_derivatives, DerivativesData};
/// use kinetree_dynamics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A 1 kg point mass on a massless 0.5 m rod hinged about y: q̈ = (τ + m·g·l·cos θ) / (m·l²).
/// let urdf = r#"<robot name="pendulum"><link name="base"/>
///   <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
///     <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
///   <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = DerivativesData::new(&model);
/// let d = aba_derivatives(&model, &mut data, &[0.3], &[0.0], &[0.1])?;
/// assert!((d.dddq_dtau[0] - 4.0).abs() < 1e-12);
/// assert!((d.dddq_dq[0] + 9.81 * 0.5 * 0.3_f64.sin() * 4.0).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
pub fn aba_derivatives<'d>(
    model: &Model,
    data: &'d mut DerivativesData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
) -> Result<AbaDerivatives<'d>, DynamicsError> {
    compute(model, data, q, v, tau, None)
}

/// As [`aba_derivatives`], with wrenches applied by the environment (see [`ExternalForces`] and
/// [`rnea_derivatives_with_external_forces`](crate::rnea_derivatives_with_external_forces) for
/// how each kind of wrench moves with `q`).
///
/// # Errors
/// As [`aba_derivatives`]; [`DynamicsError::DataMismatch`] when `fext` belongs to another model.
pub fn aba_derivatives_with_external_forces<'d>(
    model: &Model,
    data: &'d mut DerivativesData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    fext: &ExternalForces,
) -> Result<AbaDerivatives<'d>, DynamicsError> {
    fext.check_model(model)?;
    compute(model, data, q, v, tau, Some(fext))
}

fn compute<'d>(
    model: &Model,
    data: &'d mut DerivativesData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    fext: Option<&ExternalForces>,
) -> Result<AbaDerivatives<'d>, DynamicsError> {
    check_inputs(model, &data.dynamics, q, Some(v), None)?;
    check_vector("tau", tau, model.nv())?;
    crate::aba::compute(model, &mut data.dynamics, q, v, tau, fext)?;
    let ddq = core::mem::take(&mut data.ddq);
    let mut ddq = ddq;
    ddq.copy_from_slice(&data.dynamics.ddq);
    let mut dq = core::mem::take(&mut data.dtau_dq);
    sweep::<true>(model, data, q, v, &ddq, fext, &mut dq);
    data.dtau_dq = dq;
    data.ddq = ddq;
    let dynamics = &mut data.dynamics;
    dynamics.mass_matrix.copy_from_slice(&data.dtau_da);
    factorize(model, dynamics)?;
    let factor = &data.dynamics.factor;
    data.tree
        .invert(factor, &mut data.dynamics.mass_matrix_inverse);
    data.tree.neg_solve_pair(
        factor,
        &data.dtau_dq,
        &data.dtau_dv,
        &mut data.dddq_dq,
        &mut data.dddq_dv,
    );
    Ok(AbaDerivatives {
        ddq: &data.ddq,
        dddq_dq: &data.dddq_dq,
        dddq_dv: &data.dddq_dv,
        dddq_dtau: &data.dynamics.mass_matrix_inverse,
    })
}
