//! kinetree's project tasks, run as `cargo xtask <task>` (the alias is in `.cargo/config.toml`).
//!
//! Each task is one module with a `run` function; `try_main` dispatches on the first argument.
//! The tasks are plain Rust so that they run the same on every machine with only cargo installed.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod bench;
mod ci;
mod corpus;
mod ik_report;
mod layers;
mod regress;
mod regress_derivatives;
mod regress_mjcf;
mod test;
mod tidy;

const USAGE: &str = "\
usage: cargo xtask <task> [args]

tasks:
  ci             run every CI step in order (fmt, clippy, layers, tidy, tests, docs, benches build)
  test           every test: cargo test --workspace, then the Python package's pytest suite
  layers         check that each crate depends only on the layer directly below it
  tidy           reject should_panic and ignore test attributes anywhere in the tree
  corpus [<dir>] load and round-trip every .urdf under <dir> (default: example-robot-data in .venv)
  ik-report      inverse-kinematics quality table (success %, times) on panda, ur5, kinova
  regress        compare against Pinocchio's reference values and print the table of worst errors
  bench          criterion baselines (not written yet)";

fn main() -> ExitCode {
    match try_main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn try_main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((task, rest)) = args.split_first() else {
        println!("{USAGE}");
        return Ok(());
    };
    match task.as_str() {
        "ci" => ci::run(rest),
        "test" => test::run(rest),
        "layers" => layers::run(rest),
        "tidy" => tidy::run(rest),
        "corpus" => corpus::run(rest),
        "regress" => regress::run(rest),
        "bench" => bench::run(rest),
        "ik-report" => ik_report::run(rest),
        "help" | "-h" | "--help" => {
            println!("{USAGE}");
            Ok(())
        }
        other => bail!("unknown task '{other}'\n\n{USAGE}"),
    }
}

/// The workspace root (the directory holding the root `Cargo.toml`).
fn project_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives one level below the workspace root")
        .to_path_buf()
}

/// Fails when a task that takes no arguments is given some.
fn no_args(task: &str, args: &[String]) -> Result<()> {
    if args.is_empty() {
        Ok(())
    } else {
        bail!("`cargo xtask {task}` takes no arguments (got {args:?})")
    }
}

/// Reads a file to a string, naming it in the error.
fn read(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))
}
