//! What the binary's end-to-end tests share: running `kinetree`, the bundled files, reading what
//! it prints, scratch folders. Each test file includes it with `mod common;`.

#![allow(
    dead_code,
    reason = "each test file uses its own part of these helpers"
)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the binary with `args` and waits for it.
pub(crate) fn kinetree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .args(args)
        .output()
        .expect("the kinetree binary runs")
}

/// The path of `rel` under the repository's `tests/data`.
pub(crate) fn data(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(rel)
        .display()
        .to_string()
}

/// The bundled Panda URDF (with its meshes).
pub(crate) fn panda() -> String {
    data("robots/panda.urdf")
}

/// What the binary printed on stdout.
pub(crate) fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// What the binary printed on stderr.
pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A clean refusal: exit code 1, no panic, and stderr containing every `needle`.
#[track_caller]
pub(crate) fn refused(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(1), "stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "expected '{n}' in: {err}");
    }
}

/// The line of `text` that starts (after indentation) with `first_word`, split into words.
pub(crate) fn row<'a>(text: &'a str, first_word: &str) -> Vec<&'a str> {
    text.lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .find(|w| w.first() == Some(&first_word))
        .unwrap_or_else(|| panic!("no line starting with {first_word} in:\n{text}"))
}

/// The part of the report from the line starting with `header` to the next blank line.
pub(crate) fn section<'a>(text: &'a str, header: &str) -> &'a str {
    let start = text
        .find(&format!("\n{header}"))
        .unwrap_or_else(|| panic!("no section {header} in:\n{text}"));
    let rest = &text[start + 1..];
    rest.find("\n\n").map_or(rest, |end| &rest[..end])
}

/// A scratch folder for this test process, removed by the caller.
pub(crate) fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kinetree-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every number of a JSON value (nested arrays flattened).
pub(crate) fn flat(value: &serde_json::Value) -> Vec<f64> {
    match value {
        serde_json::Value::Array(a) => a.iter().flat_map(flat).collect(),
        v => vec![v.as_f64().unwrap_or(f64::NAN)],
    }
}
