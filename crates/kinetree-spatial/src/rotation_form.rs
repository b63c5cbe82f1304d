//! [`RotationForm`]: a rotation in the cheapest form the kernels can apply it in.

use crate::Symmetric3;
use crate::real::{Matrix3, Real, Vector3};
use glam::{DMat3, DVec3};

/// A rotation as the kernels apply it: the identity, a rotation about a coordinate axis (given
/// by its sine and cosine), or a general matrix. The rotations of joints about a coordinate axis
/// and most URDF placements (`rpy` about one axis, or none) take the cheap forms.
///
/// ```
/// use kinetree_spatial::{RotationForm, Se3, DVec3};
/// let r = Se3::from_rotation_z(0.3).rotation;
/// let form = RotationForm::classify(&r);
/// assert!(matches!(form, RotationForm::Axis { k: 2, .. }));
/// let v = DVec3::new(1.0, 2.0, 3.0);
/// assert!((form.apply(v) - r * v).length() < 1e-15);
/// ```
///
/// Generic over the number type ([`Real`]): `RotationForm` holds `f64`s, `RotationForm<T>` the
/// angles (or matrix) of a block of states in lanes.
#[derive(Debug, PartialEq)]
pub enum RotationForm<T: Real = f64> {
    /// No rotation.
    Identity,
    /// Rotation about coordinate axis `k` (0, 1, 2) by the angle with sine `s` and cosine `c`.
    Axis {
        /// The axis: 0, 1, 2 for x, y, z.
        k: usize,
        /// Sine of the angle.
        s: T,
        /// Cosine of the angle.
        c: T,
    },
    /// Any rotation matrix.
    General(T::M3),
}

/// The other two axes `(i, j)` of a rotation about axis `k` in cyclic order (it maps
/// `e_i → c·e_i + s·e_j`).
#[inline(always)]
const fn others(k: usize) -> (usize, usize) {
    ((k + 1) % 3, (k + 2) % 3)
}

crate::copy_by_value!(RotationForm);

impl RotationForm {
    /// The cheapest form of a constant rotation matrix (exact comparisons: only rotations that
    /// are exactly about one coordinate axis take the axis form).
    #[must_use]
    pub fn classify(r: &DMat3) -> Self {
        if *r == DMat3::IDENTITY {
            return Self::Identity;
        }
        let cols = [r.x_axis, r.y_axis, r.z_axis];
        for k in 0..3 {
            let (i, j) = others(k);
            let mut e = DVec3::ZERO;
            e[k] = 1.0;
            // Column k is e_k, row k is e_kᵀ, and the (i, j) block is [[c, -s], [s, c]].
            if cols[k] == e && cols[i][k] == 0.0 && cols[j][k] == 0.0 {
                let (c, s) = (cols[i][i], cols[i][j]);
                if cols[j][j] == c && cols[j][i] == -s {
                    return Self::Axis { k, s, c };
                }
            }
        }
        Self::General(*r)
    }
}

impl<T: Real> RotationForm<T> {
    /// A constant rotation in this number type (in every lane).
    #[inline(always)]
    #[must_use]
    pub fn from_const(r: &RotationForm) -> Self {
        match *r {
            RotationForm::Identity => Self::Identity,
            RotationForm::Axis { k, s, c } => Self::Axis {
                k,
                s: T::splat(s),
                c: T::splat(c),
            },
            RotationForm::General(m) => Self::General(T::M3::from_const(&m)),
        }
    }

    /// `R·v`.
    #[inline(always)]
    #[must_use]
    pub fn apply(&self, v: T::V3) -> T::V3 {
        // The axis is made a constant so that the entries stay in registers (with the axis known
        // only at run time, the lane kernels read and wrote them through memory).
        match *self {
            Self::Identity => v,
            Self::Axis { k: 0, s, c } => axis_apply::<T, 0>(s, c, &v),
            Self::Axis { k: 1, s, c } => axis_apply::<T, 1>(s, c, &v),
            Self::Axis { s, c, .. } => axis_apply::<T, 2>(s, c, &v),
            Self::General(r) => r.mul_vec(&v),
        }
    }

    /// `R·S·Rᵀ` for a symmetric `S`.
    #[inline(always)]
    #[must_use]
    pub fn apply_sym(&self, m: &Symmetric3<T>) -> Symmetric3<T> {
        match *self {
            Self::Identity => *m,
            Self::Axis { k: 0, s, c } => axis_apply_sym::<T, 0>(s, c, m),
            Self::Axis { k: 1, s, c } => axis_apply_sym::<T, 1>(s, c, m),
            Self::Axis { s, c, .. } => axis_apply_sym::<T, 2>(s, c, m),
            Self::General(r) => m.rotate(&r),
        }
    }
}

/// A rotation about coordinate axis `K` (sine `s`, cosine `c`) applied to `v`.
#[inline(always)]
fn axis_apply<T: Real, const K: usize>(s: T, c: T, v: &T::V3) -> T::V3 {
    let (i, j) = others(K);
    let (vi, vj) = (v.get(i), v.get(j));
    let mut out = *v;
    *out.get_mut(i) = c * vi - s * vj;
    *out.get_mut(j) = s * vi + c * vj;
    out
}

/// A rotation about coordinate axis `K` applied to a symmetric matrix (`R·S·Rᵀ`).
#[inline(always)]
fn axis_apply_sym<T: Real, const K: usize>(s: T, c: T, m: &Symmetric3<T>) -> Symmetric3<T> {
    let (i, j) = others(K);
    let (a, b, d) = (m.get(i, i), m.get(i, j), m.get(j, j));
    let (ik, jk) = (m.get(i, K), m.get(j, K));
    let (cc, ss, cs) = (c * c, s * s, c * s);
    let mut out = *m;
    out.set(i, i, cc * a - cs * 2.0 * b + ss * d);
    out.set(j, j, ss * a + cs * 2.0 * b + cc * d);
    out.set(i, j, cs * (a - d) + (cc - ss) * b);
    out.set(i, K, c * ik - s * jk);
    out.set(j, K, s * ik + c * jk);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Se3;

    #[test]
    fn every_form_matches_the_matrix() {
        let cases = [
            (Se3::from_rpy(0.0, 0.0, 0.0).rotation, "Identity"),
            (
                Se3::from_rpy(-core::f64::consts::FRAC_PI_2, 0.0, 0.0).rotation,
                "Axis",
            ),
            (Se3::from_rpy(0.0, 1.3, 0.0).rotation, "Axis"),
            (Se3::from_rpy(0.0, 0.0, -2.1).rotation, "Axis"),
            (Se3::from_rpy(0.4, 0.5, -0.6).rotation, "General"),
        ];
        let s = Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6);
        let v = DVec3::new(0.3, -1.2, 0.5);
        for (r, form) in cases {
            let f = RotationForm::classify(&r);
            assert!(format!("{f:?}").starts_with(form), "{f:?}");
            assert!((f.apply(v) - r * v).length() < 1e-15);
            let expected = r * s.to_mat3() * r.transpose();
            assert!(
                f.apply_sym(&s).to_mat3().abs_diff_eq(expected, 1e-15),
                "{form}"
            );
            assert!(
                s.rotate(&r).to_mat3().abs_diff_eq(expected, 1e-15),
                "{form}"
            );
        }
    }
}
