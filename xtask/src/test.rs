//! `cargo xtask test`: every test, Rust and Python.
//!
//! 1. `cargo test --workspace` (unit, integration and doc-tests, the layer check, the regression
//!    suite against Pinocchio);
//! 2. the Python package `crates/kinetree-py`: a virtualenv at `target/py-venv` (created on first
//!    use with `python3 -m venv`, or `$KINETREE_PYTHON -m venv`), `pip install` of maturin, numpy,
//!    pytest and `dask[distributed]` from the package index (pip skips what is already there),
//!    `maturin develop` (the extension built into the venv, dev profile), then `pytest` on
//!    `crates/kinetree-py/tests` (reference values, batches, errors, pickling, threads,
//!    doctests, the Dask example on a two-process LocalCluster).

use anyhow::{Context, Result, bail};
use std::path::Path;
use std::process::Command;

/// What pip installs into the test virtualenv.
const PYTHON_PACKAGES: &[&str] = &["maturin>=1.9,<2", "numpy", "pytest", "dask[distributed]"];

/// Runs the Rust tests, then the Python tests; fails if either does (both always run).
pub(crate) fn run(args: &[String]) -> Result<()> {
    crate::no_args("test", args)?;
    let root = crate::project_root();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    println!("==> cargo test --workspace");
    let rust = status(
        Command::new(&cargo)
            .args(["test", "--workspace"])
            .current_dir(&root),
    );
    println!("==> Python tests (crates/kinetree-py)");
    let python = python_tests(&root);
    match (rust, python) {
        (Ok(()), Ok(())) => Ok(()),
        (Err(e), Ok(())) => Err(e.context("Rust tests failed")),
        (Ok(()), Err(e)) => Err(e.context("Python tests failed")),
        (Err(r), Err(p)) => bail!("Rust tests failed ({r:#}) and Python tests failed ({p:#})"),
    }
}

/// Builds the extension into `target/py-venv` and runs pytest there.
fn python_tests(root: &Path) -> Result<()> {
    let venv = root.join("target").join("py-venv");
    let bin = venv.join("bin");
    let python = bin.join("python");
    if !python.is_file() {
        let base = std::env::var("KINETREE_PYTHON").unwrap_or_else(|_| "python3".to_string());
        status(Command::new(&base).arg("-m").arg("venv").arg(&venv))
            .with_context(|| format!("creating the virtualenv {} with {base}", venv.display()))?;
    }
    status(
        Command::new(&python)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
            ])
            .args(PYTHON_PACKAGES),
    )
    .context("installing maturin, numpy, pytest and dask")?;
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    status(
        Command::new(bin.join("maturin"))
            .args(["develop", "--quiet"])
            .current_dir(root.join("crates/kinetree-py"))
            .env("VIRTUAL_ENV", &venv)
            .env("PATH", &path),
    )
    .context("building the extension (maturin develop)")?;
    status(
        Command::new(&python)
            .args(["-m", "pytest", "crates/kinetree-py/tests", "-q"])
            .current_dir(root)
            .env("PATH", &path),
    )
    .context("pytest")
}

/// Runs a command and fails unless it exits successfully.
fn status(command: &mut Command) -> Result<()> {
    let shown = format!("{command:?}");
    let s = command
        .status()
        .with_context(|| format!("cannot run {shown}"))?;
    if s.success() {
        Ok(())
    } else {
        bail!("{shown} exited with {s}")
    }
}
