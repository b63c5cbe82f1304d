//! # kinetree-kinematics
//!
//! The kinematics layer of kinetree: forward kinematics ([`forward_kinematics`]), link and frame
//! placements, joint and frame Jacobians in three reference frames ([`ReferenceFrame`]) and their
//! time derivatives, their analytic [`derivatives`] with respect to `q`, `v` and `a`, and
//! configuration-space operations ([`configuration`]). It sits on
//! `kinetree-model`; the dynamics and collision layers sit on it.
//!
//! Algorithms are plain functions over `(&Model, &mut KinematicsData, inputs)`. A
//! [`KinematicsData`] holds every buffer they write; once it exists, no algorithm allocates.
//!
//! On top of them sit two convenience layers that own their state and may allocate:
//! [`Chain`] (set joints by name, query any part's pose, with world transforms cached and
//! recomputed only below a changed joint) and actuation groups ([`ActuationGroup`],
//! [`ActuatedChain`]: actuated coordinates mapped to the virtual joints of a sub-chain, e.g. a
//! linear actuator driving a knee; [`ActuatedChain::solve_ik`] answers in actuated coordinates,
//! [`ArgActuation`] takes arguments set at run time).
//!
//! [`codegen`] writes one frame's forward kinematics as straight-line Rust, C or Python (SymPy /
//! CasADi) source.
//!
//! ```
//! use kinetree_kinematics::{compute_frame_jacobian, configuration, forward_kinematics, FrameId,
//!                           KinematicsData, ReferenceFrame};
//! use kinetree_model::{Model, RootJoint};
//! use kinetree_model::spatial::Motion;
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/robots/panda.urdf");
//! let model = Model::from_urdf_file(path, RootJoint::Fixed)?;
//! let mut data = KinematicsData::new(&model);
//! let q = configuration::neutral_configuration(&model);
//! forward_kinematics(&model, &mut data, &q)?;
//! let hand = FrameId::find(&model, "panda_hand")?;
//! println!("hand at {}", data.world_from(hand)?.translation);
//! let mut jacobian = vec![Motion::ZERO; model.nv()];
//! compute_frame_jacobian(&model, &mut data, &q, hand, ReferenceFrame::LocalWorldAligned, &mut jacobian)?;
//! // The first joint turns about world z: its column's angular part is z.
//! assert!((jacobian[0].angular.z - 1.0).abs() < 1e-12);
//! # Ok(())
//! # }
//! ```
//!
//! ## Conventions
//! - SI units; `q` has `model.nq()` entries, `v`/`a` have `model.nv()` (layouts per joint kind in
//!   [`kinetree_model::JointKind`]; quaternions x, y, z, w).
//! - Spatial vectors and Jacobian rows are `[linear; angular]`; a Jacobian is `nv` [`Motion`](spatial::Motion)
//!   columns ([`jacobian_to_rows`] gives the 6 x nv matrix).
//! - Placements are `world_from_*` (`p_world = world_from_link.transform_point(p_link)`).
//! - Body velocities are twists in the body's own frame; floating-base velocities are in the base
//!   frame.
//!
//! ## Errors
//! [`KinematicsError`] names the offending input, joint or frame; wrong lengths and NaN inputs are
//! errors, never panics.
//!
//! ## Modules
//! - `data`: [`KinematicsData`] and [`FrameId`]; `error`: [`KinematicsError`].
//! - [`joint`]: the per-joint algebra (models, transforms, the Lie-group operations and their
//!   Jacobians), shared with the dynamics layer.
//! - `forward`: forward kinematics with velocities and accelerations, frame placements;
//!   `jacobian`: joint and frame Jacobians and their time derivatives; [`derivatives`]: their
//!   analytic derivatives; [`configuration`]: configuration-space operations.
//! - [`ik`]: the [`IkSolver`](ik::IkSolver) (`solver.rs`, one iteration in `step.rs`, its buffers
//!   in `scratch.rs`) and analytic seeders.
//! - `chain` and `chain_datums`: [`Chain`] and its files; `actuation`: actuation groups
//!   (`group.rs`), [`ActuatedChain`] (`chain.rs`), [`LinearActuator`] and actuated IK.
//! - [`codegen`]: forward kinematics as source code.
//! - [`batch`]: forward kinematics and frame Jacobians of many states per call, vectorised across
//!   states ([`KinematicsBatch`](batch::KinematicsBatch)).

mod actuation;
pub mod batch;
mod chain;
mod chain_datums;
pub mod codegen;
pub mod configuration;
mod data;
pub mod derivatives;
mod error;
mod forward;
pub mod ik;
mod jacobian;
pub mod joint;

pub use actuation::{
    ActuatedChain, Actuation, ActuationGroup, FnActuation, GroupSpec, LinearActuator,
    MappingDirection, ROUND_TRIP_TOLERANCE,
};
pub use actuation::{ActuatedIkReport, ActuationArgs, ArgActuation};
pub use chain::{Chain, ChainStats};
pub use data::{BodyBuffers, FrameId, KinematicsData};
pub use derivatives::{
    KinematicsDerivativesData, frame_acceleration_derivatives, frame_jacobian_derivatives,
    frame_velocity_derivatives,
};
pub use error::GroupProblem;
pub use error::{KinematicsError, QUATERNION_NORM_TOLERANCE};
pub use forward::{
    forward_kinematics, forward_kinematics_with_acceleration, forward_kinematics_with_velocity,
    frame_velocity, relative_transform, update_frame_placements, update_world_placements,
};
pub use jacobian::{
    ReferenceFrame, change_reference, compute_frame_jacobian, compute_joint_jacobians,
    compute_joint_jacobians_time_variation, compute_joint_jacobians_without_links, frame_jacobian,
    frame_jacobian_time_variation, jacobian_to_rows,
};
pub use joint::JointModel;
pub use joint::{difference_jacobians, integrate_jacobians};
pub use kinetree_model as model;
pub use kinetree_model::spatial;
