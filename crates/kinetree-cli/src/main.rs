//! `kinetree`: the command-line face of the kinetree library.
//!
//! One module per command under `cmd/`; each has an `Args` struct (clap derive) and a `run`
//! function returning `anyhow::Result<()>`. Errors are printed with their context chain (which
//! names the file involved) and the process exits with code 1; bad input never panics.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[macro_use]
mod out;
mod cmd;
mod interrupt;
mod plot;
mod table;

/// Kinematics, dynamics and collision of articulated rigid bodies (URDF and JSON robots).
#[derive(Debug, Parser)]
#[command(name = "kinetree", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print a model's tree, dimensions, joint table, masses, frames and load warnings.
    Inspect(cmd::inspect::Args),
    /// Convert a model between URDF and JSON (formats chosen by the file extensions).
    Convert(cmd::convert::Args),
    /// Evaluate many named states at once from a JSON file: link poses, Jacobians, dynamics
    /// quantities and collision distances.
    #[command(after_long_help = cmd::compute::WHAT_IT_COMPUTES)]
    Compute(cmd::compute::Args),
    /// Time each algorithm on random in-limit states of a model (median ns/call).
    Bench(cmd::bench::Args),
    /// Inverse kinematics of one frame: the joint values that place it at a target pose.
    Ik(cmd::ik::Args),
    /// Colliding pairs and closest pairs of a configuration, against itself and world obstacles.
    Collide(cmd::collide::Args),
    /// Inverse dynamics (τ), forward dynamics (q̈) and the mass matrix of one state, by joint name.
    Dynamics(cmd::dynamics::Args),
    /// Integrate the equations of motion from a state; report and plot joint positions and energy.
    Simulate(cmd::simulate::Args),
    /// Sample where a frame can reach: bounds, reach, volume, manipulability, files and a plot.
    Workspace(cmd::workspace::Args),
    /// Write one frame's forward kinematics as Rust, C or Python (SymPy/CasADi) source.
    Codegen(cmd::codegen::Args),
    /// Show the robot in the browser: move joints, drag a frame with IK, play a trajectory.
    View(cmd::view::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Inspect(args) => cmd::inspect::run(&args),
        Command::Convert(args) => cmd::convert::run(&args),
        Command::Compute(args) => cmd::compute::run(&args),
        Command::Bench(args) => cmd::bench::run(&args),
        Command::Workspace(args) => cmd::workspace::run(&args),
        Command::Dynamics(args) => cmd::dynamics::run(&args),
        Command::Collide(args) => cmd::collide::run(&args),
        Command::Ik(args) => cmd::ik::run(&args),
        Command::Simulate(args) => cmd::simulate::run(&args),
        Command::Codegen(args) => cmd::codegen::run(&args),
        Command::View(args) => cmd::view::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // `kinetree … | head`: the reader has what it wanted.
        Err(e) if e.downcast_ref::<out::StdoutClosed>().is_some() => ExitCode::SUCCESS,
        // Ctrl-C after the partial results were kept: say so, with the shell's SIGINT code.
        Err(e) if e.downcast_ref::<interrupt::Interrupted>().is_some() => {
            eprintln!("{e}");
            ExitCode::from(interrupt::EXIT_CODE)
        }
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::FAILURE
        }
    }
}

/// The error and its causes on one line, `outer: inner: …`, leaving out a cause whose text the
/// message already ends with (some errors print their source in their own message too).
fn message(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if out.ends_with(&text) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&text);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn causes_already_in_the_message_are_not_repeated() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let e = Err::<(), _>(io)
            .context("cannot access a.urdf: no such file")
            .context("cannot load a.urdf")
            .unwrap_err();
        assert_eq!(
            message(&e),
            "cannot load a.urdf: cannot access a.urdf: no such file"
        );
        let e = anyhow::anyhow!("inner").context("outer");
        assert_eq!(message(&e), "outer: inner");
    }
}
