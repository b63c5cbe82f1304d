//! # kinetree-spatial
//!
//! The bottom layer of kinetree: rigid transforms ([`Se3`]), rotations, 6D motion and force
//! vectors ([`Motion`], [`Force`]) and spatial inertias ([`Inertia`], [`Symmetric3`]) on top of
//! glam. Every other layer computes with these types; none of them allocates.
//!
//! [`Se3`], [`Motion`] and [`Force`] are generic over their number type ([`Real`], `f64` by
//! default): the same type and the same code hold one state (`Se3` is glam's `DMat3` and
//! `DVec3`) or `L` states side by side in SIMD lanes ([`lanes`]), so that every algorithm of the
//! layers above is written once for both.
//!
//! The kernels of the body sweeps live here too, so that kinematics and dynamics share them:
//! [`OriginInertia`] (the composite-inertia form), [`RotationForm`] (rotations about a coordinate
//! axis applied in a few multiplications) and [`axis`] (cross products with a coordinate axis).
//!
//! ```
//! use kinetree_spatial::{explog, Motion, Se3};
//! use glam::DVec3;
//! // A link 0.5 m along x, turned 90° about z: where does its tip (1, 0, 0) go?
//! let world_from_link = Se3::new(Se3::from_rotation_z(std::f64::consts::FRAC_PI_2).rotation,
//!                                DVec3::new(0.5, 0.0, 0.0));
//! let tip = world_from_link.transform_point(DVec3::X);
//! assert!((tip - DVec3::new(0.5, 1.0, 0.0)).length() < 1e-15);
//! // The twist that moves the identity to that pose in unit time, and back.
//! let twist: Motion = explog::log6(&world_from_link);
//! assert!(explog::exp6(&twist).abs_diff_eq(&world_from_link, 1e-14, 1e-14));
//! ```
//!
//! ## Conventions
//! - SI units: metres, radians, kilograms, seconds.
//! - Spatial vectors are ordered `[linear; angular]` (forces: `[force; torque]`).
//!   [`Motion::to_featherstone`] and friends convert to Featherstone's `[angular; linear]`.
//! - Transforms are named `a_from_b`: `p_a = a_from_b.transform_point(p_b)`, composition
//!   `a_from_c = a_from_b * b_from_c`. `Se3::act_motion` / `act_force` express a vector given in
//!   `b` in frame `a`; `act_inv_*` go the other way.
//! - Quaternions (glam `DQuat`) are stored x, y, z, w.
//! - URDF roll-pitch-yaw is about fixed axes: `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
//!
//! ## Errors
//! This crate is pure maths and has no error type: functions document their preconditions
//! (for example that a rotation matrix is orthonormal), and the `*_checked` constructors return an
//! `Option` or a `Result` for data coming from outside.
//!
//! ## Optional cargo features
//! - `serde`: `Serialize`/`Deserialize` for the value types.
//!
//! ## Modules
//! - `se3`: [`Se3`], rigid transforms and their action on points, motions and forces.
//! - [`rotation`]: skew matrices, the SO(3) exponential and logarithm, roll-pitch-yaw and Euler
//!   angles; [`explog`]: the SE(3) exponential and logarithm.
//! - `motion`: [`Motion`] and [`Force`]; `symmetric3`: [`Symmetric3`]; `inertia`: [`Inertia`].
//! - The kernels the body sweeps share: `origin_inertia` ([`OriginInertia`]), `rotation_form`
//!   ([`RotationForm`]) and [`axis`] (cross products with a coordinate axis).
//! - `readable`: [`Readable`], numbers in messages (scientific notation when huge or tiny).
//! - [`real`]: [`Real`], the number types the spatial types and the algorithms are generic over
//!   (`f64` for one state, [`lanes::Lanes`] for a block of states), and the fast `sin_cos`.

pub mod axis;
pub mod explog;
mod inertia;
pub mod lanes;
mod motion;
mod origin_inertia;
mod readable;
pub mod real;
pub mod rotation;
mod rotation_form;
mod se3;
mod symmetric3;

pub use glam;
pub use glam::{DMat3, DMat4, DQuat, DVec3};
pub use inertia::Inertia;
pub use motion::{Force, Motion};
pub use origin_inertia::OriginInertia;
pub use readable::Readable;
pub use real::Real;
pub use rotation_form::RotationForm;
pub use se3::Se3;
pub use symmetric3::{InertiaDefect, Symmetric3};

/// A rotational inertia tensor (kg·m²): the name the `urdf` Python library and most textbooks
/// use for [`Symmetric3`]. Build it from its moments and products
/// ([`Symmetric3::from_moments_products`]), its six entries ([`Symmetric3::from_entries`]), a
/// 3x3 matrix ([`Symmetric3::from_mat3_checked`]) or Voigt order ([`Symmetric3::from_voigt`]);
/// read it back with [`Symmetric3::moments`], [`Symmetric3::products`],
/// [`Symmetric3::to_mat3`] and [`Symmetric3::to_voigt`].
pub type InertiaTensor = Symmetric3;
