//! What the binary's messages say: a diverging simulation is called one (with its step and
//! time), and huge or tiny numbers are in scientific notation, never hundreds of digits.

mod common;

use common::*;

#[test]
fn a_diverging_simulation_says_so_naming_the_step_not_a_massless_subtree() {
    let o = kinetree(&["simulate", &panda(), "--v", "panda_joint1=1e6"]);
    refused(
        &o,
        &[
            "step 1 (t = 0.001000 s)",
            "the simulation diverged",
            "numerically singular",
            "m from the origin",
        ],
    );
    assert!(!stderr(&o).contains("massless"), "{}", stderr(&o));
}

#[test]
fn huge_and_tiny_numbers_in_messages_are_in_scientific_notation() {
    // No run of 20 digits in any message (1e300 used to print as 301 digits).
    let long_digits = |s: &str| {
        s.split(|c: char| !c.is_ascii_digit())
            .any(|run| run.len() >= 20)
    };
    for (args, needle) in [
        (
            vec![
                "dynamics",
                "--floating",
                "--q",
                "root_joint=0:0:0:1e300:0:0:1",
                "--a",
                "panda_joint1=0",
            ],
            "norm 1e300,",
        ),
        (
            vec!["workspace", "--frame", "panda_hand", "--voxel", "1e-300"],
            "voxel size 1e-300 m",
        ),
        (
            vec!["simulate", "--dt", "1e300", "--duration", "1e301"],
            "t = 1.000000e300 s",
        ),
    ] {
        let model = panda();
        let mut full = vec![args[0], model.as_str()];
        full.extend_from_slice(&args[1..]);
        let o = kinetree(&full);
        refused(&o, &[needle]);
        assert!(!long_digits(&stderr(&o)), "{}", stderr(&o));
    }
}
