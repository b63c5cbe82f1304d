//! Batch evaluation of many states through JSON: what `kinetree compute` runs, and what the
//! regression suite checks against Pinocchio.
//!
//! Request: `{"samples": [{"name": "…", "q": {...}, "v": {...}, "a": {...}, "tau": {...}}]}` with
//! each map keyed by joint name: a number for 1-DoF joints (continuous joints by angle), an array
//! for multi-DoF joints (the floating `root_joint`: q = [x, y, z, qx, qy, qz, qw], v/a/tau =
//! [linear; angular] in the base frame). A joint left out of `q` is at its neutral value, and of
//! `v`/`a`/`tau` at zero, as everywhere else in kinetree ([`BatchOptions::strict`] requires every
//! joint instead); `q` may be left out altogether. `v`, `a`, `tau` are optional: a quantity that
//! needs one is computed only when it is given. A sample may also wrap these maps in a `"state"`
//! object, so a reference file's samples can be fed straight in.
//!
//! Response: `{"model": {"name", "nq", "nv", "joints": [{"name", "type", "idx_q", "idx_v", "nq",
//! "nv"}]}, "samples": [{"name", "link_poses": {link: {"translation": [3], "rotation": 3x3
//! row-major}}, "jacobians": {link: 6 x nv, LocalWorldAligned, columns in the model's v order},
//! …}]}`. A sample's `name` (any JSON value) is copied to its result when it has one.
//!
//! With the `dynamics` feature each sample also gets what its inputs allow: always
//! `gravity_torque`, `mass_matrix` (nv x nv, row-major), `com`, `total_mass`, `potential_energy`;
//! with `v`: `nle`, `kinetic_energy`, `centroidal_momentum`; with `v` and `a`: `rnea`; with `v`
//! and `tau`: `aba`. Vectors are in the model's `v` order, and `by_joint` repeats them keyed by
//! joint name. A quantity that is undefined for a sample (`aba` with a singular mass matrix) is
//! `null`, with an `errors` entry saying why; the rest of the sample is still computed.

use crate::Error;
use crate::kinematics::configuration::{Space, from_named, neutral_configuration};
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
    /// Skip the dynamics quantities even when the inputs allow them.
    pub no_dynamics: bool,
    /// Require a value for every moving joint in each given `q`, `v`, `a`, `tau` (and a `q` in
    /// every sample); by default a joint left out is neutral (`q`) or zero.
    pub strict: bool,
    /// Add the joints' damping, friction and armature from the model to the dynamics
    /// ([`JointTerms::FromModel`](crate::dynamics::JointTerms::FromModel)). Off by default: the
    /// rigid-body quantities, as Pinocchio (and its reference data) computes them.
    pub joint_dynamics: bool,
    /// When set, every sample gets `collision`: one `{"link_a", "link_b", "distance"}` per
    /// candidate link pair, the minimum signed distance over their shapes (positive separation,
    /// negative penetration), built with these options.
    #[cfg(feature = "collision")]
    pub collision: Option<crate::collision::CollisionOptions>,
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

/// A named-state map (`{"joint": value, …}`) turned into a vector in the model's order: joints
/// left out are neutral (`q`) or zero, or an error when `strict`; unknown names are errors.
fn state_vector(
    model: &Model,
    map: &Value,
    key: &'static str,
    velocity: bool,
    strict: bool,
) -> Result<Vec<f64>, Error> {
    let map = map
        .as_object()
        .ok_or_else(|| Error::Batch(format!("'{key}' must be an object keyed by joint name")))?;
    let values = map
        .iter()
        .map(|(name, value)| Ok((name, numbers(name, value)?)))
        .collect::<Result<Vec<_>, Error>>()?;
    let space = if velocity {
        Space::Velocity
    } else {
        Space::Configuration
    };
    Ok(from_named(model, space, values, strict)?)
}

/// The inputs of one request sample in the model's order (`v`, `a`, `tau` only when given).
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

/// Parses one sample of a request; a joint left out is neutral (`q`) or zero (`v`, `a`, `tau`).
///
/// # Errors
/// [`Error::Batch`] for a malformed sample; [`Error::Kinematics`] for unknown joints and wrong
/// value counts.
pub fn parse_sample(model: &Model, sample: &Value) -> Result<SampleInput, Error> {
    parse_sample_with(model, sample, false)
}

/// [`parse_sample`], or with `strict` every moving joint required in `q` (which must be given)
/// and in each of `v`, `a`, `tau` that is given.
///
/// # Errors
/// As [`parse_sample`]; with `strict`, [`Error::Batch`] for a missing `q` and
/// [`Error::Kinematics`] naming a missing joint.
pub fn parse_sample_with(
    model: &Model,
    sample: &Value,
    strict: bool,
) -> Result<SampleInput, Error> {
    let state = if sample.get("state").is_some_and(Value::is_object) {
        &sample["state"]
    } else {
        sample
    };
    let q = match state.get("q").filter(|q| !q.is_null()) {
        Some(q) => state_vector(model, q, "q", false, strict)?,
        None if strict => return Err(Error::Batch("a sample has no 'q'".into())),
        None => neutral_configuration(model),
    };
    let opt = |key: &'static str| -> Result<Option<Vec<f64>>, Error> {
        state
            .get(key)
            .filter(|v| !v.is_null())
            .map(|m| state_vector(model, m, key, true, strict))
            .transpose()
    };
    Ok(SampleInput {
        q,
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
    #[allow(unused_mut, reason = "only the collision feature adds skipped meshes")]
    let mut skipped_meshes: Vec<Value> = Vec::new();
    #[cfg(feature = "collision")]
    let mut collision = match &options.collision {
        Some(o) => {
            let cmodel = crate::collision::CollisionModel::from_model(model, o)?;
            let cdata = crate::collision::CollisionData::new(&cmodel);
            for skipped in cmodel.skipped_meshes() {
                skipped_meshes.push(json!(format!("{skipped:?}")));
            }
            Some((cmodel, cdata))
        }
        None => None,
    };
    #[cfg(feature = "dynamics")]
    let mut dynamics_data = crate::dynamics::DynamicsData::with_joint_terms(
        model,
        if options.joint_dynamics {
            crate::dynamics::JointTerms::FromModel
        } else {
            crate::dynamics::JointTerms::Ignored
        },
    );
    let mut out = Vec::with_capacity(samples.len());
    for (i, sample) in samples.iter().enumerate() {
        let input = parse_sample_with(model, sample, options.strict)
            .map_err(|e| Error::Batch(format!("sample {i}: {e}")))?;
        compute_joint_jacobians(model, &mut data, &input.q)?;
        let mut poses = Map::new();
        for (l, link) in model.links().iter().enumerate() {
            let p = data.world_from(FrameId::Link(l))?;
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
        if let Some(name) = sample.get("name") {
            s.insert("name".into(), name.clone());
        }
        s.insert("link_poses".into(), Value::Object(poses));
        if !jacobians.is_empty() {
            s.insert("jacobians".into(), Value::Object(jacobians));
        }
        #[cfg(feature = "collision")]
        if let Some((cmodel, cdata)) = &mut collision {
            let pairs = crate::collision::compute_link_pair_distances(
                model, cmodel, &mut data, cdata, &input.q,
            )?;
            let list: Vec<Value> = pairs
                .into_iter()
                .map(|(a, b, d)| json!({"link_a": a, "link_b": b, "distance": d}))
                .collect();
            s.insert("collision".into(), Value::Array(list));
        }
        #[cfg(feature = "dynamics")]
        if !options.no_dynamics {
            dynamics::add(model, &mut dynamics_data, &input, &mut s)?;
        }
        out.push(Value::Object(s));
    }
    let mut summary = model_summary(model);
    if !skipped_meshes.is_empty() {
        summary["skipped_meshes"] = Value::Array(skipped_meshes);
    }
    Ok(json!({"model": summary, "samples": out}))
}

/// A vector in the model's `v` order keyed by joint name (numbers for 1-DoF joints, arrays for
/// multi-DoF joints).
#[must_use]
pub fn by_joint(model: &Model, x: &[f64]) -> Value {
    let mut m = Map::new();
    for j in model.moving_joints() {
        let r = model.joint_v_range(j);
        let value = if r.len() == 1 {
            json!(x[r.start])
        } else {
            json!(x[r])
        };
        m.insert(model.joint(j).name.clone(), value);
    }
    Value::Object(m)
}

#[cfg(feature = "dynamics")]
mod dynamics {
    //! The dynamics quantities of a sample: what the inputs allow (q: gravity, mass matrix, COM;
    //! with v: nle, energy, momentum; with a: rnea; with tau: aba).

    use super::{SampleInput, by_joint};
    use crate::Error;
    use crate::dynamics::{DynamicsData, compute_all_terms};
    use crate::model::Model;
    use serde_json::{Map, Value, json};

    pub(super) fn add(
        model: &Model,
        data: &mut DynamicsData,
        input: &SampleInput,
        s: &mut Map<String, Value>,
    ) -> Result<(), Error> {
        let zeros = vec![0.0; model.nv()];
        let v = input.v.as_deref().unwrap_or(&zeros);
        let a = input.a.as_deref().unwrap_or(&zeros);
        let tau = input.tau.as_deref().unwrap_or(&zeros);
        let t = compute_all_terms(model, data, &input.q, v, a, tau)?;
        let nv = model.nv();
        let mut by = Map::new();
        let mut errors = Vec::new();
        s.insert("gravity_torque".into(), json!(t.gravity_torque));
        by.insert("gravity_torque".into(), by_joint(model, &t.gravity_torque));
        let rows: Vec<&[f64]> = t.mass_matrix.chunks(nv.max(1)).take(nv).collect();
        s.insert("mass_matrix".into(), json!(rows));
        match &t.com {
            Ok(c) => {
                s.insert("com".into(), json!(c.to_array()));
            }
            Err(e) => {
                s.insert("com".into(), Value::Null);
                errors.push(json!({"quantity": "com", "error": e.to_string()}));
            }
        }
        s.insert("total_mass".into(), json!(t.moving_mass));
        s.insert("potential_energy".into(), json!(t.potential_energy));
        if input.v.is_some() {
            s.insert("nle".into(), json!(t.nle));
            by.insert("nle".into(), by_joint(model, &t.nle));
            s.insert("kinetic_energy".into(), json!(t.kinetic_energy));
            match &t.centroidal_momentum {
                Ok(h) => {
                    s.insert("centroidal_momentum".into(), json!(h.to_array()));
                }
                Err(e) => {
                    s.insert("centroidal_momentum".into(), Value::Null);
                    errors.push(json!({"quantity": "centroidal_momentum", "error": e.to_string()}));
                }
            }
        }
        if input.v.is_some() && input.a.is_some() {
            s.insert("rnea".into(), json!(t.rnea));
            by.insert("rnea".into(), by_joint(model, &t.rnea));
        }
        if input.v.is_some() && input.tau.is_some() {
            match &t.aba {
                Ok(ddq) => {
                    s.insert("aba".into(), json!(ddq));
                    by.insert("aba".into(), by_joint(model, ddq));
                }
                Err(e) => {
                    s.insert("aba".into(), Value::Null);
                    errors.push(json!({"quantity": "aba", "error": e.to_string()}));
                }
            }
        }
        s.insert("by_joint".into(), Value::Object(by));
        if !errors.is_empty() {
            s.insert("errors".into(), Value::Array(errors));
        }
        Ok(())
    }
}
