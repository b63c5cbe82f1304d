//! [`IkParams`]: the tolerances, budgets and damping of the inverse-kinematics solver.

use std::time::Duration;

/// The most targets a solver is sized for: [`IkParams::max_targets`] is capped here. The
/// solver's dense buffers grow with the square of six rows per target (256 targets: about
/// 19 MB), and a request for 10⁹ would abort on the allocation.
pub const MAX_TARGETS: usize = 256;

/// Settings of an [`IkSolver`](super::IkSolver), fixed when it is built.
///
/// The defaults solve 6- and 7-DoF arms from random starts to 1 µm and 10 µrad (see
/// `cargo xtask ik-report`); each field documents its default.
///
/// # Examples
/// ```
/// use kinetree_kinematics::ik::IkParams;
/// use std::time::Duration;
/// // Looser tolerances and a 1 ms budget, for a real-time loop.
/// let params = IkParams {
///     position_tolerance: 1e-4,
///     orientation_tolerance: 1e-3,
///     time_budget: Some(Duration::from_millis(1)),
///     ..IkParams::default()
/// };
/// assert_eq!(params.seed, IkParams::default().seed);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct IkParams {
    /// Success threshold on the position error of every target (m): the norm of the components of
    /// `frame position - target position` (in target axes) whose weight is non-zero.
    /// Default 1e-6.
    pub position_tolerance: f64,
    /// Success threshold on the orientation error of every target (rad): the norm of the
    /// components of `log(R_targetᵀ R)` whose weight is non-zero (with every angular weight
    /// non-zero, the angle between the two orientations). Default 1e-5.
    pub orientation_tolerance: f64,
    /// Total number of steps over every try (each step costs one forward kinematics).
    /// Default 10 000.
    pub max_iterations: usize,
    /// Steps before a try is abandoned and the solver restarts from a new configuration.
    /// Default 60.
    pub max_iterations_per_try: usize,
    /// Restarts after the first try; `0` makes the solver a plain local method from `q0`.
    /// Default `usize::MAX` (the iteration and time budgets decide).
    pub max_restarts: usize,
    /// Wall-clock budget of one solve, checked between steps; `None` for no limit (then the result
    /// depends only on the inputs and [`seed`](Self::seed)). Default 5 ms.
    pub time_budget: Option<Duration>,
    /// Seed of the random restarts. Each solve reseeds the generator, so a solve is reproducible
    /// (unless the time budget runs out first). Default 0.
    pub seed: u64,
    /// Most targets one solve may take (the solver's buffers are sized for them). Default 4;
    /// the solver uses at least 1 and at most [`MAX_TARGETS`].
    pub max_targets: usize,
    /// How much one radian of orientation error counts against one metre of position error in
    /// the minimised cost (metres per radian), on top of each target's weights. It changes the
    /// path to a reachable target (not where it ends), and the compromise for an unreachable one.
    /// Default 0.35, about a third of a 1-metre arm's reach, which shortens the solves of 6- and
    /// 7-DoF arms by a sixth compared with 1.
    pub orientation_weight: f64,
    /// Levenberg–Marquardt damping relative to the error: the damping added to `JᵀJ` is
    /// `λ = μ · (|r| + damping_floor)`, `|r|` the weighted residual norm (Fan and Yuan's choice,
    /// which keeps the final convergence quadratic), with `μ` starting at this value and adapted
    /// by the gain ratio of each step (down when the error model predicts the step well, up when
    /// a step is rejected). Default 0.1.
    pub damping: f64,
    /// Error-independent part of the damping (keeps `JᵀJ + λI` well conditioned at
    /// singularities; small enough not to slow the final quadratic convergence). Default 1e-9.
    pub damping_floor: f64,
    /// Largest change of any velocity coordinate in one step (rad or m); longer steps are scaled
    /// down. Default 1.0.
    pub max_step: f64,
    /// A try is abandoned when `patience` consecutive accepted steps each reduce the squared error
    /// by less than this fraction (a local minimum or a slow crawl along a limit): from a random
    /// start a try either converges quickly or not at all, and a fresh start is cheaper than a
    /// crawl. Default 0.2.
    pub min_progress: f64,
    /// See [`min_progress`](Self::min_progress). Default 2.
    pub patience: usize,
}

impl Default for IkParams {
    fn default() -> Self {
        Self {
            position_tolerance: 1e-6,
            orientation_tolerance: 1e-5,
            max_iterations: 10_000,
            max_iterations_per_try: 60,
            max_restarts: usize::MAX,
            time_budget: Some(Duration::from_millis(5)),
            seed: 0,
            max_targets: 4,
            orientation_weight: 0.35,
            damping: 0.1,
            damping_floor: 1e-9,
            max_step: 1.0,
            min_progress: 0.2,
            patience: 2,
        }
    }
}
