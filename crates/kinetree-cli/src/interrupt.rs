//! Ctrl-C (SIGINT) for the long runs: `simulate` and `bench` call [`watch`] before their loops,
//! poll [`requested`] between steps or timed chunks, stop, keep what they have (the trajectory
//! written to `--out`, the timings measured) and return [`Interrupted`], which `main` reports
//! with exit code 130 (the shell's code for SIGINT). A second Ctrl-C exits at once.
//!
//! Other commands keep the default: Ctrl-C ends them immediately, before they write anything.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// The exit code of a run stopped by Ctrl-C (128 + SIGINT).
pub(crate) const EXIT_CODE: u8 = 130;

/// Installs the Ctrl-C handler: the first Ctrl-C sets the flag [`requested`] reads, a second
/// one exits at once with [`EXIT_CODE`]. Installing twice is harmless (the second call fails and
/// the first handler stays).
pub(crate) fn watch() {
    let _ = ctrlc::set_handler(|| {
        if REQUESTED.swap(true, Ordering::SeqCst) {
            std::process::exit(i32::from(EXIT_CODE));
        }
    });
}

/// Whether Ctrl-C was pressed since [`watch`].
pub(crate) fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// A run stopped by Ctrl-C after keeping its partial results; `what` says what was kept.
#[derive(Debug)]
pub(crate) struct Interrupted {
    /// What the run did before it stopped, and what it kept.
    pub(crate) what: String,
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted by Ctrl-C: {}", self.what)
    }
}

impl std::error::Error for Interrupted {}
