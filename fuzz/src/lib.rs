//! Fuzz targets of kinetree (see CONTRIBUTING.md, "Fuzzing"); the harness is shared with the
//! stable `cargo test` cases in `tests/fuzz.rs`, and the viewer's API with the CLI's tests.

pub mod harness;
pub mod view;
