//! Joints: kinds, limits, dynamics parameters and mimic couplings.

use glam::DVec3;
use kinetree_spatial::Se3;

/// The kind of a joint, which fixes its configuration and velocity dimensions.
///
/// | kind | nq | nv | q | v |
/// |---|---|---|---|---|
/// | `Fixed` | 0 | 0 | | |
/// | `Revolute` | 1 | 1 | angle about `axis` (rad) | angular rate |
/// | `Continuous` | 1 | 1 | angle about `axis` (rad), unbounded | angular rate |
/// | `Prismatic` | 1 | 1 | displacement along `axis` (m) | linear rate |
/// | `Cylindrical` | 2 | 2 | [displacement along, angle about `axis`] | rates |
/// | `Spherical` | 4 | 3 | unit quaternion [x, y, z, w] | angular velocity in the child frame |
/// | `Planar` | 3 | 3 | [x, y, θ] in the plane normal to `axis` | rates in the child frame |
/// | `Floating` | 7 | 6 | [x, y, z, qx, qy, qz, qw] | [linear; angular] in the child frame |
///
/// For `Planar`, the in-plane directions are the joint frame's x and y axes when `axis` is z;
/// otherwise see [`plane_basis`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// No relative motion.
    Fixed,
    /// Rotation about an axis, within limits.
    Revolute,
    /// Rotation about an axis, unbounded.
    Continuous,
    /// Translation along an axis.
    Prismatic,
    /// Translation along and rotation about the same axis.
    Cylindrical,
    /// Free rotation (ball joint).
    Spherical,
    /// Motion in a plane: two translations and the rotation about the plane normal.
    Planar,
    /// Free motion (6 degrees of freedom).
    Floating,
}

impl JointKind {
    /// Every joint kind.
    pub const ALL: [JointKind; 8] = [
        Self::Fixed,
        Self::Revolute,
        Self::Continuous,
        Self::Prismatic,
        Self::Cylindrical,
        Self::Spherical,
        Self::Planar,
        Self::Floating,
    ];

    /// Size of the configuration block.
    #[inline]
    #[must_use]
    pub const fn nq(self) -> usize {
        match self {
            Self::Fixed => 0,
            Self::Revolute | Self::Continuous | Self::Prismatic => 1,
            Self::Cylindrical => 2,
            Self::Spherical => 4,
            Self::Planar => 3,
            Self::Floating => 7,
        }
    }

    /// Size of the velocity block (degrees of freedom).
    #[inline]
    #[must_use]
    pub const fn nv(self) -> usize {
        match self {
            Self::Fixed => 0,
            Self::Revolute | Self::Continuous | Self::Prismatic => 1,
            Self::Cylindrical => 2,
            Self::Spherical | Self::Planar => 3,
            Self::Floating => 6,
        }
    }

    /// Whether the joint has degrees of freedom.
    #[inline]
    #[must_use]
    pub const fn is_moving(self) -> bool {
        !matches!(self, Self::Fixed)
    }

    /// Whether the joint uses its `axis`.
    #[inline]
    #[must_use]
    pub const fn has_axis(self) -> bool {
        matches!(
            self,
            Self::Revolute | Self::Continuous | Self::Prismatic | Self::Cylindrical | Self::Planar
        )
    }

    /// Whether the joint's `lower`/`upper` position limits apply (revolute, prismatic, cylindrical).
    #[inline]
    #[must_use]
    pub const fn has_position_limits(self) -> bool {
        matches!(self, Self::Revolute | Self::Prismatic | Self::Cylindrical)
    }

    /// The lowercase name used in URDF and JSON (`"revolute"`, `"floating"`, …).
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Fixed => "fixed",
            Self::Revolute => "revolute",
            Self::Continuous => "continuous",
            Self::Prismatic => "prismatic",
            Self::Cylindrical => "cylindrical",
            Self::Spherical => "spherical",
            Self::Planar => "planar",
            Self::Floating => "floating",
        }
    }

    /// Parses a lowercase name (`"revolute"`, …).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.as_str() == name)
    }
}

impl core::fmt::Display for JointKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Position, velocity and effort limits of a joint.
///
/// Absent bounds are infinite (`lower = -∞`, `upper = +∞`). For multi-DoF joints the same limits
/// apply to every coordinate that has a position limit (cylindrical: both).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointLimits {
    /// Lower position bound (rad or m).
    pub lower: f64,
    /// Upper position bound (rad or m).
    pub upper: f64,
    /// Maximum speed magnitude (rad/s or m/s); infinite when unknown.
    pub velocity: f64,
    /// Maximum effort magnitude (N·m or N); infinite when unknown.
    pub effort: f64,
}

impl Default for JointLimits {
    fn default() -> Self {
        Self::UNLIMITED
    }
}

impl JointLimits {
    /// No limits at all.
    pub const UNLIMITED: Self = Self {
        lower: f64::NEG_INFINITY,
        upper: f64::INFINITY,
        velocity: f64::INFINITY,
        effort: f64::INFINITY,
    };

    /// Position limits only.
    #[must_use]
    pub const fn position(lower: f64, upper: f64) -> Self {
        Self {
            lower,
            upper,
            velocity: f64::INFINITY,
            effort: f64::INFINITY,
        }
    }

    /// Whether both position bounds are finite and `lower < upper`.
    #[must_use]
    pub fn has_finite_range(&self) -> bool {
        self.lower.is_finite() && self.upper.is_finite() && self.lower < self.upper
    }
}

/// Viscous damping, dry friction and rotor inertia of a joint (URDF `<dynamics>`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointDynamics {
    /// Viscous damping coefficient (N·m·s/rad or N·s/m).
    pub damping: f64,
    /// Coulomb friction (N·m or N).
    pub friction: f64,
    /// Rotor inertia reflected to the joint (kg·m² or kg), added to the mass matrix diagonal.
    pub armature: f64,
}

/// A URDF `<mimic>` coupling: `q = multiplier · q_leader + offset`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Mimic {
    /// Name of the leading joint.
    pub joint: String,
    /// Multiplier (default 1).
    pub multiplier: f64,
    /// Offset (default 0).
    pub offset: f64,
}

/// A joint connecting a parent link (or the world) to a child link.
///
/// The joint frame is the child link's frame: `placement` is `parent_link_from_joint` at zero
/// configuration, and the child link moves with the joint's motion about `axis`, which is
/// expressed in the joint frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Unique name.
    pub name: String,
    /// Kind.
    pub kind: JointKind,
    /// Index of the parent link, or `None` for a joint attached to the world (the root joint).
    pub parent_link: Option<usize>,
    /// Index of the child link.
    pub child_link: usize,
    /// Pose of the joint frame in the parent link's frame at zero configuration.
    pub placement: Se3,
    /// Unit axis in the joint frame (kinds without an axis keep the URDF default, x).
    pub axis: DVec3,
    /// Limits.
    pub limits: JointLimits,
    /// Damping, friction, armature.
    pub dynamics: JointDynamics,
    /// URDF mimic coupling (leader joint by name).
    pub mimic: Option<Mimic>,
    /// The named frame of the parent link the joint was attached to, when it was given one
    /// (yapCAD's `parent_frame`). `placement` already includes that frame's pose; the name is
    /// kept so that exports can write the attachment as it was declared.
    pub parent_frame: Option<String>,
}

/// An orthonormal basis `(u, w, n)` of a plane with unit normal `n`: the in-plane directions of a
/// planar joint. For `n = z` it is `(x, y, z)`; in general `u` is the unit vector closest to the
/// joint frame's x axis (or y when `n` is along x) in the plane, and `w = n × u`.
#[must_use]
pub fn plane_basis(n: DVec3) -> (DVec3, DVec3, DVec3) {
    let seed = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = (seed - n * n.dot(seed)).normalize();
    (u, n.cross(u), n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dimensions_follow_the_table() {
        let dims: Vec<(usize, usize)> = JointKind::ALL.iter().map(|k| (k.nq(), k.nv())).collect();
        assert_eq!(
            dims,
            [
                (0, 0),
                (1, 1),
                (1, 1),
                (1, 1),
                (2, 2),
                (4, 3),
                (3, 3),
                (7, 6)
            ]
        );
        for k in JointKind::ALL {
            assert_eq!(JointKind::from_name(k.as_str()), Some(k));
        }
    }

    #[test]
    fn plane_basis_is_right_handed() {
        let (u, w, n) = plane_basis(DVec3::Z);
        assert_eq!((u, w, n), (DVec3::X, DVec3::Y, DVec3::Z));
        let n = DVec3::new(1.0, 0.2, -0.3).normalize();
        let (u, w, n2) = plane_basis(n);
        assert!(u.dot(n).abs() < 1e-15 && w.dot(n).abs() < 1e-15);
        assert!((u.cross(w) - n2).length() < 1e-15);
    }
}
