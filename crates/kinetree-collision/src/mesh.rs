//! Mesh files for collision shapes: finding them through search paths and reading them.
//!
//! The readers and the path rules live in the model layer ([`kinetree_kinematics::model::mesh`],
//! re-exported here), which needs them too for the masses MJCF infers from meshes; this module
//! adds the collision layer's typed errors.

use crate::error::CollisionError;
pub use kinetree_kinematics::model::mesh::{
    TriangleMesh, candidate_paths, model_search_paths, parse_obj, parse_stl,
};
use std::path::{Path, PathBuf};

/// Finds a mesh file through the search paths (see [`candidate_paths`]).
///
/// # Errors
/// [`CollisionError::MeshNotFound`] listing every path tried; `link` names the link for the
/// message.
pub fn resolve_mesh_path(
    filename: &str,
    search_paths: &[PathBuf],
    link: &str,
) -> Result<PathBuf, CollisionError> {
    let candidates = candidate_paths(filename, search_paths);
    candidates
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .ok_or_else(|| CollisionError::MeshNotFound {
            link: link.to_string(),
            filename: filename.to_string(),
            searched: candidates,
        })
}

/// Reads a mesh file, choosing the reader by extension (`.stl`, `.obj`, case-insensitive).
///
/// # Errors
/// [`CollisionError::MeshParse`] when the file cannot be read, has another extension, is not
/// valid for its format or has no triangle.
pub fn read_mesh_file(path: &Path) -> Result<TriangleMesh, CollisionError> {
    kinetree_kinematics::model::mesh::read_mesh(path).map_err(|reason| CollisionError::MeshParse {
        path: path.to_path_buf(),
        reason,
    })
}
