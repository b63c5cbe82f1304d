//! `cargo xtask layers`: the layer check.
//!
//! Each crate under `crates/` may depend (in `[dependencies]` and `[build-dependencies]`, target
//! tables included) on exactly one kinetree crate, the layer directly below it:
//!
//! ```text
//! kinetree-spatial ← kinetree-model ← kinetree-kinematics ← { kinetree-dynamics, kinetree-collision,
//!                                                             kinetree-workspace }
//! kinetree-cli, kinetree-py → kinetree (the facade) only
//! ```
//!
//! Dev-dependencies are exempt from the layer rule (a test may use a higher layer). Every internal
//! dependency, in every table of every manifest, must be a workspace dependency
//! (`kinetree-x.workspace = true`), and each internal entry of `[workspace.dependencies]` must have
//! both a `path` and a `version` (so that the crates can be published), except
//! `kinetree-test-support` (`publish = false`): it has a path and no version, so that publishing
//! strips it, and may only be a dev-dependency.
//!
//! The manifests are read with a small line parser rather than a TOML crate: it only needs section
//! headers, dependency names and the `workspace`/`path`/`version` keys, and it keeps xtask's
//! dependency tree (and CI's build time) small.

use anyhow::{Result, bail};
use std::fmt;
use std::path::Path;

/// The kinetree crates each crate under `crates/` may depend on; a new crate must be added here.
const ALLOWED: &[(&str, &[&str])] = &[
    ("kinetree-spatial", &[]),
    ("kinetree-model", &["kinetree-spatial"]),
    ("kinetree-kinematics", &["kinetree-model"]),
    ("kinetree-dynamics", &["kinetree-kinematics"]),
    ("kinetree-collision", &["kinetree-kinematics"]),
    ("kinetree-workspace", &["kinetree-kinematics"]),
    (TEST_SUPPORT, &["kinetree-kinematics"]),
    ("kinetree-cli", &["kinetree"]),
    ("kinetree-py", &["kinetree"]),
];

/// The unpublished crate of test helpers: a dev-dependency only, without a version.
const TEST_SUPPORT: &str = "kinetree-test-support";

/// Runs the check on the workspace and prints what it found.
pub(crate) fn run(args: &[String]) -> Result<()> {
    crate::no_args("layers", args)?;
    let problems = check_workspace(&crate::project_root())?;
    if problems.is_empty() {
        println!("layers: every crate depends only on the layer below it");
        return Ok(());
    }
    for p in &problems {
        eprintln!("{p}");
    }
    bail!("{} layer problem(s)", problems.len())
}

/// Checks every manifest of the workspace rooted at `root` and returns the problems found.
pub(crate) fn check_workspace(root: &Path) -> Result<Vec<String>> {
    let mut problems = Vec::new();
    let root_manifest = root.join("Cargo.toml");
    let root_text = crate::read(&root_manifest)?;
    problems.extend(check_workspace_table(&parse(&root_text), "Cargo.toml"));
    // The root package (the facade) may use any layer, but through workspace dependencies.
    problems.extend(check_manifest("Cargo.toml", &root_text, None));

    let mut crates: Vec<_> = std::fs::read_dir(root.join("crates"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("Cargo.toml").is_file())
        .collect();
    crates.sort();
    if crates.is_empty() {
        bail!("no crates found under {}", root.join("crates").display());
    }
    for dir in crates {
        let manifest = dir.join("Cargo.toml");
        let shown = manifest
            .strip_prefix(root)
            .unwrap_or(&manifest)
            .display()
            .to_string();
        let text = crate::read(&manifest)?;
        let name = parse(&text).package_name.unwrap_or_default();
        let Some(allowed) = ALLOWED.iter().find(|(n, _)| *n == name).map(|(_, a)| *a) else {
            problems.push(format!(
                "{shown}: crate '{name}' is not in the layer table: add it to ALLOWED in xtask/src/layers.rs"
            ));
            continue;
        };
        problems.extend(check_manifest(&shown, &text, Some(allowed)));
    }
    let xtask = root.join("xtask/Cargo.toml");
    if xtask.is_file() {
        problems.extend(check_manifest(
            "xtask/Cargo.toml",
            &crate::read(&xtask)?,
            None,
        ));
    }
    Ok(problems)
}

/// Checks one member manifest: internal deps are workspace deps and, when `allowed` is given,
/// normal and build dependencies stay within it.
fn check_manifest(shown: &str, text: &str, allowed: Option<&[&str]>) -> Vec<String> {
    let manifest = parse(text);
    let mut problems = Vec::new();
    for dep in manifest.deps.iter().filter(|d| is_internal(&d.name)) {
        if dep.table != Table::Workspace && !dep.workspace {
            problems.push(format!(
                "{shown}:{}: {} on '{}' must be `{}.workspace = true` (internal crates are workspace dependencies)",
                dep.line, dep.table, dep.name, dep.name
            ));
        }
        if dep.name == TEST_SUPPORT && matches!(dep.table, Table::Normal | Table::Build) {
            problems.push(format!(
                "{shown}:{}: {TEST_SUPPORT} is not published: it may only be a dev-dependency",
                dep.line
            ));
        }
        if let Some(allowed) = allowed
            && matches!(dep.table, Table::Normal | Table::Build)
            && !allowed.contains(&dep.name.as_str())
        {
            let pkg = manifest.package_name.as_deref().unwrap_or("?");
            let may = if allowed.is_empty() {
                "no kinetree crate".to_string()
            } else {
                allowed.join(", ")
            };
            problems.push(format!(
                "{shown}:{}: {pkg} depends on {} in {}, but may depend only on {may} (the layer directly below)",
                dep.line, dep.name, dep.table
            ));
        }
    }
    problems
}

/// Checks that every internal entry of `[workspace.dependencies]` has a path and a version.
fn check_workspace_table(manifest: &Manifest, shown: &str) -> Vec<String> {
    manifest
        .deps
        .iter()
        .filter(|d| d.table == Table::Workspace && is_internal(&d.name))
        .filter_map(|d| {
            if d.name == TEST_SUPPORT {
                return (!d.path || d.version).then(|| {
                    format!(
                        "{shown}:{}: [workspace.dependencies] {} needs a `path` and no `version` (it is not published)",
                        d.line, d.name
                    )
                });
            }
            (!(d.path && d.version)).then(|| {
                format!(
                    "{shown}:{}: [workspace.dependencies] {} needs both `path` and `version`",
                    d.line, d.name
                )
            })
        })
        .collect()
}

fn is_internal(name: &str) -> bool {
    name == "kinetree" || name.starts_with("kinetree-")
}

/// Which dependency table an entry is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Table {
    Normal,
    Dev,
    Build,
    Workspace,
}

impl fmt::Display for Table {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Normal => "[dependencies]",
            Self::Dev => "[dev-dependencies]",
            Self::Build => "[build-dependencies]",
            Self::Workspace => "[workspace.dependencies]",
        })
    }
}

/// One dependency entry and the keys that matter here.
#[derive(Clone, Debug, PartialEq)]
struct Dep {
    name: String,
    table: Table,
    /// 1-based line of the entry (or of its `[table.name]` header).
    line: usize,
    workspace: bool,
    path: bool,
    version: bool,
}

/// What the layer check reads from a manifest.
#[derive(Debug, Default)]
struct Manifest {
    package_name: Option<String>,
    deps: Vec<Dep>,
}

/// Where the parser is.
enum Section {
    Package,
    /// A dependency table: `[dependencies]`, `[target.'cfg(..)'.dev-dependencies]`, ….
    Deps(Table),
    /// A single dependency as a table: `[dependencies.name]`; the index into `deps`.
    Dep(usize),
    Other,
}

/// Parses the parts of a manifest the layer check needs (TOML subset: section headers, one
/// `key = value` per line, inline tables on one line).
fn parse(text: &str) -> Manifest {
    let mut m = Manifest::default();
    let mut section = Section::Other;
    for (i, raw) in text.lines().enumerate() {
        let line = strip_comment(raw).trim();
        if line.is_empty() {
            continue;
        }
        if line.starts_with('[') {
            let header = line.trim_matches(|c| c == '[' || c == ']').trim();
            section = section_of(header, i + 1, &mut m.deps);
            continue;
        }
        let Some((key, value)) = split_key_value(line) else {
            continue;
        };
        match section {
            Section::Package if key == "name" => m.package_name = Some(unquote(value)),
            Section::Deps(table) => {
                // `name = "1"`, `name = { … }`, or dotted `name.workspace = true`.
                let (name, sub) = match key.split_once('.') {
                    Some((n, s)) => (n.trim(), Some(s.trim())),
                    None => (key, None),
                };
                let mut dep = Dep {
                    name: unquote(name),
                    table,
                    line: i + 1,
                    workspace: false,
                    path: false,
                    version: false,
                };
                match sub {
                    Some(sub) => set_key(&mut dep, sub, value),
                    None if value.starts_with('{') => {
                        for (k, v) in inline_table(value) {
                            set_key(&mut dep, &k, &v);
                        }
                    }
                    None => dep.version = true,
                }
                // Dotted keys may spread one dependency over several lines.
                match m
                    .deps
                    .iter_mut()
                    .find(|d| d.name == dep.name && d.table == table)
                {
                    Some(d) if sub.is_some() => {
                        d.workspace |= dep.workspace;
                        d.path |= dep.path;
                        d.version |= dep.version;
                    }
                    _ => m.deps.push(dep),
                }
            }
            Section::Dep(idx) => {
                let mut dep = m.deps[idx].clone();
                set_key(&mut dep, key, value);
                m.deps[idx] = dep;
            }
            _ => {}
        }
    }
    m
}

fn section_of(header: &str, line: usize, deps: &mut Vec<Dep>) -> Section {
    if header == "package" {
        return Section::Package;
    }
    let parts = split_dotted(header);
    let kind = |s: &str| match s {
        "dependencies" => Some(Table::Normal),
        "dev-dependencies" | "dev_dependencies" => Some(Table::Dev),
        "build-dependencies" | "build_dependencies" => Some(Table::Build),
        _ => None,
    };
    // Strip a leading `target.<cfg>` and map `workspace.dependencies` to its own table.
    let rest: &[String] = match parts.as_slice() {
        [t, _, rest @ ..] if t == "target" => rest,
        _ => &parts,
    };
    let table_and_name = match rest {
        [w, d, name @ ..] if w == "workspace" && d == "dependencies" => {
            Some((Table::Workspace, name.first()))
        }
        [d, name @ ..] => kind(d).map(|t| (t, name.first())),
        [] => None,
    };
    match table_and_name {
        Some((table, None)) => Section::Deps(table),
        Some((table, Some(name))) => {
            deps.push(Dep {
                name: name.clone(),
                table,
                line,
                workspace: false,
                path: false,
                version: false,
            });
            Section::Dep(deps.len() - 1)
        }
        None => Section::Other,
    }
}

fn set_key(dep: &mut Dep, key: &str, value: &str) {
    match key.trim() {
        "workspace" => dep.workspace = value.trim() == "true",
        "path" => dep.path = true,
        "version" => dep.version = true,
        _ => {}
    }
}

/// Splits `key = value` at the first `=` outside quotes.
fn split_key_value(line: &str) -> Option<(&str, &str)> {
    let mut quote = None;
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '=') => return Some((line[..i].trim(), line[i + 1..].trim())),
            _ => {}
        }
    }
    None
}

/// The top-level `key = value` pairs of a one-line inline table `{ a = 1, b = [x, y] }`.
fn inline_table(value: &str) -> Vec<(String, String)> {
    let inner = value.trim().trim_start_matches('{').trim_end_matches('}');
    let mut pairs = Vec::new();
    let (mut depth, mut quote, mut start) = (0i32, None, 0);
    let mut push = |s: &str| {
        if let Some((k, v)) = split_key_value(s) {
            pairs.push((k.to_string(), v.to_string()));
        }
    };
    for (i, c) in inner.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '[' | '{') => depth += 1,
            (None, ']' | '}') => depth -= 1,
            (None, ',') if depth == 0 => {
                push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    push(&inner[start..]);
    pairs
}

/// Splits a dotted header (`target.'cfg(unix)'.dependencies`) at dots outside quotes.
fn split_dotted(header: &str) -> Vec<String> {
    let mut parts = vec![String::new()];
    let mut quote = None;
    for c in header.chars() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '.') => parts.push(String::new()),
            _ => parts.last_mut().expect("parts is never empty").push(c),
        }
    }
    parts.into_iter().map(|p| p.trim().to_string()).collect()
}

fn strip_comment(line: &str) -> &str {
    let mut quote = None;
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '#') => return &line[..i],
            _ => {}
        }
    }
    line
}

fn unquote(s: &str) -> String {
    s.trim().trim_matches(|c| c == '"' || c == '\'').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workspace_respects_the_layers() {
        let problems = check_workspace(&crate::project_root()).unwrap();
        assert_eq!(problems, Vec::<String>::new());
    }

    #[test]
    fn parser_reads_every_dependency_form() {
        let m = parse(
            r#"
[package]
name = "kinetree-dynamics" # trailing comment
[dependencies]
kinetree-kinematics.workspace = true
glam = { workspace = true, features = ["std", "f64"] }
serde = "1"
[dev-dependencies]
kinetree-model = { path = "../kinetree-model", version = "0.1.0" }
[target.'cfg(unix)'.build-dependencies.kinetree-spatial]
path = "../kinetree-spatial"
"#,
        );
        assert_eq!(m.package_name.as_deref(), Some("kinetree-dynamics"));
        let got: Vec<_> = m
            .deps
            .iter()
            .map(|d| {
                (
                    d.name.as_str(),
                    d.table,
                    d.line,
                    d.workspace,
                    d.path,
                    d.version,
                )
            })
            .collect();
        assert_eq!(
            got,
            [
                ("kinetree-kinematics", Table::Normal, 5, true, false, false),
                ("glam", Table::Normal, 6, true, false, false),
                ("serde", Table::Normal, 7, false, false, true),
                ("kinetree-model", Table::Dev, 9, false, true, true),
                ("kinetree-spatial", Table::Build, 10, false, true, false),
            ]
        );
    }

    #[test]
    fn skipping_a_layer_is_reported() {
        let text = "[package]\nname = \"kinetree-dynamics\"\n[dependencies]\n\
                    kinetree-kinematics.workspace = true\nkinetree-spatial.workspace = true\n";
        let problems = check_manifest("d/Cargo.toml", text, Some(&["kinetree-kinematics"]));
        assert_eq!(
            problems,
            [
                "d/Cargo.toml:5: kinetree-dynamics depends on kinetree-spatial in [dependencies], \
              but may depend only on kinetree-kinematics (the layer directly below)"
            ]
        );
    }

    #[test]
    fn depending_upwards_and_path_deps_are_reported() {
        let text = "[package]\nname = \"kinetree-spatial\"\n[dependencies]\n\
                    kinetree-model = { path = \"../kinetree-model\" }\n\
                    [dev-dependencies]\nkinetree-kinematics.workspace = true\n";
        let problems = check_manifest("s/Cargo.toml", text, Some(&[]));
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(problems[0].contains("must be `kinetree-model.workspace = true`"));
        assert!(problems[1].contains("may depend only on no kinetree crate"));
    }

    #[test]
    fn workspace_entries_need_path_and_version() {
        let m = parse(
            "[workspace.dependencies]\nkinetree-model = { path = \"crates/kinetree-model\" }\n\
             kinetree-spatial = { path = \"crates/kinetree-spatial\", version = \"0.1.0\" }\n\
             glam = \"0.33\"\n",
        );
        assert_eq!(
            check_workspace_table(&m, "Cargo.toml"),
            [
                "Cargo.toml:2: [workspace.dependencies] kinetree-model needs both `path` and `version`"
            ]
        );
    }

    #[test]
    fn test_support_is_a_versionless_dev_dependency_only() {
        let m = parse(
            "[workspace.dependencies]\nkinetree-test-support = { path = \"crates/kinetree-test-support\", version = \"0.1.0\" }\n",
        );
        assert_eq!(
            check_workspace_table(&m, "Cargo.toml"),
            [
                "Cargo.toml:2: [workspace.dependencies] kinetree-test-support needs a `path` and no `version` (it is not published)"
            ]
        );
        let text = "[package]\nname = \"kinetree-dynamics\"\n[dependencies]\n\
                    kinetree-test-support.workspace = true\n\
                    [dev-dependencies]\nkinetree-test-support.workspace = true\n";
        let problems = check_manifest("d/Cargo.toml", text, Some(&["kinetree-kinematics"]));
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(problems[0].contains("may only be a dev-dependency"));
        assert!(problems[1].contains("may depend only on kinetree-kinematics"));
    }
}
