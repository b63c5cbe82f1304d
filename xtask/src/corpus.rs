//! `cargo xtask corpus [<dir>]`: load every `.urdf` under a folder and print one line per file.
//!
//! Without a folder it uses example-robot-data installed in the project's `.venv`
//! (`python3 -m venv .venv && .venv/bin/pip install example-robot-data`), and fails, saying so,
//! when it is not there: the corpus is an explicit task, never a silently empty test.
//!
//! Each file is loaded with a fixed and with a floating root, and the fixed model goes through
//! URDF and JSON (SI, again from JSON, and mm/deg) round trips that must give the same model.
//! Each line gives the file, its link and joint counts, `nq`/`nv`, and how many elements were
//! ignored and warnings raised, or the error. A panic while loading one file is caught and
//! reported as a failure of that file; the run goes on. The task fails if any file failed.

use anyhow::{Result, bail};
use kinetree_model::{JsonOptions, Model, RootJoint, Units};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

/// Loads every URDF under the folder given as the only argument, or under example-robot-data in
/// `.venv` without one.
pub(crate) fn run(args: &[String]) -> Result<()> {
    let dir = match args {
        [dir] => PathBuf::from(dir),
        [] => {
            let venv = crate::project_root().join(".venv");
            let Some(dir) = example_robot_data(&venv) else {
                bail!(
                    "example-robot-data is not installed in {}: run `python3 -m venv .venv && \
                     .venv/bin/pip install example-robot-data`, or pass a folder: \
                     cargo xtask corpus <dir>",
                    venv.display()
                );
            };
            println!("corpus: {}", dir.display());
            dir
        }
        _ => bail!("usage: cargo xtask corpus [<dir>]"),
    };
    let report = load_all(&dir)?;
    for line in &report.lines {
        println!("{line}");
    }
    println!(
        "{} files: {} loaded, {} failed",
        report.lines.len(),
        report.lines.len() - report.failed,
        report.failed
    );
    if report.failed > 0 {
        bail!(
            "{} of {} files failed to load",
            report.failed,
            report.lines.len()
        );
    }
    Ok(())
}

/// One line per file, and how many of them failed.
#[derive(Debug)]
pub(crate) struct Report {
    pub(crate) lines: Vec<String>,
    pub(crate) failed: usize,
}

/// Loads every `.urdf` under `dir` (recursively, in path order).
///
/// # Errors
/// When `dir` cannot be read or holds no URDF; a file that fails to load is a line of the report.
pub(crate) fn load_all(dir: &Path) -> Result<Report> {
    let mut files = Vec::new();
    urdf_files(dir, &mut files)
        .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", dir.display()))?;
    files.sort();
    if files.is_empty() {
        bail!("no .urdf file under {}", dir.display());
    }
    let width = files.iter().map(|f| shown(dir, f).len()).max().unwrap_or(0);

    // A panic still prints its location (and backtrace) on stderr through the default hook; the
    // table on stdout gets its message.
    let mut report = Report {
        lines: Vec::new(),
        failed: 0,
    };
    for file in &files {
        let name = shown(dir, file);
        let loaded = catch_unwind(AssertUnwindSafe(|| check_file(file)));
        let line = match loaded {
            Ok(Ok(m)) => format!(
                "ok    {name:width$}  {:>4} links  {:>4} joints  nq/nv {:>3}/{:<3}  {:>3} ignored  {:>3} warnings",
                m.links().len(),
                m.joints().len(),
                m.nq(),
                m.nv(),
                m.ignored().len(),
                m.warnings().len(),
            ),
            Ok(Err(e)) => {
                report.failed += 1;
                format!("ERROR {name:width$}  {e}")
            }
            Err(payload) => {
                report.failed += 1;
                let msg = payload
                    .downcast_ref::<&str>()
                    .map(|s| (*s).to_string())
                    .or_else(|| payload.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "panic with a non-text payload".to_string());
                format!("PANIC {name:width$}  {}", msg.replace('\n', " "))
            }
        };
        report.lines.push(line);
    }
    Ok(report)
}

/// Loads `file` with a fixed and a floating root and round-trips the fixed model; any failure
/// is the error text.
fn check_file(file: &Path) -> Result<Model, String> {
    Model::from_urdf_file(file, RootJoint::Floating).map_err(|e| format!("floating root: {e}"))?;
    let model = Model::from_urdf_file(file, RootJoint::Fixed).map_err(|e| e.to_string())?;
    round_trips(&model)?;
    Ok(model)
}

/// URDF → URDF, URDF → JSON (SI and mm/deg), JSON → JSON: each reload must equal the original
/// (URDF may lose named frames, and only mixed-unit joints with finite limits may refuse mm/deg).
fn round_trips(model: &Model) -> Result<(), String> {
    let root = model.root_joint();
    let urdf = model
        .to_urdf_string()
        .map_err(|e| format!("to URDF: {e}"))?;
    let back = Model::from_urdf_str(&urdf, root).map_err(|e| format!("URDF reload: {e}"))?;
    let frames_lost = format!("{} frames vs 0", model.frames().len());
    match model.first_difference(&back, 1e-12) {
        Some(d) if d != frames_lost => return Err(format!("URDF round trip differs: {d}")),
        _ => {}
    }
    let json = model
        .to_json_string(&JsonOptions::default())
        .map_err(|e| format!("to JSON: {e}"))?;
    let from_json = Model::from_json_str(&json, None).map_err(|e| format!("JSON reload: {e}"))?;
    if let Some(d) = model.first_difference(&from_json, 1e-12) {
        return Err(format!("JSON round trip differs: {d}"));
    }
    let json2 = from_json
        .to_json_string(&JsonOptions::default())
        .map_err(|e| format!("JSON again: {e}"))?;
    let again = Model::from_json_str(&json2, None).map_err(|e| format!("JSON again: {e}"))?;
    if let Some(d) = from_json.first_difference(&again, 1e-12) {
        return Err(format!("second JSON round trip differs: {d}"));
    }
    let mm = JsonOptions {
        units: Units::MM_DEG,
        ..JsonOptions::default()
    };
    match model.to_json_string(&mm) {
        Ok(json_mm) => {
            let from_mm =
                Model::from_json_str(&json_mm, None).map_err(|e| format!("mm/deg reload: {e}"))?;
            if let Some(d) = model.first_difference(&from_mm, 1e-9) {
                return Err(format!("mm/deg JSON round trip differs: {d}"));
            }
        }
        Err(e) if e.to_string().contains("mix lengths and angles") => {}
        Err(e) => return Err(format!("to mm/deg JSON: {e}")),
    }
    Ok(())
}

/// The `example-robot-data/robots` folder under `venv`, found without assuming the Python
/// version or the package layout (pip's `share/` or cmeel's prefix).
fn example_robot_data(venv: &Path) -> Option<PathBuf> {
    let mut stack = vec![venv.to_path_buf()];
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
                return Some(p);
            } else if d.components().count() < 16 {
                stack.push(p);
            }
        }
    }
    None
}

fn shown(dir: &Path, file: &Path) -> String {
    file.strip_prefix(dir).unwrap_or(file).display().to_string()
}

fn urdf_files(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            urdf_files(&path, out)?;
        } else if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
        {
            out.push(path);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_robots_all_load() {
        let dir = crate::project_root().join("tests/data/reference/urdf");
        let report = load_all(&dir).unwrap();
        assert_eq!(report.failed, 0, "{:#?}", report.lines);
        assert_eq!(report.lines.len(), 7);
        let panda = report
            .lines
            .iter()
            .find(|l| l.contains(" panda.urdf "))
            .unwrap();
        assert!(panda.starts_with("ok "), "{panda}");
        assert!(panda.contains("nq/nv   9/9"), "{panda}");
    }

    #[test]
    fn a_bad_file_is_reported_and_the_run_goes_on() {
        let dir = std::env::temp_dir().join(format!("kinetree-corpus-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("a_broken.urdf"), "<robot name=\"x\"><link name=").unwrap();
        std::fs::write(
            dir.join("sub/b_ok.urdf"),
            "<robot name=\"one\"><link name=\"base\"/></robot>",
        )
        .unwrap();
        std::fs::write(dir.join("notes.txt"), "not a robot").unwrap();
        let report = load_all(&dir);
        std::fs::remove_dir_all(&dir).unwrap();
        let report = report.unwrap();
        assert_eq!(report.failed, 1);
        assert_eq!(report.lines.len(), 2);
        assert!(
            report.lines[0].starts_with("ERROR a_broken.urdf"),
            "{}",
            report.lines[0]
        );
        assert!(
            report.lines[1].starts_with("ok    sub/b_ok.urdf"),
            "{}",
            report.lines[1]
        );
        assert!(report.lines[1].contains("1 links"), "{}", report.lines[1]);
    }

    #[test]
    fn a_missing_corpus_is_found_missing_and_a_present_one_found() {
        let venv = std::env::temp_dir().join(format!("kinetree-venv-{}", std::process::id()));
        let robots =
            venv.join("lib/python3.11/site-packages/cmeel.prefix/share/example-robot-data/robots");
        std::fs::create_dir_all(venv.join("bin")).unwrap();
        let missing = example_robot_data(&venv);
        std::fs::create_dir_all(&robots).unwrap();
        let found = example_robot_data(&venv);
        std::fs::remove_dir_all(&venv).unwrap();
        assert_eq!(missing, None);
        assert_eq!(found, Some(robots));
    }
}
