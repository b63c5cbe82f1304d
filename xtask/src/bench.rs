//! `cargo xtask bench`: run the criterion benchmarks against a saved baseline
//! (`--save-baseline` / `--baseline`) and print the comparison.
//!
//! Not written yet: it arrives with the first benchmarks in `benches/`.

use anyhow::{Result, bail};

/// Runs the benchmarks.
pub(crate) fn run(_args: &[String]) -> Result<()> {
    bail!("`cargo xtask bench` is not written yet: it arrives with the first benchmarks")
}
