//! Joint transforms, for one state or a block of states in lanes: `parent_from_child` of a
//! placed joint ([`JointModel::placed_transform`]), the mimic coupling, and the factored form
//! for composite inertias ([`JointModel::placed_transform_factored`]). The fast [`sin_cos`]
//! they use is kinetree-spatial's (re-exported here).

use super::model::JointModel;
use glam::DVec3;
use kinetree_model::Body;
use kinetree_model::spatial::real::{Matrix3, Real, Vector3};
use kinetree_model::spatial::{OriginInertia, RotationForm, Se3};

pub use kinetree_model::spatial::real::sin_cos;

/// The placement rotation `R` times a rotation by `(s, c)` about coordinate axis `k`: columns `i`
/// and `j` of `R·R_k(θ)` are `c·r_i + s·r_j` and `c·r_j - s·r_i`.
#[inline(always)]
pub(crate) fn rotate_about_axis<T: Real>(r: &T::M3, k: usize, s: T, c: T) -> T::M3 {
    let (x, y, z) = (r.col(0), r.col(1), r.col(2));
    match k {
        0 => T::M3::from_cols(x, y.scale(c) + z.scale(s), z.scale(c) - y.scale(s)),
        1 => T::M3::from_cols(x.scale(c) - z.scale(s), y, x.scale(s) + z.scale(c)),
        _ => T::M3::from_cols(x.scale(c) + y.scale(s), y.scale(c) - x.scale(s), z),
    }
}

/// The rotation by `(s, c)` about coordinate axis `k`, built entry by entry (what
/// [`rotate_about_axis`] gives for the identity, without its multiplications).
#[inline(always)]
pub(crate) fn axis_rotation<T: Real>(k: usize, s: T, c: T) -> T::M3 {
    let (o, i) = (T::ZERO, T::splat(1.0));
    let v = T::V3::new;
    match k {
        0 => T::M3::from_cols(v(i, o, o), v(o, c, s), v(o, -s, c)),
        1 => T::M3::from_cols(v(c, o, -s), v(o, i, o), v(s, o, c)),
        _ => T::M3::from_cols(v(c, s, o), v(-s, c, o), v(o, o, i)),
    }
}

/// The joint's own rotation when it is about a coordinate axis (the revolute joints about x, y,
/// z), as [`JointModel::placed_transform_factored`] reports it: small enough to keep per body.
/// Generic over the number type, as the transforms.
#[derive(Debug, PartialEq)]
pub struct JointRot<T: Real = f64> {
    /// 0, 1, 2 for x, y, z, or 3 for no joint rotation about a coordinate axis.
    k: usize,
    s: T,
    c: T,
}

kinetree_model::spatial::copy_by_value!(JointRot);

impl JointRot {
    /// No rotation about a coordinate axis (prismatic joints, or a joint of another kind whose
    /// whole rotation is then the "placement" rotation).
    pub const NONE: Self = Self {
        k: 3,
        s: 0.0,
        c: 1.0,
    };
}

impl<T: Real> JointRot<T> {
    /// [`JointRot::NONE`] in this number type.
    #[inline(always)]
    #[must_use]
    pub fn none() -> Self {
        Self {
            k: 3,
            s: T::ZERO,
            c: T::splat(1.0),
        }
    }

    /// The rotation in the kernels' form ([`RotationForm::Identity`] for [`JointRot::NONE`]).
    #[inline(always)]
    #[must_use]
    pub fn form(self) -> RotationForm<T> {
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
    /// of the configuration, of one state (`f64`) or a block of states in lanes.
    #[inline(always)]
    #[must_use]
    pub fn placed_transform<T: Real>(&self, placement: &Se3, q: &[T]) -> Se3<T> {
        // No closures here or below but the rare kinds' one-state code: a closure is a
        // function of its own that the compiler may leave out of line, and out of line it is
        // built without the caller's SIMD features (which one-state code does not need).
        let r = &placement.rotation;
        match *self {
            Self::RevoluteX => turned(placement, 0, q[0]),
            Self::RevoluteY => turned(placement, 1, q[0]),
            Self::RevoluteZ => turned(placement, 2, q[0]),
            Self::PrismaticX => slid(placement, along(r.x_axis, q[0])),
            Self::PrismaticY => slid(placement, along(r.y_axis, q[0])),
            Self::PrismaticZ => slid(placement, along(r.z_axis, q[0])),
            Self::Prismatic(a) => slid(placement, T::M3::from_const(r).mul_vec(&along(a, q[0]))),
            Self::Fixed => Se3::from_const(placement),
            // Free joints (every legged robot's root) in lanes; for one state, and for the rare
            // kinds in lanes, the one-state code out of line (see `Real::each_lane`): inlined, it
            // made the one-state frame Jacobian up to 1.5x slower.
            Self::Floating if T::LANES > 1 => placed(placement, &self.transform(q)),
            Self::Floating
            | Self::Revolute(_)
            | Self::Cylindrical(_)
            | Self::Spherical
            | Self::Planar { .. } => {
                T::each_lane(q, |q| placed(placement, &self.transform::<f64>(q)))
            }
        }
    }

    /// As [`JointModel::placed_transform`], and the joint's own rotation when it is about a
    /// coordinate axis. With the placement rotation's form ([`RotationForm::classify`]) that
    /// factors the transform as `T(t)·R_placement·R_joint` for
    /// [`JointModel::inertia_to_parent`]; joints of other kinds report [`JointRot::NONE`] and
    /// their whole rotation must be used as the placement rotation.
    #[inline(always)]
    #[must_use]
    pub fn placed_transform_factored<T: Real>(
        &self,
        placement: &Se3,
        q: &[T],
    ) -> (Se3<T>, JointRot<T>) {
        match self.axis_index() {
            Some((k, true)) => {
                let (s, c) = q[0].sin_cos();
                let x = Se3 {
                    rotation: rotate_about_axis(&T::M3::from_const(&placement.rotation), k, s, c),
                    translation: T::V3::from_const(placement.translation),
                };
                (x, JointRot { k, s, c })
            }
            _ => (self.placed_transform(placement, q), JointRot::none()),
        }
    }

    /// An inertia `y` about the child frame's origin, expressed about the parent frame's for
    /// `parent_from_child = x` as factored by [`JointModel::placed_transform_factored`]
    /// (`joint`), with `placement` the form of the placement rotation: the rotations are applied
    /// in their cheap forms. For a joint that is not axis-aligned revolute or prismatic, or a
    /// general placement rotation, the rotation of `x` is used whole.
    #[inline(always)]
    #[must_use]
    pub fn inertia_to_parent<T: Real>(
        &self,
        y: &OriginInertia<T>,
        joint: JointRot<T>,
        placement: &RotationForm,
        x: &Se3<T>,
    ) -> OriginInertia<T> {
        // A general placement rotation costs as much as the whole rotation of `x`: one product.
        let rotated =
            if self.axis_index().is_some() && !matches!(placement, RotationForm::General(_)) {
                y.rotated(&joint.form())
                    .rotated(&RotationForm::from_const(placement))
            } else {
                y.rotated(&RotationForm::General(x.rotation))
            };
        rotated.translated(&x.translation)
    }

    /// `parent_from_body` of `body` (whose joint model this is) for the full configuration `q`
    /// (of one state, or a block of states in lanes). A coupled mimic body uses
    /// `multiplier · q_leader + offset`.
    #[inline(always)]
    #[must_use]
    pub fn body_transform<T: Real>(&self, body: &Body, q: &[T]) -> Se3<T> {
        // One inlined copy of the placement kernel for both cases.
        let coupled;
        let block = if body.mimic.is_none() {
            &q[body.idx_q..body.idx_q + body.nq]
        } else {
            coupled = [mimic_value(body, q[body.idx_q])];
            &coupled[..]
        };
        self.placed_transform(&body.placement, block)
    }

    /// The joint motion `joint_from_child` for configuration block `q` (of one state, or a
    /// block of states in lanes).
    #[inline(always)]
    #[must_use]
    pub fn transform<T: Real>(&self, q: &[T]) -> Se3<T> {
        let origin = T::V3::ZERO;
        match *self {
            Self::Fixed => Se3::identity(),
            Self::RevoluteX => turned(&Se3::IDENTITY, 0, q[0]),
            Self::RevoluteY => turned(&Se3::IDENTITY, 1, q[0]),
            Self::RevoluteZ => turned(&Se3::IDENTITY, 2, q[0]),
            Self::Revolute(a) => Se3 {
                rotation: axis_angle_rotation(a, q[0]),
                translation: origin,
            },
            Self::PrismaticX => slid(&Se3::IDENTITY, along(DVec3::X, q[0])),
            Self::PrismaticY => slid(&Se3::IDENTITY, along(DVec3::Y, q[0])),
            Self::PrismaticZ => slid(&Se3::IDENTITY, along(DVec3::Z, q[0])),
            Self::Prismatic(a) => slid(&Se3::IDENTITY, along(a, q[0])),
            Self::Cylindrical(a) => Se3 {
                rotation: axis_angle_rotation(a, q[1]),
                translation: along(a, q[0]),
            },
            Self::Spherical => Se3 {
                rotation: quaternion_rotation(q[0], q[1], q[2], q[3]),
                translation: origin,
            },
            Self::Planar { u, w, n } => Se3 {
                rotation: axis_angle_rotation(n, q[2]),
                translation: along(u, q[0]) + along(w, q[1]),
            },
            Self::Floating => Se3 {
                rotation: quaternion_rotation(q[3], q[4], q[5], q[6]),
                translation: T::V3::new(q[0], q[1], q[2]),
            },
        }
    }
}

/// `placement` turned by `angle` about its coordinate axis `k`: the placement's rotation times
/// the axis rotation, two columns of three (with the fast [`sin_cos`]).
#[inline(always)]
fn turned<T: Real>(placement: &Se3, k: usize, angle: T) -> Se3<T> {
    let (s, c) = angle.sin_cos();
    Se3 {
        rotation: rotate_about_axis(&T::M3::from_const(&placement.rotation), k, s, c),
        translation: T::V3::from_const(placement.translation),
    }
}

/// `placement · x`.
#[inline(always)]
fn placed<T: Real>(placement: &Se3, x: &Se3<T>) -> Se3<T> {
    // Floating roots and many ball joints sit at the identity: skip the product.
    if *placement == Se3::IDENTITY {
        *x
    } else {
        Se3::from_const(placement).compose(x)
    }
}

/// `placement` slid by `d` (in the parent frame).
#[inline(always)]
fn slid<T: Real>(placement: &Se3, d: T::V3) -> Se3<T> {
    Se3 {
        rotation: T::M3::from_const(&placement.rotation),
        translation: T::V3::from_const(placement.translation) + d,
    }
}

/// The constant direction `a` times `s`.
#[inline(always)]
pub(crate) fn along<T: Real>(a: DVec3, s: T) -> T::V3 {
    T::V3::from_const(a).scale(s)
}

/// A coupled mimic body's joint value `multiplier · q_leader + offset` for the leader's value
/// `x` (`x` itself for other bodies): the one place the mimic coupling enters a placement.
#[inline(always)]
pub(crate) fn mimic_value<T: Real>(body: &Body, x: T) -> T {
    match &body.mimic {
        None => x,
        Some(m) => x * m.multiplier + m.offset,
    }
}

/// The rotation by `angle` about the unit vector `a` (Rodrigues' formula, the entries of
/// [`rotation::rot_axis_angle`](kinetree_model::spatial::rotation::rot_axis_angle) with the
/// fast [`sin_cos`]).
#[inline(always)]
fn axis_angle_rotation<T: Real>(a: DVec3, angle: T) -> T::M3 {
    let (s, c) = angle.sin_cos();
    let t = T::splat(1.0) - c;
    let (x, y, z) = (a.x, a.y, a.z);
    T::M3::from_cols(
        T::V3::new(t * x * x + c, t * x * y + s * z, t * x * z - s * y),
        T::V3::new(t * x * y - s * z, t * y * y + c, t * y * z + s * x),
        T::V3::new(t * x * z + s * y, t * y * z - s * x, t * z * z + c),
    )
}

/// The rotation of the quaternion `(x, y, z, w)` divided by its length (the entry checks refuse
/// norms further than [`QUATERNION_NORM_TOLERANCE`](crate::QUATERNION_NORM_TOLERANCE) from 1,
/// so this only removes rounding), with glam's `DMat3::from_quat` products.
#[inline(always)]
fn quaternion_rotation<T: Real>(x: T, y: T, z: T, w: T) -> T::M3 {
    let length = (x * x + y * y + z * z + w * w).sqrt();
    let (x, y, z, w) = (x / length, y / length, z / length, w / length);
    let (x2, y2, z2) = (x + x, y + y, z + z);
    let (xx, xy, xz) = (x * x2, x * y2, x * z2);
    let (yy, yz, zz) = (y * y2, y * z2, z * z2);
    let (wx, wy, wz) = (w * x2, w * y2, w * z2);
    let one = T::splat(1.0);
    T::M3::from_cols(
        T::V3::new(one - (yy + zz), xy + wz, xz - wy),
        T::V3::new(xy - wz, one - (xx + zz), yz + wx),
        T::V3::new(xz + wy, yz - wx, one - (xx + yy)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree_model::spatial::{Force, Inertia, Motion, Symmetric3};

    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / f64::EPSILON
    }

    /// Every joint kind, with general axes where the kind has one.
    fn every_kind() -> Vec<JointModel> {
        let a = DVec3::new(0.36, -0.48, 0.8);
        let (u, w) = (DVec3::new(0.8, 0.6, 0.0), DVec3::new(-0.6, 0.8, 0.0));
        vec![
            JointModel::Fixed,
            JointModel::RevoluteX,
            JointModel::RevoluteY,
            JointModel::RevoluteZ,
            JointModel::Revolute(a),
            JointModel::PrismaticX,
            JointModel::PrismaticY,
            JointModel::PrismaticZ,
            JointModel::Prismatic(a),
            JointModel::Cylindrical(a),
            JointModel::Spherical,
            JointModel::Planar { u, w, n: DVec3::Z },
            JointModel::Floating,
        ]
    }

    /// The one generic joint algebra gives each lane of a block of states the one-state result,
    /// bit for bit, for every joint kind: placements (with and without a placement product),
    /// motions and projections.
    #[test]
    fn every_joint_kind_gives_the_one_state_bits_in_lanes() {
        use kinetree_model::spatial::lanes::{LForce, Lanes};
        // Four states per kind: angles beyond ±π, tiny and negative values, unit quaternions
        // with rounding left in.
        let states = [
            [0.3, -1.7, 2.9, 0.1, 0.2, 0.3, 0.927_361_849_549_570_3],
            [-3.5, 0.25, -0.0, -0.5, 0.5, -0.5, 0.5],
            [1e-9, 4.0, -2.2, 0.0, 0.0, 0.0, 1.000_000_000_1],
            [12.0, -0.6, 0.7, 0.6, 0.0, 0.8, 0.0],
        ];
        let lanes: Vec<Lanes<4>> = (0..7)
            .map(|k| Lanes([states[0][k], states[1][k], states[2][k], states[3][k]]))
            .collect();
        let forces = [
            Force::from_array([0.3, -1.2, 0.5, 2.0, -0.1, 0.7]),
            Force::from_array([-2.0, 0.4, 1.5, -0.3, 0.9, 0.2]),
            Force::from_array([1.0, 1.0, -1.0, 0.5, 0.5, -0.5]),
            Force::from_array([0.0, -0.7, 0.2, 1.3, -2.1, 0.6]),
        ];
        let mut lane_force = LForce::<4>::zero();
        for (l, f) in forces.iter().enumerate() {
            lane_force.set_lane(l, f);
        }
        for placement in [
            Se3::IDENTITY,
            Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, 0.5, -0.6]),
        ] {
            for jm in every_kind() {
                let (nq, nv) = (jm.nq(), jm.nv());
                let x = jm.placed_transform(&placement, &lanes[..nq]);
                let m = jm.motion(&lanes[..nv]);
                let mut tau = [Lanes::<4>::ZERO; 6];
                jm.project_force(&lane_force, &mut tau[..nv]);
                for (l, q) in states.iter().enumerate() {
                    assert_eq!(
                        x.lane(l),
                        jm.placed_transform(&placement, &q[..nq]),
                        "{jm:?}"
                    );
                    assert_eq!(m.lane(l), jm.motion(&q[..nv]), "{jm:?}");
                    let mut one = [0.0; 6];
                    jm.project_force(&forces[l], &mut one[..nv]);
                    for k in 0..nv {
                        assert_eq!(tau[k].0[l].to_bits(), one[k].to_bits(), "{jm:?}");
                    }
                }
            }
        }
    }

    /// The placed transform is the placement times the joint motion, `Sᵀ·f` is the power of `f`
    /// along each subspace column, and `S·v` is the columns' combination: the generic kernels
    /// against their definitions, for every kind.
    #[test]
    fn every_joint_kind_matches_its_definition() {
        let placement = Se3::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, 0.5, -0.6]);
        let q = [0.3, -1.7, 2.9, 0.1, 0.2, 0.3, 0.927_361_849_549_570_3];
        let v = [0.5, -0.25, 1.5, -2.0, 0.75, 0.1];
        let f = Force::from_array([0.3, -1.2, 0.5, 2.0, -0.1, 0.7]);
        for jm in every_kind() {
            let (nq, nv) = (jm.nq(), jm.nv());
            let placed = jm.placed_transform(&placement, &q[..nq]);
            assert!(
                placed.abs_diff_eq(&(placement * jm.transform(&q[..nq])), 1e-14, 1e-14),
                "{jm:?}"
            );
            let mut tau = [0.0; 6];
            jm.project_force(&f, &mut tau[..nv]);
            let mut combined = Motion::ZERO;
            for k in 0..nv {
                let s = jm.subspace_column(k);
                assert!((tau[k] - s.dot(&f)).abs() < 1e-15, "{jm:?}");
                combined += s * v[k];
            }
            assert!(jm.motion(&v[..nv]).abs_diff_eq(&combined, 1e-15), "{jm:?}");
        }
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
