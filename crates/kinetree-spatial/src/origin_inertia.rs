//! [`OriginInertia`]: a spatial inertia about the frame origin, the form of composite inertias.

use crate::real::{Real, Vector3};
use crate::{Force, Inertia, Motion, RotationForm, Symmetric3};
use glam::DVec3;

/// A spatial inertia about the frame origin: mass `m`, first moment `h = m·c` and rotational
/// inertia `i` about the origin (not the centre of mass). Sums are plain sums (no division by
/// the mass), which makes it the form for composite inertias; [`Inertia`] is the form read from
/// model files.
///
/// ```
/// use kinetree_spatial::{Inertia, Motion, OriginInertia, Symmetric3, DVec3};
/// let body = Inertia::new(2.0, DVec3::new(0.1, 0.0, 0.0), Symmetric3::from_diagonal(DVec3::ONE));
/// let y = OriginInertia::from_inertia(&body);
/// let v = Motion::new(DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.0, 0.0, 2.0));
/// assert!(y.mul_motion(&v).abs_diff_eq(&body.mul_motion(&v), 1e-15));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OriginInertia {
    /// Mass (kg).
    pub m: f64,
    /// First moment of mass `m·c` (kg·m).
    pub h: DVec3,
    /// Rotational inertia about the origin (kg·m²).
    pub i: Symmetric3,
}

impl OriginInertia {
    /// No mass.
    pub const ZERO: Self = Self {
        m: 0.0,
        h: DVec3::ZERO,
        i: Symmetric3::ZERO,
    };

    /// The origin form of a rigid-body inertia.
    #[inline(always)]
    #[must_use]
    pub fn from_inertia(inertia: &Inertia) -> Self {
        Self {
            m: inertia.mass,
            h: inertia.com * inertia.mass,
            i: inertia.rotational_about(DVec3::ZERO),
        }
    }

    /// `self += o` (both about the same origin).
    #[inline(always)]
    pub fn add_assign(&mut self, o: &Self) {
        self.m += o.m;
        self.h += o.h;
        self.i += o.i;
    }

    /// The momentum `I·s` of a motion `s` (`[linear; angular]`).
    #[inline(always)]
    #[must_use]
    pub fn mul_motion<T: Real>(&self, s: &Motion<T>) -> Force<T> {
        Force {
            linear: s.linear.scale_by(self.m) + s.angular.cross_const(self.h),
            angular: T::V3::const_cross(self.h, &s.linear) + self.i.mul_vector::<T>(&s.angular),
        }
    }

    /// The same inertia expressed about a frame whose origin is at `-t` in this frame's axes (a
    /// pure translation of the frame: the body moves by `t`).
    #[inline(always)]
    #[must_use]
    pub fn translated(&self, t: DVec3) -> Self {
        let u = self.h + t * (0.5 * self.m);
        let d = 2.0 * u.dot(t);
        let ir = &self.i;
        Self {
            m: self.m,
            h: self.h + t * self.m,
            i: Symmetric3::new(
                ir.xx - 2.0 * t.x * u.x + d,
                ir.xy - (t.x * u.y + u.x * t.y),
                ir.xz - (t.x * u.z + u.x * t.z),
                ir.yy - 2.0 * t.y * u.y + d,
                ir.yz - (t.y * u.z + u.y * t.z),
                ir.zz - 2.0 * t.z * u.z + d,
            ),
        }
    }

    /// The same inertia in a frame rotated by `r` (same origin): `h ↦ R·h`, `I ↦ R·I·Rᵀ`, with
    /// the rotation applied in its cheap form.
    #[inline(always)]
    #[must_use]
    pub fn rotated(&self, r: &RotationForm) -> Self {
        Self {
            m: self.m,
            h: r.apply(self.h),
            i: r.apply_sym(&self.i),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Se3;

    #[test]
    fn rotation_then_translation_equals_the_rigid_transform() {
        let inertia = Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        );
        let x = Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, 0.5, -0.6]);
        let y = OriginInertia::from_inertia(&inertia);
        let a = y
            .rotated(&RotationForm::General(x.rotation))
            .translated(x.translation);
        let b = OriginInertia::from_inertia(&inertia.transformed(&x));
        assert!((a.m - b.m).abs() < 1e-15 && (a.h - b.h).length() < 1e-14);
        assert!(a.i.to_mat3().abs_diff_eq(b.i.to_mat3(), 1e-14));
        let mut sum = y;
        sum.add_assign(&y);
        let v = Motion::from_array([-0.4, 0.9, 0.2, 0.6, -0.3, 1.1]);
        assert!(
            sum.mul_motion(&v)
                .abs_diff_eq(&(inertia.mul_motion(&v) * 2.0), 1e-14)
        );
    }
}
