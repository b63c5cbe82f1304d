//! Exponential and logarithm maps between twists ([`Motion`]) and rigid transforms ([`Se3`]).

use crate::motion::Motion;
use crate::rotation::{exp3, log3, skew};
use crate::se3::Se3;
use glam::{DMat3, DVec3};

/// Below this angle the coefficients of the SE(3) maps use Taylor expansions.
const SMALL_ANGLE: f64 = 1e-4;

/// The left Jacobian of SO(3), `V(ω) = I + (1 - cos θ)/θ² [ω]× + (θ - sin θ)/θ³ [ω]×²`, which
/// maps the linear part of a twist to the translation of its exponential.
#[must_use]
pub fn so3_left_jacobian(w: DVec3) -> DMat3 {
    let theta2 = w.length_squared();
    let theta = theta2.sqrt();
    let (b, c) = if theta < SMALL_ANGLE {
        (0.5 - theta2 / 24.0, 1.0 / 6.0 - theta2 / 120.0)
    } else {
        let half = (0.5 * theta).sin();
        (
            2.0 * half * half / theta2,
            (theta - theta.sin()) / (theta2 * theta),
        )
    };
    let k = skew(w);
    DMat3::IDENTITY + k * b + (k * k) * c
}

/// The inverse of [`so3_left_jacobian`]: `I - ½[ω]× + (1/θ²)(1 - θ sin θ / (2(1 - cos θ)))[ω]×²`.
///
/// # Preconditions
/// `|ω| < 2π` (the map is singular at 2π).
#[must_use]
pub fn so3_left_jacobian_inverse(w: DVec3) -> DMat3 {
    let theta2 = w.length_squared();
    let theta = theta2.sqrt();
    let c = if theta < SMALL_ANGLE {
        1.0 / 12.0 + theta2 / 720.0
    } else {
        // θ sin θ / (2 (1 - cos θ)) = (θ/2) cot(θ/2), without the cancellation in 1 - cos θ.
        let (s, c) = (0.5 * theta).sin_cos();
        (1.0 - 0.5 * theta * c / s) / theta2
    };
    let k = skew(w);
    DMat3::IDENTITY - k * 0.5 + (k * k) * c
}

/// The SE(3) exponential: the transform reached after following the constant twist `m`
/// (expressed in the moving frame) for unit time.
#[must_use]
pub fn exp6(m: &Motion) -> Se3 {
    Se3::new(exp3(m.angular), so3_left_jacobian(m.angular) * m.linear)
}

/// The SE(3) logarithm: the twist `m` with `exp6(m) == t`, rotation angle in [0, π].
///
/// Accurate near the identity and near half-turn rotations.
#[must_use]
pub fn log6(t: &Se3) -> Motion {
    let w = log3(&t.rotation);
    Motion::new(so3_left_jacobian_inverse(w) * t.translation, w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn exp_log_round_trip() {
        let axis = DVec3::new(0.3, 0.9, -0.3).normalize();
        for theta in [0.0, 1e-10, 1e-6, 1e-3, 0.7, 2.5, PI - 1e-6, PI - 1e-9] {
            let m = Motion::new(DVec3::new(0.4, -1.0, 2.0), axis * theta);
            let t = exp6(&m);
            assert!(
                exp6(&log6(&t)).abs_diff_eq(&t, 1e-13, 1e-12),
                "theta {theta}"
            );
            if theta < PI - 1e-7 {
                assert!(log6(&t).abs_diff_eq(&m, 1e-9), "theta {theta}");
            }
        }
    }

    #[test]
    fn jacobian_inverse_is_inverse() {
        for w in [
            DVec3::ZERO,
            DVec3::new(1e-7, 0.0, 0.0),
            DVec3::new(0.3, -1.0, 2.0),
        ] {
            let p = so3_left_jacobian(w) * so3_left_jacobian_inverse(w);
            assert!(p.abs_diff_eq(DMat3::IDENTITY, 1e-13));
        }
    }

    #[test]
    fn exp_of_pure_translation_and_screw() {
        let t = exp6(&Motion::new(DVec3::new(1.0, 2.0, 3.0), DVec3::ZERO));
        assert!(t.abs_diff_eq(
            &Se3::from_translation(DVec3::new(1.0, 2.0, 3.0)),
            0.0,
            1e-15
        ));
        // A screw: rotate by π/2 about z while translating 1 along z.
        let s = exp6(&Motion::new(
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.0, 0.0, PI / 2.0),
        ));
        assert!((s.translation - DVec3::Z).length() < 1e-15);
        // A pure rotation about an axis through (1, 0, 0): linear part = -ω × p.
        let w = DVec3::new(0.0, 0.0, PI);
        let r = exp6(&Motion::new(-w.cross(DVec3::X), w));
        assert!((r.transform_point(DVec3::X) - DVec3::X).length() < 1e-14);
        assert!((r.transform_point(DVec3::ZERO) - DVec3::new(2.0, 0.0, 0.0)).length() < 1e-14);
    }
}
