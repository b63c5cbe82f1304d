//! Integration tests of the reachable-workspace crate.

mod frame_id;
mod reachable;

pub(crate) use kinetree_test_support::reference_dir;
