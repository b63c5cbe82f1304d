//! [`DerivativesData`]: the buffers of the derivative algorithms, and their borrowed results.

use super::solve::DofTree;
use crate::data::{DynamicsData, JointTerms};
use crate::error::DynamicsError;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::glam::{DMat3, DVec3};
use kinetree_kinematics::spatial::{Force, Motion, Se3};

/// A spatial inertia about the world origin: mass `m`, first moment `h = m·c` and rotational
/// inertia `i` about the origin, as the 6x6 matrix `[[m·1, -[h]×], [[h]×, i]]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WorldInertia {
    pub(crate) m: f64,
    pub(crate) h: DVec3,
    pub(crate) i: DMat3,
}

impl WorldInertia {
    pub(crate) const ZERO: Self = Self {
        m: 0.0,
        h: DVec3::ZERO,
        i: DMat3::ZERO,
    };

    /// The momentum `Y·s`.
    #[inline(always)]
    pub(crate) fn mul(&self, s: &Motion) -> Force {
        Force::new(
            s.linear * self.m - self.h.cross(s.angular),
            self.h.cross(s.linear) + self.i * s.angular,
        )
    }

    #[inline(always)]
    pub(crate) fn add_assign(&mut self, o: &Self) {
        self.m += o.m;
        self.h += o.h;
        self.i += o.i;
    }
}

/// A symmetric 6x6 inertia (rigid or articulated) in world coordinates, in 3x3 blocks
/// `[[a, b], [bᵀ, c]]` acting on `[linear; angular]` motions.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Articulated {
    a: DMat3,
    b: DMat3,
    c: DMat3,
}

impl Articulated {
    pub(crate) const ZERO: Self = Self {
        a: DMat3::ZERO,
        b: DMat3::ZERO,
        c: DMat3::ZERO,
    };

    /// `self += y` for a rigid inertia `y`.
    #[inline(always)]
    pub(crate) fn add_rigid(&mut self, y: &WorldInertia) {
        self.a += DMat3::from_diagonal(DVec3::splat(y.m));
        self.b -= skew(y.h);
        self.c += y.i;
    }

    /// The momentum `self·s`.
    #[inline(always)]
    pub(crate) fn mul(&self, s: &Motion) -> Force {
        let (v, w) = (s.linear, s.angular);
        let b = &self.b;
        Force::new(
            self.a * v + *b * w,
            DVec3::new(b.x_axis.dot(v), b.y_axis.dot(v), b.z_axis.dot(v)) + self.c * w,
        )
    }

    /// `self -= x·yᵀ` (`x·yᵀ` symmetric).
    #[inline(always)]
    pub(crate) fn sub_outer(&mut self, x: &Force, y: &Force) {
        let outer = |p: DVec3, q: DVec3| DMat3::from_cols(p * q.x, p * q.y, p * q.z);
        self.a -= outer(x.linear, y.linear);
        self.b -= outer(x.linear, y.angular);
        self.c -= outer(x.angular, y.angular);
    }

    #[inline(always)]
    pub(crate) fn add_assign(&mut self, o: &Self) {
        self.a += o.a;
        self.b += o.b;
        self.c += o.c;
    }

    /// A magnitude for pivot tolerances: the traces of the diagonal blocks.
    #[inline(always)]
    pub(crate) fn scale(&self) -> f64 {
        (self.a.x_axis.x + self.a.y_axis.y + self.a.z_axis.z).abs()
            + (self.c.x_axis.x + self.c.y_axis.y + self.c.z_axis.z).abs()
    }
}

/// The skew matrix `[x]×` with `[x]×·y = x × y`.
#[inline(always)]
pub(crate) fn skew(x: DVec3) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(0.0, x.z, -x.y),
        DVec3::new(-x.z, 0.0, x.x),
        DVec3::new(x.y, -x.x, 0.0),
    )
}

/// A 6x6 operator on motions whose first (linear-input) block column may be zero:
/// `[[0, b], [c, d]]`, used for the external-force terms.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Blocks {
    pub(crate) b: DMat3,
    pub(crate) c: DMat3,
    pub(crate) d: DMat3,
}

impl Blocks {
    pub(crate) const ZERO: Self = Self {
        b: DMat3::ZERO,
        c: DMat3::ZERO,
        d: DMat3::ZERO,
    };

    /// `E·s` as a force.
    #[inline(always)]
    pub(crate) fn mul(&self, s: &Motion) -> Force {
        Force::new(self.b * s.angular, self.c * s.linear + self.d * s.angular)
    }

    /// `Eᵀ·s` as a force (a covector on motions).
    #[inline(always)]
    pub(crate) fn mul_transpose(&self, s: &Motion) -> Force {
        Force::new(
            self.c.transpose() * s.angular,
            self.b.transpose() * s.linear + self.d.transpose() * s.angular,
        )
    }

    #[inline(always)]
    pub(crate) fn add_assign(&mut self, o: &Self) {
        self.b += o.b;
        self.c += o.c;
        self.d += o.d;
    }
}

/// The buffers of the derivative algorithms for one [`Model`] (including a [`DynamicsData`] for
/// the forward dynamics and the mass-matrix factorization), and their results.
///
/// Create it once with [`DerivativesData::new`]; the derivative functions allocate nothing
/// afterwards (except on an error path). A `DerivativesData` must only be used with the model it
/// was created for (checked at entry).
#[derive(Clone, Debug)]
pub struct DerivativesData {
    pub(crate) dynamics: DynamicsData,
    pub(crate) nv: usize,
    /// Number of degrees of freedom in each body's subtree (itself included).
    pub(crate) nv_subtree: Vec<usize>,
    // Per body, world frame.
    pub(crate) world_from_body: Vec<Se3>,
    pub(crate) velocity: Vec<Motion>,
    pub(crate) acceleration: Vec<Motion>,
    /// The velocity-product acceleration `v_parent × v_joint`.
    pub(crate) bias: Vec<Motion>,
    pub(crate) force: Vec<Force>,
    pub(crate) composite: Vec<WorldInertia>,
    /// Subtree sum of the linear momenta (the `b` block of the inertia variation is `-2[p]×`).
    pub(crate) momentum: Vec<DVec3>,
    /// Subtree sum of the angular-angular block of the inertia variation.
    pub(crate) variation: Vec<DMat3>,
    /// Subtree sum of the external-force terms that do not turn with the body.
    pub(crate) external: Vec<Blocks>,
    // Per degree of freedom, world frame.
    pub(crate) s: Vec<Motion>,
    pub(crate) dv_dq: Vec<Motion>,
    pub(crate) da_dq: Vec<Motion>,
    pub(crate) da_dv: Vec<Motion>,
    pub(crate) df_dq: Vec<Force>,
    pub(crate) df_dv: Vec<Force>,
    pub(crate) df_da: Vec<Force>,
    pub(crate) zeros: Vec<f64>,
    // Forward dynamics: per body, the articulated inertias and bias forces; per degree of
    // freedom, `U = Iᴬ·s`, `1/D` and `u` of the articulated-body algorithm.
    pub(crate) articulated: Vec<Articulated>,
    pub(crate) articulated_force: Vec<Force>,
    pub(crate) u_column: Vec<Force>,
    pub(crate) pivot_inverse: Vec<f64>,
    pub(crate) u: Vec<f64>,
    // Results.
    pub(crate) tau: Vec<f64>,
    pub(crate) dtau_dq: Vec<f64>,
    pub(crate) dtau_dv: Vec<f64>,
    pub(crate) dtau_da: Vec<f64>,
    pub(crate) dg_dq: Vec<f64>,
    pub(crate) ddq: Vec<f64>,
    pub(crate) dddq_dq: Vec<f64>,
    pub(crate) dddq_dv: Vec<f64>,
    /// The ancestor lists for `M⁻¹` and the solves.
    pub(crate) tree: DofTree,
}

/// The partial derivatives of inverse dynamics, borrowed from a [`DerivativesData`]; each is
/// `nv x nv`, row-major (see the [module documentation](crate::derivatives) for the convention).
#[derive(Clone, Copy, Debug)]
pub struct RneaDerivatives<'d> {
    /// `τ = rnea(q, v, a)` itself (length `nv`).
    pub tau: &'d [f64],
    /// `∂τ/∂q` (tangent space).
    pub dtau_dq: &'d [f64],
    /// `∂τ/∂v`.
    pub dtau_dv: &'d [f64],
    /// `∂τ/∂a`: the mass matrix `M(q)` (plus the armature with `JointTerms::FromModel`).
    pub dtau_da: &'d [f64],
}

/// The partial derivatives of forward dynamics, borrowed from a [`DerivativesData`]; each is
/// `nv x nv`, row-major (see the [module documentation](crate::derivatives) for the convention).
#[derive(Clone, Copy, Debug)]
pub struct AbaDerivatives<'d> {
    /// `q̈ = aba(q, v, τ)` itself (length `nv`).
    pub ddq: &'d [f64],
    /// `∂q̈/∂q` (tangent space).
    pub dddq_dq: &'d [f64],
    /// `∂q̈/∂v`.
    pub dddq_dv: &'d [f64],
    /// `∂q̈/∂τ = M(q)⁻¹`.
    pub dddq_dtau: &'d [f64],
}

impl DerivativesData {
    /// Allocates every buffer for `model`, for the rigid-body dynamics (the joints' damping,
    /// friction and armature left out, [`JointTerms::Ignored`]), as [`DynamicsData::new`].
    #[must_use]
    pub fn new(model: &Model) -> Self {
        Self::with_joint_terms(model, JointTerms::Ignored)
    }

    /// Allocates every buffer for `model`, choosing whether the joints' damping, friction and
    /// armature enter (see [`JointTerms`]).
    #[must_use]
    pub fn with_joint_terms(model: &Model, joint_terms: JointTerms) -> Self {
        let nv = model.nv();
        let nb = model.nbodies();
        let bodies = model.bodies();
        let mut nv_subtree = vec![0; nb];
        for i in (1..nb).rev() {
            nv_subtree[i] += bodies[i].nv;
            let p = bodies[i].parent;
            if p != 0 {
                nv_subtree[p] += nv_subtree[i];
            }
        }
        let m = |n| vec![Motion::ZERO; n];
        let f = |n| vec![Force::ZERO; n];
        let x = |n| vec![0.0; n];
        let dynamics = DynamicsData::with_joint_terms(model, joint_terms);
        let tree = DofTree::new(&dynamics.dof_parent);
        Self {
            dynamics,
            nv,
            nv_subtree,
            world_from_body: vec![Se3::IDENTITY; nb],
            velocity: m(nb),
            acceleration: m(nb),
            bias: m(nb),
            force: f(nb),
            composite: vec![WorldInertia::ZERO; nb],
            momentum: vec![DVec3::ZERO; nb],
            variation: vec![DMat3::ZERO; nb],
            external: vec![Blocks::ZERO; nb],
            s: m(nv),
            dv_dq: m(nv),
            da_dq: m(nv),
            da_dv: m(nv),
            df_dq: f(nv),
            df_dv: f(nv),
            df_da: f(nv),
            zeros: x(nv),
            articulated: vec![Articulated::ZERO; nb],
            articulated_force: f(nb),
            u_column: f(nv),
            pivot_inverse: x(nv),
            u: x(nv),
            tau: x(nv),
            dtau_dq: x(nv * nv),
            dtau_dv: x(nv * nv),
            dtau_da: x(nv * nv),
            dg_dq: x(nv * nv),
            ddq: x(nv),
            dddq_dq: x(nv * nv),
            dddq_dv: x(nv * nv),
            tree,
        }
    }

    /// Switches the joints' damping, friction and armature on or off (see [`JointTerms`]).
    ///
    /// # Errors
    /// [`DynamicsError::DataMismatch`] when `self` belongs to another model.
    pub fn set_joint_terms(
        &mut self,
        model: &Model,
        joint_terms: JointTerms,
    ) -> Result<(), DynamicsError> {
        self.dynamics.set_joint_terms(model, joint_terms)
    }

    /// The [`DynamicsData`] used by the forward-dynamics derivatives (its mass matrix, inverse
    /// and factorization are those of the last [`aba_derivatives`](crate::aba_derivatives)).
    #[must_use]
    pub fn dynamics(&self) -> &DynamicsData {
        &self.dynamics
    }

    /// `∂τ/∂q` of the last [`rnea_derivatives`](crate::rnea_derivatives) (or of the last
    /// [`aba_derivatives`](crate::aba_derivatives), at `a = q̈`).
    #[must_use]
    pub fn dtau_dq(&self) -> &[f64] {
        &self.dtau_dq
    }

    /// `∂τ/∂v` of the last inverse- or forward-dynamics derivatives.
    #[must_use]
    pub fn dtau_dv(&self) -> &[f64] {
        &self.dtau_dv
    }

    /// `∂τ/∂a = M(q)` of the last inverse- or forward-dynamics derivatives.
    #[must_use]
    pub fn dtau_da(&self) -> &[f64] {
        &self.dtau_da
    }

    /// `∂g/∂q` of the last [`generalized_gravity_derivatives`](crate::generalized_gravity_derivatives).
    #[must_use]
    pub fn dg_dq(&self) -> &[f64] {
        &self.dg_dq
    }

    /// `∂q̈/∂q` of the last [`aba_derivatives`](crate::aba_derivatives).
    #[must_use]
    pub fn dddq_dq(&self) -> &[f64] {
        &self.dddq_dq
    }

    /// `∂q̈/∂v` of the last [`aba_derivatives`](crate::aba_derivatives).
    #[must_use]
    pub fn dddq_dv(&self) -> &[f64] {
        &self.dddq_dv
    }

    /// `∂q̈/∂τ = M(q)⁻¹` of the last [`aba_derivatives`](crate::aba_derivatives).
    #[must_use]
    pub fn dddq_dtau(&self) -> &[f64] {
        self.dynamics.mass_matrix_inverse()
    }

    pub(crate) fn rnea_result(&self) -> RneaDerivatives<'_> {
        RneaDerivatives {
            tau: &self.tau,
            dtau_dq: &self.dtau_dq,
            dtau_dv: &self.dtau_dv,
            dtau_da: &self.dtau_da,
        }
    }
}
