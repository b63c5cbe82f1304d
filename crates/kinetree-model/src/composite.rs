//! Composite joints (trip_kinematics' `Transformation`): one joint made of a fixed-order product
//! of elementary factors — translations along and rotations about the joint frame's x, y, z
//! axes, and ball rotations — each either a constant or a state variable.
//!
//! [`ModelBuilder::add_composite`] places it between two links. Users see ONE joint: its name is
//! in [`Model::user_joints`](crate::Model::user_joints) with `nq` = the number of its state
//! variables (4 for a quaternion), it is addressed by that name wherever joints are named
//! (named states, the CLI's `--q name=a:b:c`, `kinetree compute`'s `model.joints`), and a JSON
//! model file writes it as one joint of `"type": "composite"`.
//!
//! Inside, it is expanded as RBDL expands multi-DoF joints: one elementary joint per state
//! variable (named `NAME.tx` … `NAME.rz`, `NAME.quat`) through massless virtual links
//! (`NAME#1`, `NAME#2`, …), with the constant factors folded into their placements. So the
//! kernels (forward kinematics, Jacobians, dynamics and their derivatives) need no joint kind
//! with a configuration-dependent motion subspace. [`Model::joints`](crate::Model::joints) and
//! [`Model::links`](crate::Model::links) list those pieces (as the algorithms index them);
//! [`Model::composite_of_joint`](crate::Model::composite_of_joint) and
//! [`Model::is_virtual_link`](crate::Model::is_virtual_link) tell them apart.
//!
//! In a JSON model file it is `{"name": "hip", "type": "composite", "parent": …, "child": …,
//! "origin": …, "factors": [{"param": "tx", "value": 100}, {"param": "ry", "limits": {…}},
//! {"param": "rz"}, {"param": "quat"}]}`: `param` is `tx`, `ty`, `tz`, `rx`, `ry`, `rz` or
//! `quat`, a factor with a `value` is a constant (a quaternion's is `[x, y, z, w]`), one without
//! is a state variable (see [`crate::json`]). URDF has no such joint: `to_urdf_string` writes the
//! expansion (pieces and virtual links), which reloads as separate joints.
//!
//! trip_kinematics' `Transformation(name, values, state_variables)` is, in its order
//! (translation, then the intrinsic x-y-z rotations, or a quaternion), the factors
//! `tx ty tz rx ry rz` (or `quat`) with `values` as constants and `state_variables` as variables.
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
//! let hip = leg.user_joint_index("hip").unwrap();
//! assert_eq!(leg.user_joint_q_range(hip), 0..2);
//! assert_eq!(leg.user_joint_type(hip), "composite");
//! # Ok(())
//! # }
//! ```

use crate::builder::{JointSpec, ModelBuilder};
use crate::error::Issue;
use crate::joint::{JointKind, JointLimits};
use crate::link::Link;
use glam::{DQuat, DVec3};
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

    /// The axis' letter (`'x'`, `'y'`, `'z'`).
    #[must_use]
    pub const fn letter(self) -> char {
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
    /// A constant rotation given as a quaternion (trip's constant `qw qx qy qz`); it need not
    /// be normalised, but must not be zero or non-finite.
    Rotation(DQuat),
}

impl Factor {
    /// The factor's parameter name as trip_kinematics and the JSON schema write it: `"tx"` …
    /// `"rz"`, or `"quat"` for [`Factor::Ball`] and [`Factor::Rotation`].
    #[must_use]
    pub fn param(&self) -> String {
        match self {
            Self::Translate(a, _) => format!("t{}", a.letter()),
            Self::Rotate(a, _) => format!("r{}", a.letter()),
            Self::Ball | Self::Rotation(_) => "quat".into(),
        }
    }

    /// Whether the factor is a state variable.
    #[must_use]
    pub const fn is_variable(&self) -> bool {
        matches!(
            self,
            Self::Translate(_, None) | Self::Rotate(_, None) | Self::Ball
        )
    }

    /// The factor from its parameter name (`"tx"` … `"rz"`, `"quat"`) and constant value (`None`
    /// for a state variable; a quaternion constant is given as [`Factor::Rotation`]).
    #[must_use]
    pub fn from_param(param: &str, value: Option<f64>) -> Option<Self> {
        let axis = match param.get(1..)? {
            "x" => Axis::X,
            "y" => Axis::Y,
            "z" => Axis::Z,
            _ => return (param == "quat" && value.is_none()).then_some(Self::Ball),
        };
        match param.as_bytes()[0] {
            b't' => Some(Self::Translate(axis, value)),
            b'r' => Some(Self::Rotate(axis, value)),
            _ => None,
        }
    }
}

/// A composite joint between two links: `placement` (the pose of the joint frame in the parent
/// link's frame), then `factors` in order.
#[derive(Clone, Debug, PartialEq)]
pub struct CompositeJointSpec {
    /// The joint's name; its elementary pieces are `NAME.tx` … `NAME.rz` and `NAME.quat`.
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
    /// A frame of the parent link that `placement` is relative to (as [`JointSpec::at_frame`]).
    pub parent_frame: Option<String>,
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
            parent_frame: None,
        }
    }

    /// Sets the placement.
    #[must_use]
    pub fn with_placement(mut self, placement: Se3) -> Self {
        self.placement = placement;
        self
    }

    /// Sets the limits of the 1-DoF variables (translations in m, rotations in rad), in their
    /// order.
    #[must_use]
    pub fn with_limits(mut self, limits: impl Into<Vec<JointLimits>>) -> Self {
        self.limits = limits.into();
        self
    }

    /// The names of its elementary joints, one per state variable, in order (`NAME.rz`,
    /// `NAME.quat`; a joint with no variable is one fixed joint named as the composite).
    #[must_use]
    pub fn variable_names(&self) -> Vec<String> {
        let names: Vec<String> = self
            .factors
            .iter()
            .filter(|f| f.is_variable())
            .map(|f| format!("{}.{}", self.name, f.param()))
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
        let count = self.factors.iter().filter(|f| f.is_variable()).count();
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
                Factor::Rotation(r) => {
                    // A zero or non-finite quaternion is reported by `check`.
                    if let Some(r) = unit_quat(r) {
                        pose *= Se3::from_quat(r);
                    }
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
        if let (Some(frame), Some(first)) = (&self.parent_frame, joints.first_mut()) {
            first.parent_frame = Some(frame.clone());
        }
        (links, joints)
    }
}

/// The factors in order, variables bare and constants with their value (SI): `tx=0.1 ry rz`.
pub(crate) fn describe(spec: &CompositeJointSpec) -> String {
    let parts: Vec<String> = spec
        .factors
        .iter()
        .map(|f| match f {
            Factor::Translate(_, Some(x)) | Factor::Rotate(_, Some(x)) => {
                format!("{}={x}", f.param())
            }
            Factor::Rotation(r) => format!("quat={:?}", r.to_array()),
            _ => f.param(),
        })
        .collect();
    parts.join(" ")
}

/// The unit quaternion along `r`, or `None` when `r` is zero or not finite.
fn unit_quat(r: DQuat) -> Option<DQuat> {
    let n = r.length();
    (n.is_finite() && n > 1e-12).then(|| DQuat::from_xyzw(r.x / n, r.y / n, r.z / n, r.w / n))
}

impl CompositeJointSpec {
    /// The problems of the spec itself, each naming the joint: a state variable given twice, a
    /// non-finite constant, a zero or non-finite quaternion constant, more limits than 1-DoF
    /// variables.
    #[must_use]
    pub fn check(&self) -> Vec<Issue> {
        let mut issues = Vec::new();
        let mut bad = |reason: String| {
            issues.push(Issue::InvalidComposite {
                joint: self.name.clone(),
                reason,
            });
        };
        let mut seen: Vec<String> = Vec::new();
        for (k, f) in self.factors.iter().enumerate() {
            if f.is_variable() {
                let p = f.param();
                if seen.contains(&p) {
                    bad(format!("state variable '{p}' is given twice"));
                }
                seen.push(p);
            }
            match *f {
                Factor::Translate(_, Some(x)) | Factor::Rotate(_, Some(x)) if !x.is_finite() => {
                    bad(format!(
                        "factor {k} ('{}') has a non-finite value {x}",
                        f.param()
                    ));
                }
                Factor::Rotation(r) if unit_quat(r).is_none() => bad(format!(
                    "factor {k} ('quat') is the quaternion {:?}, which is zero or not finite",
                    r.to_array()
                )),
                _ => {}
            }
        }
        let scalars = self
            .factors
            .iter()
            .filter(|f| f.is_variable() && **f != Factor::Ball)
            .count();
        if self.limits.len() > scalars {
            bad(format!(
                "{} limits given for {scalars} translation and rotation variables",
                self.limits.len()
            ));
        }
        issues
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
        self.add_composite_spec(joint);
        self
    }
}
