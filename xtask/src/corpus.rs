//! `cargo xtask corpus <dir>`: load every `.urdf` under a folder and print one line per file.
//!
//! Each line gives the file, its link and joint counts, `nq`/`nv`, and how many elements were
//! ignored and warnings raised, or the error. A panic while loading one file is caught and
//! reported as a failure of that file; the run goes on. The task fails if any file failed.

use anyhow::{Result, bail};
use kinetree_model::{Model, RootJoint};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

/// Loads every URDF under the folder given as the only argument.
pub(crate) fn run(args: &[String]) -> Result<()> {
    let [dir] = args else {
        bail!("usage: cargo xtask corpus <dir>");
    };
    let report = load_all(Path::new(dir))?;
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
        let loaded = catch_unwind(AssertUnwindSafe(|| {
            Model::from_urdf_file(file, RootJoint::Fixed)
        }));
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
}
