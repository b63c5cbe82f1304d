//! Per-joint algebra: joint transforms and motion subspaces, specialised by kind and axis.
//!
//! Every joint kind's motion subspace `S` is constant in the child (body) frame, so the joint's
//! velocity is `S · q̇` and its bias acceleration `Ṡ · q̇` is zero. This holds because the
//! spherical, planar and floating joints take their velocities in the child frame (see
//! [`JointKind`]).

use glam::{DMat3, DQuat, DVec3};
use kinetree_model::spatial::{Force, Motion, Se3};
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

    /// `parent_from_child` of `placement * joint_motion(q)`, computed without forming the joint
    /// motion where the axis is aligned. `q` is the joint's block of the configuration.
    #[inline]
    #[must_use]
    pub fn placed_transform(&self, placement: &Se3, q: &[f64]) -> Se3 {
        let r = &placement.rotation;
        match *self {
            Self::RevoluteX => {
                let (s, c) = q[0].sin_cos();
                Se3::new(
                    DMat3::from_cols(
                        r.x_axis,
                        r.y_axis * c + r.z_axis * s,
                        r.z_axis * c - r.y_axis * s,
                    ),
                    placement.translation,
                )
            }
            Self::RevoluteY => {
                let (s, c) = q[0].sin_cos();
                Se3::new(
                    DMat3::from_cols(
                        r.x_axis * c - r.z_axis * s,
                        r.y_axis,
                        r.x_axis * s + r.z_axis * c,
                    ),
                    placement.translation,
                )
            }
            Self::RevoluteZ => {
                let (s, c) = q[0].sin_cos();
                Se3::new(
                    DMat3::from_cols(
                        r.x_axis * c + r.y_axis * s,
                        r.y_axis * c - r.x_axis * s,
                        r.z_axis,
                    ),
                    placement.translation,
                )
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

    /// The joint velocity `S · v` (a twist in the child frame) for velocity block `v`.
    #[inline]
    #[must_use]
    pub fn motion(&self, v: &[f64]) -> Motion {
        match *self {
            Self::Fixed => Motion::ZERO,
            Self::RevoluteX => Motion::new(DVec3::ZERO, DVec3::new(v[0], 0.0, 0.0)),
            Self::RevoluteY => Motion::new(DVec3::ZERO, DVec3::new(0.0, v[0], 0.0)),
            Self::RevoluteZ => Motion::new(DVec3::ZERO, DVec3::new(0.0, 0.0, v[0])),
            Self::Revolute(a) => Motion::new(DVec3::ZERO, a * v[0]),
            Self::PrismaticX => Motion::new(DVec3::new(v[0], 0.0, 0.0), DVec3::ZERO),
            Self::PrismaticY => Motion::new(DVec3::new(0.0, v[0], 0.0), DVec3::ZERO),
            Self::PrismaticZ => Motion::new(DVec3::new(0.0, 0.0, v[0]), DVec3::ZERO),
            Self::Prismatic(a) => Motion::new(a * v[0], DVec3::ZERO),
            Self::Cylindrical(a) => Motion::new(a * v[0], a * v[1]),
            Self::Spherical => Motion::new(DVec3::ZERO, DVec3::new(v[0], v[1], v[2])),
            Self::Planar { u, w, n } => Motion::new(u * v[0] + w * v[1], n * v[2]),
            Self::Floating => Motion::from_slice(v),
        }
    }

    /// Writes `Sᵀ · f` (the generalized force of a wrench in the child frame) into `out`
    /// (length `nv()`).
    #[inline]
    pub fn project_force(&self, f: &Force, out: &mut [f64]) {
        match *self {
            Self::Fixed => {}
            Self::RevoluteX => out[0] = f.angular.x,
            Self::RevoluteY => out[0] = f.angular.y,
            Self::RevoluteZ => out[0] = f.angular.z,
            Self::Revolute(a) => out[0] = a.dot(f.angular),
            Self::PrismaticX => out[0] = f.linear.x,
            Self::PrismaticY => out[0] = f.linear.y,
            Self::PrismaticZ => out[0] = f.linear.z,
            Self::Prismatic(a) => out[0] = a.dot(f.linear),
            Self::Cylindrical(a) => {
                out[0] = a.dot(f.linear);
                out[1] = a.dot(f.angular);
            }
            Self::Spherical => out[..3].copy_from_slice(&f.angular.to_array()),
            Self::Planar { u, w, n } => {
                out[0] = u.dot(f.linear);
                out[1] = w.dot(f.linear);
                out[2] = n.dot(f.angular);
            }
            Self::Floating => f.write_to_slice(out),
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

    #[test]
    fn specialised_transforms_match_general_ones() {
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
            let a = fast.placed_transform(&placement, &q);
            let b = placement * general.transform(&q);
            assert!(a.abs_diff_eq(&b, 1e-15, 1e-15), "{fast:?}");
            assert!(
                fast.motion(&[1.3])
                    .abs_diff_eq(&general.motion(&[1.3]), 0.0)
            );
        }
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
            let mut out = vec![0.0; nv];
            m.project_force(&f, &mut out);
            for (k, o) in out.iter().enumerate() {
                assert!((m.subspace_column(k).dot(&f) - o).abs() < 1e-15, "{m:?}");
            }
        }
    }
}
