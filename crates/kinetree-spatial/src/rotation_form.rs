//! [`RotationForm`]: a rotation in the cheapest form the kernels can apply it in.

use crate::Symmetric3;
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RotationForm {
    /// No rotation.
    Identity,
    /// Rotation about coordinate axis `k` (0, 1, 2) by the angle with sine `s` and cosine `c`.
    Axis {
        /// The axis: 0, 1, 2 for x, y, z.
        k: usize,
        /// Sine of the angle.
        s: f64,
        /// Cosine of the angle.
        c: f64,
    },
    /// Any rotation matrix.
    General(DMat3),
}

/// Expands `$body` once per axis with `$i`, `$j` the other two axes in cyclic order (rotation
/// about `k` maps `e_i → c·e_i + s·e_j`).
macro_rules! per_axis {
    ($k:expr, |$i:ident, $j:ident, $kk:ident| $body:expr) => {
        match $k {
            0 => {
                let ($i, $j, $kk) = (1usize, 2usize, 0usize);
                $body
            }
            1 => {
                let ($i, $j, $kk) = (2usize, 0usize, 1usize);
                $body
            }
            _ => {
                let ($i, $j, $kk) = (0usize, 1usize, 2usize);
                $body
            }
        }
    };
}

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
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
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

    /// `R·v`.
    #[inline(always)]
    #[must_use]
    pub fn apply(&self, v: DVec3) -> DVec3 {
        match *self {
            Self::Identity => v,
            Self::Axis { k, s, c } => per_axis!(k, |i, j, _kk| {
                let mut out = v;
                out[i] = c * v[i] - s * v[j];
                out[j] = s * v[i] + c * v[j];
                out
            }),
            Self::General(r) => r * v,
        }
    }

    /// `R·S·Rᵀ` for a symmetric `S`.
    #[inline(always)]
    #[must_use]
    pub fn apply_sym(&self, m: &Symmetric3) -> Symmetric3 {
        match *self {
            Self::Identity => *m,
            Self::Axis { k, s, c } => per_axis!(k, |i, j, kk| {
                let (a, b, d) = (m.get(i, i), m.get(i, j), m.get(j, j));
                let (ik, jk) = (m.get(i, kk), m.get(j, kk));
                let (cc, ss, cs) = (c * c, s * s, c * s);
                let mut out = *m;
                out.set(i, i, cc * a - 2.0 * cs * b + ss * d);
                out.set(j, j, ss * a + 2.0 * cs * b + cc * d);
                out.set(i, j, cs * (a - d) + (cc - ss) * b);
                out.set(i, kk, c * ik - s * jk);
                out.set(j, kk, s * ik + c * jk);
                out
            }),
            Self::General(r) => m.rotate(&r),
        }
    }
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
