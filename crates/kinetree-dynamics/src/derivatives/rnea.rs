//! Derivatives of inverse dynamics and of the generalized gravity.

use super::data::{Blocks, DerivativesData, RneaDerivatives, WorldInertia, skew};
use crate::data::sign;
use crate::error::DynamicsError;
use crate::external::ExternalForces;
use crate::rnea::check_inputs;
use kinetree_kinematics::ReferenceFrame;
use kinetree_kinematics::model::{Body, Model};
use kinetree_kinematics::spatial::glam::{DMat3, DVec3};
use kinetree_kinematics::spatial::{Force, Motion};

/// The partial derivatives of inverse dynamics `τ = rnea(q, v, a)`: `∂τ/∂q` (in the tangent
/// space, see the [module documentation](crate::derivatives)), `∂τ/∂v` and `∂τ/∂a = M(q)`, all
/// in one pass, with `τ` itself.
///
/// `q` has length `model.nq()`, `v` and `a` length `model.nv()`. The results are stored in
/// `data` and borrowed in the returned [`RneaDerivatives`]. O(n·depth); allocates nothing.
///
/// # Errors
/// [`DynamicsError::DimensionMismatch`] or [`DynamicsError::NonFinite`] for a bad `q`, `v` or
/// `a`; [`DynamicsError::DataMismatch`] when `data` belongs to another model.
///
/// # Examples
/// ```
/// use kinetree_dynamics::{rnea_derivatives, DerivativesData};
/// use kinetree_dynamics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A 1 kg point mass on a massless 0.5 m rod hinged about y: g(θ) = -m·g·l·cos θ.
/// let urdf = r#"<robot name="pendulum"><link name="base"/>
///   <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
///     <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
///   <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = DerivativesData::new(&model);
/// let d = rnea_derivatives(&model, &mut data, &[0.3], &[0.0], &[0.0])?;
/// // ∂τ/∂θ = m·g·l·sin θ, and ∂τ/∂a is the inertia m·l².
/// assert!((d.dtau_dq[0] - 9.81 * 0.5 * 0.3_f64.sin()).abs() < 1e-12);
/// assert!((d.dtau_da[0] - 0.25).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
pub fn rnea_derivatives<'d>(
    model: &Model,
    data: &'d mut DerivativesData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<RneaDerivatives<'d>, DynamicsError> {
    check_inputs(model, &data.dynamics, q, Some(v), Some(a))?;
    let mut dq = core::mem::take(&mut data.dtau_dq);
    // In AVX-512 or AVX2 where the CPU has them (the results are the portable build's bit for
    // bit).
    let bounded = kinetree_kinematics::with_simd!(
        sweep_full[],
        (
            model: &Model = model,
            data: &mut DerivativesData = data,
            q: &[f64] = q,
            v: &[f64] = v,
            a: &[f64] = a,
            fext: Option<&ExternalForces> = None,
            dq: &mut [f64] = &mut dq,
        ) -> bool
    );
    data.dtau_dq = dq;
    check_rnea_outputs(model, data, bounded)?;
    Ok(data.rnea_result())
}

/// As [`rnea_derivatives`], with wrenches applied by the environment (see [`ExternalForces`]):
/// the derivatives of `τ = rnea(q, v, a) - Σ Jᵀ·f`. A wrench given in
/// [`ReferenceFrame::Local`] turns with its link; one given in [`ReferenceFrame::World`] stays
/// fixed in the world; one in [`ReferenceFrame::LocalWorldAligned`] keeps its world direction
/// and moves with its point of application.
///
/// # Errors
/// As [`rnea_derivatives`]; [`DynamicsError::DataMismatch`] when `fext` belongs to another
/// model.
pub fn rnea_derivatives_with_external_forces<'d>(
    model: &Model,
    data: &'d mut DerivativesData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    fext: &ExternalForces,
) -> Result<RneaDerivatives<'d>, DynamicsError> {
    check_inputs(model, &data.dynamics, q, Some(v), Some(a))?;
    fext.check_model(model)?;
    let mut dq = core::mem::take(&mut data.dtau_dq);
    // In AVX-512 or AVX2 where the CPU has them (the results are the portable build's bit for
    // bit).
    let bounded = kinetree_kinematics::with_simd!(
        sweep_full[],
        (
            model: &Model = model,
            data: &mut DerivativesData = data,
            q: &[f64] = q,
            v: &[f64] = v,
            a: &[f64] = a,
            fext: Option<&ExternalForces> = Some(fext),
            dq: &mut [f64] = &mut dq,
        ) -> bool
    );
    data.dtau_dq = dq;
    check_rnea_outputs(model, data, bounded)?;
    Ok(data.rnea_result())
}

/// The derivative `∂g/∂q` of the generalized gravity `g(q)` (`nv x nv`, row-major, tangent
/// space), stored in `data` and returned. Allocates nothing.
///
/// # Errors
/// As [`rnea_derivatives`], for `q`.
pub fn generalized_gravity_derivatives<'d>(
    model: &Model,
    data: &'d mut DerivativesData,
    q: &[f64],
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, &data.dynamics, q, None, None)?;
    let mut dq = core::mem::take(&mut data.dg_dq);
    let zeros = core::mem::take(&mut data.zeros);
    let bounded = sweep::<false>(model, data, q, &zeros, &zeros, None, &mut dq);
    data.zeros = zeros;
    data.dg_dq = dq;
    if !bounded {
        crate::error::check_output(model, &data.dynamics, "dg_dq", &data.dg_dq)?;
    }
    Ok(&data.dg_dq)
}

/// An overflow (finite inputs, huge lengths or velocities) is an error, never NaN in an `Ok`.
///
/// `τ` is scanned. The matrices are scanned only when the sweep could not bound them
/// (`bounded`, see [`backward`]), apart from the diagonals the joint terms add to.
fn check_rnea_outputs(
    model: &Model,
    data: &DerivativesData,
    bounded: bool,
) -> Result<(), DynamicsError> {
    crate::error::check_output(model, &data.dynamics, "tau", &data.tau)?;
    let matrices = [
        ("dtau_dq", &data.dtau_dq),
        ("dtau_dv", &data.dtau_dv),
        ("dtau_da", &data.dtau_da),
    ];
    if !bounded {
        for (what, x) in matrices {
            crate::error::check_output(model, &data.dynamics, what, x)?;
        }
    } else if data.dynamics.has_joint_terms {
        let nv = data.nv;
        for (what, x) in &matrices[1..] {
            if let Some(k) = (0..nv).find(|&k| !x[k * nv + k].is_finite()) {
                return Err(crate::error::overflow(
                    model,
                    &data.dynamics,
                    what,
                    k,
                    x[k * nv + k],
                ));
            }
        }
    }
    Ok(())
}

/// `|x|` summed with `|y|`, component-wise, for the bounds of [`backward`].
#[inline(always)]
fn abs2(x: DVec3, y: DVec3) -> DVec3 {
    x.abs() + y.abs()
}

/// `Bᵀ·s` for the inertia-variation operator `B = [[0, -2[p]×], [0, d]]` of a subtree with
/// linear momentum `p`.
#[inline(always)]
fn variation_transpose(p: DVec3, d: &DMat3, s: &Motion) -> Force {
    Force::new(
        DVec3::ZERO,
        2.0 * p.cross(s.linear) + d.transpose() * s.angular,
    )
}

/// `B·w` for the same operator.
#[inline(always)]
fn variation_mul(p: DVec3, d: &DMat3, w: &Motion) -> Force {
    Force::new(-2.0 * p.cross(w.angular), *d * w.angular)
}

/// The angular-angular block of the inertia variation of a body with world inertia `y` moving
/// with twist `v` (momentum `h = y·v`): the map `w ↦ v ×* (Y·w) - Y·(v × w) + w ×* h` is
/// `[[0, -2[h_lin]×], [0, d]]` with this `d`.
#[inline(always)]
fn variation_block(y: &WorldInertia, v: &Motion, h: &Force) -> DMat3 {
    let (vl, vw) = (skew(v.linear), skew(v.angular));
    let hx = skew(y.h);
    vw * y.i - y.i * vw - (vl * hx + hx * vl) - skew(h.angular)
}

/// The sweeps. With `FULL`, `∂τ/∂v` and `∂τ/∂a` are written too (else only `∂τ/∂q`, into `dq`).
/// True when every matrix entry written is proven finite (see [`backward`]).
/// [`sweep`] with every matrix, to be compiled for the instruction set it runs with.
#[inline(always)]
fn sweep_full(
    model: &Model,
    data: &mut DerivativesData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    fext: Option<&ExternalForces>,
    dq: &mut [f64],
) -> bool {
    sweep::<true>(model, data, q, v, a, fext, dq)
}

#[inline(always)]
pub(super) fn sweep<const FULL: bool>(
    model: &Model,
    data: &mut DerivativesData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    fext: Option<&ExternalForces>,
    dq: &mut [f64],
) -> bool {
    forward_velocity(model, data, q, v);
    let has_external = apply_external(data, fext);
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
            ai += data.s[d] * a[d];
        }
        forward_acceleration(data, i, b, ap, ai);
    }
    backward::<FULL>(model, data, v, a, has_external, dq)
}

/// Forward, what does not depend on the acceleration: placements, velocities, the velocity
/// product bias `c = v_parent × v_joint`, rigid inertias, bias forces `v × (Y·v)` and the
/// per-column derivatives of velocity.
#[inline(always)]
pub(super) fn forward_velocity(model: &Model, data: &mut DerivativesData, q: &[f64], v: &[f64]) {
    let bodies = model.bodies();
    let joint_models = data.dynamics.kinematics.joint_models();
    for i in 1..bodies.len() {
        let b = &bodies[i];
        let jm = &joint_models[i];
        let x = jm.placed_transform(&b.placement, &q[b.idx_q..b.idx_q + b.nq]);
        let p = b.parent;
        let (omi, vp) = if p == 0 {
            (x, Motion::ZERO)
        } else {
            (data.world_from_body[p] * x, data.velocity[p])
        };
        data.world_from_body[i] = omi;
        let mut vj = Motion::ZERO;
        for k in 0..b.nv {
            let d = b.idx_v + k;
            let s = omi.act_motion(&jm.subspace_column(k));
            data.s[d] = s;
            vj += s * v[d];
            data.dv_dq[d] = vp.cross_motion(&s);
        }
        let vi = vp + vj;
        for d in b.idx_v..b.idx_v + b.nv {
            data.da_dv[d] = vi.cross_motion(&data.s[d]) + data.dv_dq[d];
        }
        let inertia = b.inertia.transformed(&omi);
        let c = inertia.com;
        let y = WorldInertia {
            m: inertia.mass,
            h: c * inertia.mass,
            i: inertia.rotational.to_mat3()
                + (DMat3::from_diagonal(DVec3::splat(c.length_squared()))
                    - DMat3::from_cols(c * c.x, c * c.y, c * c.z))
                    * inertia.mass,
        };
        let h = y.mul(&vi);
        data.velocity[i] = vi;
        data.bias[i] = vp.cross_motion(&vj);
        data.force[i] = vi.cross_force(&h);
        data.momentum[i] = h.linear;
        data.variation[i] = variation_block(&y, &vi, &h);
        data.composite[i] = y;
        data.external[i] = Blocks::ZERO;
    }
}

/// Forward, for body `i` (`b`) with parent acceleration `ap` and acceleration `ai` (gravity
/// included): stores `ai`, adds `Y·ai` to the body's force and fills the per-column
/// derivatives of acceleration.
#[inline(always)]
pub(super) fn forward_acceleration(
    data: &mut DerivativesData,
    i: usize,
    b: &Body,
    ap: Motion,
    ai: Motion,
) {
    let vp = if b.parent == 0 {
        Motion::ZERO
    } else {
        data.velocity[b.parent]
    };
    for d in b.idx_v..b.idx_v + b.nv {
        data.da_dq[d] = ap.cross_motion(&data.s[d]) + vp.cross_motion(&data.dv_dq[d]);
    }
    data.acceleration[i] = ai;
    let f = data.composite[i].mul(&ai);
    data.force[i] += f;
}

/// Subtracts the external wrenches from the bodies' forces and records the parts of their
/// derivatives that the rigid motion of the bodies does not explain; whether there were any.
#[inline(always)]
pub(super) fn apply_external(data: &mut DerivativesData, fext: Option<&ExternalForces>) -> bool {
    let mut has_external = false;
    if let Some(fext) = fext {
        let force = &mut data.force;
        let external = &mut data.external;
        fext.for_each_world_with_point(&data.world_from_body, |body, f, reference, point| {
            force[body] -= f;
            // The part of the wrench's derivative that the rigid motion of the body does not
            // explain, negated (the wrench is subtracted).
            let e = match reference {
                ReferenceFrame::Local => return,
                // Fixed in the world: -(s ×* f) is missing.
                ReferenceFrame::World => Blocks {
                    b: -skew(f.linear),
                    c: -skew(f.linear),
                    d: -skew(f.angular),
                },
                // Fixed direction, moving point: the force -(ω × F) at the point is missing.
                ReferenceFrame::LocalWorldAligned => {
                    let fx = skew(f.linear);
                    let torque = f.angular - point.cross(f.linear);
                    Blocks {
                        b: -fx,
                        c: DMat3::ZERO,
                        d: -skew(point) * fx - skew(torque),
                    }
                }
            };
            external[body].add_assign(&e);
            has_external = true;
        });
    }
    has_external
}

/// Backward: composite quantities and the matrix rows (the forward passes done at `a`).
///
/// Only the entries that can be nonzero are written: row `r` at the columns of its joint's
/// subtree and of its ancestors. The others are the same for every call and stay at the zero
/// the buffers were made with.
///
/// Returns true when every entry written is proven finite without reading the matrices back.
/// Each entry is a sum of products `Σ aₖ·bₖ` (plus the joint terms on the diagonal, which
/// are not covered): a left factor (`s` of the row, or `Y·s`, `Bᵀ·s` and `Eᵀ·s` of a row
/// against its ancestors) against right factors (the force and acceleration derivatives of
/// the columns). So `|entry| ≤ L·R` with `L` the sum of `|aₖ|` over every left factor and
/// `R` the sum of `|bₖ|` over every right factor; both sums are accumulated on the way, and
/// `L·R < 1e300` (false for an infinite or NaN sum) proves every entry finite with rounding
/// to spare. Otherwise the caller scans the matrices.
#[inline(always)]
pub(super) fn backward<const FULL: bool>(
    model: &Model,
    data: &mut DerivativesData,
    v: &[f64],
    a: &[f64],
    has_external: bool,
    dq: &mut [f64],
) -> bool {
    let nv = data.nv;
    let bodies = model.bodies();
    let nb = bodies.len();
    let (mut left, mut right) = (DVec3::ZERO, DVec3::ZERO);
    // Backward: composite quantities and the matrix rows.
    for i in (1..nb).rev() {
        let b = &bodies[i];
        let (f, y, pm, dm, e) = (
            data.force[i],
            data.composite[i],
            data.momentum[i],
            data.variation[i],
            data.external[i],
        );
        let r0 = b.idx_v;
        let r1 = r0 + b.nv;
        let c1 = r0 + data.nv_subtree[i];
        for d in r0..r1 {
            let s = data.s[d];
            data.tau[d] = s.dot(&f);
            let mut fq = y.mul(&data.da_dq[d]) + variation_mul(pm, &dm, &data.dv_dq[d]);
            if has_external {
                fq += e.mul(&s);
            }
            data.df_dq[d] = fq;
            let sa = abs2(s.linear, s.angular);
            left += sa;
            right += sa
                + abs2(fq.linear, fq.angular)
                + abs2(data.da_dq[d].linear, data.da_dq[d].angular)
                + abs2(data.dv_dq[d].linear, data.dv_dq[d].angular);
            if FULL {
                let (fa, fv) = (
                    y.mul(&s),
                    y.mul(&data.da_dv[d]) + variation_mul(pm, &dm, &s),
                );
                data.df_da[d] = fa;
                data.df_dv[d] = fv;
                right += abs2(fa.linear, fa.angular)
                    + abs2(fv.linear, fv.angular)
                    + abs2(data.da_dv[d].linear, data.da_dv[d].angular);
            }
        }
        // Rows of this joint, columns of its subtree (itself included).
        for r in r0..r1 {
            let s = data.s[r];
            let row = r * nv;
            for c in r0..c1 {
                dq[row + c] = s.dot(&data.df_dq[c]);
            }
            if FULL {
                for c in r0..c1 {
                    data.dtau_dv[row + c] = s.dot(&data.df_dv[c]);
                    data.dtau_da[row + c] = s.dot(&data.df_da[c]);
                }
            }
        }
        for d in r0..r1 {
            let fq = data.df_dq[d] + data.s[d].cross_force(&f);
            data.df_dq[d] = fq;
            right += abs2(fq.linear, fq.angular);
        }
        // Rows of this joint, columns of its strict ancestors (a slice, so the loads of one
        // column do not wait for the previous column's parent index).
        let ancestors = if b.nv > 0 {
            data.tree.ancestors(r0)
        } else {
            &[]
        };
        if !ancestors.is_empty() {
            for r in r0..r1 {
                let s = data.s[r];
                let ys = y.mul(&s);
                let bs = variation_transpose(pm, &dm, &s);
                let es = if has_external {
                    e.mul_transpose(&s)
                } else {
                    Force::ZERO
                };
                left += abs2(ys.linear, ys.angular)
                    + abs2(bs.linear, bs.angular)
                    + abs2(es.linear, es.angular);
                let row = r * nv;
                for &j in ancestors {
                    let sj = &data.s[j];
                    let mut x = ys.dot(&data.da_dq[j]) + bs.dot(&data.dv_dq[j]);
                    if has_external {
                        x += es.dot(sj);
                    }
                    dq[row + j] = x;
                    if FULL {
                        data.dtau_dv[row + j] = ys.dot(&data.da_dv[j]) + bs.dot(sj);
                        data.dtau_da[row + j] = ys.dot(sj);
                    }
                }
            }
        }
        let p = b.parent;
        if p != 0 {
            data.force[p] += f;
            data.composite[p].add_assign(&y);
            data.momentum[p] += pm;
            data.variation[p] += dm;
            if has_external {
                data.external[p].add_assign(&e);
            }
        }
    }
    let dynamics = &data.dynamics;
    if FULL && dynamics.has_joint_terms {
        for k in 0..nv {
            data.tau[k] += dynamics.armature[k] * a[k]
                + dynamics.damping[k] * v[k]
                + dynamics.friction[k] * sign(v[k]);
            data.dtau_da[k * nv + k] += dynamics.armature[k];
            // Friction's sign(v) contributes nothing (zero derivative, also at v = 0).
            data.dtau_dv[k * nv + k] += dynamics.damping[k];
        }
    }
    left.element_sum() * right.element_sum() < 1e300
}
