//! # kinetree-dynamics
//!
//! The dynamics layer of kinetree: how an articulated rigid body accelerates under torques,
//! gravity and external forces. Inverse dynamics ([`rnea`], [`nonlinear_effects`],
//! [`generalized_gravity`]), the joint-space mass matrix ([`crba`]) and its tree-sparse
//! factorization ([`factorize_mass_matrix`], [`solve_mass_matrix`], [`mass_matrix_inverse`]),
//! forward dynamics ([`aba`]), energies, centre of mass and centroidal momentum, a
//! fixed-step integrator ([`step`]) with optional inelastic joint-limit stops
//! ([`apply_hard_stops`]), and the analytic [`derivatives`] of inverse dynamics, gravity
//! and forward dynamics ([`rnea_derivatives`], [`aba_derivatives`]). It sits on `kinetree-kinematics` (re-exported as
//! [`kinematics`], with [`model`] and [`spatial`] below it).
//!
//! Algorithms are plain functions over `(&Model, &mut DynamicsData, inputs)` that return a borrow
//! of their result stored in the [`DynamicsData`], as Pinocchio returns `data.tau`. Once the
//! `DynamicsData` exists, no algorithm allocates.
//!
//! ```
//! use kinetree_dynamics::{aba, crba, rnea, DynamicsData};
//! use kinetree_dynamics::kinematics::configuration;
//! use kinetree_dynamics::model::{Model, RootJoint};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/reference/urdf/ur5.urdf");
//! let model = Model::from_urdf_file(path, RootJoint::Fixed)?;
//! let mut data = DynamicsData::new(&model);
//! let q = configuration::neutral_configuration(&model);
//! let (v, a) = (vec![0.1; model.nv()], vec![0.5; model.nv()]);
//! // Inverse dynamics: the torques for acceleration a …
//! let tau = rnea(&model, &mut data, &q, &v, &a)?.to_vec();
//! // … and forward dynamics gives a back.
//! let ddq = aba(&model, &mut data, &q, &v, &tau)?;
//! assert!(ddq.iter().zip(&a).all(|(x, y)| (x - y).abs() < 1e-9));
//! // The mass matrix, row-major: symmetric, positive diagonal.
//! let m = crba(&model, &mut data, &q)?;
//! assert!((m[1] - m[model.nv()]).abs() < 1e-15 && m[0] > 0.0);
//! # Ok(())
//! # }
//! ```
//!
//! ## Conventions
//! - SI units: kg, m, s, rad, N, N·m, J. Gravity is [`Model::gravity`](model::Model::gravity)
//!   (default `[0, 0, -9.81]` in the world frame).
//! - `q` has `model.nq()` entries; `v`, `a` (= `q̈`), `tau` have `model.nv()` (per-joint layouts in
//!   [`JointKind`](model::JointKind); quaternions x, y, z, w). Floating-base velocities and
//!   accelerations are `[linear; angular]` in the base frame, with `a` the derivative of that
//!   twist; the floating-base entries of `tau` are the wrench on the base in the base frame.
//! - Spatial vectors are `[linear; angular]` (forces `[force; torque]`); the [`exudyn`] helpers
//!   use Featherstone's `[angular; linear]`, as Exudyn does.
//! - Matrices (mass matrix and its inverse) are `nv x nv`, row-major, full and symmetric.
//! - The equations of motion are the rigid-body ones, `M(q)·q̈ + C(q, q̇)·q̇ + g(q) = τ + Σ Jᵀ·f_ext`,
//!   as in Pinocchio, RBDL and the reference data. The joints' armature, damping and friction
//!   from the model are opt-in: [`DynamicsData::with_joint_terms`] with
//!   [`JointTerms::FromModel`] adds them as described in [`JointTerms`].
//! - Mass properties count the moving bodies only: the links welded to the world (a fixed root
//!   and its fixed attachments) are left out of [`moving_mass`], the centre of mass and the
//!   energies, as in Pinocchio.
//!
//! ## Errors
//! [`DynamicsError`] names the offending input, joint or link: wrong lengths, NaN inputs, data
//! built for another model, unknown links in external forces, and singular mass matrices
//! (massless subtrees, naming the joints) are errors, never panics or NaN results.
//!
//! ## Modules
//! - `data`: [`DynamicsData`], every buffer the algorithms write; `error`: [`DynamicsError`].
//! - `rnea` (inverse dynamics, nonlinear effects, gravity), `crba` (the mass matrix), `aba`
//!   (forward dynamics), `factor` (the tree-sparse `Lᵀ·D·L` of M and M⁻¹), `external`
//!   ([`ExternalForces`]).
//! - `com` (mass, centre of mass, centroidal momentum), `energy` (kinetic and potential).
//! - `integrator` (fixed-step integration on the configuration manifold) and `limits` (joint
//!   limits during a simulation).
//! - [`derivatives`]: analytic derivatives of RNEA, gravity and ABA; [`exudyn`]: Exudyn-named
//!   helpers; `all_terms`: every quantity of one state, for the tools.
//! - [`batch`]: RNEA, ABA and CRBA of many states per call, vectorised across states
//!   ([`DynamicsBatch`](batch::DynamicsBatch)).
//!
//! ## Optional cargo features
//! None.

mod aba;
mod all_terms;
mod articulated;
pub mod batch;
mod com;
mod crba;
mod data;
pub mod derivatives;
mod energy;
mod error;
mod external;
pub mod exudyn;
mod factor;
mod integrator;
mod limits;
mod rnea;

pub use aba::{aba, aba_with_external_forces};
pub use all_terms::{AllTerms, compute_all_terms};
pub use com::{
    center_of_mass, center_of_mass_jacobian, center_of_mass_velocity, centroidal_momentum,
    moving_mass,
};
pub use crba::crba;
pub use data::{DynamicsData, JointTerms};
pub use derivatives::{
    AbaDerivatives, DerivativesData, RneaDerivatives, aba_derivatives,
    aba_derivatives_with_external_forces, generalized_gravity_derivatives, rnea_derivatives,
    rnea_derivatives_with_external_forces,
};
pub use energy::{kinetic_energy, mechanical_energy, potential_energy};
pub use error::DynamicsError;
pub use external::ExternalForces;
pub use factor::{factorize_mass_matrix, mass_matrix_inverse, solve_mass_matrix};
pub use integrator::{Integrator, step, step_with_external_forces};
pub use kinetree_kinematics as kinematics;
pub use kinetree_kinematics::{FrameId, ReferenceFrame, model, spatial};
pub use limits::{HardStopReport, LimitModel, apply_hard_stops, limited_coordinates};
pub use rnea::{generalized_gravity, nonlinear_effects, rnea, rnea_with_external_forces};
