//! `<include>`: models from other files, found through the model search path and spliced in
//! as nested models (or as top-level models of a `<world>`), with include loops refused.

use super::SdfOptions;
use super::read::{Located, NEWEST, Res, Resolved, Version, fail, parse_version};
use crate::error::ModelError;
use crate::xml_tree::{self, Element, MAX_XML_DEPTH};
use std::path::{Path, PathBuf};

/// Upper bound on the number of files one document may include.
const MAX_INCLUDES: usize = 1000;

/// The files of one document: the main file first, then every included file, with their
/// SDFormat versions.
pub(crate) struct Files {
    pub(crate) paths: Vec<Option<PathBuf>>,
    versions: Vec<Version>,
}

impl Files {
    pub(crate) fn new(path: Option<&Path>) -> Self {
        Self {
            paths: vec![path.map(Path::to_path_buf)],
            versions: vec![NEWEST],
        }
    }

    pub(crate) fn set_version(&mut self, file: usize, version: Version) {
        self.versions[file] = version;
    }

    pub(crate) fn version(&self, file: usize) -> Version {
        self.versions.get(file).copied().unwrap_or(NEWEST)
    }

    /// The folder of file `file` (the current folder for a document read from a string).
    pub(crate) fn dir(&self, file: usize) -> PathBuf {
        self.paths
            .get(file)
            .cloned()
            .flatten()
            .and_then(|p| p.parent().map(Path::to_path_buf))
            .map(|p| {
                if p.as_os_str().is_empty() {
                    PathBuf::from(".")
                } else {
                    p
                }
            })
            .unwrap_or_else(|| PathBuf::from("."))
    }

    pub(crate) fn error(&self, l: Located) -> ModelError {
        ModelError::Sdf {
            file: self.paths.get(l.file).cloned().flatten(),
            line: l.line,
            element: l.element,
            message: l.message,
        }
    }
}

fn child<'a>(e: &'a Element, name: &str) -> Option<&'a Element> {
    e.children.iter().find(|c| c.name == name)
}

fn set_attr(e: &mut Element, key: &str, value: &str) {
    match e.attrs.iter_mut().find(|(k, _)| k == key) {
        Some((_, v)) => *v = value.to_string(),
        None => e.attrs.push((key.to_string(), value.to_string())),
    }
}

fn read_text(path: &Path) -> Result<String, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    String::from_utf8(bytes).map_err(|_| format!("{} is not UTF-8 text", path.display()))
}

fn canonical(p: &Path) -> PathBuf {
    p.canonicalize().unwrap_or_else(|_| p.to_path_buf())
}

/// Replaces every `<include>` of a `<model>` or `<world>` below `root` by the model it names.
pub(crate) fn expand_includes(
    root: &mut Element,
    files: &mut Files,
    options: &SdfOptions,
) -> Res<()> {
    let mut stack: Vec<PathBuf> = files.paths[0].iter().map(|p| canonical(p)).collect();
    expand(root, files, options, &mut stack, 0)
}

fn expand(
    e: &mut Element,
    files: &mut Files,
    options: &SdfOptions,
    stack: &mut Vec<PathBuf>,
    depth: usize,
) -> Res<()> {
    if depth > MAX_XML_DEPTH {
        return fail(
            e,
            format!("models nested deeper than {MAX_XML_DEPTH} levels"),
        );
    }
    let container = matches!(e.name.as_str(), "model" | "world");
    for i in 0..e.children.len() {
        if container && e.children[i].name == "include" {
            let model = load_include(&e.children[i], files, options, stack, depth)?;
            e.children[i] = model;
        } else if matches!(e.children[i].name.as_str(), "model" | "world") {
            expand(&mut e.children[i], files, options, stack, depth + 1)?;
        }
    }
    Ok(())
}

/// The SDFormat file of a model folder: the newest `<sdf>` its `model.config` lists, else
/// `model.sdf`.
fn model_file(dir: &Path) -> Result<PathBuf, String> {
    let config = dir.join("model.config");
    if config.is_file() {
        let text = read_text(&config)?;
        let root = xml_tree::parse(&text, 0)
            .map_err(|x| format!("{}: line {}: {}", config.display(), x.line, x.message))?;
        let mut best: Option<(Version, String)> = None;
        for s in root.children.iter().filter(|c| c.name == "sdf") {
            let version = parse_version(s).unwrap_or(NEWEST);
            let name = s.text.trim().to_string();
            if !name.is_empty() && best.as_ref().is_none_or(|(v, _)| version > *v) {
                best = Some((version, name));
            }
        }
        xml_tree::drop_flat(root);
        if let Some((_, name)) = best {
            return Ok(dir.join(name));
        }
    }
    let m = dir.join("model.sdf");
    if m.is_file() {
        Ok(m)
    } else {
        Err(format!(
            "{} has neither a model.config naming an SDFormat file nor a model.sdf",
            dir.display()
        ))
    }
}

fn load_include(
    inc: &Element,
    files: &mut Files,
    options: &SdfOptions,
    stack: &mut Vec<PathBuf>,
    depth: usize,
) -> Res<Element> {
    let Some(uri) = child(inc, "uri").map(|u| u.text.trim()) else {
        return fail(inc, "an <include> needs a <uri>");
    };
    if inc.attr("merge").is_some_and(|m| m == "true" || m == "1") {
        return fail(inc, "merge=\"true\" includes are not supported yet");
    }
    let path = match files.resolve(uri, inc.file, options) {
        Resolved::Found(p) => p,
        Resolved::Missing(p) => {
            return fail(
                inc,
                format!("included model '{uri}' not found ({})", p.display()),
            );
        }
        Resolved::Unresolved => {
            return fail(
                inc,
                format!(
                    "included model '{uri}' not found in the model search path (SdfOptions::search_path, SDF_PATH, GZ_SIM_RESOURCE_PATH, the file's folder)"
                ),
            );
        }
    };
    let file = if path.is_dir() {
        match model_file(&path) {
            Ok(f) => f,
            Err(m) => return fail(inc, m),
        }
    } else {
        path
    };
    let key = canonical(&file);
    if stack.contains(&key) {
        return fail(
            inc,
            format!(
                "include loop: '{uri}' ({}) is already being included",
                file.display()
            ),
        );
    }
    if files.paths.len() > MAX_INCLUDES {
        return fail(inc, format!("more than {MAX_INCLUDES} included files"));
    }
    let text = match read_text(&file) {
        Ok(t) => t,
        Err(m) => return fail(inc, m),
    };
    let index = files.paths.len();
    files.paths.push(Some(file.clone()));
    files.versions.push(NEWEST);
    let root = xml_tree::parse(&text, index).map_err(|x| Located {
        file: index,
        line: x.line,
        element: "include".to_string(),
        message: format!("malformed XML: {}", x.message),
    })?;
    let mut model = if root.name == "sdf" {
        let version = parse_version(&root)?;
        files.set_version(index, version);
        let mut root = root;
        let Some(k) = root.children.iter().position(|c| c.name == "model") else {
            return fail(&root, format!("{} holds no <model>", file.display()));
        };
        let model = root.children.swap_remove(k);
        xml_tree::drop_flat(root);
        model
    } else if root.name == "model" {
        root
    } else {
        return fail(
            &root,
            format!("{} is not an SDFormat model file", file.display()),
        );
    };
    if let Some(name) = child(inc, "name") {
        set_attr(&mut model, "name", name.text.trim());
    }
    for (tag, replace) in [("pose", true), ("static", true), ("plugin", false)] {
        let given: Vec<Element> = inc
            .children
            .iter()
            .filter(|c| c.name == tag)
            .cloned()
            .collect();
        if given.is_empty() {
            continue;
        }
        if replace {
            model.children.retain(|c| c.name != tag);
        }
        model.children.extend(given);
    }
    if let Some(pf) = child(inc, "placement_frame") {
        set_attr(&mut model, "placement_frame", pf.text.trim());
    }
    stack.push(key);
    if let Err(e) = expand(&mut model, files, options, stack, depth + 1) {
        // A tree spliced from many includes can be deep: drop it without recursion.
        xml_tree::drop_flat(model);
        return Err(e);
    }
    stack.pop();
    Ok(model)
}
