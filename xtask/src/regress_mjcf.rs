//! The MJCF part of `cargo xtask regress`: every model of `tests/data/reference/mjcf` through the
//! batch evaluator (the code behind `kinetree compute`), against MuJoCo 4.0's values.
//!
//! MuJoCo's states are converted with the model's own `*_from_mujoco` functions and the results
//! mapped back: generalized forces with `tau_to_mujoco`, the mass matrix as `Gᵀ M G` with
//! `v = G · qvel` (see `kinetree_model::mjcf`). Each reference sample runs twice: with its
//! `qacc` (inverse dynamics, `tau`) and with `qacc = 0` (bias forces, `qfrc_bias`).

use crate::regress::{Row, Tolerance};
use anyhow::{Context, Result, bail};
use kinetree::batch::{
    BatchOptions, FrameSelection, JointValue, NamedValues, SampleInput, evaluate,
};
use kinetree::model::Model;
use serde_json::Value;
use std::path::Path;

fn numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(numbers).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap_or(f64::NAN)],
        _ => vec![f64::NAN],
    }
}

/// `x` (in the model's q or v layout) keyed by joint name.
fn named(model: &Model, x: &[f64], configuration: bool) -> NamedValues {
    model
        .moving_joints()
        .map(|j| {
            let r = if configuration {
                model.joint_q_range(j)
            } else {
                model.joint_v_range(j)
            };
            let value = if r.len() == 1 {
                JointValue::Scalar(x[r.start])
            } else {
                JointValue::Block(x[r].to_vec())
            };
            (model.joint(j).name.clone(), value)
        })
        .collect()
}

/// `G` with `v = G · qvel` at `qpos` (row-major), column by column through the model's own
/// conversion.
fn velocity_map(model: &Model, qpos: &[f64]) -> Result<Vec<f64>> {
    let nv = model.nv();
    let mut g = vec![0.0; nv * nv];
    for j in 0..nv {
        let mut e = vec![0.0; nv];
        e[j] = 1.0;
        let col = model.v_from_mujoco(qpos, &e)?;
        for i in 0..nv {
            g[i * nv + j] = col[i];
        }
    }
    Ok(g)
}

/// Compares one MJCF model; returns its rows.
fn check_model(root: &Path, file: &Path) -> Result<Vec<Row>> {
    let text =
        std::fs::read_to_string(file).with_context(|| format!("cannot read {}", file.display()))?;
    let reference: Value = serde_json::from_str(&text)?;
    let name = format!("mjcf/{}", reference["name"].as_str().unwrap_or("?"));
    let xml = root
        .join("tests/data/reference/mjcf")
        .join(reference["xml"].as_str().unwrap_or_default());
    let model = Model::from_mjcf_file(&xml).with_context(|| format!("{name}: cannot load"))?;
    let nv = model.nv();
    let samples = reference["samples"].as_array().cloned().unwrap_or_default();
    let mut inputs = Vec::new();
    for s in &samples {
        let (qpos, qvel, qacc) = (
            numbers(&s["qpos"]),
            numbers(&s["qvel"]),
            numbers(&s["qacc"]),
        );
        let q = model.q_from_mujoco(&qpos)?;
        let v = model.v_from_mujoco(&qpos, &qvel)?;
        for acc in [qacc, vec![0.0; nv]] {
            let a = model.a_from_mujoco(&qpos, &qvel, &acc)?;
            inputs.push(SampleInput {
                q: Some(named(&model, &q, true)),
                v: Some(named(&model, &v, false)),
                a: Some(named(&model, &a, false)),
                tau: None,
            });
        }
    }
    let options = BatchOptions {
        jacobians: Vec::new(),
        frames: FrameSelection::None,
        no_dynamics: false,
        derivatives: false,
        joint_dynamics: false,
        strict: true,
        collision: None,
    };
    let output =
        evaluate(&model, &inputs, &options).with_context(|| format!("{name}: evaluation"))?;
    let mut poses = Row::new(&name, "link_poses", Tolerance::Absolute(1e-9));
    let mut mass = Row::new(&name, "mass_matrix", Tolerance::RelativeFloor(1e-9));
    let mut tau = Row::new(&name, "rnea (tau)", Tolerance::RelativeFloor(1e-9));
    let mut bias = Row::new(&name, "rnea (qfrc_bias)", Tolerance::RelativeFloor(1e-9));
    let nbody = reference["nbody"].as_u64().unwrap_or(0) as usize;
    for (k, s) in samples.iter().enumerate() {
        let qpos = numbers(&s["qpos"]);
        let q = model.q_from_mujoco(&qpos)?;
        let (with_acc, without) = (&output.samples[2 * k], &output.samples[2 * k + 1]);
        let xpos = numbers(&s["xpos"]);
        let xmat = numbers(&s["xmat"]);
        let mut pairs = Vec::new();
        for b in 0..nbody {
            let body = reference["bodies"][b]["name"]
                .as_str()
                .map_or_else(|| format!("body{b}"), str::to_string);
            let Some(p) = with_acc.link_poses.get(&body) else {
                bail!("{name}: no link for body '{body}'");
            };
            for i in 0..3 {
                pairs.push((p.translation[i], xpos[3 * b + i]));
                for j in 0..3 {
                    pairs.push((p.rotation[i][j], xmat[9 * b + 3 * i + j]));
                }
            }
        }
        poses.record(&pairs);
        let (Some(d), Some(d0)) = (&with_acc.dynamics, &without.dynamics) else {
            bail!("{name}: no dynamics in the output");
        };
        let g = velocity_map(&model, &qpos)?;
        let m: Vec<f64> = d.mass_matrix.iter().flatten().copied().collect();
        let expected = numbers(&s["M"]);
        let mut pairs = Vec::new();
        for i in 0..nv {
            for j in 0..nv {
                // (Gᵀ M G)[i][j]
                let mut x = 0.0;
                for a in 0..nv {
                    for b in 0..nv {
                        x += g[a * nv + i] * m[a * nv + b] * g[b * nv + j];
                    }
                }
                pairs.push((x, expected[i * nv + j]));
            }
        }
        mass.record(&pairs);
        for (row, out, key) in [(&mut tau, d, "tau"), (&mut bias, d0, "qfrc_bias")] {
            let ours = model.tau_to_mujoco(&q, out.rnea.as_deref().unwrap_or_default())?;
            let theirs = numbers(&s[key]);
            let pairs: Vec<(f64, f64)> = ours.into_iter().zip(theirs).collect();
            row.record(&pairs);
        }
    }
    Ok(vec![poses, mass, tau, bias])
}

/// Every MJCF reference model's rows.
pub(crate) fn check_all(root: &Path) -> Result<Vec<Row>> {
    let dir = root.join("tests/data/reference/mjcf");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut rows = Vec::new();
    for file in files {
        rows.extend(check_model(root, &file)?);
    }
    Ok(rows)
}
