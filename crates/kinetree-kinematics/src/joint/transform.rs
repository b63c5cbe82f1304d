//! Joint transforms: the fast [`sin_cos`], `parent_from_child` of a placed joint
//! ([`JointModel::placed_transform`]) and its factored form for composite inertias
//! ([`JointModel::placed_transform_factored`]).

use super::model::{JointModel, quat};
use glam::{DMat3, DVec3};
use kinetree_model::Body;
use kinetree_model::spatial::{OriginInertia, RotationForm, Se3};

/// `(sin x, cos x)` to within an ulp or two, inlined and branch-free for `|x| < 1e5` (every
/// joint angle in practice); larger arguments fall back to [`f64::sin_cos`].
///
/// Cody–Waite reduction by π/2 with a three-part constant, then fdlibm's minimax kernels on
/// `[-π/4, π/4]`. About half the cost of the libm call, which matters because every revolute
/// joint of every sweep needs one.
///
/// ```
/// let (s, c) = kinetree_kinematics::joint::sin_cos(0.5);
/// assert!((s - 0.5f64.sin()).abs() <= f64::EPSILON && (c - 0.5f64.cos()).abs() <= f64::EPSILON);
/// ```
#[inline(always)]
#[must_use]
#[allow(
    clippy::excessive_precision,
    reason = "fdlibm's constants, digit for digit"
)]
pub fn sin_cos(x: f64) -> (f64, f64) {
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

/// The placement rotation `R` times a rotation by `(s, c)` about coordinate axis `k`: columns `i`
/// and `j` of `R·R_k(θ)` are `c·r_i + s·r_j` and `c·r_j - s·r_i`.
#[inline(always)]
pub(crate) fn rotate_about_axis(r: &DMat3, k: usize, s: f64, c: f64) -> DMat3 {
    match k {
        0 => DMat3::from_cols(
            r.x_axis,
            r.y_axis * c + r.z_axis * s,
            r.z_axis * c - r.y_axis * s,
        ),
        1 => DMat3::from_cols(
            r.x_axis * c - r.z_axis * s,
            r.y_axis,
            r.x_axis * s + r.z_axis * c,
        ),
        _ => DMat3::from_cols(
            r.x_axis * c + r.y_axis * s,
            r.y_axis * c - r.x_axis * s,
            r.z_axis,
        ),
    }
}

/// The rotation by `(s, c)` about coordinate axis `k`, built entry by entry (what
/// [`rotate_about_axis`] gives for the identity, without its multiplications).
#[inline(always)]
pub(crate) fn axis_rotation(k: usize, s: f64, c: f64) -> DMat3 {
    match k {
        0 => DMat3::from_cols(DVec3::X, DVec3::new(0.0, c, s), DVec3::new(0.0, -s, c)),
        1 => DMat3::from_cols(DVec3::new(c, 0.0, -s), DVec3::Y, DVec3::new(s, 0.0, c)),
        _ => DMat3::from_cols(DVec3::new(c, s, 0.0), DVec3::new(-s, c, 0.0), DVec3::Z),
    }
}

/// The joint's own rotation when it is about a coordinate axis (the revolute joints about x, y,
/// z), as [`JointModel::placed_transform_factored`] reports it: small enough to keep per body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointRot {
    /// 0, 1, 2 for x, y, z, or 3 for no joint rotation about a coordinate axis.
    k: usize,
    s: f64,
    c: f64,
}

impl JointRot {
    /// No rotation about a coordinate axis (prismatic joints, or a joint of another kind whose
    /// whole rotation is then the "placement" rotation).
    pub const NONE: Self = Self {
        k: 3,
        s: 0.0,
        c: 1.0,
    };

    /// The rotation in the kernels' form ([`RotationForm::Identity`] for [`JointRot::NONE`]).
    #[inline(always)]
    #[must_use]
    pub fn form(self) -> RotationForm {
        if self.k < 3 {
            RotationForm::Axis {
                k: self.k,
                s: self.s,
                c: self.c,
            }
        } else {
            RotationForm::Identity
        }
    }
}

impl JointModel {
    /// `parent_from_child` of `placement * joint_motion(q)`, computed without forming the joint
    /// motion where the axis is aligned (and with the fast [`sin_cos`]). `q` is the joint's block
    /// of the configuration.
    #[inline(always)]
    #[must_use]
    pub fn placed_transform(&self, placement: &Se3, q: &[f64]) -> Se3 {
        let r = &placement.rotation;
        match *self {
            Self::RevoluteX => {
                let (s, c) = sin_cos(q[0]);
                Se3::new(rotate_about_axis(r, 0, s, c), placement.translation)
            }
            Self::RevoluteY => {
                let (s, c) = sin_cos(q[0]);
                Se3::new(rotate_about_axis(r, 1, s, c), placement.translation)
            }
            Self::RevoluteZ => {
                let (s, c) = sin_cos(q[0]);
                Se3::new(rotate_about_axis(r, 2, s, c), placement.translation)
            }
            Self::PrismaticX => Se3::new(*r, placement.translation + r.x_axis * q[0]),
            Self::PrismaticY => Se3::new(*r, placement.translation + r.y_axis * q[0]),
            Self::PrismaticZ => Se3::new(*r, placement.translation + r.z_axis * q[0]),
            Self::Prismatic(a) => Se3::new(*r, placement.translation + *r * (a * q[0])),
            Self::Fixed => *placement,
            // Floating roots and many ball joints sit at the identity: skip the product.
            _ if *placement == Se3::IDENTITY => self.transform(q),
            _ => *placement * self.transform(q),
        }
    }

    /// As [`JointModel::placed_transform`], and the joint's own rotation when it is about a
    /// coordinate axis. With the placement rotation's form ([`RotationForm::classify`]) that
    /// factors the transform as `T(t)·R_placement·R_joint` for
    /// [`JointModel::inertia_to_parent`]; joints of other kinds report [`JointRot::NONE`] and
    /// their whole rotation must be used as the placement rotation.
    #[inline(always)]
    #[must_use]
    pub fn placed_transform_factored(&self, placement: &Se3, q: &[f64]) -> (Se3, JointRot) {
        match self.axis_index() {
            Some((k, true)) => {
                let (s, c) = sin_cos(q[0]);
                (
                    Se3::new(
                        rotate_about_axis(&placement.rotation, k, s, c),
                        placement.translation,
                    ),
                    JointRot { k, s, c },
                )
            }
            _ => (self.placed_transform(placement, q), JointRot::NONE),
        }
    }

    /// An inertia `y` about the child frame's origin, expressed about the parent frame's for
    /// `parent_from_child = x` as factored by [`JointModel::placed_transform_factored`]
    /// (`joint`), with `placement` the form of the placement rotation: the rotations are applied
    /// in their cheap forms. For a joint that is not axis-aligned revolute or prismatic, or a
    /// general placement rotation, the rotation of `x` is used whole.
    #[inline(always)]
    #[must_use]
    pub fn inertia_to_parent(
        &self,
        y: &OriginInertia,
        joint: JointRot,
        placement: &RotationForm,
        x: &Se3,
    ) -> OriginInertia {
        // A general placement rotation costs as much as the whole rotation of `x`: one product.
        let rotated =
            if self.axis_index().is_some() && !matches!(placement, RotationForm::General(_)) {
                y.rotated(&joint.form()).rotated(placement)
            } else {
                y.rotated(&RotationForm::General(x.rotation))
            };
        rotated.translated(x.translation)
    }

    /// `parent_from_body` of `body` (whose joint model this is) for the full configuration `q`.
    /// A coupled mimic body uses `multiplier · q_leader + offset`.
    #[inline]
    #[must_use]
    pub fn body_transform(&self, body: &Body, q: &[f64]) -> Se3 {
        match &body.mimic {
            None => self.placed_transform(&body.placement, &q[body.idx_q..body.idx_q + body.nq]),
            Some(m) => {
                self.placed_transform(&body.placement, &[m.multiplier * q[body.idx_q] + m.offset])
            }
        }
    }

    /// The joint motion `joint_from_child` for configuration block `q`.
    #[must_use]
    pub fn transform(&self, q: &[f64]) -> Se3 {
        match *self {
            Self::Fixed => Se3::IDENTITY,
            Self::RevoluteX => Se3::from_rotation_x(q[0]),
            Self::RevoluteY => Se3::from_rotation_y(q[0]),
            Self::RevoluteZ => Se3::from_rotation_z(q[0]),
            Self::Revolute(a) => Se3::from_axis_angle(a, q[0]),
            Self::PrismaticX => Se3::from_translation(DVec3::X * q[0]),
            Self::PrismaticY => Se3::from_translation(DVec3::Y * q[0]),
            Self::PrismaticZ => Se3::from_translation(DVec3::Z * q[0]),
            Self::Prismatic(a) => Se3::from_translation(a * q[0]),
            Self::Cylindrical(a) => Se3::new(Se3::from_axis_angle(a, q[1]).rotation, a * q[0]),
            Self::Spherical => Se3::from_quat(quat(q)),
            Self::Planar { u, w, n } => {
                Se3::new(Se3::from_axis_angle(n, q[2]).rotation, u * q[0] + w * q[1])
            }
            Self::Floating => {
                Se3::from_translation_quat(DVec3::new(q[0], q[1], q[2]), quat(&q[3..7]))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree_model::spatial::{Force, Inertia, Motion, Symmetric3};

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
    fn placed_transforms_match_the_product_with_the_joint_motion() {
        let placement = Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, 0.5, -0.6]);
        let q = [0.7];
        let cases = [
            (JointModel::RevoluteX, JointModel::Revolute(DVec3::X)),
            (JointModel::RevoluteY, JointModel::Revolute(DVec3::Y)),
            (JointModel::RevoluteZ, JointModel::Revolute(DVec3::Z)),
            (JointModel::PrismaticX, JointModel::Prismatic(DVec3::X)),
            (JointModel::PrismaticY, JointModel::Prismatic(DVec3::Y)),
            (JointModel::PrismaticZ, JointModel::Prismatic(DVec3::Z)),
        ];
        for (fast, general) in cases {
            for q in [[-3.0], [-0.7], [0.0], q, [2.9], [12.0]] {
                let a = fast.placed_transform(&placement, &q);
                let b = placement * general.transform(&q);
                assert!(a.abs_diff_eq(&b, 1e-15, 1e-15), "{fast:?}");
            }
            assert!(
                fast.motion(&[1.3])
                    .abs_diff_eq(&general.motion(&[1.3]), 0.0)
            );
        }
    }

    #[test]
    fn factored_transforms_and_inertias_match_se3() {
        let placements = [
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.0, 0.0, 0.0]),
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [-core::f64::consts::FRAC_PI_2, 0.0, 0.0]),
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.0, 1.3, 0.0]),
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.0, 0.0, -2.1]),
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, 0.5, -0.6]),
        ];
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
        for p in &placements {
            let rot = RotationForm::classify(&p.rotation);
            for jm in joints {
                let q: &[f64] = if jm == JointModel::Spherical {
                    &[0.1, 0.2, 0.3, 0.927_361_849_549_570_3]
                } else {
                    &[0.7]
                };
                let x = *p * jm.transform(q);
                let (x2, jr) = jm.placed_transform_factored(p, q);
                assert!(x2.abs_diff_eq(&x, 1e-15, 1e-15), "{jm:?}");
                // The sweeps' force and motion kernels against the 6x6 matrices.
                let xf = x.to_dual_action_matrix();
                let expected: [f64; 6] =
                    core::array::from_fn(|r| (0..6).map(|c| xf[r][c] * f.to_array()[c]).sum());
                assert!(
                    x.act_force(&f)
                        .abs_diff_eq(&Force::from_array(expected), 1e-14)
                );
                assert!(x.act_motion(&x.act_inv_motion(&m)).abs_diff_eq(&m, 1e-14));
                let a = jm.inertia_to_parent(&y, jr, &rot, &x2);
                let b = OriginInertia::from_inertia(&inertia.transformed(&x));
                assert!((a.m - b.m).abs() < 1e-15 && (a.h - b.h).length() < 1e-14);
                assert!(a.i.to_mat3().abs_diff_eq(b.i.to_mat3(), 1e-14), "{jm:?}");
            }
        }
    }
}
