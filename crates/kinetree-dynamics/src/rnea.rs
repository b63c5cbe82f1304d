//! Inverse dynamics: the recursive Newton–Euler algorithm and the torques derived from it.

use crate::data::DynamicsData;
use crate::error::{DynamicsError, check_output, check_vector};
use crate::external::ExternalForces;
use core::ops::IndexMut;
use kinetree_kinematics::JointModel;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::real::{Matrix3, Real, Vector3};
use kinetree_kinematics::spatial::{Force, Motion, RotationForm, Se3};

/// Which output buffer a sweep writes.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Output {
    Tau,
    Nle,
    Gravity,
}

/// Inverse dynamics: the joint torques `τ = M(q)·q̈ + C(q, q̇)·q̇ + g(q)` that produce joint
/// accelerations `a` at configuration `q` and velocity `v`, under gravity
/// ([`Model::gravity`]).
///
/// `q` has length `model.nq()`, `v` and `a` length `model.nv()`. The result (length `nv`) is
/// stored in [`DynamicsData::tau`] and returned. With [`JointTerms::FromModel`] the joints'
/// armature, damping and friction are included (`+ r·a + d·v + μ·sign(v)`). Floating-base
/// entries are the wrench `[force; torque]` on the base in the base frame.
///
/// Recursive Newton–Euler in body-local coordinates (Featherstone's RNEA, Pinocchio's `rnea`):
/// O(n), allocates nothing.
///
/// # Errors
/// [`DynamicsError::DimensionMismatch`] or [`DynamicsError::NonFinite`] for a bad `q`, `v` or
/// `a`; [`DynamicsError::DataMismatch`] when `data` belongs to another model.
///
/// # Examples
/// ```
/// use kinetree_dynamics::{rnea, DynamicsData};
/// use kinetree_dynamics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A 1 kg point mass on a massless 0.5 m rod, hinged about y; gravity along -z.
/// let urdf = r#"<robot name="pendulum"><link name="base"/>
///   <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
///     <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
///   <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = DynamicsData::new(&model);
/// // Gravity pulls the bob (at +x) down -z: a torque of +m·g·l = 4.905 N·m about +y. Holding
/// // the rod horizontal takes the opposite torque.
/// let tau = rnea(&model, &mut data, &[0.0], &[0.0], &[0.0])?;
/// assert!((tau[0] + 9.81 * 0.5).abs() < 1e-12);
/// // Accelerating it at 2 rad/s² about +y takes m·l²·a = 0.5 N·m more.
/// let tau = rnea(&model, &mut data, &[0.0], &[0.0], &[2.0])?;
/// assert!((tau[0] - (-4.905 + 0.5)).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
///
/// [`JointTerms::FromModel`]: crate::JointTerms::FromModel
#[doc(alias = "inverse_dynamics")]
#[doc(alias = "rne")]
pub fn rnea<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, data, q, Some(v), Some(a))?;
    sweep::<true, true>(model, data, q, v, a, None, Output::Tau);
    check_output(model, data, "tau", &data.tau)?;
    Ok(&data.tau)
}

/// As [`rnea`], with wrenches applied by the environment (see [`ExternalForces`]): the torques
/// that produce `a` while the environment pushes with `fext` (`τ = rnea(q, v, a) - Σ Jᵀ·f`).
///
/// # Errors
/// As [`rnea`]; [`DynamicsError::DataMismatch`] when `fext` belongs to another model.
pub fn rnea_with_external_forces<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    fext: &ExternalForces,
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, data, q, Some(v), Some(a))?;
    fext.check_model(model)?;
    sweep::<true, true>(model, data, q, v, a, Some(fext), Output::Tau);
    check_output(model, data, "tau", &data.tau)?;
    Ok(&data.tau)
}

/// The nonlinear effects `C(q, q̇)·q̇ + g(q)` (Coriolis, centrifugal and gravity torques; plus
/// `d·v + μ·sign(v)` with [`JointTerms::FromModel`]): [`rnea`] with zero acceleration, so that
/// `crba(q)·a + nonlinear_effects(q, v) = rnea(q, v, a)`.
///
/// Stored in [`DynamicsData::nle`] and returned (length `model.nv()`). Allocates nothing.
///
/// # Errors
/// As [`rnea`].
///
/// [`JointTerms::FromModel`]: crate::JointTerms::FromModel
#[doc(alias = "nle")]
#[doc(alias = "bias_forces")]
#[doc(alias = "coriolis")]
pub fn nonlinear_effects<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
    v: &[f64],
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    sweep::<true, false>(model, data, q, v, &[], None, Output::Nle);
    check_output(model, data, "nonlinear effects", &data.nle)?;
    Ok(&data.nle)
}

/// The generalized gravity `g(q)`: the torques that hold the robot still at `q` against gravity
/// ([`rnea`] with zero velocity and acceleration).
///
/// Stored in [`DynamicsData::gravity_torque`] and returned (length `model.nv()`). Allocates
/// nothing.
///
/// # Errors
/// As [`rnea`], for `q`.
#[doc(alias = "gravity_torque")]
#[doc(alias = "compute_generalized_gravity")]
pub fn generalized_gravity<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, data, q, None, None)?;
    sweep::<false, false>(model, data, q, &[], &[], None, Output::Gravity);
    check_output(model, data, "gravity torque", &data.gravity_torque)?;
    Ok(&data.gravity_torque)
}

/// Entry checks shared by the dynamics algorithms.
pub(crate) fn check_inputs(
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    v: Option<&[f64]>,
    a: Option<&[f64]>,
) -> Result<(), DynamicsError> {
    data.check_model(model)?;
    check_vector("q", q, model.nq())?;
    // The configuration check repeats the length and finiteness checks just made; what it adds
    // is the quaternions' norms.
    if !model.quaternion_blocks().is_empty() {
        kinetree_kinematics::configuration::check_configuration(model, q)?;
    }
    if let Some(v) = v {
        check_vector("v", v, model.nv())?;
    }
    if let Some(a) = a {
        check_vector("a", a, model.nv())?;
    }
    Ok(())
}

/// The RNEA sweeps of one state. `VEL`: `v` is used (else zero); `ACC`: `a` is used (else
/// zero).
///
/// `q`, the local placements and the body velocities go to the embedded
/// [`KinematicsData`](kinetree_kinematics::KinematicsData), as forward kinematics would write
/// them (the world placements only when an external wrench needs them); the accelerations carry
/// gravity (the root accelerates by `-g`, Pinocchio's `a_gf`) and stay in [`DynamicsData`].
pub(crate) fn sweep<const VEL: bool, const ACC: bool>(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    fext: Option<&ExternalForces>,
    output: Output,
) {
    kinetree_kinematics::with_simd!(
        sweep_kernel[const VEL: bool, const ACC: bool],
        (
            model: &Model = model,
            data: &mut DynamicsData = data,
            q: &[f64] = q,
            v: &[f64] = v,
            a: &[f64] = a,
            fext: Option<&ExternalForces> = fext,
            output: Output = output,
        ) -> ()
    );
}

/// [`sweep`], to be compiled for the instruction set it runs with: the generic sweeps on `f64`.
#[inline(always)]
fn sweep_kernel<const VEL: bool, const ACC: bool>(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    fext: Option<&ExternalForces>,
    output: Output,
) {
    let kin = data.kinematics.body_buffers_mut();
    kin.q.copy_from_slice(q);
    let joint_models = kin.joint_models;
    let bodies = Bodies {
        model,
        joint_models,
        turn: &data.turn,
    };
    let mut state = Sweep {
        parent_from_body: &mut *kin.parent_from_body,
        velocity: &mut *kin.body_velocity,
        acceleration: &mut data.acceleration,
        force: &mut data.force,
    };
    forward::<f64, VEL, ACC>(&bodies, &mut state, q, v, a);
    if let Some(fext) = fext {
        if fext.needs_world() {
            let world = &mut *kin.world_from_body;
            for (i, b) in model.bodies().iter().enumerate().skip(1) {
                let x = state.parent_from_body[i];
                world[i] = if b.parent == 0 {
                    x
                } else {
                    world[b.parent] * x
                };
            }
        }
        let force = &mut *state.force;
        fext.for_each_local(&*kin.world_from_body, |body, f| force[body] -= f);
    }
    let out = match output {
        Output::Tau => &mut data.tau,
        Output::Nle => &mut data.nle,
        Output::Gravity => &mut data.gravity_torque,
    };
    backward(&bodies, &mut state, out);
    if data.has_joint_terms {
        let terms = JointTermsRef {
            armature: &data.armature,
            damping: &data.damping,
            friction: &data.friction,
        };
        terms.add::<f64, VEL, ACC>(v, a, out);
    }
}

/// What the RNEA sweeps read of the model: its bodies, their joint models and, per body, the
/// coordinate axis its revolute joint turns about alone (`DynamicsData::turn`, else 3).
pub(crate) struct Bodies<'a> {
    pub(crate) model: &'a Model,
    pub(crate) joint_models: &'a [JointModel],
    pub(crate) turn: &'a [u8],
}

/// The per-body buffers the RNEA sweeps write: of one state (`T = f64`, slices of the data) or
/// of a block of states in lanes (the batch's lane buffers).
pub(crate) struct Sweep<'a, P: ?Sized, V: ?Sized, F: ?Sized> {
    pub(crate) parent_from_body: &'a mut P,
    pub(crate) velocity: &'a mut V,
    pub(crate) acceleration: &'a mut V,
    pub(crate) force: &'a mut F,
}

/// The joints' armature, damping and friction per degree of freedom.
pub(crate) struct JointTermsRef<'a> {
    pub(crate) armature: &'a [f64],
    pub(crate) damping: &'a [f64],
    pub(crate) friction: &'a [f64],
}

impl JointTermsRef<'_> {
    /// `out += r·a + d·v + μ·sign(v)` (the terms of `ACC` and `VEL` only).
    #[inline(always)]
    pub(crate) fn add<T: Real, const VEL: bool, const ACC: bool>(
        &self,
        v: &[T],
        a: &[T],
        out: &mut [T],
    ) {
        for k in 0..self.armature.len() {
            let mut t = T::ZERO;
            if ACC {
                t += a[k] * self.armature[k];
            }
            if VEL {
                t += v[k] * self.damping[k] + v[k].sign() * self.friction[k];
            }
            out[k] += t;
        }
    }
}

/// The forward sweep of RNEA, written once for one state (`T = f64`) and for a block of states
/// in lanes: each body's placement, velocity, acceleration (with gravity: the root accelerates
/// by `-g`) and net force `I·a + v ×* I·v`.
#[inline(always)]
pub(crate) fn forward<T: Real, const VEL: bool, const ACC: bool>(
    bodies: &Bodies<'_>,
    state: &mut Sweep<
        '_,
        impl IndexMut<usize, Output = Se3<T>> + ?Sized,
        impl IndexMut<usize, Output = Motion<T>> + ?Sized,
        impl IndexMut<usize, Output = Force<T>> + ?Sized,
    >,
    q: &[T],
    v: &[T],
    a: &[T],
) {
    let model = bodies.model;
    let a0 = Motion::<T> {
        linear: T::V3::from_const(-model.gravity()),
        angular: T::V3::ZERO,
    };
    for (i, b) in model.bodies().iter().enumerate().skip(1) {
        let jm = &bodies.joint_models[i];
        let x = jm.placed_transform(&b.placement, &q[b.idx_q..b.idx_q + b.nq]);
        state.parent_from_body[i].assign(&x);
        let p = b.parent;
        let parent_a = if p == 0 { a0 } else { state.acceleration[p] };
        let parent_v = if VEL && p != 0 {
            state.velocity[p]
        } else {
            Motion::zero()
        };
        let (vi, ai) = match jm.axis_index() {
            Some((k, revolute)) => {
                let qd = if VEL { v[b.idx_v] } else { T::ZERO };
                let qdd = if ACC { a[b.idx_v] } else { T::ZERO };
                // A revolute joint whose placement does not rotate, or rotates about the joint's
                // own axis, turns about that axis only (see `AxisTurn`).
                let turn = usize::from(bodies.turn[i]) == k;
                let (pv, pa) = (&parent_v, &parent_a);
                match (k, revolute, turn) {
                    (0, true, true) => {
                        axis_body::<T, VEL, ACC, 0, true, true>(&x, p, pv, pa, qd, qdd)
                    }
                    (1, true, true) => {
                        axis_body::<T, VEL, ACC, 1, true, true>(&x, p, pv, pa, qd, qdd)
                    }
                    (_, true, true) => {
                        axis_body::<T, VEL, ACC, 2, true, true>(&x, p, pv, pa, qd, qdd)
                    }
                    (0, true, false) => {
                        axis_body::<T, VEL, ACC, 0, true, false>(&x, p, pv, pa, qd, qdd)
                    }
                    (1, true, false) => {
                        axis_body::<T, VEL, ACC, 1, true, false>(&x, p, pv, pa, qd, qdd)
                    }
                    (_, true, false) => {
                        axis_body::<T, VEL, ACC, 2, true, false>(&x, p, pv, pa, qd, qdd)
                    }
                    (0, false, _) => {
                        axis_body::<T, VEL, ACC, 0, false, false>(&x, p, pv, pa, qd, qdd)
                    }
                    (1, false, _) => {
                        axis_body::<T, VEL, ACC, 1, false, false>(&x, p, pv, pa, qd, qdd)
                    }
                    (_, false, _) => {
                        axis_body::<T, VEL, ACC, 2, false, false>(&x, p, pv, pa, qd, qdd)
                    }
                }
            }
            None => {
                let r = b.idx_v..b.idx_v + b.nv;
                let mut ai = x.act_inv_motion(&parent_a);
                if ACC {
                    ai += jm.motion(&a[r.clone()]);
                }
                let mut vi = Motion::zero();
                if VEL {
                    let vj = jm.motion(&v[r]);
                    vi = if p == 0 {
                        vj
                    } else {
                        x.act_inv_motion(&parent_v) + vj
                    };
                    ai += vi.cross_motion(&vj);
                }
                (vi, ai)
            }
        };
        let f = if VEL {
            b.inertia.rnea_force(&vi, &ai)
        } else {
            b.inertia.mul_motion(&ai)
        };
        state.velocity[i] = vi;
        state.acceleration[i] = ai;
        state.force[i] = f;
    }
}

/// The backward sweep of RNEA, written once for one state and for lanes: each joint's torque
/// `Sᵀ·f` into `out`, and each body's force added to its parent's.
#[inline(always)]
pub(crate) fn backward<T: Real, P, V>(
    bodies: &Bodies<'_>,
    state: &mut Sweep<'_, P, V, impl IndexMut<usize, Output = Force<T>> + ?Sized>,
    out: &mut [T],
) where
    P: IndexMut<usize, Output = Se3<T>> + ?Sized,
    V: ?Sized,
{
    for (i, b) in bodies.model.bodies().iter().enumerate().skip(1).rev() {
        let fi = state.force[i];
        let jm = &bodies.joint_models[i];
        match jm.project_axis(&fi) {
            Some(x) => out[b.idx_v] = x,
            None => jm.project_force(&fi, &mut out[b.idx_v..b.idx_v + b.nv]),
        }
        if b.parent != 0 {
            let x = &state.parent_from_body[i];
            let fp = match bodies.turn[i] {
                0 => AxisTurn::<T, 0>(x).act_force(&fi),
                1 => AxisTurn::<T, 1>(x).act_force(&fi),
                2 => AxisTurn::<T, 2>(x).act_force(&fi),
                _ => x.act_force(&fi),
            };
            state.force[b.parent] += fp;
        }
    }
}

/// Per body, the coordinate axis (0, 1, 2) its revolute joint turns about alone, or 3: when
/// the placement does not rotate, or rotates about the joint's own axis, the placed rotation's
/// axis column and row are exactly `e_k` (see [`AxisTurn`]).
pub(crate) fn turn_axes(joint_models: &[JointModel], placement_rot: &[RotationForm]) -> Vec<u8> {
    joint_models
        .iter()
        .zip(placement_rot)
        .enumerate()
        .map(|(i, (jm, placement))| match (jm.axis_index(), placement) {
            (Some((k, true)), RotationForm::Identity) if i > 0 => k as u8,
            (Some((k, true)), RotationForm::Axis { k: j, .. }) if i > 0 && *j == k => k as u8,
            _ => 3,
        })
        .collect()
}

/// Velocity and acceleration of a body whose joint is revolute about (`REV`) or prismatic along
/// its axis `K`, from the parent's (in the parent frame) and the joint rates `qd`, `qdd`.
/// With `TURN`, `x`'s rotation is about axis `K` only and is applied through [`AxisTurn`].
#[inline(always)]
fn axis_body<
    T: Real,
    const VEL: bool,
    const ACC: bool,
    const K: usize,
    const REV: bool,
    const TURN: bool,
>(
    x: &Se3<T>,
    parent: usize,
    parent_v: &Motion<T>,
    parent_a: &Motion<T>,
    qd: T,
    qdd: T,
) -> (Motion<T>, Motion<T>) {
    let mut ai = inv_motion::<T, K, TURN>(x, parent_a);
    if ACC {
        if REV {
            *ai.angular.get_mut(K) += qdd;
        } else {
            *ai.linear.get_mut(K) += qdd;
        }
    }
    let mut vi = Motion::zero();
    if VEL {
        if parent != 0 {
            vi = inv_motion::<T, K, TURN>(x, parent_v);
        }
        // a += v ×ₘ vj, with vj = qd·e_K (angular or linear); exactly zero when v = vj.
        if REV {
            *vi.angular.get_mut(K) += qd;
            add_cross_unit::<T, K>(&mut ai.linear, &vi.linear, qd);
            add_cross_unit::<T, K>(&mut ai.angular, &vi.angular, qd);
        } else {
            *vi.linear.get_mut(K) += qd;
            add_cross_unit::<T, K>(&mut ai.linear, &vi.angular, qd);
        }
    }
    (vi, ai)
}

/// `x.act_inv_motion(m)`, through [`AxisTurn`] with `TURN`.
#[inline(always)]
fn inv_motion<T: Real, const K: usize, const TURN: bool>(x: &Se3<T>, m: &Motion<T>) -> Motion<T> {
    if TURN {
        AxisTurn::<T, K>(x).act_inv_motion(m)
    } else {
        x.act_inv_motion(m)
    }
}

/// `out += u × (s·e_K)`, leaving out the component that is zero.
#[inline(always)]
fn add_cross_unit<T: Real, const K: usize>(out: &mut T::V3, u: &T::V3, s: T) {
    let (i, j) = ((K + 1) % 3, (K + 2) % 3);
    // e_i × e_K = -e_j and e_j × e_K = e_i, for (i, j, K) a cyclic order.
    *out.get_mut(i) += u.get(j) * s;
    *out.get_mut(j) += -u.get(i) * s;
}

/// A transform whose rotation turns about coordinate axis `K` only (its `K` column and row are
/// `e_K`): the motion and force kernels with the products by those 0 and 1 entries left out.
/// The same numbers as [`Se3::act_inv_motion`] and [`Se3::act_force`] (adding a product by 0
/// changes nothing).
struct AxisTurn<'a, T: Real, const K: usize>(&'a Se3<T>);

impl<T: Real, const K: usize> AxisTurn<'_, T, K> {
    /// `R·u` (`TRANSPOSE`: `Rᵀ·u`) over the two coordinates other than `K`.
    #[inline(always)]
    fn rotate<const TRANSPOSE: bool>(&self, u: &T::V3) -> T::V3 {
        let r = &self.0.rotation;
        let (i, j) = ((K + 1) % 3, (K + 2) % 3);
        let mut out = *u;
        // Entries (i, i), (i, j), (j, i), (j, j) of R, or of Rᵀ.
        let (ii, ij, ji, jj) = if TRANSPOSE {
            (
                r.col(i).get(i),
                r.col(i).get(j),
                r.col(j).get(i),
                r.col(j).get(j),
            )
        } else {
            (
                r.col(i).get(i),
                r.col(j).get(i),
                r.col(i).get(j),
                r.col(j).get(j),
            )
        };
        *out.get_mut(i) = ii * u.get(i) + ij * u.get(j);
        *out.get_mut(j) = ji * u.get(i) + jj * u.get(j);
        out
    }

    /// [`Se3::act_inv_motion`].
    #[inline(always)]
    fn act_inv_motion(&self, m: &Motion<T>) -> Motion<T> {
        Motion {
            linear: self.rotate::<true>(&(m.linear - self.0.translation.cross(&m.angular))),
            angular: self.rotate::<true>(&m.angular),
        }
    }

    /// [`Se3::act_force`].
    #[inline(always)]
    fn act_force(&self, f: &Force<T>) -> Force<T> {
        let lin = self.rotate::<false>(&f.linear);
        Force {
            linear: lin,
            angular: self.rotate::<false>(&f.angular) + self.0.translation.cross(&lin),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree_kinematics::spatial::glam::DVec3;

    #[test]
    fn axis_turns_match_the_full_kernels() {
        let m = Motion::from_array([-0.4, 0.9, 0.2, 0.6, -0.3, 1.1]);
        let f = Force::from_array([0.3, -1.2, 0.5, 2.0, -0.1, 0.7]);
        let t = DVec3::new(0.1, -0.2, 0.3);
        for theta in [-2.5, -0.3, 0.0, 0.7, 3.0] {
            let x = Se3::new(Se3::from_rotation_x(theta).rotation, t);
            assert!(
                AxisTurn::<f64, 0>(&x)
                    .act_inv_motion(&m)
                    .abs_diff_eq(&x.act_inv_motion(&m), 1e-15)
            );
            assert!(
                AxisTurn::<f64, 0>(&x)
                    .act_force(&f)
                    .abs_diff_eq(&x.act_force(&f), 1e-15)
            );
            let x = Se3::new(Se3::from_rotation_y(theta).rotation, t);
            assert!(
                AxisTurn::<f64, 1>(&x)
                    .act_inv_motion(&m)
                    .abs_diff_eq(&x.act_inv_motion(&m), 1e-15)
            );
            assert!(
                AxisTurn::<f64, 1>(&x)
                    .act_force(&f)
                    .abs_diff_eq(&x.act_force(&f), 1e-15)
            );
            let x = Se3::new(Se3::from_rotation_z(theta).rotation, t);
            assert!(
                AxisTurn::<f64, 2>(&x)
                    .act_inv_motion(&m)
                    .abs_diff_eq(&x.act_inv_motion(&m), 1e-15)
            );
            assert!(
                AxisTurn::<f64, 2>(&x)
                    .act_force(&f)
                    .abs_diff_eq(&x.act_force(&f), 1e-15)
            );
        }
    }
}
