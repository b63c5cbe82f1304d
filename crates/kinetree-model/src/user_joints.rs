//! The joints as users name them: every elementary joint is itself, and a composite joint
//! ([`crate::composite`]) is ONE joint covering the elementary pieces it is built from.
//!
//! [`Model::joints`] lists what the algorithms sweep over (a composite's pieces `NAME.rz` …
//! included); [`Model::user_joints`] lists what the model's author wrote, and is what named
//! states, the CLI and the JSON export use.

use crate::builder::{FrameSpec, JointSpec};
use crate::composite::CompositeJointSpec;
use crate::error::Issue;
use crate::model::Model;
use crate::state::Coordinate;
use core::ops::Range;
use std::collections::HashMap;

/// A composite joint of a built model: its spec (in SI) and the pieces it was expanded into.
#[derive(Clone, Debug, PartialEq)]
pub struct CompositeJoint {
    /// The spec it was built from (name, parent, child, placement, factors, limits).
    pub spec: CompositeJointSpec,
    /// Its elementary joints (indices into [`Model::joints`]), consecutive in depth-first order.
    pub joints: Range<usize>,
    /// Its massless virtual links (indices into [`Model::links`]).
    pub links: Vec<usize>,
}

/// A joint as users name it: an elementary joint, or a composite joint's pieces taken together.
#[derive(Clone, Debug, PartialEq)]
pub struct UserJoint {
    /// Its name.
    pub name: String,
    /// The elementary joints it covers (indices into [`Model::joints`]; one for an elementary
    /// joint).
    pub joints: Range<usize>,
    /// The composite joint it is (index into [`Model::composites`]), if it is one.
    pub composite: Option<usize>,
}

/// The model's user-facing joint list, computed once by the builder.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct UserJoints {
    composites: Vec<CompositeJoint>,
    list: Vec<UserJoint>,
    names: HashMap<String, usize>,
    /// The user joint of each elementary joint.
    of_joint: Vec<usize>,
    /// The composite joint each link is a virtual link of.
    virtual_link: Vec<Option<usize>>,
}

/// Virtual link names of a composite (`NAME#1` … `NAME#count`; which of them exist depends on
/// the constants after its last variable).
fn virtual_names(spec: &CompositeJointSpec) -> Vec<String> {
    let count = spec.factors.iter().filter(|f| f.is_variable()).count();
    (1..=count).map(|k| format!("{}#{k}", spec.name)).collect()
}

/// Names of a composite's pieces: its variables' joints, the fixed tail, or the one fixed joint
/// of a constants-only composite.
fn piece_names(spec: &CompositeJointSpec) -> Vec<String> {
    let mut names = spec.variable_names();
    names.push(format!("{}.fixed", spec.name));
    names
}

/// Builder check: every composite's own problems, and joints or frames attached to a link inside
/// a composite joint (between its pieces).
pub(crate) fn check(
    composites: &[CompositeJointSpec],
    joints: &[JointSpec],
    frames: &[FrameSpec],
) -> Vec<Issue> {
    let mut issues = Vec::new();
    for (k, c) in composites.iter().enumerate() {
        issues.extend(c.check());
        let pieces = piece_names(c);
        let clash = composites[..k].iter().any(|o| o.name == c.name)
            || joints
                .iter()
                .any(|j| j.name == c.name && !pieces.contains(&j.name));
        if clash {
            issues.push(Issue::DuplicateName {
                kind: crate::error::ItemKind::Joint,
                name: c.name.clone(),
            });
        }
        let inside = virtual_names(c);
        for j in joints {
            if inside.contains(&j.parent) && !pieces.contains(&j.name) {
                issues.push(Issue::InvalidComposite {
                    joint: c.name.clone(),
                    reason: format!(
                        "joint '{}' is attached to '{}', a virtual link inside it; attach it to '{}' or '{}'",
                        j.name, j.parent, c.parent, c.child
                    ),
                });
            }
        }
        for f in frames.iter().filter(|f| inside.contains(&f.link)) {
            issues.push(Issue::InvalidComposite {
                joint: c.name.clone(),
                reason: format!(
                    "frame '{}' is attached to '{}', a virtual link inside it",
                    f.name, f.link
                ),
            });
        }
    }
    issues
}

/// The user joints of a freshly assembled model.
pub(crate) fn resolve(model: &Model, specs: &[CompositeJointSpec]) -> UserJoints {
    let mut composites = Vec::with_capacity(specs.len());
    let mut composite_of_joint: Vec<Option<usize>> = vec![None; model.joints.len()];
    let mut virtual_link = vec![None; model.links.len()];
    for (c, spec) in specs.iter().enumerate() {
        let mut pieces: Vec<usize> = piece_names(spec)
            .iter()
            .filter_map(|n| model.joint_index(n))
            .collect();
        pieces.sort_unstable();
        let joints = match (pieces.first(), pieces.last()) {
            (Some(&a), Some(&b)) => a..b + 1,
            _ => 0..0,
        };
        for j in joints.clone() {
            composite_of_joint[j] = Some(c);
        }
        let links: Vec<usize> = virtual_names(spec)
            .iter()
            .filter_map(|n| model.link_index(n))
            .collect();
        for &l in &links {
            virtual_link[l] = Some(c);
        }
        composites.push(CompositeJoint {
            spec: spec.clone(),
            joints,
            links,
        });
    }
    let mut list = Vec::with_capacity(model.joints.len());
    let mut of_joint = Vec::with_capacity(model.joints.len());
    for (j, joint) in model.joints.iter().enumerate() {
        match composite_of_joint[j] {
            Some(c) if composites[c].joints.start != j => {}
            Some(c) => list.push(UserJoint {
                name: composites[c].spec.name.clone(),
                joints: composites[c].joints.clone(),
                composite: Some(c),
            }),
            None => list.push(UserJoint {
                name: joint.name.clone(),
                joints: j..j + 1,
                composite: None,
            }),
        }
        of_joint.push(list.len() - 1);
    }
    let names = list
        .iter()
        .enumerate()
        .map(|(i, u)| (u.name.clone(), i))
        .collect();
    UserJoints {
        composites,
        list,
        names,
        of_joint,
        virtual_link,
    }
}

impl Model {
    /// The joints as users name them, in depth-first order: each elementary joint, and each
    /// composite joint once (in place of its pieces). See [`crate::composite`].
    #[must_use]
    pub fn user_joints(&self) -> &[UserJoint] {
        &self.user.list
    }

    /// The composite joints ([`crate::composite`]), in the order they were added.
    #[must_use]
    pub fn composites(&self) -> &[CompositeJoint] {
        &self.user.composites
    }

    /// The index of the user joint called `name` (a composite joint by its own name, not its
    /// pieces').
    #[must_use]
    pub fn user_joint_index(&self, name: &str) -> Option<usize> {
        self.user.names.get(name).copied()
    }

    /// The user joint that elementary joint `joint` belongs to (itself, or its composite joint).
    #[must_use]
    pub fn user_joint_of(&self, joint: usize) -> usize {
        self.user.of_joint[joint]
    }

    /// The composite joint that elementary joint `joint` is a piece of, if any.
    #[must_use]
    pub fn composite_of_joint(&self, joint: usize) -> Option<usize> {
        self.user.list[self.user.of_joint[joint]].composite
    }

    /// The composite joint whose massless virtual link `link` is (`None` for a link the model's
    /// author wrote).
    #[must_use]
    pub fn composite_of_link(&self, link: usize) -> Option<usize> {
        self.user.virtual_link[link]
    }

    /// Whether link `link` is a massless virtual link inside a composite joint.
    #[must_use]
    pub fn is_virtual_link(&self, link: usize) -> bool {
        self.user.virtual_link[link].is_some()
    }

    /// The type name of user joint `joint`: `"composite"`, or its kind's (`"revolute"`, …).
    #[must_use]
    pub fn user_joint_type(&self, joint: usize) -> &'static str {
        let u = &self.user.list[joint];
        match u.composite {
            Some(_) => "composite",
            None => self.joints[u.joints.start].kind.as_str(),
        }
    }

    /// User joint `joint`'s block in `q` (a composite joint's pieces' blocks, which are
    /// consecutive; empty for fixed joints and coupled mimic joints).
    #[must_use]
    pub fn user_joint_q_range(&self, joint: usize) -> Range<usize> {
        self.user_range(joint, Model::joint_q_range)
    }

    /// User joint `joint`'s block in `v` (as [`Model::user_joint_q_range`]).
    #[must_use]
    pub fn user_joint_v_range(&self, joint: usize) -> Range<usize> {
        self.user_range(joint, Model::joint_v_range)
    }

    fn user_range(&self, joint: usize, range: fn(&Model, usize) -> Range<usize>) -> Range<usize> {
        let mut out: Option<Range<usize>> = None;
        for r in self.user.list[joint].joints.clone().map(|j| range(self, j)) {
            if r.is_empty() {
                continue;
            }
            out = Some(match out {
                Some(o) => o.start.min(r.start)..o.end.max(r.end),
                None => r,
            });
        }
        out.unwrap_or(0..0)
    }

    /// The user joints that own coordinates, in the order of their blocks in `q` and `v` (as
    /// [`Model::moving_joints`], with each composite joint once).
    pub fn moving_user_joints(&self) -> impl Iterator<Item = usize> + '_ {
        let mut last = None;
        self.moving_joints().filter_map(move |j| {
            let u = self.user.of_joint[j];
            (last != Some(u)).then(|| {
                last = Some(u);
                u
            })
        })
    }

    /// What each coordinate of user joint `joint`'s `q` block measures (a composite joint's
    /// pieces' coordinates in order; empty when it owns no coordinates).
    #[must_use]
    pub fn user_joint_q_coordinates(&self, joint: usize) -> Vec<Coordinate> {
        self.user_coordinates(joint, false)
    }

    /// What each coordinate of user joint `joint`'s `v` block measures.
    #[must_use]
    pub fn user_joint_v_coordinates(&self, joint: usize) -> Vec<Coordinate> {
        self.user_coordinates(joint, true)
    }

    fn user_coordinates(&self, joint: usize, velocity: bool) -> Vec<Coordinate> {
        self.user.list[joint]
            .joints
            .clone()
            .filter(|&j| !self.joint_q_range(j).is_empty())
            .flat_map(|j| {
                let kind = self.joints[j].kind;
                if velocity {
                    kind.v_coordinates()
                } else {
                    kind.q_coordinates()
                }
            })
            .copied()
            .collect()
    }

    /// The user joint called `name`, or else the user joint of the elementary joint called
    /// `name` (so a composite's piece `hip.ry` finds `hip`).
    #[must_use]
    pub fn find_user_joint(&self, name: &str) -> Option<usize> {
        self.user_joint_index(name)
            .or_else(|| self.joint_index(name).map(|j| self.user.of_joint[j]))
    }
}
