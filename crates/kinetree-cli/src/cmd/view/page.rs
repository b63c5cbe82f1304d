//! The page: three.js and the viewer script, compiled into the binary, and the HTML around
//! them (linked for the server, inlined for `--export`).
//!
//! `assets/three.min.js` is three.js 0.187.0 from the npm package `three` (MIT, licence in
//! `assets/THREE-LICENSE`) with the addons the viewer uses (orbit and transform controls, the
//! STL, OBJ, COLLADA and PLY loaders, CSS2D labels), bundled into one classic script that
//! defines the global `THREE`, because a page opened from `file://` cannot import ES modules
//! from other files. `assets/README.md` says how to rebuild it.

use super::State;
use super::api;
use anyhow::Result;
use kinetree::kinematics::KinematicsData;
use serde_json::{Map, json};
use std::path::Path;

/// three.js and its addons as one script defining `THREE`.
pub(crate) const THREE_JS: &[u8] = include_bytes!("assets/three.min.js");
/// The viewer.
pub(crate) const VIEWER_JS: &[u8] = include_bytes!("assets/viewer.js");
/// The page; `<!--SCRIPTS-->` is replaced by the script tags.
const INDEX_HTML: &str = include_str!("assets/index.html");

/// The page: linked scripts when `inline` is `None` (served), else the given inline scripts.
pub(crate) fn index_html(inline: Option<&str>) -> String {
    let scripts = inline.map_or_else(
        || "<script src=\"/three.js\"></script>\n<script src=\"/viewer.js\"></script>".to_string(),
        str::to_string,
    );
    INDEX_HTML.replace("<!--SCRIPTS-->", &scripts)
}

/// The content type of a served file, by extension.
pub(crate) fn content_type(path: &Path) -> &'static str {
    match path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .as_deref()
    {
        Some("dae") => "model/vnd.collada+xml",
        Some("obj") => "text/plain",
        Some("stl") => "model/stl",
        Some("png") => "image/png",
        Some("jpg" | "jpeg") => "image/jpeg",
        _ => "application/octet-stream",
    }
}

/// One HTML file with three.js, the viewer, the model, its meshes (base64), the poses at the
/// initial configuration, the trajectory and the workspace inlined: it opens from disk.
///
/// # Errors
/// A mesh file that cannot be read, or an initial configuration the model refuses.
pub(crate) fn export_html(state: &State) -> Result<String> {
    let mut meshes = Map::new();
    for (url, file) in &state.mesh_files {
        let bytes = std::fs::read(file)
            .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", file.display()))?;
        meshes.insert(url.clone(), json!(base64(&bytes)));
    }
    let mut data = KinematicsData::new(&state.model);
    let poses = api::poses_json(&state.model, &mut data, &state.initial_q)
        .map_err(|e| anyhow::anyhow!("{}", e.message))?;
    let collide = api::collide(
        &state.model,
        state.collision.as_ref().map_err(String::as_str),
        json!({"q": state.initial_q}).to_string().as_bytes(),
    )
    .map_err(|e| anyhow::anyhow!("{}", e.message))?;
    let embed = json!({
        "model": state.model_json,
        "meshes": meshes,
        "poses": poses,
        "collide": collide,
        "trajectory": state.trajectory,
        "workspace": state.workspace.as_deref().map(base64),
    });
    let embed = script_json(&embed);
    let three = String::from_utf8_lossy(THREE_JS);
    let viewer = String::from_utf8_lossy(VIEWER_JS);
    let scripts = format!(
        "<script>{three}</script>\n<script>window.KINETREE_EMBED = {embed};</script>\n<script>{viewer}</script>"
    );
    Ok(index_html(Some(&scripts)))
}

/// `value` as JSON text that is safe inside an HTML `<script>` element, whatever its strings
/// hold (link and joint names come from the model file): `<`, `>` and `&` (a `</script>` would
/// close the element, and a `<!--<script>` would make the parser swallow the next one) and
/// U+2028 and U+2029 (line ends to older JavaScript) are written as `\u` escapes. JSON has none
/// of these characters outside strings, so the text is still the same JSON.
pub(crate) fn script_json(value: &serde_json::Value) -> String {
    let text = value.to_string();
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            '\u{2028}' => out.push_str("\\u2028"),
            '\u{2029}' => out.push_str("\\u2029"),
            c => out.push(c),
        }
    }
    out
}

/// Standard base64 with padding.
pub(crate) fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> (18 - 6 * i)) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}
