//! Joint and frame Jacobians and their time derivatives.
//!
//! A Jacobian is stored as `nv` columns of [`Motion`] (`[linear; angular]`): column `k` is the
//! twist produced by a unit velocity of coordinate `k`. Use [`jacobian_to_rows`] for a 6 x nv
//! row-major matrix.

use crate::data::{FrameId, KinematicsData};
use crate::error::{KinematicsError, check_q};
use crate::forward::{body_placements, forward_kinematics_with_velocity, placements_to};
use kinetree_model::Model;
use kinetree_model::spatial::{Motion, Se3};

/// The point and the axes in which a frame's velocity or Jacobian is expressed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ReferenceFrame {
    /// World axes; the linear part is the velocity of the (possibly imaginary) point of the body
    /// that is at the world origin. This is the natural spatial-algebra form.
    World,
    /// The frame's own axes; the linear part is the velocity of the frame origin.
    Local,
    /// World axes; the linear part is the velocity of the frame origin. The usual choice for
    /// task-space control and inverse kinematics (and the reference data's convention).
    #[default]
    LocalWorldAligned,
}

/// Re-expresses a twist given in a frame's own coordinates (`local`, at the frame origin) in
/// `reference`, for a frame at `world_from_frame`.
#[inline]
#[must_use]
pub fn change_reference(
    world_from_frame: &Se3,
    local: &Motion,
    reference: ReferenceFrame,
) -> Motion {
    match reference {
        ReferenceFrame::Local => *local,
        ReferenceFrame::World => world_from_frame.act_motion(local),
        ReferenceFrame::LocalWorldAligned => Motion::new(
            world_from_frame.rotation * local.linear,
            world_from_frame.rotation * local.angular,
        ),
    }
}

/// A world-frame twist (at the world origin) re-expressed for a frame at `world_from_frame`.
#[inline]
fn world_to_reference(world_from_frame: &Se3, world: &Motion, reference: ReferenceFrame) -> Motion {
    match reference {
        ReferenceFrame::World => *world,
        ReferenceFrame::Local => world_from_frame.act_inv_motion(world),
        ReferenceFrame::LocalWorldAligned => Motion::new(
            world.linear + world.angular.cross(world_from_frame.translation),
            world.angular,
        ),
    }
}

/// Computes forward kinematics for `q` and every joint Jacobian column in the world frame
/// ([`KinematicsData::joint_jacobians`]). Link placements are updated too
/// ([`compute_joint_jacobians_without_links`] skips them). Allocates nothing.
///
/// # Errors
/// As [`forward_kinematics`](crate::forward_kinematics).
pub fn compute_joint_jacobians(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
) -> Result<(), KinematicsError> {
    crate::forward_kinematics(model, data, q)?;
    fill_joint_jacobians(model, data);
    Ok(())
}

/// Computes the body placements for `q` ([`KinematicsData::world_from_body`], Pinocchio's `oMi`)
/// and every joint Jacobian column in the world frame ([`KinematicsData::joint_jacobians`]), and
/// nothing else: the work of Pinocchio's `computeJointJacobians`. Unlike
/// [`compute_joint_jacobians`] it leaves the link placements
/// ([`KinematicsData::world_from_link`]) as they were, so call [`forward_kinematics`](crate::forward_kinematics)
/// before reading those; [`frame_jacobian`] reads only the body placements and works after either
/// call. The Jacobian columns are the same numbers as [`compute_joint_jacobians`]'s, bit for bit.
/// Allocates nothing.
///
/// # Errors
/// As [`forward_kinematics`](crate::forward_kinematics).
///
/// # Examples
/// ```
/// use kinetree_kinematics::{compute_joint_jacobians_without_links, frame_jacobian, FrameId,
///                           KinematicsData, ReferenceFrame};
/// use kinetree_model::{Model, RootJoint};
/// use kinetree_model::spatial::Motion;
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let urdf = r#"<robot name="arm"><link name="base"/><link name="tip"/>
///   <joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
///     <origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = KinematicsData::new(&model);
/// compute_joint_jacobians_without_links(&model, &mut data, &[0.3])?;
/// // The joint turns about world z through (1, 0, 0): its world twist is (0, -1, 0; 0, 0, 1).
/// let column = data.joint_jacobians()[0];
/// assert!((column.linear.y + 1.0).abs() < 1e-15 && (column.angular.z - 1.0).abs() < 1e-15);
/// // A frame Jacobian reads the body placements this call wrote.
/// let mut jacobian = vec![Motion::ZERO; model.nv()];
/// let tip = FrameId::find(&model, "tip")?;
/// frame_jacobian(&model, &data, tip, ReferenceFrame::LocalWorldAligned, &mut jacobian)?;
/// assert!((jacobian[0].linear.y - 0.0).abs() < 1e-15);
/// # Ok(())
/// # }
/// ```
pub fn compute_joint_jacobians_without_links(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
) -> Result<(), KinematicsError> {
    body_placements(model, data, q)?;
    fill_joint_jacobians(model, data);
    Ok(())
}

fn fill_joint_jacobians(model: &Model, data: &mut KinematicsData) {
    for (i, b) in model.bodies().iter().enumerate().skip(1) {
        let x = &data.world_from_body[i];
        let jm = &data.joint_models[i];
        if let Some(col) = jm.act_axis(x) {
            if b.mimic.is_some() {
                data.mimic_jacobian[i] = col;
            } else {
                data.jacobian[b.idx_v] = col;
            }
            continue;
        }
        if b.mimic.is_some() {
            data.mimic_jacobian[i] = x.act_motion(&jm.subspace_column(0));
        }
        for k in 0..b.nv {
            data.jacobian[b.idx_v + k] = x.act_motion(&jm.subspace_column(k));
        }
    }
}

fn check_out(out: &[Motion], nv: usize) -> Result<(), KinematicsError> {
    if out.len() != nv {
        return Err(KinematicsError::DimensionMismatch {
            what: "jacobian",
            expected: nv,
            actual: out.len(),
        });
    }
    Ok(())
}

/// Writes the Jacobian of a link or frame into `out` (`nv` columns) from the joint Jacobians of
/// the last [`compute_joint_jacobians`]: `out · v` is the frame's twist in `reference`. Columns of
/// joints that do not move the frame are zero. Allocates nothing.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] when `out.len() != model.nv()`,
/// [`KinematicsError::DataMismatch`] when `data` belongs to another model,
/// [`KinematicsError::FrameOutOfRange`] for a link or frame index `model` does not have.
pub fn frame_jacobian(
    model: &Model,
    data: &KinematicsData,
    frame: FrameId,
    reference: ReferenceFrame,
    out: &mut [Motion],
) -> Result<(), KinematicsError> {
    data.check_model(model)?;
    check_out(out, model.nv())?;
    let (body, body_from_frame) = frame.body(model)?;
    let world_from_frame = data.world_from_body[body] * body_from_frame;
    out.fill(Motion::ZERO);
    let bodies = model.bodies();
    let mut i = body;
    while i != 0 {
        let b = &bodies[i];
        // Accumulate: a coupled mimic follower adds to its leader's column.
        if let Some(m) = &b.mimic {
            out[b.idx_v] +=
                world_to_reference(&world_from_frame, &data.mimic_jacobian[i], reference)
                    * m.multiplier;
        }
        for k in b.idx_v..b.idx_v + b.nv {
            out[k] += world_to_reference(&world_from_frame, &data.jacobian[k], reference);
        }
        i = b.parent;
    }
    Ok(())
}

/// Computes the Jacobian of one link or frame at `q`, touching only the joints that move it
/// (cheaper than [`compute_joint_jacobians`] + [`frame_jacobian`] for a single frame): the
/// placements of the frame's body and its ancestors are updated in `data` (and the link's, for a
/// link), the other bodies' are not. Allocates nothing.
///
/// # Errors
/// As [`forward_kinematics`](crate::forward_kinematics) and [`frame_jacobian`].
pub fn compute_frame_jacobian(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    out: &mut [Motion],
) -> Result<(), KinematicsError> {
    data.check_model(model)?;
    check_q(model, "q", q)?;
    check_out(out, model.nv())?;
    let (body, body_from_frame) = frame.body(model)?;
    placements_to(model, data, q, body);
    // The first body on the path (from the root) whose placement overflowed.
    let mut bad = None;
    let mut i = body;
    while i != 0 {
        if !data.world_from_body[i].translation.is_finite() {
            bad = Some(i);
        }
        i = model.bodies()[i].parent;
    }
    if let Some(i) = bad {
        return Err(crate::forward::overflow(model, "placement", i));
    }
    let world_from_frame = data.world_from_body[body] * body_from_frame;
    if let FrameId::Link(l) = frame {
        data.world_from_link[l] = world_from_frame;
    }
    out.fill(Motion::ZERO);
    let bodies = model.bodies();
    let mut i = body;
    while i != 0 {
        let b = &bodies[i];
        let x = &data.world_from_body[i];
        let jm = &data.joint_models[i];
        if let Some(m) = &b.mimic {
            let col = jm
                .act_axis(x)
                .unwrap_or_else(|| x.act_motion(&jm.subspace_column(0)));
            out[b.idx_v] += world_to_reference(&world_from_frame, &col, reference) * m.multiplier;
        } else if let Some(col) = jm.act_axis(x) {
            out[b.idx_v] += world_to_reference(&world_from_frame, &col, reference);
        } else {
            for k in 0..b.nv {
                let col = x.act_motion(&jm.subspace_column(k));
                out[b.idx_v + k] += world_to_reference(&world_from_frame, &col, reference);
            }
        }
        i = b.parent;
    }
    Ok(())
}

/// Computes forward kinematics with velocity `v`, the joint Jacobians and their time derivatives
/// (world frame). Afterwards [`frame_jacobian`] and [`frame_jacobian_time_variation`] read them.
///
/// # Errors
/// As [`forward_kinematics_with_velocity`].
pub fn compute_joint_jacobians_time_variation(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
    v: &[f64],
) -> Result<(), KinematicsError> {
    forward_kinematics_with_velocity(model, data, q, v)?;
    fill_joint_jacobians(model, data);
    for (i, b) in model.bodies().iter().enumerate().skip(1) {
        let ov = data.world_from_body[i].act_motion(&data.body_velocity[i]);
        data.world_velocity[i] = ov;
        if b.mimic.is_some() {
            data.mimic_jacobian_dot[i] = ov.cross_motion(&data.mimic_jacobian[i]);
        }
        for k in b.idx_v..b.idx_v + b.nv {
            data.jacobian_dot[k] = ov.cross_motion(&data.jacobian[k]);
        }
    }
    Ok(())
}

/// Writes the time derivative of a frame Jacobian (`nv` columns) in `reference`, from the last
/// [`compute_joint_jacobians_time_variation`]. Allocates nothing.
///
/// # Errors
/// As [`frame_jacobian`].
pub fn frame_jacobian_time_variation(
    model: &Model,
    data: &KinematicsData,
    frame: FrameId,
    reference: ReferenceFrame,
    out: &mut [Motion],
) -> Result<(), KinematicsError> {
    data.check_model(model)?;
    check_out(out, model.nv())?;
    let (body, body_from_frame) = frame.body(model)?;
    let world_from_frame = data.world_from_body[body] * body_from_frame;
    let p = world_from_frame.translation;
    // Twist of the frame's body in the world frame, and the velocity of the frame origin.
    let ov = data.world_velocity[body];
    let p_dot = ov.linear + ov.angular.cross(p);
    let local_v = world_from_frame.act_inv_motion(&ov);
    out.fill(Motion::ZERO);
    let bodies = model.bodies();
    let mut i = body;
    while i != 0 {
        let b = &bodies[i];
        let derivative = |j: Motion, dj: Motion| match reference {
            ReferenceFrame::World => dj,
            ReferenceFrame::LocalWorldAligned => Motion::new(
                dj.linear + dj.angular.cross(p) + j.angular.cross(p_dot),
                dj.angular,
            ),
            ReferenceFrame::Local => {
                let jl = world_from_frame.act_inv_motion(&j);
                world_from_frame.act_inv_motion(&dj) - local_v.cross_motion(&jl)
            }
        };
        if let Some(m) = &b.mimic {
            out[b.idx_v] +=
                derivative(data.mimic_jacobian[i], data.mimic_jacobian_dot[i]) * m.multiplier;
        }
        for k in b.idx_v..b.idx_v + b.nv {
            out[k] += derivative(data.jacobian[k], data.jacobian_dot[k]);
        }
        i = b.parent;
    }
    Ok(())
}

/// The 6 x nv row-major matrix of a Jacobian given as columns (rows `[linear; angular]`).
#[must_use]
pub fn jacobian_to_rows(columns: &[Motion]) -> Vec<Vec<f64>> {
    let mut rows = vec![vec![0.0; columns.len()]; 6];
    for (k, c) in columns.iter().enumerate() {
        for (r, x) in c.to_array().into_iter().enumerate() {
            rows[r][k] = x;
        }
    }
    rows
}
