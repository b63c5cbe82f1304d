//! Standard output that survives its reader going away: `kinetree … | head` closes the pipe,
//! which is a normal end of the command (exit code 0), never a panic.
//!
//! Commands print with [`outln!`] and [`out!`] (as `println!` and `print!`, returning a
//! `Result`); a closed pipe becomes [`StdoutClosed`], which `main` treats as success.

use std::io::Write;

/// Standard output was closed by its reader: the command stops early, successfully.
#[derive(Debug)]
pub(crate) struct StdoutClosed;

impl std::fmt::Display for StdoutClosed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("standard output was closed")
    }
}

impl std::error::Error for StdoutClosed {}

/// Writes `text` to standard output and flushes.
///
/// # Errors
/// [`StdoutClosed`] when the reader has gone (broken pipe); the I/O error otherwise.
pub(crate) fn emit(text: &str) -> anyhow::Result<()> {
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(StdoutClosed.into()),
        Err(e) => Err(anyhow::Error::new(e).context("cannot write to standard output")),
    }
}

/// `println!` that returns `anyhow::Result<()>` (see [`emit`]).
macro_rules! outln {
    () => {
        $crate::out::emit("\n")
    };
    ($($arg:tt)*) => {
        $crate::out::emit(&format!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that returns `anyhow::Result<()>` (see [`emit`]).
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::out::emit(&format!($($arg)*))
    };
}
