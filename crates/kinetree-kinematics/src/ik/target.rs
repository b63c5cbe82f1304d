//! [`IkTarget`]: where a link or frame should be, and which of its six pose components matter.

use crate::data::FrameId;
use glam::{DMat3, DVec3};
use kinetree_model::spatial::Se3;

/// One goal of an inverse-kinematics solve: the desired world pose of a link or named frame, with
/// a weight per pose component.
///
/// `weights` are `[x, y, z; rx, ry, rz]`: the position components, then the rotation components,
/// all along the axes of the **target** pose. The solver minimises
/// `Σ (weight · error component)²` over every target; a zero weight frees that component
/// entirely (it is neither minimised nor checked for convergence). So:
/// - [`IkTarget::new`]: full pose, every weight 1;
/// - [`IkTarget::position`]: position only (rotation weights 0; the target axes are the world
///   axes);
/// - [`IkTarget::orientation`]: orientation only;
/// - [`IkTarget::with_axis_weights`]: anything between, e.g. `[1, 1, 1, 1, 1, 0]` leaves the tool
///   free to spin about the target's z axis.
///
/// Position errors are in metres and rotation errors in radians, so a weight of 1 on both treats
/// 1 mm like 1 mrad.
///
/// # Examples
/// ```
/// use kinetree_kinematics::ik::IkTarget;
/// use kinetree_kinematics::FrameId;
/// use kinetree_kinematics::spatial::Se3;
/// use glam::DVec3;
/// let tool = FrameId::Link(3);
/// let grasp = IkTarget::new(tool, Se3::from_xyz_rpy([0.4, 0.0, 0.3], [3.14159, 0.0, 0.0]));
/// let point = IkTarget::position(tool, DVec3::new(0.4, 0.0, 0.3)).with_weight(2.0);
/// assert_eq!(point.weights, [2.0, 2.0, 2.0, 0.0, 0.0, 0.0]);
/// # let _ = grasp;
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkTarget {
    /// The link or frame to place.
    pub frame: FrameId,
    /// Its desired world pose (`world_from_frame`). The rotation must be a rotation matrix (to
    /// 1e-6); it is re-orthonormalised before use.
    pub pose: Se3,
    /// Weights of the position components then the rotation components, along the target's axes
    /// (finite, not negative; at least one non-zero).
    pub weights: [f64; 6],
}

impl IkTarget {
    /// Full pose target: position and orientation, every weight 1.
    #[must_use]
    pub fn new(frame: FrameId, pose: Se3) -> Self {
        Self {
            frame,
            pose,
            weights: [1.0; 6],
        }
    }

    /// Position-only target (the frame's orientation is free).
    #[must_use]
    pub fn position(frame: FrameId, position: DVec3) -> Self {
        Self {
            frame,
            pose: Se3::from_translation(position),
            weights: [1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
        }
    }

    /// Orientation-only target (the frame's position is free). `rotation` is `world_R_frame`.
    #[must_use]
    pub fn orientation(frame: FrameId, rotation: DMat3) -> Self {
        Self {
            frame,
            pose: Se3::from_rotation(rotation),
            weights: [0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        }
    }

    /// Multiplies every weight by `weight` (the importance of this target among several).
    #[must_use]
    pub fn with_weight(mut self, weight: f64) -> Self {
        for w in &mut self.weights {
            *w *= weight;
        }
        self
    }

    /// Replaces the per-component weights `[x, y, z; rx, ry, rz]` (target axes).
    #[must_use]
    pub fn with_axis_weights(mut self, weights: [f64; 6]) -> Self {
        self.weights = weights;
        self
    }
}
