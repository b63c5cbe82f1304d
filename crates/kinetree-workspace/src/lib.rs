//! # kinetree-workspace
//!
//! Reachable workspace: where a frame can go, sampled over the joint space, in parallel with
//! rayon. It sits on `kinetree-kinematics` (a sibling of the dynamics and collision layers) and
//! re-exports it as [`kinematics`]; the core kinematics crate has no thread pool.
//!
//! ```
//! use kinetree_workspace::kinematics::FrameId;
//! use kinetree_workspace::kinematics::model::samples;
//! use kinetree_workspace::kinematics::spatial::DVec3;
//! use kinetree_workspace::{ReachableParams, sample_reachable};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let model = samples::planar_2r(1.0, 0.5);
//! let tool = FrameId::find(&model, "tool")?;
//! let set = sample_reachable(&model, tool, &ReachableParams::grid(101))?;
//! // The tool sweeps the annulus 0.5 m <= r <= 1.5 m.
//! assert!((set.max_reach(DVec3::ZERO)? - 1.5).abs() < 1e-9);
//! let voxels = set.voxelize(0.05)?;
//! assert!(voxels.is_reachable(DVec3::new(1.0, 0.0, 0.0)));
//! assert!(!voxels.is_reachable(DVec3::ZERO));
//! # Ok(())
//! # }
//! ```
//!
//! ## Modules
//! - `params`: what to sample ([`Sampling`], [`TaskSpace`], [`ReachableParams`]) and the limits
//!   ([`CHUNK_SIZE`], [`MAX_SAMPLES`]).
//! - `sample`: [`sample_reachable`] and [`sample_reachable_with_progress`] (the plan, the parallel
//!   tasks, the manipulability index).
//! - `set`: [`ReachableSet`] and [`Bounds`]; `voxel`: [`VoxelMap`] and [`VoxelStats`].
//! - `export`: CSV, PLY and JSON writers of sets and voxel maps.
//! - `error`: [`ReachableError`], which wraps the kinematics layer's error.
//!
//! ## Method
//!
//! [`sample_reachable`] evaluates the pose of one link or frame at many configurations and keeps,
//! for each, the position, optionally the orientation, and the Yoshikawa manipulability index.
//! The configurations come from a [`Sampling`]:
//! - [`Sampling::Grid`]: the product of linspaces over the sampled coordinates (the textbook's
//!   `itertools.product(*[linspace(lo, hi, k) …])`), `k^d` samples for `d` coordinates;
//! - [`Sampling::Random`]: uniform within the limits (as
//!   [`random_configuration`](kinetree_kinematics::configuration::random_configuration)), from a seed.
//!
//! **Which joints move.** Only the joints on the path from the root to the frame are sampled
//! (for a coupled mimic joint on the path, its leader); every other coordinate keeps its value in
//! [`ReachableParams::q0`] (the neutral configuration by default), since it cannot move the
//! frame. Floating joints (such as the `root_joint` of
//! [`RootJoint::Floating`](kinetree_kinematics::model::RootJoint::Floating)) are never sampled: they are held
//! at `q0`, so the cloud is expressed relative to the base placed there. Ranges: finite position
//! limits are used as they are; joints without finite limits use
//! [`sampling_range`](kinetree_kinematics::configuration::sampling_range) (angles in [-π, π], translations in
//! [-1, 1] m). Grid coordinates per joint kind: revolute, prismatic and continuous one (a
//! continuous joint's grid leaves out the end point π, which is -π again), cylindrical two
//! (displacement, angle), planar three (x, y in [-1, 1] m, θ), spherical three (the components of
//! a rotation vector, each in [-π, π], mapped to a quaternion by the exponential). A grid of one
//! point per coordinate takes the middle of each range.
//!
//! **Manipulability.** For each sample, `J` is the frame Jacobian in
//! [`ReferenceFrame::LocalWorldAligned`](kinetree_kinematics::ReferenceFrame::LocalWorldAligned) (world axes, at the frame origin) restricted to the
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
//! [`KinematicsData`](kinetree_kinematics::KinematicsData) and its buffers once, then evaluates its samples without allocating. A
//! random chunk seeds its own generator from `(seed, chunk index)`, so the result depends on the
//! seed only, never on the number of threads or the order in which chunks run.
//!
//! **From the samples.** [`ReachableSet`] gives the axis-aligned [`Bounds`], the maximum reach
//! from a point ([`ReachableSet::max_reach`]), a [`VoxelMap`] at a chosen resolution
//! ([`ReachableSet::voxelize`]) whose [`VoxelMap::is_reachable`] answers from the voxels actually
//! hit (not from the bounding box), and exports to CSV, PLY and JSON (`export.rs`).
//!
//! Sampling is an approximation from inside: a point reported reachable was reached (to within a
//! voxel), while a point reported unreachable may still be reachable between samples.

mod error;
mod export;
mod params;
mod sample;
mod set;
mod voxel;

pub use error::ReachableError;
pub use kinetree_kinematics as kinematics;
pub use params::{CHUNK_SIZE, MAX_SAMPLES, ReachableParams, Sampling, TaskSpace};
pub use sample::{sample_reachable, sample_reachable_with_progress};
pub use set::{Bounds, ReachableSet};
pub use voxel::{VoxelMap, VoxelStats};
