//! Rotation helpers over glam's `DMat3`: skew matrices, the SO(3) exponential and logarithm,
//! URDF roll-pitch-yaw and intrinsic XYZ Euler angles.
//!
//! Every function takes and returns rotation matrices whose columns are the rotated frame's
//! axes expressed in the reference frame (`world_from_link` style).

use glam::{DMat3, DVec3};

/// Threshold below which a rotation angle is treated with Taylor expansions.
const SMALL_ANGLE: f64 = 1e-4;

/// The skew-symmetric (cross-product) matrix of `v`: `skew(v) * u == v.cross(u)`.
#[inline]
#[must_use]
pub fn skew(v: DVec3) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(0.0, v.z, -v.y),
        DVec3::new(-v.z, 0.0, v.x),
        DVec3::new(v.y, -v.x, 0.0),
    )
}

/// The vector of the skew-symmetric part of `m`: `vee(skew(v)) == v`.
#[inline]
#[must_use]
pub fn vee(m: &DMat3) -> DVec3 {
    DVec3::new(
        0.5 * (m.y_axis.z - m.z_axis.y),
        0.5 * (m.z_axis.x - m.x_axis.z),
        0.5 * (m.x_axis.y - m.y_axis.x),
    )
}

/// Rotation by `angle` radians about the x axis.
#[inline]
#[must_use]
pub fn rot_x(angle: f64) -> DMat3 {
    let (s, c) = angle.sin_cos();
    DMat3::from_cols(DVec3::X, DVec3::new(0.0, c, s), DVec3::new(0.0, -s, c))
}

/// Rotation by `angle` radians about the y axis.
#[inline]
#[must_use]
pub fn rot_y(angle: f64) -> DMat3 {
    let (s, c) = angle.sin_cos();
    DMat3::from_cols(DVec3::new(c, 0.0, -s), DVec3::Y, DVec3::new(s, 0.0, c))
}

/// Rotation by `angle` radians about the z axis.
#[inline]
#[must_use]
pub fn rot_z(angle: f64) -> DMat3 {
    let (s, c) = angle.sin_cos();
    DMat3::from_cols(DVec3::new(c, s, 0.0), DVec3::new(-s, c, 0.0), DVec3::Z)
}

/// Rotation by `angle` radians about the unit vector `axis` (Rodrigues' formula).
///
/// # Preconditions
/// `axis` is normalized; this is not checked.
#[inline]
#[must_use]
pub fn rot_axis_angle(axis: DVec3, angle: f64) -> DMat3 {
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    let (x, y, z) = (axis.x, axis.y, axis.z);
    DMat3::from_cols(
        DVec3::new(t * x * x + c, t * x * y + s * z, t * x * z - s * y),
        DVec3::new(t * x * y - s * z, t * y * y + c, t * y * z + s * x),
        DVec3::new(t * x * z + s * y, t * y * z - s * x, t * z * z + c),
    )
}

/// The SO(3) exponential: the rotation by `|w|` radians about `w / |w|`.
///
/// Exact for small angles (a Taylor expansion is used below 1e-4 rad).
#[must_use]
pub fn exp3(w: DVec3) -> DMat3 {
    let theta2 = w.length_squared();
    let theta = theta2.sqrt();
    // R = I + a [w]x + b [w]x^2 with a = sin(t)/t, b = (1 - cos t)/t^2.
    let (a, b) = if theta < SMALL_ANGLE {
        (1.0 - theta2 / 6.0, 0.5 - theta2 / 24.0)
    } else {
        let half = (0.5 * theta).sin();
        (theta.sin() / theta, 2.0 * half * half / theta2)
    };
    let k = skew(w);
    DMat3::IDENTITY + k * a + (k * k) * b
}

/// The SO(3) logarithm: the rotation vector `w` (axis times angle, angle in [0, π]) with
/// `exp3(w) == r`.
///
/// Accurate over the whole range, including angles near 0 and near π (where the axis is read
/// from the symmetric part of `r` instead of its vanishing skew part).
///
/// # Preconditions
/// `r` is a rotation matrix (orthonormal, determinant +1).
#[must_use]
pub fn log3(r: &DMat3) -> DVec3 {
    let cos = ((r.x_axis.x + r.y_axis.y + r.z_axis.z - 1.0) * 0.5).clamp(-1.0, 1.0);
    let v = vee(r); // = sin(theta) * axis
    let sin = v.length();
    if cos > 0.0 {
        // theta < π/2: the skew part is well conditioned.
        let theta = sin.atan2(cos);
        if theta < SMALL_ANGLE {
            // theta / sin(theta) ≈ 1 + theta²/6.
            return v * (1.0 + theta * theta / 6.0);
        }
        return v * (theta / sin);
    }
    // theta >= π/2: take the axis from the symmetric part, (R + Rᵀ)/2 = cos I + (1 - cos) k kᵀ.
    let one_minus_cos = 1.0 - cos;
    let diag = DVec3::new(r.x_axis.x, r.y_axis.y, r.z_axis.z);
    let kk = (diag - DVec3::splat(cos)) / one_minus_cos; // squares of the axis components
    let mut axis = if kk.x >= kk.y && kk.x >= kk.z {
        let x = kk.x.max(0.0).sqrt();
        DVec3::new(
            x,
            (r.x_axis.y + r.y_axis.x) * 0.5 / (one_minus_cos * x),
            (r.x_axis.z + r.z_axis.x) * 0.5 / (one_minus_cos * x),
        )
    } else if kk.y >= kk.z {
        let y = kk.y.max(0.0).sqrt();
        DVec3::new(
            (r.x_axis.y + r.y_axis.x) * 0.5 / (one_minus_cos * y),
            y,
            (r.y_axis.z + r.z_axis.y) * 0.5 / (one_minus_cos * y),
        )
    } else {
        let z = kk.z.max(0.0).sqrt();
        DVec3::new(
            (r.x_axis.z + r.z_axis.x) * 0.5 / (one_minus_cos * z),
            (r.y_axis.z + r.z_axis.y) * 0.5 / (one_minus_cos * z),
            z,
        )
    };
    axis = axis.normalize();
    // The sign of the axis comes from the skew part (sin(theta) * axis).
    let signed_sin = axis.dot(v);
    if signed_sin < 0.0 {
        axis = -axis;
    }
    let theta = signed_sin.abs().atan2(cos);
    axis * theta
}

/// The URDF roll-pitch-yaw rotation: fixed axes x, y, z, i.e. `R = Rz(yaw) · Ry(pitch) · Rx(roll)`.
#[inline]
#[must_use]
pub fn from_rpy(roll: f64, pitch: f64, yaw: f64) -> DMat3 {
    rot_z(yaw) * rot_y(pitch) * rot_x(roll)
}

/// Roll, pitch and yaw of `r` (inverse of [`from_rpy`]), with pitch in [-π/2, π/2].
///
/// At and near gimbal lock (pitch = ±π/2) the split between roll and yaw is not unique; the
/// angles returned always reproduce `r` exactly through [`from_rpy`].
///
/// # Preconditions
/// `r` is a rotation matrix.
#[must_use]
pub fn to_rpy(r: &DMat3) -> [f64; 3] {
    // Rz(y) Ry(p) Rx(r): R21 = cos p sin r, R22 = cos p cos r.
    let roll = r.y_axis.z.atan2(r.z_axis.z);
    // M = R · Rx(roll)ᵀ = Rz(yaw) · Ry(pitch), whose entries read yaw and pitch without division.
    let m = *r * rot_x(-roll);
    let yaw = (-m.y_axis.x).atan2(m.y_axis.y);
    let pitch = (-m.x_axis.z).atan2(m.z_axis.z);
    [roll, pitch, yaw]
}

/// Intrinsic X-Y'-Z'' Euler angles: `R = Rx(a) · Ry(b) · Rz(c)`.
#[inline]
#[must_use]
pub fn from_euler_xyz(a: f64, b: f64, c: f64) -> DMat3 {
    rot_x(a) * rot_y(b) * rot_z(c)
}

/// Intrinsic XYZ Euler angles of `r` (inverse of [`from_euler_xyz`]), with `b` in [-π/2, π/2].
///
/// Exact at and near gimbal lock (`b` = ±π/2) in the same sense as [`to_rpy`].
///
/// # Preconditions
/// `r` is a rotation matrix.
#[must_use]
pub fn to_euler_xyz(r: &DMat3) -> [f64; 3] {
    // Rx(a) Ry(b) Rz(c): R00 = cos b cos c, R01 = -cos b sin c.
    let c = (-r.y_axis.x).atan2(r.x_axis.x);
    // M = R · Rz(c)ᵀ = Rx(a) · Ry(b).
    let m = *r * rot_z(-c);
    let a = m.y_axis.z.atan2(m.y_axis.y);
    let b = m.z_axis.x.atan2(m.x_axis.x);
    [a, b, c]
}

/// Re-orthonormalizes a nearly-orthonormal matrix (Gram–Schmidt on the columns x, y; z = x × y).
#[must_use]
pub fn orthonormalize(r: &DMat3) -> DMat3 {
    let x = r.x_axis.normalize();
    let y = (r.y_axis - x * x.dot(r.y_axis)).normalize();
    DMat3::from_cols(x, y, x.cross(y))
}

/// Whether `r` is a rotation matrix within `tolerance` (orthonormal columns, determinant +1).
#[must_use]
pub fn is_rotation(r: &DMat3, tolerance: f64) -> bool {
    let rtr = r.transpose() * *r;
    let err = (rtr - DMat3::IDENTITY).to_cols_array();
    err.iter().all(|e| e.is_finite() && e.abs() <= tolerance)
        && (r.determinant() - 1.0).abs() <= tolerance
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn close(a: &DMat3, b: &DMat3, tol: f64) -> bool {
        a.to_cols_array()
            .iter()
            .zip(b.to_cols_array())
            .all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn skew_is_cross_product() {
        let v = DVec3::new(0.3, -1.2, 2.5);
        let u = DVec3::new(-0.7, 0.1, 0.4);
        assert!((skew(v) * u - v.cross(u)).length() < 1e-15);
        assert!((vee(&skew(v)) - v).length() < 1e-15);
    }

    #[test]
    fn elementary_rotations_match_hand_values() {
        // Rz(90°) maps x to y.
        let r = rot_z(FRAC_PI_2);
        assert!((r * DVec3::X - DVec3::Y).length() < 1e-15);
        // Rx(90°) maps y to z, Ry(90°) maps z to x.
        assert!((rot_x(FRAC_PI_2) * DVec3::Y - DVec3::Z).length() < 1e-15);
        assert!((rot_y(FRAC_PI_2) * DVec3::Z - DVec3::X).length() < 1e-15);
        let axis = DVec3::new(1.0, 2.0, -0.5).normalize();
        assert!(close(
            &rot_axis_angle(axis, 0.83),
            &DMat3::from_axis_angle(axis, 0.83),
            1e-15
        ));
    }

    #[test]
    fn exp_log_round_trip_near_zero_and_pi() {
        let axis = DVec3::new(0.2, -0.5, 0.8).normalize();
        for theta in [
            0.0,
            1e-12,
            1e-8,
            1e-5,
            1e-3,
            0.5,
            2.0,
            PI - 1e-3,
            PI - 1e-7,
            PI - 1e-10,
            PI,
        ] {
            let w = axis * theta;
            let r = exp3(w);
            assert!(
                close(&r, &DMat3::from_axis_angle(axis, theta), 1e-14),
                "exp {theta}"
            );
            let back = log3(&r);
            // At π the axis sign is ambiguous; compare rotations instead of vectors there.
            assert!(close(&exp3(back), &r, 1e-14), "log {theta}");
            if theta < PI - 1e-6 {
                assert!((back - w).length() < 1e-12, "log {theta}: {back} vs {w}");
            }
        }
        // Every axis near π.
        for axis in [
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
            DVec3::new(-1.0, 1.0, 1.0).normalize(),
        ] {
            let r = exp3(axis * (PI - 1e-9));
            assert!((log3(&r) - axis * (PI - 1e-9)).length() < 1e-8);
        }
    }

    #[test]
    fn rpy_matches_urdf_convention() {
        // Worked by hand: roll only about x, then the yaw rotates the rolled frame about world z.
        let r = from_rpy(FRAC_PI_2, 0.0, FRAC_PI_2);
        // Rz(90) Rx(90): x -> y, y -> z, z -> x.
        assert!((r * DVec3::X - DVec3::Y).length() < 1e-15);
        assert!((r * DVec3::Y - DVec3::Z).length() < 1e-15);
        assert!((r * DVec3::Z - DVec3::X).length() < 1e-15);
    }

    #[test]
    fn rpy_round_trip_including_gimbal_lock() {
        let mut cases = vec![[0.1, 0.2, 0.3], [-2.0, 1.0, 3.0], [3.0, -1.2, -2.9]];
        for eps in [0.0, 1e-15, 1e-12, 1e-9, 1e-6, 1e-3] {
            cases.push([0.4, FRAC_PI_2 - eps, -1.1]);
            cases.push([-2.4, -FRAC_PI_2 + eps, 0.7]);
        }
        for [r0, p0, y0] in cases {
            let r = from_rpy(r0, p0, y0);
            let [a, b, c] = to_rpy(&r);
            assert!((-FRAC_PI_2..=FRAC_PI_2).contains(&b));
            assert!(close(&from_rpy(a, b, c), &r, 2e-15), "rpy {r0} {p0} {y0}");
            let [a, b, c] = to_euler_xyz(&r);
            assert!(
                close(&from_euler_xyz(a, b, c), &r, 2e-15),
                "euler of rpy {r0} {p0} {y0}"
            );
            let e = from_euler_xyz(r0, p0, y0);
            let [a, b, c] = to_euler_xyz(&e);
            assert!(
                close(&from_euler_xyz(a, b, c), &e, 2e-15),
                "euler {r0} {p0} {y0}"
            );
        }
        // Away from gimbal lock the angles themselves come back.
        let [a, b, c] = to_rpy(&from_rpy(0.3, -0.4, 1.2));
        assert!((a - 0.3).abs() < 1e-15 && (b + 0.4).abs() < 1e-15 && (c - 1.2).abs() < 1e-15);
        let [a, b, c] = to_euler_xyz(&from_euler_xyz(0.3, -0.4, 1.2));
        assert!((a - 0.3).abs() < 1e-15 && (b + 0.4).abs() < 1e-15 && (c - 1.2).abs() < 1e-15);
    }

    #[test]
    fn orthonormalize_repairs_drift() {
        let mut r = from_rpy(0.3, 0.2, 0.1);
        r.x_axis *= 1.0 + 1e-6;
        assert!(!is_rotation(&r, 1e-9));
        assert!(is_rotation(&orthonormalize(&r), 1e-14));
    }
}
