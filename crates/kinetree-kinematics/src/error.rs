//! The kinematics layer's error type.

use core::fmt;
use kinetree_model::{Model, ModelError};

/// How far from 1 the norm of a configuration's quaternion (spherical and floating joints) may
/// be: within it the quaternion is normalized, beyond it the configuration is refused with
/// [`KinematicsError::NonUnitQuaternion`].
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

/// Everything that can go wrong in the kinematics layer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum KinematicsError {
    /// An error from the model layer.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An input vector or output buffer has the wrong length.
    #[error("{what} has length {actual}, expected {expected}")]
    DimensionMismatch {
        /// Which input (`"q"`, `"v"`, `"a"`, `"jacobian"`, …).
        what: &'static str,
        /// The required length.
        expected: usize,
        /// The length given.
        actual: usize,
    },
    /// An input contains NaN or an infinity.
    #[error("{what}[{index}] is not finite")]
    NonFinite {
        /// Which input.
        what: &'static str,
        /// The first offending index.
        index: usize,
    },
    /// A spherical or floating joint's quaternion in a configuration is further than
    /// [`QUATERNION_NORM_TOLERANCE`] from unit norm (or zero); within the tolerance it is
    /// normalized.
    #[error(
        "joint '{joint}': the quaternion has norm {}, not 1 (accepted within {QUATERNION_NORM_TOLERANCE:e}; normalize it first)",
        kinetree_model::spatial::Readable(*norm)
    )]
    NonUnitQuaternion {
        /// The joint.
        joint: String,
        /// The quaternion's norm.
        norm: f64,
    },
    /// A result overflowed: every input is finite, but a placement or velocity is not (joint
    /// values, lengths or velocities too large for `f64` arithmetic). Never a non-finite value in
    /// an `Ok`.
    #[error(
        "the {what} of body '{body}' overflowed although every input is finite: the joint values, velocities or the model's lengths are too large"
    )]
    Overflow {
        /// `"placement"`, `"velocity"`, `"acceleration"` or `"configuration"` (of
        /// [`integrate`](crate::configuration::integrate) and
        /// [`interpolate`](crate::configuration::interpolate)).
        what: &'static str,
        /// The first body (named by its link) whose result is not finite.
        body: String,
    },
    /// A name for the function [`crate::codegen::generate`] writes that the target language
    /// cannot use (see [`crate::codegen::check_name`]).
    #[error("'{name}' cannot name the generated {lang} function: {reason}")]
    InvalidCodegenName {
        /// The name as given.
        name: String,
        /// The target language.
        lang: &'static str,
        /// Why not.
        reason: &'static str,
    },
    /// A state of a batch (see [`crate::batch`]) failed: `index` is the state's position in the
    /// batch and `source` says what was wrong with it.
    #[error("state {index} of the batch: {source}")]
    InBatchState {
        /// The state's index in the batch (0-based).
        index: usize,
        /// What went wrong with that state.
        #[source]
        source: Box<KinematicsError>,
    },
    /// A data object was created for a different model.
    #[error(
        "the data was created for a model with {data_bodies} bodies and nv = {data_nv}, not this one ({model_bodies} bodies, nv = {model_nv})"
    )]
    DataMismatch {
        /// Bodies of the data's model.
        data_bodies: usize,
        /// nv of the data's model.
        data_nv: usize,
        /// Bodies of the model passed in.
        model_bodies: usize,
        /// nv of the model passed in.
        model_nv: usize,
    },
    /// Several links carry a frame of this name: it must be given as `link/frame`.
    #[error("'{name}' is ambiguous: {} links have a frame of that name; give one of {}", .candidates.len(), .candidates.join(", "))]
    AmbiguousFrame {
        /// The name as given.
        name: String,
        /// Each frame of that name as `link/frame`.
        candidates: Vec<String>,
    },
    /// No link or frame has this name.
    #[error("unknown link or frame '{name}'")]
    UnknownFrame {
        /// The name looked up.
        name: String,
    },
    /// A link or frame index the model does not have.
    #[error("{what} index {index} is out of range (the model has {count})")]
    FrameOutOfRange {
        /// `"link"` or `"frame"` (named frame).
        what: &'static str,
        /// The index given.
        index: usize,
        /// The number of links (for a link) or named frames (for a frame) of the model.
        count: usize,
    },
    /// No joint has this name.
    #[error("unknown joint '{name}'")]
    UnknownJoint {
        /// The name looked up.
        name: String,
    },
    /// A joint exists but cannot be used this way (e.g. a scalar value for a floating joint).
    #[error("joint '{joint}': {reason}")]
    InvalidJointValue {
        /// The joint.
        joint: String,
        /// Why.
        reason: String,
    },
    /// A vector given by joint name leaves out a moving joint that must be named.
    #[error("'{space}' has no value for joint '{joint}'")]
    MissingJointValue {
        /// The joint left out.
        joint: String,
        /// `"q"` (configuration) or `"v"` (velocity-space vector).
        space: &'static str,
    },
    /// No link (part) has this name.
    #[error("unknown link '{name}'")]
    UnknownLink {
        /// The name looked up.
        name: String,
    },
    /// A joint has the wrong kind for the operation (e.g. degrees for a prismatic joint).
    #[error("joint '{joint}' is {kind}, expected {expected}")]
    WrongJointKind {
        /// The joint.
        joint: String,
        /// Its kind.
        kind: kinetree_model::JointKind,
        /// What the operation accepts.
        expected: &'static str,
    },
    /// An actuation group is ill-defined (no actuators, duplicate names, a joint in two groups…).
    #[error("actuation group '{group}': {problem}")]
    InvalidGroup {
        /// The group.
        group: String,
        /// What is wrong with it.
        problem: GroupProblem,
    },
    /// An actuation group's mapping wrote the wrong number of values.
    #[error(
        "actuation group '{group}': the {direction} mapping wrote {actual} value(s), expected {expected}"
    )]
    MappingSize {
        /// The group.
        group: String,
        /// Which mapping.
        direction: MappingDirection,
        /// The number of values the other side has.
        expected: usize,
        /// The number written.
        actual: usize,
    },
    /// An actuation group's mapping produced NaN or an infinity (its input is outside its domain).
    #[error("actuation group '{group}': the {direction} mapping gave a non-finite value {index}")]
    MappingNonFinite {
        /// The group.
        group: String,
        /// Which mapping.
        direction: MappingDirection,
        /// The first offending output index.
        index: usize,
    },
    /// An actuation group's mappings are not inverses at the probe point.
    #[error(
        "actuation group '{group}': actuator '{actuator}' = {probe} comes back as {round_trip} through virtual and back (tolerance {tolerance})"
    )]
    MappingInconsistent {
        /// The group.
        group: String,
        /// The first actuated coordinate that does not come back.
        actuator: String,
        /// Its value at the probe point.
        probe: f64,
        /// The value after actuated → virtual → actuated.
        round_trip: f64,
        /// The tolerance it missed.
        tolerance: f64,
    },
    /// No actuated coordinate has this name.
    #[error("unknown actuator '{name}'")]
    UnknownActuator {
        /// The name looked up.
        name: String,
    },
    /// An inverse-kinematics target cannot be used (see [`crate::ik::IkTarget`]).
    #[error("ik target {index}: {reason}")]
    InvalidTarget {
        /// The target's index in the list given to the solver.
        index: usize,
        /// Why.
        reason: &'static str,
    },
}

/// Which of an actuation group's two mappings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MappingDirection {
    /// Actuated coordinates → virtual joint coordinates
    /// ([`Actuation::to_virtual`](crate::Actuation::to_virtual)).
    ActuatedToVirtual,
    /// Virtual joint coordinates → actuated coordinates
    /// ([`Actuation::to_actuated`](crate::Actuation::to_actuated)).
    VirtualToActuated,
}

impl fmt::Display for MappingDirection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::ActuatedToVirtual => "actuated → virtual",
            Self::VirtualToActuated => "virtual → actuated",
        })
    }
}

/// What makes an actuation group ill-defined ([`KinematicsError::InvalidGroup`]).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum GroupProblem {
    /// The group lists no actuated coordinates.
    NoActuators,
    /// An actuated coordinate is listed twice.
    DuplicateActuator {
        /// Its name.
        actuator: String,
    },
    /// The group lists no joints.
    NoJoints,
    /// A joint is listed twice.
    DuplicateJoint {
        /// Its name.
        joint: String,
    },
    /// The round-trip tolerance is negative or not finite.
    InvalidTolerance {
        /// The tolerance given.
        tolerance: f64,
    },
    /// Two groups of an actuated chain have the same name.
    DuplicateGroup,
    /// The group was built for another model than the chain's.
    OtherModel,
    /// A joint of the group is already driven by an earlier group.
    JointAlreadyDriven {
        /// The joint.
        joint: String,
        /// The group that drives it first.
        by: String,
    },
    /// An actuated coordinate name is used twice in an actuated chain (by two groups, or by a
    /// group and a directly driven joint).
    DuplicateCoordinate {
        /// The name.
        name: String,
    },
}

impl fmt::Display for GroupProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoActuators => f.write_str("no actuated coordinates"),
            Self::DuplicateActuator { actuator } => {
                write!(f, "actuator '{actuator}' is listed twice")
            }
            Self::NoJoints => f.write_str("no joints"),
            Self::DuplicateJoint { joint } => write!(f, "joint '{joint}' is listed twice"),
            Self::InvalidTolerance { tolerance } => {
                write!(
                    f,
                    "tolerance {tolerance} is not a finite non-negative number"
                )
            }
            Self::DuplicateGroup => f.write_str("two groups have this name"),
            Self::OtherModel => f.write_str("it was built for another model"),
            Self::JointAlreadyDriven { joint, by } => {
                write!(f, "joint '{joint}' is already driven by group '{by}'")
            }
            Self::DuplicateCoordinate { name } => {
                write!(f, "actuated coordinate name '{name}' is used twice")
            }
        }
    }
}

/// Checks the length and finiteness of an input vector.
pub(crate) fn check_vector(
    what: &'static str,
    x: &[f64],
    expected: usize,
) -> Result<(), KinematicsError> {
    if x.len() != expected {
        return Err(KinematicsError::DimensionMismatch {
            what,
            expected,
            actual: x.len(),
        });
    }
    if let Some(index) = first_non_finite(x) {
        return Err(KinematicsError::NonFinite { what, index });
    }
    Ok(())
}

/// The index of the first entry of `x` that is not finite. The usual all-finite case is one
/// branch-free pass that the compiler vectorises; only a failure searches for the index.
#[inline]
pub(crate) fn first_non_finite(x: &[f64]) -> Option<usize> {
    if x.iter().fold(true, |ok, v| ok & v.is_finite()) {
        None
    } else {
        x.iter().position(|v| !v.is_finite())
    }
}

/// Checks a configuration: its length, finiteness, and that every quaternion's norm is within
/// [`QUATERNION_NORM_TOLERANCE`] of 1. Allocates nothing unless it fails.
pub(crate) fn check_q(model: &Model, what: &'static str, q: &[f64]) -> Result<(), KinematicsError> {
    check_vector(what, q, model.nq())?;
    for &(body, start) in model.quaternion_blocks() {
        let norm = quaternion_norm(&q[start..start + 4]);
        if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
            // Named as users name it (a composite joint by its own name, not its piece's).
            let joint = model.bodies()[body].joint.map_or_else(
                || "root".to_string(),
                |j| model.user_joints()[model.user_joint_of(j)].name.clone(),
            );
            return Err(KinematicsError::NonUnitQuaternion { joint, norm });
        }
    }
    Ok(())
}

/// The Euclidean norm of a stored quaternion, scaled first so that huge components do not
/// overflow the sum of squares.
pub(crate) fn quaternion_norm(x: &[f64]) -> f64 {
    let m = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if m > 0.0 && m.is_finite() {
        m * x.iter().map(|v| (v / m) * (v / m)).sum::<f64>().sqrt()
    } else {
        m
    }
}
