//! [`JointSpec`] and [`FrameSpec`]: a joint and a frame as the builder receives them, with links
//! referred to by name.

use crate::joint::{JointDynamics, JointKind, JointLimits, Mimic};
use glam::DVec3;
use kinetree_spatial::Se3;

/// A joint as the builder receives it: links referred to by name.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpec {
    /// Unique name.
    pub name: String,
    /// Kind.
    pub kind: JointKind,
    /// Parent link name.
    pub parent: String,
    /// Child link name.
    pub child: String,
    /// Optional named frame on the parent link that `placement` is relative to (yapCAD's
    /// "parent frame the part attaches to"). `None` means the parent link's own frame.
    pub parent_frame: Option<String>,
    /// Pose of the joint frame relative to the parent link (or `parent_frame`) at zero configuration.
    pub placement: Se3,
    /// Axis in the joint frame (normalized by the builder; must be nonzero for kinds with an axis).
    pub axis: DVec3,
    /// Limits.
    pub limits: JointLimits,
    /// Damping, friction, armature.
    pub dynamics: JointDynamics,
    /// Mimic coupling.
    pub mimic: Option<Mimic>,
}

impl JointSpec {
    /// A joint of `kind` from `parent` to `child` at the identity, axis z, no limits.
    #[must_use]
    pub fn new(
        name: impl Into<String>,
        kind: JointKind,
        parent: impl Into<String>,
        child: impl Into<String>,
    ) -> Self {
        Self {
            name: name.into(),
            kind,
            parent: parent.into(),
            child: child.into(),
            parent_frame: None,
            placement: Se3::IDENTITY,
            axis: DVec3::Z,
            limits: JointLimits::UNLIMITED,
            dynamics: JointDynamics::default(),
            mimic: None,
        }
    }

    /// Sets the placement (pose of the joint frame in the parent frame at zero configuration).
    #[must_use]
    pub fn with_placement(mut self, placement: Se3) -> Self {
        self.placement = placement;
        self
    }

    /// Sets the axis.
    #[must_use]
    pub fn with_axis(mut self, axis: DVec3) -> Self {
        self.axis = axis;
        self
    }

    /// Sets the limits.
    #[must_use]
    pub fn with_limits(mut self, limits: JointLimits) -> Self {
        self.limits = limits;
        self
    }

    /// Sets damping, friction and armature.
    #[must_use]
    pub fn with_dynamics(mut self, dynamics: JointDynamics) -> Self {
        self.dynamics = dynamics;
        self
    }

    /// Makes the joint follow `leader`: `q = multiplier · q_leader + offset`.
    #[must_use]
    pub fn with_mimic(mut self, leader: impl Into<String>, multiplier: f64, offset: f64) -> Self {
        self.mimic = Some(Mimic {
            joint: leader.into(),
            multiplier,
            offset,
        });
        self
    }

    /// Attaches the joint to a named frame of the parent link instead of the link's own frame.
    #[must_use]
    pub fn at_frame(mut self, frame: impl Into<String>) -> Self {
        self.parent_frame = Some(frame.into());
        self
    }
}

/// A named frame as the builder receives it: its link referred to by name.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSpec {
    /// Unique name.
    pub name: String,
    /// Link name.
    pub link: String,
    /// Pose in the link frame.
    pub placement: Se3,
    /// Free-text description.
    pub description: Option<String>,
    /// `(file, datum)` when the placement was read from an external datum file.
    pub datum: Option<(String, String)>,
}

impl FrameSpec {
    /// A frame on `link` at `placement`.
    #[must_use]
    pub fn new(name: impl Into<String>, link: impl Into<String>, placement: Se3) -> Self {
        Self {
            name: name.into(),
            link: link.into(),
            placement,
            description: None,
            datum: None,
        }
    }

    /// Sets the description.
    #[must_use]
    pub fn with_description(mut self, description: impl Into<String>) -> Self {
        self.description = Some(description.into());
        self
    }
}
