//! The JSON API of `kinetree view`: pure functions from a request body to a response, so they
//! are tested without a socket. Every error is an [`ApiError`] with the HTTP status and a
//! message naming what is wrong; nothing here panics on any body.

use kinetree::collision::{CollisionData, CollisionModel, compute_distances};
use kinetree::dynamics::{DynamicsData, DynamicsError, compute_all_terms};
use kinetree::kinematics::configuration::{
    check_configuration, neutral_configuration, set_joint_q,
};
use kinetree::kinematics::ik::{IkParams, IkSolver, IkStatus, IkTarget};
use kinetree::kinematics::{
    FrameId, KinematicsData, compute_joint_jacobians, forward_kinematics, update_frame_placements,
};
use kinetree::model::{Geometry, JointKind, Model};
use kinetree::spatial::{DQuat, DVec3, Se3};
use serde_json::{Map, Value, json};

/// An error answer: the HTTP status code and a message for the body.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ApiError {
    /// 400, 404, 405 or 413.
    pub(crate) status: u16,
    /// What is wrong, for a human.
    pub(crate) message: String,
}

impl ApiError {
    /// A 400 Bad Request with `message`.
    pub(crate) fn bad(message: impl Into<String>) -> Self {
        Self {
            status: 400,
            message: message.into(),
        }
    }
}

/// A pose as `[x, y, z, qx, qy, qz, qw]` (metres; unit quaternion, scalar last).
pub(crate) fn pose(x: &Se3) -> [f64; 7] {
    let q = x.to_quat();
    let t = x.translation;
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
}

/// Parses a request body as a JSON object.
///
/// # Errors
/// 400 naming the JSON error, or when the body is not an object.
pub(crate) fn parse_body(body: &[u8]) -> Result<Map<String, Value>, ApiError> {
    match serde_json::from_slice::<Value>(body) {
        Ok(Value::Object(m)) => Ok(m),
        Ok(_) => Err(ApiError::bad("the request body must be a JSON object")),
        Err(e) => Err(ApiError::bad(format!(
            "the request body is not valid JSON: {e}"
        ))),
    }
}

/// A number, or a 400 naming `what`.
fn number(v: &Value, what: &str) -> Result<f64, ApiError> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| ApiError::bad(format!("{what} must be a finite number, got {v}")))
}

/// An array of `n` numbers (any length when `n` is `None`).
fn numbers(v: &Value, n: Option<usize>, what: &str) -> Result<Vec<f64>, ApiError> {
    let a = v
        .as_array()
        .ok_or_else(|| ApiError::bad(format!("{what} must be an array of numbers")))?;
    if let Some(n) = n
        && a.len() != n
    {
        return Err(ApiError::bad(format!(
            "{what} must have {n} numbers, got {}",
            a.len()
        )));
    }
    a.iter()
        .enumerate()
        .map(|(i, x)| number(x, &format!("{what}[{i}]")))
        .collect()
}

/// The configuration of a request: `"q"` as an array of `model.nq()` numbers, or an object of
/// joint name → value (an array for multi-coordinate joints), the others neutral. A missing
/// `"q"` is the neutral configuration.
///
/// # Errors
/// 400 for a wrong length, an unknown joint, a non-number or a value the model refuses.
pub(crate) fn parse_q(model: &Model, body: &Map<String, Value>) -> Result<Vec<f64>, ApiError> {
    let mut q = neutral_configuration(model);
    match body.get("q") {
        None => {}
        Some(v @ Value::Array(_)) => q = numbers(v, Some(model.nq()), "q")?,
        Some(Value::Object(by_name)) => {
            for (name, value) in by_name {
                if model.find_user_joint(name).is_none() {
                    return Err(ApiError::bad(format!("unknown joint '{name}' in q")));
                }
                let values = match value {
                    Value::Array(_) => numbers(value, None, &format!("q.{name}"))?,
                    v => vec![number(v, &format!("q.{name}"))?],
                };
                set_joint_q(model, &mut q, name, &values)
                    .map_err(|e| ApiError::bad(format!("q.{name}: {e}")))?;
            }
        }
        Some(v) => {
            return Err(ApiError::bad(format!(
                "q must be an array of {} numbers or an object of joint names, got {v}",
                model.nq()
            )));
        }
    }
    Ok(q)
}

/// The configuration of a request ([`parse_q`]), refused as `kinetree compute` refuses it: the
/// library's check of a configuration (length, finite numbers, unit quaternions), then what
/// `compute` evaluates for a state given only by `q` (the Jacobians, and the dynamics terms at
/// zero velocity, acceleration and torque) must not overflow. A state so far out that they do
/// (a finger at 1e308 m) is refused with the library's message rather than drawn.
///
/// # Errors
/// 400 as [`parse_q`], or naming the check that fails.
fn checked_q(model: &Model, body: &Map<String, Value>) -> Result<Vec<f64>, ApiError> {
    let q = parse_q(model, body)?;
    let refused = |e: &dyn std::fmt::Display| ApiError::bad(format!("q: {e}"));
    check_configuration(model, &q).map_err(|e| refused(&e))?;
    compute_joint_jacobians(model, &mut KinematicsData::new(model), &q).map_err(|e| refused(&e))?;
    let zeros = vec![0.0; model.nv()];
    let mut data = DynamicsData::new(model);
    match compute_all_terms(model, &mut data, &q, &zeros, &zeros, &zeros) {
        // A model the dynamics do not support yet is still drawn.
        Ok(_) | Err(DynamicsError::CoupledMimic { .. }) => Ok(q),
        Err(e) => Err(refused(&e)),
    }
}

/// The geometry of a visual or collision element, with `url` for a mesh (`None` when the file
/// was not found: the page then skips it).
fn geometry_json(g: &Geometry, mesh_url: &dyn Fn(&str) -> Option<String>) -> Value {
    match g {
        Geometry::Box { size } => json!({"type": "box", "size": size}),
        Geometry::Cylinder { radius, length } => {
            json!({"type": "cylinder", "radius": radius, "length": length})
        }
        Geometry::Sphere { radius } => json!({"type": "sphere", "radius": radius}),
        Geometry::Capsule { radius, length } => {
            json!({"type": "capsule", "radius": radius, "length": length})
        }
        Geometry::Mesh { filename, scale } => json!({
            "type": "mesh", "filename": filename, "scale": scale, "url": mesh_url(filename),
        }),
    }
}

/// `GET /api/model`: what the page needs to build the scene and the sliders.
pub(crate) fn model_json(model: &Model, mesh_url: &dyn Fn(&str) -> Option<String>) -> Value {
    let links: Vec<Value> = model
        .links()
        .iter()
        .enumerate()
        .map(|(i, l)| {
            json!({
                "name": l.name,
                // A composite joint's massless virtual link (`hip#1`): internal, nothing to show.
                "virtual": model.is_virtual_link(i),
                "parent": model.parent_link(i).map(|p| model.link(p).name.clone()),
                "mass": l.inertial.as_ref().map_or(0.0, |m| m.mass),
                "visuals": l.visuals.iter().map(|v| json!({
                    "origin": pose(&v.origin),
                    "geometry": geometry_json(&v.geometry, mesh_url),
                    "color": v.color.or(l.metadata.color),
                })).collect::<Vec<_>>(),
                "collisions": l.collisions.iter().map(|c| json!({
                    "origin": pose(&c.origin),
                    "geometry": geometry_json(&c.geometry, mesh_url),
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    let neutral = neutral_configuration(model);
    let joints: Vec<Value> = model
        .moving_joints()
        .map(|j| {
            let joint = model.joint(j);
            let kind = match joint.kind {
                JointKind::Fixed => "fixed",
                JointKind::Revolute => "revolute",
                JointKind::Continuous => "continuous",
                JointKind::Prismatic => "prismatic",
                JointKind::Cylindrical => "cylindrical",
                JointKind::Spherical => "spherical",
                JointKind::Planar => "planar",
                JointKind::Floating => "floating",
            };
            let r = model.joint_q_range(j);
            json!({
                "name": joint.name, "kind": kind, "q_index": r.start, "nq": r.len(),
                "lower": joint.limits.lower, "upper": joint.limits.upper,
                "mimic": joint.mimic.is_some(),
                "neutral": &neutral[r],
                // The composite joint this slider is a state variable of, if any.
                "composite": model
                    .composite_of_joint(j)
                    .map(|c| model.composites()[c].spec.name.clone()),
            })
        })
        .collect();
    json!({
        "name": model.name(),
        "nq": model.nq(),
        "links": links,
        "joints": joints,
        "frames": model.frames().iter().map(|f| f.name.clone()).collect::<Vec<_>>(),
    })
}

/// Forward kinematics of `q` as JSON: `links` and `frames` poses (in model order) and the
/// centre of mass.
///
/// # Errors
/// 400 with the library's message when `q` is refused.
pub(crate) fn poses_json(
    model: &Model,
    data: &mut KinematicsData,
    q: &[f64],
) -> Result<Value, ApiError> {
    forward_kinematics(model, data, q).map_err(|e| ApiError::bad(format!("q: {e}")))?;
    update_frame_placements(model, data).map_err(|e| ApiError::bad(e.to_string()))?;
    let mut mass = 0.0;
    let mut moment = DVec3::ZERO;
    for (l, x) in model.links().iter().zip(data.world_from_link()) {
        if let Some(i) = &l.inertial {
            mass += i.mass;
            moment += i.mass * x.transform_point(i.origin.translation);
        }
    }
    let com = if mass > 0.0 {
        moment / mass
    } else {
        DVec3::ZERO
    };
    Ok(json!({
        "q": q,
        "links": data.world_from_link().iter().map(pose).collect::<Vec<_>>(),
        "frames": data.world_from_frame().iter().map(pose).collect::<Vec<_>>(),
        "com": [com.x, com.y, com.z],
    }))
}

/// `POST /api/fk` with `{"q": …}`: [`poses_json`].
///
/// # Errors
/// 400 for a bad body or a configuration [`checked_q`] refuses.
pub(crate) fn fk(model: &Model, body: &[u8]) -> Result<Value, ApiError> {
    let body = parse_body(body)?;
    let q = checked_q(model, &body)?;
    poses_json(model, &mut KinematicsData::new(model), &q)
}

/// `POST /api/ik` with `{"q": start, "frame": name, "target": {"xyz": [3], "quat": [x,y,z,w]}}`
/// (`quat` optional: without it only the position is reached): the solver's answer from the
/// start configuration, and the poses at the answer.
///
/// # Errors
/// 400 for a bad body, an unknown frame or a zero quaternion.
pub(crate) fn ik(model: &Model, body: &[u8]) -> Result<Value, ApiError> {
    let body = parse_body(body)?;
    let q0 = checked_q(model, &body)?;
    let frame_name = body
        .get("frame")
        .and_then(Value::as_str)
        .ok_or_else(|| ApiError::bad("ik needs \"frame\": the name of a link or frame"))?;
    let frame = FrameId::find(model, frame_name).map_err(|e| ApiError::bad(e.to_string()))?;
    let target = body
        .get("target")
        .and_then(Value::as_object)
        .ok_or_else(|| ApiError::bad("ik needs \"target\": {\"xyz\": [x, y, z], \"quat\": …}"))?;
    let xyz = numbers(
        target.get("xyz").unwrap_or(&Value::Null),
        Some(3),
        "target.xyz",
    )?;
    let position = DVec3::new(xyz[0], xyz[1], xyz[2]);
    let target = match target.get("quat") {
        None | Some(Value::Null) => IkTarget::position(frame, position),
        Some(v) => {
            let q = numbers(v, Some(4), "target.quat")?;
            let quat = DQuat::from_xyzw(q[0], q[1], q[2], q[3]);
            let norm = quat.length();
            if norm <= 1e-9 || !norm.is_finite() {
                return Err(ApiError::bad("target.quat must not be zero"));
            }
            IkTarget::new(frame, Se3::from_translation_quat(position, quat / norm))
        }
    };
    let mut data = KinematicsData::new(model);
    let mut solver = IkSolver::new(model, IkParams::default());
    let report = solver
        .solve(model, &mut data, &target, &q0)
        .map_err(|e| ApiError::bad(format!("ik: {e}")))?;
    let status = match report.status {
        IkStatus::Converged => "converged",
        IkStatus::BestEffort { .. } => "best_effort",
        IkStatus::Failed => "failed",
    };
    let (position_error, orientation_error) = (report.position_error, report.orientation_error);
    let iterations = report.iterations;
    let q = report.q.to_vec();
    let mut out = poses_json(model, &mut data, &q)?;
    out["status"] = json!(status);
    out["position_error"] = json!(position_error);
    out["orientation_error"] = json!(orientation_error);
    out["iterations"] = json!(iterations);
    Ok(out)
}

/// `POST /api/collide` with `{"q": …}`: every candidate pair's signed distance (link names,
/// metres) and the colliding ones (distance < 0), or `"available": false` with the reason when
/// the model has no collision model.
///
/// # Errors
/// 400 for a bad body or configuration.
pub(crate) fn collide(
    model: &Model,
    cmodel: Result<&CollisionModel, &str>,
    body: &[u8],
) -> Result<Value, ApiError> {
    let body = parse_body(body)?;
    let q = checked_q(model, &body)?;
    let cmodel = match cmodel {
        Ok(c) => c,
        Err(reason) => return Ok(json!({"available": false, "reason": reason, "pairs": []})),
    };
    let mut kd = KinematicsData::new(model);
    let mut cd = CollisionData::new(cmodel);
    cd.compute_placements(model, cmodel, &mut kd, &q)
        .map_err(|e| ApiError::bad(format!("q: {e}")))?;
    let shape_link = |s: usize| model.link(cmodel.shapes()[s].link()).name.clone();
    let pairs: Vec<Value> = compute_distances(cmodel, &mut cd)
        .map_err(|e| ApiError::bad(e.to_string()))?
        .iter()
        .map(|p| {
            json!({"link_a": shape_link(p.a), "link_b": shape_link(p.b),
                   "distance": p.distance, "colliding": p.distance < 0.0})
        })
        .collect();
    Ok(json!({"available": true, "pairs": pairs}))
}
