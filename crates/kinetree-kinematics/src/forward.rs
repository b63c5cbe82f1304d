//! Forward kinematics: world placements of bodies, links and frames; body velocities and
//! accelerations.

use crate::data::{FrameId, KinematicsData};
use crate::error::{KinematicsError, check_q, check_vector};
use crate::joint::sin_cos;
use crate::joint::transform::{axis_rotation, rotate_about_axis};
use kinetree_model::Model;
use kinetree_model::spatial::{Motion, Se3};

/// Computes the world placement of every body and link for configuration `q` (length
/// `model.nq()`).
///
/// Results are stored in `data`: [`KinematicsData::world_from_body`],
/// [`KinematicsData::world_from_link`]. Allocates nothing.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] or [`KinematicsError::NonFinite`] for a bad `q`,
/// [`KinematicsError::DataMismatch`] when `data` belongs to another model.
///
/// # Examples
/// ```
/// use kinetree_kinematics::{forward_kinematics, FrameId, KinematicsData};
/// use kinetree_model::{Model, RootJoint};
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let urdf = r#"<robot name="arm"><link name="base"/><link name="tip"/>
///   <joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
///     <origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = KinematicsData::new(&model);
/// forward_kinematics(&model, &mut data, &[std::f64::consts::FRAC_PI_2])?;
/// let tip = data.world_from(FrameId::find(&model, "tip")?)?;
/// // The tip frame sits at x = 1, turned 90° about z: its x axis points along world y.
/// assert!((tip.translation.x - 1.0).abs() < 1e-15);
/// assert!((tip.rotation.x_axis.y - 1.0).abs() < 1e-15);
/// # Ok(())
/// # }
/// ```
pub fn forward_kinematics(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
) -> Result<(), KinematicsError> {
    body_placements(model, data, q)?;
    link_placements(model, data);
    Ok(())
}

/// Checks the model and `q`, then writes the body placements and checks they are finite: what
/// [`forward_kinematics`] and the Jacobians without links share.
pub(crate) fn body_placements(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
) -> Result<(), KinematicsError> {
    data.check_model(model)?;
    check_q(model, "q", q)?;
    placements(model, data, q);
    check_finite(model, "placement", &data.world_from_body, |x| {
        x.translation.is_finite()
    })
}

/// Forward kinematics with velocities: as [`forward_kinematics`], and the spatial velocity of each
/// body in its own frame ([`KinematicsData::body_velocity`]) for joint velocity `v` (length
/// `model.nv()`).
///
/// # Errors
/// As [`forward_kinematics`], for `q` and `v`.
pub fn forward_kinematics_with_velocity(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
    v: &[f64],
) -> Result<(), KinematicsError> {
    data.check_model(model)?;
    check_q(model, "q", q)?;
    check_vector("v", v, model.nv())?;
    placements(model, data, q);
    let bodies = model.bodies();
    for i in 1..bodies.len() {
        let b = &bodies[i];
        let vj = data.joint_models[i].body_motion(b, v);
        let parent_v = data.parent_from_body[i].act_inv_motion(&data.body_velocity[b.parent]);
        data.body_velocity[i] = parent_v + vj;
    }
    check_finite(model, "placement", &data.world_from_body, |x| {
        x.translation.is_finite()
    })?;
    check_finite(model, "velocity", &data.body_velocity, Motion::is_finite)?;
    link_placements(model, data);
    Ok(())
}

/// Forward kinematics with velocities and accelerations: as
/// [`forward_kinematics_with_velocity`], and the spatial acceleration of each body in its own
/// frame ([`KinematicsData::body_acceleration`]) for joint acceleration `a` (length `model.nv()`).
/// Gravity is not included.
///
/// # Errors
/// As [`forward_kinematics`], for `q`, `v` and `a`.
pub fn forward_kinematics_with_acceleration(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<(), KinematicsError> {
    check_vector("a", a, model.nv())?;
    forward_kinematics_with_velocity(model, data, q, v)?;
    let bodies = model.bodies();
    for i in 1..bodies.len() {
        let b = &bodies[i];
        let jm = &data.joint_models[i];
        let aj = jm.body_motion(b, a);
        let vj = jm.body_motion(b, v);
        let parent_a = data.parent_from_body[i].act_inv_motion(&data.body_acceleration[b.parent]);
        data.body_acceleration[i] = parent_a + aj + data.body_velocity[i].cross_motion(&vj);
    }
    check_finite(
        model,
        "acceleration",
        &data.body_acceleration,
        Motion::is_finite,
    )?;
    Ok(())
}

/// [`KinematicsError::Overflow`] naming the first body whose entry of `xs` fails `ok`.
pub(crate) fn check_finite<T>(
    model: &Model,
    what: &'static str,
    xs: &[T],
    ok: impl Fn(&T) -> bool,
) -> Result<(), KinematicsError> {
    match xs.iter().position(|x| !ok(x)) {
        None => Ok(()),
        Some(i) => Err(overflow(model, what, i)),
    }
}

/// [`KinematicsError::Overflow`] of `what` at body `i`, named by its first link.
pub(crate) fn overflow(model: &Model, what: &'static str, i: usize) -> KinematicsError {
    let body = model
        .links()
        .iter()
        .enumerate()
        .find(|&(l, _)| model.link_body(l).0 == i)
        .map_or_else(|| format!("#{i}"), |(_, link)| link.name.clone());
    KinematicsError::Overflow { what, body }
}

/// The body sweep shared by every variant: `parent_from_body` and `world_from_body`.
#[inline]
pub(crate) fn placements(model: &Model, data: &mut KinematicsData, q: &[f64]) {
    data.q.copy_from_slice(q);
    for i in 1..model.bodies().len() {
        place(model, data, q, i);
    }
}

/// [`placements`] of body `target` and its ancestors only (the joints that move it); the other
/// bodies keep their earlier placements. Bodies are stored depth-first, so body `i` supports
/// `target` exactly when `i <= target < subtree_end(i)`.
#[inline]
pub(crate) fn placements_to(model: &Model, data: &mut KinematicsData, q: &[f64], target: usize) {
    data.q.copy_from_slice(q);
    let bodies = model.bodies();
    for i in 1..=target.min(bodies.len() - 1) {
        if bodies[i].subtree_end > target {
            place(model, data, q, i);
        }
    }
}

/// `parent_from_body[i]` and `world_from_body[i]` from `q` and the parent's world placement.
#[inline(always)]
fn place(model: &Model, data: &mut KinematicsData, q: &[f64], i: usize) {
    let b = &model.bodies()[i];
    let jm = &data.joint_models[i];
    // A revolute joint about a coordinate axis whose placement does not rotate (most joints
    // of legged robots and humanoids): the world rotation is the parent's turned about that
    // axis, two columns of three, instead of a 3x3 product. Same numbers as the product
    // (it only skips multiplications by 0 and 1).
    let k = usize::from(data.turn_axis[i]);
    if k < 3 {
        let (s, c) = sin_cos(q[b.idx_q]);
        let t = b.placement.translation;
        data.parent_from_body[i] = Se3::new(axis_rotation(k, s, c), t);
        let w = &data.world_from_body[b.parent];
        data.world_from_body[i] = Se3::new(
            rotate_about_axis(&w.rotation, k, s, c),
            w.rotation * t + w.translation,
        );
        return;
    }
    // The joint's kernel inlined into the sweep (`body_transform` was a call that returned the
    // placement through memory).
    let local = match &b.mimic {
        None => jm.placed_transform(&b.placement, &q[b.idx_q..b.idx_q + b.nq]),
        Some(_) => jm.body_transform(b, q),
    };
    data.parent_from_body[i] = local;
    data.world_from_body[i] = if b.parent == 0 {
        local
    } else {
        data.world_from_body[b.parent] * local
    };
}

#[inline]
fn link_placements(model: &Model, data: &mut KinematicsData) {
    for (l, out) in data.world_from_link.iter_mut().enumerate() {
        let (b, body_from_link) = model.link_body(l);
        *out = if data.link_on_body_frame[l] {
            data.world_from_body[b]
        } else {
            data.world_from_body[b] * *body_from_link
        };
    }
}

/// Recomputes the world placement of every body and link ([`KinematicsData::world_from_body`],
/// [`KinematicsData::world_from_link`]) from the stored
/// [`parent_from_body`](KinematicsData::parent_from_body): what is left of forward kinematics
/// after a sweep that stored the local placements only (the dynamics algorithms: RNEA, CRBA and
/// ABA leave their configuration's `parent_from_body` in the kinematics data they embed).
/// No trigonometry; allocates nothing.
///
/// # Errors
/// [`KinematicsError::DataMismatch`] when `data` belongs to another model.
pub fn update_world_placements(
    model: &Model,
    data: &mut KinematicsData,
) -> Result<(), KinematicsError> {
    data.check_model(model)?;
    let bodies = model.bodies();
    for i in 1..bodies.len() {
        let p = bodies[i].parent;
        let local = data.parent_from_body[i];
        data.world_from_body[i] = if p == 0 {
            local
        } else {
            data.world_from_body[p] * local
        };
    }
    link_placements(model, data);
    Ok(())
}

/// Updates the world placement of every named frame from the last forward kinematics
/// ([`KinematicsData::world_from_frame`]). Allocates nothing.
///
/// # Errors
/// [`KinematicsError::DataMismatch`] when `data` belongs to another model.
pub fn update_frame_placements(
    model: &Model,
    data: &mut KinematicsData,
) -> Result<(), KinematicsError> {
    data.check_model(model)?;
    for (f, out) in data.world_from_frame.iter_mut().enumerate() {
        let frame = &model.frames()[f];
        *out = data.world_from_link[frame.link] * frame.placement;
    }
    Ok(())
}

/// The pose of frame `b` in frame `a` (`a_from_b`) from the last forward kinematics (and
/// [`update_frame_placements`] for named frames).
///
/// # Errors
/// [`KinematicsError::FrameOutOfRange`] for an index the data's model does not have.
pub fn relative_transform(
    data: &KinematicsData,
    a: FrameId,
    b: FrameId,
) -> Result<Se3, KinematicsError> {
    Ok(data.world_from(a)?.inv_mul(data.world_from(b)?))
}

/// The spatial velocity of a link or frame from the last
/// [`forward_kinematics_with_velocity`], in the given reference frame
/// (see [`ReferenceFrame`](crate::ReferenceFrame)).
///
/// # Errors
/// [`KinematicsError::FrameOutOfRange`] for an index `model` does not have,
/// [`KinematicsError::DataMismatch`] when `data` belongs to another model.
pub fn frame_velocity(
    model: &Model,
    data: &KinematicsData,
    frame: FrameId,
    reference: crate::ReferenceFrame,
) -> Result<Motion, KinematicsError> {
    data.check_model(model)?;
    let (b, body_from_frame) = frame.body(model)?;
    let local = body_from_frame.act_inv_motion(&data.body_velocity[b]);
    let world_from_frame = data.world_from_body[b] * body_from_frame;
    Ok(crate::jacobian::change_reference(
        &world_from_frame,
        &local,
        reference,
    ))
}
