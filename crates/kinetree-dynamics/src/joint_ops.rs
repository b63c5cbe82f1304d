//! Small spatial kernels shared by the sweeps, and the per-joint specialisations that skip the
//! zero entries of axis-aligned motion subspaces.

use kinetree_kinematics::JointModel;
use kinetree_kinematics::spatial::glam::{DMat3, DVec3};
use kinetree_kinematics::spatial::{Force, Inertia, Motion, Se3, Symmetric3};

/// `Rᵀ·v` without forming the transpose.
#[inline(always)]
pub(crate) fn rot_t(r: &DMat3, v: DVec3) -> DVec3 {
    DVec3::new(r.x_axis.dot(v), r.y_axis.dot(v), r.z_axis.dot(v))
}

/// `x⁻¹·m` for a motion given in the parent frame of `x = parent_from_child`.
#[inline(always)]
pub(crate) fn inv_motion(x: &Se3, m: &Motion) -> Motion {
    Motion::new(
        rot_t(&x.rotation, m.linear - x.translation.cross(m.angular)),
        rot_t(&x.rotation, m.angular),
    )
}

/// `x·f` for a force given in the child frame of `x = parent_from_child`.
#[inline(always)]
pub(crate) fn act_force(x: &Se3, f: &Force) -> Force {
    let linear = x.rotation * f.linear;
    Force::new(linear, x.rotation * f.angular + x.translation.cross(linear))
}

/// `a × (s·e_K)` for the unit axis `e_K`.
#[inline(always)]
pub(crate) fn cross_axis<const K: usize>(a: DVec3, s: f64) -> DVec3 {
    match K {
        0 => DVec3::new(0.0, a.z * s, -a.y * s),
        1 => DVec3::new(-a.z * s, 0.0, a.x * s),
        _ => DVec3::new(a.y * s, -a.x * s, 0.0),
    }
}

/// `e_K × a` for the unit axis `e_K`.
#[inline(always)]
pub(crate) fn axis_cross<const K: usize>(a: DVec3) -> DVec3 {
    match K {
        0 => DVec3::new(0.0, -a.z, a.y),
        1 => DVec3::new(a.z, 0.0, -a.x),
        _ => DVec3::new(-a.y, a.x, 0.0),
    }
}

/// Column `K` of a symmetric matrix.
#[inline(always)]
pub(crate) fn sym_col<const K: usize>(s: &Symmetric3) -> DVec3 {
    match K {
        0 => DVec3::new(s.xx, s.xy, s.xz),
        1 => DVec3::new(s.xy, s.yy, s.yz),
        _ => DVec3::new(s.xz, s.yz, s.zz),
    }
}

/// `Sᵀ·f` for an axis-aligned joint: the torque about (`REV`) or force along axis `K`.
#[inline(always)]
pub(crate) fn axis_project<const K: usize, const REV: bool>(f: &Force) -> f64 {
    if REV { f.angular[K] } else { f.linear[K] }
}

/// `I·S` for an axis-aligned joint's subspace `S = e_K` (angular if `REV`, else linear).
#[inline(always)]
pub(crate) fn axis_momentum<const K: usize, const REV: bool>(y: &OriginInertia) -> Force {
    if REV {
        Force::new(axis_cross::<K>(y.h), sym_col::<K>(&y.i))
    } else {
        let mut lin = DVec3::ZERO;
        lin[K] = y.m;
        Force::new(lin, -axis_cross::<K>(y.h))
    }
}

/// `Sᵀ·f` for one degree of freedom of a 1-DoF axis-aligned joint (`None` for other kinds).
#[inline(always)]
pub(crate) fn project_1dof(kind: Kind, f: &Force) -> Option<f64> {
    Some(match kind {
        Kind::RevoluteAxis(0) => axis_project::<0, true>(f),
        Kind::RevoluteAxis(1) => axis_project::<1, true>(f),
        Kind::RevoluteAxis(_) => axis_project::<2, true>(f),
        Kind::PrismaticAxis(0) => axis_project::<0, false>(f),
        Kind::PrismaticAxis(1) => axis_project::<1, false>(f),
        Kind::PrismaticAxis(_) => axis_project::<2, false>(f),
        Kind::Other => return None,
    })
}

/// A joint kind as the hot loops dispatch on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// Revolute about axis `0..3` of the body frame.
    RevoluteAxis(usize),
    /// Prismatic along axis `0..3` of the body frame.
    PrismaticAxis(usize),
    /// Anything else (general axis, multi-DoF): the generic path.
    Other,
}

impl Kind {
    #[inline(always)]
    pub(crate) fn of(jm: &JointModel) -> Self {
        match jm {
            JointModel::RevoluteX => Self::RevoluteAxis(0),
            JointModel::RevoluteY => Self::RevoluteAxis(1),
            JointModel::RevoluteZ => Self::RevoluteAxis(2),
            JointModel::PrismaticX => Self::PrismaticAxis(0),
            JointModel::PrismaticY => Self::PrismaticAxis(1),
            JointModel::PrismaticZ => Self::PrismaticAxis(2),
            _ => Self::Other,
        }
    }
}

/// A spatial inertia about the body-frame origin: mass `m`, first moment `h = m·c` and
/// rotational inertia `i` about the origin. Sums are plain sums (no division), which makes it the
/// form for composite inertias.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OriginInertia {
    pub(crate) m: f64,
    pub(crate) h: DVec3,
    pub(crate) i: Symmetric3,
}

impl OriginInertia {
    pub(crate) const ZERO: Self = Self {
        m: 0.0,
        h: DVec3::ZERO,
        i: Symmetric3::ZERO,
    };

    /// The origin form of a rigid-body inertia.
    #[inline(always)]
    pub(crate) fn from_inertia(inertia: &Inertia) -> Self {
        Self {
            m: inertia.mass,
            h: inertia.com * inertia.mass,
            i: inertia.rotational_about(DVec3::ZERO),
        }
    }

    /// `self += o`.
    #[inline(always)]
    pub(crate) fn add_assign(&mut self, o: &Self) {
        self.m += o.m;
        self.h += o.h;
        self.i += o.i;
    }

    /// The momentum `I·s` of a motion `s` (`[linear; angular]`).
    #[inline(always)]
    pub(crate) fn mul_motion(&self, s: &Motion) -> Force {
        Force::new(
            s.linear * self.m + s.angular.cross(self.h),
            self.h.cross(s.linear) + self.i.mul_vec3(s.angular),
        )
    }
}

/// `R·S·Rᵀ` for a symmetric `S`.
#[inline(always)]
pub(crate) fn rotate_symmetric(s: &Symmetric3, r: &DMat3) -> Symmetric3 {
    // M = R·S (columns), then (M·Rᵀ)_ij = Σ_k M_ik·R_jk for i ≤ j.
    let sx = DVec3::new(s.xx, s.xy, s.xz);
    let sy = DVec3::new(s.xy, s.yy, s.yz);
    let sz = DVec3::new(s.xz, s.yz, s.zz);
    let m0 = *r * sx;
    let m1 = *r * sy;
    let m2 = *r * sz;
    let row = |v: DVec3, k: usize| v[k];
    let entry = |i: usize, j: usize| {
        row(m0, i) * r.x_axis[j] + row(m1, i) * r.y_axis[j] + row(m2, i) * r.z_axis[j]
    };
    Symmetric3::new(
        entry(0, 0),
        entry(0, 1),
        entry(0, 2),
        entry(1, 1),
        entry(1, 2),
        entry(2, 2),
    )
}

/// `(sin x, cos x)` to within an ulp or two, inlined and branch-free for `|x| < 1e5` (every
/// joint angle in practice); larger arguments fall back to [`f64::sin_cos`].
///
/// Cody–Waite reduction by π/2 with a three-part constant, then fdlibm's minimax kernels on
/// `[-π/4, π/4]`. About half the cost of the libm call, which matters because every revolute
/// joint of every sweep needs one.
#[inline(always)]
#[allow(
    clippy::excessive_precision,
    reason = "fdlibm's constants, digit for digit"
)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    // π/2 split into parts whose products with |k| < 2^20 are exact (fdlibm's pio2_1, pio2_2).
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17e0;
    const PIO2_2: f64 = 6.077_100_506_303_965_976_6e-11;
    const PIO2_3: f64 = 2.022_266_248_795_950_631_54e-21;
    const ROUND: f64 = 6_755_399_441_055_744.0; // 1.5·2^52: adding it rounds to an integer.
    const S1: f64 = -1.666_666_666_666_663_243_48e-1;
    const S2: f64 = 8.333_333_333_322_489_461_24e-3;
    const S3: f64 = -1.984_126_982_985_794_931_34e-4;
    const S4: f64 = 2.755_731_370_707_006_767_89e-6;
    const S5: f64 = -2.505_076_025_340_686_341_95e-8;
    const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    const C1: f64 = 4.166_666_666_666_660_190_37e-2;
    const C2: f64 = -1.388_888_888_887_410_957_49e-3;
    const C3: f64 = 2.480_158_728_947_672_941_78e-5;
    const C4: f64 = -2.755_731_435_139_066_330_35e-7;
    const C5: f64 = 2.087_572_321_298_174_827_90e-9;
    const C6: f64 = -1.135_964_755_778_819_482_65e-11;
    if x.abs() >= 1e5 {
        return x.sin_cos();
    }
    let kf = (x * core::f64::consts::FRAC_2_PI + ROUND) - ROUND;
    let r = ((x - kf * PIO2_1) - kf * PIO2_2) - kf * PIO2_3;
    let z = r * r;
    let s = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    let p = z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let c = w + (((1.0 - w) - hz) + p);
    // Quadrant n = k mod 4: (sin, cos) = (s, c), (c, -s), (-s, -c), (-c, s).
    let n = kf as i64 as u64;
    let swap = 0u64.wrapping_sub(n & 1);
    let (sb, cb) = (s.to_bits(), c.to_bits());
    let sin_bits = (sb & !swap) | (cb & swap);
    let cos_bits = (cb & !swap) | (sb & swap);
    let sin_sign = (n & 2) << 62;
    let cos_sign = (n.wrapping_add(1) & 2) << 62;
    (
        f64::from_bits(sin_bits ^ sin_sign),
        f64::from_bits(cos_bits ^ cos_sign),
    )
}

/// `parent_from_child` of a body at joint configuration `q` (as
/// [`JointModel::placed_transform`]), with the fast [`sin_cos`] for axis-aligned revolute joints.
#[inline(always)]
pub(crate) fn placed_transform(jm: &JointModel, placement: &Se3, q: &[f64]) -> Se3 {
    let r = &placement.rotation;
    match jm {
        JointModel::RevoluteX => {
            let (s, c) = sin_cos(q[0]);
            Se3::new(
                DMat3::from_cols(
                    r.x_axis,
                    r.y_axis * c + r.z_axis * s,
                    r.z_axis * c - r.y_axis * s,
                ),
                placement.translation,
            )
        }
        JointModel::RevoluteY => {
            let (s, c) = sin_cos(q[0]);
            Se3::new(
                DMat3::from_cols(
                    r.x_axis * c - r.z_axis * s,
                    r.y_axis,
                    r.x_axis * s + r.z_axis * c,
                ),
                placement.translation,
            )
        }
        JointModel::RevoluteZ => {
            let (s, c) = sin_cos(q[0]);
            Se3::new(
                DMat3::from_cols(
                    r.x_axis * c + r.y_axis * s,
                    r.y_axis * c - r.x_axis * s,
                    r.z_axis,
                ),
                placement.translation,
            )
        }
        _ => jm.placed_transform(placement, q),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / f64::EPSILON
    }

    #[test]
    fn sin_cos_matches_libm() {
        let mut worst: f64 = 0.0;
        let mut x = -1.0e5 + 0.123;
        while x < 1.0e5 {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max(ulps(s, s0)).max(ulps(c, c0));
            x += 0.777_123;
        }
        for i in -2000..2000 {
            // Around multiples of π/4 and tiny arguments.
            let x = f64::from(i) * core::f64::consts::FRAC_PI_4 * (1.0 + 1e-12);
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max(ulps(s, s0)).max(ulps(c, c0));
            let t = f64::from(i) * 1e-9;
            let (s, c) = sin_cos(t);
            assert!(s == t.sin() || ulps(s, t.sin()) <= 1.0, "{t}");
            assert!(c == t.cos() || ulps(c, t.cos()) <= 1.0, "{t}");
        }
        assert!(
            worst <= 2.0,
            "worst error {worst} ulp (absolute, in units of 2^-52)"
        );
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(1e6), 1e6f64.sin_cos());
    }

    #[test]
    fn fast_placed_transform_matches_the_kinematics_one() {
        let placement = Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, 0.5, -0.6]);
        for jm in [
            JointModel::RevoluteX,
            JointModel::RevoluteY,
            JointModel::RevoluteZ,
        ] {
            for q in [-3.0, -0.7, 0.0, 0.3, 2.9, 12.0] {
                let a = placed_transform(&jm, &placement, &[q]);
                let b = jm.placed_transform(&placement, &[q]);
                assert!(a.abs_diff_eq(&b, 1e-15, 1e-15), "{jm:?} {q}");
            }
        }
    }
}

/// A rotation as the kernels apply it: the identity, a rotation about a coordinate axis (given
/// by its sine and cosine), or a general matrix. Joint rotations of axis-aligned revolute joints
/// and most URDF placements (`rpy` about one axis, or none) take the cheap forms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Rot {
    Identity,
    /// Rotation about axis `k` (0, 1, 2) by the angle with sine `s` and cosine `c`.
    Axis {
        k: usize,
        s: f64,
        c: f64,
    },
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

/// Entry `(i, j)` of a symmetric matrix.
#[inline(always)]
fn sym_get(s: &Symmetric3, i: usize, j: usize) -> f64 {
    match (i.min(j), i.max(j)) {
        (0, 0) => s.xx,
        (0, 1) => s.xy,
        (0, _) => s.xz,
        (1, 1) => s.yy,
        (1, _) => s.yz,
        _ => s.zz,
    }
}

/// Sets entry `(i, j)` (and `(j, i)`) of a symmetric matrix.
#[inline(always)]
fn sym_set(s: &mut Symmetric3, i: usize, j: usize, x: f64) {
    match (i.min(j), i.max(j)) {
        (0, 0) => s.xx = x,
        (0, 1) => s.xy = x,
        (0, _) => s.xz = x,
        (1, 1) => s.yy = x,
        (1, _) => s.yz = x,
        _ => s.zz = x,
    }
}

impl Rot {
    /// The cheapest form of a constant rotation matrix (exact comparisons: only rotations that
    /// are exactly about one coordinate axis take the axis form).
    pub(crate) fn classify(r: &DMat3) -> Self {
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
    pub(crate) fn apply(&self, v: DVec3) -> DVec3 {
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
    pub(crate) fn apply_sym(&self, m: &Symmetric3) -> Symmetric3 {
        match *self {
            Self::Identity => *m,
            Self::Axis { k, s, c } => per_axis!(k, |i, j, kk| {
                let (a, b, d) = (sym_get(m, i, i), sym_get(m, i, j), sym_get(m, j, j));
                let (ik, jk) = (sym_get(m, i, kk), sym_get(m, j, kk));
                let (cc, ss, cs) = (c * c, s * s, c * s);
                let mut out = *m;
                sym_set(&mut out, i, i, cc * a - 2.0 * cs * b + ss * d);
                sym_set(&mut out, j, j, ss * a + 2.0 * cs * b + cc * d);
                sym_set(&mut out, i, j, cs * (a - d) + (cc - ss) * b);
                sym_set(&mut out, i, kk, c * ik - s * jk);
                sym_set(&mut out, j, kk, s * ik + c * jk);
                out
            }),
            Self::General(r) => rotate_symmetric(m, &r),
        }
    }
}

/// The joint's own rotation when it is about a coordinate axis (axis-aligned revolute joints):
/// `k` is 0, 1, 2 for x, y, z, or 3 for no rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct JointRot {
    k: usize,
    s: f64,
    c: f64,
}

impl JointRot {
    pub(crate) const NONE: Self = Self {
        k: 3,
        s: 0.0,
        c: 1.0,
    };

    #[inline(always)]
    fn rot(self) -> Rot {
        if self.k < 3 {
            Rot::Axis {
                k: self.k,
                s: self.s,
                c: self.c,
            }
        } else {
            Rot::Identity
        }
    }
}

/// `parent_from_body` of a body with joint `jm` and constant placement `placement` at joint
/// configuration `q` (as [`JointModel::placed_transform`], with the fast [`sin_cos`]), and the
/// joint's own rotation when it is about a coordinate axis. With the placement's rotation form
/// (see [`Rot::classify`]) that factors the transform as `T(t)·R_placement·R_joint` for
/// [`act_inertia`]; joints of other kinds report [`JointRot::NONE`] and their whole rotation
/// must be used as the placement rotation.
#[inline(always)]
pub(crate) fn placed_transform_factored(
    jm: &JointModel,
    placement: &Se3,
    q: &[f64],
) -> (Se3, JointRot) {
    match Kind::of(jm) {
        Kind::RevoluteAxis(k) => {
            let (s, c) = sin_cos(q[0]);
            let r = &placement.rotation;
            let (ci, cj) = match k {
                0 => (r.y_axis, r.z_axis),
                1 => (r.z_axis, r.x_axis),
                _ => (r.x_axis, r.y_axis),
            };
            // Columns i and j of R·R_k(θ): e_i ↦ c·e_i + s·e_j, e_j ↦ -s·e_i + c·e_j.
            let (ni, nj) = (ci * c + cj * s, cj * c - ci * s);
            let rotation = match k {
                0 => DMat3::from_cols(r.x_axis, ni, nj),
                1 => DMat3::from_cols(nj, r.y_axis, ni),
                _ => DMat3::from_cols(ni, nj, r.z_axis),
            };
            (
                Se3::new(rotation, placement.translation),
                JointRot { k, s, c },
            )
        }
        Kind::PrismaticAxis(k) => (
            Se3::new(
                placement.rotation,
                placement.translation + placement.rotation.col(k) * q[0],
            ),
            JointRot::NONE,
        ),
        Kind::Other => (jm.placed_transform(placement, q), JointRot::NONE),
    }
}

/// An inertia in the child frame of `x = T(t)·R_placement·R_joint`, expressed in the parent
/// frame: the rotations are applied in their cheap forms.
#[inline(always)]
pub(crate) fn act_inertia(
    y: &OriginInertia,
    joint: JointRot,
    placement: &Rot,
    t: DVec3,
) -> OriginInertia {
    let jr = joint.rot();
    let h = placement.apply(jr.apply(y.h));
    let i = placement.apply_sym(&jr.apply_sym(&y.i));
    OriginInertia { m: y.m, h, i }.translated(t)
}

impl OriginInertia {
    /// The same inertia about a frame whose origin is at `-t` (a pure translation of the frame:
    /// the inertia moves by `t`).
    #[inline(always)]
    pub(crate) fn translated(&self, t: DVec3) -> Self {
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
}

#[cfg(test)]
mod factored_tests {
    use super::*;

    #[test]
    fn factored_transforms_match_se3() {
        let placements = [
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.0, 0.0, 0.0]),
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [-core::f64::consts::FRAC_PI_2, 0.0, 0.0]),
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.0, 1.3, 0.0]),
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.0, 0.0, -2.1]),
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, 0.5, -0.6]),
        ];
        let expected_forms = ["Identity", "Axis", "Axis", "Axis", "General"];
        let f = Force::from_array([0.3, -1.2, 0.5, 2.0, -0.1, 0.7]);
        let m = Motion::from_array([-0.4, 0.9, 0.2, 0.6, -0.3, 1.1]);
        let inertia = Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        );
        let y = OriginInertia::from_inertia(&inertia);
        let joints = [
            JointModel::RevoluteX,
            JointModel::RevoluteY,
            JointModel::RevoluteZ,
            JointModel::PrismaticX,
            JointModel::PrismaticY,
            JointModel::PrismaticZ,
            JointModel::Revolute(DVec3::new(0.6, 0.0, 0.8)),
            JointModel::Spherical,
        ];
        for (p, form) in placements.iter().zip(expected_forms) {
            let rot = Rot::classify(&p.rotation);
            assert!(format!("{rot:?}").starts_with(form), "{rot:?}");
            for jm in joints {
                let q: &[f64] = if jm == JointModel::Spherical {
                    &[0.1, 0.2, 0.3, 0.927_361_849_549_570_3]
                } else {
                    &[0.7]
                };
                let x = jm.placed_transform(p, q);
                let (x2, jr) = placed_transform_factored(&jm, p, q);
                assert!(x2.abs_diff_eq(&x, 1e-15, 1e-15), "{jm:?} {form}");
                assert!(act_force(&x, &f).abs_diff_eq(&x.act_force(&f), 1e-14));
                assert!(inv_motion(&x, &m).abs_diff_eq(&x.act_inv_motion(&m), 1e-14));
                let placement_rot = if Kind::of(&jm) == Kind::Other {
                    Rot::General(x.rotation)
                } else {
                    rot
                };
                let a = act_inertia(&y, jr, &placement_rot, x.translation);
                let b = OriginInertia::from_inertia(&inertia.transformed(&x));
                assert!((a.m - b.m).abs() < 1e-15 && (a.h - b.h).length() < 1e-14);
                assert!(
                    a.i.to_mat3().abs_diff_eq(b.i.to_mat3(), 1e-14),
                    "{jm:?} {form}"
                );
            }
        }
    }
}
