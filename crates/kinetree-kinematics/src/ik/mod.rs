//! Inverse kinematics: joint positions that put one or more frames on target poses.
//!
//! [`IkSolver`] is a damped least-squares (Levenberg–Marquardt) solver on the SE(3) log error,
//! with adaptive damping, box constraints on the joint limits (every iterate respects them), a
//! null-space posture objective, and random restarts within an iteration and a time budget. It
//! works on every joint kind and on floating-base models (steps are integrated on each joint's
//! manifold), and by default moves only the joints on the paths from the root to the target
//! frames. Build it once per model with [`IkParams`]; a solve then allocates nothing.
//!
//! - [`IkTarget`]: a frame and its desired pose; full pose, position only, orientation only or
//!   any per-axis weighting, several at once (two feet and a hand) with a weight each.
//! - [`IkReport`]: status ([`IkStatus::Converged`], [`IkStatus::BestEffort`] with its residual,
//!   [`IkStatus::Failed`]), iterations, restarts, position and orientation errors, elapsed time,
//!   and `q`. Not converging is a status; bad inputs (unknown frame, NaN, wrong length) are
//!   [`KinematicsError`](crate::KinematicsError)s.
//! - [`PlanarTwoLink`]: the two-link planar arm in closed form (both elbows, reachability), and
//!   [`IkSeeder`], through which an analytic solver seeds the numeric one.
//!
//! # Examples
//! ```
//! use kinetree_kinematics::ik::{IkParams, IkSolver, IkTarget};
//! use kinetree_kinematics::{configuration, forward_kinematics, FrameId, KinematicsData};
//! use kinetree_kinematics::model::{Model, RootJoint};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/robots/panda.urdf");
//! let model = Model::from_urdf_file(path, RootJoint::Fixed)?;
//! let mut data = KinematicsData::new(&model);
//! let hand = FrameId::find(&model, "panda_hand")?;
//!
//! // A reachable target: where the hand is at some configuration.
//! let mut q_goal = configuration::neutral_configuration(&model);
//! q_goal[..7].copy_from_slice(&[0.3, -0.5, 0.2, -2.0, 0.1, 1.6, 0.7]);
//! forward_kinematics(&model, &mut data, &q_goal)?;
//! let goal = *data.world_from(hand)?;
//!
//! let mut solver = IkSolver::new(&model, IkParams::default());
//! let q0 = configuration::neutral_configuration(&model);
//! let report = solver.solve(&model, &mut data, &IkTarget::new(hand, goal), &q0)?;
//! assert!(report.is_converged());
//! assert!(report.position_error < 1e-6 && report.orientation_error < 1e-5);
//! // `data` now holds the forward kinematics of the solution.
//! assert!((data.world_from(hand)?.translation - goal.translation).length() < 1e-6);
//! println!("{} iterations, {} restarts, {:?}", report.iterations, report.restarts, report.elapsed);
//! # Ok(())
//! # }
//! ```

mod analytic;
mod cholesky;
mod params;
mod report;
mod scratch;
mod solver;
mod step;
mod target;

pub use analytic::{IkSeeder, PlanarTwoLink, TwoLinkSeeder, TwoLinkSolutions};
pub use params::{IkParams, MAX_TARGETS};
pub use report::{IkIterate, IkReport, IkStatus};
pub use solver::IkSolver;
pub use target::IkTarget;
