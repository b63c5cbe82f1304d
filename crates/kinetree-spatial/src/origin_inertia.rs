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
///
/// Generic over the number type ([`Real`]) as the other spatial types: `OriginInertia` is the
/// `f64` form, `OriginInertia<T>` the one the generic algorithms carry.
#[derive(Debug, Default, PartialEq)]
pub struct OriginInertia<T: Real = f64> {
    /// Mass (kg).
    pub m: T,
    /// First moment of mass `m·c` (kg·m).
    pub h: T::V3,
    /// Rotational inertia about the origin (kg·m²).
    pub i: Symmetric3<T>,
}

crate::copy_by_value!(OriginInertia);

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
}

impl<T: Real> OriginInertia<T> {
    /// A constant inertia in this number type (in every lane).
    #[inline(always)]
    #[must_use]
    pub fn from_const(y: &OriginInertia) -> Self {
        Self {
            m: T::splat(y.m),
            h: T::V3::from_const(y.h),
            i: Symmetric3::from_const(&y.i),
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
    pub fn mul_motion(&self, s: &Motion<T>) -> Force<T> {
        Force {
            linear: s.linear.scale(self.m) + s.angular.cross(&self.h),
            angular: self.h.cross(&s.linear) + self.i.mul_vec(&s.angular),
        }
    }

    /// The same inertia expressed about a frame whose origin is at `-t` in this frame's axes (a
    /// pure translation of the frame: the body moves by `t`).
    #[inline(always)]
    #[must_use]
    pub fn translated(&self, t: &T::V3) -> Self {
        let u = self.h + t.scale(self.m * 0.5);
        let d = u.dot(t) * 2.0;
        let ir = &self.i;
        let (tx, ty, tz) = (t.get(0), t.get(1), t.get(2));
        let (ux, uy, uz) = (u.get(0), u.get(1), u.get(2));
        Self {
            m: self.m,
            h: self.h + t.scale(self.m),
            i: Symmetric3 {
                xx: ir.xx - tx * 2.0 * ux + d,
                xy: ir.xy - (tx * uy + ux * ty),
                xz: ir.xz - (tx * uz + ux * tz),
                yy: ir.yy - ty * 2.0 * uy + d,
                yz: ir.yz - (ty * uz + uy * tz),
                zz: ir.zz - tz * 2.0 * uz + d,
            },
        }
    }

    /// The same inertia in a frame rotated by `r` (same origin): `h ↦ R·h`, `I ↦ R·I·Rᵀ`, with
    /// the rotation applied in its cheap form.
    #[inline(always)]
    #[must_use]
    pub fn rotated(&self, r: &RotationForm<T>) -> Self {
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
            .translated(&x.translation);
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

    #[test]
    fn every_lane_is_the_one_state_result_bit_for_bit() {
        use crate::lanes::{LMat3, LMotion, LVec3, Lanes};
        let xs = [
            Se3::from_xyz_rpy([0.1, 0.2, 0.3], [0.4, 0.5, 0.6]),
            Se3::from_xyz_rpy([-0.3, 0.0, 0.7], [0.1, -0.2, 0.3]),
            Se3::from_xyz_rpy([1.3, -2.0, 0.1], [3.0, 1.2, -2.3]),
            Se3::from_xyz_rpy([0.0, 0.5, -0.5], [-1.0, 0.0, 2.0]),
        ];
        let y = OriginInertia::from_inertia(&Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        ));
        let angles: [f64; 4] = [0.3, -1.2, 2.9, 0.0];
        let mut rot = LMat3::<4>::default();
        let mut t = LVec3::<4>::ZERO;
        let (mut s, mut c) = (Lanes::<4>::ZERO, Lanes::<4>::ZERO);
        let mut m = LMotion::<4>::zero();
        for l in 0..4 {
            rot.set_lane(l, &xs[l].rotation);
            t.set_lane(l, xs[l].translation);
            (s.0[l], c.0[l]) = angles[l].sin_cos();
            m.set_lane(l, &Motion::new(xs[l].translation, xs[l].rotation.x_axis));
        }
        let constant = RotationForm::classify(&xs[1].rotation);
        for k in 0..3 {
            let lanes = OriginInertia::<Lanes<4>>::from_const(&y)
                .rotated(&RotationForm::Axis { k, s, c })
                .rotated(&RotationForm::from_const(&constant))
                .rotated(&RotationForm::General(rot))
                .translated(&t);
            let mut sum = lanes;
            sum.add_assign(&lanes);
            let f = sum.mul_motion(&m);
            for l in 0..4 {
                let (sl, cl) = (s.0[l], c.0[l]);
                let one = y
                    .rotated(&RotationForm::Axis { k, s: sl, c: cl })
                    .rotated(&constant)
                    .rotated(&RotationForm::General(xs[l].rotation))
                    .translated(&xs[l].translation);
                let mut two = one;
                two.add_assign(&one);
                assert_eq!(f.lane(l), two.mul_motion(&m.lane(l)));
                assert_eq!(lanes.h.lane(l), one.h);
                let i = &lanes.i;
                let got = [i.xx, i.xy, i.xz, i.yy, i.yz, i.zz].map(|x| x.0[l]);
                assert_eq!(got, one.i.to_urdf_array());
            }
        }
    }
}
