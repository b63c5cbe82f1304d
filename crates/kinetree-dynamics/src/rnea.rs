//! Inverse dynamics: the recursive Newton–Euler algorithm and the torques derived from it.

use crate::data::{DynamicsData, sign};
use crate::error::{DynamicsError, check_output, check_vector};
use crate::external::ExternalForces;
use kinetree_kinematics::JointModel;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::RotationForm;
use kinetree_kinematics::spatial::axis::cross_unit;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::{Force, Motion, Se3};

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

/// The RNEA sweeps. `VEL`: `v` is used (else zero); `ACC`: `a` is used (else zero).
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

/// [`sweep`], to be compiled for the instruction set it runs with.
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
    let bodies = model.bodies();
    let a0 = Motion::new(-model.gravity(), DVec3::ZERO);
    let world = fext.is_some_and(ExternalForces::needs_world);
    let kin = data.kinematics.body_buffers_mut();
    kin.q.copy_from_slice(q);
    let joint_models = kin.joint_models;
    let placement_rot = &data.placement_rot;
    for i in 1..bodies.len() {
        let b = &bodies[i];
        let jm = &joint_models[i];
        let x = jm.placed_transform(&b.placement, &q[b.idx_q..b.idx_q + b.nq]);
        kin.parent_from_body[i] = x;
        let p = b.parent;
        if world {
            kin.world_from_body[i] = if p == 0 {
                x
            } else {
                kin.world_from_body[p] * x
            };
        }
        let parent_a = if p == 0 { a0 } else { data.acceleration[p] };
        let parent_v = if VEL && p != 0 {
            kin.body_velocity[p]
        } else {
            Motion::ZERO
        };
        let scalar = |s: &[f64]| if s.is_empty() { 0.0 } else { s[b.idx_v] };
        let (qd, qdd) = (scalar(v), scalar(a));
        // A revolute joint whose placement does not rotate, or rotates about the joint's own
        // axis, turns about that axis only: its rotation has four entries that are not 0 or 1
        // (see `AxisTurn`).
        let placement = &placement_rot[i];
        let (vi, ai) = match jm {
            JointModel::RevoluteX if turns_about(placement, 0) => {
                body::<VEL, ACC, 0, true, true>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            JointModel::RevoluteY if turns_about(placement, 1) => {
                body::<VEL, ACC, 1, true, true>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            JointModel::RevoluteZ if turns_about(placement, 2) => {
                body::<VEL, ACC, 2, true, true>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            JointModel::RevoluteX => {
                body::<VEL, ACC, 0, true, false>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            JointModel::RevoluteY => {
                body::<VEL, ACC, 1, true, false>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            JointModel::RevoluteZ => {
                body::<VEL, ACC, 2, true, false>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            JointModel::PrismaticX => {
                body::<VEL, ACC, 0, false, false>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            JointModel::PrismaticY => {
                body::<VEL, ACC, 1, false, false>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            JointModel::PrismaticZ => {
                body::<VEL, ACC, 2, false, false>(&x, p, &parent_v, &parent_a, qd, qdd)
            }
            _ => {
                let r = b.idx_v..b.idx_v + b.nv;
                let mut ai = x.act_inv_motion(&parent_a);
                if ACC {
                    ai += jm.motion(&a[r.clone()]);
                }
                let mut vi = Motion::ZERO;
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
        let inertia = &b.inertia;
        let f = if VEL {
            inertia.rnea_force(&vi, &ai)
        } else {
            inertia.mul_motion(&ai)
        };
        kin.body_velocity[i] = vi;
        data.acceleration[i] = ai;
        data.force[i] = f;
    }
    if let Some(fext) = fext {
        let force = &mut data.force;
        fext.for_each_local(data.kinematics.world_from_body(), |body, f| {
            force[body] -= f
        });
    }
    let out = match output {
        Output::Tau => &mut data.tau,
        Output::Nle => &mut data.nle,
        Output::Gravity => &mut data.gravity_torque,
    };
    let (joint_models, parent_from_body) = (
        data.kinematics.joint_models(),
        data.kinematics.parent_from_body(),
    );
    for i in (1..bodies.len()).rev() {
        let b = &bodies[i];
        let fi = data.force[i];
        let jm = &joint_models[i];
        match jm.project_axis(&fi) {
            Some(x) => out[b.idx_v] = x,
            None => jm.project_force(&fi, &mut out[b.idx_v..b.idx_v + b.nv]),
        }
        if b.parent != 0 {
            let x = &parent_from_body[i];
            let fp = match jm.axis_index() {
                Some((k, true)) if turns_about(&data.placement_rot[i], k) => match k {
                    0 => AxisTurn::<0>(x).act_force(&fi),
                    1 => AxisTurn::<1>(x).act_force(&fi),
                    _ => AxisTurn::<2>(x).act_force(&fi),
                },
                _ => x.act_force(&fi),
            };
            data.force[b.parent] += fp;
        }
    }
    if data.has_joint_terms {
        for k in 0..out.len() {
            let mut t = 0.0;
            if ACC {
                t += data.armature[k] * a[k];
            }
            if VEL {
                t += data.damping[k] * v[k] + data.friction[k] * sign(v[k]);
            }
            out[k] += t;
        }
    }
}

/// Whether a revolute joint about coordinate axis `k` placed with rotation `placement` turns
/// about that axis only: the placement does not rotate, or rotates about the same axis (then
/// the placed rotation's `k` column and row are exactly `e_k`, see [`AxisTurn`]).
#[inline(always)]
pub(crate) fn turns_about(placement: &RotationForm, k: usize) -> bool {
    match placement {
        RotationForm::Identity => true,
        RotationForm::Axis { k: j, .. } => *j == k,
        RotationForm::General(_) => false,
    }
}

/// Velocity and acceleration of a body whose joint is revolute about (`REV`) or prismatic along
/// its axis `K`, from the parent's (in the parent frame) and the joint rates `qd`, `qdd`.
/// With `TURN`, `x`'s rotation is about axis `K` only (a revolute joint whose placement does not
/// rotate) and is applied through [`AxisTurn`].
#[inline(always)]
fn body<const VEL: bool, const ACC: bool, const K: usize, const REV: bool, const TURN: bool>(
    x: &Se3,
    parent: usize,
    parent_v: &Motion,
    parent_a: &Motion,
    qd: f64,
    qdd: f64,
) -> (Motion, Motion) {
    let inv = |m: &Motion| {
        if TURN {
            AxisTurn::<K>(x).act_inv_motion(m)
        } else {
            x.act_inv_motion(m)
        }
    };
    let mut ai = inv(parent_a);
    if ACC {
        if REV {
            ai.angular[K] += qdd;
        } else {
            ai.linear[K] += qdd;
        }
    }
    let mut vi = Motion::ZERO;
    if VEL {
        if parent != 0 {
            vi = inv(parent_v);
        }
        // a += v ×ₘ vj, with vj = qd·e_K (angular or linear); exactly zero when v = vj.
        if REV {
            vi.angular[K] += qd;
            ai.linear += cross_unit::<K>(vi.linear, qd);
            ai.angular += cross_unit::<K>(vi.angular, qd);
        } else {
            vi.linear[K] += qd;
            ai.linear += cross_unit::<K>(vi.angular, qd);
        }
    }
    (vi, ai)
}

/// A transform whose rotation turns about coordinate axis `K` only (its `K` column and row are
/// `e_K`): the motion and force kernels with the products by those 0 and 1 entries left out.
/// The same numbers as [`Se3::act_inv_motion`] and [`Se3::act_force`] (adding a product by 0
/// changes nothing).
struct AxisTurn<'a, const K: usize>(&'a Se3);

impl<const K: usize> AxisTurn<'_, K> {
    /// `R·u`.
    #[inline(always)]
    fn rotate(&self, u: DVec3) -> DVec3 {
        let r = &self.0.rotation;
        match K {
            0 => DVec3::new(
                u.x,
                r.y_axis.y * u.y + r.z_axis.y * u.z,
                r.y_axis.z * u.y + r.z_axis.z * u.z,
            ),
            1 => DVec3::new(
                r.x_axis.x * u.x + r.z_axis.x * u.z,
                u.y,
                r.x_axis.z * u.x + r.z_axis.z * u.z,
            ),
            _ => DVec3::new(
                r.x_axis.x * u.x + r.y_axis.x * u.y,
                r.x_axis.y * u.x + r.y_axis.y * u.y,
                u.z,
            ),
        }
    }

    /// `Rᵀ·u`.
    #[inline(always)]
    fn inverse_rotate(&self, u: DVec3) -> DVec3 {
        let r = &self.0.rotation;
        match K {
            0 => DVec3::new(
                u.x,
                r.y_axis.y * u.y + r.y_axis.z * u.z,
                r.z_axis.y * u.y + r.z_axis.z * u.z,
            ),
            1 => DVec3::new(
                r.x_axis.x * u.x + r.x_axis.z * u.z,
                u.y,
                r.z_axis.x * u.x + r.z_axis.z * u.z,
            ),
            _ => DVec3::new(
                r.x_axis.x * u.x + r.x_axis.y * u.y,
                r.y_axis.x * u.x + r.y_axis.y * u.y,
                u.z,
            ),
        }
    }

    /// [`Se3::act_inv_motion`].
    #[inline(always)]
    fn act_inv_motion(&self, m: &Motion) -> Motion {
        Motion::new(
            self.inverse_rotate(m.linear - self.0.translation.cross(m.angular)),
            self.inverse_rotate(m.angular),
        )
    }

    /// [`Se3::act_force`].
    #[inline(always)]
    fn act_force(&self, f: &Force) -> Force {
        let lin = self.rotate(f.linear);
        Force::new(lin, self.rotate(f.angular) + self.0.translation.cross(lin))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_turns_match_the_full_kernels() {
        let m = Motion::from_array([-0.4, 0.9, 0.2, 0.6, -0.3, 1.1]);
        let f = Force::from_array([0.3, -1.2, 0.5, 2.0, -0.1, 0.7]);
        let t = DVec3::new(0.1, -0.2, 0.3);
        for theta in [-2.5, -0.3, 0.0, 0.7, 3.0] {
            let x = Se3::new(Se3::from_rotation_x(theta).rotation, t);
            assert!(
                AxisTurn::<0>(&x)
                    .act_inv_motion(&m)
                    .abs_diff_eq(&x.act_inv_motion(&m), 1e-15)
            );
            assert!(
                AxisTurn::<0>(&x)
                    .act_force(&f)
                    .abs_diff_eq(&x.act_force(&f), 1e-15)
            );
            let x = Se3::new(Se3::from_rotation_y(theta).rotation, t);
            assert!(
                AxisTurn::<1>(&x)
                    .act_inv_motion(&m)
                    .abs_diff_eq(&x.act_inv_motion(&m), 1e-15)
            );
            assert!(
                AxisTurn::<1>(&x)
                    .act_force(&f)
                    .abs_diff_eq(&x.act_force(&f), 1e-15)
            );
            let x = Se3::new(Se3::from_rotation_z(theta).rotation, t);
            assert!(
                AxisTurn::<2>(&x)
                    .act_inv_motion(&m)
                    .abs_diff_eq(&x.act_inv_motion(&m), 1e-15)
            );
            assert!(
                AxisTurn::<2>(&x)
                    .act_force(&f)
                    .abs_diff_eq(&x.act_force(&f), 1e-15)
            );
        }
    }
}
