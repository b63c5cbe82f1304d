//! libFuzzer target: `kinetree_fuzz::harness::mjcf` (see CONTRIBUTING.md, "Fuzzing").
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kinetree_fuzz::harness::mjcf(data));
