//! Reachable workspace: where a frame can go, sampled over the joint space.
//!
//! [`sample_reachable`] evaluates the pose of one link or frame at many configurations and keeps,
//! for each, the position, optionally the orientation, and the Yoshikawa manipulability index.
//! The configurations come from a [`Sampling`]:
//! - [`Sampling::Grid`]: the product of linspaces over the sampled coordinates (the textbook's
//!   `itertools.product(*[linspace(lo, hi, k) …])`), `k^d` samples for `d` coordinates;
//! - [`Sampling::Random`]: uniform within the limits (as
//!   [`random_configuration`]), from a seed.
//!
//! **Which joints move.** Only the joints on the path from the root to the frame are sampled
//! (for a coupled mimic joint on the path, its leader); every other coordinate keeps its value in
//! [`ReachableParams::q0`] (the neutral configuration by default), since it cannot move the
//! frame. Floating joints (such as the `root_joint` of
//! [`RootJoint::Floating`](kinetree_model::RootJoint::Floating)) are never sampled: they are held
//! at `q0`, so the cloud is expressed relative to the base placed there. Ranges: finite position
//! limits are used as they are; joints without finite limits use
//! [`sampling_range`] (angles in [-π, π], translations in
//! [-1, 1] m). Grid coordinates per joint kind: revolute, prismatic and continuous one (a
//! continuous joint's grid leaves out the end point π, which is -π again), cylindrical two
//! (displacement, angle), planar three (x, y in [-1, 1] m, θ), spherical three (the components of
//! a rotation vector, each in [-π, π], mapped to a quaternion by the exponential). A grid of one
//! point per coordinate takes the middle of each range.
//!
//! **Manipulability.** For each sample, `J` is the frame Jacobian in
//! [`ReferenceFrame::LocalWorldAligned`] (world axes, at the frame origin) restricted to the
//! columns of the sampled joints: with [`TaskSpace::Position`] its three linear rows (`3 x n`),
//! with [`TaskSpace::Pose`] all six rows `[linear; angular]` (`6 x n`, mixing metres and radians).
//! The index is the product of the singular values of `J`: `w = sqrt(det(J·Jᵀ))` when `J` has no
//! more rows than columns (Yoshikawa's definition), and `sqrt(det(Jᵀ·J))` when it has fewer
//! columns than rows (e.g. a planar 2R arm's `3 x 2` position Jacobian, whose `det(J·Jᵀ)` is
//! identically zero); that case gives `l1·l2·|sin θ2|` for the planar 2R arm, as its `2 x 2`
//! Jacobian does. With no sampled joint, `w = 0`. With [`TaskSpace::Position`] `w` is in m³.
//!
//! **Parallelism and determinism.** Samples are cut into chunks of [`CHUNK_SIZE`] consecutive
//! indices, processed in parallel with rayon (on the current rayon pool: use
//! `rayon::ThreadPoolBuilder` and `install` to choose the thread count). Each chunk creates one
//! [`KinematicsData`] and its buffers once, then evaluates its samples without allocating. A
//! random chunk seeds its own generator from `(seed, chunk index)`, so the result depends on the
//! seed only, never on the number of threads or the order in which chunks run.
//!
//! **From the samples.** [`ReachableSet`] gives the axis-aligned [`Bounds`], the maximum reach
//! from a point ([`ReachableSet::max_reach`]), a [`VoxelMap`] at a chosen resolution
//! ([`ReachableSet::voxelize`]) whose [`VoxelMap::is_reachable`] answers from the voxels actually
//! hit (not from the bounding box), and exports to CSV, PLY and JSON.
//!
//! Sampling is an approximation from inside: a point reported reachable was reached (to within a
//! voxel), while a point reported unreachable may still be reachable between samples.

use crate::configuration::{random_configuration, sampling_range};
use crate::{
    FrameId, KinematicsData, KinematicsError, ReferenceFrame, compute_frame_jacobian, configuration,
};
use glam::{DQuat, DVec3};
use kinetree_model::spatial::{Motion, Se3};
use kinetree_model::{JointKind, Model};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use rayon::prelude::*;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::io::{self, BufWriter, Write};
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Samples per parallel task. Each task allocates its buffers once; the random generator of a
/// task is seeded from the seed and the task's index, which is what makes results independent of
/// the thread count.
pub const CHUNK_SIZE: usize = 1024;

/// The largest number of samples one call may ask for (about 2 GiB of results with
/// orientations); larger requests are refused with [`ReachableError::TooManySamples`].
pub const MAX_SAMPLES: usize = 1 << 25;

/// What can go wrong while sampling a reachable workspace or querying it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReachableError {
    /// An error from the kinematics layer (unknown frame, wrong `q0` length, NaN in `q0`, …).
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
    /// The sampling asks for no samples at all.
    #[error("the sampling asks for no samples ({what} is 0)")]
    NoSamples {
        /// The parameter that is zero (`"samples"` or `"per_coordinate"`).
        what: &'static str,
    },
    /// The sampling asks for more than [`MAX_SAMPLES`] samples.
    #[error("{requested} samples exceed the limit of {limit}")]
    TooManySamples {
        /// The number asked for (saturated at `u128::MAX` for enormous grids).
        requested: u128,
        /// [`MAX_SAMPLES`].
        limit: usize,
    },
    /// A voxel size is zero, negative, NaN or infinite.
    #[error("voxel size {size} is not a positive finite length")]
    InvalidVoxelSize {
        /// The size given, in metres.
        size: f64,
    },
    /// A voxel size is so small that voxel indices of the samples overflow.
    #[error("voxel size {size} m is too small for points {distance} m from the origin")]
    VoxelTooSmall {
        /// The size given, in metres.
        size: f64,
        /// The farthest coordinate that does not fit, in metres.
        distance: f64,
    },
    /// A query point is NaN or infinite.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which input.
        what: &'static str,
    },
}

/// How configurations are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampling {
    /// The product of linspaces: `per_coordinate` evenly spaced values (end points included) on
    /// each sampled coordinate, `per_coordinate^d` samples in all. Sample `i` is the `i`-th
    /// combination in row-major order, the first joint varying slowest.
    Grid {
        /// Values per coordinate (at least 1; 1 takes the middle of each range).
        per_coordinate: usize,
    },
    /// `samples` configurations uniform within the ranges, from `seed`.
    Random {
        /// How many samples (at least 1).
        samples: usize,
        /// Seed of the generator; the same seed gives the same samples on any thread count.
        seed: u64,
    },
}

/// Which part of the frame's motion the manipulability measures, and whether orientations are
/// kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TaskSpace {
    /// Positions only: the 3 linear rows of the Jacobian; orientations are not stored.
    #[default]
    Position,
    /// Full pose: all 6 rows `[linear; angular]`; orientations are stored.
    Pose,
}

impl TaskSpace {
    /// Number of Jacobian rows used (3 or 6).
    #[must_use]
    pub fn rows(self) -> usize {
        match self {
            TaskSpace::Position => 3,
            TaskSpace::Pose => 6,
        }
    }

    /// Lower-case name (`"position"` or `"pose"`), as written in exports.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            TaskSpace::Position => "position",
            TaskSpace::Pose => "pose",
        }
    }
}

/// Parameters of [`sample_reachable`].
#[derive(Clone, Debug, PartialEq)]
pub struct ReachableParams {
    /// How configurations are drawn. Default: 100 000 random samples with seed 0.
    pub sampling: Sampling,
    /// Position only or full pose. Default: [`TaskSpace::Position`].
    pub task: TaskSpace,
    /// The configuration of the joints that are not sampled (length `model.nq()`); `None` means
    /// the neutral configuration.
    pub q0: Option<Vec<f64>>,
}

impl Default for ReachableParams {
    fn default() -> Self {
        Self::random(100_000, 0)
    }
}

impl ReachableParams {
    /// A grid of `per_coordinate` values on each sampled coordinate, position task.
    #[must_use]
    pub fn grid(per_coordinate: usize) -> Self {
        Self {
            sampling: Sampling::Grid { per_coordinate },
            task: TaskSpace::Position,
            q0: None,
        }
    }

    /// `samples` random configurations from `seed`, position task.
    #[must_use]
    pub fn random(samples: usize, seed: u64) -> Self {
        Self {
            sampling: Sampling::Random { samples, seed },
            task: TaskSpace::Position,
            q0: None,
        }
    }

    /// The same parameters with another task space.
    #[must_use]
    pub fn with_task(mut self, task: TaskSpace) -> Self {
        self.task = task;
        self
    }

    /// The same parameters holding the non-sampled joints at `q0` (length `model.nq()`).
    #[must_use]
    pub fn with_q0(mut self, q0: Vec<f64>) -> Self {
        self.q0 = Some(q0);
        self
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Smallest x, y and z.
    pub min: DVec3,
    /// Largest x, y and z.
    pub max: DVec3,
}

impl Bounds {
    /// `max - min`.
    #[must_use]
    pub fn size(&self) -> DVec3 {
        self.max - self.min
    }

    /// The middle of the box.
    #[must_use]
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Whether `p` is inside the box or on its boundary (false for NaN).
    #[must_use]
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// Samples of the poses a frame reaches, with their manipulability (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ReachableSet {
    frame: String,
    task: TaskSpace,
    sampling: Sampling,
    joints: Vec<String>,
    positions: Vec<DVec3>,
    orientations: Vec<DQuat>,
    manipulability: Vec<f64>,
    bounds: Bounds,
}

/// One sampled coordinate: its range and whether it is periodic (a continuous joint).
#[derive(Clone, Copy, Debug)]
struct Axis {
    lo: f64,
    hi: f64,
    periodic: bool,
}

impl Axis {
    fn new((lo, hi): (f64, f64), periodic: bool) -> Self {
        Self { lo, hi, periodic }
    }

    /// The `d`-th of `k` grid values.
    #[inline]
    fn value(&self, d: usize, k: usize) -> f64 {
        if k == 1 {
            return 0.5 * (self.lo + self.hi);
        }
        let steps = if self.periodic { k } else { k - 1 };
        self.lo + (self.hi - self.lo) * d as f64 / steps as f64
    }
}

/// A sampled joint: where its coordinates are and which grid axes drive them.
#[derive(Clone, Debug)]
struct PlanJoint {
    kind: JointKind,
    idx_q: usize,
    axes: Range<usize>,
}

/// Everything the workers share, computed once per call.
#[derive(Debug)]
struct Plan {
    frame: FrameId,
    body: usize,
    body_from_frame: Se3,
    q0: Vec<f64>,
    joints: Vec<PlanJoint>,
    axes: Vec<Axis>,
    /// Velocity indices of the Jacobian columns used.
    dofs: Vec<usize>,
    /// `q` ranges restored from `q0` after a random draw.
    held: Vec<Range<usize>>,
    sampling: Sampling,
    task: TaskSpace,
    total: usize,
}

/// One parallel task: its index and its slices of positions, manipulabilities and orientations
/// (empty with [`TaskSpace::Position`]).
type Task<'a> = (usize, &'a mut [DVec3], &'a mut [f64], &'a mut [DQuat]);

/// The buffers of one parallel task.
struct Worker {
    data: KinematicsData,
    q: Vec<f64>,
    jacobian: Vec<Motion>,
    digits: Vec<usize>,
    scratch: Vec<f64>,
}

impl Plan {
    fn new(
        model: &Model,
        frame: FrameId,
        params: &ReachableParams,
    ) -> Result<(Self, Vec<String>), ReachableError> {
        frame.check(model)?;
        let q0 = match &params.q0 {
            Some(q0) => {
                crate::error::check_q(model, "q0", q0)?;
                q0.clone()
            }
            None => configuration::neutral_configuration(model),
        };
        let (body, body_from_frame) = frame.body(model)?;
        let bodies = model.bodies();
        let mut path = Vec::new();
        let mut i = body;
        while i != 0 {
            path.push(i);
            i = bodies[i].parent;
        }
        path.reverse();
        let (mut joints, mut axes, mut dofs, mut names) = (Vec::new(), Vec::new(), vec![], vec![]);
        let mut sampled = vec![false; model.nq()];
        let mut done: Vec<usize> = Vec::new();
        for &i in &path {
            // A coupled mimic follower owns no coordinate: its leader's moves it.
            let i = match bodies[i].mimic {
                Some(m) => match model.joint_body(m.leader) {
                    Some(leader) => leader,
                    None => continue,
                },
                None => i,
            };
            if done.contains(&i) {
                continue;
            }
            done.push(i);
            let b = &bodies[i];
            let Some(j) = b.joint else { continue };
            let lim = &model.joint(j).limits;
            let first = axes.len();
            match b.kind {
                JointKind::Fixed | JointKind::Floating => continue,
                JointKind::Revolute | JointKind::Prismatic => {
                    axes.push(Axis::new(
                        sampling_range(b.kind, lim.lower, lim.upper),
                        false,
                    ));
                }
                JointKind::Continuous => {
                    axes.push(Axis::new(
                        sampling_range(b.kind, lim.lower, lim.upper),
                        true,
                    ));
                }
                JointKind::Cylindrical => {
                    axes.push(Axis::new(
                        sampling_range(JointKind::Prismatic, lim.lower, lim.upper),
                        false,
                    ));
                    axes.push(Axis::new(
                        sampling_range(JointKind::Revolute, lim.lower, lim.upper),
                        false,
                    ));
                }
                JointKind::Planar => {
                    axes.push(Axis::new((-1.0, 1.0), false));
                    axes.push(Axis::new((-1.0, 1.0), false));
                    axes.push(Axis::new((-PI, PI), true));
                }
                JointKind::Spherical => {
                    for _ in 0..3 {
                        axes.push(Axis::new((-PI, PI), false));
                    }
                }
            }
            joints.push(PlanJoint {
                kind: b.kind,
                idx_q: b.idx_q,
                axes: first..axes.len(),
            });
            dofs.extend(b.idx_v..b.idx_v + b.nv);
            sampled[b.idx_q..b.idx_q + b.nq].fill(true);
            names.push(model.joint(j).name.clone());
        }
        let mut held: Vec<Range<usize>> = Vec::new();
        for (k, &s) in sampled.iter().enumerate() {
            if s {
                continue;
            }
            match held.last_mut() {
                Some(r) if r.end == k => r.end = k + 1,
                _ => held.push(k..k + 1),
            }
        }
        let total = match params.sampling {
            Sampling::Grid { per_coordinate } => {
                if per_coordinate == 0 {
                    return Err(ReachableError::NoSamples {
                        what: "per_coordinate",
                    });
                }
                let exp = u32::try_from(axes.len()).unwrap_or(u32::MAX);
                let requested = (per_coordinate as u128)
                    .checked_pow(exp)
                    .unwrap_or(u128::MAX);
                usize::try_from(requested)
                    .ok()
                    .filter(|&n| n <= MAX_SAMPLES)
                    .ok_or(ReachableError::TooManySamples {
                        requested,
                        limit: MAX_SAMPLES,
                    })?
            }
            Sampling::Random { samples, .. } => {
                if samples == 0 {
                    return Err(ReachableError::NoSamples { what: "samples" });
                }
                if samples > MAX_SAMPLES {
                    return Err(ReachableError::TooManySamples {
                        requested: samples as u128,
                        limit: MAX_SAMPLES,
                    });
                }
                samples
            }
        };
        let plan = Plan {
            frame,
            body,
            body_from_frame,
            q0,
            joints,
            axes,
            dofs,
            held,
            sampling: params.sampling,
            task: params.task,
            total,
        };
        Ok((plan, names))
    }

    /// Writes the grid point given by `digits` into the sampled coordinates of `q`.
    #[inline]
    fn write_grid(&self, per_coordinate: usize, digits: &[usize], q: &mut [f64]) {
        for j in &self.joints {
            let value = |a: usize| self.axes[a].value(digits[a], per_coordinate);
            let a = j.axes.start;
            let qi = &mut q[j.idx_q..];
            match j.kind {
                JointKind::Spherical => {
                    let r = DVec3::new(value(a), value(a + 1), value(a + 2));
                    qi[..4].copy_from_slice(&DQuat::from_scaled_axis(r).to_array());
                }
                _ => {
                    for (k, x) in qi[..j.axes.len()].iter_mut().enumerate() {
                        *x = value(a + k);
                    }
                }
            }
        }
    }

    /// Evaluates one parallel task: samples `start .. start + positions.len()`.
    fn run_chunk(
        &self,
        model: &Model,
        chunk: usize,
        positions: &mut [DVec3],
        manipulability: &mut [f64],
        orientations: &mut [DQuat],
    ) -> Result<(), KinematicsError> {
        let mut w = Worker {
            data: KinematicsData::new(model),
            q: self.q0.clone(),
            jacobian: vec![Motion::ZERO; model.nv()],
            digits: vec![0; self.axes.len()],
            scratch: vec![0.0; 6 * self.dofs.len().max(6)],
        };
        let start = chunk * CHUNK_SIZE;
        let mut rng = SmallRng::seed_from_u64(chunk_seed(self.sampling, chunk));
        if let Sampling::Grid { per_coordinate } = self.sampling {
            // Mixed-radix digits of the first index, the last coordinate varying fastest.
            let mut rest = start;
            for d in w.digits.iter_mut().rev() {
                *d = rest % per_coordinate;
                rest /= per_coordinate;
            }
        }
        for i in 0..positions.len() {
            match self.sampling {
                Sampling::Grid { per_coordinate } => {
                    self.write_grid(per_coordinate, &w.digits, &mut w.q);
                    for d in w.digits.iter_mut().rev() {
                        *d += 1;
                        if *d < per_coordinate {
                            break;
                        }
                        *d = 0;
                    }
                }
                Sampling::Random { .. } => {
                    random_configuration(model, &mut rng, &mut w.q)?;
                    for r in &self.held {
                        w.q[r.clone()].copy_from_slice(&self.q0[r.clone()]);
                    }
                }
            }
            compute_frame_jacobian(
                model,
                &mut w.data,
                &w.q,
                self.frame,
                ReferenceFrame::LocalWorldAligned,
                &mut w.jacobian,
            )?;
            let world_from_frame = w.data.world_from_body()[self.body] * self.body_from_frame;
            positions[i] = world_from_frame.translation;
            if let Some(o) = orientations.get_mut(i) {
                *o = DQuat::from_mat3(&world_from_frame.rotation).normalize();
            }
            manipulability[i] =
                manipulability_index(&w.jacobian, &self.dofs, self.task.rows(), &mut w.scratch);
        }
        Ok(())
    }
}

/// The generator seed of a random task: a splitmix64 mix of the user's seed and the task index.
fn chunk_seed(sampling: Sampling, chunk: usize) -> u64 {
    let seed = match sampling {
        Sampling::Random { seed, .. } => seed,
        Sampling::Grid { .. } => 0,
    };
    let mut z = seed
        .wrapping_add((chunk as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Product of the singular values of the `rows x dofs.len()` Jacobian made of the first `rows`
/// rows of the columns `dofs` of `jacobian` (see the module docs). Allocates nothing: `scratch`
/// holds at least `6 * dofs.len().max(6)` values.
///
/// Modified Gram-Schmidt on the rows of `J` (or its columns when it has fewer columns than rows):
/// the product of the orthogonalised lengths is `sqrt(det(J·Jᵀ))` (resp. `sqrt(det(Jᵀ·J))`),
/// with an absolute error of a few ulps of `|J|^k` even at singularities, where forming the Gram
/// matrix and its determinant would leave `sqrt(ε)`.
fn manipulability_index(
    jacobian: &[Motion],
    dofs: &[usize],
    rows: usize,
    scratch: &mut [f64],
) -> f64 {
    let n = dofs.len();
    if n == 0 {
        return 0.0;
    }
    let entry = |r: usize, c: usize| {
        let col = &jacobian[dofs[c]];
        if r < 3 {
            col.linear[r]
        } else {
            col.angular[r - 3]
        }
    };
    let by_rows = rows <= n;
    let (k, len) = if by_rows { (rows, n) } else { (n, rows) };
    let v = &mut scratch[..k * len];
    for i in 0..k {
        for t in 0..len {
            v[i * len + t] = if by_rows { entry(i, t) } else { entry(t, i) };
        }
    }
    let mut w = 1.0;
    for i in 0..k {
        let (done, rest) = v.split_at_mut(i * len);
        let vi = &mut rest[..len];
        for j in 0..i {
            let qj = &done[j * len..(j + 1) * len];
            let d: f64 = qj.iter().zip(vi.iter()).map(|(a, b)| a * b).sum();
            for (x, q) in vi.iter_mut().zip(qj) {
                *x -= d * q;
            }
        }
        let norm = vi.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            return 0.0;
        }
        w *= norm;
        for x in vi.iter_mut() {
            *x /= norm;
        }
    }
    w
}

/// Samples the poses a frame reaches (see the module docs for the method and its conventions),
/// in parallel on the current rayon pool. Equivalent to [`sample_reachable_with_progress`] with
/// no progress report.
///
/// `frame` is a link or named frame of `model`; positions and orientations are in the world
/// frame.
///
/// # Errors
/// [`ReachableError::NoSamples`] and [`ReachableError::TooManySamples`] for an empty or
/// oversized sampling; [`ReachableError::Kinematics`] wrapping
/// [`KinematicsError::FrameOutOfRange`] for a frame id not from this model,
/// [`KinematicsError::DimensionMismatch`] or [`KinematicsError::NonFinite`] for a bad `q0`.
///
/// # Examples
/// The tool of a planar 2R arm with links 1 m and 0.5 m sweeps the annulus 0.5 m ≤ r ≤ 1.5 m:
/// ```
/// use kinetree_kinematics::FrameId;
/// use kinetree_kinematics::reachable::{ReachableParams, sample_reachable};
/// use kinetree_kinematics::spatial::DVec3;
/// use kinetree_model::samples;
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let model = samples::planar_2r(1.0, 0.5);
/// let tool = FrameId::find(&model, "tool")?;
/// let set = sample_reachable(&model, tool, &ReachableParams::grid(101))?;
/// assert_eq!(set.len(), 101 * 101);
/// let reach = set.max_reach(DVec3::ZERO)?;
/// assert!((reach - 1.5).abs() < 1e-9);
/// let voxels = set.voxelize(0.05)?;
/// assert!(voxels.is_reachable(DVec3::new(1.0, 0.0, 0.0)));
/// assert!(!voxels.is_reachable(DVec3::ZERO)); // the hole in the middle
/// assert!(!voxels.is_reachable(DVec3::new(1.7, 0.0, 0.0))); // beyond reach
/// let mut ply = Vec::new();
/// set.write_ply(&mut ply)?;
/// # Ok(())
/// # }
/// ```
pub fn sample_reachable(
    model: &Model,
    frame: FrameId,
    params: &ReachableParams,
) -> Result<ReachableSet, ReachableError> {
    sample_reachable_with_progress(model, frame, params, &|_, _| {})
}

/// [`sample_reachable`] with a progress report: `progress(done, total)` is called, from the
/// worker threads and possibly concurrently, each time a task of [`CHUNK_SIZE`] samples ends
/// (`done` counts samples, `total` is the number of samples of the call).
///
/// # Errors
/// As [`sample_reachable`].
///
/// # Examples
/// ```
/// use kinetree_kinematics::FrameId;
/// use kinetree_kinematics::reachable::{ReachableParams, sample_reachable_with_progress};
/// use kinetree_model::samples;
/// use std::sync::atomic::{AtomicUsize, Ordering};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let model = samples::six_axis();
/// let tool = FrameId::find(&model, "tool")?;
/// let last = AtomicUsize::new(0);
/// let report = |done: usize, _total: usize| {
///     last.fetch_max(done, Ordering::Relaxed);
/// };
/// let set = sample_reachable_with_progress(&model, tool, &ReachableParams::random(5000, 7), &report)?;
/// assert_eq!(last.load(Ordering::Relaxed), set.len());
/// # Ok(())
/// # }
/// ```
pub fn sample_reachable_with_progress(
    model: &Model,
    frame: FrameId,
    params: &ReachableParams,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<ReachableSet, ReachableError> {
    let (plan, joints) = Plan::new(model, frame, params)?;
    let n = plan.total;
    let mut positions = vec![DVec3::ZERO; n];
    let mut manipulability = vec![0.0; n];
    let mut orientations = match plan.task {
        TaskSpace::Position => Vec::new(),
        TaskSpace::Pose => vec![DQuat::IDENTITY; n],
    };
    let mut tasks: Vec<Task<'_>> = positions
        .chunks_mut(CHUNK_SIZE)
        .zip(manipulability.chunks_mut(CHUNK_SIZE))
        .enumerate()
        .map(|(c, (p, m))| (c, p, m, &mut [][..]))
        .collect();
    for (task, o) in tasks.iter_mut().zip(orientations.chunks_mut(CHUNK_SIZE)) {
        task.3 = o;
    }
    let done = AtomicUsize::new(0);
    tasks.into_par_iter().try_for_each(|(c, p, m, o)| {
        plan.run_chunk(model, c, p, m, o)?;
        let now = done.fetch_add(p.len(), Ordering::Relaxed) + p.len();
        progress(now, n);
        Ok::<(), KinematicsError>(())
    })?;
    let bounds = positions.iter().fold(
        Bounds {
            min: DVec3::INFINITY,
            max: DVec3::NEG_INFINITY,
        },
        |b, &p| Bounds {
            min: b.min.min(p),
            max: b.max.max(p),
        },
    );
    Ok(ReachableSet {
        frame: frame.name(model)?.to_string(),
        task: plan.task,
        sampling: plan.sampling,
        joints,
        positions,
        orientations,
        manipulability,
        bounds,
    })
}

impl ReachableSet {
    /// Number of samples (never 0).
    #[must_use]
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Always false: a set holds at least one sample. Present for API symmetry.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Name of the sampled link or frame.
    #[must_use]
    pub fn frame_name(&self) -> &str {
        &self.frame
    }

    /// The task space used for the manipulability (and whether orientations were kept).
    #[must_use]
    pub fn task(&self) -> TaskSpace {
        self.task
    }

    /// The sampling that produced the set.
    #[must_use]
    pub fn sampling(&self) -> Sampling {
        self.sampling
    }

    /// Names of the sampled joints, root first (the joints on the frame's path, less floating
    /// joints).
    #[must_use]
    pub fn joints(&self) -> &[String] {
        &self.joints
    }

    /// World position of the frame origin at each sample.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// World orientation of the frame at each sample with [`TaskSpace::Pose`]; `None` with
    /// [`TaskSpace::Position`].
    #[must_use]
    pub fn orientations(&self) -> Option<&[DQuat]> {
        match self.task {
            TaskSpace::Position => None,
            TaskSpace::Pose => Some(&self.orientations),
        }
    }

    /// The manipulability index at each sample (see the module docs).
    #[must_use]
    pub fn manipulability(&self) -> &[f64] {
        &self.manipulability
    }

    /// The axis-aligned box of all sampled positions.
    #[must_use]
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// The largest distance from `base` to a sampled position (e.g. from the shoulder of an
    /// arm).
    ///
    /// # Errors
    /// [`ReachableError::NonFinite`] when `base` has a NaN or infinite coordinate.
    pub fn max_reach(&self, base: DVec3) -> Result<f64, ReachableError> {
        if !base.is_finite() {
            return Err(ReachableError::NonFinite { what: "base" });
        }
        Ok(self
            .positions
            .iter()
            .map(|p| p.distance(base))
            .fold(0.0, f64::max))
    }

    /// Bins the sampled positions into cubic voxels of side `voxel_size` (metres) on a grid
    /// anchored at the world origin: voxel `(i, j, k)` covers `[i·s, (i+1)·s) x …`. Each voxel
    /// hit by at least one sample records its sample count and the maximum and mean
    /// manipulability of those samples.
    ///
    /// # Errors
    /// [`ReachableError::InvalidVoxelSize`] when `voxel_size` is not positive and finite,
    /// [`ReachableError::VoxelTooSmall`] when voxel indices would overflow.
    ///
    /// # Examples
    /// ```
    /// use kinetree_kinematics::FrameId;
    /// use kinetree_kinematics::reachable::{ReachableError, ReachableParams, sample_reachable};
    /// use kinetree_model::samples;
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// let model = samples::planar_2r(1.0, 1.0);
    /// let set = sample_reachable(&model, FrameId::find(&model, "tool")?, &ReachableParams::grid(50))?;
    /// assert!(matches!(set.voxelize(0.0), Err(ReachableError::InvalidVoxelSize { .. })));
    /// let voxels = set.voxelize(0.1)?;
    /// assert!(voxels.len() > 100);
    /// # Ok(())
    /// # }
    /// ```
    pub fn voxelize(&self, voxel_size: f64) -> Result<VoxelMap, ReachableError> {
        if !(voxel_size.is_finite() && voxel_size > 0.0) {
            return Err(ReachableError::InvalidVoxelSize { size: voxel_size });
        }
        let far = self
            .bounds
            .min
            .abs()
            .max(self.bounds.max.abs())
            .max_element();
        if far / voxel_size >= VOXEL_INDEX_LIMIT {
            return Err(ReachableError::VoxelTooSmall {
                size: voxel_size,
                distance: far,
            });
        }
        let mut map = VoxelMap {
            size: voxel_size,
            cells: HashMap::new(),
        };
        for (p, &w) in self.positions.iter().zip(&self.manipulability) {
            let Some(key) = map.index_of(*p) else {
                continue;
            };
            let cell = map.cells.entry(key).or_insert(VoxelStats {
                count: 0,
                max_manipulability: f64::NEG_INFINITY,
                mean_manipulability: 0.0,
            });
            cell.count += 1;
            cell.max_manipulability = cell.max_manipulability.max(w);
            // Running sum for now; divided by the count below.
            cell.mean_manipulability += w;
        }
        for cell in map.cells.values_mut() {
            cell.mean_manipulability /= cell.count as f64;
        }
        Ok(map)
    }

    /// Writes the samples as CSV: a header `x,y,z,manipulability` (plus `,qx,qy,qz,qw` with
    /// [`TaskSpace::Pose`]) and one line per sample, in metres, in sample order.
    ///
    /// # Errors
    /// Any error of `out`.
    pub fn write_csv<W: Write>(&self, out: W) -> io::Result<()> {
        let mut out = BufWriter::new(out);
        write!(out, "x,y,z,manipulability")?;
        if self.task == TaskSpace::Pose {
            write!(out, ",qx,qy,qz,qw")?;
        }
        writeln!(out)?;
        for i in 0..self.len() {
            let p = self.positions[i];
            write!(out, "{},{},{},{}", p.x, p.y, p.z, self.manipulability[i])?;
            if let Some(o) = self.orientations.get(i) {
                write!(out, ",{},{},{},{}", o.x, o.y, o.z, o.w)?;
            }
            writeln!(out)?;
        }
        out.flush()
    }

    /// Writes the samples as an ASCII PLY point cloud: vertices `x y z` (metres) with a scalar
    /// property `manipulability` (plus `qx qy qz qw` with [`TaskSpace::Pose`]), all `double`.
    /// Point-cloud viewers (CloudCompare, MeshLab, ParaView) colour by the scalar.
    ///
    /// # Errors
    /// Any error of `out`.
    pub fn write_ply<W: Write>(&self, out: W) -> io::Result<()> {
        let mut out = BufWriter::new(out);
        writeln!(out, "ply\nformat ascii 1.0")?;
        writeln!(
            out,
            "comment kinetree reachable workspace of frame {} ({} task, {})",
            self.frame.replace(['\n', '\r'], " "),
            self.task.name(),
            sampling_text(self.sampling)
        )?;
        writeln!(out, "element vertex {}", self.len())?;
        let mut properties = vec!["x", "y", "z", "manipulability"];
        if self.task == TaskSpace::Pose {
            properties.extend(["qx", "qy", "qz", "qw"]);
        }
        for p in properties {
            writeln!(out, "property double {p}")?;
        }
        writeln!(out, "end_header")?;
        for i in 0..self.len() {
            let p = self.positions[i];
            write!(out, "{} {} {} {}", p.x, p.y, p.z, self.manipulability[i])?;
            if let Some(o) = self.orientations.get(i) {
                write!(out, " {} {} {} {}", o.x, o.y, o.z, o.w)?;
            }
            writeln!(out)?;
        }
        out.flush()
    }

    /// Writes the samples as one JSON object: `frame`, `task`, `sampling`, `joints`, `count`,
    /// `bounds` (`min`, `max`), `columns` (the names of each sample's entries) and `samples`, an
    /// array of `[x, y, z, manipulability]` (plus `qx, qy, qz, qw` with [`TaskSpace::Pose`]).
    ///
    /// # Errors
    /// Any error of `out`.
    pub fn write_json<W: Write>(&self, out: W) -> io::Result<()> {
        let mut out = BufWriter::new(out);
        let v = |v: DVec3| format!("[{}, {}, {}]", v.x, v.y, v.z);
        writeln!(out, "{{")?;
        writeln!(out, "  \"frame\": {},", json_string(&self.frame))?;
        writeln!(out, "  \"task\": \"{}\",", self.task.name())?;
        let sampling = match self.sampling {
            Sampling::Grid { per_coordinate } => {
                format!("{{\"kind\": \"grid\", \"per_coordinate\": {per_coordinate}}}")
            }
            Sampling::Random { samples, seed } => {
                format!("{{\"kind\": \"random\", \"samples\": {samples}, \"seed\": {seed}}}")
            }
        };
        writeln!(out, "  \"sampling\": {sampling},")?;
        let joints: Vec<String> = self.joints.iter().map(|j| json_string(j)).collect();
        writeln!(out, "  \"joints\": [{}],", joints.join(", "))?;
        writeln!(out, "  \"count\": {},", self.len())?;
        writeln!(
            out,
            "  \"bounds\": {{\"min\": {}, \"max\": {}}},",
            v(self.bounds.min),
            v(self.bounds.max)
        )?;
        let columns = match self.task {
            TaskSpace::Position => r#"["x", "y", "z", "manipulability"]"#,
            TaskSpace::Pose => r#"["x", "y", "z", "manipulability", "qx", "qy", "qz", "qw"]"#,
        };
        writeln!(out, "  \"columns\": {columns},")?;
        writeln!(out, "  \"samples\": [")?;
        for i in 0..self.len() {
            let p = self.positions[i];
            write!(
                out,
                "    [{}, {}, {}, {}",
                p.x, p.y, p.z, self.manipulability[i]
            )?;
            if let Some(o) = self.orientations.get(i) {
                write!(out, ", {}, {}, {}, {}", o.x, o.y, o.z, o.w)?;
            }
            let comma = if i + 1 < self.len() { "," } else { "" };
            writeln!(out, "]{comma}")?;
        }
        writeln!(out, "  ]\n}}")?;
        out.flush()
    }
}

fn sampling_text(s: Sampling) -> String {
    match s {
        Sampling::Grid { per_coordinate } => format!("grid of {per_coordinate} per coordinate"),
        Sampling::Random { samples, seed } => format!("{samples} random samples, seed {seed}"),
    }
}

fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if u32::from(c) < 0x20 => out.push_str(&format!("\\u{:04x}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Voxel indices stay below this magnitude, so that they and their centres are exact in `f64`
/// and fit in `i64`.
const VOXEL_INDEX_LIMIT: f64 = (1u64 << 52) as f64;

/// What a [`VoxelMap`] knows about one voxel hit by samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelStats {
    /// Number of samples in the voxel (at least 1).
    pub count: usize,
    /// The largest manipulability of those samples.
    pub max_manipulability: f64,
    /// The mean manipulability of those samples.
    pub mean_manipulability: f64,
}

/// The voxels hit by the samples of a [`ReachableSet`] (built by [`ReachableSet::voxelize`]).
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelMap {
    size: f64,
    cells: HashMap<[i64; 3], VoxelStats>,
}

impl VoxelMap {
    /// The side of a voxel, in metres.
    #[must_use]
    pub fn voxel_size(&self) -> f64 {
        self.size
    }

    /// Number of voxels hit.
    #[must_use]
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether no voxel was hit (never true for a map built from a [`ReachableSet`]).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The volume of the voxels hit, in m³: an estimate of the reachable volume (exact as the
    /// sampling gets denser and the voxels smaller, for a solid workspace).
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.cells.len() as f64 * self.size.powi(3)
    }

    /// The index `(⌊x/s⌋, ⌊y/s⌋, ⌊z/s⌋)` of the voxel holding `point`, or `None` for a point
    /// with a NaN or infinite coordinate or too far from the origin for the index to fit.
    #[must_use]
    pub fn index_of(&self, point: DVec3) -> Option<[i64; 3]> {
        let i = (point / self.size).floor();
        if !(i.is_finite() && i.abs().max_element() < VOXEL_INDEX_LIMIT) {
            return None;
        }
        // Exact: `i` holds integers below 2^52 in magnitude.
        Some([i.x as i64, i.y as i64, i.z as i64])
    }

    /// The centre of voxel `index`, in metres.
    #[must_use]
    pub fn center_of(&self, index: [i64; 3]) -> DVec3 {
        (DVec3::new(index[0] as f64, index[1] as f64, index[2] as f64) + 0.5) * self.size
    }

    /// Whether the voxel holding `point` was hit by a sample (false for a non-finite point).
    #[must_use]
    pub fn is_reachable(&self, point: DVec3) -> bool {
        self.stats_at(point).is_some()
    }

    /// What is known about the voxel holding `point`, if it was hit.
    #[must_use]
    pub fn stats_at(&self, point: DVec3) -> Option<&VoxelStats> {
        self.index_of(point).and_then(|k| self.cells.get(&k))
    }

    /// Every voxel hit with its statistics, sorted by index (x, then y, then z).
    #[must_use]
    pub fn voxels(&self) -> Vec<([i64; 3], VoxelStats)> {
        let mut v: Vec<_> = self.cells.iter().map(|(k, s)| (*k, *s)).collect();
        v.sort_unstable_by_key(|(k, _)| *k);
        v
    }

    /// Writes the voxels hit as CSV: a header `x,y,z,count,max_manipulability,mean_manipulability`
    /// and one line per voxel (its centre in metres), sorted as [`VoxelMap::voxels`].
    ///
    /// # Errors
    /// Any error of `out`.
    pub fn write_csv<W: Write>(&self, out: W) -> io::Result<()> {
        let mut out = BufWriter::new(out);
        writeln!(out, "x,y,z,count,max_manipulability,mean_manipulability")?;
        for (k, s) in self.voxels() {
            let c = self.center_of(k);
            writeln!(
                out,
                "{},{},{},{},{},{}",
                c.x, c.y, c.z, s.count, s.max_manipulability, s.mean_manipulability
            )?;
        }
        out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_values_are_a_linspace() {
        let a = Axis::new((-1.0, 1.0), false);
        let v: Vec<f64> = (0..5).map(|d| a.value(d, 5)).collect();
        assert_eq!(v, [-1.0, -0.5, 0.0, 0.5, 1.0]);
        assert_eq!(a.value(0, 1), 0.0);
        let p = Axis::new((-PI, PI), true);
        assert!((p.value(3, 4) - PI / 2.0).abs() < 1e-15);
    }

    #[test]
    fn manipulability_of_a_square_jacobian_is_its_determinant() {
        let cols = [
            Motion::new(DVec3::new(1.0, 2.0, 0.0), DVec3::ZERO),
            Motion::new(DVec3::new(3.0, 4.0, 0.0), DVec3::Z),
            Motion::new(DVec3::new(0.0, 0.0, 5.0), DVec3::Z),
        ];
        let mut scratch = [0.0; 36];
        let w = manipulability_index(&cols, &[0, 1, 2], 3, &mut scratch);
        assert!((w - 10.0).abs() < 1e-12, "{w}");
        // Three rows, two columns: sqrt(det(Jᵀ·J)) = |det| of the 2 x 2 xy block.
        let w = manipulability_index(&cols, &[0, 1], 3, &mut scratch);
        assert!((w - 2.0).abs() < 1e-12, "{w}");
        assert_eq!(manipulability_index(&cols, &[], 3, &mut scratch), 0.0);
        // Six rows, three columns: sqrt(det(Jᵀ·J)) from the Gram matrix by hand.
        let g = |a: &Motion, b: &Motion| a.linear.dot(b.linear) + a.angular.dot(b.angular);
        let m = [
            [
                g(&cols[0], &cols[0]),
                g(&cols[0], &cols[1]),
                g(&cols[0], &cols[2]),
            ],
            [
                g(&cols[1], &cols[0]),
                g(&cols[1], &cols[1]),
                g(&cols[1], &cols[2]),
            ],
            [
                g(&cols[2], &cols[0]),
                g(&cols[2], &cols[1]),
                g(&cols[2], &cols[2]),
            ],
        ];
        let det = glam::DMat3::from_cols_array_2d(&m).determinant();
        let w = manipulability_index(&cols, &[0, 1, 2], 6, &mut scratch);
        assert!((w - det.sqrt()).abs() < 1e-12, "{w} vs {}", det.sqrt());
    }

    #[test]
    fn chunk_seeds_differ() {
        let s = Sampling::Random {
            samples: 1,
            seed: 3,
        };
        assert_ne!(chunk_seed(s, 0), chunk_seed(s, 1));
    }
}
