//! Symmetric 3x3 matrices, used for rotational inertia tensors.

use crate::real::{Matrix3, Real, Vector3};
use core::fmt;
use core::ops::{Add, AddAssign, Mul, Sub};
use glam::{DMat3, DVec3};

/// A symmetric 3x3 matrix stored as its six independent entries.
///
/// Used for rotational inertia tensors (kg·m²). Generic over the number type ([`Real`]): `Symmetric3` is the `f64` matrix, `Symmetric3<T>`
/// the one the generic algorithms carry (a matrix per lane for SIMD lanes). The entries follow URDF's names: `ixx, ixy, ixz,
/// iyy, iyz, izz` are the matrix entries (products of inertia enter with their sign as written in
/// URDF, i.e. `ixy` is the (0, 1) entry of the tensor).
#[derive(Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[doc(alias = "InertiaTensor")]
pub struct Symmetric3<T: Real = f64> {
    /// Entry (0, 0).
    pub xx: T,
    /// Entry (0, 1) = (1, 0).
    pub xy: T,
    /// Entry (0, 2) = (2, 0).
    pub xz: T,
    /// Entry (1, 1).
    pub yy: T,
    /// Entry (1, 2) = (2, 1).
    pub yz: T,
    /// Entry (2, 2).
    pub zz: T,
}

/// Why a rotational inertia is not physically valid (see [`Symmetric3::check_inertia`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum InertiaDefect {
    /// An entry is NaN or infinite.
    NonFinite,
    /// A 3x3 input was not symmetric: the largest asymmetry `|A_ij - A_ji|` is given.
    NotSymmetric {
        /// The largest `|A_ij - A_ji|`.
        asymmetry: f64,
    },
    /// The mass is negative.
    NegativeMass {
        /// The mass given, kg.
        mass: f64,
    },
    /// A principal moment is negative (or not positive when strict).
    NotPositive {
        /// The smallest principal moment.
        smallest_moment: f64,
    },
    /// The principal moments violate the triangle inequality `I1 + I2 >= I3`.
    TriangleInequality {
        /// The principal moments, ascending.
        moments: [f64; 3],
    },
}

impl fmt::Display for InertiaDefect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite => write!(f, "an inertia entry is not finite"),
            Self::NegativeMass { mass } => {
                write!(f, "the mass {} kg is negative", crate::Readable(*mass))
            }
            Self::NotSymmetric { asymmetry } => {
                write!(
                    f,
                    "inertia matrix is not symmetric (asymmetry {asymmetry:e})"
                )
            }
            Self::NotPositive { smallest_moment } => {
                write!(
                    f,
                    "inertia is not positive semi-definite (principal moment {smallest_moment:e})"
                )
            }
            Self::TriangleInequality { moments } => write!(
                f,
                "principal moments {:e}, {:e}, {:e} violate the triangle inequality",
                moments[0], moments[1], moments[2]
            ),
        }
    }
}

impl std::error::Error for InertiaDefect {}

crate::copy_by_value!(Symmetric3);

impl Symmetric3 {
    /// The zero matrix.
    pub const ZERO: Self = Self {
        xx: 0.0,
        xy: 0.0,
        xz: 0.0,
        yy: 0.0,
        yz: 0.0,
        zz: 0.0,
    };
    /// The identity matrix.
    pub const IDENTITY: Self = Self {
        xx: 1.0,
        xy: 0.0,
        xz: 0.0,
        yy: 1.0,
        yz: 0.0,
        zz: 1.0,
    };

    /// From the six entries in URDF order `(ixx, ixy, ixz, iyy, iyz, izz)`.
    #[inline]
    #[must_use]
    pub const fn new(xx: f64, xy: f64, xz: f64, yy: f64, yz: f64, zz: f64) -> Self {
        Self {
            xx,
            xy,
            xz,
            yy,
            yz,
            zz,
        }
    }

    /// From the moments of inertia `[ixx, iyy, izz]` (the diagonal) and the products of inertia
    /// `[ixy, ixz, iyz]` (the off-diagonal entries, as URDF writes them), as the `urdf` Python
    /// library's `InertiaTensor(moments=…, products=…)`.
    ///
    /// # Examples
    /// ```
    /// use kinetree_spatial::InertiaTensor;
    /// let tensor = InertiaTensor::from_moments_products([0.05, 0.06, 0.03], [0.001, -0.002, 0.0]);
    /// assert_eq!(tensor.moments(), [0.05, 0.06, 0.03]);
    /// assert_eq!(tensor.products(), [0.001, -0.002, 0.0]);
    /// assert_eq!(tensor.to_mat3().row(0).to_array(), [0.05, 0.001, -0.002]);
    /// ```
    #[inline]
    #[must_use]
    pub const fn from_moments_products(moments: [f64; 3], products: [f64; 3]) -> Self {
        Self::new(
            moments[0],
            products[0],
            products[1],
            moments[1],
            products[2],
            moments[2],
        )
    }

    /// The moments of inertia `[ixx, iyy, izz]`: the diagonal.
    #[inline]
    #[must_use]
    pub const fn moments(&self) -> [f64; 3] {
        [self.xx, self.yy, self.zz]
    }

    /// The products of inertia `[ixy, ixz, iyz]`: the off-diagonal entries.
    #[inline]
    #[must_use]
    pub const fn products(&self) -> [f64; 3] {
        [self.xy, self.xz, self.yz]
    }

    /// From the six scalar entries by URDF name (the `urdf` library's `from_entries`); the
    /// same as [`Symmetric3::new`].
    #[inline]
    #[must_use]
    pub const fn from_entries(ixx: f64, ixy: f64, ixz: f64, iyy: f64, iyz: f64, izz: f64) -> Self {
        Self::new(ixx, ixy, ixz, iyy, iyz, izz)
    }

    /// A diagonal matrix.
    #[inline]
    #[must_use]
    pub const fn from_diagonal(d: DVec3) -> Self {
        Self::new(d.x, 0.0, 0.0, d.y, 0.0, d.z)
    }

    /// The six entries in URDF order `[ixx, ixy, ixz, iyy, iyz, izz]`.
    #[inline]
    #[must_use]
    pub const fn to_urdf_array(&self) -> [f64; 6] {
        [self.xx, self.xy, self.xz, self.yy, self.yz, self.zz]
    }

    /// From Voigt order `[ixx, iyy, izz, iyz, ixz, ixy]`.
    #[inline]
    #[must_use]
    pub const fn from_voigt(v: [f64; 6]) -> Self {
        Self::new(v[0], v[5], v[4], v[1], v[3], v[2])
    }

    /// The entries in Voigt order `[ixx, iyy, izz, iyz, ixz, ixy]`.
    #[inline]
    #[must_use]
    #[doc(alias = "as_voigt")]
    pub const fn to_voigt(&self) -> [f64; 6] {
        [self.xx, self.yy, self.zz, self.yz, self.xz, self.xy]
    }

    /// From a 3x3 matrix, or the asymmetry defect when `|A_ij - A_ji| > tolerance` for some pair.
    ///
    /// # Errors
    /// [`InertiaDefect::NotSymmetric`] or [`InertiaDefect::NonFinite`].
    pub fn from_mat3_checked(m: &DMat3, tolerance: f64) -> Result<Self, InertiaDefect> {
        if !m.is_finite() {
            return Err(InertiaDefect::NonFinite);
        }
        let asymmetry = (m.y_axis.x - m.x_axis.y)
            .abs()
            .max((m.z_axis.x - m.x_axis.z).abs())
            .max((m.z_axis.y - m.y_axis.z).abs());
        if asymmetry > tolerance {
            return Err(InertiaDefect::NotSymmetric { asymmetry });
        }
        Ok(Self::from_mat3(m))
    }

    /// From a 3x3 matrix, symmetrizing it (`(A + Aᵀ)/2`).
    #[inline]
    #[must_use]
    pub fn from_mat3(m: &DMat3) -> Self {
        Self::new(
            m.x_axis.x,
            0.5 * (m.y_axis.x + m.x_axis.y),
            0.5 * (m.z_axis.x + m.x_axis.z),
            m.y_axis.y,
            0.5 * (m.z_axis.y + m.y_axis.z),
            m.z_axis.z,
        )
    }

    /// The full 3x3 matrix.
    #[inline]
    #[must_use]
    #[doc(alias = "as_matrix")]
    pub fn to_mat3(&self) -> DMat3 {
        DMat3::from_cols(
            DVec3::new(self.xx, self.xy, self.xz),
            DVec3::new(self.xy, self.yy, self.yz),
            DVec3::new(self.xz, self.yz, self.zz),
        )
    }

    /// The product with a vector.
    #[inline]
    #[must_use]
    pub fn mul_vec3(&self, v: DVec3) -> DVec3 {
        self.mul_vector::<f64>(&v)
    }

    /// The product with a vector of any number type ([`Real`]; [`Symmetric3::mul_vec3`] is
    /// the `f64` one).
    #[inline(always)]
    #[must_use]
    pub fn mul_vector<T: Real>(&self, v: &T::V3) -> T::V3 {
        let (x, y, z) = (v.get(0), v.get(1), v.get(2));
        T::V3::new(
            x * self.xx + y * self.xy + z * self.xz,
            x * self.xy + y * self.yy + z * self.yz,
            x * self.xz + y * self.yz + z * self.zz,
        )
    }

    /// `Rᵀ · self · R`.
    #[inline]
    #[must_use]
    pub fn rotate_inv(&self, r: &DMat3) -> Self {
        Self::from_mat3(&(r.transpose() * self.to_mat3() * *r))
    }

    /// `[v]×ᵀ [v]× = |v|² I - v vᵀ`: the parallel-axis term for a unit mass at offset `v`.
    #[inline]
    #[must_use]
    pub fn skew_square(v: DVec3) -> Self {
        skew_square::<f64>(&v)
    }

    /// Whether every entry is finite.
    #[inline]
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.to_urdf_array().iter().all(|x| x.is_finite())
    }

    /// The eigenvalues, ascending (closed form for symmetric 3x3 matrices).
    #[must_use]
    pub fn eigenvalues(&self) -> [f64; 3] {
        let p1 = self.xy * self.xy + self.xz * self.xz + self.yz * self.yz;
        let q = self.trace() / 3.0;
        if p1 <= f64::EPSILON * f64::EPSILON * (q * q).max(f64::MIN_POSITIVE) {
            let mut e = [self.xx, self.yy, self.zz];
            e.sort_by(f64::total_cmp);
            return e;
        }
        let p2 = (self.xx - q).powi(2) + (self.yy - q).powi(2) + (self.zz - q).powi(2) + 2.0 * p1;
        let p = (p2 / 6.0).sqrt();
        let b = (self.to_mat3() - DMat3::IDENTITY * q) * (1.0 / p);
        let r = (b.determinant() / 2.0).clamp(-1.0, 1.0);
        let phi = r.acos() / 3.0;
        let e_max = q + 2.0 * p * phi.cos();
        let e_min = q + 2.0 * p * (phi + 2.0 * core::f64::consts::PI / 3.0).cos();
        let e_mid = 3.0 * q - e_max - e_min;
        [e_min, e_mid, e_max]
    }

    /// Checks that this is a physically valid rotational inertia about the centre of mass:
    /// finite, positive semi-definite and with principal moments satisfying the triangle
    /// inequality (all within a relative `tolerance` of the largest moment).
    ///
    /// # Errors
    /// The first defect found.
    pub fn check_inertia(&self, tolerance: f64) -> Result<(), InertiaDefect> {
        if !self.is_finite() {
            return Err(InertiaDefect::NonFinite);
        }
        let e = self.eigenvalues();
        let scale = e[2].abs().max(f64::MIN_POSITIVE);
        if e[0] < -tolerance * scale {
            return Err(InertiaDefect::NotPositive {
                smallest_moment: e[0],
            });
        }
        if e[0] + e[1] < e[2] - tolerance * scale {
            return Err(InertiaDefect::TriangleInequality { moments: e });
        }
        Ok(())
    }
}

impl<T: Real> Symmetric3<T> {
    /// A constant matrix in this number type (in every lane).
    #[inline(always)]
    #[must_use]
    pub fn from_const(s: &Symmetric3) -> Self {
        Self {
            xx: T::splat(s.xx),
            xy: T::splat(s.xy),
            xz: T::splat(s.xz),
            yy: T::splat(s.yy),
            yz: T::splat(s.yz),
            zz: T::splat(s.zz),
        }
    }

    /// Column (= row) `k` of the matrix (`k` is 0, 1 or 2; larger values give column 2).
    #[inline(always)]
    #[must_use]
    pub fn column(&self, k: usize) -> T::V3 {
        match k {
            0 => T::V3::new(self.xx, self.xy, self.xz),
            1 => T::V3::new(self.xy, self.yy, self.yz),
            _ => T::V3::new(self.xz, self.yz, self.zz),
        }
    }

    /// Entry `(i, j)` (indices 0, 1, 2; larger values count as 2).
    #[inline(always)]
    #[must_use]
    pub fn get(&self, i: usize, j: usize) -> T {
        match (i.min(j), i.max(j)) {
            (0, 0) => self.xx,
            (0, 1) => self.xy,
            (0, _) => self.xz,
            (1, 1) => self.yy,
            (1, _) => self.yz,
            _ => self.zz,
        }
    }

    /// Sets entry `(i, j)` and its mirror `(j, i)` (indices as [`Symmetric3::get`]).
    #[inline(always)]
    pub fn set(&mut self, i: usize, j: usize, x: T) {
        match (i.min(j), i.max(j)) {
            (0, 0) => self.xx = x,
            (0, 1) => self.xy = x,
            (0, _) => self.xz = x,
            (1, 1) => self.yy = x,
            (1, _) => self.yz = x,
            _ => self.zz = x,
        }
    }

    /// The product with a vector of the same number type ([`Symmetric3::mul_vector`] multiplies
    /// a constant matrix with a vector of any number type).
    #[inline(always)]
    #[must_use]
    pub fn mul_vec(&self, v: &T::V3) -> T::V3 {
        let (x, y, z) = (v.get(0), v.get(1), v.get(2));
        T::V3::new(
            x * self.xx + y * self.xy + z * self.xz,
            x * self.xy + y * self.yy + z * self.yz,
            x * self.xz + y * self.yz + z * self.zz,
        )
    }

    /// The trace.
    #[inline(always)]
    #[must_use]
    pub fn trace(&self) -> T {
        self.xx + self.yy + self.zz
    }

    /// `self + m·[c]×ᵀ[c]×`: a rotational inertia moved from the centre of mass `c` to the
    /// origin (the parallel-axis theorem, as [`Inertia::rotational_about`] the origin).
    ///
    /// [`Inertia::rotational_about`]: crate::Inertia::rotational_about
    #[inline(always)]
    #[must_use]
    pub fn add_parallel_axis(&self, c: &T::V3, m: f64) -> Self {
        *self + skew_square::<T>(c) * m
    }

    /// `R · self · Rᵀ`: the same tensor expressed in a frame rotated by `r`.
    #[inline(always)]
    #[must_use]
    pub fn rotate(&self, r: &T::M3) -> Self {
        // M = R·S by columns, then (M·Rᵀ)_ij = Σ_k M_ik·R_jk for the six entries i ≤ j only.
        let m = [
            r.mul_vec(&self.column(0)),
            r.mul_vec(&self.column(1)),
            r.mul_vec(&self.column(2)),
        ];
        Self {
            xx: rotated_entry::<T>(&m, r, 0, 0),
            xy: rotated_entry::<T>(&m, r, 0, 1),
            xz: rotated_entry::<T>(&m, r, 0, 2),
            yy: rotated_entry::<T>(&m, r, 1, 1),
            yz: rotated_entry::<T>(&m, r, 1, 2),
            zz: rotated_entry::<T>(&m, r, 2, 2),
        }
    }
}

/// `[v]×ᵀ [v]×` in any number type ([`Symmetric3::skew_square`]).
#[inline(always)]
fn skew_square<T: Real>(v: &T::V3) -> Symmetric3<T> {
    let (x, y, z) = (v.get(0), v.get(1), v.get(2));
    Symmetric3 {
        xx: y * y + z * z,
        xy: -x * y,
        xz: -x * z,
        yy: x * x + z * z,
        yz: -y * z,
        zz: x * x + y * y,
    }
}

/// Entry `(i, j)` of `M·Rᵀ` for the columns `m` of `M` (a plain function, not a closure: see
/// the note in `Se3`'s generic kernels about closures and SIMD features).
#[inline(always)]
fn rotated_entry<T: Real>(m: &[T::V3; 3], r: &T::M3, i: usize, j: usize) -> T {
    m[0].get(i) * r.col(0).get(j) + m[1].get(i) * r.col(1).get(j) + m[2].get(i) * r.col(2).get(j)
}

impl<T: Real> Add for Symmetric3<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self {
            xx: self.xx + o.xx,
            xy: self.xy + o.xy,
            xz: self.xz + o.xz,
            yy: self.yy + o.yy,
            yz: self.yz + o.yz,
            zz: self.zz + o.zz,
        }
    }
}

impl<T: Real> AddAssign for Symmetric3<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<T: Real> Sub for Symmetric3<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self + o * -1.0
    }
}

impl<T: Real> Mul<f64> for Symmetric3<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: f64) -> Self {
        Self {
            xx: self.xx * s,
            xy: self.xy * s,
            xz: self.xz * s,
            yy: self.yy * s,
            yz: self.yz * s,
            zz: self.zz * s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn voigt_and_urdf_orders() {
        let s = Symmetric3::new(1.0, 0.1, 0.2, 2.0, 0.3, 3.0);
        assert_eq!(s.to_voigt(), [1.0, 2.0, 3.0, 0.3, 0.2, 0.1]);
        assert_eq!(Symmetric3::from_voigt(s.to_voigt()), s);
        assert_eq!(s.to_urdf_array(), [1.0, 0.1, 0.2, 2.0, 0.3, 3.0]);
        assert_eq!(Symmetric3::from_mat3(&s.to_mat3()), s);
        let v = DVec3::new(0.5, -1.0, 2.0);
        assert!((s.mul_vec3(v) - s.to_mat3() * v).length() < 1e-15);
    }

    #[test]
    fn eigenvalues_of_rotated_diagonal() {
        let d = Symmetric3::from_diagonal(DVec3::new(3.0, 1.0, 2.0));
        let r = crate::rotation::from_rpy(0.3, 0.7, -1.1);
        let e = d.rotate(&r).eigenvalues();
        for (x, y) in e.iter().zip([1.0, 2.0, 3.0]) {
            assert!((x - y).abs() < 1e-13, "{e:?}");
        }
    }

    #[test]
    fn validity_check_reports_the_defect() {
        assert!(
            Symmetric3::from_diagonal(DVec3::new(1.0, 1.0, 1.0))
                .check_inertia(1e-9)
                .is_ok()
        );
        // A thin rod: I1 + I2 = I3 exactly is still valid.
        assert!(
            Symmetric3::from_diagonal(DVec3::new(0.0, 1.0, 1.0))
                .check_inertia(1e-9)
                .is_ok()
        );
        assert!(matches!(
            Symmetric3::from_diagonal(DVec3::new(-1.0, 2.0, 2.0)).check_inertia(1e-9),
            Err(InertiaDefect::NotPositive { .. })
        ));
        assert!(matches!(
            Symmetric3::from_diagonal(DVec3::new(1.0, 1.0, 5.0)).check_inertia(1e-9),
            Err(InertiaDefect::TriangleInequality { .. })
        ));
        assert_eq!(
            Symmetric3::new(f64::NAN, 0.0, 0.0, 1.0, 0.0, 1.0).check_inertia(1e-9),
            Err(InertiaDefect::NonFinite)
        );
        let mut m = DMat3::IDENTITY;
        m.y_axis.x = 0.5;
        assert!(matches!(
            Symmetric3::from_mat3_checked(&m, 1e-12),
            Err(InertiaDefect::NotSymmetric { .. })
        ));
    }
}
