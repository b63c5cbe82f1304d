//! [`IkReport`] and [`IkStatus`]: how a solve went; [`IkIterate`]: one step, for observers.

use std::time::Duration;

/// The outcome of an inverse-kinematics solve. Not converging is a status, not an error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IkStatus {
    /// Every target is within the position and orientation tolerances.
    Converged,
    /// The budget ran out first; `q` is the best configuration met (smallest weighted residual),
    /// and it improves on the start.
    BestEffort {
        /// The weighted residual norm `|r|` at `q` (see [`IkTarget`](super::IkTarget)).
        residual: f64,
    },
    /// Nothing improved on the start configuration (no budget at all, or no selected joint moves
    /// the targets); `q` is the start, clamped into the limits.
    Failed,
}

/// What an [`IkSolver`](super::IkSolver) solve found.
///
/// `q` borrows the solver's buffer (no allocation per solve); copy it with `report.q.to_vec()` to
/// keep it past the next solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkReport<'a> {
    /// Converged, best effort or failed.
    pub status: IkStatus,
    /// Steps taken over every try (each costs one forward kinematics).
    pub iterations: usize,
    /// Tries after the first one.
    pub restarts: usize,
    /// Largest position error over the targets (m), at `q` (see
    /// [`IkParams::position_tolerance`](super::IkParams::position_tolerance)).
    pub position_error: f64,
    /// Largest orientation error over the targets (rad), at `q`.
    pub orientation_error: f64,
    /// Wall-clock time of the solve, validation included.
    pub elapsed: Duration,
    /// The configuration found (length `model.nq()`): within the joint limits, quaternions
    /// normalised, continuous joints wrapped to (-π, π]; joints that were not allowed to move keep
    /// their value from `q0`.
    pub q: &'a [f64],
}

impl IkReport<'_> {
    /// Whether the solve converged.
    #[must_use]
    pub fn is_converged(&self) -> bool {
        self.status == IkStatus::Converged
    }
}

/// One configuration the solver visited, passed to an observer (see
/// [`IkSolver::set_observer`](super::IkSolver::set_observer)): the start of every try and every
/// accepted step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkIterate<'a> {
    /// The try (0 for the first).
    pub attempt: usize,
    /// Steps taken so far in this try (0 at its start).
    pub iteration: usize,
    /// The configuration (length `model.nq()`), always within the joint limits.
    pub q: &'a [f64],
    /// Largest position error over the targets (m).
    pub position_error: f64,
    /// Largest orientation error over the targets (rad).
    pub orientation_error: f64,
}
