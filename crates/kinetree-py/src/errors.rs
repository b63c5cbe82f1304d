//! The Python exceptions: `KinetreeError` (a `ValueError`: every error kinetree raises is about
//! its input) and one subclass per error family of the Rust crates.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    kinetree,
    KinetreeError,
    PyValueError,
    "Base class of every kinetree error; a ValueError, since each names an input at fault."
);
create_exception!(
    kinetree,
    ModelError,
    KinetreeError,
    "Loading or building a model failed (bad file, bad XML/JSON, invalid tree, bad DH row)."
);
create_exception!(
    kinetree,
    KinematicsError,
    KinetreeError,
    "A kinematics call rejected its input (array shape, NaN/inf, unknown frame or joint)."
);
create_exception!(
    kinetree,
    DynamicsError,
    KinetreeError,
    "A dynamics call rejected its input (array shape, NaN/inf, singular mass matrix)."
);
create_exception!(
    kinetree,
    CollisionError,
    KinetreeError,
    "Building a collision model or a collision query failed (missing mesh, bad SRDF, unknown link)."
);
create_exception!(
    kinetree,
    IkError,
    KinetreeError,
    "An inverse-kinematics request was malformed (unknown frame, bad target or parameters)."
);

/// Which exception class an error raised from a call belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Family {
    /// [`ModelError`].
    Model,
    /// [`KinematicsError`].
    Kinematics,
    /// [`DynamicsError`].
    Dynamics,
    /// [`CollisionError`].
    Collision,
    /// [`IkError`].
    Ik,
}

impl Family {
    /// The exception of this family with `message`.
    pub(crate) fn err(self, message: impl Into<String>) -> PyErr {
        let message = message.into();
        match self {
            Family::Model => ModelError::new_err(message),
            Family::Kinematics => KinematicsError::new_err(message),
            Family::Dynamics => DynamicsError::new_err(message),
            Family::Collision => CollisionError::new_err(message),
            Family::Ik => IkError::new_err(message),
        }
    }
}

/// The exception for a kinetree error: the class of its layer, or `IkError` for any error of an
/// IK call.
pub(crate) fn to_py(error: &kinetree::Error, ik: bool) -> PyErr {
    let family = if ik { Family::Ik } else { family_of(error) };
    family.err(error.to_string())
}

/// The family of a kinetree error: its layer.
pub(crate) fn family_of(error: &kinetree::Error) -> Family {
    use kinetree::Error as E;
    match error {
        E::Model(_) => Family::Model,
        E::Dynamics(_) => Family::Dynamics,
        E::Collision(_) => Family::Collision,
        _ => Family::Kinematics,
    }
}

/// Converts any layer's error into a Python exception of its family.
pub(crate) fn py_err<E: Into<kinetree::Error>>(error: E) -> PyErr {
    to_py(&error.into(), false)
}

/// Adds the exception classes to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("KinetreeError", py.get_type::<KinetreeError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("KinematicsError", py.get_type::<KinematicsError>())?;
    m.add("DynamicsError", py.get_type::<DynamicsError>())?;
    m.add("CollisionError", py.get_type::<CollisionError>())?;
    m.add("IkError", py.get_type::<IkError>())?;
    Ok(())
}
