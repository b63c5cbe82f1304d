//! Rigid transforms (the group SE(3)) and their action on points, vectors, motions and forces.

use crate::motion::{Force, Motion};
use crate::real::{Matrix3, Real, Vector3};
use crate::rotation;
use core::ops::{Mul, MulAssign};
use glam::{DMat3, DMat4, DQuat, DVec3, DVec4};

/// A rigid transform: a rotation matrix and a translation.
///
/// Named `a_from_b`, it maps coordinates in frame `b` to coordinates in frame `a`:
/// `p_a = rotation · p_b + translation`. Its rotation's columns are `b`'s axes expressed in `a` and
/// its translation is `b`'s origin expressed in `a`. Composition reads right to left:
/// `a_from_c = a_from_b * b_from_c`.
///
/// # Examples
/// ```
/// use kinetree_spatial::Se3;
/// use glam::DVec3;
/// let world_from_link = Se3::from_translation(DVec3::new(1.0, 0.0, 0.0)) * Se3::from_rotation_z(0.5);
/// let p = world_from_link.transform_point(DVec3::X);
/// let back = world_from_link.inverse().transform_point(p);
/// assert!((back - DVec3::X).length() < 1e-15);
/// ```
///
/// Generic over its number type ([`Real`]): `Se3` is `Se3<f64>` (glam's `DMat3` and `DVec3`),
/// and `Se3<Lanes<L>>` holds `L` transforms side by side for the batched sweeps.
#[derive(Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "T::M3: serde::Serialize, T::V3: serde::Serialize",
        deserialize = "T::M3: serde::Deserialize<'de>, T::V3: serde::Deserialize<'de>"
    ))
)]
#[doc(alias = "SE3")]
#[doc(alias = "Isometry3")]
// `repr(C)`: the rotation's nine `f64` (column by column) and the translation's three, which
// the batched kernels store whole.
#[repr(C)]
pub struct Se3<T: Real = f64> {
    /// Rotation matrix (orthonormal, determinant +1).
    pub rotation: T::M3,
    /// Translation.
    pub translation: T::V3,
}

crate::copy_by_value!(Se3);

impl<T: Real> Default for Se3<T> {
    #[inline(always)]
    fn default() -> Self {
        Self::identity()
    }
}

impl Se3 {
    /// The identity transform.
    pub const IDENTITY: Self = Self {
        rotation: DMat3::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// From a rotation matrix and a translation.
    ///
    /// # Preconditions
    /// `rotation` is orthonormal with determinant +1; this is not checked (see
    /// [`Se3::from_rotation_translation_checked`]).
    #[inline]
    #[must_use]
    pub const fn new(rotation: DMat3, translation: DVec3) -> Self {
        Self {
            rotation,
            translation,
        }
    }

    /// From a rotation matrix and a translation, or `None` when `rotation` is not a rotation
    /// within `1e-9` or a value is not finite. Use on data from outside the program.
    #[must_use]
    pub fn from_rotation_translation_checked(rotation: DMat3, translation: DVec3) -> Option<Self> {
        (translation.is_finite() && rotation::is_rotation(&rotation, 1e-9)).then_some(Self {
            rotation,
            translation,
        })
    }

    /// A pure translation.
    #[inline]
    #[must_use]
    pub const fn from_translation(translation: DVec3) -> Self {
        Self {
            rotation: DMat3::IDENTITY,
            translation,
        }
    }

    /// A pure rotation.
    #[inline]
    #[must_use]
    pub const fn from_rotation(rotation: DMat3) -> Self {
        Self {
            rotation,
            translation: DVec3::ZERO,
        }
    }

    /// A rotation by `angle` radians about x.
    #[inline]
    #[must_use]
    pub fn from_rotation_x(angle: f64) -> Self {
        Self::from_rotation(rotation::rot_x(angle))
    }

    /// A rotation by `angle` radians about y.
    #[inline]
    #[must_use]
    pub fn from_rotation_y(angle: f64) -> Self {
        Self::from_rotation(rotation::rot_y(angle))
    }

    /// A rotation by `angle` radians about z.
    #[inline]
    #[must_use]
    pub fn from_rotation_z(angle: f64) -> Self {
        Self::from_rotation(rotation::rot_z(angle))
    }

    /// A rotation by `angle` radians about the unit vector `axis` (Rodrigues' formula).
    ///
    /// # Preconditions
    /// `axis` is normalized.
    #[inline]
    #[must_use]
    pub fn from_axis_angle(axis: DVec3, angle: f64) -> Self {
        Self::from_rotation(rotation::rot_axis_angle(axis, angle))
    }

    /// A rotation from a unit quaternion (glam's `DQuat`, coefficients x, y, z, w).
    ///
    /// # Preconditions
    /// `q` is normalized.
    #[inline]
    #[must_use]
    pub fn from_quat(q: DQuat) -> Self {
        Self::from_rotation(DMat3::from_quat(q))
    }

    /// From a translation and a unit quaternion.
    #[inline]
    #[must_use]
    pub fn from_translation_quat(translation: DVec3, q: DQuat) -> Self {
        Self::new(DMat3::from_quat(q), translation)
    }

    /// The rotation as a unit quaternion (w ≥ 0 is not guaranteed).
    #[inline]
    #[must_use]
    pub fn to_quat(&self) -> DQuat {
        DQuat::from_mat3(&self.rotation)
    }

    /// From a translation and URDF roll-pitch-yaw angles (fixed axes: `R = Rz(yaw)·Ry(pitch)·Rx(roll)`),
    /// as in a URDF `<origin xyz=".." rpy=".."/>`.
    #[inline]
    #[must_use]
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Self {
        Self::new(
            rotation::from_rpy(rpy[0], rpy[1], rpy[2]),
            DVec3::from_array(xyz),
        )
    }

    /// A rotation from URDF roll-pitch-yaw angles (fixed axes: `R = Rz(yaw)·Ry(pitch)·Rx(roll)`).
    #[inline]
    #[must_use]
    pub fn from_rpy(roll: f64, pitch: f64, yaw: f64) -> Self {
        Self::from_rotation(rotation::from_rpy(roll, pitch, yaw))
    }

    /// The URDF roll, pitch and yaw of the rotation, pitch in [-π/2, π/2].
    ///
    /// Exact at and near gimbal lock: `from_rpy(to_rpy())` reproduces the rotation to round-off
    /// even where roll and yaw are not unique.
    #[inline]
    #[must_use]
    pub fn to_rpy(&self) -> [f64; 3] {
        rotation::to_rpy(&self.rotation)
    }

    /// A rotation from intrinsic X-Y'-Z'' Euler angles: `R = Rx(a)·Ry(b)·Rz(c)`.
    #[inline]
    #[must_use]
    pub fn from_euler_xyz(a: f64, b: f64, c: f64) -> Self {
        Self::from_rotation(rotation::from_euler_xyz(a, b, c))
    }

    /// The intrinsic XYZ Euler angles of the rotation (`b` in [-π/2, π/2]), exact at and near
    /// gimbal lock in the same sense as [`Se3::to_rpy`].
    #[inline]
    #[must_use]
    pub fn to_euler_xyz(&self) -> [f64; 3] {
        rotation::to_euler_xyz(&self.rotation)
    }

    /// From a 4x4 homogeneous matrix (glam, column-major). The last row is ignored.
    #[inline]
    #[must_use]
    pub fn from_mat4(m: &DMat4) -> Self {
        Self::new(DMat3::from_mat4(*m), m.w_axis.truncate())
    }

    /// The 4x4 homogeneous matrix (glam, column-major).
    #[inline]
    #[must_use]
    pub fn to_mat4(&self) -> DMat4 {
        DMat4::from_cols(
            self.rotation.x_axis.extend(0.0),
            self.rotation.y_axis.extend(0.0),
            self.rotation.z_axis.extend(0.0),
            DVec4::new(
                self.translation.x,
                self.translation.y,
                self.translation.z,
                1.0,
            ),
        )
    }

    /// From a 4x4 homogeneous matrix given as row-major nested arrays (`m[row][col]`, as in JSON).
    ///
    /// Returns `None` when the last row is not `[0, 0, 0, 1]` or the rotation block is not a
    /// rotation within `1e-9`.
    #[must_use]
    pub fn from_rows(m: &[[f64; 4]; 4]) -> Option<Self> {
        let last = m[3];
        if last != [0.0, 0.0, 0.0, 1.0] {
            return None;
        }
        let r = DMat3::from_cols(
            DVec3::new(m[0][0], m[1][0], m[2][0]),
            DVec3::new(m[0][1], m[1][1], m[2][1]),
            DVec3::new(m[0][2], m[1][2], m[2][2]),
        );
        Self::from_rotation_translation_checked(r, DVec3::new(m[0][3], m[1][3], m[2][3]))
    }

    /// The 4x4 homogeneous matrix as row-major nested arrays (`m[row][col]`).
    #[must_use]
    pub fn to_rows(&self) -> [[f64; 4]; 4] {
        let r = &self.rotation;
        let t = self.translation;
        [
            [r.x_axis.x, r.y_axis.x, r.z_axis.x, t.x],
            [r.x_axis.y, r.y_axis.y, r.z_axis.y, t.y],
            [r.x_axis.z, r.y_axis.z, r.z_axis.z, t.z],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }

    /// The rotation as row-major nested arrays (`r[row][col]`).
    #[must_use]
    pub fn rotation_rows(&self) -> [[f64; 3]; 3] {
        let r = &self.rotation;
        [
            [r.x_axis.x, r.y_axis.x, r.z_axis.x],
            [r.x_axis.y, r.y_axis.y, r.z_axis.y],
            [r.x_axis.z, r.y_axis.z, r.z_axis.z],
        ]
    }

    /// The 6x6 motion transform (Plücker matrix) in `[linear; angular]` order, row-major, such
    /// that `X · m == act_motion(m)`: `[[R, [t]×R], [0, R]]`.
    #[must_use]
    #[doc(alias = "plucker")]
    pub fn to_action_matrix(&self) -> [[f64; 6]; 6] {
        let r = self.rotation;
        let tr = rotation::skew(self.translation) * r;
        let mut out = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                out[i][j] = r.col(j)[i];
                out[i][j + 3] = tr.col(j)[i];
                out[i + 3][j + 3] = r.col(j)[i];
            }
        }
        out
    }

    /// The 6x6 force transform in `[linear; angular]` order, row-major, such that
    /// `X* · f == act_force(f)`: `[[R, 0], [[t]×R, R]]` (the inverse transpose of the action matrix).
    #[must_use]
    pub fn to_dual_action_matrix(&self) -> [[f64; 6]; 6] {
        let r = self.rotation;
        let tr = rotation::skew(self.translation) * r;
        let mut out = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                out[i][j] = r.col(j)[i];
                out[i + 3][j] = tr.col(j)[i];
                out[i + 3][j + 3] = r.col(j)[i];
            }
        }
        out
    }

    /// Whether `self` and `other` agree within `rotation_tolerance` on every rotation entry and
    /// `translation_tolerance` (same length unit as the translation) on every translation entry.
    #[inline]
    #[must_use]
    pub fn abs_diff_eq(
        &self,
        other: &Se3,
        rotation_tolerance: f64,
        translation_tolerance: f64,
    ) -> bool {
        self.rotation
            .abs_diff_eq(other.rotation, rotation_tolerance)
            && self
                .translation
                .abs_diff_eq(other.translation, translation_tolerance)
    }

    /// Whether every entry is finite.
    #[inline]
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.rotation.is_finite() && self.translation.is_finite()
    }

    /// Interpolates along the screw motion from `self` (t = 0) to `other` (t = 1):
    /// `self · exp6(t · log6(self⁻¹ · other))`.
    #[must_use]
    pub fn interpolate(&self, other: &Se3, t: f64) -> Se3 {
        let delta = crate::explog::log6(&self.inv_mul(other));
        *self * crate::explog::exp6(&(delta * t))
    }
}

impl<T: Real> Se3<T> {
    /// The identity transform (for every number type; [`Se3::IDENTITY`] is the `f64` one).
    #[inline(always)]
    #[must_use]
    pub fn identity() -> Self {
        Self {
            rotation: T::M3::IDENTITY,
            translation: T::V3::ZERO,
        }
    }

    /// The constant transform `x` (in every lane).
    #[inline(always)]
    #[must_use]
    pub fn from_const(x: &Se3) -> Self {
        Self {
            rotation: T::M3::from_const(&x.rotation),
            translation: T::V3::from_const(x.translation),
        }
    }

    /// `*self = *src`, lane vector by lane vector: a whole-struct copy of a transform of 8
    /// lanes (768 bytes) compiles to a call of `memcpy`, which took about 8 % of a batched
    /// RNEA; twelve vector copies do not.
    #[inline(always)]
    pub fn assign(&mut self, src: &Self) {
        self.rotation.assign(&src.rotation);
        self.translation.assign(&src.translation);
    }

    /// The inverse transform: `b_from_a` for `a_from_b`.
    #[inline(always)]
    #[must_use]
    pub fn inverse(&self) -> Self {
        let rt = self.rotation.transpose();
        Self {
            rotation: rt,
            translation: -rt.mul_vec(&self.translation),
        }
    }

    /// `self.inverse() * other`, without forming the inverse.
    #[inline(always)]
    #[must_use]
    pub fn inv_mul(&self, other: &Self) -> Self {
        let rt = self.rotation.transpose();
        Self {
            rotation: rt.mul_mat(&other.rotation),
            translation: rt.mul_vec(&(other.translation - self.translation)),
        }
    }

    /// Composition `self * o`: `a_from_c = a_from_b * b_from_c` (what `*` does).
    #[inline(always)]
    #[must_use]
    pub fn compose(&self, o: &Self) -> Self {
        Self {
            rotation: self.rotation.mul_mat(&o.rotation),
            translation: self.rotation.mul_vec(&o.translation) + self.translation,
        }
    }

    /// Composition `self * o` with a constant `o`.
    #[inline(always)]
    #[must_use]
    pub fn mul_const(&self, o: &Se3) -> Self {
        Self {
            rotation: self.rotation.mul_const_mat(&o.rotation),
            translation: self.rotation.mul_const_vec(o.translation) + self.translation,
        }
    }

    /// Maps a point from the source frame to the target frame: `R·p + t`.
    #[inline(always)]
    #[must_use]
    pub fn transform_point(&self, p: T::V3) -> T::V3 {
        self.rotation.mul_vec(&p) + self.translation
    }

    /// Maps a direction from the source frame to the target frame: `R·v`.
    #[inline(always)]
    #[must_use]
    pub fn transform_vector(&self, v: T::V3) -> T::V3 {
        self.rotation.mul_vec(&v)
    }

    /// Maps a point from the target frame back to the source frame: `Rᵀ·(p - t)`.
    #[inline(always)]
    #[must_use]
    pub fn inverse_transform_point(&self, p: T::V3) -> T::V3 {
        self.inverse_transform_vector(p - self.translation)
    }

    /// Maps a direction from the target frame back to the source frame: `Rᵀ·v`, as three dot
    /// products without forming the transpose.
    #[inline(always)]
    #[must_use]
    pub fn inverse_transform_vector(&self, v: T::V3) -> T::V3 {
        self.rotation.transpose_mul_vec(&v)
    }

    /// Expresses in frame `a` a motion given in frame `b` (for `self = a_from_b`):
    /// `[R·v + t × (R·ω); R·ω]`.
    #[inline(always)]
    #[must_use]
    pub fn act_motion(&self, m: &Motion<T>) -> Motion<T> {
        let w = self.rotation.mul_vec(&m.angular);
        Motion {
            linear: self.rotation.mul_vec(&m.linear) + self.translation.cross(&w),
            angular: w,
        }
    }

    /// Expresses in frame `b` a motion given in frame `a` (the inverse of [`Se3::act_motion`]).
    /// A kernel of every body sweep (always inlined).
    #[inline(always)]
    #[must_use]
    pub fn act_inv_motion(&self, m: &Motion<T>) -> Motion<T> {
        Motion {
            linear: self.inverse_transform_vector(m.linear - self.translation.cross(&m.angular)),
            angular: self.inverse_transform_vector(m.angular),
        }
    }

    /// Expresses in frame `a` a force given in frame `b` (for `self = a_from_b`):
    /// `[R·f; R·n + t × (R·f)]`. A kernel of every body sweep (always inlined).
    #[inline(always)]
    #[must_use]
    pub fn act_force(&self, f: &Force<T>) -> Force<T> {
        let lin = self.rotation.mul_vec(&f.linear);
        Force {
            linear: lin,
            angular: self.rotation.mul_vec(&f.angular) + self.translation.cross(&lin),
        }
    }

    /// Expresses in frame `b` a force given in frame `a` (the inverse of [`Se3::act_force`]).
    #[inline(always)]
    #[must_use]
    pub fn act_inv_force(&self, f: &Force<T>) -> Force<T> {
        Force {
            linear: self.inverse_transform_vector(f.linear),
            angular: self.inverse_transform_vector(f.angular - self.translation.cross(&f.linear)),
        }
    }
}

impl<T: Real> Mul for Se3<T> {
    type Output = Se3<T>;
    /// Composition: `a_from_c = a_from_b * b_from_c`.
    #[inline(always)]
    fn mul(self, o: Se3<T>) -> Se3<T> {
        self.compose(&o)
    }
}

impl<T: Real> Mul<&Se3<T>> for &Se3<T> {
    type Output = Se3<T>;
    #[inline(always)]
    fn mul(self, o: &Se3<T>) -> Se3<T> {
        self.compose(o)
    }
}

impl<T: Real> MulAssign for Se3<T> {
    #[inline(always)]
    fn mul_assign(&mut self, o: Se3<T>) {
        *self = self.compose(&o);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Se3 {
        Se3::from_xyz_rpy([0.3, -1.2, 0.8], [0.4, -0.9, 2.1])
    }

    fn mat6_vec(m: &[[f64; 6]; 6], v: [f64; 6]) -> [f64; 6] {
        let mut out = [0.0; 6];
        for i in 0..6 {
            out[i] = (0..6).map(|j| m[i][j] * v[j]).sum();
        }
        out
    }

    #[test]
    fn inverse_composes_to_identity() {
        let t = sample();
        assert!((t * t.inverse()).abs_diff_eq(&Se3::IDENTITY, 1e-15, 1e-15));
        assert!((t.inverse() * t).abs_diff_eq(&Se3::IDENTITY, 1e-15, 1e-15));
        assert!(t.inv_mul(&t).abs_diff_eq(&Se3::IDENTITY, 1e-15, 1e-15));
    }

    #[test]
    fn matrix_forms_round_trip() {
        let t = sample();
        assert!(Se3::from_mat4(&t.to_mat4()).abs_diff_eq(&t, 0.0, 0.0));
        assert!(
            Se3::from_rows(&t.to_rows())
                .unwrap()
                .abs_diff_eq(&t, 0.0, 0.0)
        );
        let mut bad = t.to_rows();
        bad[0][0] *= 2.0;
        assert!(Se3::from_rows(&bad).is_none());
        // The homogeneous product agrees with transform_point.
        let p = DVec3::new(0.1, 0.2, 0.3);
        let hp = t.to_mat4() * p.extend(1.0);
        assert!((hp.truncate() - t.transform_point(p)).length() < 1e-15);
    }

    #[test]
    fn actions_equal_matrix_products() {
        let t = sample();
        let m = Motion::from_array([0.5, -0.2, 0.9, -1.3, 0.4, 0.6]);
        let f = Force::from_array([-0.7, 1.5, 0.2, 0.3, -0.8, 1.1]);
        let xm = mat6_vec(&t.to_action_matrix(), m.to_array());
        let xf = mat6_vec(&t.to_dual_action_matrix(), f.to_array());
        for i in 0..6 {
            assert!((xm[i] - t.act_motion(&m).to_array()[i]).abs() < 1e-14);
            assert!((xf[i] - t.act_force(&f).to_array()[i]).abs() < 1e-14);
        }
        assert!(t.act_inv_motion(&t.act_motion(&m)).abs_diff_eq(&m, 1e-14));
        assert!(t.act_inv_force(&t.act_force(&f)).abs_diff_eq(&f, 1e-14));
        // Power is frame independent.
        assert!((t.act_motion(&m).dot(&t.act_force(&f)) - m.dot(&f)).abs() < 1e-14);
    }

    #[test]
    fn motion_transform_agrees_with_point_velocities() {
        // A body spinning about b's z axis: the velocity of b's origin seen in a, at a's origin.
        let a_from_b = Se3::from_translation(DVec3::new(2.0, 0.0, 0.0));
        let in_b = Motion::new(DVec3::ZERO, DVec3::Z);
        let in_a = a_from_b.act_motion(&in_b);
        // The point at a's origin is at -2 x from the spin axis: v = ω × r = z × (-2x) = -2 y.
        assert!((in_a.linear - DVec3::new(0.0, -2.0, 0.0)).length() < 1e-15);
    }

    #[test]
    fn interpolation_hits_ends_and_midpoint() {
        let a = Se3::IDENTITY;
        let b = Se3::new(rotation::rot_z(1.0), DVec3::new(1.0, 0.0, 0.0));
        assert!(a.interpolate(&b, 0.0).abs_diff_eq(&a, 1e-15, 1e-15));
        assert!(a.interpolate(&b, 1.0).abs_diff_eq(&b, 1e-14, 1e-14));
        let mid = a.interpolate(&b, 0.5);
        assert!(mid.rotation.abs_diff_eq(rotation::rot_z(0.5), 1e-14));
        // Two half steps make the whole.
        assert!((mid * mid).abs_diff_eq(&b, 1e-14, 1e-14));
    }
}
