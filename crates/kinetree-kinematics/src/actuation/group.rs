//! [`ActuationGroup`]: one group of actuated coordinates and the joints its mappings drive.

use super::*;
use crate::error::{GroupProblem, KinematicsError, check_vector};
use core::fmt;
use core::ops::Range;
use kinetree_model::Model;

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
    pub(super) name: String,
    pub(super) actuators: Vec<String>,
    pub(super) joints: Vec<usize>,
    pub(super) joint_names: Vec<String>,
    /// Per joint: its block in the model's `q` and where it starts in `virtual_q`.
    pub(super) blocks: Vec<(Range<usize>, usize)>,
    pub(super) model_nq: usize,
    pub(super) map: Box<dyn Actuation>,
    pub(super) actuated: Vec<f64>,
    pub(super) virtual_q: Vec<f64>,
    pub(super) scratch: Vec<f64>,
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
    pub(super) fn checked_to_virtual(
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
