//! The commands, one module each, and what they share: loading a model from a path.

pub(crate) mod inspect;

use anyhow::{Context, Result, bail};
use kinetree::model::{Model, RootJoint};
use std::path::Path;

/// Loads a URDF or JSON model, choosing the format by the file extension.
///
/// # Errors
/// The loader's error, with context naming the file.
pub(crate) fn load_model(path: &Path, root: RootJoint) -> Result<Model> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let model = match ext.as_deref() {
        Some("urdf") => Model::from_urdf_file(path, root),
        _ => bail!(
            "cannot load {}: unknown model format (expected a .urdf file)",
            path.display()
        ),
    };
    model.with_context(|| format!("cannot load {}", path.display()))
}

/// The root attachment chosen by a `--floating` flag.
pub(crate) fn root_joint(floating: bool) -> RootJoint {
    if floating {
        RootJoint::Floating
    } else {
        RootJoint::Fixed
    }
}
