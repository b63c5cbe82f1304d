//! Conversions between kinetree's [`Se3`] (rotation matrix + translation) and parry's
//! [`Pose`] (unit quaternion + translation).

use glam::{DMat3, DQuat};
use kinetree_kinematics::spatial::Se3;
use parry3d_f64::math::Pose;

/// The parry pose of a rigid transform: same map `p ↦ R·p + t`, the rotation as a unit
/// quaternion.
///
/// # Preconditions
/// `x.rotation` is orthonormal (as every placement kinetree computes is); the quaternion is
/// renormalized, so round-off in `x` is not amplified.
///
/// # Examples
/// ```
/// use kinetree_collision::{pose_to_se3, se3_to_pose};
/// use kinetree_collision::kinematics::spatial::Se3;
/// use glam::DVec3;
/// let x = Se3::from_rotation_z(0.3) * Se3::from_translation(DVec3::new(1.0, 2.0, 3.0));
/// let p = se3_to_pose(&x);
/// let v = DVec3::new(0.5, -1.0, 2.0);
/// assert!((p * v - x.transform_point(v)).length() < 1e-15);
/// assert!(pose_to_se3(&p).abs_diff_eq(&x, 1e-15, 1e-15));
/// ```
#[inline]
#[must_use]
pub fn se3_to_pose(x: &Se3) -> Pose {
    Pose::from_parts(x.translation, DQuat::from_mat3(&x.rotation).normalize())
}

/// The kinetree transform of a parry pose (inverse of [`se3_to_pose`]).
#[inline]
#[must_use]
pub fn pose_to_se3(p: &Pose) -> Se3 {
    Se3::new(DMat3::from_quat(p.rotation), p.translation)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn round_trip_and_action_agree() {
        // Rotations near every branch of the matrix-to-quaternion conversion (trace > 0 and each
        // diagonal element largest), including half turns.
        let cases = [
            Se3::IDENTITY,
            Se3::from_rotation_x(std::f64::consts::PI),
            Se3::from_rotation_y(std::f64::consts::PI),
            Se3::from_rotation_z(std::f64::consts::PI),
            Se3::from_rpy(0.3, -1.2, 2.9),
            Se3::from_rpy(3.0, 0.1, -3.1),
            Se3::from_axis_angle(DVec3::new(1.0, 1.0, 1.0).normalize(), 2.5),
        ];
        let points = [
            DVec3::X,
            DVec3::new(-0.3, 2.0, 0.7),
            DVec3::new(5.0, -4.0, 3.0),
        ];
        for (k, r) in cases.iter().enumerate() {
            let x = Se3::from_translation(DVec3::new(0.1 * k as f64, -0.2, 0.3)) * *r;
            let p = se3_to_pose(&x);
            assert!((p.rotation.length() - 1.0).abs() < 1e-15);
            for v in points {
                assert!((p * v - x.transform_point(v)).length() < 1e-14, "case {k}");
                assert!(
                    (p.rotation * v - x.transform_vector(v)).length() < 1e-14,
                    "case {k}"
                );
            }
            assert!(pose_to_se3(&p).abs_diff_eq(&x, 1e-14, 1e-14), "case {k}");
            // Composition commutes with the conversion.
            let y = Se3::from_rpy(-0.4, 0.2, 1.0) * Se3::from_translation(DVec3::Y);
            let composed = se3_to_pose(&(x * y));
            let product = p * se3_to_pose(&y);
            assert!((composed.translation - product.translation).length() < 1e-14);
            assert!(composed.rotation.dot(product.rotation).abs() > 1.0 - 1e-14);
        }
    }
}
