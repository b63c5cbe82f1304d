//! Forward dynamics: the articulated-body algorithm.

use crate::data::{DynamicsData, sign};
use crate::error::{DynamicsError, check_vector};
use crate::external::ExternalForces;
use crate::rnea::check_inputs;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::glam::{DMat3, DVec3};
use kinetree_kinematics::spatial::{Force, Inertia, Motion, Symmetric3};

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

/// The three ABA sweeps (inputs already checked); the result goes to `data.ddq`.
pub(crate) fn compute(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    fext: Option<&ExternalForces>,
) -> Result<(), DynamicsError> {
    let bodies = model.bodies();
    let nb = bodies.len();
    // Pass 1, root to leaves: placements, velocities, bias accelerations, rigid inertias and
    // bias forces, all in the world frame. `q` and the placements go to the embedded kinematics
    // data.
    let kin = data.kinematics.body_buffers_mut();
    kin.q.copy_from_slice(q);
    let joint_models = kin.joint_models;
    for i in 1..nb {
        let b = &bodies[i];
        let jm = &joint_models[i];
        let x = jm.placed_transform(&b.placement, &q[b.idx_q..b.idx_q + b.nq]);
        kin.parent_from_body[i] = x;
        let p = b.parent;
        let world_from_body = if p == 0 {
            x
        } else {
            kin.world_from_body[p] * x
        };
        kin.world_from_body[i] = world_from_body;
        let mut vj = Motion::ZERO;
        for k in 0..b.nv {
            let s = world_from_body.act_motion(&jm.subspace_column(k));
            data.subspace[b.idx_v + k] = s;
            vj += s * v[b.idx_v + k];
        }
        let (vi, ci) = if p == 0 {
            (vj, Motion::ZERO)
        } else {
            let vp = data.world_velocity[p];
            (vp + vj, vp.cross_motion(&vj))
        };
        data.world_velocity[i] = vi;
        data.bias[i] = ci;
        let inertia = b.inertia.transformed(&world_from_body);
        data.articulated[i] = ArticulatedInertia::from_inertia(&inertia);
        data.force[i] = vi.cross_force(&inertia.mul_motion(&vi));
    }
    if let Some(fext) = fext {
        let force = &mut data.force;
        fext.for_each_world(data.kinematics.world_from_body(), |body, f| {
            force[body] -= f
        });
    }
    // Pass 2, leaves to root: articulated inertias and bias forces.
    let mut singular: Vec<usize> = Vec::new();
    for i in (1..nb).rev() {
        let b = &bodies[i];
        let (iv, ni) = (b.idx_v, b.nv);
        let ia = data.articulated[i];
        let pa = data.force[i];
        let off = data.dinv_offset[i];
        if ni == 1 {
            let s = data.subspace[iv];
            let u_col = ia.mul_motion(&s);
            data.u_columns[iv] = u_col;
            let mut d = s.dot(&u_col);
            let mut u = tau[iv] - s.dot(&pa);
            if data.has_joint_terms {
                d += data.armature[iv];
                u -= data.damping[iv] * v[iv] + data.friction[iv] * sign(v[iv]);
            }
            let dinv = if d > PIVOT_TOLERANCE * ia.scale() {
                1.0 / d
            } else {
                singular.push(iv);
                0.0
            };
            data.dinv[off] = dinv;
            data.u[iv] = u;
            if b.parent != 0 {
                let mut ia = ia;
                ia.sub_outer(&u_col, &(u_col * dinv));
                let pa = pa + ia.mul_motion(&data.bias[i]) + u_col * (dinv * u);
                data.articulated[b.parent].add_assign(&ia);
                data.force[b.parent] += pa;
            }
        } else {
            let mut d = [[0.0; 6]; 6];
            for k in 0..ni {
                let s = data.subspace[iv + k];
                let u_col = ia.mul_motion(&s);
                data.u_columns[iv + k] = u_col;
                let mut u = tau[iv + k] - s.dot(&pa);
                if data.has_joint_terms {
                    d[k][k] += data.armature[iv + k];
                    u -= data.damping[iv + k] * v[iv + k] + data.friction[iv + k] * sign(v[iv + k]);
                }
                data.u[iv + k] = u;
            }
            for k in 0..ni {
                for l in 0..=k {
                    let x = data.subspace[iv + l].dot(&data.u_columns[iv + k]);
                    d[k][l] += x;
                    if l != k {
                        d[l][k] = d[k][l];
                    }
                }
            }
            let dinv = &mut data.dinv[off..off + ni * ni];
            if !invert_spd(&d, ni, PIVOT_TOLERANCE * ia.scale(), dinv) {
                singular.extend(iv..iv + ni);
                dinv.fill(0.0);
            }
            if b.parent != 0 {
                let mut ia = ia;
                let mut pa = pa;
                for k in 0..ni {
                    // W_k = Σ_l D⁻¹[k][l]·U_l.
                    let mut w = Force::ZERO;
                    let mut du = 0.0;
                    for l in 0..ni {
                        w += data.u_columns[iv + l] * dinv[k * ni + l];
                        du += dinv[k * ni + l] * data.u[iv + l];
                    }
                    ia.sub_outer(&data.u_columns[iv + k], &w);
                    pa += data.u_columns[iv + k] * du;
                }
                let pa = pa + ia.mul_motion(&data.bias[i]);
                data.articulated[b.parent].add_assign(&ia);
                data.force[b.parent] += pa;
            }
        }
    }
    if !singular.is_empty() {
        // A pivot that is not finite is an overflow (huge masses, lengths or velocities), not a
        // massless subtree.
        if let Some(i) = (1..nb)
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
        singular.sort_unstable();
        return Err(singular_error(model, data, &singular));
    }
    // Pass 3, root to leaves: accelerations.
    let a0 = Motion::new(-model.gravity(), DVec3::ZERO);
    for i in 1..nb {
        let b = &bodies[i];
        let (iv, ni) = (b.idx_v, b.nv);
        let p = b.parent;
        let mut ai = if p == 0 { a0 } else { data.acceleration[p] } + data.bias[i];
        let off = data.dinv_offset[i];
        if ni == 1 {
            let u_col = data.u_columns[iv];
            let qdd = data.dinv[off] * (data.u[iv] - a_dot(&ai, &u_col));
            data.ddq[iv] = qdd;
            ai += data.subspace[iv] * qdd;
        } else {
            let mut r = [0.0; 6];
            for k in 0..ni {
                r[k] = data.u[iv + k] - a_dot(&ai, &data.u_columns[iv + k]);
            }
            let mut da = Motion::ZERO;
            for k in 0..ni {
                let mut qdd = 0.0;
                for l in 0..ni {
                    qdd += data.dinv[off + k * ni + l] * r[l];
                }
                data.ddq[iv + k] = qdd;
                da += data.subspace[iv + k] * qdd;
            }
            ai += da;
        }
        data.acceleration[i] = ai;
    }
    Ok(())
}

#[inline]
fn a_dot(a: &Motion, f: &Force) -> f64 {
    a.dot(f)
}

/// Inverts a small symmetric positive definite matrix (`n ≤ 6`, stored in `d[..n][..n]`) into
/// `out` (row-major `n x n`) by Cholesky; `false` when a pivot is `≤ tolerance`.
fn invert_spd(d: &[[f64; 6]; 6], n: usize, tolerance: f64, out: &mut [f64]) -> bool {
    // Cholesky: d = L·Lᵀ.
    let mut l = [[0.0; 6]; 6];
    for j in 0..n {
        let mut s = d[j][j];
        for k in 0..j {
            s -= l[j][k] * l[j][k];
        }
        if s.is_nan() || s <= tolerance {
            return false;
        }
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
        let mut y = [0.0; 6];
        for i in 0..n {
            let mut s = if i == c { 1.0 } else { 0.0 };
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
    true
}

/// A symmetric 6x6 spatial inertia (rigid or articulated) in 3x3 blocks, acting on
/// `[linear; angular]` motions: `f = A·v + B·ω`, `n = Bᵀ·v + C·ω`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ArticulatedInertia {
    a: Symmetric3,
    b: DMat3,
    c: Symmetric3,
}

impl ArticulatedInertia {
    pub(crate) const ZERO: Self = Self {
        a: Symmetric3::ZERO,
        b: DMat3::ZERO,
        c: Symmetric3::ZERO,
    };

    /// The 6x6 form of a rigid-body inertia.
    #[inline]
    pub(crate) fn from_inertia(i: &Inertia) -> Self {
        let m = i.mass;
        let mc = i.com * m;
        Self {
            a: Symmetric3::new(m, 0.0, 0.0, m, 0.0, m),
            // -m·[c]×
            b: DMat3::from_cols(
                DVec3::new(0.0, -mc.z, mc.y),
                DVec3::new(mc.z, 0.0, -mc.x),
                DVec3::new(-mc.y, mc.x, 0.0),
            ),
            c: i.rotational_about(DVec3::ZERO),
        }
    }

    /// The product with a motion vector.
    #[inline]
    pub(crate) fn mul_motion(&self, m: &Motion) -> Force {
        let (v, w) = (m.linear, m.angular);
        Force::new(
            self.a.mul_vec3(v) + self.b * w,
            self.b.transpose() * v + self.c.mul_vec3(w),
        )
    }

    /// `self -= x·yᵀ` for forces `x`, `y` whose outer product is symmetric in sum (only the
    /// lower blocks' symmetric parts are kept).
    #[inline]
    pub(crate) fn sub_outer(&mut self, x: &Force, y: &Force) {
        let (xl, xa, yl, ya) = (x.linear, x.angular, y.linear, y.angular);
        self.a.xx -= xl.x * yl.x;
        self.a.xy -= xl.x * yl.y;
        self.a.xz -= xl.x * yl.z;
        self.a.yy -= xl.y * yl.y;
        self.a.yz -= xl.y * yl.z;
        self.a.zz -= xl.z * yl.z;
        // B (linear rows, angular columns) gets x_lin·y_angᵀ.
        self.b.x_axis -= xl * ya.x;
        self.b.y_axis -= xl * ya.y;
        self.b.z_axis -= xl * ya.z;
        self.c.xx -= xa.x * ya.x;
        self.c.xy -= xa.x * ya.y;
        self.c.xz -= xa.x * ya.z;
        self.c.yy -= xa.y * ya.y;
        self.c.yz -= xa.y * ya.z;
        self.c.zz -= xa.z * ya.z;
    }

    /// `self += o`.
    #[inline]
    pub(crate) fn add_assign(&mut self, o: &Self) {
        self.a += o.a;
        self.b += o.b;
        self.c += o.c;
    }

    /// A magnitude for pivot tolerances: the traces of the diagonal blocks.
    #[inline]
    pub(crate) fn scale(&self) -> f64 {
        self.a.trace().abs() + self.c.trace().abs()
    }
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
