//! Each joint's configuration manifold: integration `q ⊕ v`, difference `q₁ ⊖ q₀`, and the
//! inverse differential of the exponential `dexp⁻¹` that integrators need.
//!
//! Per joint kind (see [`kinetree_model::JointKind`] for the q/v layouts):
//! - revolute, prismatic: the real line; `integrate` adds.
//! - continuous: the circle; `difference` is wrapped to (-π, π] so it follows the short way
//!   round.
//! - cylindrical: line × circle (no wrapping of the angle: it may carry limits).
//! - spherical: SO(3), `q ⊕ ω = q · exp(ω)` with ω in the child frame.
//! - planar: SE(2) with the velocity in the child frame, `q ⊕ v = q · exp(v)`.
//! - floating: SE(3) with the twist in the child frame, `q ⊕ v = q · exp6(v)` (Pinocchio's
//!   convention).
//!
//! ## Jacobians of integrate and difference
//!
//! Derivatives with respect to a configuration are taken in the tangent space, as everywhere in
//! kinetree: column `k` of `∂f/∂q` is `d f(q ⊕ ε·e_k)/dε` at 0, and a configuration-valued result
//! is differentiated in the tangent space at the result (`(q ⊕ v) ⊕ δ`). So every Jacobian is
//! `nv x nv`, row-major and block-diagonal (one block per joint). For the vector-space joints
//! (revolute, prismatic, continuous, cylindrical) the blocks are `±1`; for the Lie groups
//! (spherical SO(3), planar SE(2), floating SE(3), all with velocities in the child frame):
//! - `∂(q ⊕ v)/∂q = Ad(exp v)⁻¹` and `∂(q ⊕ v)/∂v = J_r(v)`, the right Jacobian of `exp`;
//! - `∂(q₁ ⊖ q₀)/∂q₁ = J_r(d)⁻¹` and `∂(q₁ ⊖ q₀)/∂q₀ = -J_l(d)⁻¹`, with `d = q₁ ⊖ q₀`.

use super::model::{JointModel, quat};
use crate::error::{KinematicsError, check_vector};
use glam::{DMat3, DQuat, DVec3};
use kinetree_model::spatial::explog::{so3_left_jacobian, so3_left_jacobian_inverse};
use kinetree_model::spatial::rotation::{exp3, skew};
use kinetree_model::spatial::{Motion, Se3, explog, rotation};
use kinetree_model::{JointKind, Model};
use std::f64::consts::PI;

/// The SE(2) exponential of a body velocity `(vx, vy, ω)`: the local displacement `(dx, dy)`.
fn se2_exp_translation(vx: f64, vy: f64, w: f64) -> (f64, f64) {
    let (a, b) = se2_v(w);
    (a * vx - b * vy, b * vx + a * vy)
}

/// Entries of `V(ω) = [[a, -b], [b, a]]` with `a = sin ω / ω`, `b = (1 - cos ω)/ω`.
fn se2_v(w: f64) -> (f64, f64) {
    if w.abs() < 1e-6 {
        (1.0 - w * w / 6.0, w / 2.0 - w * w * w / 24.0)
    } else {
        let half = (0.5 * w).sin();
        (w.sin() / w, 2.0 * half * half / w)
    }
}

fn floating_pose(q: &[f64]) -> Se3 {
    Se3::from_translation_quat(DVec3::new(q[0], q[1], q[2]), quat(&q[3..7]).normalize())
}

fn write_floating(t: &Se3, q: &mut [f64]) {
    q[..3].copy_from_slice(&t.translation.to_array());
    q[3..7].copy_from_slice(&DQuat::from_mat3(&t.rotation).normalize().to_array());
}

/// `q ⊕ v` for one joint's blocks (lengths `kind.nq()`, `kind.nv()`, `kind.nq()`).
///
/// # Panics
/// When a block is shorter than the kind requires.
pub fn integrate_joint(kind: JointKind, qi: &[f64], vi: &[f64], qo: &mut [f64]) {
    match kind {
        JointKind::Fixed => {}
        JointKind::Revolute
        | JointKind::Continuous
        | JointKind::Prismatic
        | JointKind::Cylindrical => {
            for k in 0..kind.nq() {
                qo[k] = qi[k] + vi[k];
            }
        }
        JointKind::Spherical => {
            let r = quat(qi).normalize() * DQuat::from_scaled_axis(DVec3::new(vi[0], vi[1], vi[2]));
            qo[..4].copy_from_slice(&r.normalize().to_array());
        }
        JointKind::Planar => {
            let (dx, dy) = se2_exp_translation(vi[0], vi[1], vi[2]);
            let (s, c) = qi[2].sin_cos();
            qo[0] = qi[0] + c * dx - s * dy;
            qo[1] = qi[1] + s * dx + c * dy;
            qo[2] = qi[2] + vi[2];
        }
        JointKind::Floating => {
            let t = floating_pose(qi) * explog::exp6(&Motion::from_slice(vi));
            write_floating(&t, qo);
        }
    }
}

/// The velocity taking `a` to `c` for one joint's blocks (see
/// [`configuration::difference`](crate::configuration::difference)).
///
/// # Panics
/// When a block is shorter than the kind requires.
pub fn difference_joint(kind: JointKind, a: &[f64], c: &[f64], vo: &mut [f64]) {
    match kind {
        JointKind::Fixed => {}
        JointKind::Continuous => vo[0] = wrap_angle(c[0] - a[0]),
        JointKind::Revolute | JointKind::Prismatic | JointKind::Cylindrical => {
            for k in 0..kind.nq() {
                vo[k] = c[k] - a[k];
            }
        }
        JointKind::Spherical => {
            let r0 = glam::DMat3::from_quat(quat(a).normalize());
            let r1 = glam::DMat3::from_quat(quat(c).normalize());
            vo[..3].copy_from_slice(&rotation::log3(&(r0.transpose() * r1)).to_array());
        }
        JointKind::Planar => {
            let w = c[2] - a[2];
            let (s, co) = a[2].sin_cos();
            let (dx, dy) = (c[0] - a[0], c[1] - a[1]);
            let (lx, ly) = (co * dx + s * dy, -s * dx + co * dy);
            let (p, m) = se2_v(w);
            let det = p * p + m * m;
            vo[0] = (p * lx + m * ly) / det;
            vo[1] = (-m * lx + p * ly) / det;
            vo[2] = w;
        }
        JointKind::Floating => {
            let d = explog::log6(&floating_pose(a).inv_mul(&floating_pose(c)));
            d.write_to_slice(vo);
        }
    }
}

/// Wraps an angle to (-π, π].
#[inline]
#[must_use]
pub fn wrap_angle(x: f64) -> f64 {
    let y = x.rem_euclid(2.0 * PI);
    if y > PI { y - 2.0 * PI } else { y }
}

impl JointModel {
    /// `out = dexp⁻¹_{-θ}(ξ) ≈ ξ + ½[θ, ξ] + 1/12·[θ, [θ, ξ]]` for this joint's velocity blocks
    /// `theta`, `xi` (length `nv()`): the rate of `θ` for `q·exp(θ)` moving with body velocity
    /// `ξ`, to third order in `θ` (as the Munthe-Kaas integrators need). Vector-space joints
    /// (revolute, prismatic, cylindrical) commute: `out = ξ`.
    #[inline]
    pub fn dexp_inv(&self, theta: &[f64], xi: &[f64], out: &mut [f64]) {
        if !matches!(self, Self::Spherical | Self::Planar { .. } | Self::Floating) {
            out.copy_from_slice(xi);
            return;
        }
        let t = self.motion(theta);
        let x = self.motion(xi);
        let tx = t.cross_motion(&x);
        let corrected = x + tx * 0.5 + t.cross_motion(&tx) * (1.0 / 12.0);
        // The joint coordinates of a twist in the span of the (orthonormal) motion subspace.
        for (k, o) in out.iter_mut().enumerate() {
            let s = self.subspace_column(k);
            *o = s.linear.dot(corrected.linear) + s.angular.dot(corrected.angular);
        }
    }
}

/// A 6x6 matrix in 3x3 blocks `[[a, b], [c, d]]` acting on `[linear; angular]`.
#[derive(Clone, Copy)]
struct Mat6 {
    a: DMat3,
    b: DMat3,
    c: DMat3,
    d: DMat3,
}

impl Mat6 {
    fn get(&self, r: usize, c: usize) -> f64 {
        let m = match (r < 3, c < 3) {
            (true, true) => &self.a,
            (true, false) => &self.b,
            (false, true) => &self.c,
            (false, false) => &self.d,
        };
        m.col(c % 3)[r % 3]
    }
}

/// Sum of a power series in `θ²`: `Σ coefficients[k]·θ^{2k}`.
fn series(theta2: f64, coefficients: &[f64]) -> f64 {
    coefficients
        .iter()
        .rev()
        .fold(0.0, |acc, c| acc * theta2 + c)
}

/// Barfoot's `Q(ρ, φ)`: the upper-right block of the SE(3) left Jacobian `[[J, Q], [0, J]]`.
fn se3_q(rho: DVec3, phi: DVec3) -> DMat3 {
    let theta2 = phi.length_squared();
    let theta = theta2.sqrt();
    let (c1, c2, c3) = if theta < 0.5 {
        (
            series(
                theta2,
                &[1.0 / 6.0, -1.0 / 120.0, 1.0 / 5040.0, -1.0 / 362_880.0],
            ),
            series(
                theta2,
                &[1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3_628_800.0],
            ),
            series(
                theta2,
                &[
                    1.0 / 120.0,
                    -2.0 / 5040.0,
                    3.0 / 362_880.0,
                    -4.0 / 39_916_800.0,
                ],
            ),
        )
    } else {
        let (s, c) = theta.sin_cos();
        (
            (theta - s) / (theta2 * theta),
            (theta2 + 2.0 * c - 2.0) / (2.0 * theta2 * theta2),
            (2.0 * theta - 3.0 * s + theta * c) / (2.0 * theta2 * theta2 * theta),
        )
    };
    let (r, p) = (skew(rho), skew(phi));
    let pr = p * r;
    let rp = r * p;
    let prp = pr * p;
    r * 0.5 + (pr + rp + prp) * c1 + (p * pr + rp * p - prp * 3.0) * c2 + (prp * p + p * prp) * c3
}

/// The SE(3) left Jacobian of the twist `(rho, phi)`.
fn se3_left(rho: DVec3, phi: DVec3) -> Mat6 {
    let j = so3_left_jacobian(phi);
    Mat6 {
        a: j,
        b: se3_q(rho, phi),
        c: DMat3::ZERO,
        d: j,
    }
}

/// The inverse of [`se3_left`].
fn se3_left_inverse(rho: DVec3, phi: DVec3) -> Mat6 {
    let ji = so3_left_jacobian_inverse(phi);
    Mat6 {
        a: ji,
        b: -(ji * se3_q(rho, phi) * ji),
        c: DMat3::ZERO,
        d: ji,
    }
}

/// `Ad(exp(ρ, φ))⁻¹`.
fn se3_ad_exp_inverse(rho: DVec3, phi: DVec3) -> Mat6 {
    let rt = exp3(phi).transpose();
    let p = so3_left_jacobian(phi) * rho;
    Mat6 {
        a: rt,
        b: -(rt * skew(p)),
        c: DMat3::ZERO,
        d: rt,
    }
}

/// The twist of a joint's tangent vector, and the indices of its coordinates in `[linear;
/// angular]`.
fn embed(kind: JointKind, x: &[f64]) -> (DVec3, DVec3, &'static [usize]) {
    match kind {
        JointKind::Spherical => (DVec3::ZERO, DVec3::new(x[0], x[1], x[2]), &[3, 4, 5]),
        JointKind::Planar => (
            DVec3::new(x[0], x[1], 0.0),
            DVec3::new(0.0, 0.0, x[2]),
            &[0, 1, 5],
        ),
        _ => (
            DVec3::new(x[0], x[1], x[2]),
            DVec3::new(x[3], x[4], x[5]),
            &[0, 1, 2, 3, 4, 5],
        ),
    }
}

/// Writes the joint block `m` (restricted to `idx`) at rows and columns `offset..` of `out`
/// (`nv x nv`, row-major), scaled by `sign`.
fn write_block(out: &mut [f64], nv: usize, offset: usize, idx: &[usize], m: &Mat6, sign: f64) {
    for (r, &ir) in idx.iter().enumerate() {
        for (c, &ic) in idx.iter().enumerate() {
            out[(offset + r) * nv + offset + c] = sign * m.get(ir, ic);
        }
    }
}

fn write_identity(out: &mut [f64], nv: usize, offset: usize, n: usize, sign: f64) {
    for k in 0..n {
        out[(offset + k) * nv + offset + k] = sign;
    }
}

fn is_group(kind: JointKind) -> bool {
    matches!(
        kind,
        JointKind::Spherical | JointKind::Planar | JointKind::Floating
    )
}

fn check_out(what: &'static str, m: &[f64], nv: usize) -> Result<(), KinematicsError> {
    if m.len() != nv * nv {
        return Err(KinematicsError::DimensionMismatch {
            what,
            expected: nv * nv,
            actual: m.len(),
        });
    }
    Ok(())
}

/// The Jacobians of `q ⊕ v` ([`integrate`](crate::configuration::integrate)) with respect to
/// `q` (into `d_dq`) and to `v` (into `d_dv`), each `nv x nv`, row-major, block-diagonal, in the
/// tangent space at `q ⊕ v`. Allocates nothing.
///
/// Column `k` of `∂f/∂q` is `d f(q ⊕ ε·e_k)/dε` at 0, and the configuration-valued result is
/// differentiated in the tangent space at the result. The blocks of the vector-space joints
/// (revolute, prismatic, continuous, cylindrical) are `±1`; for the Lie groups (spherical SO(3),
/// planar SE(2), floating SE(3), velocities in the child frame) `∂(q ⊕ v)/∂q = Ad(exp v)⁻¹` and
/// `∂(q ⊕ v)/∂v = J_r(v)`, the right Jacobian of `exp`.
///
/// # Errors
/// Length or finiteness errors for `q`, `v` and the outputs.
///
/// # Examples
/// ```
/// use kinetree_kinematics::integrate_jacobians;
/// use kinetree_kinematics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// # let model = Model::from_urdf_str(r#"<robot name="r"><link name="a"/><link name="b"/>
/// #   <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
/// #   <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#, RootJoint::Fixed)?;
/// let (mut dq, mut dv) = (vec![0.0; 1], vec![0.0; 1]);
/// integrate_jacobians(&model, &[0.2], &[0.5], &mut dq, &mut dv)?;
/// // A revolute joint adds: both Jacobians are the identity.
/// assert_eq!((dq[0], dv[0]), (1.0, 1.0));
/// # Ok(())
/// # }
/// ```
pub fn integrate_jacobians(
    model: &Model,
    q: &[f64],
    v: &[f64],
    d_dq: &mut [f64],
    d_dv: &mut [f64],
) -> Result<(), KinematicsError> {
    let nv = model.nv();
    check_vector("q", q, model.nq())?;
    check_vector("v", v, nv)?;
    check_out("d_dq", d_dq, nv)?;
    check_out("d_dv", d_dv, nv)?;
    d_dq.fill(0.0);
    d_dv.fill(0.0);
    for b in model.bodies().iter().skip(1).filter(|b| b.mimic.is_none()) {
        let vi = &v[b.idx_v..b.idx_v + b.nv];
        if is_group(b.kind) {
            let (rho, phi, idx) = embed(b.kind, vi);
            // J_r(v) = J_l(-v).
            write_block(d_dv, nv, b.idx_v, idx, &se3_left(-rho, -phi), 1.0);
            write_block(d_dq, nv, b.idx_v, idx, &se3_ad_exp_inverse(rho, phi), 1.0);
        } else {
            write_identity(d_dq, nv, b.idx_v, b.nv, 1.0);
            write_identity(d_dv, nv, b.idx_v, b.nv, 1.0);
        }
    }
    Ok(())
}

/// The Jacobians of `q₁ ⊖ q₀` ([`difference`](crate::configuration::difference)) with respect to
/// `q₀` (into `d_dq0`) and to `q₁` (into `d_dq1`), each `nv x nv`, row-major, block-diagonal
/// (conventions as [`integrate_jacobians`]: `∂(q₁ ⊖ q₀)/∂q₁ = J_r(d)⁻¹` and
/// `∂(q₁ ⊖ q₀)/∂q₀ = -J_l(d)⁻¹` with `d = q₁ ⊖ q₀` on the Lie groups). Allocates nothing.
///
/// # Errors
/// Length or finiteness errors for `q0`, `q1` and the outputs.
pub fn difference_jacobians(
    model: &Model,
    q0: &[f64],
    q1: &[f64],
    d_dq0: &mut [f64],
    d_dq1: &mut [f64],
) -> Result<(), KinematicsError> {
    let nv = model.nv();
    check_vector("q0", q0, model.nq())?;
    check_vector("q1", q1, model.nq())?;
    check_out("d_dq0", d_dq0, nv)?;
    check_out("d_dq1", d_dq1, nv)?;
    d_dq0.fill(0.0);
    d_dq1.fill(0.0);
    for b in model.bodies().iter().skip(1).filter(|b| b.mimic.is_none()) {
        if is_group(b.kind) {
            let mut d = [0.0; 6];
            let r = b.idx_q..b.idx_q + b.nq;
            difference_joint(b.kind, &q0[r.clone()], &q1[r], &mut d[..b.nv]);
            let (rho, phi, idx) = embed(b.kind, &d);
            // J_r(d)⁻¹ = J_l(-d)⁻¹.
            write_block(d_dq1, nv, b.idx_v, idx, &se3_left_inverse(-rho, -phi), 1.0);
            write_block(d_dq0, nv, b.idx_v, idx, &se3_left_inverse(rho, phi), -1.0);
        } else {
            write_identity(d_dq0, nv, b.idx_v, b.nv, -1.0);
            write_identity(d_dq1, nv, b.idx_v, b.nv, 1.0);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dexp_inv_is_the_identity_for_commuting_joints_and_matches_the_series() {
        let theta = [0.1, -0.2, 0.3];
        let xi = [0.5, 0.4, -0.6];
        let mut out = [0.0; 3];
        JointModel::Cylindrical(DVec3::X).dexp_inv(&theta[..2], &xi[..2], &mut out[..2]);
        assert_eq!(out[..2], xi[..2]);
        // SO(3): ξ + ½ θ×ξ + 1/12 θ×(θ×ξ).
        JointModel::Spherical.dexp_inv(&theta, &xi, &mut out);
        let (t, x) = (DVec3::from_array(theta), DVec3::from_array(xi));
        let expected = x + t.cross(x) * 0.5 + t.cross(t.cross(x)) / 12.0;
        assert!((DVec3::from_array(out) - expected).length() < 1e-15);
    }
}
