//! Analytic derivatives of kinematics: of a frame's velocity and acceleration with respect to
//! `q`, `v` and `a` ([`frame_velocity_derivatives`], [`frame_acceleration_derivatives`]) and of a
//! frame Jacobian with respect to `q` ([`frame_jacobian_derivatives`], the "Hessian").
//!
//! # Conventions
//!
//! A derivative with respect to `q` is taken in the tangent space: column `k` is
//! `d f(q ⊕ ε·e_k) / dε` at `ε = 0`, with `⊕` = [`configuration::integrate`](crate::configuration::integrate)
//! (spherical, planar and floating joints: a velocity in the child frame; revolute, prismatic and
//! continuous joints: the plain coordinate). The velocity and acceleration are the frame's spatial
//! velocity and spatial acceleration (the derivative of the twist, not the classical
//! acceleration), expressed in the [`ReferenceFrame`] asked for, exactly as
//! [`frame_velocity`](crate::frame_velocity) and [`frame_jacobian`](crate::frame_jacobian) express
//! them; gravity is not included. Each derivative is a `6 x nv` matrix, row-major
//! (`m[r * nv + k]`), rows `[linear; angular]`; columns of joints that do not move the frame are
//! zero. The Jacobian derivative is `nv` such matrices one after the other: block `k` is
//! `∂J/∂q_k`.
//!
//! Coupled mimic joints are not supported (a typed error).

use crate::data::{FrameId, KinematicsData};
use crate::error::{KinematicsError, check_vector};
use crate::jacobian::ReferenceFrame;
use kinetree_model::Model;
use kinetree_model::spatial::{Motion, Se3};

/// The buffers of the kinematics derivatives for one [`Model`]. Create it once with
/// [`KinematicsDerivativesData::new`]; the functions allocate nothing afterwards.
#[derive(Clone, Debug)]
pub struct KinematicsDerivativesData {
    kinematics: KinematicsData,
    /// World-frame spatial velocity and acceleration of each body (at the world origin).
    velocity: Vec<Motion>,
    acceleration: Vec<Motion>,
    /// World-frame motion subspace column of each degree of freedom.
    s: Vec<Motion>,
}

impl KinematicsDerivativesData {
    /// Allocates every buffer for `model`.
    #[must_use]
    pub fn new(model: &Model) -> Self {
        let nb = model.nbodies();
        Self {
            kinematics: KinematicsData::new(model),
            velocity: vec![Motion::ZERO; nb],
            acceleration: vec![Motion::ZERO; nb],
            s: vec![Motion::ZERO; model.nv()],
        }
    }

    /// The kinematics buffers: after a derivative call they hold the placements for its `q`.
    #[must_use]
    pub fn kinematics(&self) -> &KinematicsData {
        &self.kinematics
    }
}

/// Placements, world subspaces, and world velocities/accelerations (when given).
fn sweep(
    model: &Model,
    data: &mut KinematicsDerivativesData,
    q: &[f64],
    v: Option<&[f64]>,
    a: Option<&[f64]>,
) -> Result<(), KinematicsError> {
    data.kinematics.check_model(model)?;
    check_vector("q", q, model.nq())?;
    if let Some(v) = v {
        check_vector("v", v, model.nv())?;
    }
    if let Some(a) = a {
        check_vector("a", a, model.nv())?;
    }
    if let Some(b) = model.bodies().iter().find(|b| b.mimic.is_some()) {
        let joint = b
            .joint
            .map(|j| model.joint(j).name.clone())
            .unwrap_or_default();
        return Err(KinematicsError::WrongJointKind {
            joint,
            kind: b.kind,
            expected: "a joint without mimic coupling (the kinematics derivatives do not support coupled mimic joints)",
        });
    }
    crate::forward::placements(model, &mut data.kinematics, q);
    let kin = &data.kinematics;
    for (i, b) in model.bodies().iter().enumerate().skip(1) {
        let x = kin.world_from_body[i];
        let jm = &kin.joint_models[i];
        let (mut vj, mut aj) = (Motion::ZERO, Motion::ZERO);
        for k in 0..b.nv {
            let d = b.idx_v + k;
            let s = x.act_motion(&jm.subspace_column(k));
            data.s[d] = s;
            if let Some(v) = v {
                vj += s * v[d];
            }
            if let Some(a) = a {
                aj += s * a[d];
            }
        }
        let vi = data.velocity[b.parent] + vj;
        data.velocity[i] = vi;
        data.acceleration[i] = data.acceleration[b.parent] + aj + vi.cross_motion(&vj);
    }
    Ok(())
}

/// Writes column `k` of a 6-row row-major matrix.
#[inline]
fn put(m: &mut [f64], nv: usize, k: usize, x: &Motion) {
    let a = x.to_array();
    for r in 0..6 {
        m[r * nv + k] = a[r];
    }
}

/// Re-expresses the derivative `dx` of a world motion `x` of the frame at `world_from_frame`
/// along the tangent direction `s` (`None`: a derivative along `v` or `a`, which does not move
/// the frame).
#[inline]
fn to_reference(
    world_from_frame: &Se3,
    x: &Motion,
    dx: &Motion,
    s: Option<&Motion>,
    reference: ReferenceFrame,
) -> Motion {
    match reference {
        ReferenceFrame::World => *dx,
        ReferenceFrame::Local => match s {
            Some(s) => world_from_frame.act_inv_motion(&(*dx - s.cross_motion(x))),
            None => world_from_frame.act_inv_motion(dx),
        },
        ReferenceFrame::LocalWorldAligned => {
            let p = world_from_frame.translation;
            let mut out = Motion::new(dx.linear + dx.angular.cross(p), dx.angular);
            if let Some(s) = s {
                let dp = s.linear + s.angular.cross(p);
                out.linear += x.angular.cross(dp);
            }
            out
        }
    }
}

fn check_len(what: &'static str, m: &[f64], expected: usize) -> Result<(), KinematicsError> {
    if m.len() != expected {
        return Err(KinematicsError::DimensionMismatch {
            what,
            expected,
            actual: m.len(),
        });
    }
    Ok(())
}

fn check_matrix(what: &'static str, m: &[f64], nv: usize) -> Result<(), KinematicsError> {
    check_len(what, m, 6 * nv)
}

/// The derivatives of a frame's spatial velocity (in `reference`) with respect to `q` (tangent
/// space) and `v`: `6 x nv` row-major matrices written into `dv_dq` and `dv_dv` (`∂v/∂v` is the
/// frame Jacobian). See the [module documentation](self) for the conventions. Allocates nothing.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] or [`KinematicsError::NonFinite`] for a bad `q`, `v` or
/// output length; [`KinematicsError::DataMismatch`] when `data` belongs to another model;
/// [`KinematicsError::WrongJointKind`] for a model with coupled mimic joints.
///
/// # Examples
/// ```
/// use kinetree_kinematics::{frame_velocity_derivatives, FrameId, KinematicsDerivativesData, ReferenceFrame};
/// use kinetree_kinematics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A 0.5 m rod hinged about z: the tip moves at (-l·sin θ, l·cos θ)·θ̇ in the world.
/// let urdf = r#"<robot name="r"><link name="base"/><link name="rod"/><link name="tip"/>
///   <joint name="hinge" type="continuous"><parent link="base"/><child link="rod"/><axis xyz="0 0 1"/></joint>
///   <joint name="fix" type="fixed"><parent link="rod"/><child link="tip"/><origin xyz="0.5 0 0"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = KinematicsDerivativesData::new(&model);
/// let tip = FrameId::find(&model, "tip")?;
/// let (mut dq, mut dv) = ([0.0; 6], [0.0; 6]);
/// let (theta, rate) = (0.3_f64, 2.0);
/// frame_velocity_derivatives(&model, &mut data, &[theta], &[rate], tip,
///     ReferenceFrame::LocalWorldAligned, &mut dq, &mut dv)?;
/// // ∂ẋ/∂θ = -l·cos θ·θ̇, and ∂ẋ/∂θ̇ = -l·sin θ.
/// assert!((dq[0] + 0.5 * theta.cos() * rate).abs() < 1e-12);
/// assert!((dv[0] + 0.5 * theta.sin()).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
#[allow(
    clippy::too_many_arguments,
    reason = "mirrors Pinocchio's getFrameVelocityDerivatives"
)]
pub fn frame_velocity_derivatives(
    model: &Model,
    data: &mut KinematicsDerivativesData,
    q: &[f64],
    v: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    dv_dq: &mut [f64],
    dv_dv: &mut [f64],
) -> Result<(), KinematicsError> {
    let nv = model.nv();
    check_matrix("dv_dq", dv_dq, nv)?;
    check_matrix("dv_dv", dv_dv, nv)?;
    sweep(model, data, q, Some(v), None)?;
    dv_dq.fill(0.0);
    dv_dv.fill(0.0);
    let (body, body_from_frame) = frame.body(model)?;
    let omf = data.kinematics.world_from_body[body] * body_from_frame;
    let vi = data.velocity[body];
    let bodies = model.bodies();
    let mut i = body;
    while i != 0 {
        let b = &bodies[i];
        let vp = data.velocity[b.parent];
        for d in b.idx_v..b.idx_v + b.nv {
            let s = data.s[d];
            let dq = s.cross_motion(&(vi - vp));
            put(
                dv_dq,
                nv,
                d,
                &to_reference(&omf, &vi, &dq, Some(&s), reference),
            );
            put(dv_dv, nv, d, &to_reference(&omf, &vi, &s, None, reference));
        }
        i = b.parent;
    }
    Ok(())
}

/// The derivatives of a frame's spatial velocity and spatial acceleration (in `reference`):
/// `∂v/∂q`, `∂a/∂q` (tangent space), `∂a/∂v` and `∂a/∂a` (the frame Jacobian), each a `6 x nv`
/// row-major matrix. See the [module documentation](self) for the conventions. Allocates
/// nothing.
///
/// # Errors
/// As [`frame_velocity_derivatives`], and for a bad `a`.
#[allow(
    clippy::too_many_arguments,
    reason = "mirrors Pinocchio's getFrameAccelerationDerivatives"
)]
pub fn frame_acceleration_derivatives(
    model: &Model,
    data: &mut KinematicsDerivativesData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    dv_dq: &mut [f64],
    da_dq: &mut [f64],
    da_dv: &mut [f64],
    da_da: &mut [f64],
) -> Result<(), KinematicsError> {
    let nv = model.nv();
    for (what, m) in [
        ("dv_dq", &*dv_dq),
        ("da_dq", &*da_dq),
        ("da_dv", &*da_dv),
        ("da_da", &*da_da),
    ] {
        check_matrix(what, m, nv)?;
    }
    sweep(model, data, q, Some(v), Some(a))?;
    for m in [&mut *dv_dq, &mut *da_dq, &mut *da_dv, &mut *da_da] {
        m.fill(0.0);
    }
    let (body, body_from_frame) = frame.body(model)?;
    let omf = data.kinematics.world_from_body[body] * body_from_frame;
    let (vi, ai) = (data.velocity[body], data.acceleration[body]);
    let bodies = model.bodies();
    let mut i = body;
    while i != 0 {
        let b = &bodies[i];
        let (vp, ap) = (data.velocity[b.parent], data.acceleration[b.parent]);
        let vb = data.velocity[i];
        for d in b.idx_v..b.idx_v + b.nv {
            let s = data.s[d];
            let rel = vi - vp;
            let dvq = s.cross_motion(&rel);
            put(
                dv_dq,
                nv,
                d,
                &to_reference(&omf, &vi, &dvq, Some(&s), reference),
            );
            let daq = s.cross_motion(&(ai - ap)) - s.cross_motion(&vp).cross_motion(&rel);
            put(
                da_dq,
                nv,
                d,
                &to_reference(&omf, &ai, &daq, Some(&s), reference),
            );
            let dav = dvq + vb.cross_motion(&s);
            put(
                da_dv,
                nv,
                d,
                &to_reference(&omf, &ai, &dav, None, reference),
            );
            put(da_da, nv, d, &to_reference(&omf, &ai, &s, None, reference));
        }
        i = b.parent;
    }
    Ok(())
}

/// The derivative of a frame Jacobian (in `reference`) with respect to `q` (tangent space):
/// `out` holds `nv` row-major `6 x nv` blocks, block `k` being `∂J/∂q_k` (length `6·nv²`).
/// Roboticists call this the manipulator Hessian. Allocates nothing.
///
/// # Errors
/// As [`frame_velocity_derivatives`], for `q` and `out`.
pub fn frame_jacobian_derivatives(
    model: &Model,
    data: &mut KinematicsDerivativesData,
    q: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    out: &mut [f64],
) -> Result<(), KinematicsError> {
    let nv = model.nv();
    check_len("out", out, 6 * nv * nv)?;
    sweep(model, data, q, None, None)?;
    out.fill(0.0);
    let (body, body_from_frame) = frame.body(model)?;
    let omf = data.kinematics.world_from_body[body] * body_from_frame;
    let bodies = model.bodies();
    // Each column m of the chain, differentiated along each chain coordinate k.
    let mut bm = body;
    while bm != 0 {
        let b = &bodies[bm];
        for m in b.idx_v..b.idx_v + b.nv {
            let sm = data.s[m];
            let mut bk = body;
            while bk != 0 {
                let c = &bodies[bk];
                for k in c.idx_v..c.idx_v + c.nv {
                    let sk = data.s[k];
                    // S_m turns with q_k when k's joint carries m's joint (or is it).
                    let ds = if bk <= bm {
                        sk.cross_motion(&sm)
                    } else {
                        Motion::ZERO
                    };
                    let x = to_reference(&omf, &sm, &ds, Some(&sk), reference);
                    put(&mut out[k * 6 * nv..(k + 1) * 6 * nv], nv, m, &x);
                }
                bk = c.parent;
            }
        }
        bm = b.parent;
    }
    Ok(())
}
