//! The derivative part of `cargo xtask regress`: Pinocchio's `computeRNEADerivatives`,
//! `computeGeneralizedGravityDerivatives` and `computeABADerivatives`
//! (`tests/data/reference/derivatives/<robot>.json`) against kinetree's analytic derivatives,
//! every matrix of every sample, mapped by joint name.
//!
//! Tolerances as the issue sets them: `1e-8` relative to `max(1, largest reference entry)` for
//! the inverse-dynamics and gravity matrices, scaled by `max(1, cond(M)/1e3)` for the
//! forward-dynamics ones.

use crate::regress::{Row, Tolerance};
use anyhow::{Context, Result};
use kinetree::dynamics::{
    DerivativesData, JointTerms, aba_derivatives, generalized_gravity_derivatives, rnea_derivatives,
};
use kinetree::kinematics::configuration::{neutral_configuration, set_joint_q, set_joint_v};
use kinetree::model::{Model, RootJoint};
use serde_json::Value;
use std::path::Path;

fn values(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect(),
        x => vec![x.as_f64().unwrap_or(f64::NAN)],
    }
}

/// A sample's `q`, `v`, `a`, `tau` in our order.
type State = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

/// Our `q` and velocity-space vectors from a sample's `state` (keyed by joint name).
fn state(model: &Model, sample: &Value) -> Result<State> {
    let mut q = neutral_configuration(model);
    for (name, value) in sample["state"]["q"].as_object().into_iter().flatten() {
        set_joint_q(model, &mut q, name, &values(value))?;
    }
    let mut vectors = Vec::new();
    for key in ["v", "a", "tau"] {
        let mut x = vec![0.0; model.nv()];
        for (name, value) in sample["state"][key].as_object().into_iter().flatten() {
            set_joint_v(model, &mut x, name, &values(value))?;
        }
        vectors.push(x);
    }
    let tau = vectors.pop().unwrap_or_default();
    let a = vectors.pop().unwrap_or_default();
    let v = vectors.pop().unwrap_or_default();
    Ok((q, v, a, tau))
}

/// (ours, reference) pairs of an `nv x nv` matrix, the reference in Pinocchio's order.
fn pairs(ours: &[f64], reference: &Value, map: &[usize]) -> Vec<(f64, f64)> {
    let n = map.len();
    let mut out = Vec::with_capacity(n * n);
    for (i, &oi) in map.iter().enumerate() {
        for (j, &oj) in map.iter().enumerate() {
            out.push((
                ours[oi * n + oj],
                reference[i][j].as_f64().unwrap_or(f64::NAN),
            ));
        }
    }
    out
}

/// Compares one robot's derivatives; `main` is its main reference file (for `cond(M)`).
pub(crate) fn check_robot(root: &Path, robot: &str, main: &Value) -> Result<Vec<Row>> {
    let file = root.join(format!("tests/data/reference/derivatives/{robot}.json"));
    let text = std::fs::read_to_string(&file)
        .with_context(|| format!("cannot read {}", file.display()))?;
    let reference: Value =
        serde_json::from_str(&text).with_context(|| format!("cannot parse {}", file.display()))?;
    let root_joint = match reference["root_joint"].as_str() {
        Some("fixed") => RootJoint::Fixed,
        _ => RootJoint::Floating,
    };
    let urdf = root
        .join("tests/data/reference/derivatives")
        .join(reference["urdf"].as_str().unwrap_or_default());
    let model = Model::from_urdf_file(&urdf, root_joint)?;
    // Our v index of each of Pinocchio's.
    let mut map = vec![usize::MAX; model.nv()];
    for j in reference["joints"].as_array().into_iter().flatten() {
        let name = j["name"].as_str().unwrap_or_default();
        let index = model
            .joint_index(name)
            .with_context(|| format!("{robot}: no joint {name}"))?;
        let theirs = j["idx_v"].as_u64().unwrap_or_default() as usize;
        for (k, o) in model.joint_v_range(index).enumerate() {
            if let Some(m) = map.get_mut(theirs + k) {
                *m = o;
            }
        }
    }
    anyhow::ensure!(
        map.iter().all(|&m| m < model.nv()),
        "{robot}: joint table does not cover v"
    );
    let rel = Tolerance::RelativeFloor(1e-8);
    let mut rows: Vec<Row> = [
        "dtau_dq",
        "dtau_dv",
        "dtau_da",
        "dg_dq",
        "dddq_dq",
        "dddq_dv",
        "dddq_dtau",
    ]
    .into_iter()
    .enumerate()
    .map(|(k, q)| {
        let tolerance = if k < 4 {
            rel
        } else {
            Tolerance::RelativeFloorCond(1e-8)
        };
        Row::new(robot, q, tolerance)
    })
    .collect();
    let mut data = DerivativesData::with_joint_terms(&model, JointTerms::Ignored);
    for (k, sample) in reference["samples"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        let (q, v, a, tau) = state(&model, sample)?;
        let d = rnea_derivatives(&model, &mut data, &q, &v, &a)?;
        for (row, (ours, key)) in rows.iter_mut().zip([
            (d.dtau_dq, "dtau_dq"),
            (d.dtau_dv, "dtau_dv"),
            (d.dtau_da, "dtau_da"),
        ]) {
            row.record(&pairs(ours, &sample["rnea"][key], &map));
        }
        let dg = generalized_gravity_derivatives(&model, &mut data, &q)?;
        rows[3].record(&pairs(dg, &sample["gravity"]["dg_dq"], &map));
        if sample["aba"].is_null() {
            continue;
        }
        let cond = main["samples"][k]["mass_matrix_cond"]
            .as_f64()
            .unwrap_or(f64::INFINITY);
        let d = aba_derivatives(&model, &mut data, &q, &v, &tau)?;
        for (row, (ours, key)) in rows[4..].iter_mut().zip([
            (d.dddq_dq, "dddq_dq"),
            (d.dddq_dv, "dddq_dv"),
            (d.dddq_dtau, "dddq_dtau"),
        ]) {
            row.record_with(&pairs(ours, &sample["aba"][key], &map), cond);
        }
    }
    Ok(rows)
}
