//! Every URDF of example-robot-data (installed in the workspace's `.venv`) loads without error.

use kinetree_model::{Model, RootJoint};
use std::path::{Path, PathBuf};

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            collect(&p, out);
        } else if p.extension().is_some_and(|x| x == "urdf") {
            out.push(p);
        }
    }
}

pub(crate) fn corpus() -> Vec<PathBuf> {
    let venv = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../.venv");
    let mut roots = Vec::new();
    let mut stack = vec![venv];
    // Find `.../share/example-robot-data/robots` without assuming the Python version.
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if !p.is_dir() {
                continue;
            }
            if p.ends_with("example-robot-data/robots") {
                roots.push(p);
            } else if d.components().count() < 16 {
                stack.push(p);
            }
        }
    }
    let mut files = Vec::new();
    for r in roots {
        collect(&r, &mut files);
    }
    // `lib64` is often a link to `lib`: keep each file once.
    let mut files: Vec<PathBuf> = files
        .into_iter()
        .filter_map(|f| f.canonicalize().ok())
        .collect();
    files.sort();
    files.dedup();
    files
}

#[test]
fn example_robot_data_loads() {
    let files = corpus();
    if files.is_empty() {
        eprintln!("example-robot-data not installed in .venv: corpus test skipped");
        return;
    }
    let mut failures = Vec::new();
    for f in &files {
        for root in [RootJoint::Fixed, RootJoint::Floating] {
            if let Err(e) = Model::from_urdf_file(f, root) {
                failures.push(format!("{}: {e}", f.display()));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} failed:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}
