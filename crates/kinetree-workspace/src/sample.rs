//! The sampling itself: the plan shared by the workers, one parallel task per [`CHUNK_SIZE`]
//! samples, and the manipulability index.

use crate::{
    Bounds, CHUNK_SIZE, MAX_SAMPLES, ReachableError, ReachableParams, ReachableSet, Sampling,
    TaskSpace,
};
use kinetree_kinematics::configuration::{self, random_configuration, sampling_range};
use kinetree_kinematics::model::{JointKind, Model};
use kinetree_kinematics::spatial::{DQuat, DVec3, Motion, Se3};
use kinetree_kinematics::{
    FrameId, KinematicsData, KinematicsError, ReferenceFrame, compute_frame_jacobian,
};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use rayon::prelude::*;
use std::f64::consts::PI;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

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
            return 0.5 * self.lo + 0.5 * self.hi;
        }
        let steps = if self.periodic { k } else { k - 1 };
        // lo·(1 − t) + hi·t stays finite for any finite limits (hi − lo may overflow).
        let t = d as f64 / steps as f64;
        self.lo * (1.0 - t) + self.hi * t
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
                check_q0(model, q0)?;
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

/// Checks `q0` as every kinematics algorithm checks a configuration, naming it `q0` in the
/// error (the kinematics layer names it `q`).
fn check_q0(model: &Model, q0: &[f64]) -> Result<(), KinematicsError> {
    configuration::check_configuration(model, q0).map_err(|e| match e {
        KinematicsError::DimensionMismatch {
            what: "q",
            expected,
            actual,
        } => KinematicsError::DimensionMismatch {
            what: "q0",
            expected,
            actual,
        },
        KinematicsError::NonFinite { what: "q", index } => {
            KinematicsError::NonFinite { what: "q0", index }
        }
        e => e,
    })
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
/// use kinetree_workspace::kinematics::FrameId;
/// use kinetree_workspace::{ReachableParams, sample_reachable};
/// use kinetree_workspace::kinematics::spatial::DVec3;
/// use kinetree_workspace::kinematics::model::samples;
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
/// use kinetree_workspace::kinematics::FrameId;
/// use kinetree_workspace::{ReachableParams, sample_reachable_with_progress};
/// use kinetree_workspace::kinematics::model::samples;
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
        let det = kinetree_kinematics::spatial::DMat3::from_cols_array_2d(&m).determinant();
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
