//! Per-joint algebra, in one place: adding a joint kind touches this folder (and the model's
//! [`JointKind`](kinetree_model::JointKind)).
//!
//! - [`JointModel`] (`model.rs`): the joint kinds specialised by axis, their sizes `nq`/`nv`,
//!   motion subspaces and the axis-aligned kernels of the sweeps.
//! - `transform.rs`: the fast [`sin_cos`] (re-exported from kinetree-spatial), [`JointModel::placed_transform`] (`parent_from_child`
//!   of a placed joint) and its factored form for composite inertias
//!   ([`JointModel::placed_transform_factored`], [`JointRot`]).
//! - `lie_group.rs`: each joint's configuration manifold: [`integrate_joint`],
//!   [`difference_joint`], [`wrap_angle`], [`JointModel::dexp_inv`], and the Jacobians of
//!   integrate and difference in both arguments ([`integrate_jacobians`],
//!   [`difference_jacobians`]).
//!
//! Forward kinematics, the Jacobians and the dynamics sweeps (RNEA, CRBA, ABA) all go through
//! these kernels and the spatial ones of `kinetree-spatial`.
//!
//! ```
//! use kinetree_kinematics::joint::JointModel;
//! use kinetree_kinematics::spatial::Se3;
//! let x = JointModel::RevoluteZ.placed_transform(&Se3::IDENTITY, &[std::f64::consts::FRAC_PI_2]);
//! assert!((x.rotation.x_axis.y - 1.0).abs() < 1e-15);
//! assert_eq!((JointModel::Floating.nq(), JointModel::Floating.nv()), (7, 6));
//! ```

mod lie_group;
mod model;
pub(crate) mod transform;

pub use lie_group::{
    difference_jacobians, difference_joint, integrate_jacobians, integrate_joint, wrap_angle,
};
pub use model::JointModel;
pub(crate) use model::axis_column;
pub use transform::{JointRot, sin_cos};
