//! Batch evaluation of many states through JSON: what `kinetree compute` runs, and what the
//! regression suite checks against Pinocchio.
//!
//! Request: `{"samples": [{"q": {...}, "v": {...}, "a": {...}, "tau": {...}}]}` with each map keyed
//! by joint name: a number for 1-DoF joints (continuous joints by angle), an array for multi-DoF
//! joints (the floating `root_joint`: q = [x, y, z, qx, qy, qz, qw], v/a/tau = [linear; angular]
//! in the base frame). `v`, `a`, `tau` are optional. A sample may also wrap these maps in a
//! `"state"` object, so a reference file's samples can be fed straight in.
//!
//! Response: `{"model": {"name", "nq", "nv", "joints": [{"name", "type", "idx_q", "idx_v", "nq",
//! "nv"}]}, "samples": [{"link_poses": {link: {"translation": [3], "rotation": 3x3 row-major}},
//! "jacobians": {link: 6 x nv, LocalWorldAligned, columns in the model's v order}, …}]}`.

use crate::Error;
use crate::kinematics::configuration::{neutral_configuration, set_joint_q, set_joint_v};
use crate::kinematics::spatial::Motion;
use crate::kinematics::{
    FrameId, KinematicsData, KinematicsError, ReferenceFrame, compute_joint_jacobians,
    frame_jacobian, jacobian_to_rows,
};
use crate::model::Model;
use serde_json::{Map, Value, json};

/// What to compute besides link poses.
#[derive(Clone, Debug, Default)]
pub struct BatchOptions {
    /// Links or frames whose LocalWorldAligned Jacobian is reported.
    pub jacobians: Vec<String>,
}

/// The `model` block of a response: name, sizes and every moving joint's blocks.
#[must_use]
pub fn model_summary(model: &Model) -> Value {
    let joints: Vec<Value> = model
        .moving_joints()
        .map(|j| {
            let joint = model.joint(j);
            let (rq, rv) = (model.joint_q_range(j), model.joint_v_range(j));
            json!({
                "name": joint.name, "type": joint.kind.as_str(),
                "idx_q": rq.start, "idx_v": rv.start, "nq": rq.len(), "nv": rv.len(),
            })
        })
        .collect();
    json!({"name": model.name(), "nq": model.nq(), "nv": model.nv(), "joints": joints})
}

fn numbers(joint: &str, value: &Value) -> Result<Vec<f64>, Error> {
    let bad = || {
        Error::Kinematics(KinematicsError::InvalidJointValue {
            joint: joint.to_string(),
            reason: format!("expected a number or an array of numbers, got {value}"),
        })
    };
    match value {
        Value::Number(n) => Ok(vec![n.as_f64().ok_or_else(bad)?]),
        Value::Array(a) => a.iter().map(|x| x.as_f64().ok_or_else(bad)).collect(),
        _ => Err(bad()),
    }
}

/// A named-state map (`{"joint": value, …}`) turned into a vector in the model's order.
/// Every moving joint must be present; unknown names are errors.
fn state_vector(
    model: &Model,
    map: &Value,
    key: &'static str,
    velocity: bool,
) -> Result<Vec<f64>, Error> {
    let map = map
        .as_object()
        .ok_or_else(|| Error::Batch(format!("'{key}' must be an object keyed by joint name")))?;
    let mut out = if velocity {
        vec![0.0; model.nv()]
    } else {
        neutral_configuration(model)
    };
    for (name, value) in map {
        let x = numbers(name, value)?;
        if velocity {
            set_joint_v(model, &mut out, name, &x)?;
        } else {
            set_joint_q(model, &mut out, name, &x)?;
        }
    }
    if let Some(missing) = model
        .moving_joints()
        .map(|j| &model.joint(j).name)
        .find(|n| !map.contains_key(*n))
    {
        return Err(Error::Batch(format!(
            "'{key}' has no value for joint '{missing}'"
        )));
    }
    Ok(out)
}

/// The named inputs of one request sample (`q` required; `v`, `a`, `tau` optional).
#[derive(Clone, Debug)]
pub struct SampleInput {
    /// Configuration (length nq).
    pub q: Vec<f64>,
    /// Velocity (length nv), if given.
    pub v: Option<Vec<f64>>,
    /// Acceleration (length nv), if given.
    pub a: Option<Vec<f64>>,
    /// Joint effort (length nv), if given.
    pub tau: Option<Vec<f64>>,
}

/// Parses one sample of a request.
///
/// # Errors
/// [`Error::Batch`] for a malformed sample or a missing joint; [`Error::Kinematics`] for unknown
/// joints and wrong value counts.
pub fn parse_sample(model: &Model, sample: &Value) -> Result<SampleInput, Error> {
    let state = if sample.get("state").is_some_and(Value::is_object) {
        &sample["state"]
    } else {
        sample
    };
    let q = state
        .get("q")
        .ok_or_else(|| Error::Batch("a sample has no 'q'".into()))?;
    let opt = |key: &'static str| -> Result<Option<Vec<f64>>, Error> {
        state
            .get(key)
            .filter(|v| !v.is_null())
            .map(|m| state_vector(model, m, key, true))
            .transpose()
    };
    Ok(SampleInput {
        q: state_vector(model, q, "q", false)?,
        v: opt("v")?,
        a: opt("a")?,
        tau: opt("tau")?,
    })
}

/// Evaluates every sample of `request` and returns the response document.
///
/// # Errors
/// [`Error::Batch`] for a malformed request (the message names the sample), errors of the layers
/// for unknown joints or frames.
pub fn evaluate(model: &Model, request: &Value, options: &BatchOptions) -> Result<Value, Error> {
    let samples = request
        .get("samples")
        .and_then(Value::as_array)
        .ok_or_else(|| Error::Batch("the request has no 'samples' array".into()))?;
    let frames: Vec<FrameId> = options
        .jacobians
        .iter()
        .map(|n| FrameId::find(model, n))
        .collect::<Result<_, _>>()?;
    let mut data = KinematicsData::new(model);
    let mut jac = vec![Motion::ZERO; model.nv()];
    let mut out = Vec::with_capacity(samples.len());
    for (i, sample) in samples.iter().enumerate() {
        let input =
            parse_sample(model, sample).map_err(|e| Error::Batch(format!("sample {i}: {e}")))?;
        compute_joint_jacobians(model, &mut data, &input.q)?;
        let mut poses = Map::new();
        for (l, link) in model.links().iter().enumerate() {
            let p = data.world_placement(FrameId::Link(l));
            poses.insert(
                link.name.clone(),
                json!({"translation": p.translation.to_array(), "rotation": p.rotation_rows()}),
            );
        }
        let mut jacobians = Map::new();
        for (name, frame) in options.jacobians.iter().zip(&frames) {
            frame_jacobian(
                model,
                &data,
                *frame,
                ReferenceFrame::LocalWorldAligned,
                &mut jac,
            )?;
            jacobians.insert(name.clone(), json!(jacobian_to_rows(&jac)));
        }
        let mut s = Map::new();
        s.insert("link_poses".into(), Value::Object(poses));
        if !jacobians.is_empty() {
            s.insert("jacobians".into(), Value::Object(jacobians));
        }
        out.push(Value::Object(s));
    }
    Ok(json!({"model": model_summary(model), "samples": out}))
}
