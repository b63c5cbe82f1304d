//! The commands, one module each, and what they share: loading a model from a path.

pub(crate) mod bench;
pub(crate) mod compute;
pub(crate) mod convert;
pub(crate) mod inspect;
pub(crate) mod workspace;

use anyhow::{Context, Result};
use kinetree::model::{Model, RootJoint};
use std::path::Path;

/// Loads a URDF or JSON model with [`Model::from_file`]: `.urdf`/`.xml` are URDF, `.json` is
/// JSON, and any other file is told by its first character.
///
/// `root`: `None` welds a URDF's root to the world and keeps a JSON file's own `root_joint`.
///
/// # Errors
/// The loader's error, with context naming the file.
pub(crate) fn load_model(path: &Path, root: impl Into<Option<RootJoint>>) -> Result<Model> {
    Model::from_file(path, root).with_context(|| format!("cannot load {}", path.display()))
}

/// The root attachment asked for by a `--floating` flag: `None` leaves it to the file.
pub(crate) fn root_joint(floating: bool) -> Option<RootJoint> {
    floating.then_some(RootJoint::Floating)
}
