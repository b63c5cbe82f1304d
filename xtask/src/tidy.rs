//! `cargo xtask tidy`: source rules that neither rustc nor clippy enforce.
//!
//! - No `should_panic` test attribute: assert on the returned `Err` instead (no panics on user
//!   input).
//! - No `ignore` test attribute: a test that cannot pass asserts today's behaviour with a FIXME.

use anyhow::{Result, bail};
use std::path::{Path, PathBuf};

/// The attributes tidy rejects, built with `concat!` so this file does not trip its own check.
const FORBIDDEN: &[(&str, &str)] = &[
    (
        concat!("#[", "should_panic"),
        "assert on the returned Err instead",
    ),
    (
        concat!("#[", "ignore"),
        "assert today's behaviour and add a FIXME instead",
    ),
];

/// Folders of the workspace that hold no source of ours.
const SKIP: &[&str] = &["target", ".git", ".venv", "node_modules"];

/// Runs the checks on the workspace and prints every offence.
pub(crate) fn run(args: &[String]) -> Result<()> {
    crate::no_args("tidy", args)?;
    let root = crate::project_root();
    let offences = check_tree(&root)?;
    if offences.is_empty() {
        println!("tidy: no forbidden test attributes");
        return Ok(());
    }
    for o in &offences {
        eprintln!("{o}");
    }
    bail!("{} tidy offence(s)", offences.len())
}

/// Every offence in the `.rs` files under `root`, as `path:line: message`.
pub(crate) fn check_tree(root: &Path) -> Result<Vec<String>> {
    let mut files = Vec::new();
    rust_files(root, &mut files)?;
    files.sort();
    let mut offences = Vec::new();
    for file in files {
        let text = crate::read(&file)?;
        let shown = file
            .strip_prefix(root)
            .unwrap_or(&file)
            .display()
            .to_string();
        offences.extend(check_source(&shown, &text));
    }
    Ok(offences)
}

/// The offences in one source file.
fn check_source(shown: &str, text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        // Spaces are allowed inside attributes, so they are squeezed out before matching.
        let squeezed: String = line.chars().filter(|c| !c.is_whitespace()).collect();
        for (needle, advice) in FORBIDDEN {
            if squeezed.contains(needle) {
                out.push(format!(
                    "{shown}:{}: `{needle}]` is not allowed: {advice}",
                    i + 1
                ));
            }
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if path.is_dir() {
            if !SKIP.contains(&name) {
                rust_files(&path, out)?;
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tree_is_tidy() {
        let offences = check_tree(&crate::project_root()).unwrap();
        assert_eq!(offences, Vec::<String>::new());
    }

    #[test]
    fn forbidden_attributes_are_found_with_their_line() {
        let src = format!(
            "#[test]\n{}]\nfn a() {{}}\n#[test]\n# [ {} = \"slow\"]\nfn b() {{}}\n",
            FORBIDDEN[0].0, "ignore"
        );
        let found = check_source("x.rs", &src);
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(found[0].starts_with("x.rs:2: "), "{}", found[0]);
        assert!(found[1].starts_with("x.rs:5: "), "{}", found[1]);
        // Words that merely contain the names are fine.
        assert!(check_source("y.rs", "let ignore_case = true; // should_panic").is_empty());
    }
}
