//! [`IkSolver`]: Levenberg–Marquardt on the SE(3) log error with box constraints, random restarts
//! and a null-space posture objective.
//!
//! One step, for the stacked residual `r(q)` of every target (see [`IkTarget`]) and its Jacobian
//! `J` (exact: the frame Jacobian mapped through the inverse left Jacobian of SO(3)):
//!
//! 1. `(JᵀJ + λI) δ = Jᵀ(-r - J z)`, `dq = z + δ`, where `z` is the posture step (zero without a
//!    posture). With `λ → 0` this is the Gauss–Newton step plus `z` projected on the null space of
//!    `J`. `λ = μ (|r| + λ₀)`: large far from the target, vanishing at it, so the last steps
//!    converge quadratically. When `J` has fewer rows `m` than free columns `n` (a redundant arm,
//!    several targets on a humanoid) the same `δ` is computed as `Jᵀ(JJᵀ + λI)⁻¹(-r - J z)`, an
//!    `m x m` system instead of `n x n`.
//! 2. Box constraints: a coordinate at a limit that steepest descent pushes outwards is frozen,
//!    and so is any whose step still points outwards (the system is solved again without it: an
//!    active set); the remaining step is projected into the limits. Every iterate therefore
//!    satisfies the limits.
//! 3. `q ⊕ dq` on each joint's manifold ([`integrate_joint`]), so quaternions stay unit.
//! 4. The step is kept if it lowers `½|r|²`; `μ` follows the ratio of the actual to the predicted
//!    decrease (Nielsen's rule). A try ends on convergence, after
//!    [`IkParams::max_iterations_per_try`] steps, or when it stalls; the next try starts from a
//!    seed, `q0`, then random configurations of the moving joints.

use super::analytic::IkSeeder;
use super::params::{IkParams, MAX_TARGETS};
use super::report::{IkIterate, IkReport, IkStatus};
use super::target::IkTarget;
use crate::configuration::{sampling_range, wrap_angle};
use crate::data::KinematicsData;
use crate::error::{KinematicsError, check_vector};
use crate::forward::{forward_kinematics, update_frame_placements};
use crate::joint::JointModel;
use glam::DQuat;
use kinetree_model::spatial::rotation::{is_rotation, orthonormalize};
use kinetree_model::spatial::{Motion, RotationForm};
use kinetree_model::{JointKind, Model};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use std::f64::consts::PI;
use std::fmt;
use std::time::Instant;

use super::scratch::{COLUMN_GENERAL, DofBound, Eval, PathBody, TargetState, Workspace};
use super::step::{MU_MAX, MU_MIN, clamp_moving, step, within_limits};

/// The largest target coordinate (m) or weight the solver takes: squared weighted residuals
/// of larger values can overflow.
const MAX_TARGET_MAGNITUDE: f64 = 1e50;

/// A boxed iterate observer (see [`IkSolver::set_observer`]).
type Observer = Box<dyn FnMut(&IkIterate<'_>) + Send>;

/// The inverse-kinematics solver: built once per model, it owns every buffer, so a solve
/// allocates nothing.
///
/// See the [module docs](super) for the method and an example. By default only the joints on the
/// paths from the root to the target frames move ([`set_moving_joints`](Self::set_moving_joints)
/// narrows that); every iterate respects the position limits of the moving joints.
pub struct IkSolver {
    params: IkParams,
    nq: usize,
    nv: usize,
    nbodies: usize,
    nlinks: usize,
    nframes: usize,
    /// Per body: whether its joint may move.
    allowed: Vec<bool>,
    /// Per velocity coordinate: the limits of the coordinate it drives.
    bounds: Vec<DofBound>,
    /// Per velocity coordinate: its joint's motion subspace column (body frame).
    axes: Vec<Motion>,
    posture: Vec<f64>,
    posture_gain: f64,
    rng: SmallRng,
    seeder: Option<Box<dyn IkSeeder + Send>>,
    observer: Option<Observer>,
    ws: Workspace,
}

impl fmt::Debug for IkSolver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("IkSolver")
            .field("params", &self.params)
            .field("nq", &self.nq)
            .field("nv", &self.nv)
            .field("posture_gain", &self.posture_gain)
            .field("has_seeder", &self.seeder.is_some())
            .field("has_observer", &self.observer.is_some())
            .finish_non_exhaustive()
    }
}

impl IkSolver {
    /// A solver for `model` with `params`; allocates every buffer a solve needs (for up to
    /// `params.max_targets` targets, at least 1 and at most [`MAX_TARGETS`]: the parameters kept
    /// say which).
    #[must_use]
    pub fn new(model: &Model, mut params: IkParams) -> Self {
        params.max_targets = params.max_targets.clamp(1, MAX_TARGETS);
        let mut bounds = vec![
            DofBound {
                q: 0,
                lower: f64::NEG_INFINITY,
                upper: f64::INFINITY,
            };
            model.nv()
        ];
        for b in model.bodies().iter().skip(1) {
            let Some(j) = b.joint else { continue };
            let lim = &model.joint(j).limits;
            // Placeholder limits (lower == upper, as some URDFs write for unlimited joints) are
            // treated as no limits, as the random sampling does.
            if b.kind.has_position_limits() && lim.lower < lim.upper {
                for k in 0..b.nv {
                    bounds[b.idx_v + k] = DofBound {
                        q: b.idx_q + k,
                        lower: lim.lower,
                        upper: lim.upper,
                    };
                }
            }
        }
        let mut axes = vec![Motion::ZERO; model.nv()];
        for b in model.bodies().iter().skip(1) {
            let joint = JointModel::from_body(b);
            for k in 0..b.nv {
                axes[b.idx_v + k] = joint.subspace_column(k);
            }
        }
        Self {
            axes,
            nq: model.nq(),
            nv: model.nv(),
            nbodies: model.nbodies(),
            nlinks: model.links().len(),
            nframes: model.frames().len(),
            allowed: vec![true; model.nbodies()],
            bounds,
            posture: vec![0.0; model.nq()],
            posture_gain: 0.0,
            rng: SmallRng::seed_from_u64(params.seed),
            seeder: None,
            observer: None,
            ws: Workspace::new(model.nq(), model.nv(), model.nbodies(), params.max_targets),
            params,
        }
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &IkParams {
        &self.params
    }

    /// Replaces the parameters (reallocates the buffers when `max_targets` changes).
    pub fn set_params(&mut self, mut params: IkParams) {
        params.max_targets = params.max_targets.clamp(1, MAX_TARGETS);
        if params.max_targets != self.params.max_targets {
            self.ws = Workspace::new(self.nq, self.nv, self.nbodies, params.max_targets);
        }
        self.params = params;
    }

    /// Lets only the named joints move (always further restricted to the joints on the paths to
    /// the targets). Names of fixed joints are accepted and ignored; a coupled mimic follower
    /// moves with its leader, so name the leader.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`] for a name that is not a joint of `model`;
    /// [`KinematicsError::DataMismatch`] when `model` is not the solver's model.
    pub fn set_moving_joints<S: AsRef<str>>(
        &mut self,
        model: &Model,
        joints: &[S],
    ) -> Result<(), KinematicsError> {
        self.check_model(model)?;
        let mut allowed = vec![false; model.nbodies()];
        for name in joints {
            let name = name.as_ref();
            let j = model
                .joint_index(name)
                .ok_or_else(|| KinematicsError::UnknownJoint {
                    name: name.to_string(),
                })?;
            if let Some(b) = model.joint_body(j) {
                allowed[b] = true;
            }
        }
        self.allowed = allowed;
        Ok(())
    }

    /// Lets every joint on the paths to the targets move again (the default).
    pub fn move_all_joints(&mut self) {
        self.allowed.fill(true);
    }

    /// Sets a posture objective: each step also moves the configuration a fraction `gain` (per
    /// step, in `[0, 1]`) of the way towards `q_posture` (length `model.nq()`), in the null space
    /// of the targets. Among the many solutions of a redundant arm this picks one near the
    /// posture; it never prevents convergence.
    ///
    /// # Errors
    /// [`KinematicsError::DimensionMismatch`] / [`KinematicsError::NonFinite`] for a bad
    /// `q_posture` or `gain`; [`KinematicsError::DataMismatch`] for another model.
    pub fn set_posture(
        &mut self,
        model: &Model,
        q_posture: &[f64],
        gain: f64,
    ) -> Result<(), KinematicsError> {
        self.check_model(model)?;
        check_vector("q_posture", q_posture, self.nq)?;
        crate::error::check_q(model, "q_posture", q_posture)?;
        if !gain.is_finite() {
            return Err(KinematicsError::NonFinite {
                what: "posture gain",
                index: 0,
            });
        }
        let mut posture = q_posture.to_vec();
        crate::configuration::normalize(model, &mut posture)?;
        self.posture.copy_from_slice(&posture);
        self.posture_gain = gain.clamp(0.0, 1.0);
        Ok(())
    }

    /// Removes the posture objective.
    pub fn clear_posture(&mut self) {
        self.posture_gain = 0.0;
    }

    /// Installs a seeder (e.g. an analytic solver) whose configurations are tried first (see
    /// [`IkSeeder`]).
    pub fn set_seeder(&mut self, seeder: impl IkSeeder + Send + 'static) {
        self.seeder = Some(Box::new(seeder));
    }

    /// Removes the seeder.
    pub fn clear_seeder(&mut self) {
        self.seeder = None;
    }

    /// Installs an observer, called with the start of every try and every accepted step (for
    /// debugging, plotting or progress). Without one, nothing is called.
    pub fn set_observer(&mut self, observer: impl FnMut(&IkIterate<'_>) + Send + 'static) {
        self.observer = Some(Box::new(observer));
    }

    /// Removes the observer.
    pub fn clear_observer(&mut self) {
        self.observer = None;
    }

    fn check_model(&self, model: &Model) -> Result<(), KinematicsError> {
        if model.nq() != self.nq
            || model.nv() != self.nv
            || model.nbodies() != self.nbodies
            || model.links().len() != self.nlinks
            || model.frames().len() != self.nframes
        {
            return Err(KinematicsError::DataMismatch {
                data_bodies: self.nbodies,
                data_nv: self.nv,
                model_bodies: model.nbodies(),
                model_nv: model.nv(),
            });
        }
        Ok(())
    }

    /// Solves for one target from `q0` (length `model.nq()`). See
    /// [`solve_targets`](Self::solve_targets).
    ///
    /// # Errors
    /// As [`solve_targets`](Self::solve_targets).
    pub fn solve(
        &mut self,
        model: &Model,
        data: &mut KinematicsData,
        target: &IkTarget,
        q0: &[f64],
    ) -> Result<IkReport<'_>, KinematicsError> {
        self.solve_targets(model, data, std::slice::from_ref(target), q0)
    }

    /// Finds a configuration that puts every target's frame on its pose, starting from `q0`
    /// (length `model.nq()`), within the parameters' budgets. Allocates nothing.
    ///
    /// `q0` is normalised (quaternions) and clamped into the limits of the moving joints; joints
    /// that do not move keep their `q0` value. On return `data` holds the forward kinematics (and
    /// frame placements) of `report.q`. Not converging is reported in
    /// [`IkReport::status`], not as an error.
    ///
    /// # Errors
    /// - [`KinematicsError::DimensionMismatch`] / [`KinematicsError::NonFinite`]: `q0` has the
    ///   wrong length or a NaN; more targets than [`IkParams::max_targets`]; a target pose or
    ///   weight is not finite.
    /// - [`KinematicsError::FrameOutOfRange`]: a target's frame is not in `model`.
    /// - [`KinematicsError::InvalidTarget`]: no target, a target rotation that is not a rotation
    ///   matrix, a negative weight, every weight zero, or a position coordinate or weight above
    ///   1e50 (its squared residual would overflow).
    /// - [`KinematicsError::DataMismatch`]: `model` or `data` is not the solver's model.
    pub fn solve_targets(
        &mut self,
        model: &Model,
        data: &mut KinematicsData,
        targets: &[IkTarget],
        q0: &[f64],
    ) -> Result<IkReport<'_>, KinematicsError> {
        let started = Instant::now();
        self.check_model(model)?;
        data.check_model(model)?;
        check_vector("q0", q0, self.nq)?;
        crate::error::check_q(model, "q0", q0)?;
        self.prepare(model, targets)?;
        let Self {
            params,
            bounds,
            posture,
            posture_gain,
            rng,
            seeder,
            observer,
            ws,
            ..
        } = self;
        let params = &*params;
        ws.q_start.copy_from_slice(q0);
        crate::configuration::normalize(model, &mut ws.q_start)?;
        clamp_moving(bounds, &ws.dofs, &mut ws.q_start);
        *rng = SmallRng::seed_from_u64(params.seed);
        let deadline = params
            .time_budget
            .and_then(|budget| started.checked_add(budget));
        let posture = (*posture_gain > 0.0).then_some((&posture[..], *posture_gain));

        let mut total = 0usize;
        let mut attempt = 0usize;
        let mut seed_index = 0usize;
        let mut seeding = seeder.is_some();
        let mut q0_used = false;
        let mut best = Eval::WORST;
        let mut first = Eval::WORST;
        let mut converged = false;
        loop {
            // The start of this try: the next seed, then q0, then a random configuration.
            ws.q_trial.copy_from_slice(&ws.q_start);
            let mut chosen = false;
            if seeding {
                if let Some(s) = seeder.as_mut()
                    && s.seed(model, targets, seed_index, &mut ws.q_trial)
                {
                    seed_index += 1;
                    let usable = ws.q_trial.len() == ws.q_start.len()
                        && ws.q_trial.iter().all(|x| x.is_finite())
                        && crate::configuration::normalize(model, &mut ws.q_trial).is_ok();
                    if usable {
                        clamp_moving(bounds, &ws.dofs, &mut ws.q_trial);
                    } else {
                        ws.q_trial.copy_from_slice(&ws.q_start);
                    }
                    chosen = true;
                } else {
                    seeding = false;
                    ws.q_trial.copy_from_slice(&ws.q_start);
                }
            }
            if !chosen {
                if q0_used {
                    random_start(model, &ws.moving, rng, &mut ws.q_trial);
                } else {
                    q0_used = true;
                }
            }
            let mut cur = ws.evaluate(model, data);
            ws.accept();
            debug_assert!(within_limits(bounds, &ws.dofs, &ws.q));
            if attempt == 0 {
                first = cur;
            }
            if cur.e < best.e {
                best = cur;
                ws.q_best.copy_from_slice(&ws.q);
            }
            if let Some(obs) = observer.as_mut() {
                obs(&IkIterate {
                    attempt,
                    iteration: 0,
                    q: &ws.q,
                    position_error: cur.pos,
                    orientation_error: cur.ori,
                });
            }
            if cur.converged(params) {
                converged = true;
                break;
            }
            let mut out_of_budget = ws.dofs.is_empty();
            let mut mu = params.damping;
            let mut nu = 2.0;
            let mut slow = 0usize;
            let mut it = 0usize;
            let mut linearized = false;
            while !out_of_budget {
                if total >= params.max_iterations {
                    out_of_budget = true;
                    break;
                }
                if it >= params.max_iterations_per_try {
                    break;
                }
                if total.is_multiple_of(4)
                    && let Some(d) = deadline
                    && Instant::now() >= d
                {
                    out_of_budget = true;
                    break;
                }
                if !linearized {
                    ws.linearize(model, data);
                    linearized = true;
                }
                let lambda = mu * ((2.0 * cur.e).sqrt() + params.damping_floor);
                it += 1;
                total += 1;
                let Some(predicted) = step(ws, model, bounds, params, lambda, posture) else {
                    // Not numerically positive definite: damp more.
                    mu *= 10.0;
                    if mu > MU_MAX {
                        break;
                    }
                    continue;
                };
                let trial = ws.evaluate(model, data);
                if trial.e < cur.e {
                    let rho = if predicted > 0.0 {
                        (cur.e - trial.e) / predicted
                    } else {
                        1.0
                    };
                    let f = 1.0 - (2.0 * rho - 1.0).powi(3);
                    mu = (mu * f.max(1.0 / 3.0)).max(MU_MIN);
                    nu = 2.0;
                    if trial.e > (1.0 - params.min_progress) * cur.e {
                        slow += 1;
                    } else {
                        slow = 0;
                    }
                    ws.accept();
                    debug_assert!(within_limits(bounds, &ws.dofs, &ws.q));
                    cur = trial;
                    linearized = false;
                    if cur.e < best.e {
                        best = cur;
                        ws.q_best.copy_from_slice(&ws.q);
                    }
                    if let Some(obs) = observer.as_mut() {
                        obs(&IkIterate {
                            attempt,
                            iteration: it,
                            q: &ws.q,
                            position_error: cur.pos,
                            orientation_error: cur.ori,
                        });
                    }
                    if cur.converged(params) {
                        converged = true;
                        break;
                    }
                    if slow >= params.patience {
                        break;
                    }
                } else {
                    mu *= nu;
                    nu *= 2.0;
                    if mu > MU_MAX {
                        break;
                    }
                }
            }
            if converged || out_of_budget || attempt >= params.max_restarts {
                break;
            }
            if let Some(d) = deadline
                && Instant::now() >= d
            {
                break;
            }
            attempt += 1;
        }

        // Continuous joints read better in (-π, π]; the pose does not change.
        for &b in &ws.moving {
            let body = &model.bodies()[b];
            if body.kind == JointKind::Continuous {
                ws.q_best[body.idx_q] = wrap_angle(ws.q_best[body.idx_q]);
            }
        }
        forward_kinematics(model, data, &ws.q_best)?;
        update_frame_placements(model, data)?;
        let status = if converged {
            IkStatus::Converged
        } else if best.e < first.e {
            IkStatus::BestEffort {
                residual: (2.0 * best.e).sqrt(),
            }
        } else {
            IkStatus::Failed
        };
        Ok(IkReport {
            status,
            iterations: total,
            restarts: attempt,
            position_error: best.pos,
            orientation_error: best.ori,
            elapsed: started.elapsed(),
            q: &ws.q_best,
        })
    }

    /// Validates the targets and prepares the per-solve structure: target rows, the bodies to
    /// sweep and the moving coordinates.
    fn prepare(&mut self, model: &Model, targets: &[IkTarget]) -> Result<(), KinematicsError> {
        let ws = &mut self.ws;
        if targets.is_empty() {
            return Err(KinematicsError::InvalidTarget {
                index: 0,
                reason: "no target given",
            });
        }
        if targets.len() > self.params.max_targets {
            return Err(KinematicsError::DimensionMismatch {
                what: "targets (IkParams::max_targets)",
                expected: self.params.max_targets,
                actual: targets.len(),
            });
        }
        ws.marked.fill(false);
        let bodies = model.bodies();
        let mut m = 0;
        for (index, t) in targets.iter().enumerate() {
            t.frame.check(model)?;
            if !t.pose.is_finite() {
                return Err(KinematicsError::NonFinite {
                    what: "target pose",
                    index,
                });
            }
            if t.weights.iter().any(|w| !w.is_finite()) {
                return Err(KinematicsError::NonFinite {
                    what: "target weights",
                    index,
                });
            }
            if t.weights.iter().any(|w| *w < 0.0) {
                return Err(KinematicsError::InvalidTarget {
                    index,
                    reason: "a weight is negative",
                });
            }
            // Squared weighted residuals of larger values overflow, so the errors reported
            // would be infinite or NaN.
            if t.pose.translation.abs().max_element() > MAX_TARGET_MAGNITUDE {
                return Err(KinematicsError::InvalidTarget {
                    index,
                    reason: "the position is farther than 1e50 m from the origin",
                });
            }
            if t.weights.iter().any(|w| *w > MAX_TARGET_MAGNITUDE) {
                return Err(KinematicsError::InvalidTarget {
                    index,
                    reason: "a weight is above 1e50",
                });
            }
            if !is_rotation(&t.pose.rotation, 1e-6) {
                return Err(KinematicsError::InvalidTarget {
                    index,
                    reason: "the pose's rotation is not a rotation matrix",
                });
            }
            let (body, body_from_frame) = t.frame.body(model)?;
            let mut s = TargetState {
                body,
                body_from_frame,
                rot_t: orthonormalize(&t.pose.rotation).transpose(),
                position: t.pose.translation,
                weights: t.weights,
                offset: m,
                ..TargetState::EMPTY
            };
            for (a, w) in t.weights.iter().enumerate() {
                if *w != 0.0 {
                    s.rows[s.nrows] = a;
                    s.nrows += 1;
                }
                if a >= 3 {
                    s.weights[a] *= self.params.orientation_weight;
                }
            }
            if s.nrows == 0 {
                return Err(KinematicsError::InvalidTarget {
                    index,
                    reason: "every weight is zero",
                });
            }
            m += s.nrows;
            ws.targets[index] = s;
            let mut b = body;
            while b != 0 && !ws.marked[b] {
                ws.marked[b] = true;
                b = bodies[b].parent;
            }
        }
        ws.ntargets = targets.len();
        ws.m = m;
        ws.path.clear();
        ws.moving.clear();
        ws.dofs.clear();
        ws.dof_body.clear();
        ws.dof_axis.clear();
        ws.dof_kind.clear();
        ws.dof_q.clear();
        ws.additive = true;
        ws.followers.clear();
        // The coordinates that move a target: those of the marked bodies, and the leaders of
        // marked coupled mimic followers.
        ws.owner.copy_from_slice(&ws.marked);
        for (i, b) in bodies.iter().enumerate().skip(1) {
            if ws.marked[i]
                && let Some(mimic) = &b.mimic
                && let Some(leader) = model.joint_body(mimic.leader)
            {
                ws.owner[leader] = true;
            }
        }
        for (i, b) in bodies.iter().enumerate().skip(1) {
            let joint = JointModel::from_body(b);
            if ws.marked[i] {
                let axis = match joint.axis_index() {
                    Some((k, true)) if b.parent != 0 && b.mimic.is_none() => k as u8,
                    _ => 3,
                };
                ws.path.push(PathBody {
                    body: i,
                    parent: b.parent,
                    qi: b.idx_q,
                    axis,
                    place: RotationForm::classify(&b.placement.rotation),
                });
            }
            if ws.owner[i] && self.allowed[i] && b.nv > 0 {
                ws.moving.push(i);
                let additive = matches!(
                    b.kind,
                    JointKind::Revolute
                        | JointKind::Continuous
                        | JointKind::Prismatic
                        | JointKind::Cylindrical
                ) && b.nq == b.nv;
                ws.additive &= additive;
                let kind = match joint.axis_index() {
                    Some((k, true)) => k as u8,
                    Some((k, false)) => 3 + k as u8,
                    None => COLUMN_GENERAL,
                };
                for k in 0..b.nv {
                    ws.dofs.push(b.idx_v + k);
                    ws.dof_body.push(i);
                    ws.dof_axis.push(self.axes[b.idx_v + k]);
                    ws.dof_kind
                        .push(if b.nv == 1 { kind } else { COLUMN_GENERAL });
                    ws.dof_q.push(b.idx_q + k);
                }
            }
        }
        for (i, b) in bodies.iter().enumerate().skip(1) {
            if ws.marked[i]
                && let Some(mimic) = &b.mimic
                && let Some(c) = ws.dofs.iter().position(|&d| d == b.idx_v)
            {
                ws.followers.push((i, c, mimic.multiplier));
            }
        }
        Ok(())
    }
}

/// Draws a random start for the moving joints: uniform within the limits (a 2π window for
/// angles with wider limits, [-π, π] for continuous joints), uniform rotations for spherical
/// joints; planar and floating joints keep their value.
fn random_start(model: &Model, moving: &[usize], rng: &mut SmallRng, q: &mut [f64]) {
    let bodies = model.bodies();
    for &b in moving {
        let body = &bodies[b];
        let lim = &model.joint(body.joint.unwrap_or(0)).limits;
        let qi = &mut q[body.idx_q..body.idx_q + body.nq];
        match body.kind {
            JointKind::Revolute | JointKind::Continuous | JointKind::Prismatic => {
                qi[0] = sample(body.kind, lim.lower, lim.upper, rng);
            }
            JointKind::Cylindrical => {
                qi[0] = sample(JointKind::Prismatic, lim.lower, lim.upper, rng);
                qi[1] = sample(JointKind::Revolute, lim.lower, lim.upper, rng);
            }
            JointKind::Spherical => qi.copy_from_slice(&random_quat(rng).to_array()),
            JointKind::Fixed | JointKind::Planar | JointKind::Floating => {}
        }
    }
}

fn sample(kind: JointKind, lower: f64, upper: f64, rng: &mut SmallRng) -> f64 {
    let (mut lo, mut hi) = sampling_range(kind, lower, upper);
    if kind != JointKind::Prismatic && hi - lo > 2.0 * PI {
        let c = 0.0f64.clamp(lo + PI, hi - PI);
        (lo, hi) = (c - PI, c + PI);
    }
    lo + (hi - lo) * rng.random::<f64>()
}

/// Shoemake's uniform unit quaternion.
fn random_quat(rng: &mut SmallRng) -> DQuat {
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let (t2, t3) = (2.0 * PI * u2, 2.0 * PI * u3);
    DQuat::from_xyzw(a * t2.sin(), a * t2.cos(), b * t3.sin(), b * t3.cos())
}
