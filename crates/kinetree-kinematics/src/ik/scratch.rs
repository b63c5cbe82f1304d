//! The scratch buffers of an [`IkSolver`](super::IkSolver) solve, allocated once by
//! `IkSolver::new`: per-coordinate bounds, per-target state and the [`Workspace`].

use super::params::IkParams;
use glam::{DMat3, DVec3};
use kinetree_model::spatial::{Motion, RotationForm, Se3};

/// The limits of the configuration coordinate a velocity coordinate drives (infinite when none).
#[derive(Clone, Copy, Debug)]
pub(super) struct DofBound {
    pub(super) q: usize,
    pub(super) lower: f64,
    pub(super) upper: f64,
}

impl DofBound {
    #[inline]
    pub(super) fn is_bounded(&self) -> bool {
        self.lower > f64::NEG_INFINITY || self.upper < f64::INFINITY
    }
}

/// One target, prepared for a solve, and what the last evaluation found for it.
#[derive(Clone, Copy, Debug)]
pub(super) struct TargetState {
    pub(super) body: usize,
    pub(super) body_from_frame: Se3,
    /// `target_R_world`.
    pub(super) rot_t: DMat3,
    pub(super) position: DVec3,
    pub(super) weights: [f64; 6],
    /// The components with a non-zero weight, and where their rows start in `r`.
    pub(super) rows: [usize; 6],
    pub(super) nrows: usize,
    pub(super) offset: usize,
    /// From the last evaluation: the frame origin (world) and `log(R_targetᵀ R)`.
    pub(super) frame_position: DVec3,
    pub(super) phi: DVec3,
    /// `J_l⁻¹(phi) · target_R_world`: world angular velocity to `d(phi)/dt`.
    pub(super) ang_map: DMat3,
}

impl TargetState {
    pub(super) const EMPTY: Self = Self {
        body: 0,
        body_from_frame: Se3::IDENTITY,
        rot_t: DMat3::IDENTITY,
        position: DVec3::ZERO,
        weights: [0.0; 6],
        rows: [0; 6],
        nrows: 0,
        offset: 0,
        frame_position: DVec3::ZERO,
        phi: DVec3::ZERO,
        ang_map: DMat3::IDENTITY,
    };
}

/// How the residual's forward pass places one body of the path.
#[derive(Clone, Copy, Debug)]
pub(super) struct PathBody {
    pub(super) body: usize,
    pub(super) parent: usize,
    /// Its configuration coordinate (when `axis < 3`).
    pub(super) qi: usize,
    /// 0, 1, 2: a revolute joint about that coordinate axis, not a mimic, under another body,
    /// placed as `world_from_parent · placement · R_axis(q)` with the placement rotation in
    /// `place`; 3: any other joint (its general transform).
    pub(super) axis: u8,
    pub(super) place: RotationForm,
}

/// How a moving velocity coordinate's Jacobian column is formed.
pub(super) const COLUMN_GENERAL: u8 = 6;

/// The cost and errors of one configuration.
#[derive(Clone, Copy, Debug)]
pub(super) struct Eval {
    /// `½|r|²`.
    pub(super) e: f64,
    pub(super) pos: f64,
    pub(super) ori: f64,
}

impl Eval {
    pub(super) const WORST: Self = Self {
        e: f64::INFINITY,
        pos: f64::INFINITY,
        ori: f64::INFINITY,
    };

    #[inline]
    pub(super) fn converged(&self, p: &IkParams) -> bool {
        self.pos < p.position_tolerance && self.ori < p.orientation_tolerance
    }
}

/// Every buffer of a solve, allocated by [`IkSolver::new`].
#[derive(Clone, Debug)]
pub(super) struct Workspace {
    /// Per body: on the path from the root to a target (its placement is needed).
    pub(super) marked: Vec<bool>,
    /// The marked bodies, in increasing order, and how each is placed.
    pub(super) path: Vec<PathBody>,
    /// Per body: owns a coordinate that moves a target (directly or through a coupled mimic
    /// follower).
    pub(super) owner: Vec<bool>,
    /// Coupled mimic followers on a path: (body, column of the leader's coordinate, multiplier).
    pub(super) followers: Vec<(usize, usize, f64)>,
    /// The bodies whose joints move in this solve.
    pub(super) moving: Vec<usize>,
    /// The moving velocity coordinates, their body and their joint's motion subspace column
    /// (in the body frame), looked up once per solve.
    pub(super) dofs: Vec<usize>,
    pub(super) dof_body: Vec<usize>,
    pub(super) dof_axis: Vec<Motion>,
    /// Per moving coordinate: 0, 1, 2 for a revolute joint about that coordinate axis, 3, 4, 5
    /// for a prismatic joint along axis `kind - 3`, [`COLUMN_GENERAL`] for any other.
    pub(super) dof_kind: Vec<u8>,
    /// Per moving coordinate: its configuration coordinate, when `additive`.
    pub(super) dof_q: Vec<usize>,
    /// Every moving joint is a vector space (revolute, continuous, prismatic, cylindrical), so
    /// `q ⊕ dq` adds `dq[c]` to coordinate `dof_q[c]`.
    pub(super) additive: bool,
    pub(super) targets: Vec<TargetState>,
    pub(super) ntargets: usize,
    /// Number of residual rows.
    pub(super) m: usize,
    /// Weighted Jacobian, row-major (row `k` is `jac[k*n..(k+1)*n]`, `n` moving coordinates).
    pub(super) jac: Vec<f64>,
    pub(super) r: Vec<f64>,
    pub(super) r_trial: Vec<f64>,
    /// The normal-equation matrix (`J_F J_Fᵀ + λI` or `J_FᵀJ_F + λI`, F the free columns) and
    /// its factor.
    pub(super) chol: Vec<f64>,
    /// `J` with the frozen columns removed (`m x f`, row-major).
    pub(super) jf: Vec<f64>,
    /// `-r - J z` (length m) and the solution of the m x m system.
    pub(super) w: Vec<f64>,
    pub(super) y: Vec<f64>,
    /// `1 / D` of the `L D Lᵀ` factorisation.
    pub(super) inv_diag: Vec<f64>,
    pub(super) rhs: Vec<f64>,
    pub(super) step: Vec<f64>,
    pub(super) z: Vec<f64>,
    pub(super) fixed: Vec<bool>,
    pub(super) free: Vec<usize>,
    pub(super) dv: Vec<f64>,
    pub(super) q: Vec<f64>,
    pub(super) q_trial: Vec<f64>,
    pub(super) q_best: Vec<f64>,
    pub(super) q_start: Vec<f64>,
}

impl Workspace {
    pub(super) fn new(nq: usize, nv: usize, nb: usize, max_targets: usize) -> Self {
        let rows = 6 * max_targets;
        Self {
            marked: vec![false; nb],
            path: Vec::with_capacity(nb),
            owner: vec![false; nb],
            followers: Vec::with_capacity(nb),
            moving: Vec::with_capacity(nb),
            dofs: Vec::with_capacity(nv),
            dof_body: Vec::with_capacity(nv),
            dof_axis: Vec::with_capacity(nv),
            dof_kind: Vec::with_capacity(nv),
            dof_q: Vec::with_capacity(nv),
            additive: false,
            targets: vec![TargetState::EMPTY; max_targets],
            ntargets: 0,
            m: 0,
            jac: vec![0.0; rows * nv],
            r: vec![0.0; rows],
            r_trial: vec![0.0; rows],
            chol: vec![0.0; nv.max(rows).pow(2)],
            inv_diag: vec![0.0; nv.max(rows)],
            jf: vec![0.0; rows * nv],
            w: vec![0.0; rows],
            y: vec![0.0; rows],
            rhs: vec![0.0; nv],
            step: vec![0.0; nv],
            z: vec![0.0; nv],
            fixed: vec![false; nv],
            free: Vec::with_capacity(nv),
            dv: vec![0.0; nv],
            q: vec![0.0; nq],
            q_trial: vec![0.0; nq],
            q_best: vec![0.0; nq],
            q_start: vec![0.0; nq],
        }
    }

    /// Makes the trial configuration (and its residual) the current one.
    #[inline]
    pub(super) fn accept(&mut self) {
        std::mem::swap(&mut self.q, &mut self.q_trial);
        std::mem::swap(&mut self.r, &mut self.r_trial);
    }
}
