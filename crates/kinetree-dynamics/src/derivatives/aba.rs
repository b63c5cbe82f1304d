//! Derivatives of forward dynamics.

use super::data::Articulated;
use super::data::{AbaDerivatives, DerivativesData};
use super::rnea::{apply_external, backward, forward_acceleration, forward_velocity};
use super::solve::DofTree;
use crate::data::sign;
use crate::error::{DynamicsError, check_vector};
use crate::external::ExternalForces;
use crate::factor::PIVOT_TOLERANCE;
use crate::rnea::check_inputs;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::{Force, Motion};

/// The partial derivatives of forward dynamics `q̈ = aba(q, v, τ)`: `∂q̈/∂q` (in the tangent
/// space, see the [module documentation](crate::derivatives)), `∂q̈/∂v` and `∂q̈/∂τ = M(q)⁻¹`,
/// with `q̈` itself.
///
/// From `M(q)·q̈ + b(q, v) = τ`: `∂q̈/∂x = -M⁻¹·∂τ/∂x` with `∂τ/∂x` the inverse-dynamics
/// derivatives ([`rnea_derivatives`](crate::rnea_derivatives)) at `a = q̈`. One set of sweeps
/// does it all: the placements and velocities are computed once, the articulated-body pass
/// gives `q̈` and the tree-sparse factorization `M = Lᵀ·D·L` together, the accelerations at `q̈`
/// feed the inverse-dynamics derivatives, and `M⁻¹` and the products are tree-sparse solves on
/// whole rows; no dense inverse, no finite differences. The inverse-dynamics derivatives at `q̈`
/// stay readable in `data` ([`DerivativesData::dtau_dq`], …). Allocates nothing.
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
    kinetree_kinematics::with_simd!(
        kernel[],
        (
            model: &Model = model,
            data: &mut DerivativesData = data,
            q: &[f64] = q,
            v: &[f64] = v,
            tau: &[f64] = tau,
            fext: Option<&ExternalForces> = fext,
        ) -> Result<(), DynamicsError>
    )?;
    // An overflow (finite inputs, huge lengths or velocities) is an error, never NaN in an Ok.
    for (what, x) in [
        ("ddq", &data.ddq),
        ("dddq_dq", &data.dddq_dq),
        ("dddq_dv", &data.dddq_dv),
        ("dddq_dtau", &data.dynamics.mass_matrix_inverse),
    ] {
        crate::error::check_output(model, &data.dynamics, what, x)?;
    }
    Ok(AbaDerivatives {
        ddq: &data.ddq,
        dddq_dq: &data.dddq_dq,
        dddq_dv: &data.dddq_dv,
        dddq_dtau: &data.dynamics.mass_matrix_inverse,
    })
}

/// The sweeps and solves of [`compute`], compiled for AVX-512 or AVX2 where the CPU has it (no
/// FMA, no reordering: the results are the portable build's bit for bit).
#[inline(always)]
fn kernel(
    model: &Model,
    data: &mut DerivativesData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    fext: Option<&ExternalForces>,
) -> Result<(), DynamicsError> {
    forward_velocity(model, data, q, v);
    let has_external = apply_external(data, fext);
    data.dynamics.factorized = false;
    articulated(model, data, v, tau)?;
    // Forward: q̈ = aba(q, v, τ), and with it the accelerations and forces of the derivatives.
    let mut ddq = core::mem::take(&mut data.ddq);
    let a0 = Motion::new(-model.gravity(), DVec3::ZERO);
    let bodies = model.bodies();
    for i in 1..bodies.len() {
        let b = &bodies[i];
        let ap = if b.parent == 0 {
            a0
        } else {
            data.acceleration[b.parent]
        };
        let mut ai = ap + data.bias[i];
        for d in b.idx_v..b.idx_v + b.nv {
            let qdd = data.pivot_inverse[d] * (data.u[d] - ai.dot(&data.u_column[d]));
            ddq[d] = qdd;
            ai += data.s[d] * qdd;
        }
        forward_acceleration(data, i, b, ap, ai);
    }
    let mut dq = core::mem::take(&mut data.dtau_dq);
    backward::<true>(model, data, v, &ddq, has_external, &mut dq);
    data.dtau_dq = dq;
    data.ddq = ddq;
    let dynamics = &mut data.dynamics;
    dynamics.mass_matrix.copy_from_slice(&data.dtau_da);
    dynamics.factorized = true;
    solve(
        &mut data.tree,
        &dynamics.factor,
        &mut dynamics.mass_matrix_inverse,
        &data.dtau_dq,
        &data.dtau_dv,
        &mut data.dddq_dq,
        &mut data.dddq_dv,
    );
    Ok(())
}

/// `M⁻¹` and `-M⁻¹·∂τ/∂q`, `-M⁻¹·∂τ/∂v` from the factor.
#[inline(always)]
fn solve(
    tree: &mut DofTree,
    factor: &[f64],
    inverse: &mut [f64],
    dtau_dq: &[f64],
    dtau_dv: &[f64],
    dddq_dq: &mut [f64],
    dddq_dv: &mut [f64],
) {
    tree.invert(factor, inverse);
    tree.neg_solve_pair(factor, dtau_dq, dtau_dv, dddq_dq, dddq_dv);
}

/// Backward pass of the articulated-body algorithm in world coordinates, one degree of freedom
/// at a time (a joint with several is a chain of one-degree-of-freedom joints, the last one
/// eliminated first): `U = Iᴬ·s`, `D = sᵀ·U` (plus the armature), `u = τ - sᵀ·pᴬ` (minus damping
/// and friction), then `Iᴬ -= U·Uᵀ/D` and `pᴬ += U·u/D`, carried to the parent with the
/// velocity-product bias.
///
/// These pivots are those of the tree-sparse factorization `M = Lᵀ·D·L` eliminated from the
/// leaves, and its off-diagonal entries follow at once: once the subtree below a degree of
/// freedom `i` is eliminated it acts as the rigid inertia `Iᴬ` on `i`'s body, so
/// `L[i][j] = s_jᵀ·U_i / D_i` for every ancestor `j`. They are written into
/// `data.dynamics.factor`, so no mass matrix needs factorizing.
#[inline(always)]
fn articulated(
    model: &Model,
    data: &mut DerivativesData,
    v: &[f64],
    tau: &[f64],
) -> Result<(), DynamicsError> {
    let nv = data.nv;
    let bodies = model.bodies();
    data.articulated.fill(Articulated::ZERO);
    data.articulated_force.fill(Force::ZERO);
    let dynamics = &mut data.dynamics;
    let factor = &mut dynamics.factor;
    let mut singular: Vec<usize> = Vec::new();
    for i in (1..bodies.len()).rev() {
        let b = &bodies[i];
        let mut ia = data.articulated[i];
        ia.add_rigid(&data.composite[i]);
        let mut pa = data.articulated_force[i] + data.force[i];
        for d in (b.idx_v..b.idx_v + b.nv).rev() {
            let s = data.s[d];
            let u_col = ia.mul(&s);
            let mut pivot = s.dot(&u_col);
            let mut u = tau[d] - s.dot(&pa);
            if dynamics.has_joint_terms {
                pivot += dynamics.armature[d];
                u -= dynamics.damping[d] * v[d] + dynamics.friction[d] * sign(v[d]);
            }
            let inverse = if pivot > PIVOT_TOLERANCE * ia.scale() {
                1.0 / pivot
            } else {
                singular.push(d);
                0.0
            };
            let row = &mut factor[d * nv..(d + 1) * nv];
            row[d] = pivot;
            for &j in data.tree.ancestors(d) {
                row[j] = data.s[j].dot(&u_col) * inverse;
            }
            data.u_column[d] = u_col;
            data.pivot_inverse[d] = inverse;
            data.u[d] = u;
            ia.sub_outer(&u_col, &(u_col * inverse));
            pa += u_col * (inverse * u);
        }
        let p = b.parent;
        if p != 0 {
            pa += ia.mul(&data.bias[i]);
            data.articulated[p].add_assign(&ia);
            data.articulated_force[p] += pa;
        }
    }
    if singular.is_empty() {
        Ok(())
    } else {
        // A bias force that is not finite is an overflow (huge lengths or velocities), not a
        // massless subtree.
        if let Some(i) = (1..model.bodies().len()).find(|&i| !data.articulated_force[i].is_finite())
        {
            let dof = model.bodies()[i].idx_v;
            return Err(crate::error::overflow(
                model,
                &data.dynamics,
                "the articulated bias force",
                dof,
                f64::NAN,
            ));
        }
        singular.sort_unstable();
        Err(DynamicsError::SingularMassMatrix {
            joints: data.dynamics.joint_names(model, &singular),
        })
    }
}
