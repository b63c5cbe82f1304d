//! `cargo xtask regress`: runs every reference robot's samples through kinetree's batch evaluator
//! (the same code as `kinetree compute`) and compares the results with Pinocchio's values in
//! `tests/data/reference/*.json`, printing one table of worst errors (robot × quantity); the MJCF
//! models of `tests/data/reference/mjcf` are compared with MuJoCo's values in the same table
//! (`regress_mjcf`).
//!
//! Vectors and matrices are mapped by joint name through the reference's `joints` table (Pinocchio
//! orders child joints by name; kinetree keeps its own order). The same check runs under
//! `cargo test` (see the test at the bottom).

use anyhow::{Context, Result, bail};
use kinetree::batch::{BatchOptions, SampleInput, evaluate};
use kinetree::model::{Model, RootJoint};
use serde_json::Value;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

/// How a quantity's error is judged.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Tolerance {
    /// Every entry within this absolute error.
    Absolute(f64),
    /// Every entry within this error relative to the largest reference entry of the sample.
    Relative(f64),
    /// Relative, scaled per sample by the mass matrix condition number: `max(base, cond · 1e-13)`
    /// (the reference expects differences of order `cond · 1e-15` between implementations).
    RelativeCond(f64),
    /// Relative to `max(1, largest reference entry)` of the sample.
    RelativeFloor(f64),
    /// As `RelativeFloor`, scaled by `max(1, cond / 1e3)`.
    RelativeFloorCond(f64),
}

/// Worst errors of one quantity of one robot.
#[derive(Clone, Debug)]
pub(crate) struct Row {
    pub(crate) robot: String,
    pub(crate) quantity: &'static str,
    pub(crate) worst_abs: f64,
    /// Worst error divided by the largest reference magnitude of that quantity in the sample.
    pub(crate) worst_rel: f64,
    tolerance: Tolerance,
    pub(crate) entries: usize,
    /// Worst error divided by its sample's tolerance: the check passes when this is at most 1.
    worst_ratio: f64,
}

impl Row {
    pub(crate) fn new(robot: &str, quantity: &'static str, tolerance: Tolerance) -> Self {
        Self {
            robot: robot.to_string(),
            quantity,
            worst_abs: 0.0,
            worst_rel: 0.0,
            tolerance,
            entries: 0,
            worst_ratio: 0.0,
        }
    }

    /// Records one sample's pairs (ours, reference); `cond` is the sample's mass matrix condition
    /// number (used by [`Tolerance::RelativeCond`]).
    pub(crate) fn record_with(&mut self, pairs: &[(f64, f64)], cond: f64) {
        let scale = pairs.iter().fold(0.0f64, |m, (_, r)| m.max(r.abs()));
        for (ours, reference) in pairs {
            // A NaN never compares as small: record it as an infinite error.
            let err = if ours.is_finite() {
                (ours - reference).abs()
            } else {
                f64::INFINITY
            };
            self.worst_abs = self.worst_abs.max(err);
            let rel = if scale > 0.0 { err / scale } else { err };
            self.worst_rel = self.worst_rel.max(rel);
            let ratio = match self.tolerance {
                Tolerance::Absolute(t) => err / t,
                Tolerance::Relative(t) => rel / t,
                Tolerance::RelativeCond(t) => rel / t.max(cond * 1e-13),
                Tolerance::RelativeFloor(t) => err / scale.max(1.0) / t,
                Tolerance::RelativeFloorCond(t) => {
                    err / scale.max(1.0) / (t * (cond / 1e3).max(1.0))
                }
            };
            self.worst_ratio = self.worst_ratio.max(ratio);
        }
        self.entries += pairs.len();
    }

    pub(crate) fn record(&mut self, pairs: &[(f64, f64)]) {
        self.record_with(pairs, 1.0);
    }

    pub(crate) fn passed(&self) -> bool {
        self.entries > 0 && self.worst_ratio <= 1.0
    }

    fn tolerance_text(&self) -> String {
        match self.tolerance {
            Tolerance::Absolute(t) => format!("{t:.0e} abs"),
            Tolerance::Relative(t) => format!("{t:.0e} rel"),
            Tolerance::RelativeCond(t) => format!("{t:.0e}*cond"),
            Tolerance::RelativeFloor(t) => format!("{t:.0e} rel1"),
            Tolerance::RelativeFloorCond(t) => format!("{t:.0e}*c/1e3"),
        }
    }
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// Compares one robot; returns its rows.
pub(crate) fn check_robot(root: &Path, file: &Path) -> Result<Vec<Row>> {
    let text =
        std::fs::read_to_string(file).with_context(|| format!("cannot read {}", file.display()))?;
    let reference: Value =
        serde_json::from_str(&text).with_context(|| format!("cannot parse {}", file.display()))?;
    let robot = reference["robot"].as_str().unwrap_or("?").to_string();
    let root_joint = match reference["root_joint"].as_str() {
        Some("fixed") => RootJoint::Fixed,
        _ => RootJoint::Floating,
    };
    let urdf = root
        .join("tests/data/reference")
        .join(reference["urdf"].as_str().unwrap_or_default());
    let model = Model::from_urdf_file(&urdf, root_joint)?;
    let jacobian_links: Vec<String> = reference["jacobian_links"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|x| x.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    let options = BatchOptions {
        jacobians: jacobian_links.clone(),
        frames: kinetree::batch::FrameSelection::None,
        no_dynamics: false,
        // The derivatives have their own check (regress_derivatives).
        derivatives: false,
        // The reference ignores URDF <dynamics> damping and friction, as Pinocchio does.
        joint_dynamics: false,
        strict: true,
        // Collision is compared where the reference has it (primitive geometry, no meshes).
        collision: reference["samples"][0]["collision"]
            .is_array()
            .then(kinetree::collision::CollisionOptions::default),
    };
    let inputs = reference["samples"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|sample| serde_json::from_value::<SampleInput>(sample["state"].clone()))
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("{robot}: malformed sample state"))?;
    let output = evaluate(&model, &inputs, &options)
        .with_context(|| format!("{robot}: evaluation failed"))?;
    // The comparison below reads the response in its JSON form, key by key as the reference.
    let response = serde_json::to_value(&output)?;

    // Our v column of each of Pinocchio's v columns, by joint name.
    let ours_idx: HashMap<&str, usize> = response["model"]["joints"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|j| Some((j["name"].as_str()?, j["idx_v"].as_u64()? as usize)))
        .collect();
    let mut column_map = Vec::new(); // (ours, theirs)
    for j in reference["joints"].as_array().into_iter().flatten() {
        let name = j["name"].as_str().unwrap_or_default();
        let Some(&ours) = ours_idx.get(name) else {
            bail!("{robot}: joint '{name}' missing from kinetree's model")
        };
        let (theirs, nv) = (
            j["idx_v"].as_u64().unwrap_or(0) as usize,
            j["nv"].as_u64().unwrap_or(0) as usize,
        );
        for k in 0..nv {
            column_map.push((ours + k, theirs + k));
        }
    }

    let mut poses = Row::new(&robot, "link_poses", Tolerance::Absolute(1e-9));
    let mut jacobians = Row::new(&robot, "jacobians", Tolerance::Absolute(1e-9));
    let rel = Tolerance::Relative(1e-9);
    let vector_names = ["rnea", "nle", "gravity_torque", "aba"];
    let mut vectors: Vec<Row> = vector_names
        .iter()
        .map(|&q| {
            Row::new(
                &robot,
                q,
                if q == "aba" {
                    Tolerance::RelativeCond(1e-9)
                } else {
                    rel
                },
            )
        })
        .collect();
    let mut mass_matrix = Row::new(&robot, "mass_matrix", rel);
    let mut com = Row::new(&robot, "com", rel);
    let mut energy = Row::new(&robot, "kinetic_energy", rel);
    let mut momentum = Row::new(&robot, "centroidal_momentum", rel);
    let mut collision = Row::new(&robot, "collision", Tolerance::Absolute(1e-6));
    let mut pair_sets_equal = true;
    let samples = reference["samples"]
        .as_array()
        .map(Vec::as_slice)
        .unwrap_or_default();
    for (sample, ours) in samples
        .iter()
        .zip(response["samples"].as_array().into_iter().flatten())
    {
        let mut pairs = Vec::new();
        for (link, pose) in sample["link_poses"].as_object().into_iter().flatten() {
            let got = &ours["link_poses"][link];
            for i in 0..3 {
                pairs.push((f(&got["translation"][i]), f(&pose["translation"][i])));
                for j in 0..3 {
                    pairs.push((f(&got["rotation"][i][j]), f(&pose["rotation"][i][j])));
                }
            }
        }
        poses.record(&pairs);
        for (link, expected) in sample["jacobians"].as_object().into_iter().flatten() {
            let got = &ours["jacobians"][link];
            let mut pairs = Vec::new();
            for r in 0..6 {
                for &(o, t) in &column_map {
                    pairs.push((f(&got[r][o]), f(&expected[r][t])));
                }
            }
            jacobians.record(&pairs);
        }
        let cond = sample["mass_matrix_cond"].as_f64().unwrap_or(f64::INFINITY);
        // Joint-space vectors by joint name (numbers for 1-DoF joints, arrays otherwise).
        for (row, name) in vectors.iter_mut().zip(vector_names) {
            let expected = &sample["by_joint"][name];
            let Some(expected) = expected.as_object() else {
                continue;
            };
            let mut pairs = Vec::new();
            for (joint, value) in expected {
                let got = &ours["by_joint"][name][joint];
                match value {
                    Value::Array(a) => {
                        pairs.extend(a.iter().enumerate().map(|(k, x)| (f(&got[k]), f(x))));
                    }
                    x => pairs.push((f(got), f(x))),
                }
            }
            row.record_with(&pairs, cond);
        }
        if let Some(m) = sample["mass_matrix"].as_array() {
            let mut pairs = Vec::new();
            for &(oi, ti) in &column_map {
                for &(oj, tj) in &column_map {
                    pairs.push((f(&ours["mass_matrix"][oi][oj]), f(&m[ti][tj])));
                }
            }
            mass_matrix.record(&pairs);
        }
        let triples = |key: &str, n: usize| -> Vec<(f64, f64)> {
            (0..n)
                .map(|k| (f(&ours[key][k]), f(&sample[key][k])))
                .collect()
        };
        if sample["com"].is_array() {
            com.record(&triples("com", 3));
        }
        if sample["centroidal_momentum"].is_array() {
            momentum.record(&triples("centroidal_momentum", 6));
        }
        if let Some(e) = sample["kinetic_energy"].as_f64() {
            energy.record(&[(f(&ours["kinetic_energy"]), e)]);
        }
        if let Some(expected) = sample["collision"].as_array() {
            // Unordered link pairs: kinetree and Pinocchio order links differently.
            let key = |p: &Value| {
                let (a, b) = (
                    p["link_a"].as_str().unwrap_or_default(),
                    p["link_b"].as_str().unwrap_or_default(),
                );
                if a < b {
                    (a.to_string(), b.to_string())
                } else {
                    (b.to_string(), a.to_string())
                }
            };
            let got: HashMap<(String, String), f64> = ours["collision"]
                .as_array()
                .into_iter()
                .flatten()
                .map(|p| (key(p), f(&p["distance"])))
                .collect();
            pair_sets_equal &= got.len() == expected.len();
            let mut pairs = Vec::new();
            for p in expected {
                match got.get(&key(p)) {
                    Some(&d) => pairs.push((d, f(&p["distance"]))),
                    None => {
                        pair_sets_equal = false;
                        pairs.push((f64::NAN, f(&p["distance"])));
                    }
                }
            }
            collision.record(&pairs);
        }
    }
    if !pair_sets_equal {
        // A pair missing on either side fails the check.
        collision.record(&[(f64::NAN, 0.0)]);
    }
    let mut rows = vec![poses, jacobians];
    rows.extend(vectors);
    rows.extend([mass_matrix, com, energy, momentum]);
    if collision.entries > 0 {
        rows.push(collision);
    }
    // The analytic derivatives, from derivatives/<same file name>.
    let stem = file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_default();
    rows.extend(crate::regress_derivatives::check_robot(
        root, stem, &reference,
    )?);
    Ok(rows)
}

/// Runs every reference file and returns all rows.
pub(crate) fn check_all(root: &Path) -> Result<Vec<Row>> {
    let dir = root.join("tests/data/reference");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!("no reference files in {}", dir.display());
    }
    let mut rows = Vec::new();
    for file in files {
        rows.extend(check_robot(root, &file)?);
    }
    rows.extend(crate::regress_mjcf::check_all(root)?);
    Ok(rows)
}

/// The table, one line per robot × quantity.
pub(crate) fn table(rows: &[Row]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<34} {:<20} {:>12} {:>12} {:>10} {:>8}  result",
        "robot", "quantity", "worst abs", "worst rel", "tolerance", "entries"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:<34} {:<20} {:>12.3e} {:>12.3e} {:>10} {:>8}  {}",
            r.robot,
            r.quantity,
            r.worst_abs,
            r.worst_rel,
            r.tolerance_text(),
            r.entries,
            if r.passed() { "pass" } else { "FAIL" }
        );
    }
    s
}

/// Runs the regression suite and prints the table; fails when any quantity fails.
pub(crate) fn run(args: &[String]) -> Result<()> {
    crate::no_args("regress", args)?;
    let rows = check_all(&crate::project_root())?;
    print!("{}", table(&rows));
    let failed = rows.iter().filter(|r| !r.passed()).count();
    if failed > 0 {
        bail!("{failed} of {} checks failed", rows.len());
    }
    println!("all {} checks passed", rows.len());
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn regression_suite_passes() {
        let rows = super::check_all(&crate::project_root()).unwrap();
        let table = super::table(&rows);
        assert!(rows.len() >= 7 * 10, "{table}");
        assert!(rows.iter().all(super::Row::passed), "{table}");
    }
}
