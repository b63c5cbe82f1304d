//! [`LinearActuator`]: a linear actuator driving a revolute joint, in closed form.

use super::*;
use crate::configuration::wrap_angle;
use crate::error::KinematicsError;
use glam::DVec3;
use kinetree_model::{JointKind, Model};

/// A linear actuator driving a revolute joint: a prismatic length `s` between an anchor on the
/// parent link and an anchor on the child link, solved both ways in closed form by the law of
/// cosines.
///
/// Project both anchors onto the plane through the joint's pivot normal to its axis: at radii `a`
/// (parent anchor) and `c` (child anchor), an angle `ψ = θ + β` apart, where `θ` is the joint angle
/// and `β` the angle between them at `θ = 0`; let `h` be their offset along the axis. Then
///
/// `s² = a² + c² − 2·a·c·cos ψ + h²`, and back, `ψ = ±acos((a² + c² + h² − s²) / (2·a·c))`.
///
/// The sign (the side of the pivot the actuator works on) is the one `ψ` has at the middle of the
/// joint's position limits (at `θ = 0` when they are not finite); a stroke outside
/// [`LinearActuator::length_range`] gives NaN, which a group reports as
/// [`KinematicsError::MappingNonFinite`]. Returned angles are wrapped to (-π, π].
///
/// # Examples
/// ```
/// use kinetree_kinematics::LinearActuator;
/// use kinetree_model::{JointKind, JointSpec, Link, ModelBuilder};
/// use glam::DVec3;
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let mut b = ModelBuilder::new("leg");
/// b.add_link(Link::new("thigh"));
/// b.add_part(Link::new("shank"), JointSpec::new("knee", JointKind::Revolute, "thigh", "shank"));
/// let model = b.build()?;
/// let actuator = LinearActuator::new(&model, "knee", DVec3::new(0.0, -0.4, 0.0), DVec3::new(0.1, 0.0, 0.0))?;
/// // Anchors 0.4 and 0.1 m from the pivot, 90° apart at θ = 0: s² = 0.17 + 0.08 sin θ.
/// assert!((actuator.length(0.0) - 0.17f64.sqrt()).abs() < 1e-15);
/// assert!((actuator.angle(0.21f64.sqrt()) - 30f64.to_radians()).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearActuator {
    /// Distance of the parent anchor from the axis.
    parent_radius: f64,
    /// Distance of the child anchor from the axis.
    child_radius: f64,
    /// Offset between the anchors along the axis.
    axial_offset: f64,
    /// Angle from the parent anchor to the child anchor about the axis at θ = 0 (β).
    phase: f64,
    /// +1 or -1: the sign of sin ψ on the side the actuator works on.
    branch: f64,
}

impl LinearActuator {
    /// The actuator between `parent_anchor` (a point in the parent link's frame) and
    /// `child_anchor` (a point in the child link's frame) across the revolute or continuous joint
    /// named `joint` of `model`.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`]; [`KinematicsError::WrongJointKind`] for other kinds;
    /// [`KinematicsError::InvalidJointValue`] when an anchor lies on the joint axis, a value is
    /// not finite, or the anchors are in line with the pivot (dead centre) at the middle of the
    /// joint's range, where the side the actuator works on is ambiguous.
    pub fn new(
        model: &Model,
        joint: &str,
        parent_anchor: DVec3,
        child_anchor: DVec3,
    ) -> Result<Self, KinematicsError> {
        let j = model
            .joint_index(joint)
            .ok_or_else(|| KinematicsError::UnknownJoint {
                name: joint.to_string(),
            })?;
        let spec = model.joint(j);
        if !matches!(spec.kind, JointKind::Revolute | JointKind::Continuous) {
            return Err(KinematicsError::WrongJointKind {
                joint: joint.to_string(),
                kind: spec.kind,
                expected: "a revolute or continuous joint",
            });
        }
        let bad = |reason: &str| KinematicsError::InvalidJointValue {
            joint: joint.to_string(),
            reason: reason.to_string(),
        };
        if !(parent_anchor.is_finite() && child_anchor.is_finite()) {
            return Err(bad("an actuator anchor is not finite"));
        }
        let axis = spec.axis;
        // Both anchors in the joint frame at θ = 0 (the child frame is the joint frame).
        let p = spec.placement.inverse_transform_point(parent_anchor);
        let c = child_anchor;
        let (p_perp, c_perp) = (p - axis * p.dot(axis), c - axis * c.dot(axis));
        let (parent_radius, child_radius) = (p_perp.length(), c_perp.length());
        let scale = 1e-12 * (1.0 + p.length() + c.length());
        if parent_radius <= scale || child_radius <= scale {
            return Err(bad("an actuator anchor lies on the joint axis"));
        }
        let phase = axis.dot(p_perp.cross(c_perp)).atan2(p_perp.dot(c_perp));
        let limits = spec.limits;
        let reference = if spec.kind == JointKind::Revolute && limits.has_finite_range() {
            0.5 * (limits.lower + limits.upper)
        } else {
            0.0
        };
        let side = (reference + phase).sin();
        if side.abs() < 1e-9 {
            return Err(bad(
                "the actuator is at dead centre (anchors in line with the pivot) in the middle of the joint's range",
            ));
        }
        Ok(Self {
            parent_radius,
            child_radius,
            axial_offset: p.dot(axis) - c.dot(axis),
            phase,
            branch: side.signum(),
        })
    }

    /// The actuator length `s` (m) at joint angle `angle` (rad).
    #[must_use]
    pub fn length(&self, angle: f64) -> f64 {
        let (a, c, h) = (self.parent_radius, self.child_radius, self.axial_offset);
        (a * a + c * c - 2.0 * a * c * (angle + self.phase).cos() + h * h).sqrt()
    }

    /// The joint angle (rad, wrapped to (-π, π]) at actuator length `length` (m), on the
    /// actuator's working side; NaN outside [`LinearActuator::length_range`].
    #[must_use]
    pub fn angle(&self, length: f64) -> f64 {
        let (a, c, h) = (self.parent_radius, self.child_radius, self.axial_offset);
        let cos_psi = (a * a + c * c + h * h - length * length) / (2.0 * a * c);
        wrap_angle(self.branch * cos_psi.acos() - self.phase)
    }

    /// The shortest and longest reachable lengths (m): anchors in line with the pivot on the same
    /// side, then on opposite sides.
    #[must_use]
    pub fn length_range(&self) -> (f64, f64) {
        let (a, c, h) = (self.parent_radius, self.child_radius, self.axial_offset);
        ((a - c).hypot(h), (a + c).hypot(h))
    }
}

impl Actuation for LinearActuator {
    fn to_virtual(&self, actuated: &[f64], virtual_q: &mut Vec<f64>) {
        if let Some(&s) = actuated.first() {
            virtual_q.push(self.angle(s));
        }
    }

    fn to_actuated(&self, virtual_q: &[f64], actuated: &mut Vec<f64>) {
        if let Some(&theta) = virtual_q.first() {
            actuated.push(self.length(theta));
        }
    }
}
