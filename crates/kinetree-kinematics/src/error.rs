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
