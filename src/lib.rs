#![doc = include_str!("../README.md")]
//!
//! ## This crate
//!
//! `kinetree` is the facade: it re-exports each layer as a module ([`spatial`], `model`,
//! `kinematics`, `dynamics`, `collision`, `workspace`), gathers the everyday names in [`prelude`], and wraps
//! every layer's error in one [`Error`] so that `?` works across layers.
//!
//! ## Optional cargo features
//! - `model` (default): [`model`], the `Model` type and the URDF/JSON loaders.
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

pub use error::Error;

/// `docs/from-the-seeds.md`, compiled and run as doc tests so its examples stay true.
#[cfg(doctest)]
#[doc = include_str!("../docs/from-the-seeds.md")]
pub struct FromTheSeeds;

/// The names most programs need, for `use kinetree::prelude::*;`.
///
/// # Examples
/// ```
/// use kinetree::prelude::*;
/// let world_from_tool = Se3::from_translation(DVec3::new(0.0, 0.0, 0.1));
/// assert_eq!(world_from_tool.transform_point(DVec3::ZERO).z, 0.1);
/// ```
pub mod prelude {
    pub use crate::Error;
    pub use crate::spatial::{DMat3, DQuat, DVec3, Force, Inertia, Motion, Se3, Symmetric3};

    #[cfg(feature = "model")]
    pub use crate::model::{JointKind, JointLimits, Model, ModelBuilder, ModelError, RootJoint};
    // The kinematics, dynamics and collision layers add their Data types, algorithms and
    // errors here as they land (for example `KinematicsData`, `forward_kinematics`, `rnea`).
}
