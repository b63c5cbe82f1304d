//! `cargo xtask regress`: compare kinetree against the reference values in
//! `tests/data/reference/*.json` and print the table of worst errors.
//!
//! Not written yet: it lands with the kinematics layer (which has quantities to compare). When it
//! does, add a `#[test]` here that runs it so that `cargo test --workspace` covers it, as
//! `layers::tests::workspace_respects_the_layers` does for the layer check.

use anyhow::{Result, bail};

/// Runs the regression suite.
pub(crate) fn run(_args: &[String]) -> Result<()> {
    bail!("`cargo xtask regress` is not written yet: it arrives with kinetree-kinematics")
}
