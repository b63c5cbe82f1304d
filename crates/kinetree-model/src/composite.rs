//! Composite joints (trip_kinematics' `Transformation`): one joint made of a fixed-order product
//! of elementary factors — translations along and rotations about the joint frame's x, y, z
//! axes, and ball rotations — each either a constant or a state variable.
//!
//! [`ModelBuilder::add_composite`] places it between two links. Inside the model it is a chain
//! of elementary joints (one per state variable, named `NAME.tx` … `NAME.rz`, `NAME.ball`)
//! through massless links named `NAME#1`, `NAME#2`, …, with the constant factors folded into
//! their placements; so forward kinematics, Jacobians, dynamics, inverse kinematics and the
//! configuration-space operations all handle it, and its `nq` is the number of its state
//! variables (4 for a ball factor's quaternion).
//!
//! trip_kinematics' `Transformation(name, values, state_variables)` is, in its order
//! (translation, then the intrinsic x-y-z rotations), the factors `tx ty tz rx ry rz` with
//! `values` as constants and `state_variables` as variables; a quaternion state is a
//! [`Factor::Ball`].
//!
//! # Examples
//! ```
//! use kinetree_model::composite::{Axis, CompositeJointSpec, Factor};
//! use kinetree_model::{Link, ModelBuilder};
//! # fn main() -> Result<(), kinetree_model::ModelError> {
//! // trip's Transformation("hip", {"tx": 0.1, "ry": 0, "rz": 0}, state_variables=["ry", "rz"]).
//! let hip = CompositeJointSpec::new("hip", "pelvis", "thigh", [
//!     Factor::Translate(Axis::X, Some(0.1)),
//!     Factor::Rotate(Axis::Y, None),
//!     Factor::Rotate(Axis::Z, None),
//! ]);
//! let mut b = ModelBuilder::new("leg");
//! b.add_link(Link::new("pelvis")).add_link(Link::new("thigh"));
//! b.add_composite(hip);
//! let leg = b.build()?;
//! assert_eq!(leg.nq(), 2);
//! assert!(leg.joint_index("hip.ry").is_some() && leg.joint_index("hip.rz").is_some());
//! # Ok(())
//! # }
//! ```

use crate::builder::{JointSpec, ModelBuilder};
use crate::joint::{JointKind, JointLimits};
use crate::link::Link;
use glam::DVec3;
use kinetree_spatial::Se3;

/// A coordinate axis of the composite joint's frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

impl Axis {
    /// The unit vector.
    #[must_use]
    pub const fn unit(self) -> DVec3 {
        match self {
            Self::X => DVec3::X,
            Self::Y => DVec3::Y,
            Self::Z => DVec3::Z,
        }
    }

    const fn letter(self) -> char {
        match self {
            Self::X => 'x',
            Self::Y => 'y',
            Self::Z => 'z',
        }
    }
}

/// One factor of a composite joint: a constant (`Some(value)`, m or rad) or a state variable
/// (`None`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Factor {
    /// Translation along an axis.
    Translate(Axis, Option<f64>),
    /// Rotation about an axis.
    Rotate(Axis, Option<f64>),
    /// A free rotation whose state is a quaternion `[x, y, z, w]` (trip's quaternion state).
    Ball,
}

/// A composite joint between two links: `placement` (the pose of the joint frame in the parent
/// link's frame), then `factors` in order.
#[derive(Clone, Debug, PartialEq)]
pub struct CompositeJointSpec {
    /// The joint's name; its variables are `NAME.tx` … `NAME.rz` and `NAME.ball`.
    pub name: String,
    /// Parent link.
    pub parent: String,
    /// Child link.
    pub child: String,
    /// The pose of the joint frame in the parent link's frame.
    pub placement: Se3,
    /// The factors, applied left to right (`T = placement · F₁ · F₂ · …`).
    pub factors: Vec<Factor>,
    /// Limits of every translation variable (m) and every rotation variable (rad), in the order
    /// of the variables; unlimited when empty or shorter.
    pub limits: Vec<JointLimits>,
}

impl CompositeJointSpec {
    /// A composite joint from `parent` to `child` at the identity placement, unlimited.
    #[must_use]
    pub fn new(
        name: impl Into<String>,
        parent: impl Into<String>,
        child: impl Into<String>,
        factors: impl Into<Vec<Factor>>,
    ) -> Self {
        Self {
            name: name.into(),
            parent: parent.into(),
            child: child.into(),
            placement: Se3::IDENTITY,
            factors: factors.into(),
            limits: Vec::new(),
        }
    }

    /// Sets the placement.
    #[must_use]
    pub fn with_placement(mut self, placement: Se3) -> Self {
        self.placement = placement;
        self
    }

    /// Sets the limits of the 1-DoF variables, in their order.
    #[must_use]
    pub fn with_limits(mut self, limits: impl Into<Vec<JointLimits>>) -> Self {
        self.limits = limits.into();
        self
    }

    /// The names of its elementary joints, one per state variable, in order (a joint with no
    /// variable is one fixed joint named as the composite).
    #[must_use]
    pub fn variable_names(&self) -> Vec<String> {
        let names: Vec<String> = self
            .factors
            .iter()
            .filter_map(|f| match f {
                Factor::Translate(a, None) => Some(format!("{}.t{}", self.name, a.letter())),
                Factor::Rotate(a, None) => Some(format!("{}.r{}", self.name, a.letter())),
                Factor::Ball => Some(format!("{}.ball", self.name)),
                _ => None,
            })
            .collect();
        if names.is_empty() {
            vec![self.name.clone()]
        } else {
            names
        }
    }

    /// The links and joints it stands for (the intermediate links massless).
    fn expand(&self) -> (Vec<Link>, Vec<JointSpec>) {
        let names = self.variable_names();
        let mut links = Vec::new();
        let mut joints = Vec::new();
        let mut pose = self.placement;
        let mut parent = self.parent.clone();
        let mut variable = 0;
        let mut limits = self.limits.iter();
        let count = self
            .factors
            .iter()
            .filter(|f| {
                matches!(
                    f,
                    Factor::Translate(_, None) | Factor::Rotate(_, None) | Factor::Ball
                )
            })
            .count();
        for factor in &self.factors {
            let (kind, axis) = match *factor {
                Factor::Translate(a, Some(x)) => {
                    pose *= Se3::from_translation(a.unit() * x);
                    continue;
                }
                Factor::Rotate(a, Some(x)) => {
                    pose *= Se3::from_axis_angle(a.unit(), x);
                    continue;
                }
                Factor::Translate(a, None) => (JointKind::Prismatic, a.unit()),
                Factor::Rotate(a, None) => (JointKind::Revolute, a.unit()),
                Factor::Ball => (JointKind::Spherical, DVec3::Z),
            };
            let last = variable + 1 == count;
            let child = if last {
                self.child.clone()
            } else {
                format!("{}#{}", self.name, variable + 1)
            };
            let limit = if kind == JointKind::Spherical {
                JointLimits::UNLIMITED
            } else {
                limits.next().copied().unwrap_or(JointLimits::UNLIMITED)
            };
            if !last {
                links.push(Link::new(child.clone()));
            }
            joints.push(
                JointSpec::new(names[variable].clone(), kind, parent, child.clone())
                    .with_placement(pose)
                    .with_axis(axis)
                    .with_limits(limit),
            );
            parent = child;
            pose = Se3::IDENTITY;
            variable += 1;
        }
        if count == 0 {
            joints.push(
                JointSpec::new(
                    self.name.clone(),
                    JointKind::Fixed,
                    parent,
                    self.child.clone(),
                )
                .with_placement(pose),
            );
        } else if pose != Se3::IDENTITY {
            // Constant factors after the last variable: the last variable's joint moves an
            // intermediate link, welded to the child at their product.
            let inner = format!("{}#{}", self.name, count);
            links.push(Link::new(inner.clone()));
            if let Some(j) = joints.last_mut() {
                j.child = inner.clone();
            }
            joints.push(
                JointSpec::new(
                    format!("{}.fixed", self.name),
                    JointKind::Fixed,
                    inner,
                    self.child.clone(),
                )
                .with_placement(pose),
            );
        }
        (links, joints)
    }
}

impl ModelBuilder {
    /// Adds a composite joint ([`CompositeJointSpec`]) between two links added with
    /// [`ModelBuilder::add_link`] (or as parts): its elementary joints and massless intermediate
    /// links (see the [module documentation](crate::composite)). Problems (an unknown link, a
    /// name used twice) are reported by [`ModelBuilder::build`] like any joint's.
    pub fn add_composite(&mut self, joint: CompositeJointSpec) -> &mut Self {
        let (links, joints) = joint.expand();
        for link in links {
            self.add_link(link);
        }
        for j in joints {
            self.add_joint(j);
        }
        self
    }
}
