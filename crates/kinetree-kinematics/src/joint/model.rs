//! [`JointModel`]: the joint kinds specialised by axis, their sizes and motion subspaces.
//!
//! Every joint kind's motion subspace `S` is constant in the child (body) frame, so the joint's
//! velocity is `S · q̇` and its bias acceleration `Ṡ · q̇` is zero. This holds because the
//! spherical, planar and floating joints take their velocities in the child frame (see
//! [`JointKind`]).

use super::transform::along;
use glam::{DQuat, DVec3};
use kinetree_model::spatial::axis::unit_cross;
use kinetree_model::spatial::real::{Matrix3, Real, Vector3};
use kinetree_model::spatial::{Force, Motion, OriginInertia, Se3};
use kinetree_model::{Body, JointKind, plane_basis};

/// A joint specialised for fast evaluation: axis-aligned revolute and prismatic joints skip the
/// general axis algebra.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointModel {
    /// No degree of freedom (the world body).
    Fixed,
    /// Revolute (or continuous) about the joint frame's x axis.
    RevoluteX,
    /// Revolute (or continuous) about y.
    RevoluteY,
    /// Revolute (or continuous) about z.
    RevoluteZ,
    /// Revolute (or continuous) about a unit axis.
    Revolute(DVec3),
    /// Prismatic along x.
    PrismaticX,
    /// Prismatic along y.
    PrismaticY,
    /// Prismatic along z.
    PrismaticZ,
    /// Prismatic along a unit axis.
    Prismatic(DVec3),
    /// Translation along and rotation about a unit axis: q = [d, θ].
    Cylindrical(DVec3),
    /// Ball joint: q = quaternion [x, y, z, w], v = angular velocity in the child frame.
    Spherical,
    /// Planar joint with in-plane basis `(u, w)` and normal `n`: q = [x, y, θ],
    /// v = [vx, vy, ω] in the child frame (along u, w and about n).
    Planar {
        /// First in-plane direction.
        u: DVec3,
        /// Second in-plane direction.
        w: DVec3,
        /// Plane normal (rotation axis).
        n: DVec3,
    },
    /// Free joint: q = [x, y, z, qx, qy, qz, qw], v = [linear; angular] in the child frame.
    Floating,
}

fn classify(
    axis: DVec3,
    x: JointModel,
    y: JointModel,
    z: JointModel,
    general: JointModel,
) -> JointModel {
    if axis == DVec3::X {
        x
    } else if axis == DVec3::Y {
        y
    } else if axis == DVec3::Z {
        z
    } else {
        general
    }
}

impl JointModel {
    /// The specialised model of a body's joint.
    #[must_use]
    pub fn from_body(body: &Body) -> Self {
        let a = body.axis;
        match body.kind {
            JointKind::Fixed => Self::Fixed,
            JointKind::Revolute | JointKind::Continuous => classify(
                a,
                Self::RevoluteX,
                Self::RevoluteY,
                Self::RevoluteZ,
                Self::Revolute(a),
            ),
            JointKind::Prismatic => classify(
                a,
                Self::PrismaticX,
                Self::PrismaticY,
                Self::PrismaticZ,
                Self::Prismatic(a),
            ),
            JointKind::Cylindrical => Self::Cylindrical(a),
            JointKind::Spherical => Self::Spherical,
            JointKind::Planar => {
                let (u, w, n) = plane_basis(a);
                Self::Planar { u, w, n }
            }
            JointKind::Floating => Self::Floating,
        }
    }

    /// Number of configuration coordinates (4 for a ball joint's quaternion, 7 for a free joint).
    #[inline]
    #[must_use]
    pub fn nq(&self) -> usize {
        match self {
            Self::Spherical => 4,
            Self::Floating => 7,
            _ => self.nv(),
        }
    }

    /// The coordinate axis of a joint that is revolute about (`true`) or prismatic along
    /// (`false`) the x, y or z axis (0, 1, 2): the kinds whose sweeps skip the zero entries of the
    /// motion subspace. `None` for every other kind.
    #[inline(always)]
    #[must_use]
    pub fn axis_index(&self) -> Option<(usize, bool)> {
        match self {
            Self::RevoluteX => Some((0, true)),
            Self::RevoluteY => Some((1, true)),
            Self::RevoluteZ => Some((2, true)),
            Self::PrismaticX => Some((0, false)),
            Self::PrismaticY => Some((1, false)),
            Self::PrismaticZ => Some((2, false)),
            _ => None,
        }
    }

    /// `Sᵀ·f` of a joint with one degree of freedom about or along a coordinate axis (see
    /// [`JointModel::axis_index`]); `None` for other kinds (use [`JointModel::project_force`]).
    #[inline(always)]
    #[must_use]
    pub fn project_axis<T: Real>(&self, f: &Force<T>) -> Option<T> {
        match self {
            Self::RevoluteX => Some(f.angular.get(0)),
            Self::RevoluteY => Some(f.angular.get(1)),
            Self::RevoluteZ => Some(f.angular.get(2)),
            Self::PrismaticX => Some(f.linear.get(0)),
            Self::PrismaticY => Some(f.linear.get(1)),
            Self::PrismaticZ => Some(f.linear.get(2)),
            _ => None,
        }
    }

    /// The momentum `I·S` of an inertia `y` (about the child frame's origin) moving with the
    /// joint's single subspace column, for the joints of [`JointModel::axis_index`]; `None` for
    /// other kinds (use [`JointModel::subspace_column`]).
    #[inline(always)]
    #[must_use]
    pub fn axis_momentum<T: Real>(&self, y: &OriginInertia<T>) -> Option<Force<T>> {
        Some(match self {
            Self::RevoluteX => axis_momentum::<T, 0, true>(y),
            Self::RevoluteY => axis_momentum::<T, 1, true>(y),
            Self::RevoluteZ => axis_momentum::<T, 2, true>(y),
            Self::PrismaticX => axis_momentum::<T, 0, false>(y),
            Self::PrismaticY => axis_momentum::<T, 1, false>(y),
            Self::PrismaticZ => axis_momentum::<T, 2, false>(y),
            _ => return None,
        })
    }

    /// `x · S` for the joints of [`JointModel::axis_index`]: their one subspace column moved by
    /// `x` (a joint Jacobian column when `x` is `world_from_body`). The axis is a column of `x`'s
    /// rotation, so there is no matrix product. `None` for other kinds (use
    /// [`Se3::act_motion`](kinetree_model::spatial::Se3::act_motion) on
    /// [`JointModel::subspace_column`]).
    #[inline(always)]
    #[must_use]
    pub fn act_axis(&self, x: &Se3) -> Option<Motion> {
        let (k, rev) = self.axis_index()?;
        Some(axis_column(x, k, rev))
    }

    /// `x · S_k`: subspace column `k` moved by `x` (a joint Jacobian column when `x` is
    /// `world_from_body`), for one state or a block of states in lanes. For the joints about or
    /// along a coordinate axis it is a column of `x`'s rotation (no matrix product).
    #[inline(always)]
    #[must_use]
    pub fn act_column<T: Real>(&self, x: &Se3<T>, k: usize) -> Motion<T> {
        match self.axis_index() {
            Some((a, rev)) => axis_column(x, a, rev),
            None => x.act_motion(&Motion::from_const(&self.subspace_column(k))),
        }
    }

    /// Number of velocity coordinates.
    #[inline]
    #[must_use]
    pub fn nv(&self) -> usize {
        match self {
            Self::Fixed => 0,
            Self::Cylindrical(_) => 2,
            Self::Spherical | Self::Planar { .. } => 3,
            Self::Floating => 6,
            _ => 1,
        }
    }

    /// The joint velocity `S · v` of `body` for the full velocity vector `v` (a coupled mimic body
    /// moves at `multiplier · v_leader`).
    #[inline]
    #[must_use]
    pub fn body_motion(&self, body: &Body, v: &[f64]) -> Motion {
        match &body.mimic {
            None => self.motion(&v[body.idx_v..body.idx_v + body.nv]),
            Some(m) => self.motion(&[m.multiplier * v[body.idx_v]]),
        }
    }

    /// Column `k` of the motion subspace `S` (a twist in the child frame).
    #[inline]
    #[must_use]
    pub fn subspace_column(&self, k: usize) -> Motion {
        let lin = |v| Motion::new(v, DVec3::ZERO);
        let ang = |v| Motion::new(DVec3::ZERO, v);
        match *self {
            Self::Fixed => Motion::ZERO,
            Self::RevoluteX => ang(DVec3::X),
            Self::RevoluteY => ang(DVec3::Y),
            Self::RevoluteZ => ang(DVec3::Z),
            Self::Revolute(a) => ang(a),
            Self::PrismaticX => lin(DVec3::X),
            Self::PrismaticY => lin(DVec3::Y),
            Self::PrismaticZ => lin(DVec3::Z),
            Self::Prismatic(a) => lin(a),
            Self::Cylindrical(a) => {
                if k == 0 {
                    lin(a)
                } else {
                    ang(a)
                }
            }
            Self::Spherical => ang(unit(k)),
            Self::Planar { u, w, n } => match k {
                0 => lin(u),
                1 => lin(w),
                _ => ang(n),
            },
            Self::Floating => {
                if k < 3 {
                    lin(unit(k))
                } else {
                    ang(unit(k - 3))
                }
            }
        }
    }

    /// The joint velocity `S · v` (a twist in the child frame) for velocity block `v`, for one
    /// state (`f64`) or a block of states in lanes.
    #[inline(always)]
    #[must_use]
    pub fn motion<T: Real>(&self, v: &[T]) -> Motion<T> {
        let (o, zero) = (T::ZERO, T::V3::ZERO);
        let (linear, angular) = match *self {
            Self::Fixed => (zero, zero),
            Self::RevoluteX => (zero, T::V3::new(v[0], o, o)),
            Self::RevoluteY => (zero, T::V3::new(o, v[0], o)),
            Self::RevoluteZ => (zero, T::V3::new(o, o, v[0])),
            Self::Revolute(a) => (zero, along(a, v[0])),
            Self::PrismaticX => (T::V3::new(v[0], o, o), zero),
            Self::PrismaticY => (T::V3::new(o, v[0], o), zero),
            Self::PrismaticZ => (T::V3::new(o, o, v[0]), zero),
            Self::Prismatic(a) => (along(a, v[0]), zero),
            Self::Cylindrical(a) => (along(a, v[0]), along(a, v[1])),
            Self::Spherical => (zero, T::V3::new(v[0], v[1], v[2])),
            Self::Planar { u, w, n } => (along(u, v[0]) + along(w, v[1]), along(n, v[2])),
            Self::Floating => (T::V3::new(v[0], v[1], v[2]), T::V3::new(v[3], v[4], v[5])),
        };
        Motion { linear, angular }
    }

    /// Writes `Sᵀ · f` (the generalized force of a wrench in the child frame) into `out`
    /// (length `nv()`), for one state (`f64`) or a block of states in lanes.
    #[inline(always)]
    pub fn project_force<T: Real>(&self, f: &Force<T>, out: &mut [T]) {
        let (lin, ang) = (&f.linear, &f.angular);
        match *self {
            Self::Fixed => {}
            Self::RevoluteX => out[0] = ang.get(0),
            Self::RevoluteY => out[0] = ang.get(1),
            Self::RevoluteZ => out[0] = ang.get(2),
            Self::Revolute(a) => out[0] = dot_const(a, ang),
            Self::PrismaticX => out[0] = lin.get(0),
            Self::PrismaticY => out[0] = lin.get(1),
            Self::PrismaticZ => out[0] = lin.get(2),
            Self::Prismatic(a) => out[0] = dot_const(a, lin),
            Self::Cylindrical(a) => {
                out[0] = dot_const(a, lin);
                out[1] = dot_const(a, ang);
            }
            Self::Spherical => {
                for k in 0..3 {
                    out[k] = ang.get(k);
                }
            }
            Self::Planar { u, w, n } => {
                out[0] = dot_const(u, lin);
                out[1] = dot_const(w, lin);
                out[2] = dot_const(n, ang);
            }
            Self::Floating => {
                for k in 0..3 {
                    out[k] = lin.get(k);
                    out[k + 3] = ang.get(k);
                }
            }
        }
    }
}

/// `a · x` for a constant direction `a`.
#[inline(always)]
fn dot_const<T: Real>(a: DVec3, x: &T::V3) -> T {
    T::V3::from_const(a).dot(x)
}

/// `x · S` for a joint about (`rev`) or along coordinate axis `a`: a column of `x`'s rotation,
/// and for a turn the translation's cross product with it (no matrix product).
#[inline(always)]
pub(crate) fn axis_column<T: Real>(x: &Se3<T>, a: usize, rev: bool) -> Motion<T> {
    let axis = x.rotation.col(a);
    if rev {
        Motion {
            linear: x.translation.cross(&axis),
            angular: axis,
        }
    } else {
        Motion {
            linear: axis,
            angular: T::V3::ZERO,
        }
    }
}

/// `I·S` for an axis-aligned joint's subspace `S = e_K` (angular if `REV`, else linear).
#[inline(always)]
pub(crate) fn axis_momentum<T: Real, const K: usize, const REV: bool>(
    y: &OriginInertia<T>,
) -> Force<T> {
    if REV {
        Force {
            linear: unit_cross::<T, K>(&y.h),
            angular: y.i.column(K),
        }
    } else {
        let mut linear = T::V3::ZERO;
        *linear.get_mut(K) = y.m;
        Force {
            linear,
            angular: -unit_cross::<T, K>(&y.h),
        }
    }
}

#[inline]
fn unit(k: usize) -> DVec3 {
    match k {
        0 => DVec3::X,
        1 => DVec3::Y,
        _ => DVec3::Z,
    }
}

/// The quaternion stored at `q[0..4]` as x, y, z, w, normalized (the entry checks refuse norms
/// further than [`QUATERNION_NORM_TOLERANCE`](crate::QUATERNION_NORM_TOLERANCE) from 1, so this
/// only removes rounding).
#[inline]
pub(crate) fn quat(q: &[f64]) -> DQuat {
    let r = DQuat::from_xyzw(q[0], q[1], q[2], q[3]);
    r / r.length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree_model::spatial::{Inertia, Symmetric3};

    #[test]
    fn axis_kernels_match_the_subspace_columns() {
        let y = OriginInertia::from_inertia(&Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        ));
        let f = Force::from_array([0.3, -1.2, 0.5, 2.0, -0.1, 0.7]);
        for m in [
            JointModel::RevoluteX,
            JointModel::RevoluteY,
            JointModel::RevoluteZ,
            JointModel::PrismaticX,
            JointModel::PrismaticY,
            JointModel::PrismaticZ,
        ] {
            let s = m.subspace_column(0);
            let (k, revolute) = m.axis_index().expect("axis-aligned");
            let unit = if revolute { s.angular } else { s.linear };
            assert_eq!(unit[k], 1.0);
            assert_eq!(m.project_axis(&f), Some(s.dot(&f)));
            let momentum = m.axis_momentum(&y).expect("axis-aligned");
            assert!(momentum.abs_diff_eq(&y.mul_motion(&s), 1e-15), "{m:?}");
        }
        let general = JointModel::Revolute(DVec3::new(0.6, 0.0, 0.8));
        assert_eq!(general.axis_index(), None);
        assert_eq!(general.project_axis(&f), None);
        assert_eq!(general.axis_momentum(&y), None);
    }

    #[test]
    fn subspace_columns_agree_with_motion_and_projection() {
        let models = [
            JointModel::Cylindrical(DVec3::new(0.0, 0.6, 0.8)),
            JointModel::Spherical,
            JointModel::Planar {
                u: DVec3::X,
                w: DVec3::Y,
                n: DVec3::Z,
            },
            JointModel::Floating,
            JointModel::Revolute(DVec3::new(0.6, 0.0, 0.8)),
        ];
        let f = Force::from_array([0.3, -1.2, 0.5, 2.0, -0.1, 0.7]);
        for m in models {
            let nv = m.nv();
            let v: Vec<f64> = (0..nv).map(|k| 0.5 + k as f64).collect();
            let mut sum = Motion::ZERO;
            for (k, vk) in v.iter().enumerate() {
                sum += m.subspace_column(k) * *vk;
            }
            assert!(sum.abs_diff_eq(&m.motion(&v), 1e-15), "{m:?}");
            assert_eq!(
                m.nq(),
                m.nv() + usize::from(m == JointModel::Spherical || m == JointModel::Floating)
            );
            let mut out = vec![0.0; nv];
            m.project_force(&f, &mut out);
            for (k, o) in out.iter().enumerate() {
                assert!((m.subspace_column(k).dot(&f) - o).abs() < 1e-15, "{m:?}");
            }
        }
    }
}
