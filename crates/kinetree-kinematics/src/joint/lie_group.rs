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

use super::model::{JointModel, quat};
use glam::{DQuat, DVec3};
use kinetree_model::JointKind;
use kinetree_model::spatial::{Motion, Se3, explog, rotation};
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
