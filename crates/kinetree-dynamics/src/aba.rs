//! Forward dynamics: the articulated-body algorithm.

use crate::articulated::{ArticulatedInertia, RigidInertia};
use crate::data::DynamicsData;
use crate::error::{DynamicsError, check_vector};
use crate::external::ExternalForces;
use crate::rnea::{JointTermsRef, check_inputs};
use core::ops::{IndexMut, Range};
use kinetree_kinematics::JointModel;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::real::Real;
use kinetree_kinematics::spatial::{Force, Motion, Se3};

/// Relative size of an articulated pivot below which the joint counts as moving no mass.
pub(crate) const PIVOT_TOLERANCE: f64 = 1e-13;

/// Forward dynamics: the joint accelerations `q̈ = M(q)⁻¹·(τ - C(q, q̇)·q̇ - g(q))` produced by
/// joint torques `tau` at configuration `q` and velocity `v`, under gravity.
///
/// `q` has length `model.nq()`, `v` and `tau` length `model.nv()`. The result (length `nv`) is
/// stored in [`DynamicsData::ddq`] and returned. With [`JointTerms::FromModel`] the joints'
/// armature, damping and friction are included, consistently with [`rnea`](crate::rnea):
/// `aba(q, v, rnea(q, v, a)) = a`. Floating-base entries are the derivative of the base twist in
/// the base frame.
///
/// Featherstone's articulated-body algorithm with world-frame articulated inertias (Pinocchio's
/// `aba` with `Convention::WORLD`): O(n), allocates nothing (except the joint names of an
/// error).
///
/// # Errors
/// [`DynamicsError::SingularMassMatrix`] naming the joints that move no mass (massless
/// subtrees), where the accelerations are undefined; [`DynamicsError::DimensionMismatch`] or
/// [`DynamicsError::NonFinite`] for a bad `q`, `v` or `tau`; [`DynamicsError::DataMismatch`] when
/// `data` belongs to another model.
///
/// # Examples
/// ```
/// use kinetree_dynamics::{aba, DynamicsData};
/// use kinetree_dynamics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A 1 kg point mass 0.5 m from a hinge about y, released horizontally.
/// let urdf = r#"<robot name="pendulum"><link name="base"/>
///   <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
///     <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
///   <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = DynamicsData::new(&model);
/// let ddq = aba(&model, &mut data, &[0.0], &[0.0], &[0.0])?;
/// // g / l = 19.62 rad/s², about +y (the bob falls towards -z).
/// assert!((ddq[0] - 9.81 / 0.5).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
///
/// [`JointTerms::FromModel`]: crate::JointTerms::FromModel
#[doc(alias = "forward_dynamics")]
#[doc(alias = "articulated_body_algorithm")]
pub fn aba<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    check_vector("tau", tau, model.nv())?;
    compute(model, data, q, v, tau, None)?;
    crate::error::check_output(model, data, "ddq", &data.ddq)?;
    Ok(&data.ddq)
}

/// As [`aba`], with wrenches applied by the environment (see [`ExternalForces`]).
///
/// # Errors
/// As [`aba`]; [`DynamicsError::DataMismatch`] when `fext` belongs to another model.
pub fn aba_with_external_forces<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    fext: &ExternalForces,
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    check_vector("tau", tau, model.nv())?;
    fext.check_model(model)?;
    compute(model, data, q, v, tau, Some(fext))?;
    crate::error::check_output(model, data, "ddq", &data.ddq)?;
    Ok(&data.ddq)
}

/// The three ABA sweeps of one state (inputs already checked): the generic passes of
/// [`AbaSweep`] on `f64`, with the external forces and the pivot checks at their edges. The
/// result goes to `data.ddq`; `q` and the placements to the embedded kinematics data.
pub(crate) fn compute(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    fext: Option<&ExternalForces>,
) -> Result<(), DynamicsError> {
    let singular = {
        let kin = data.kinematics.body_buffers_mut();
        kin.q.copy_from_slice(q);
        let tree = AbaTree {
            model,
            joint_models: kin.joint_models,
            dinv_offset: &data.dinv_offset,
            terms: data.has_joint_terms.then_some(JointTermsRef {
                armature: &data.armature,
                damping: &data.damping,
                friction: &data.friction,
            }),
        };
        let mut sweep = AbaSweep {
            parent_from_body: &mut *kin.parent_from_body,
            world_from_body: &mut *kin.world_from_body,
            velocity: &mut data.world_velocity,
            bias: &mut data.bias,
            acceleration: &mut data.acceleration,
            subspace: &mut data.subspace,
            force: &mut data.force,
            u_columns: &mut data.u_columns,
            articulated: &mut data.articulated,
            u: &mut data.u,
            dinv: &mut data.dinv,
            ddq: &mut data.ddq,
        };
        sweep.forward(&tree, q, v);
        if let Some(fext) = fext {
            let force = &mut *sweep.force;
            fext.for_each_world(&*sweep.world_from_body, |body, f| force[body] -= f);
        }
        // Allocates only when a pivot is refused.
        let mut singular = Singular(Vec::new());
        sweep.backward(&tree, v, tau, &mut singular);
        if singular.0.is_empty() {
            sweep.accelerations(&tree);
        }
        singular.0
    };
    if singular.is_empty() {
        return Ok(());
    }
    let bodies = model.bodies();
    // A pivot that is not finite is an overflow (huge masses, lengths or velocities), not a
    // massless subtree.
    if let Some(i) = (1..bodies.len())
        .find(|&i| !(data.articulated[i].scale().is_finite() && data.force[i].is_finite()))
    {
        let dof = bodies[i].idx_v;
        let what = if data.articulated[i].scale().is_finite() {
            "the articulated bias force"
        } else {
            "the articulated-body inertia"
        };
        return Err(crate::error::overflow(model, data, what, dof, f64::NAN));
    }
    let mut singular = singular;
    singular.sort_unstable();
    Err(singular_error(model, data, &singular))
}

/// What the ABA sweeps read: the model's bodies and joint models, where each body's inverse
/// pivot block starts, and the joint terms when they are included.
pub(crate) struct AbaTree<'a> {
    pub(crate) model: &'a Model,
    pub(crate) joint_models: &'a [JointModel],
    pub(crate) dinv_offset: &'a [usize],
    pub(crate) terms: Option<JointTermsRef<'a>>,
}

impl<'a> AbaTree<'a> {
    /// The sweeps' view of `model` and `data`.
    pub(crate) fn of(model: &'a Model, data: &'a DynamicsData) -> Self {
        Self {
            model,
            joint_models: data.kinematics.joint_models(),
            dinv_offset: &data.dinv_offset,
            terms: data.has_joint_terms.then_some(JointTermsRef {
                armature: &data.armature,
                damping: &data.damping,
                friction: &data.friction,
            }),
        }
    }
}

/// What becomes of the pivots the backward sweep refuses (at most the tolerance, or NaN): the
/// one-state sweep names their joints, the lanes mark their states.
pub(crate) trait Pivots<T: Real> {
    /// The pivots of the degrees of freedom `dofs`, whose inverse block is `dinv`, were refused
    /// where `refused` is not 0.
    fn check(&mut self, dofs: Range<usize>, refused: T, dinv: &mut [T]);
}

/// The degrees of freedom of one state whose pivots were refused; their inverse blocks are set
/// to 0, so that the sums up the tree stay finite for the overflow check.
struct Singular(Vec<usize>);

impl Pivots<f64> for Singular {
    #[inline(always)]
    fn check(&mut self, dofs: Range<usize>, refused: f64, dinv: &mut [f64]) {
        if refused != 0.0 {
            self.0.extend(dofs);
            dinv.fill(0.0);
        }
    }
}

/// The per-body (and per degree of freedom) buffers the ABA sweeps write: of one state (slices
/// of the data) or of a block of states in lanes (the batch's lane buffers).
pub(crate) struct AbaSweep<'a, T, X: ?Sized, M: ?Sized, F: ?Sized, A: ?Sized> {
    pub(crate) parent_from_body: &'a mut X,
    pub(crate) world_from_body: &'a mut X,
    /// The bodies' velocities, in the world frame.
    pub(crate) velocity: &'a mut M,
    /// The velocity-product accelerations `vₚ × vⱼ`.
    pub(crate) bias: &'a mut M,
    /// The bodies' accelerations (with gravity: the root accelerates by `-g`).
    pub(crate) acceleration: &'a mut M,
    /// The joints' subspace columns in the world frame, per degree of freedom.
    pub(crate) subspace: &'a mut M,
    /// The articulated bias forces.
    pub(crate) force: &'a mut F,
    /// `U = Iᵃ·S`, per degree of freedom.
    pub(crate) u_columns: &'a mut F,
    pub(crate) articulated: &'a mut A,
    /// `u = τ - Sᵀ·pᵃ` (less the joint terms), per degree of freedom.
    pub(crate) u: &'a mut [T],
    /// The inverse pivot blocks `D⁻¹` (at `dinv_offset`).
    pub(crate) dinv: &'a mut [T],
    pub(crate) ddq: &'a mut [T],
}

impl<T, X, M, F, A> AbaSweep<'_, T, X, M, F, A>
where
    T: Real,
    X: IndexMut<usize, Output = Se3<T>> + ?Sized,
    M: IndexMut<usize, Output = Motion<T>> + ?Sized,
    F: IndexMut<usize, Output = Force<T>> + ?Sized,
    A: IndexMut<usize, Output = ArticulatedInertia<T>> + ?Sized,
{
    /// Pass 1, root to leaves: placements, velocities, bias accelerations, rigid inertias and
    /// bias forces, all in the world frame.
    #[inline(always)]
    pub(crate) fn forward(&mut self, tree: &AbaTree<'_>, q: &[T], v: &[T]) {
        for (i, b) in tree.model.bodies().iter().enumerate().skip(1) {
            let jm = &tree.joint_models[i];
            let x = jm.placed_transform(&b.placement, &q[b.idx_q..b.idx_q + b.nq]);
            self.parent_from_body[i].assign(&x);
            let p = b.parent;
            let world = if p == 0 {
                x
            } else {
                self.world_from_body[p].compose(&x)
            };
            self.world_from_body[i] = world;
            let mut vj = Motion::zero();
            for k in 0..b.nv {
                let s = jm.act_column(&world, k);
                self.subspace[b.idx_v + k] = s;
                vj += s.scale(v[b.idx_v + k]);
            }
            let (vi, ci) = if p == 0 {
                (vj, Motion::zero())
            } else {
                let vp = self.velocity[p];
                (vp + vj, vp.cross_motion(&vj))
            };
            self.velocity[i] = vi;
            self.bias[i] = ci;
            let inertia = RigidInertia::transformed(&b.inertia, &world);
            self.articulated[i] = ArticulatedInertia::from_rigid(&inertia);
            self.force[i] = vi.cross_force(&inertia.mul_motion(&vi));
        }
    }

    /// Pass 2, leaves to root: articulated inertias and bias forces, and each joint's inverse
    /// pivot block (checked through `pivots`).
    #[inline(always)]
    pub(crate) fn backward(
        &mut self,
        tree: &AbaTree<'_>,
        v: &[T],
        tau: &[T],
        pivots: &mut impl Pivots<T>,
    ) {
        let bodies = tree.model.bodies();
        for i in (1..bodies.len()).rev() {
            let b = &bodies[i];
            let (iv, ni) = (b.idx_v, b.nv);
            let ia = self.articulated[i];
            let pa = self.force[i];
            let off = tree.dinv_offset[i];
            let tolerance = ia.scale() * PIVOT_TOLERANCE;
            if ni == 1 {
                let s = self.subspace[iv];
                let u_col = ia.mul_motion(&s);
                self.u_columns[iv] = u_col;
                let mut d = s.dot(&u_col);
                let mut u = tau[iv] - s.dot(&pa);
                if let Some(t) = &tree.terms {
                    d += T::splat(t.armature[iv]);
                    u -= v[iv] * t.damping[iv] + v[iv].sign() * t.friction[iv];
                }
                let (dinv, refused) = d.pivot(tolerance);
                self.dinv[off] = dinv;
                pivots.check(iv..iv + 1, refused, &mut self.dinv[off..=off]);
                let dinv = self.dinv[off];
                self.u[iv] = u;
                if b.parent != 0 {
                    let mut ia = ia;
                    ia.sub_outer(&u_col, &u_col.scale(dinv));
                    let pa = pa + ia.mul_motion(&self.bias[i]) + u_col.scale(dinv * u);
                    self.articulated[b.parent].add_assign(&ia);
                    self.force[b.parent] += pa;
                }
            } else {
                let mut d = [[T::ZERO; 6]; 6];
                for k in 0..ni {
                    let s = self.subspace[iv + k];
                    let u_col = ia.mul_motion(&s);
                    self.u_columns[iv + k] = u_col;
                    let mut u = tau[iv + k] - s.dot(&pa);
                    if let Some(t) = &tree.terms {
                        let vk = v[iv + k];
                        d[k][k] += T::splat(t.armature[iv + k]);
                        u -= vk * t.damping[iv + k] + vk.sign() * t.friction[iv + k];
                    }
                    self.u[iv + k] = u;
                }
                for k in 0..ni {
                    for l in 0..=k {
                        let x = self.subspace[iv + l].dot(&self.u_columns[iv + k]);
                        d[k][l] += x;
                        if l != k {
                            d[l][k] = d[k][l];
                        }
                    }
                }
                let dinv = &mut self.dinv[off..off + ni * ni];
                let refused = invert_spd(&d, ni, tolerance, dinv);
                pivots.check(iv..iv + ni, refused, dinv);
                if b.parent != 0 {
                    let mut ia = ia;
                    let mut pa = pa;
                    for k in 0..ni {
                        // W_k = Σ_l D⁻¹[k][l]·U_l.
                        let mut w = Force::zero();
                        let mut du = T::ZERO;
                        for l in 0..ni {
                            w += self.u_columns[iv + l].scale(dinv[k * ni + l]);
                            du += dinv[k * ni + l] * self.u[iv + l];
                        }
                        ia.sub_outer(&self.u_columns[iv + k], &w);
                        pa += self.u_columns[iv + k].scale(du);
                    }
                    let pa = pa + ia.mul_motion(&self.bias[i]);
                    self.articulated[b.parent].add_assign(&ia);
                    self.force[b.parent] += pa;
                }
            }
        }
    }

    /// Pass 3, root to leaves: the accelerations, with `ddq`.
    #[inline(always)]
    pub(crate) fn accelerations(&mut self, tree: &AbaTree<'_>) {
        let a0 = Motion::from_const(&Motion::new(-tree.model.gravity(), DVec3::ZERO));
        for (i, b) in tree.model.bodies().iter().enumerate().skip(1) {
            let (iv, ni) = (b.idx_v, b.nv);
            let p = b.parent;
            let mut ai = if p == 0 { a0 } else { self.acceleration[p] } + self.bias[i];
            let off = tree.dinv_offset[i];
            if ni == 1 {
                let u_col = self.u_columns[iv];
                let qdd = self.dinv[off] * (self.u[iv] - ai.dot(&u_col));
                self.ddq[iv] = qdd;
                ai += self.subspace[iv].scale(qdd);
            } else {
                let mut r = [T::ZERO; 6];
                for k in 0..ni {
                    r[k] = self.u[iv + k] - ai.dot(&self.u_columns[iv + k]);
                }
                let mut da = Motion::zero();
                for k in 0..ni {
                    let mut qdd = T::ZERO;
                    for l in 0..ni {
                        qdd += self.dinv[off + k * ni + l] * r[l];
                    }
                    self.ddq[iv + k] = qdd;
                    da += self.subspace[iv + k].scale(qdd);
                }
                ai += da;
            }
            self.acceleration[i] = ai;
        }
    }
}

/// Inverts a small symmetric positive definite matrix (`n ≤ 6`, stored in `d[..n][..n]`) into
/// `out` (row-major `n x n`) by Cholesky. Returns what [`Real::pivot`] says of the pivots: not
/// 0 where one is `≤ tolerance` (or NaN), and `out` is then meaningless.
#[inline(always)]
fn invert_spd<T: Real>(d: &[[T; 6]; 6], n: usize, tolerance: T, out: &mut [T]) -> T {
    let mut refused = T::ZERO;
    // Cholesky: d = L·Lᵀ.
    let mut l = [[T::ZERO; 6]; 6];
    for j in 0..n {
        let mut s = d[j][j];
        for k in 0..j {
            s -= l[j][k] * l[j][k];
        }
        refused += s.pivot(tolerance).1;
        let ljj = s.sqrt();
        l[j][j] = ljj;
        for i in j + 1..n {
            let mut s = d[i][j];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            l[i][j] = s / ljj;
        }
    }
    // Columns of the inverse: solve L·Lᵀ·x = e_c.
    for c in 0..n {
        let mut y = [T::ZERO; 6];
        for i in 0..n {
            let mut s = if i == c { T::splat(1.0) } else { T::ZERO };
            for k in 0..i {
                s -= l[i][k] * y[k];
            }
            y[i] = s / l[i][i];
        }
        for i in (0..n).rev() {
            let mut s = y[i];
            for k in i + 1..n {
                s -= l[k][i] * y[k];
            }
            y[i] = s / l[i][i];
        }
        for i in 0..n {
            out[i * n + c] = y[i];
        }
    }
    refused
}

/// Placements farther than this from the origin (metres) are beyond any robot: a singular
/// pivot there is a loss of precision, not a massless subtree.
const ILL_CONDITIONED_REACH: f64 = 1e6;

/// Body masses (or rotational inertias) further apart than this ratio leave the lighter ones
/// below the pivot tolerance.
const ILL_CONDITIONED_MASS_RATIO: f64 = 1e12;

/// The error for vanished pivots at degrees of freedom `dofs` (sorted): a massless subtree, or,
/// when the subtrees carry mass and the links are absurdly far out or the masses (or inertias)
/// absurdly different, a loss of precision. Reads the world placements in `data.kinematics`.
pub(crate) fn singular_error(model: &Model, data: &DynamicsData, dofs: &[usize]) -> DynamicsError {
    let bodies = model.bodies();
    let reach = data
        .kinematics
        .world_from_body()
        .iter()
        .map(|x| x.translation.length())
        .fold(0.0, f64::max);
    // The body masses and rotational inertias (largest principal-axis entry), as magnitudes.
    let (lightest, heaviest) = bodies
        .iter()
        .flat_map(|b| {
            let r = &b.inertia.rotational;
            [b.inertia.mass, r.xx.max(r.yy).max(r.zz)]
        })
        .filter(|&m| m > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), m| {
            (lo.min(m), hi.max(m))
        });
    let carries_mass = |dof: usize| {
        let Some(top) = (1..bodies.len())
            .find(|&i| (bodies[i].idx_v..bodies[i].idx_v + bodies[i].nv).contains(&dof))
        else {
            return false;
        };
        (top..bodies.len()).any(|mut j| {
            let massive = bodies[j].inertia.mass > 0.0;
            while j > top {
                j = bodies[j].parent;
            }
            j == top && massive
        })
    };
    let massive: Vec<usize> = dofs.iter().copied().filter(|&d| carries_mass(d)).collect();
    let ill_conditioned =
        reach > ILL_CONDITIONED_REACH || heaviest > ILL_CONDITIONED_MASS_RATIO * lightest;
    if ill_conditioned && !massive.is_empty() {
        return DynamicsError::IllConditionedMassMatrix {
            joints: data.joint_names(model, &massive),
            reach,
            masses: [lightest, heaviest],
        };
    }
    DynamicsError::SingularMassMatrix {
        joints: data.joint_names(model, dofs),
    }
}
