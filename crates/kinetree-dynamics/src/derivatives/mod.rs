//! Analytic derivatives of the dynamics: of inverse dynamics ([`rnea_derivatives`]), of the
//! generalized gravity ([`generalized_gravity_derivatives`]) and of forward dynamics
//! ([`aba_derivatives`]).
//!
//! # Tangent-space convention
//!
//! A derivative with respect to `q` is taken in the tangent space of the configuration space:
//! column `k` of `∂f/∂q` is `d f(q ⊕ ε·e_k) / dε` at `ε = 0`, where `⊕` is
//! [`configuration::integrate`](kinetree_kinematics::configuration::integrate). So `∂f/∂q` is
//! `nv x nv`, not `nv x nq`: for a revolute, continuous or prismatic joint the column is the
//! ordinary partial derivative with respect to the angle or distance; for a spherical joint it is
//! the derivative along an angular velocity in the child frame (`q · exp(ω)`); for a planar joint
//! along `(vx, vy, ω)` in the child frame; for a floating base along a body-frame twist
//! `[linear; angular]` (`q · exp6(ξ)`), as Pinocchio's derivatives. Derivatives with respect to
//! `v`, `a` and `τ` are ordinary ones. Every matrix is `nv x nv`, row-major (`m[i * nv + j]` is
//! `∂fᵢ/∂xⱼ`), rows and columns in the model's `v` order.
//!
//! # Joint damping, friction and armature
//!
//! With [`JointTerms::FromModel`](crate::JointTerms::FromModel) the armature `r` adds to the
//! diagonal of `∂τ/∂a` (the mass matrix), the damping `d` to the diagonal of `∂τ/∂v` (and so
//! `-M⁻¹·diag(d)` to `∂q̈/∂v`). Coulomb friction `μ·sign(q̇)` is piecewise constant: its derivative
//! is zero for `q̇ ≠ 0` and undefined at `q̇ = 0`, where these functions also return zero (the
//! derivative of the `sign(0) = 0` branch), never an impulse.
//!
//! # Method
//!
//! One forward and one backward sweep in world coordinates (the recursive scheme of Carpentier &
//! Mansard, *Analytical derivatives of rigid body dynamics algorithms*, RSS 2018): the motion of a
//! joint moves its whole subtree rigidly, which leaves the projections `Sᵀ·F` of the bodies it
//! carries unchanged, so only the velocity-, acceleration- and force-dependent parts need
//! propagating. O(n·d) for a tree of n degrees of freedom and depth d. Forward-dynamics
//! derivatives follow from `M·q̈ = τ - b(q, v)`: `∂q̈/∂x = -M⁻¹·∂τ/∂x` evaluated at `q̈ =
//! aba(q, v, τ)`, with `M⁻¹` and the solves from the tree-sparse factorization `M = Lᵀ·D·L`
//! (as [`factorize_mass_matrix`](crate::factorize_mass_matrix)), never a dense inverse. The
//! articulated-body pass that gives `q̈` gives that factorization too: its pivots are `D`, and
//! `L[i][j] = s_jᵀ·U_i / D_i` for each ancestor `j` of `i` (`U_i = Iᴬ·s_i`).

mod aba;
mod data;
mod rnea;
pub(crate) mod solve;

pub use aba::{aba_derivatives, aba_derivatives_with_external_forces};
pub use data::{AbaDerivatives, DerivativesData, RneaDerivatives};
pub use rnea::{
    generalized_gravity_derivatives, rnea_derivatives, rnea_derivatives_with_external_forces,
};
