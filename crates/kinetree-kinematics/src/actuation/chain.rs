//! [`ActuatedChain`]: a [`Chain`] driven through [`ActuationGroup`]s.

use super::*;
use crate::chain::Chain;
use crate::data::KinematicsData;
use crate::error::{GroupProblem, KinematicsError, check_vector};
use kinetree_model::JointKind;
use kinetree_model::spatial::Se3;
use std::collections::HashMap;

/// Where one robot-level actuated coordinate lives.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Coordinate {
    /// Coordinate `index` of group `group`.
    Group { group: usize, index: usize },
    /// Entry `idx_q` of the chain's configuration (a joint outside every group).
    Joint { idx_q: usize },
}

/// A [`Chain`] driven through [`ActuationGroup`]s: a robot as a union of groups.
///
/// The robot-level actuated state lists every group's actuated coordinates (groups in the order
/// given, each in its own order), then the configuration coordinates of every moving joint that
/// belongs to no group, in `q` order: those are driven directly, like trip_kinematics' open
/// groups. Such a coordinate is named after its joint, or `joint[k]` for the `k`-th coordinate of
/// a multi-DoF joint (set quaternions as a whole with [`ActuatedChain::set_joint_q`]).
///
/// The chain's configuration always equals what the groups' actuated states give: the chain is
/// only reachable read-only ([`ActuatedChain::chain`]) or through the pose queries here.
///
/// # Examples
/// A knee driven by a linear actuator (see [`LinearActuator`] for the geometry):
/// ```
/// use kinetree_kinematics::{ActuatedChain, ActuationGroup, Chain, GroupSpec, LinearActuator};
/// use kinetree_model::{FrameSpec, JointKind, JointLimits, JointSpec, Link, ModelBuilder};
/// use kinetree_model::spatial::Se3;
/// use glam::DVec3;
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let mut b = ModelBuilder::new("leg");
/// b.add_link(Link::new("thigh"));
/// b.add_part(
///     Link::new("shank"),
///     JointSpec::new("knee", JointKind::Revolute, "thigh", "shank")
///         .with_limits(JointLimits::position(-1.2, 1.2)),
/// );
/// b.add_frame(FrameSpec::new("foot", "shank", Se3::from_translation(DVec3::new(0.5, 0.0, 0.0))));
/// let model = b.build()?;
/// // The actuator runs from 0.4 m below the knee on the thigh to 0.1 m along the shank.
/// let actuator = LinearActuator::new(&model, "knee", DVec3::new(0.0, -0.4, 0.0), DVec3::new(0.1, 0.0, 0.0))?;
/// let spec = GroupSpec::new("knee_drive", ["knee_actuator"], ["knee"], [0.42]);
/// let knee = ActuationGroup::new(&model, spec, actuator)?;
/// let mut leg = ActuatedChain::new(Chain::new(model), vec![knee])?;
///
/// // s² = 0.17 + 0.08 sin θ: a 0.21 m² stroke squared puts the knee at 30°.
/// leg.set_actuated("knee_actuator", 0.21f64.sqrt())?;
/// assert!((leg.chain().joint_value_deg("knee")? - 30.0).abs() < 1e-9);
/// let foot = leg.world_from("foot")?;
/// assert!((foot.translation - DVec3::new(0.5 * 30f64.to_radians().cos(), 0.25, 0.0)).length() < 1e-12);
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct ActuatedChain {
    chain: Chain,
    groups: Vec<ActuationGroup>,
    /// Per model joint: the group driving it.
    joint_group: Vec<Option<usize>>,
    names: Vec<String>,
    coordinates: Vec<Coordinate>,
    index: HashMap<String, usize>,
    /// Where each group's coordinates start in the actuated state.
    group_offsets: Vec<usize>,
    state: Vec<f64>,
}

impl ActuatedChain {
    /// Couples `chain` with `groups` (built for the chain's model) and moves the groups' joints to
    /// the groups' current states.
    ///
    /// # Errors
    /// [`KinematicsError::InvalidGroup`] when two groups share a name, a joint or an actuator
    /// name, when an actuator is named like a directly driven coordinate, or when a group was
    /// built for another model.
    pub fn new(mut chain: Chain, groups: Vec<ActuationGroup>) -> Result<Self, KinematicsError> {
        let model = chain.model();
        let mut joint_group = vec![None; model.joints().len()];
        let mut names = Vec::new();
        let mut coordinates = Vec::new();
        let mut group_offsets = Vec::with_capacity(groups.len());
        for (g, group) in groups.iter().enumerate() {
            let invalid = |problem: GroupProblem| KinematicsError::InvalidGroup {
                group: group.name.clone(),
                problem,
            };
            if groups[..g].iter().any(|o| o.name == group.name) {
                return Err(invalid(GroupProblem::DuplicateGroup));
            }
            let same_model = group.model_nq == model.nq()
                && group.joints.iter().zip(&group.joint_names).all(|(&j, n)| {
                    j < model.joints().len()
                        && model.joint(j).name == *n
                        && !model.joint_q_range(j).is_empty()
                });
            if !same_model {
                return Err(invalid(GroupProblem::OtherModel));
            }
            for (&j, n) in group.joints.iter().zip(&group.joint_names) {
                if let Some(first) = joint_group[j] {
                    let first: &ActuationGroup = &groups[first];
                    return Err(invalid(GroupProblem::JointAlreadyDriven {
                        joint: n.clone(),
                        by: first.name.clone(),
                    }));
                }
                joint_group[j] = Some(g);
            }
            group_offsets.push(names.len());
            for (index, a) in group.actuators.iter().enumerate() {
                names.push(a.clone());
                coordinates.push(Coordinate::Group { group: g, index });
            }
        }
        for j in model.moving_joints() {
            if joint_group[j].is_none() {
                let range = model.joint_q_range(j);
                let name = &model.joint(j).name;
                for (k, idx_q) in range.clone().enumerate() {
                    names.push(if range.len() == 1 {
                        name.clone()
                    } else {
                        format!("{name}[{k}]")
                    });
                    coordinates.push(Coordinate::Joint { idx_q });
                }
            }
        }
        let mut index = HashMap::with_capacity(names.len());
        for (k, n) in names.iter().enumerate() {
            if let Some(first) = index.insert(n.clone(), k) {
                // Name the later group, or the group whose actuator clashes with a joint.
                let group = [coordinates[k], coordinates[first]]
                    .into_iter()
                    .find_map(|c| match c {
                        Coordinate::Group { group, .. } => Some(groups[group].name.clone()),
                        Coordinate::Joint { .. } => None,
                    })
                    .unwrap_or_else(|| "(directly driven joints)".into());
                return Err(KinematicsError::InvalidGroup {
                    group,
                    problem: GroupProblem::DuplicateCoordinate { name: n.clone() },
                });
            }
        }
        let mut q = chain.q().to_vec();
        for group in &groups {
            group.write_q(&mut q)?;
        }
        chain.set_q(&q)?;
        let mut robot = Self {
            chain,
            groups,
            joint_group,
            names,
            coordinates,
            index,
            group_offsets,
            state: Vec::new(),
        };
        robot.refresh_state();
        Ok(robot)
    }

    /// The chain, read-only (its configuration follows the groups).
    #[must_use]
    pub fn chain(&self) -> &Chain {
        &self.chain
    }

    /// The groups.
    #[must_use]
    pub fn groups(&self) -> &[ActuationGroup] {
        &self.groups
    }

    /// The group called `name`.
    #[must_use]
    pub fn group(&self, name: &str) -> Option<&ActuationGroup> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// Gives the chain and the groups back.
    #[must_use]
    pub fn into_parts(self) -> (Chain, Vec<ActuationGroup>) {
        (self.chain, self.groups)
    }

    /// Names of the robot-level actuated coordinates (see the type docs for the order).
    #[must_use]
    pub fn actuator_names(&self) -> &[String] {
        &self.names
    }

    /// The robot-level actuated state, in the order of [`ActuatedChain::actuator_names`].
    #[must_use]
    pub fn actuated_state(&self) -> &[f64] {
        &self.state
    }

    /// One actuated coordinate by name.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownActuator`].
    pub fn actuated(&self, name: &str) -> Result<f64, KinematicsError> {
        Ok(self.state[self.coordinate(name)?])
    }

    /// Sets one actuated coordinate by name and moves the joints it drives.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownActuator`]; a non-finite value or a failing mapping as in
    /// [`ActuationGroup::set_actuated`]. Nothing changes on error.
    pub fn set_actuated(&mut self, name: &str, value: f64) -> Result<(), KinematicsError> {
        let k = self.coordinate(name)?;
        match self.coordinates[k] {
            Coordinate::Group { group, index } => {
                let mut a = self.groups[group].actuated.clone();
                a[index] = value;
                self.groups[group].set_actuated(&a)?;
                self.apply_group(group)?;
            }
            Coordinate::Joint { idx_q } => {
                let mut q = self.chain.q().to_vec();
                q[idx_q] = value;
                self.chain.set_q(&q)?;
            }
        }
        self.refresh_state();
        Ok(())
    }

    /// Sets the whole robot-level actuated state (length `actuator_names().len()`) and moves every
    /// joint accordingly.
    ///
    /// # Errors
    /// [`KinematicsError::DimensionMismatch`] or [`KinematicsError::NonFinite`] for `state`; a
    /// failing mapping as in [`ActuationGroup::set_actuated`]. Every mapping runs before anything
    /// changes, so nothing changes on error.
    pub fn set_actuated_state(&mut self, state: &[f64]) -> Result<(), KinematicsError> {
        check_vector("actuated", state, self.names.len())?;
        let mut virtuals = Vec::with_capacity(self.groups.len());
        for (g, group) in self.groups.iter().enumerate() {
            let a = &state[self.group_offsets[g]..self.group_offsets[g] + group.actuators.len()];
            let mut v = Vec::new();
            group.checked_to_virtual(a, &mut v)?;
            virtuals.push(v);
        }
        let mut q = self.chain.q().to_vec();
        for (g, v) in virtuals.into_iter().enumerate() {
            let group = &mut self.groups[g];
            let start = self.group_offsets[g];
            group
                .actuated
                .copy_from_slice(&state[start..start + group.actuators.len()]);
            group.virtual_q = v;
            group.write_q(&mut q)?;
        }
        for (k, c) in self.coordinates.iter().enumerate() {
            if let Coordinate::Joint { idx_q } = *c {
                q[idx_q] = state[k];
            }
        }
        self.chain.set_q(&q)?;
        self.refresh_state();
        Ok(())
    }

    /// Sets the configuration block of a joint by name. For a joint driven by a group, the
    /// group's other joints keep their values and its actuated coordinates follow.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`]; [`KinematicsError::InvalidJointValue`] for a fixed
    /// joint, a wrong number of values or a non-finite value; a failing mapping as in
    /// [`ActuationGroup::set_virtual_q`]. Nothing changes on error.
    pub fn set_joint_q(&mut self, name: &str, values: &[f64]) -> Result<(), KinematicsError> {
        let j =
            self.chain
                .model()
                .joint_index(name)
                .ok_or_else(|| KinematicsError::UnknownJoint {
                    name: name.to_string(),
                })?;
        match self.joint_group[j] {
            Some(g) => {
                self.groups[g].set_joint_q(name, values)?;
                self.apply_group(g)?;
            }
            None => self.chain.set_joint_q(name, values)?,
        }
        self.refresh_state();
        Ok(())
    }

    /// Sets the 1-DoF joint named `name` to `value` (rad or m), as [`ActuatedChain::set_joint_q`].
    ///
    /// # Errors
    /// As [`ActuatedChain::set_joint_q`], and [`KinematicsError::WrongJointKind`] for a joint that
    /// is not revolute, continuous or prismatic.
    pub fn set_joint_value(&mut self, name: &str, value: f64) -> Result<(), KinematicsError> {
        if let Some(j) = self.chain.model().joint_index(name) {
            let kind = self.chain.model().joint(j).kind;
            if !matches!(
                kind,
                JointKind::Revolute | JointKind::Continuous | JointKind::Prismatic
            ) {
                return Err(KinematicsError::WrongJointKind {
                    joint: name.to_string(),
                    kind,
                    expected: "a revolute, continuous or prismatic joint",
                });
            }
        }
        self.set_joint_q(name, &[value])
    }

    /// The world placement of a link or named frame (see [`Chain::world_from`]).
    ///
    /// # Errors
    /// [`KinematicsError::UnknownFrame`].
    pub fn world_from(&mut self, name: &str) -> Result<Se3, KinematicsError> {
        self.chain.world_from(name)
    }

    /// The pose of `b` in `a` (see [`Chain::relative_transform`]).
    ///
    /// # Errors
    /// [`KinematicsError::UnknownFrame`].
    pub fn relative_transform(&mut self, a: &str, b: &str) -> Result<Se3, KinematicsError> {
        self.chain.relative_transform(a, b)
    }

    /// The world placement of every link (see [`Chain::world_from_link`]).
    pub fn world_from_link(&mut self) -> &[Se3] {
        self.chain.world_from_link()
    }

    /// The up-to-date kinematics data (see [`Chain::data`]).
    pub fn data(&mut self) -> &KinematicsData {
        self.chain.data()
    }

    fn coordinate(&self, name: &str) -> Result<usize, KinematicsError> {
        self.index
            .get(name)
            .copied()
            .ok_or_else(|| KinematicsError::UnknownActuator {
                name: name.to_string(),
            })
    }

    /// Writes group `g`'s virtual state into the chain.
    fn apply_group(&mut self, g: usize) -> Result<(), KinematicsError> {
        let mut q = self.chain.q().to_vec();
        self.groups[g].write_q(&mut q)?;
        self.chain.set_q(&q)
    }

    fn refresh_state(&mut self) {
        let q = self.chain.q();
        self.state.clear();
        self.state.extend(self.coordinates.iter().map(|c| match *c {
            Coordinate::Group { group, index } => self.groups[group].actuated[index],
            Coordinate::Joint { idx_q } => q[idx_q],
        }));
    }
}
