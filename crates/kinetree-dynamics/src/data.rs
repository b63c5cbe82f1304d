//! [`DynamicsData`]: every buffer the dynamics algorithms write, allocated once per model.

use crate::articulated::ArticulatedInertia;
use crate::error::DynamicsError;
use kinetree_kinematics::JointModel;
use kinetree_kinematics::KinematicsData;
use kinetree_kinematics::joint::JointRot;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::{Force, Motion, OriginInertia, RotationForm};

/// Marks "no parent" in the degree-of-freedom parent array.
pub(crate) const NO_PARENT: usize = usize::MAX;

/// CRBA's step from a body `j` to its parent `p` while a force column is carried up to every
/// ancestor: the few numbers that walk reads, kept apart from the large [`Body`] records.
///
/// [`Body`]: kinetree_kinematics::model::Body
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct AncestorStep {
    /// The parent `p` (0: `j` hangs from the root, and the walk ends at `j`).
    pub(crate) parent: usize,
    /// `p`'s first velocity index.
    pub(crate) parent_v: usize,
    /// How `p`'s rows read a force: `0..6` the single component (`[linear; angular]` order) of a
    /// joint about or along a coordinate axis, else [`AncestorStep::FLOATING`] or
    /// [`AncestorStep::GENERAL`].
    pub(crate) kind: u8,
    /// `p` has an axis kind and hangs from the root: its entry is the last of the walk.
    pub(crate) last: bool,
    /// `j` has no child: its composite inertia is its own.
    pub(crate) leaf: bool,
    /// `j` is `p`'s last child (highest index), the first the backward sweep reaches: its moved
    /// composite inertia starts `p`'s sum (`p`'s own inertia plus it).
    pub(crate) opens_parent: bool,
}

impl AncestorStep {
    /// `kind` of a floating parent: its rows are the wrench itself.
    pub(crate) const FLOATING: u8 = 6;
    /// `kind` of any other parent: `JointModel::project_force`.
    pub(crate) const GENERAL: u8 = 7;

    fn table(model: &Model) -> Vec<Self> {
        let bodies = model.bodies();
        let joint_models: Vec<JointModel> = bodies.iter().map(JointModel::from_body).collect();
        // The last child of each body (0: none).
        let mut last_child = vec![0; bodies.len()];
        for (i, b) in bodies.iter().enumerate().skip(1) {
            last_child[b.parent] = i;
        }
        bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let p = b.parent;
                let (leaf, opens_parent) = (last_child[i] == 0, i > 0 && last_child[p] == i);
                if p == 0 {
                    return Self {
                        parent: 0,
                        parent_v: 0,
                        kind: Self::GENERAL,
                        last: false,
                        leaf,
                        opens_parent,
                    };
                }
                let kind = match joint_models[p].axis_index() {
                    Some((k, angular)) => (k + 3 * usize::from(angular)) as u8,
                    None if joint_models[p] == JointModel::Floating => Self::FLOATING,
                    None => Self::GENERAL,
                };
                Self {
                    parent: p,
                    parent_v: bodies[p].idx_v,
                    kind,
                    last: kind < 6 && bodies[p].parent == 0,
                    leaf,
                    opens_parent,
                }
            })
            .collect()
    }
}

/// Whether the joints' damping, friction and armature ([`JointDynamics`]) enter the equations of
/// motion.
///
/// By default ([`JointTerms::Ignored`], what [`DynamicsData::new`] uses) every algorithm computes
/// the textbook rigid-body quantities, as Pinocchio, RBDL and Featherstone's book mean by RNEA,
/// CRBA and ABA: `M(q)·q̈ + C(q, q̇)·q̇ + g(q) = τ + Jᵀ·f_ext`. They are smooth in `(q, q̇)`, and
/// they agree with the Pinocchio reference data.
///
/// With [`JointTerms::FromModel`] (opt-in, [`DynamicsData::with_joint_terms`]) every algorithm
/// also uses, per degree of freedom of a joint, the joint's `armature` `r`, `damping` `d` and
/// `friction` `μ`:
///
/// `(M(q) + diag(r))·q̈ + C(q, q̇)·q̇ + g(q) + d·q̇ + μ·sign(q̇) = τ + Jᵀ·f_ext`
///
/// - armature (rotor inertia reflected through the gearbox) is added to the diagonal of the mass
///   matrix ([`crba`](crate::crba)), to the joint's articulated inertia ([`aba`](crate::aba)),
///   and as `r·q̈` to [`rnea`](crate::rnea); the kinetic energy gains `½·r·q̇²`;
/// - damping is a viscous torque `-d·q̇` acting on the joint: [`rnea`](crate::rnea) and
///   [`nonlinear_effects`](crate::nonlinear_effects) add `d·q̇` to the torque they return,
///   [`aba`](crate::aba) subtracts it from the applied torque;
/// - friction is Coulomb (sliding) friction `-μ·sign(q̇)` with `sign(0) = 0`, treated like damping.
///   Static friction (sticking at `q̇ = 0`) is not modelled, and the term is discontinuous at
///   `q̇ = 0` (so derivatives of the dynamics do not exist there): a simulation with friction
///   chatters around rest unless the time step is small.
///
/// URDF files give damping and friction in `<dynamics>`; without that element they are zero. A
/// simulation of the real machine wants them (`kinetree simulate` turns them on by default).
///
/// [`JointDynamics`]: kinetree_kinematics::model::JointDynamics
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum JointTerms {
    /// Use each joint's damping, friction and armature from the model (opt-in).
    FromModel,
    /// Ignore them: rigid-body dynamics only, as Pinocchio's algorithms (the default).
    #[default]
    Ignored,
}

/// The buffers of the dynamics algorithms for one [`Model`]: joint torques, the mass matrix and
/// its factorization, accelerations, per-body spatial quantities, centre-of-mass results and the
/// integrator's stages. It contains a [`KinematicsData`] ([`DynamicsData::kinematics`]).
///
/// Create it once with [`DynamicsData::new`]; no algorithm of this crate allocates afterwards
/// (except on an error path, to name the offending joints). A `DynamicsData` must only be used
/// with the model it was created for (checked at entry of every algorithm by comparing sizes).
#[derive(Clone, Debug)]
pub struct DynamicsData {
    pub(crate) kinematics: KinematicsData,
    pub(crate) nq: usize,
    pub(crate) nv: usize,
    pub(crate) nbodies: usize,
    pub(crate) nlinks: usize,
    pub(crate) nframes: usize,
    /// A coupled mimic joint of the model, if any: the dynamics algorithms do not support them.
    pub(crate) coupled_mimic: Option<String>,
    pub(crate) joint_terms: JointTerms,
    /// Whether any of `armature`, `damping`, `friction` is nonzero.
    pub(crate) has_joint_terms: bool,
    pub(crate) armature: Vec<f64>,
    pub(crate) damping: Vec<f64>,
    pub(crate) friction: Vec<f64>,
    /// Body of each degree of freedom.
    pub(crate) dof_body: Vec<usize>,
    /// Parent degree of freedom (Featherstone's λ for the mass matrix sparsity), or `NO_PARENT`.
    pub(crate) dof_parent: Vec<usize>,
    /// Per body: CRBA's step from it to its parent (see [`AncestorStep`]).
    pub(crate) ancestor_step: Vec<AncestorStep>,
    // Per body.
    // Placements and body velocities live in `kinematics`. ABA's world-frame velocities and the
    // spatial accelerations of RNEA (body frame) and ABA (world frame), which include gravity
    // (Pinocchio's `a_gf`), are quantities of their own.
    pub(crate) world_velocity: Vec<Motion>,
    pub(crate) acceleration: Vec<Motion>,
    pub(crate) force: Vec<Force>,
    pub(crate) composite: Vec<OriginInertia>,
    /// Each body's inertia about its origin (constant, from the model).
    pub(crate) body_inertia: Vec<OriginInertia>,
    /// The form of each body's placement rotation (constant, from the model).
    pub(crate) placement_rot: Vec<RotationForm>,
    /// Per body, the coordinate axis its revolute joint turns about alone, else 3
    /// ([`turn_axes`](crate::rnea::turn_axes)).
    pub(crate) turn: Vec<u8>,
    /// The joint rotation of each body in the last sweep, when about a coordinate axis.
    pub(crate) joint_rot: Vec<JointRot>,
    pub(crate) articulated: Vec<ArticulatedInertia>,
    pub(crate) bias: Vec<Motion>,
    /// Offset of each body's block in `dinv` (sum of the squares of the preceding `nv`s).
    pub(crate) dinv_offset: Vec<usize>,
    // Per degree of freedom.
    pub(crate) subspace: Vec<Motion>,
    pub(crate) u_columns: Vec<Force>,
    pub(crate) u: Vec<f64>,
    pub(crate) dinv: Vec<f64>,
    // Results.
    pub(crate) tau: Vec<f64>,
    pub(crate) nle: Vec<f64>,
    pub(crate) gravity_torque: Vec<f64>,
    pub(crate) ddq: Vec<f64>,
    pub(crate) mass_matrix: Vec<f64>,
    pub(crate) factor: Vec<f64>,
    pub(crate) factorized: bool,
    pub(crate) mass_matrix_inverse: Vec<f64>,
    pub(crate) com: DVec3,
    pub(crate) com_velocity: DVec3,
    pub(crate) com_jacobian: Vec<DVec3>,
    pub(crate) subtree_mass: Vec<f64>,
    pub(crate) subtree_moment: Vec<DVec3>,
    pub(crate) centroidal_momentum: Force,
    // Integrator stages.
    pub(crate) q_stage: Vec<f64>,
    pub(crate) v_stage: Vec<f64>,
    pub(crate) theta: Vec<f64>,
    pub(crate) k_vel: [Vec<f64>; 4],
    pub(crate) k_acc: [Vec<f64>; 4],
}

impl DynamicsData {
    /// Allocates every buffer for `model`, for the rigid-body dynamics: the joints' damping,
    /// friction and armature are left out ([`JointTerms::Ignored`]); opt in with
    /// [`DynamicsData::with_joint_terms`] and [`JointTerms::FromModel`].
    #[must_use]
    pub fn new(model: &Model) -> Self {
        Self::with_joint_terms(model, JointTerms::Ignored)
    }

    /// Allocates every buffer for `model`, choosing whether the joints' damping, friction and
    /// armature enter the dynamics (see [`JointTerms`]).
    #[must_use]
    pub fn with_joint_terms(model: &Model, joint_terms: JointTerms) -> Self {
        let nv = model.nv();
        let nb = model.nbodies();
        let bodies = model.bodies();
        let mut dof_body = vec![0; nv];
        let mut dof_parent = vec![NO_PARENT; nv];
        let mut dinv_offset = vec![0; nb + 1];
        // The last degree of freedom of each body (or NO_PARENT for the world).
        let mut last_dof = vec![NO_PARENT; nb];
        for (i, b) in bodies.iter().enumerate() {
            dinv_offset[i + 1] = dinv_offset[i] + b.nv * b.nv;
            if i == 0 {
                continue;
            }
            for k in 0..b.nv {
                let d = b.idx_v + k;
                dof_body[d] = i;
                dof_parent[d] = if k > 0 { d - 1 } else { last_dof[b.parent] };
            }
            last_dof[i] = if b.nv > 0 {
                b.idx_v + b.nv - 1
            } else {
                last_dof[b.parent]
            };
        }
        let kinematics = KinematicsData::new(model);
        let mut data = Self {
            kinematics,
            nq: model.nq(),
            nv,
            nbodies: nb,
            nlinks: model.links().len(),
            nframes: model.frames().len(),
            coupled_mimic: model
                .bodies()
                .iter()
                .find(|b| b.mimic.is_some())
                .and_then(|b| b.joint)
                .map(|j| model.joint(j).name.clone()),
            joint_terms,
            has_joint_terms: false,
            armature: vec![0.0; nv],
            damping: vec![0.0; nv],
            friction: vec![0.0; nv],
            dof_body,
            dof_parent,
            ancestor_step: AncestorStep::table(model),
            world_velocity: vec![Motion::ZERO; nb],
            acceleration: vec![Motion::ZERO; nb],
            force: vec![Force::ZERO; nb],
            composite: vec![OriginInertia::ZERO; nb],
            body_inertia: bodies
                .iter()
                .map(|b| OriginInertia::from_inertia(&b.inertia))
                .collect(),
            placement_rot: bodies
                .iter()
                .map(|b| RotationForm::classify(&b.placement.rotation))
                .collect(),
            turn: Vec::new(),
            joint_rot: vec![JointRot::NONE; nb],
            articulated: vec![ArticulatedInertia::default(); nb],
            bias: vec![Motion::ZERO; nb],
            subspace: vec![Motion::ZERO; nv],
            u_columns: vec![Force::ZERO; nv],
            u: vec![0.0; nv],
            dinv: vec![0.0; dinv_offset[nb]],
            dinv_offset,
            tau: vec![0.0; nv],
            nle: vec![0.0; nv],
            gravity_torque: vec![0.0; nv],
            ddq: vec![0.0; nv],
            mass_matrix: vec![0.0; nv * nv],
            factor: vec![0.0; nv * nv],
            factorized: false,
            mass_matrix_inverse: vec![0.0; nv * nv],
            com: DVec3::ZERO,
            com_velocity: DVec3::ZERO,
            com_jacobian: vec![DVec3::ZERO; nv],
            subtree_mass: vec![0.0; nb],
            subtree_moment: vec![DVec3::ZERO; nb],
            centroidal_momentum: Force::ZERO,
            q_stage: vec![0.0; model.nq()],
            v_stage: vec![0.0; nv],
            theta: vec![0.0; nv],
            k_vel: core::array::from_fn(|_| vec![0.0; nv]),
            k_acc: core::array::from_fn(|_| vec![0.0; nv]),
        };
        data.fill_joint_terms(model, joint_terms);
        data.turn = crate::rnea::turn_axes(data.kinematics.joint_models(), &data.placement_rot);
        data
    }

    /// Switches the joints' damping, friction and armature on or off (see [`JointTerms`]).
    /// Allocates nothing.
    ///
    /// # Errors
    /// [`DynamicsError::DataMismatch`] when `self` belongs to another model.
    pub fn set_joint_terms(
        &mut self,
        model: &Model,
        joint_terms: JointTerms,
    ) -> Result<(), DynamicsError> {
        self.check_model(model)?;
        self.fill_joint_terms(model, joint_terms);
        Ok(())
    }

    fn fill_joint_terms(&mut self, model: &Model, joint_terms: JointTerms) {
        self.joint_terms = joint_terms;
        self.armature.fill(0.0);
        self.damping.fill(0.0);
        self.friction.fill(0.0);
        if joint_terms == JointTerms::FromModel {
            for b in model.bodies().iter().skip(1) {
                let Some(j) = b.joint else { continue };
                let dynamics = model.joint(j).dynamics;
                for k in b.idx_v..b.idx_v + b.nv {
                    self.armature[k] = dynamics.armature;
                    self.damping[k] = dynamics.damping;
                    self.friction[k] = dynamics.friction;
                }
            }
        }
        self.has_joint_terms = [&self.armature, &self.damping, &self.friction]
            .iter()
            .any(|x| x.iter().any(|&y| y != 0.0));
        // The factorization belongs to the old mass matrix.
        self.factorized = false;
    }

    /// Whether the joints' damping, friction and armature are used (see [`JointTerms`]).
    #[must_use]
    pub fn joint_terms(&self) -> JointTerms {
        self.joint_terms
    }

    /// Checks that this data belongs to `model`.
    ///
    /// # Errors
    /// [`DynamicsError::DataMismatch`].
    pub fn check_model(&self, model: &Model) -> Result<(), DynamicsError> {
        if self.nbodies != model.nbodies()
            || self.nv != model.nv()
            || self.nq != model.nq()
            || self.nlinks != model.links().len()
            || self.nframes != model.frames().len()
            || self.kinematics.check_model(model).is_err()
        {
            return Err(DynamicsError::DataMismatch {
                what: "data",
                data_bodies: self.nbodies,
                data_nv: self.nv,
                model_bodies: model.nbodies(),
                model_nv: model.nv(),
            });
        }
        if let Some(joint) = &self.coupled_mimic {
            return Err(DynamicsError::CoupledMimic {
                joint: joint.clone(),
            });
        }
        Ok(())
    }

    /// The kinematics buffers: the one home of the configuration, placements and velocities the
    /// dynamics sweeps compute (as Pinocchio's single `Data`).
    /// - [`rnea`](crate::rnea), [`nonlinear_effects`](crate::nonlinear_effects),
    ///   [`generalized_gravity`](crate::generalized_gravity), [`crba`](crate::crba),
    ///   [`aba`](crate::aba) and the functions built on them leave their `q` and each body's
    ///   [`parent_from_body`](KinematicsData::parent_from_body);
    ///   [`update_world_placements`](kinetree_kinematics::update_world_placements) turns these
    ///   into the world placements of every body and link (what forward kinematics would give,
    ///   without its trigonometry). The sweeps do not do it themselves: it would cost RNEA and
    ///   CRBA 5–30 %.
    /// - The RNEA family also leaves the body velocities of
    ///   [`forward_kinematics_with_velocity`](kinetree_kinematics::forward_kinematics_with_velocity)
    ///   (zero where the function takes no `v`); [`aba`](crate::aba) leaves the world placements
    ///   of the bodies (not yet of the links).
    /// - The centre-of-mass, energy and momentum functions run forward kinematics here.
    #[inline]
    #[must_use]
    pub fn kinematics(&self) -> &KinematicsData {
        &self.kinematics
    }

    /// Mutable access to the kinematics buffers, to run kinematics algorithms on them.
    #[inline]
    #[must_use]
    pub fn kinematics_mut(&mut self) -> &mut KinematicsData {
        &mut self.kinematics
    }

    /// The joint torques of the last [`rnea`](crate::rnea) (length `nv`).
    #[inline]
    #[must_use]
    pub fn tau(&self) -> &[f64] {
        &self.tau
    }

    /// The nonlinear effects `C(q, q̇)·q̇ + g(q)` of the last
    /// [`nonlinear_effects`](crate::nonlinear_effects) (length `nv`).
    #[inline]
    #[must_use]
    pub fn nle(&self) -> &[f64] {
        &self.nle
    }

    /// The generalized gravity `g(q)` of the last
    /// [`generalized_gravity`](crate::generalized_gravity) (length `nv`).
    #[inline]
    #[must_use]
    pub fn gravity_torque(&self) -> &[f64] {
        &self.gravity_torque
    }

    /// The joint accelerations `q̈` of the last [`aba`](crate::aba) (length `nv`).
    #[inline]
    #[must_use]
    pub fn ddq(&self) -> &[f64] {
        &self.ddq
    }

    /// The joint-space mass matrix of the last [`crba`](crate::crba): `nv x nv`, row-major, full
    /// and symmetric (`m[i * nv + j]`).
    #[inline]
    #[must_use]
    pub fn mass_matrix(&self) -> &[f64] {
        &self.mass_matrix
    }

    /// The inverse mass matrix of the last
    /// [`mass_matrix_inverse`](crate::mass_matrix_inverse): `nv x nv`, row-major, full and
    /// symmetric.
    #[inline]
    #[must_use]
    pub fn mass_matrix_inverse(&self) -> &[f64] {
        &self.mass_matrix_inverse
    }

    /// The centre of mass (world frame) of the last centre-of-mass computation.
    #[inline]
    #[must_use]
    pub fn com(&self) -> DVec3 {
        self.com
    }

    /// The centre-of-mass velocity (world frame) of the last
    /// [`center_of_mass_velocity`](crate::center_of_mass_velocity).
    #[inline]
    #[must_use]
    pub fn com_velocity(&self) -> DVec3 {
        self.com_velocity
    }

    /// The centre-of-mass Jacobian of the last
    /// [`center_of_mass_jacobian`](crate::center_of_mass_jacobian): `nv` columns (world frame).
    #[inline]
    #[must_use]
    pub fn com_jacobian(&self) -> &[DVec3] {
        &self.com_jacobian
    }

    /// The centroidal momentum of the last
    /// [`centroidal_momentum`](crate::centroidal_momentum).
    #[inline]
    #[must_use]
    pub fn centroidal_momentum(&self) -> Force {
        self.centroidal_momentum
    }

    /// Spatial velocity of each body in its own frame after [`rnea`](crate::rnea) (index 0 is
    /// the world): the embedded kinematics data's
    /// [`body_velocity`](KinematicsData::body_velocity).
    #[inline]
    #[must_use]
    pub fn body_velocity(&self) -> &[Motion] {
        self.kinematics.body_velocity()
    }

    /// Spatial force each body exerts on its subtree through its joint, in the body's frame,
    /// after [`rnea`](crate::rnea) (Pinocchio's `data.f`; index 0 is unused).
    #[inline]
    #[must_use]
    pub fn joint_wrench(&self) -> &[Force] {
        &self.force
    }

    /// The names of the joints owning the given degrees of freedom, deduplicated, in order.
    pub(crate) fn joint_names(&self, model: &Model, dofs: &[usize]) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for &k in dofs {
            let body = &model.bodies()[self.dof_body[k]];
            if let Some(j) = body.joint {
                let name = &model.joint(j).name;
                if names.last() != Some(name) && !names.contains(name) {
                    names.push(name.clone());
                }
            }
        }
        names
    }
}

#[inline]
pub(crate) fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}
