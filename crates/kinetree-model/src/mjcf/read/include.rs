//! `<include>`: the included documents spliced into the main one, as MuJoCo resolves them.

use super::*;

/// Replaces every `<include file=…/>` below `e` by the children of the included document's root,
/// recursively, as MuJoCo: a file is looked up relative to the main model's folder first, then
/// relative to the including file's; including a file twice is an error.
pub(super) fn expand_includes(
    e: &mut Element,
    files: &mut Files,
    model_dir: &Path,
    included: &mut HashSet<PathBuf>,
    depth: usize,
) -> Res<()> {
    if depth > MAX_XML_DEPTH {
        return fail(
            e,
            format!("elements nested deeper than {MAX_XML_DEPTH} levels"),
        );
    }
    let mut i = 0;
    while i < e.children.len() {
        if e.children[i].name != "include" {
            expand_includes(&mut e.children[i], files, model_dir, included, depth + 1)?;
            i += 1;
            continue;
        }
        let inc = &e.children[i];
        if !inc.children.is_empty() {
            return fail(inc, "an include element cannot have children");
        }
        let Some(name) = inc.attr("file") else {
            return fail(inc, "missing attribute 'file'");
        };
        let including_dir = files
            .paths
            .get(inc.file)
            .cloned()
            .flatten()
            .and_then(|p| p.parent().map(Path::to_path_buf))
            .unwrap_or_else(|| model_dir.to_path_buf());
        let first = model_dir.join(name);
        let path = if first.is_file() {
            first
        } else {
            including_dir.join(name)
        };
        let key = path.canonicalize().unwrap_or_else(|_| path.clone());
        if included.contains(&key) {
            return fail(inc, format!("file '{name}' is already included"));
        }
        if included.len() >= MAX_INCLUDES {
            return fail(inc, format!("more than {MAX_INCLUDES} included files"));
        }
        let text = match read_text(&path) {
            Ok(t) => t,
            Err(message) => return fail(inc, message),
        };
        let index = files.paths.len();
        files.paths.push(Some(path.clone()));
        let mut root = match xml_tree::parse(&text, index) {
            Ok(r) => r,
            Err(x) => {
                return Err(Located {
                    file: index,
                    line: x.line,
                    element: "include".to_string(),
                    message: format!("malformed XML: {}", x.message),
                });
            }
        };
        included.insert(key);
        expand_includes(&mut root, files, model_dir, included, depth + 1)?;
        let children = std::mem::take(&mut root.children);
        e.children.splice(i..=i, children.iter().cloned());
        i += children.len();
    }
    Ok(())
}
