//! Integration tests of the reachable-workspace crate.

mod frame_id;
mod reachable;

use std::path::PathBuf;

/// The Pinocchio reference folder (its `urdf/` holds the robots).
pub(crate) fn reference_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/reference")
}
