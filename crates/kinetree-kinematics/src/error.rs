//! The kinematics layer's error type.

use kinetree_model::ModelError;

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
    /// No link or frame has this name.
    #[error("unknown link or frame '{name}'")]
    UnknownFrame {
        /// The name looked up.
        name: String,
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
    #[error("actuation group '{group}': {reason}")]
    InvalidGroup {
        /// The group.
        group: String,
        /// Why.
        reason: String,
    },
    /// An actuation group's mapping wrote the wrong number of values.
    #[error(
        "actuation group '{group}': the {direction} mapping wrote {actual} value(s), expected {expected}"
    )]
    MappingSize {
        /// The group.
        group: String,
        /// Which mapping.
        direction: crate::group::MappingDirection,
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
        direction: crate::group::MappingDirection,
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
    if let Some(index) = x.iter().position(|v| !v.is_finite()) {
        return Err(KinematicsError::NonFinite { what, index });
    }
    Ok(())
}
