//! libFuzzer target: `kinetree_fuzz::harness::yapcad` (see CONTRIBUTING.md, "Fuzzing").
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = kinetree_fuzz::harness::yapcad(data);
});
