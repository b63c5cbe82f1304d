//! libFuzzer target: `kinetree_fuzz::view::view` (see CONTRIBUTING.md, "Fuzzing").
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kinetree_fuzz::view::view(data));
