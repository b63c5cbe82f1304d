//! Spatial inertia of a rigid body: mass, centre of mass and rotational inertia.

use crate::motion::{Force, Motion};
use crate::real::{Real, Vector3};
use crate::rotation::skew;
use crate::se3::Se3;
use crate::symmetric3::{InertiaDefect, Symmetric3};
use core::ops::{Add, AddAssign};
use glam::{DMat3, DVec3};

/// The spatial inertia of a rigid body, expressed in some frame `F`.
///
/// `mass` in kg, `com` the centre of mass in `F`'s coordinates, `rotational` the rotational
/// inertia about the centre of mass with `F`'s axes (kg·m²).
///
/// # Examples
/// ```
/// use kinetree_spatial::{Inertia, Motion, Symmetric3};
/// use glam::DVec3;
/// // A 2 kg point mass one metre along x, spinning at 3 rad/s about z.
/// let body = Inertia::new(2.0, DVec3::X, Symmetric3::ZERO);
/// let twist = Motion::new(DVec3::ZERO, DVec3::new(0.0, 0.0, 3.0));
/// // Speed 3 m/s: kinetic energy ½·2·3² = 9 J.
/// assert!((body.kinetic_energy(&twist) - 9.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Inertia {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass (m).
    pub com: DVec3,
    /// Rotational inertia about the centre of mass (kg·m²).
    pub rotational: Symmetric3,
}

impl Inertia {
    /// No mass at all.
    pub const ZERO: Self = Self {
        mass: 0.0,
        com: DVec3::ZERO,
        rotational: Symmetric3::ZERO,
    };

    /// From mass, centre of mass and rotational inertia about the centre of mass.
    #[inline]
    #[must_use]
    pub const fn new(mass: f64, com: DVec3, rotational: Symmetric3) -> Self {
        Self {
            mass,
            com,
            rotational,
        }
    }

    /// A point mass at `com`.
    #[inline]
    #[must_use]
    pub const fn point_mass(mass: f64, com: DVec3) -> Self {
        Self::new(mass, com, Symmetric3::ZERO)
    }

    /// Whether every value is finite.
    #[inline]
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.mass.is_finite() && self.com.is_finite() && self.rotational.is_finite()
    }

    /// Checks physical validity: non-negative mass and a valid rotational inertia
    /// ([`Symmetric3::check_inertia`]).
    ///
    /// # Errors
    /// The defect found; a negative mass is [`InertiaDefect::NegativeMass`].
    pub fn check(&self, tolerance: f64) -> Result<(), InertiaDefect> {
        if !self.is_finite() {
            return Err(InertiaDefect::NonFinite);
        }
        if self.mass < 0.0 {
            return Err(InertiaDefect::NegativeMass { mass: self.mass });
        }
        self.rotational.check_inertia(tolerance)
    }

    /// The rotational inertia about `point` (parallel-axis theorem): `I_c + m [c - p]×ᵀ[c - p]×`.
    #[inline]
    #[must_use]
    pub fn rotational_about(&self, point: DVec3) -> Symmetric3 {
        self.rotational + Symmetric3::skew_square(self.com - point) * self.mass
    }

    /// The 6x6 spatial inertia matrix in `[linear; angular]` order, row-major:
    /// `[[m·I, -m[c]×], [m[c]×, I_c + m[c]×ᵀ[c]×]]`, such that `M · v` is the momentum of twist `v`.
    #[must_use]
    #[doc(alias = "MassCOMinertia2T66")]
    pub fn to_matrix(&self) -> [[f64; 6]; 6] {
        let mc = skew(self.com) * self.mass;
        let io = self.rotational_about(DVec3::ZERO).to_mat3();
        let mut out = [[0.0; 6]; 6];
        for i in 0..3 {
            out[i][i] = self.mass;
            for j in 0..3 {
                out[i][j + 3] = -mc.col(j)[i];
                out[i + 3][j] = mc.col(j)[i];
                out[i + 3][j + 3] = io.col(j)[i];
            }
        }
        out
    }

    /// From a 6x6 spatial inertia matrix in `[linear; angular]` order (row-major), the inverse of
    /// [`Inertia::to_matrix`]. The matrix is read, not checked: use [`Inertia::check`] on the result.
    ///
    /// A zero mass gives a centre of mass at the origin.
    #[must_use]
    #[doc(alias = "Inertia66toMassCOMinertia")]
    pub fn from_matrix(m: &[[f64; 6]; 6]) -> Self {
        let mass = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
        // Lower-left block is m[c]×: read m·c from its skew part.
        let mc = DVec3::new(
            0.5 * (m[5][1] - m[4][2]),
            0.5 * (m[3][2] - m[5][0]),
            0.5 * (m[4][0] - m[3][1]),
        );
        let com = if mass != 0.0 { mc / mass } else { DVec3::ZERO };
        let io = DMat3::from_cols(
            DVec3::new(m[3][3], m[4][3], m[5][3]),
            DVec3::new(m[3][4], m[4][4], m[5][4]),
            DVec3::new(m[3][5], m[4][5], m[5][5]),
        );
        let rotational = Symmetric3::from_mat3(&io) - Symmetric3::skew_square(com) * mass;
        Self::new(mass, com, rotational)
    }

    /// The momentum `I · v` of a body moving with twist `v` (same frame as the inertia).
    #[inline(always)]
    #[must_use]
    pub fn mul_motion<T: Real>(&self, v: &Motion<T>) -> Force<T> {
        // Linear momentum m (v + ω × c); angular momentum about the origin c × p + I_c ω.
        let lin = (v.linear + v.angular.cross_const(self.com)).scale_by(self.mass);
        let angular =
            T::V3::const_cross(self.com, &lin) + self.rotational.mul_vector::<T>(&v.angular);
        Force {
            linear: lin,
            angular,
        }
    }

    /// The net force `I·a + v ×* (I·v)` on a body moving with twist `v` and acceleration `a`
    /// (the body force of the recursive Newton–Euler algorithm), in fewer operations than the
    /// two products and the cross product: with the linear momentum `p = m·(v + ω × c)`, the
    /// gyroscopic term `v ×* (I·v)` is `(ω × p, c × (ω × p) + ω × (I_c·ω))`.
    #[inline(always)]
    #[must_use]
    pub fn rnea_force<T: Real>(&self, v: &Motion<T>, a: &Motion<T>) -> Force<T> {
        let w = &v.angular;
        let p = (v.linear + w.cross_const(self.com)).scale_by(self.mass);
        let lin = (a.linear + a.angular.cross_const(self.com)).scale_by(self.mass) + w.cross(&p);
        let angular = T::V3::const_cross(self.com, &lin)
            + self.rotational.mul_vector::<T>(&a.angular)
            + w.cross(&self.rotational.mul_vector::<T>(w));
        Force {
            linear: lin,
            angular,
        }
    }

    /// The kinetic energy `½ vᵀ I v` of a body moving with twist `v`.
    #[inline]
    #[must_use]
    pub fn kinetic_energy(&self, v: &Motion) -> f64 {
        0.5 * v.dot(&self.mul_motion(v))
    }

    /// Expresses in frame `a` an inertia given in frame `b` (for `a_from_b`).
    #[inline]
    #[must_use]
    pub fn transformed(&self, a_from_b: &Se3) -> Self {
        Self::new(
            self.mass,
            a_from_b.transform_point(self.com),
            self.rotational.rotate(&a_from_b.rotation),
        )
    }

    /// Expresses in frame `b` an inertia given in frame `a` (the inverse of [`Inertia::transformed`]).
    #[inline]
    #[must_use]
    pub fn transformed_inv(&self, a_from_b: &Se3) -> Self {
        Self::new(
            self.mass,
            a_from_b.inverse_transform_point(self.com),
            self.rotational.rotate_inv(&a_from_b.rotation),
        )
    }
}

impl Add for Inertia {
    type Output = Inertia;
    /// The inertia of two bodies rigidly joined (both in the same frame).
    #[inline]
    fn add(self, o: Inertia) -> Inertia {
        let mass = self.mass + o.mass;
        if mass == 0.0 {
            return Inertia::new(0.0, DVec3::ZERO, self.rotational + o.rotational);
        }
        let com = (self.com * self.mass + o.com * o.mass) / mass;
        let d = self.com - o.com;
        let rotational = self.rotational
            + o.rotational
            + Symmetric3::skew_square(d) * (self.mass * o.mass / mass);
        Inertia::new(mass, com, rotational)
    }
}

impl AddAssign for Inertia {
    #[inline]
    fn add_assign(&mut self, o: Inertia) {
        *self = *self + o;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Inertia {
        Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        )
    }

    #[test]
    fn matrix_form_round_trips_and_gives_momentum() {
        let i = sample();
        let m = i.to_matrix();
        let back = Inertia::from_matrix(&m);
        assert!((back.mass - i.mass).abs() < 1e-14);
        assert!((back.com - i.com).length() < 1e-14);
        assert!(
            back.rotational
                .to_mat3()
                .abs_diff_eq(i.rotational.to_mat3(), 1e-14)
        );
        let v = Motion::from_array([0.3, -0.1, 0.7, 1.2, -0.4, 0.5]);
        let h = i.mul_motion(&v).to_array();
        for r in 0..6 {
            let mv: f64 = (0..6).map(|c| m[r][c] * v.to_array()[c]).sum();
            assert!((mv - h[r]).abs() < 1e-14);
        }
        // Symmetric.
        for r in 0..6 {
            for c in 0..6 {
                assert!((m[r][c] - m[c][r]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn rnea_force_is_the_momentum_rate() {
        let i = sample();
        for (v, a) in [
            (
                [0.3, -0.1, 0.7, 1.2, -0.4, 0.5],
                [-0.8, 0.2, 0.1, 0.3, 0.9, -1.4],
            ),
            ([5.0, 2.0, -3.0, -7.0, 4.0, 6.0], [0.0; 6]),
        ] {
            let (v, a) = (Motion::from_array(v), Motion::from_array(a));
            let want = i.mul_motion(&a) + v.cross_force(&i.mul_motion(&v));
            let got = i.rnea_force(&v, &a);
            assert!(got.abs_diff_eq(&want, 1e-13), "{got:?} against {want:?}");
        }
    }

    #[test]
    fn transform_commutes_with_momentum() {
        let i = sample();
        let x = Se3::from_xyz_rpy([0.5, 1.0, -0.3], [0.2, 0.4, -0.8]);
        let v = Motion::from_array([0.3, -0.1, 0.7, 1.2, -0.4, 0.5]);
        // h_a = X* h_b with h_b = I_b v_b and v_a = X v_b.
        let lhs = i.transformed(&x).mul_motion(&x.act_motion(&v));
        let rhs = x.act_force(&i.mul_motion(&v));
        assert!(lhs.abs_diff_eq(&rhs, 1e-13));
        let back = i.transformed(&x).transformed_inv(&x);
        assert!((back.com - i.com).length() < 1e-14);
        // Kinetic energy is frame independent.
        assert!(
            (i.kinetic_energy(&v) - i.transformed(&x).kinetic_energy(&x.act_motion(&v))).abs()
                < 1e-13
        );
    }

    #[test]
    fn sum_equals_sum_of_matrices() {
        let a = sample();
        let b = Inertia::new(
            1.5,
            DVec3::new(-0.4, 0.2, 0.1),
            Symmetric3::new(0.2, 0.0, 0.01, 0.3, 0.0, 0.1),
        );
        let s = (a + b).to_matrix();
        let (ma, mb) = (a.to_matrix(), b.to_matrix());
        for r in 0..6 {
            for c in 0..6 {
                assert!((s[r][c] - ma[r][c] - mb[r][c]).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn parallel_axis_for_a_point_mass() {
        // 3 kg at (0, 2, 0): about the origin, Ixx = Izz = 3·4 = 12, Iyy = 0.
        let i = Inertia::point_mass(3.0, DVec3::new(0.0, 2.0, 0.0));
        let io = i.rotational_about(DVec3::ZERO);
        assert_eq!(io.to_urdf_array(), [12.0, 0.0, 0.0, 0.0, 0.0, 12.0]);
        // A negative mass is named as such (it was "not positive semi-definite").
        let e = Inertia::new(-1.0, DVec3::ZERO, Symmetric3::IDENTITY)
            .check(1e-9)
            .unwrap_err();
        assert_eq!(e, InertiaDefect::NegativeMass { mass: -1.0 });
        assert_eq!(e.to_string(), "the mass -1 kg is negative");
    }
}
