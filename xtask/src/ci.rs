//! `cargo xtask ci`: every CI step, in order, each reported PASS or FAIL.
//!
//! All steps run even when one fails, so one run shows every problem; the task fails at the end
//! if any step did. `.ci/run` installs the toolchain components and calls this.

use anyhow::{Result, bail};
use std::process::Command;
use std::time::Instant;

/// The test command: the Rust tests and the Python package's tests (see `test.rs`). README.md's
/// "two commands" section shows exactly this string (a test below keeps them equal), so what a
/// contributor runs is what CI runs.
pub(crate) const TEST_COMMAND: &str = "cargo xtask test";

/// How a step runs: a cargo command line, or a check inside this process.
enum Action {
    /// `cargo` arguments and extra environment variables.
    Cargo(
        &'static [&'static str],
        &'static [(&'static str, &'static str)],
    ),
    /// A task of this xtask, run in-process (same code as `cargo xtask <task>`).
    InProcess(fn(&[String]) -> Result<()>),
}

/// The steps, in order: cheap checks first, then the builds.
fn steps() -> Vec<(&'static str, Action)> {
    vec![
        (
            "cargo fmt --all --check",
            Action::Cargo(&["fmt", "--all", "--check"], &[]),
        ),
        (
            "cargo clippy --workspace --all-targets -- -D warnings",
            Action::Cargo(
                &[
                    "clippy",
                    "--workspace",
                    "--all-targets",
                    "--",
                    "-D",
                    "warnings",
                ],
                &[],
            ),
        ),
        ("cargo xtask layers", Action::InProcess(crate::layers::run)),
        ("cargo xtask tidy", Action::InProcess(crate::tidy::run)),
        (TEST_COMMAND, Action::InProcess(crate::test::run)),
        (
            "RUSTDOCFLAGS=-D warnings cargo doc --workspace --no-deps",
            Action::Cargo(
                &["doc", "--workspace", "--no-deps"],
                &[("RUSTDOCFLAGS", "-D warnings")],
            ),
        ),
        (
            "cargo bench --workspace --no-run",
            Action::Cargo(&["bench", "--workspace", "--no-run"], &[]),
        ),
    ]
}

/// Runs every step and fails if any failed.
pub(crate) fn run(args: &[String]) -> Result<()> {
    crate::no_args("ci", args)?;
    let root = crate::project_root();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let steps = steps();
    let total = Instant::now();
    let mut results = Vec::new();
    for (i, (name, action)) in steps.iter().enumerate() {
        println!("\n==> [{}/{}] {name}", i + 1, steps.len());
        let start = Instant::now();
        let outcome = match action {
            Action::Cargo(args, env) => Command::new(&cargo)
                .args(*args)
                .envs(env.iter().copied())
                .current_dir(&root)
                .status()
                .map_err(anyhow::Error::from)
                .and_then(|s| {
                    if s.success() {
                        Ok(())
                    } else {
                        bail!("exited with {s}")
                    }
                }),
            Action::InProcess(task) => task(&[]),
        };
        let secs = start.elapsed().as_secs_f64();
        let passed = match &outcome {
            Ok(()) => true,
            Err(e) => {
                eprintln!("{name}: {e:#}");
                false
            }
        };
        println!(
            "{} {name} ({secs:.1} s)",
            if passed { "PASS" } else { "FAIL" }
        );
        results.push((*name, passed, secs));
    }

    println!("\nsummary ({:.1} s in all):", total.elapsed().as_secs_f64());
    for (name, passed, secs) in &results {
        let verdict = if *passed { "PASS" } else { "FAIL" };
        println!("  {verdict}  {secs:>7.1} s  {name}");
    }
    let failed = results.iter().filter(|(_, passed, _)| !passed).count();
    if failed > 0 {
        bail!("{failed} of {} CI steps failed", results.len());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readme_shows_the_ci_test_command() {
        let readme = crate::read(&crate::project_root().join("README.md")).unwrap();
        let block = format!("```sh\n{TEST_COMMAND}\n```");
        assert!(
            readme.contains(&block),
            "README.md must show CI's test command as its own block:\n{block}"
        );
    }

    #[test]
    fn readme_main_command_names_a_bundled_file() {
        let readme = crate::read(&crate::project_root().join("README.md")).unwrap();
        let command = readme
            .lines()
            .find(|l| l.starts_with("cargo run --release -p kinetree-cli -- "))
            .expect("README.md shows the main command");
        let file = command.split_whitespace().last().unwrap();
        assert!(
            crate::project_root().join(file).is_file(),
            "{file} does not exist"
        );
    }

    #[test]
    fn every_step_is_named_after_its_command() {
        let names: Vec<_> = steps().into_iter().map(|(n, _)| n).collect();
        assert_eq!(names[4], TEST_COMMAND);
        for (name, action) in steps() {
            if let Action::Cargo(args, env) = action {
                let env: String = env.iter().map(|(k, v)| format!("{k}={v} ")).collect();
                assert_eq!(name, format!("{env}cargo {}", args.join(" ")));
            }
        }
    }
}
