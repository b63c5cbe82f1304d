//! Fuzz targets of kinetree (see CONTRIBUTING.md, "Fuzzing"); the harness is shared with the
//! stable `cargo test` cases in `tests/fuzz.rs`.

pub mod harness;
