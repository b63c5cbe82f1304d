//! The dynamics layer's error type.

use kinetree_kinematics::KinematicsError;

/// Everything that can go wrong in the dynamics layer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// An error from the kinematics layer (or, through it, the model layer).
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
    /// An input vector or output buffer has the wrong length.
    #[error("{what} has length {actual}, expected {expected}")]
    DimensionMismatch {
        /// Which input (`"q"`, `"v"`, `"a"`, `"tau"`, `"rhs"`, …).
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
    /// A result overflowed: every input is finite, but the computation produced an infinity or
    /// NaN (velocities, masses, lengths or torques too large for `f64` arithmetic). Never a
    /// non-finite value in an `Ok`.
    #[error(
        "{what} overflowed{} (got {}) although every input is finite: the state or the model's masses, inertias or lengths are too large",
        if joint.is_empty() { String::new() } else { format!(" at joint '{joint}'") },
        kinetree_kinematics::spatial::Readable(*value)
    )]
    Overflow {
        /// The result that overflowed (`"tau"`, `"ddq"`, `"mass matrix"`, `"v"` …).
        what: &'static str,
        /// The joint of the first non-finite entry (empty when no joint applies).
        joint: String,
        /// The non-finite value.
        value: f64,
    },
    /// A state of a batch (see [`crate::batch`]) failed: `index` is the state's position in the
    /// batch and `source` says what was wrong with it.
    #[error("state {index} of the batch: {source}")]
    InBatchState {
        /// The state's index in the batch (0-based).
        index: usize,
        /// What went wrong with that state.
        #[source]
        source: Box<DynamicsError>,
    },
    /// A data object (or an [`ExternalForces`](crate::ExternalForces)) was created for a different
    /// model.
    #[error(
        "the {what} was created for a model with {data_bodies} bodies and nv = {data_nv}, not this one ({model_bodies} bodies, nv = {model_nv})"
    )]
    DataMismatch {
        /// `"data"` or `"external forces"`.
        what: &'static str,
        /// Bodies (or links, for external forces) of the data's model.
        data_bodies: usize,
        /// nv (or named frames, for external forces) of the data's model.
        data_nv: usize,
        /// Bodies (or links) of the model passed in.
        model_bodies: usize,
        /// nv (or named frames) of the model passed in.
        model_nv: usize,
    },
    /// The joint-space mass matrix is singular (not positive definite): the named joints move no
    /// mass or inertia along some direction, typically because everything they carry is
    /// massless (e.g. inertia-free finger links). Forward dynamics is undefined there.
    #[error("the mass matrix is singular: joint(s) {} move no mass (massless subtree)", .joints.join(", "))]
    SingularMassMatrix {
        /// The joints whose pivots vanished, in body order.
        joints: Vec<String>,
    },
    /// The mass matrix is singular to `f64` precision although the named joints carry mass:
    /// links are so far from the origin (a state that has run away, or lengths far beyond any
    /// robot) or masses and inertias so different that the articulated inertias lose every
    /// significant digit.
    #[error(
        "the mass matrix is numerically singular at joint(s) {}: they carry mass, but links are {:.1e} m from the origin and masses and inertias range from {:.1e} to {:.1e} (kg, kg·m²), beyond what f64 arithmetic resolves (a diverging state, or absurd lengths, masses or inertias)",
        .joints.join(", "),
        .reach,
        .masses[0],
        .masses[1]
    )]
    IllConditionedMassMatrix {
        /// The joints whose pivots vanished although their subtrees have mass, in body order.
        joints: Vec<String>,
        /// The largest distance of a link origin from the world origin, in metres.
        reach: f64,
        /// The smallest positive and the largest body mass or rotational inertia (diagonal
        /// entry about the centre of mass), in kg and kg·m².
        masses: [f64; 2],
    },
    /// No link or frame has this name.
    #[error("unknown link or frame '{name}'")]
    UnknownLink {
        /// The name looked up.
        name: String,
    },
    /// A link or frame index is out of range.
    #[error("{what} index {index} is out of range (the model has {count})")]
    IndexOutOfRange {
        /// `"link"` or `"frame"`.
        what: &'static str,
        /// The index given.
        index: usize,
        /// How many the model has.
        count: usize,
    },
    /// The centre of mass is undefined: no moving body carries mass.
    #[error("the centre of mass is undefined: the moving bodies carry no mass")]
    ZeroMass,
    /// [`solve_mass_matrix`](crate::solve_mass_matrix) was called before a successful
    /// [`factorize_mass_matrix`](crate::factorize_mass_matrix).
    #[error("the mass matrix has not been factorized (call factorize_mass_matrix first)")]
    NotFactorized,
    /// A time step that is not positive and finite.
    #[error("time step {} is not positive and finite", kinetree_kinematics::spatial::Readable(*dt))]
    InvalidTimeStep {
        /// The step given (s).
        dt: f64,
    },
    /// The model has coupled mimic joints ([`MimicMode::Coupled`]), which the dynamics algorithms
    /// do not support yet: load it with independent mimic joints (the default).
    ///
    /// [`MimicMode::Coupled`]: kinetree_kinematics::model::MimicMode::Coupled
    #[error(
        "joint '{joint}' is a coupled mimic joint; the dynamics algorithms need mimic joints loaded as independent DoFs"
    )]
    CoupledMimic {
        /// A coupled mimic joint of the model.
        joint: String,
    },
}

/// Checks the length and finiteness of an input vector.
pub(crate) fn check_vector(
    what: &'static str,
    x: &[f64],
    expected: usize,
) -> Result<(), DynamicsError> {
    check_len(what, x, expected)?;
    // A finite sum proves every entry finite in fewer instructions than testing each entry.
    if sum_is_finite(x) {
        return Ok(());
    }
    if let Some(index) = first_non_finite(x) {
        return Err(DynamicsError::NonFinite { what, index });
    }
    Ok(())
}

/// The index of the first entry of `x` that is not finite. The usual all-finite case is one
/// branch-free pass that the compiler vectorises (a mass matrix has `nv²` entries); only a
/// failure searches for the index.
#[inline]
pub(crate) fn first_non_finite(x: &[f64]) -> Option<usize> {
    if x.iter().fold(true, |ok, v| ok & v.is_finite()) {
        None
    } else {
        x.iter().position(|v| !v.is_finite())
    }
}

/// Checks the length of a vector or buffer.
pub(crate) fn check_len(
    what: &'static str,
    x: &[f64],
    expected: usize,
) -> Result<(), DynamicsError> {
    if x.len() != expected {
        return Err(DynamicsError::DimensionMismatch {
            what,
            expected,
            actual: x.len(),
        });
    }
    Ok(())
}

/// Checks that a result is finite; `x` is a vector over the degrees of freedom or a matrix
/// stored row after row (its entry `k` belongs to the degree of freedom `k % nv`).
pub(crate) fn check_output(
    model: &kinetree_kinematics::model::Model,
    data: &crate::DynamicsData,
    what: &'static str,
    x: &[f64],
) -> Result<(), DynamicsError> {
    if sum_is_finite(x) {
        return Ok(());
    }
    match first_non_finite(x) {
        None => Ok(()),
        Some(k) => Err(overflow(model, data, what, k % model.nv().max(1), x[k])),
    }
}

/// Whether the sum of `x` is finite, summed in eight independent lanes (a few vector additions
/// per eight entries, no dependency chain). A finite sum proves every entry finite; a sum that
/// is not finite comes from a bad entry or from finite entries whose sum overflows, which
/// [`first_non_finite`] tells apart.
#[inline]
pub(crate) fn sum_is_finite(x: &[f64]) -> bool {
    let mut acc = [0.0f64; 8];
    let mut chunks = x.chunks_exact(8);
    for c in &mut chunks {
        for (a, v) in acc.iter_mut().zip(c) {
            *a += v;
        }
    }
    for (a, v) in acc.iter_mut().zip(chunks.remainder()) {
        *a += v;
    }
    acc.iter().sum::<f64>().is_finite()
}

/// [`DynamicsError::Overflow`] at degree of freedom `dof`.
pub(crate) fn overflow(
    model: &kinetree_kinematics::model::Model,
    data: &crate::DynamicsData,
    what: &'static str,
    dof: usize,
    value: f64,
) -> DynamicsError {
    let joint = if dof < model.nv() {
        data.joint_names(model, &[dof]).pop().unwrap_or_default()
    } else {
        String::new()
    };
    DynamicsError::Overflow { what, joint, value }
}
