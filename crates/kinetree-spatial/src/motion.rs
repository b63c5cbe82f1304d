//! Spatial motion vectors (twists) and force vectors (wrenches), ordered `[linear; angular]`.

use crate::real::{Real, Vector3};
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};
use glam::DVec3;

/// A spatial motion vector (twist): the linear velocity of the point at the frame origin and the
/// angular velocity, both expressed in the frame's axes. Ordered `[linear; angular]`.
///
/// Generic over its number type ([`Real`]): `Motion` is `Motion<f64>`, and `Motion<Lanes<L>>`
/// holds `L` motions side by side.
#[derive(Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "T::V3: serde::Serialize",
        deserialize = "T::V3: serde::Deserialize<'de>"
    ))
)]
#[doc(alias = "Twist")]
// `repr(C)`: six `f64` in field order, which the batched kernels store whole.
#[repr(C)]
pub struct Motion<T: Real = f64> {
    /// Linear part: velocity of the point at the frame origin.
    pub linear: T::V3,
    /// Angular part: angular velocity.
    pub angular: T::V3,
}

/// A spatial force vector (wrench): the force and the moment about the frame origin, both
/// expressed in the frame's axes. Ordered `[linear; angular]` = `[force; torque]`.
///
/// Generic over its number type as [`Motion`] is.
#[derive(Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "T::V3: serde::Serialize",
        deserialize = "T::V3: serde::Deserialize<'de>"
    ))
)]
#[doc(alias = "Wrench")]
#[repr(C)]
pub struct Force<T: Real = f64> {
    /// Linear part: the force.
    pub linear: T::V3,
    /// Angular part: the moment about the frame origin.
    pub angular: T::V3,
}

macro_rules! spatial_vector_common {
    ($t:ident) => {
        impl $t {
            /// The zero vector.
            pub const ZERO: Self = Self {
                linear: DVec3::ZERO,
                angular: DVec3::ZERO,
            };

            /// From the linear and angular parts.
            #[inline]
            #[must_use]
            pub const fn new(linear: DVec3, angular: DVec3) -> Self {
                Self { linear, angular }
            }

            /// From six numbers ordered `[linear; angular]`.
            #[inline]
            #[must_use]
            pub fn from_array(a: [f64; 6]) -> Self {
                Self::new(DVec3::new(a[0], a[1], a[2]), DVec3::new(a[3], a[4], a[5]))
            }

            /// From the first six entries of `s`, ordered `[linear; angular]`.
            ///
            /// # Panics
            /// When `s` has fewer than six entries.
            #[inline]
            #[must_use]
            pub fn from_slice(s: &[f64]) -> Self {
                Self::new(DVec3::new(s[0], s[1], s[2]), DVec3::new(s[3], s[4], s[5]))
            }

            /// The six numbers ordered `[linear; angular]`.
            #[inline]
            #[must_use]
            pub fn to_array(&self) -> [f64; 6] {
                let (l, a) = (self.linear, self.angular);
                [l.x, l.y, l.z, a.x, a.y, a.z]
            }

            /// Writes the six numbers ordered `[linear; angular]` into the first six entries of `out`.
            ///
            /// # Panics
            /// When `out` has fewer than six entries.
            #[inline]
            pub fn write_to_slice(&self, out: &mut [f64]) {
                out[..6].copy_from_slice(&self.to_array());
            }

            /// The six numbers in Featherstone's order `[angular; linear]`.
            #[inline]
            #[must_use]
            pub fn to_featherstone(&self) -> [f64; 6] {
                let (l, a) = (self.linear, self.angular);
                [a.x, a.y, a.z, l.x, l.y, l.z]
            }

            /// From six numbers in Featherstone's order `[angular; linear]`.
            #[inline]
            #[must_use]
            pub fn from_featherstone(a: [f64; 6]) -> Self {
                Self::new(DVec3::new(a[3], a[4], a[5]), DVec3::new(a[0], a[1], a[2]))
            }

            /// Whether every component is finite.
            #[inline]
            #[must_use]
            pub fn is_finite(&self) -> bool {
                self.linear.is_finite() && self.angular.is_finite()
            }

            /// Whether every component of `self - other` is at most `tolerance` in magnitude.
            #[inline]
            #[must_use]
            pub fn abs_diff_eq(&self, other: &Self, tolerance: f64) -> bool {
                self.linear.abs_diff_eq(other.linear, tolerance)
                    && self.angular.abs_diff_eq(other.angular, tolerance)
            }
        }

        impl<T: Real> Default for $t<T> {
            #[inline(always)]
            fn default() -> Self {
                Self::zero()
            }
        }

        impl<T: Real> $t<T> {
            /// The zero vector (for every number type; `ZERO` is the `f64` one).
            #[inline(always)]
            #[must_use]
            pub fn zero() -> Self {
                Self {
                    linear: T::V3::ZERO,
                    angular: T::V3::ZERO,
                }
            }

            /// A constant vector in this number type (in every lane).
            #[inline(always)]
            #[must_use]
            pub fn from_const(x: &$t) -> Self {
                Self {
                    linear: T::V3::from_const(x.linear),
                    angular: T::V3::from_const(x.angular),
                }
            }

            /// Every coordinate times `s`.
            #[inline(always)]
            #[must_use]
            pub fn scale(&self, s: T) -> Self {
                Self {
                    linear: self.linear.scale(s),
                    angular: self.angular.scale(s),
                }
            }
        }

        impl<T: Real> Add for $t<T> {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                Self {
                    linear: self.linear + o.linear,
                    angular: self.angular + o.angular,
                }
            }
        }
        impl<T: Real> AddAssign for $t<T> {
            #[inline(always)]
            fn add_assign(&mut self, o: Self) {
                self.linear += o.linear;
                self.angular += o.angular;
            }
        }
        impl<T: Real> Sub for $t<T> {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                Self {
                    linear: self.linear - o.linear,
                    angular: self.angular - o.angular,
                }
            }
        }
        impl<T: Real> SubAssign for $t<T> {
            #[inline(always)]
            fn sub_assign(&mut self, o: Self) {
                self.linear -= o.linear;
                self.angular -= o.angular;
            }
        }
        impl<T: Real> Neg for $t<T> {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self {
                    linear: -self.linear,
                    angular: -self.angular,
                }
            }
        }
        impl<T: Real> Mul<f64> for $t<T> {
            type Output = Self;
            #[inline(always)]
            fn mul(self, s: f64) -> Self {
                Self {
                    linear: self.linear.scale_by(s),
                    angular: self.angular.scale_by(s),
                }
            }
        }
        impl Mul<$t> for f64 {
            type Output = $t;
            #[inline]
            fn mul(self, m: $t) -> $t {
                m * self
            }
        }
    };
}

spatial_vector_common!(Motion);
spatial_vector_common!(Force);

crate::copy_by_value!(Motion, Force);

impl<T: Real> Motion<T> {
    /// The spatial cross product with a motion, `self ×ₘ m` (Featherstone's `crm(self) · m`):
    /// the rate of change of `m` when it moves with velocity `self`.
    #[inline(always)]
    #[must_use]
    #[doc(alias = "crm")]
    pub fn cross_motion(&self, m: &Self) -> Self {
        Motion {
            linear: self.angular.cross(&m.linear) + self.linear.cross(&m.angular),
            angular: self.angular.cross(&m.angular),
        }
    }

    /// The spatial cross product with a force, `self ×* f` (Featherstone's `crf(self) · f`,
    /// with `crf(v) = -crm(v)ᵀ`).
    #[inline(always)]
    #[must_use]
    #[doc(alias = "crf")]
    pub fn cross_force(&self, f: &Force<T>) -> Force<T> {
        Force {
            linear: self.angular.cross(&f.linear),
            angular: self.angular.cross(&f.angular) + self.linear.cross(&f.linear),
        }
    }

    /// The power `f · self` delivered by a force acting along this motion.
    #[inline(always)]
    #[must_use]
    pub fn dot(&self, f: &Force<T>) -> T {
        self.linear.dot(&f.linear) + self.angular.dot(&f.angular)
    }
}

impl Motion {
    /// The 6x6 matrix `crm(self)` in `[linear; angular]` order, row-major.
    #[must_use]
    pub fn to_cross_motion_matrix(&self) -> [[f64; 6]; 6] {
        let mut out = [[0.0; 6]; 6];
        let w = crate::rotation::skew(self.angular);
        let v = crate::rotation::skew(self.linear);
        for i in 0..3 {
            for j in 0..3 {
                out[i][j] = w.col(j)[i];
                out[i][j + 3] = v.col(j)[i];
                out[i + 3][j + 3] = w.col(j)[i];
            }
        }
        out
    }

    /// The 6x6 matrix `crf(self) = -crm(self)ᵀ` in `[linear; angular]` order, row-major.
    #[must_use]
    pub fn to_cross_force_matrix(&self) -> [[f64; 6]; 6] {
        let m = self.to_cross_motion_matrix();
        let mut out = [[0.0; 6]; 6];
        for (i, row) in out.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = -m[j][i];
            }
        }
        out
    }
}

impl<T: Real> Force<T> {
    /// The power `self · m` delivered along a motion.
    #[inline(always)]
    #[must_use]
    pub fn dot(&self, m: &Motion<T>) -> T {
        m.dot(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mat_vec(m: &[[f64; 6]; 6], v: [f64; 6]) -> [f64; 6] {
        let mut out = [0.0; 6];
        for i in 0..6 {
            out[i] = (0..6).map(|j| m[i][j] * v[j]).sum();
        }
        out
    }

    #[test]
    fn cross_products_match_matrices() {
        let v = Motion::from_array([0.1, -0.4, 0.7, 1.1, 0.3, -0.8]);
        let m = Motion::from_array([-0.3, 0.2, 0.5, -0.6, 0.9, 0.4]);
        let f = Force::from_array([2.0, -1.0, 0.5, 0.25, 0.75, -1.5]);
        let crm = mat_vec(&v.to_cross_motion_matrix(), m.to_array());
        let crf = mat_vec(&v.to_cross_force_matrix(), f.to_array());
        for i in 0..6 {
            assert!((crm[i] - v.cross_motion(&m).to_array()[i]).abs() < 1e-15);
            assert!((crf[i] - v.cross_force(&f).to_array()[i]).abs() < 1e-15);
        }
        // v ×ₘ v = 0, and the power identity (v ×ₘ m)·f = -m·(v ×* f).
        assert!(v.cross_motion(&v).abs_diff_eq(&Motion::ZERO, 1e-15));
        assert!((v.cross_motion(&m).dot(&f) + m.dot(&v.cross_force(&f))).abs() < 1e-14);
    }

    #[test]
    fn featherstone_order_swaps_halves() {
        let m = Motion::from_array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(m.to_featherstone(), [4.0, 5.0, 6.0, 1.0, 2.0, 3.0]);
        assert_eq!(Motion::from_featherstone(m.to_featherstone()), m);
    }
}
