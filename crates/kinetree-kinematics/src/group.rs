//! Actuation groups: actuated coordinates coupled to the joints they drive through a pair of
//! mappings (trip_kinematics' kinematic groups), and a chain driven through them.

use crate::chain::Chain;
use crate::configuration::wrap_angle;
use crate::data::KinematicsData;
pub use crate::error::MappingDirection;
use crate::error::{GroupProblem, KinematicsError, check_vector};
use core::fmt;
use core::ops::Range;
use glam::DVec3;
use kinetree_model::spatial::Se3;
use kinetree_model::{JointKind, Model};
use std::collections::HashMap;

/// Default tolerance of the round-trip check of a group's mappings (see [`GroupSpec::tolerance`]).
pub const ROUND_TRIP_TOLERANCE: f64 = 1e-9;

/// The two mappings of an [`ActuationGroup`].
///
/// Each appends its result to an empty vector (so a mapping that writes the wrong number of values
/// is caught, and no allocation happens once the vector has grown). Virtual coordinates are the
/// configuration blocks of the group's joints, concatenated in the order the group lists them
/// (SI units; see [`JointKind`] for multi-DoF layouts). A mapping signals an input outside its
/// domain by writing NaN, which the group reports as [`KinematicsError::MappingNonFinite`].
///
/// Implement it on a type that holds the mechanism's parameters (as [`LinearActuator`] does), or
/// wrap two closures in [`FnActuation`].
pub trait Actuation: Send + Sync {
    /// Appends the virtual joint coordinates produced by the actuated coordinates `actuated`.
    fn to_virtual(&self, actuated: &[f64], virtual_q: &mut Vec<f64>);
    /// Appends the actuated coordinates that produce the virtual joint coordinates `virtual_q`.
    fn to_actuated(&self, virtual_q: &[f64], actuated: &mut Vec<f64>);
}

/// An [`Actuation`] made of two closures.
///
/// # Examples
/// ```
/// use kinetree_kinematics::{Actuation, FnActuation};
/// // A belt with a 3:1 reduction.
/// let belt = FnActuation::new(
///     |motor: &[f64], joint: &mut Vec<f64>| joint.push(motor[0] / 3.0),
///     |joint: &[f64], motor: &mut Vec<f64>| motor.push(joint[0] * 3.0),
/// );
/// let mut joint = Vec::new();
/// belt.to_virtual(&[1.5], &mut joint);
/// assert_eq!(joint, [0.5]);
/// ```
pub struct FnActuation<F, G> {
    to_virtual: F,
    to_actuated: G,
}

impl<F, G> FnActuation<F, G>
where
    F: Fn(&[f64], &mut Vec<f64>) + Send + Sync,
    G: Fn(&[f64], &mut Vec<f64>) + Send + Sync,
{
    /// Pairs `to_virtual` (actuated → virtual) with `to_actuated` (virtual → actuated).
    pub fn new(to_virtual: F, to_actuated: G) -> Self {
        Self {
            to_virtual,
            to_actuated,
        }
    }
}

impl<F, G> Actuation for FnActuation<F, G>
where
    F: Fn(&[f64], &mut Vec<f64>) + Send + Sync,
    G: Fn(&[f64], &mut Vec<f64>) + Send + Sync,
{
    fn to_virtual(&self, actuated: &[f64], virtual_q: &mut Vec<f64>) {
        (self.to_virtual)(actuated, virtual_q);
    }

    fn to_actuated(&self, virtual_q: &[f64], actuated: &mut Vec<f64>) {
        (self.to_actuated)(virtual_q, actuated);
    }
}

impl<F, G> fmt::Debug for FnActuation<F, G> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FnActuation").finish_non_exhaustive()
    }
}

/// What an [`ActuationGroup`] is made of, before its mappings are checked.
#[derive(Clone, Debug, PartialEq)]
pub struct GroupSpec {
    /// The group's name (unique within an [`ActuatedChain`]).
    pub name: String,
    /// Names of the actuated coordinates (unique within an [`ActuatedChain`]).
    pub actuators: Vec<String>,
    /// Names of the moving joints the group drives, in the order of the virtual coordinates.
    pub joints: Vec<String>,
    /// The actuated state at which the mappings are checked; it is also the group's initial
    /// state (length `actuators.len()`).
    pub probe: Vec<f64>,
    /// Tolerance of the round trip actuated → virtual → actuated at the probe, relative to
    /// `max(1, |probe value|)` (default [`ROUND_TRIP_TOLERANCE`]).
    pub tolerance: f64,
}

impl GroupSpec {
    /// A group called `name` driving `joints` from `actuators`, checked and started at `probe`.
    #[must_use]
    pub fn new(
        name: impl Into<String>,
        actuators: impl IntoIterator<Item = impl Into<String>>,
        joints: impl IntoIterator<Item = impl Into<String>>,
        probe: impl Into<Vec<f64>>,
    ) -> Self {
        Self {
            name: name.into(),
            actuators: actuators.into_iter().map(Into::into).collect(),
            joints: joints.into_iter().map(Into::into).collect(),
            probe: probe.into(),
            tolerance: ROUND_TRIP_TOLERANCE,
        }
    }

    /// Sets the round-trip tolerance.
    #[must_use]
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }
}

/// Actuated coordinates coupled to the joints they drive through a pair of mappings
/// (trip_kinematics' kinematic group).
///
/// Many mechanisms are not driven joint by joint. A linear actuator pushes a knee through a
/// four-bar; two motors drive a wrist's pitch and roll through a differential. The model keeps the
/// *virtual* joints (the serial sub-chain whose motion the mechanism produces: the knee, the pitch
/// and roll joints) and an [`ActuationGroup`] adds the *actuated* coordinates (the actuator
/// length, the two motor angles) with two mappings, actuated → virtual and virtual → actuated
/// ([`Actuation`]). Setting either side updates the other. An [`ActuatedChain`] is a robot as a
/// union of groups: its actuated state is every group's actuated coordinates, then the coordinates
/// of the joints outside any group (driven directly, an identity mapping).
///
/// The mappings are checked when a group is built: at a probe point given in the [`GroupSpec`],
/// each must write the right number of finite values, and actuated → virtual → actuated must come
/// back within the spec's tolerance. [`LinearActuator`] is a worked example solved in closed form.
///
/// The group holds both states and keeps them consistent: [`ActuationGroup::set_actuated`] maps
/// to the joints, [`ActuationGroup::set_virtual_q`] maps back. On any error the state is
/// unchanged.
///
/// # Examples
/// A differential: two motors `a` and `b` give pitch `(a + b) / 2` and roll `(a - b) / 2`.
/// ```
/// use kinetree_kinematics::{ActuatedChain, ActuationGroup, Chain, FnActuation, GroupSpec};
/// use kinetree_model::{JointKind, JointSpec, Link, ModelBuilder};
/// use glam::DVec3;
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let mut b = ModelBuilder::new("wrist");
/// b.add_link(Link::new("forearm"));
/// b.add_part(Link::new("yoke"), JointSpec::new("pitch", JointKind::Revolute, "forearm", "yoke").with_axis(DVec3::Y));
/// b.add_part(Link::new("hand"), JointSpec::new("roll", JointKind::Revolute, "yoke", "hand").with_axis(DVec3::X));
/// let model = b.build()?;
///
/// let differential = FnActuation::new(
///     |motors: &[f64], joints: &mut Vec<f64>| {
///         joints.extend([(motors[0] + motors[1]) / 2.0, (motors[0] - motors[1]) / 2.0]);
///     },
///     |joints: &[f64], motors: &mut Vec<f64>| {
///         motors.extend([joints[0] + joints[1], joints[0] - joints[1]]);
///     },
/// );
/// let spec = GroupSpec::new("wrist", ["motor_a", "motor_b"], ["pitch", "roll"], [0.0, 0.0]);
/// let group = ActuationGroup::new(&model, spec, differential)?;
/// let mut robot = ActuatedChain::new(Chain::new(model), vec![group])?;
///
/// robot.set_actuated_state(&[0.3, 0.1])?;
/// assert!((robot.chain().joint_value("pitch")? - 0.2).abs() < 1e-15);
/// assert!((robot.chain().joint_value("roll")? - 0.1).abs() < 1e-15);
///
/// // Setting a virtual joint moves the motors.
/// robot.set_joint_value("roll", 0.0)?;
/// assert!((robot.actuated("motor_a")? - 0.2).abs() < 1e-15);
/// assert!((robot.actuated("motor_b")? - 0.2).abs() < 1e-15);
/// # Ok(())
/// # }
/// ```
pub struct ActuationGroup {
    name: String,
    actuators: Vec<String>,
    joints: Vec<usize>,
    joint_names: Vec<String>,
    /// Per joint: its block in the model's `q` and where it starts in `virtual_q`.
    blocks: Vec<(Range<usize>, usize)>,
    model_nq: usize,
    map: Box<dyn Actuation>,
    actuated: Vec<f64>,
    virtual_q: Vec<f64>,
    scratch: Vec<f64>,
}

impl fmt::Debug for ActuationGroup {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ActuationGroup")
            .field("name", &self.name)
            .field("actuators", &self.actuators)
            .field("joints", &self.joint_names)
            .field("actuated", &self.actuated)
            .field("virtual_q", &self.virtual_q)
            .finish_non_exhaustive()
    }
}

impl ActuationGroup {
    /// Builds a group of `model` from `spec` and `map`, checking the mappings at `spec.probe`.
    ///
    /// # Errors
    /// - [`KinematicsError::InvalidGroup`]: no actuators or joints, a name listed twice, a
    ///   negative or non-finite tolerance;
    /// - [`KinematicsError::UnknownJoint`], or [`KinematicsError::WrongJointKind`] for a fixed
    ///   joint;
    /// - [`KinematicsError::DimensionMismatch`] or [`KinematicsError::NonFinite`] for the probe;
    /// - [`KinematicsError::MappingSize`] or [`KinematicsError::MappingNonFinite`] when a mapping
    ///   writes the wrong number of values or a non-finite one at the probe;
    /// - [`KinematicsError::MappingInconsistent`] when actuated → virtual → actuated does not come
    ///   back to the probe within the tolerance.
    pub fn new(
        model: &Model,
        spec: GroupSpec,
        map: impl Actuation + 'static,
    ) -> Result<Self, KinematicsError> {
        let GroupSpec {
            name,
            actuators,
            joints: joint_names,
            probe,
            tolerance,
        } = spec;
        let invalid = |problem: GroupProblem| KinematicsError::InvalidGroup {
            group: name.clone(),
            problem,
        };
        if actuators.is_empty() {
            return Err(invalid(GroupProblem::NoActuators));
        }
        if let Some(a) = first_duplicate(&actuators) {
            return Err(invalid(GroupProblem::DuplicateActuator {
                actuator: a.to_string(),
            }));
        }
        if joint_names.is_empty() {
            return Err(invalid(GroupProblem::NoJoints));
        }
        if let Some(j) = first_duplicate(&joint_names) {
            return Err(invalid(GroupProblem::DuplicateJoint {
                joint: j.to_string(),
            }));
        }
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(invalid(GroupProblem::InvalidTolerance { tolerance }));
        }
        let mut joints = Vec::with_capacity(joint_names.len());
        let mut blocks = Vec::with_capacity(joint_names.len());
        let mut nvirtual = 0;
        for jn in &joint_names {
            let j = model
                .joint_index(jn)
                .ok_or_else(|| KinematicsError::UnknownJoint { name: jn.clone() })?;
            let range = model.joint_q_range(j);
            if range.is_empty() {
                return Err(KinematicsError::WrongJointKind {
                    joint: jn.clone(),
                    kind: model.joint(j).kind,
                    expected: "a moving joint",
                });
            }
            blocks.push((range.clone(), nvirtual));
            nvirtual += range.len();
            joints.push(j);
        }
        check_vector("probe", &probe, actuators.len())?;
        let mut group = Self {
            name,
            actuators,
            joints,
            joint_names,
            blocks,
            model_nq: model.nq(),
            map: Box::new(map),
            actuated: probe,
            virtual_q: Vec::with_capacity(nvirtual),
            scratch: Vec::with_capacity(nvirtual),
        };
        let mut virtual_q = Vec::with_capacity(nvirtual);
        group.checked_to_virtual(&group.actuated, &mut virtual_q)?;
        let mut round_trip = Vec::with_capacity(group.actuated.len());
        group.checked_to_actuated(&virtual_q, &mut round_trip)?;
        for (k, (&p, &r)) in group.actuated.iter().zip(&round_trip).enumerate() {
            if (r - p).abs() > tolerance * p.abs().max(1.0) {
                return Err(KinematicsError::MappingInconsistent {
                    group: group.name.clone(),
                    actuator: group.actuators[k].clone(),
                    probe: p,
                    round_trip: r,
                    tolerance,
                });
            }
        }
        group.virtual_q = virtual_q;
        Ok(group)
    }

    /// The group's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Names of the actuated coordinates.
    #[must_use]
    pub fn actuators(&self) -> &[String] {
        &self.actuators
    }

    /// Names of the joints driven, in the order of the virtual coordinates.
    #[must_use]
    pub fn joints(&self) -> &[String] {
        &self.joint_names
    }

    /// The actuated coordinates (length `actuators().len()`).
    #[must_use]
    pub fn actuated(&self) -> &[f64] {
        &self.actuated
    }

    /// The virtual coordinates: the configuration blocks of [`ActuationGroup::joints`],
    /// concatenated.
    #[must_use]
    pub fn virtual_q(&self) -> &[f64] {
        &self.virtual_q
    }

    /// Sets the actuated coordinates and updates the virtual ones through the mapping.
    ///
    /// # Errors
    /// [`KinematicsError::DimensionMismatch`] or [`KinematicsError::NonFinite`] for `actuated`;
    /// [`KinematicsError::MappingSize`] or [`KinematicsError::MappingNonFinite`] when the mapping
    /// fails (e.g. an actuator length the mechanism cannot reach). The group is unchanged on error.
    pub fn set_actuated(&mut self, actuated: &[f64]) -> Result<(), KinematicsError> {
        check_vector("actuated", actuated, self.actuators.len())?;
        let mut out = core::mem::take(&mut self.scratch);
        let result = self.checked_to_virtual(actuated, &mut out);
        if result.is_ok() {
            self.actuated.copy_from_slice(actuated);
            core::mem::swap(&mut self.virtual_q, &mut out);
        }
        self.scratch = out;
        result
    }

    /// Sets one actuated coordinate by name, keeping the others, and updates the virtual ones.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownActuator`], then as [`ActuationGroup::set_actuated`].
    pub fn set_actuator(&mut self, name: &str, value: f64) -> Result<(), KinematicsError> {
        let k = self
            .actuators
            .iter()
            .position(|a| a == name)
            .ok_or_else(|| KinematicsError::UnknownActuator {
                name: name.to_string(),
            })?;
        let mut actuated = self.actuated.clone();
        actuated[k] = value;
        self.set_actuated(&actuated)
    }

    /// Sets the virtual coordinates and updates the actuated ones through the mapping.
    ///
    /// # Errors
    /// [`KinematicsError::DimensionMismatch`] or [`KinematicsError::NonFinite`] for `virtual_q`;
    /// [`KinematicsError::MappingSize`] or [`KinematicsError::MappingNonFinite`] when the mapping
    /// fails. The group is unchanged on error.
    pub fn set_virtual_q(&mut self, virtual_q: &[f64]) -> Result<(), KinematicsError> {
        check_vector("virtual_q", virtual_q, self.virtual_q.len())?;
        let mut out = core::mem::take(&mut self.scratch);
        let result = self.checked_to_actuated(virtual_q, &mut out);
        if result.is_ok() {
            self.virtual_q.copy_from_slice(virtual_q);
            core::mem::swap(&mut self.actuated, &mut out);
        }
        self.scratch = out;
        result
    }

    /// Sets the configuration block of one of the group's joints, keeping the others, and updates
    /// the actuated coordinates.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`] when the group does not drive a joint of this name;
    /// [`KinematicsError::InvalidJointValue`] for a block of the wrong length; then as
    /// [`ActuationGroup::set_virtual_q`].
    pub fn set_joint_q(&mut self, name: &str, values: &[f64]) -> Result<(), KinematicsError> {
        let k = self
            .joint_names
            .iter()
            .position(|j| j == name)
            .ok_or_else(|| KinematicsError::UnknownJoint {
                name: name.to_string(),
            })?;
        let (range, start) = &self.blocks[k];
        if values.len() != range.len() {
            return Err(KinematicsError::InvalidJointValue {
                joint: name.to_string(),
                reason: format!("takes {} value(s), got {}", range.len(), values.len()),
            });
        }
        let mut virtual_q = self.virtual_q.clone();
        virtual_q[*start..*start + range.len()].copy_from_slice(values);
        self.set_virtual_q(&virtual_q)
    }

    /// Writes the virtual coordinates into their joints' blocks of a model configuration `q`
    /// (length `model.nq()`), leaving the other entries alone.
    ///
    /// # Errors
    /// [`KinematicsError::DimensionMismatch`] when `q` does not have the model's `nq`.
    pub fn write_q(&self, q: &mut [f64]) -> Result<(), KinematicsError> {
        if q.len() != self.model_nq {
            return Err(KinematicsError::DimensionMismatch {
                what: "q",
                expected: self.model_nq,
                actual: q.len(),
            });
        }
        for (range, start) in &self.blocks {
            q[range.clone()].copy_from_slice(&self.virtual_q[*start..*start + range.len()]);
        }
        Ok(())
    }

    /// Runs actuated → virtual into `out` (cleared first) and checks its size and finiteness.
    fn checked_to_virtual(
        &self,
        actuated: &[f64],
        out: &mut Vec<f64>,
    ) -> Result<(), KinematicsError> {
        out.clear();
        self.map.to_virtual(actuated, out);
        let expected = self.blocks.last().map_or(0, |(r, s)| s + r.len());
        self.check_output(MappingDirection::ActuatedToVirtual, out, expected)
    }

    /// Runs virtual → actuated into `out` (cleared first) and checks its size and finiteness.
    fn checked_to_actuated(
        &self,
        virtual_q: &[f64],
        out: &mut Vec<f64>,
    ) -> Result<(), KinematicsError> {
        out.clear();
        self.map.to_actuated(virtual_q, out);
        self.check_output(
            MappingDirection::VirtualToActuated,
            out,
            self.actuators.len(),
        )
    }

    fn check_output(
        &self,
        direction: MappingDirection,
        out: &[f64],
        expected: usize,
    ) -> Result<(), KinematicsError> {
        if out.len() != expected {
            return Err(KinematicsError::MappingSize {
                group: self.name.clone(),
                direction,
                expected,
                actual: out.len(),
            });
        }
        if let Some(index) = out.iter().position(|x| !x.is_finite()) {
            return Err(KinematicsError::MappingNonFinite {
                group: self.name.clone(),
                direction,
                index,
            });
        }
        Ok(())
    }
}

fn first_duplicate(names: &[String]) -> Option<&str> {
    names
        .iter()
        .enumerate()
        .find(|(i, n)| names[..*i].contains(n))
        .map(|(_, n)| n.as_str())
}

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FrameId, forward_kinematics, update_frame_placements};
    use kinetree_model::{FrameSpec, JointLimits, JointSpec, Link, ModelBuilder};
    use std::f64::consts::FRAC_PI_6;

    /// A thigh with a knee 1 m up, axis z, limits ±1.2 rad, and a foot frame 0.5 m along the shank.
    fn leg() -> Model {
        let mut b = ModelBuilder::new("leg");
        b.add_link(Link::new("thigh"));
        b.add_part(
            Link::new("shank"),
            JointSpec::new("knee", JointKind::Revolute, "thigh", "shank")
                .with_placement(Se3::from_translation(DVec3::new(0.0, 0.0, 1.0)))
                .with_limits(JointLimits::position(-1.2, 1.2)),
        );
        b.add_frame(FrameSpec::new(
            "foot",
            "shank",
            Se3::from_translation(DVec3::new(0.5, 0.0, 0.0)),
        ));
        b.build().unwrap()
    }

    const PARENT_ANCHOR: DVec3 = DVec3::new(0.0, -0.4, 1.0);
    const CHILD_ANCHOR: DVec3 = DVec3::new(0.1, 0.0, 0.0);

    fn knee_group(model: &Model) -> ActuationGroup {
        let actuator = LinearActuator::new(model, "knee", PARENT_ANCHOR, CHILD_ANCHOR).unwrap();
        let spec = GroupSpec::new("knee_drive", ["knee_actuator"], ["knee"], [0.42]);
        ActuationGroup::new(model, spec, actuator).unwrap()
    }

    #[test]
    fn linear_actuator_matches_the_law_of_cosines_by_hand() {
        let model = leg();
        let act = LinearActuator::new(&model, "knee", PARENT_ANCHOR, CHILD_ANCHOR).unwrap();
        // In the knee frame the anchors are (0, -0.4, 0) and (0.1, 0, 0): radii 0.4 and 0.1, no
        // axial offset, β = 90°, so s² = 0.17 − 0.08·cos(θ + 90°) = 0.17 + 0.08·sin θ.
        for theta in [-1.2, -0.5, 0.0, FRAC_PI_6, 1.1] {
            let by_hand = (0.17 + 0.08 * f64::sin(theta)).sqrt();
            assert!((act.length(theta) - by_hand).abs() < 1e-15, "θ = {theta}");
            // And back: θ = asin((s² − 0.17) / 0.08).
            assert!((act.angle(by_hand) - theta).abs() < 1e-12, "θ = {theta}");
        }
        let (lo, hi) = act.length_range();
        assert!((lo - 0.3).abs() < 1e-15 && (hi - 0.5).abs() < 1e-15);
        assert!(act.angle(0.29).is_nan() && act.angle(0.51).is_nan());
    }

    #[test]
    fn linear_actuator_round_trips_and_drives_forward_kinematics() {
        let model = leg();
        let mut leg =
            ActuatedChain::new(Chain::new(model.clone()), vec![knee_group(&model)]).unwrap();
        assert_eq!(leg.actuator_names(), ["knee_actuator"]);
        // The group starts at its probe length.
        assert!((leg.actuated_state()[0] - 0.42).abs() < 1e-15);

        // Round trip actuated → virtual → actuated over the working stroke.
        let group = &leg.groups()[0];
        let mut v = Vec::new();
        let mut back = Vec::new();
        for k in 0..=20 {
            let s = 0.32 + 0.16 * f64::from(k) / 20.0;
            group.map.to_virtual(&[s], &mut v);
            group.map.to_actuated(&v, &mut back);
            assert!((back[0] - s).abs() < 1e-12, "s = {s}");
            v.clear();
            back.clear();
        }

        // 0.21 m² gives 30°: the foot is 0.5 m along a shank turned 30° about z, 1 m up.
        leg.set_actuated("knee_actuator", 0.21f64.sqrt()).unwrap();
        assert!((leg.chain().joint_value("knee").unwrap() - FRAC_PI_6).abs() < 1e-12);
        let foot = leg.world_from("foot").unwrap();
        let by_hand = DVec3::new(0.5 * FRAC_PI_6.cos(), 0.5 * FRAC_PI_6.sin(), 1.0);
        assert!((foot.translation - by_hand).length() < 1e-12);
        assert!(foot.abs_diff_eq(
            &Se3::new(Se3::from_rotation_z(FRAC_PI_6).rotation, by_hand),
            1e-12,
            1e-12
        ));
        // The anchors, placed by forward kinematics, are exactly one stroke apart.
        let shank = leg.world_from("shank").unwrap();
        let gap = shank.transform_point(CHILD_ANCHOR) - PARENT_ANCHOR;
        assert!((gap.length() - 0.21f64.sqrt()).abs() < 1e-12);

        // Setting the joint moves the actuator: at -30°, s² = 0.17 − 0.04.
        leg.set_joint_value("knee", -FRAC_PI_6).unwrap();
        assert!((leg.actuated("knee_actuator").unwrap() - 0.13f64.sqrt()).abs() < 1e-12);

        // A stroke the mechanism cannot reach is an error and changes nothing.
        let err = leg.set_actuated("knee_actuator", 0.6).unwrap_err();
        assert!(matches!(
            err,
            KinematicsError::MappingNonFinite { ref group, direction: MappingDirection::ActuatedToVirtual, index: 0 }
                if group == "knee_drive"
        ));
        assert!((leg.actuated("knee_actuator").unwrap() - 0.13f64.sqrt()).abs() < 1e-12);
        assert!((leg.chain().joint_value("knee").unwrap() + FRAC_PI_6).abs() < 1e-12);
    }

    #[test]
    fn linear_actuator_length_is_the_anchor_distance_in_a_general_geometry() {
        // A tilted joint with an oblique axis and anchors off the pivot plane.
        let mut b = ModelBuilder::new("arm");
        b.add_link(Link::new("base"));
        b.add_part(
            Link::new("arm"),
            JointSpec::new("elbow", JointKind::Revolute, "base", "arm")
                .with_placement(Se3::from_xyz_rpy([0.2, -0.1, 0.5], [0.3, -0.2, 0.7]))
                .with_axis(DVec3::new(0.2, 0.3, 0.9))
                .with_limits(JointLimits::position(-0.8, 0.6)),
        );
        let model = b.build().unwrap();
        let (pa, ca) = (DVec3::new(0.1, 0.3, 0.2), DVec3::new(0.25, -0.05, 0.12));
        let act = LinearActuator::new(&model, "elbow", pa, ca).unwrap();
        let mut data = KinematicsData::new(&model);
        let arm = FrameId::find(&model, "arm").unwrap();
        for k in 0..=10 {
            let theta = -0.8 + 1.4 * f64::from(k) / 10.0;
            forward_kinematics(&model, &mut data, &[theta]).unwrap();
            let distance = (data.world_from(arm).unwrap().transform_point(ca) - pa).length();
            assert!((act.length(theta) - distance).abs() < 1e-12, "θ = {theta}");
            assert!((act.angle(distance) - theta).abs() < 1e-9, "θ = {theta}");
        }
    }

    #[test]
    fn linear_actuator_rejects_bad_geometry() {
        let model = leg();
        assert!(matches!(
            LinearActuator::new(&model, "hip", PARENT_ANCHOR, CHILD_ANCHOR),
            Err(KinematicsError::UnknownJoint { name }) if name == "hip"
        ));
        // The child anchor on the knee axis.
        assert!(matches!(
            LinearActuator::new(&model, "knee", PARENT_ANCHOR, DVec3::new(0.0, 0.0, 0.3)),
            Err(KinematicsError::InvalidJointValue { joint, .. }) if joint == "knee"
        ));
        // In line with the pivot at θ = 0, the middle of the range.
        assert!(matches!(
            LinearActuator::new(&model, "knee", DVec3::new(-0.4, 0.0, 1.0), CHILD_ANCHOR),
            Err(KinematicsError::InvalidJointValue { joint, .. }) if joint == "knee"
        ));
        let mut b = ModelBuilder::new("slider");
        b.add_link(Link::new("a"));
        b.add_part(
            Link::new("b"),
            JointSpec::new("s", JointKind::Prismatic, "a", "b"),
        );
        assert!(matches!(
            LinearActuator::new(&b.build().unwrap(), "s", PARENT_ANCHOR, CHILD_ANCHOR),
            Err(KinematicsError::WrongJointKind {
                kind: JointKind::Prismatic,
                ..
            })
        ));
    }

    /// A forearm, a pitch joint (y) and a roll joint (x), then a finger on a prismatic joint.
    fn wrist() -> Model {
        let mut b = ModelBuilder::new("wrist");
        b.add_link(Link::new("forearm"));
        b.add_part(
            Link::new("yoke"),
            JointSpec::new("pitch", JointKind::Revolute, "forearm", "yoke").with_axis(DVec3::Y),
        );
        b.add_part(
            Link::new("hand"),
            JointSpec::new("roll", JointKind::Revolute, "yoke", "hand")
                .with_axis(DVec3::X)
                .with_placement(Se3::from_translation(DVec3::new(0.05, 0.0, 0.0))),
        );
        b.add_part(
            Link::new("finger"),
            JointSpec::new("grip", JointKind::Prismatic, "hand", "finger").with_axis(DVec3::Y),
        );
        b.build().unwrap()
    }

    /// Bevel differential with a 2:1 output: pitch = (a + b) / 4, roll = (a − b) / 4.
    fn differential() -> impl Actuation {
        FnActuation::new(
            |m: &[f64], j: &mut Vec<f64>| j.extend([(m[0] + m[1]) / 4.0, (m[0] - m[1]) / 4.0]),
            |j: &[f64], m: &mut Vec<f64>| m.extend([2.0 * (j[0] + j[1]), 2.0 * (j[0] - j[1])]),
        )
    }

    #[test]
    fn differential_couples_two_motors_to_pitch_and_roll() {
        let model = wrist();
        let spec = GroupSpec::new(
            "wrist",
            ["motor_a", "motor_b"],
            ["pitch", "roll"],
            [0.0, 0.0],
        );
        let group = ActuationGroup::new(&model, spec, differential()).unwrap();
        let mut robot = ActuatedChain::new(Chain::new(model.clone()), vec![group]).unwrap();
        // The union: the group's motors, then the directly driven grip.
        assert_eq!(robot.actuator_names(), ["motor_a", "motor_b", "grip"]);

        robot.set_actuated_state(&[1.0, 0.2, 0.01]).unwrap();
        let chain = robot.chain();
        assert!((chain.joint_value("pitch").unwrap() - 0.3).abs() < 1e-15);
        assert!((chain.joint_value("roll").unwrap() - 0.2).abs() < 1e-15);
        assert!((chain.joint_value("grip").unwrap() - 0.01).abs() < 1e-15);

        // Equal motor motion pitches only.
        robot.set_actuated("motor_b", 1.0).unwrap();
        assert!((robot.chain().joint_value("pitch").unwrap() - 0.5).abs() < 1e-15);
        assert!(robot.chain().joint_value("roll").unwrap().abs() < 1e-15);

        // Setting a virtual joint keeps the group's other joint and moves both motors.
        robot.set_joint_value("roll", 0.1).unwrap();
        assert!((robot.chain().joint_value("pitch").unwrap() - 0.5).abs() < 1e-15);
        let state = robot.actuated_state();
        assert!((state[0] - 1.2).abs() < 1e-15 && (state[1] - 0.8).abs() < 1e-15);

        // The hand pose equals a full forward kinematics at pitch 0.5, roll 0.1.
        let mut data = KinematicsData::new(&model);
        forward_kinematics(&model, &mut data, &[0.5, 0.1, 0.01]).unwrap();
        update_frame_placements(&model, &mut data).unwrap();
        let hand = robot.world_from("hand").unwrap();
        let full = data
            .world_from(FrameId::find(&model, "hand").unwrap())
            .unwrap();
        assert!(hand.abs_diff_eq(full, 1e-15, 1e-15));
        let by_hand = Se3::from_rotation_y(0.5)
            * Se3::from_translation(DVec3::new(0.05, 0.0, 0.0))
            * Se3::from_rotation_x(0.1);
        assert!(hand.abs_diff_eq(&by_hand, 1e-15, 1e-15));

        // Unknown names and wrong sizes are errors that change nothing.
        assert!(matches!(
            robot.set_actuated("motor_c", 0.0),
            Err(KinematicsError::UnknownActuator { name }) if name == "motor_c"
        ));
        assert!(matches!(
            robot.set_actuated_state(&[0.0, 0.0]),
            Err(KinematicsError::DimensionMismatch {
                expected: 3,
                actual: 2,
                ..
            })
        ));
        assert!((robot.actuated("motor_a").unwrap() - 1.2).abs() < 1e-15);
    }

    #[test]
    fn construction_reports_bad_mappings() {
        let model = wrist();
        let spec = || GroupSpec::new("wrist", ["a", "b"], ["pitch", "roll"], [0.3, -0.1]);

        // actuated → virtual writes one value for two joints.
        let short = FnActuation::new(
            |m: &[f64], j: &mut Vec<f64>| j.push(m[0]),
            |j: &[f64], m: &mut Vec<f64>| m.extend([j[0], j[0]]),
        );
        let err = ActuationGroup::new(&model, spec(), short).unwrap_err();
        assert!(matches!(
            err,
            KinematicsError::MappingSize { ref group, direction: MappingDirection::ActuatedToVirtual, expected: 2, actual: 1 }
                if group == "wrist"
        ));

        // virtual → actuated writes three values for two actuators.
        let long = FnActuation::new(
            |m: &[f64], j: &mut Vec<f64>| j.extend_from_slice(m),
            |j: &[f64], m: &mut Vec<f64>| m.extend([j[0], j[1], 0.0]),
        );
        let err = ActuationGroup::new(&model, spec(), long).unwrap_err();
        assert!(matches!(
            err,
            KinematicsError::MappingSize {
                direction: MappingDirection::VirtualToActuated,
                expected: 2,
                actual: 3,
                ..
            }
        ));

        // The inverse forgets the gear ratio: not a round trip.
        let inconsistent = FnActuation::new(
            |m: &[f64], j: &mut Vec<f64>| j.extend([(m[0] + m[1]) / 4.0, (m[0] - m[1]) / 4.0]),
            |j: &[f64], m: &mut Vec<f64>| m.extend([j[0] + j[1], j[0] - j[1]]),
        );
        let err = ActuationGroup::new(&model, spec(), inconsistent).unwrap_err();
        match err {
            KinematicsError::MappingInconsistent {
                group,
                actuator,
                probe,
                round_trip,
                ..
            } => {
                assert_eq!((group.as_str(), actuator.as_str()), ("wrist", "a"));
                assert!((probe - 0.3).abs() < 1e-15 && (round_trip - 0.15).abs() < 1e-15);
            }
            other => panic!("unexpected {other}"),
        }

        // NaN at the probe.
        let nan = FnActuation::new(
            |m: &[f64], j: &mut Vec<f64>| j.extend([m[0], m[1].ln()]),
            |j: &[f64], m: &mut Vec<f64>| m.extend([j[0], j[1].exp()]),
        );
        assert!(matches!(
            ActuationGroup::new(&model, spec(), nan),
            Err(KinematicsError::MappingNonFinite { index: 1, .. })
        ));

        // Ill-defined groups.
        let ok = || differential();
        let bad_specs = [
            GroupSpec::new("g", Vec::<String>::new(), ["pitch"], Vec::new()),
            GroupSpec::new("g", ["a", "a"], ["pitch", "roll"], [0.0, 0.0]),
            GroupSpec::new("g", ["a", "b"], ["pitch", "pitch"], [0.0, 0.0]),
            spec().with_tolerance(-1.0),
        ];
        for s in bad_specs {
            assert!(matches!(
                ActuationGroup::new(&model, s, ok()),
                Err(KinematicsError::InvalidGroup { .. })
            ));
        }
        assert!(matches!(
            ActuationGroup::new(&model, GroupSpec::new("g", ["a", "b"], ["pitch", "yaw"], [0.0, 0.0]), ok()),
            Err(KinematicsError::UnknownJoint { name }) if name == "yaw"
        ));
        assert!(matches!(
            ActuationGroup::new(
                &model,
                GroupSpec::new("g", ["a", "b"], ["pitch", "roll"], [0.0]),
                ok()
            ),
            Err(KinematicsError::DimensionMismatch { what: "probe", .. })
        ));
    }

    #[test]
    fn groups_must_not_overlap() {
        let model = wrist();
        let make = |name: &str, actuators: [&str; 2]| {
            ActuationGroup::new(
                &model,
                GroupSpec::new(name, actuators, ["pitch", "roll"], [0.0, 0.0]),
                differential(),
            )
            .unwrap()
        };
        let err = ActuatedChain::new(
            Chain::new(model.clone()),
            vec![make("first", ["a", "b"]), make("second", ["c", "d"])],
        )
        .unwrap_err();
        assert!(matches!(
            err,
            KinematicsError::InvalidGroup { ref group, problem: GroupProblem::JointAlreadyDriven { ref joint, ref by } }
                if group == "second" && joint == "pitch" && by == "first"
        ));
        // An actuator named like a directly driven joint.
        let err = ActuatedChain::new(Chain::new(model.clone()), vec![make("w", ["grip", "b"])])
            .unwrap_err();
        assert!(matches!(err, KinematicsError::InvalidGroup { ref group, .. } if group == "w"));
        // A group built for another model.
        let other = leg();
        let err = ActuatedChain::new(Chain::new(other), vec![make("w", ["a", "b"])]).unwrap_err();
        assert!(matches!(
            err,
            KinematicsError::InvalidGroup {
                problem: GroupProblem::OtherModel,
                ..
            }
        ));
    }

    #[test]
    fn chains_and_groups_can_move_between_threads() {
        fn send_sync<T: Send + Sync>() {}
        send_sync::<Chain>();
        send_sync::<ActuationGroup>();
        send_sync::<ActuatedChain>();
    }

    #[test]
    fn group_state_stays_consistent_both_ways() {
        let model = wrist();
        let spec = GroupSpec::new("wrist", ["a", "b"], ["pitch", "roll"], [0.4, 0.0]);
        let mut group = ActuationGroup::new(&model, spec, differential()).unwrap();
        let close = |a: &[f64], b: &[f64]| {
            assert!(
                a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-15),
                "{a:?} != {b:?}"
            );
        };
        close(group.virtual_q(), &[0.1, 0.1]);
        group.set_virtual_q(&[0.2, -0.1]).unwrap();
        close(group.actuated(), &[0.2, 0.6]);
        group.set_actuator("b", 0.2).unwrap();
        close(group.virtual_q(), &[0.1, 0.0]);
        group.set_joint_q("roll", &[0.05]).unwrap();
        close(group.actuated(), &[0.3, 0.1]);
        let mut q = vec![9.0; model.nq()];
        group.write_q(&mut q).unwrap();
        close(&q, &[0.1, 0.05, 9.0]);
        assert!(matches!(
            group.set_actuated(&[f64::NAN, 0.0]),
            Err(KinematicsError::NonFinite {
                what: "actuated",
                index: 0
            })
        ));
        assert!(matches!(
            group.write_q(&mut [0.0; 2]),
            Err(KinematicsError::DimensionMismatch { .. })
        ));
    }
}
