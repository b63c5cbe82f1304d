#![doc = include_str!("../README.md")]
//!
//! ## This crate
//!
//! `kinetree` is the facade: it re-exports each layer as a module ([`spatial`], `model`,
//! `kinematics`, `dynamics`, `collision`, `workspace`), gathers the everyday names in [`prelude`], and wraps
//! every layer's error in one [`Error`] so that `?` works across layers.
//!
//! ## Optional cargo features
//! - `model` (default): [`model`], the `Model` type and the URDF, MJCF and JSON loaders.
//! - `kinematics` (default, implies `model`): forward kinematics, Jacobians, IK.
//! - `dynamics` (default, implies `kinematics`): RNEA, CRBA, ABA.
//! - `collision` (default, implies `kinematics`): self and world collision.
//! - `workspace` (default, implies `kinematics`): reachable-workspace sampling, in parallel with
//!   rayon.
//!
//! With `default-features = false` only [`spatial`] is left.

pub use kinetree_spatial as spatial;

#[cfg(feature = "model")]
pub use kinetree_model as model;

#[cfg(feature = "kinematics")]
pub use kinetree_kinematics as kinematics;

#[cfg(feature = "dynamics")]
pub use kinetree_dynamics as dynamics;

#[cfg(feature = "collision")]
pub use kinetree_collision as collision;

#[cfg(feature = "workspace")]
pub use kinetree_workspace as workspace;

#[cfg(feature = "kinematics")]
pub mod batch;
mod error;
#[cfg(feature = "parallel")]
pub mod parallel;

pub use error::Error;

/// `docs/from-the-seeds.md`, compiled and run as doc tests so its examples stay true.
#[cfg(doctest)]
#[doc = include_str!("../docs/from-the-seeds.md")]
pub struct FromTheSeeds;

/// `docs/formats.md`, compiled and run as doc tests so its examples stay true.
#[cfg(doctest)]
#[doc = include_str!("../docs/formats.md")]
pub struct Formats;

/// The names most programs need, for `use kinetree::prelude::*;`: from every layer its Data
/// types, its main algorithms and its error (each behind the layer's feature).
///
/// # Examples
/// ```
/// use kinetree::prelude::*;
/// let world_from_tool = Se3::from_translation(DVec3::new(0.0, 0.0, 0.1));
/// assert_eq!(world_from_tool.transform_point(DVec3::ZERO).z, 0.1);
/// # #[cfg(feature = "dynamics")] {
/// let pendulum = kinetree::model::samples::pendulum();
/// let mut data = DynamicsData::new(&pendulum);
/// // Held horizontal (q = π/2), the 1 kg bob 1 m out needs m·g·l = 9.81 N·m.
/// let tau = rnea(&pendulum, &mut data, &[std::f64::consts::FRAC_PI_2], &[0.0], &[0.0])?;
/// assert!((tau[0] - 9.81).abs() < 1e-12);
/// # }
/// # Ok::<(), kinetree::Error>(())
/// ```
pub mod prelude {
    pub use crate::Error;
    pub use crate::spatial::{DMat3, DQuat, DVec3, Force, Inertia, Motion, Se3, Symmetric3};

    #[cfg(feature = "model")]
    pub use crate::model::{JointKind, JointLimits, Model, ModelBuilder, ModelError, RootJoint};

    #[cfg(feature = "kinematics")]
    pub use crate::kinematics::ik::{IkParams, IkSolver, IkTarget};
    #[cfg(feature = "kinematics")]
    pub use crate::kinematics::{
        Chain, FrameId, KinematicsData, KinematicsError, ReferenceFrame, compute_frame_jacobian,
        configuration, forward_kinematics, update_frame_placements,
    };

    #[cfg(feature = "dynamics")]
    pub use crate::dynamics::{
        DynamicsData, DynamicsError, aba, crba, generalized_gravity, nonlinear_effects, rnea,
    };

    #[cfg(feature = "collision")]
    pub use crate::collision::{
        CollisionData, CollisionError, CollisionModel, CollisionOptions, ObstacleScene,
        any_collision, compute_distances, compute_world_distances,
    };

    #[cfg(feature = "workspace")]
    pub use crate::workspace::{ReachableError, ReachableParams, sample_reachable};
}
