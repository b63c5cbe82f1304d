//! Mesh files: resolving `package://`, `file://`, relative and absolute names through search
//! paths, and reading STL (binary and ASCII) and Wavefront OBJ triangle meshes.
//!
//! The readers are small and dependency-free on purpose: a collision mesh needs vertex positions
//! and triangles only (no normals, colours, materials or texture coordinates), and the two
//! formats take a few dozen lines each, less than the build time of a general mesh crate on CI's
//! two cores.

use crate::error::CollisionError;
use glam::DVec3;
use std::path::{Path, PathBuf};

/// A triangle mesh as read from a file: vertex positions (in the file's units, before any
/// scale) and triangles as vertex indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub vertices: Vec<DVec3>,
    /// Triangles, counter-clockwise seen from outside when the file is well oriented.
    pub triangles: Vec<[u32; 3]>,
}

/// The candidate paths for a mesh name, in the order they are tried.
///
/// - `package://pkg/rel/path`: for every search path `dir`, `dir/pkg/rel/path` then
///   `dir/rel/path` (so a search path may be the directory that contains the ROS packages or the
///   package directory itself).
/// - `file:///abs/path` and absolute paths: that path only.
/// - relative paths: `dir/path` for every search path, in order.
#[must_use]
pub fn candidate_paths(filename: &str, search_paths: &[PathBuf]) -> Vec<PathBuf> {
    if let Some(rest) = filename.strip_prefix("package://") {
        let mut out = Vec::new();
        let within_package = rest.split_once('/').map(|(_, r)| r);
        for dir in search_paths {
            out.push(dir.join(rest));
            if let Some(r) = within_package {
                out.push(dir.join(r));
            }
        }
        return out;
    }
    let plain = filename.strip_prefix("file://").unwrap_or(filename);
    let path = Path::new(plain);
    if path.is_absolute() {
        return vec![path.to_path_buf()];
    }
    search_paths.iter().map(|d| d.join(path)).collect()
}

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
    let parse_error = |reason: String| CollisionError::MeshParse {
        path: path.to_path_buf(),
        reason,
    };
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let bytes = std::fs::read(path).map_err(|e| parse_error(e.to_string()))?;
    let mesh = match ext.as_str() {
        "stl" => parse_stl(&bytes),
        "obj" => parse_obj(&String::from_utf8_lossy(&bytes)),
        "dae" => Err("COLLADA (.dae) meshes are not supported; convert to STL or OBJ".to_string()),
        _ => Err(format!(
            "unsupported mesh format '{ext}' (expected .stl or .obj)"
        )),
    }
    .map_err(parse_error)?;
    if mesh.triangles.is_empty() {
        return Err(parse_error("the mesh has no triangle".to_string()));
    }
    Ok(mesh)
}

/// Parses an STL file, binary or ASCII.
///
/// A file is binary when its size is exactly `84 + 50·n` bytes for the triangle count `n` stored
/// at byte 80 (binary files may also begin with `solid`, so the header alone does not decide).
/// Vertices are shared between triangles only when bit-identical.
///
/// # Errors
/// A message saying what is wrong (truncated file, bad number, non-finite coordinate).
pub fn parse_stl(bytes: &[u8]) -> Result<TriangleMesh, String> {
    let is_binary = bytes.len() >= 84 && {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        n.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len())
    };
    let mut builder = MeshBuilder::default();
    if is_binary {
        for tri in bytes[84..].chunks_exact(50) {
            let mut corners = [0u32; 3];
            for (k, corner) in corners.iter_mut().enumerate() {
                let at = 12 + 12 * k;
                let f = |i: usize| {
                    let o = at + 4 * i;
                    f64::from(f32::from_le_bytes([
                        tri[o],
                        tri[o + 1],
                        tri[o + 2],
                        tri[o + 3],
                    ]))
                };
                *corner = builder.vertex(DVec3::new(f(0), f(1), f(2)))?;
            }
            builder.triangles.push(corners);
        }
    } else {
        let text = std::str::from_utf8(bytes).map_err(|_| {
            "neither a binary STL (size does not match its triangle count) nor ASCII text"
                .to_string()
        })?;
        if !text.trim_start().starts_with("solid") {
            return Err("an ASCII STL file must begin with 'solid'".to_string());
        }
        let mut corners = Vec::with_capacity(3);
        for (line_no, line) in text.lines().enumerate() {
            let mut words = line.split_whitespace();
            match words.next() {
                Some("vertex") => {
                    let mut c = [0.0; 3];
                    for x in &mut c {
                        *x = words
                            .next()
                            .and_then(|w| w.parse::<f64>().ok())
                            .ok_or_else(|| format!("line {}: bad vertex", line_no + 1))?;
                    }
                    corners.push(builder.vertex(DVec3::from_array(c))?);
                }
                Some("endloop") => {
                    if corners.len() != 3 {
                        return Err(format!(
                            "line {}: a facet has {} vertices, expected 3",
                            line_no + 1,
                            corners.len()
                        ));
                    }
                    builder.triangles.push([corners[0], corners[1], corners[2]]);
                    corners.clear();
                }
                _ => {}
            }
        }
    }
    Ok(builder.finish())
}

/// Parses the vertices (`v`) and faces (`f`) of a Wavefront OBJ file; polygons are split into
/// triangle fans, `v/vt/vn` forms and negative (relative) indices are accepted, everything else
/// is ignored.
///
/// # Errors
/// A message naming the line of a bad number or an out-of-range index.
pub fn parse_obj(text: &str) -> Result<TriangleMesh, String> {
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    let mut face = Vec::new();
    for (line_no, line) in text.lines().enumerate() {
        let bad = |what: &str| format!("line {}: {what}", line_no + 1);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut c = [0.0; 3];
                for x in &mut c {
                    *x = words
                        .next()
                        .and_then(|w| w.parse::<f64>().ok())
                        .ok_or_else(|| bad("bad vertex"))?;
                }
                if !c.iter().all(|x| x.is_finite()) {
                    return Err(bad("non-finite vertex"));
                }
                vertices.push(DVec3::from_array(c));
            }
            Some("f") => {
                face.clear();
                for w in words {
                    let index: i64 = w
                        .split('/')
                        .next()
                        .and_then(|i| i.parse().ok())
                        .ok_or_else(|| bad("bad face index"))?;
                    let n = vertices.len() as i64;
                    let resolved = if index > 0 { index - 1 } else { n + index };
                    if index == 0 || resolved < 0 || resolved >= n {
                        return Err(bad("face index out of range"));
                    }
                    face.push(u32::try_from(resolved).map_err(|_| bad("too many vertices"))?);
                }
                if face.len() < 3 {
                    return Err(bad("a face needs at least 3 vertices"));
                }
                for k in 1..face.len() - 1 {
                    triangles.push([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(TriangleMesh {
        vertices,
        triangles,
    })
}

/// Collects STL corners, merging bit-identical vertices.
#[derive(Default)]
struct MeshBuilder {
    vertices: Vec<DVec3>,
    index: std::collections::HashMap<[u64; 3], u32>,
    triangles: Vec<[u32; 3]>,
}

impl MeshBuilder {
    fn vertex(&mut self, p: DVec3) -> Result<u32, String> {
        if !p.is_finite() {
            return Err("non-finite vertex coordinate".to_string());
        }
        // +0.0 and -0.0 are the same point.
        let key = (p + DVec3::ZERO).to_array().map(f64::to_bits);
        if let Some(&i) = self.index.get(&key) {
            return Ok(i);
        }
        let i = u32::try_from(self.vertices.len()).map_err(|_| "too many vertices".to_string())?;
        self.vertices.push(p);
        self.index.insert(key, i);
        Ok(i)
    }

    fn finish(self) -> TriangleMesh {
        TriangleMesh {
            vertices: self.vertices,
            triangles: self.triangles,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn package_uris_try_both_layouts() {
        let dirs = [PathBuf::from("/a"), PathBuf::from("/b/pkg")];
        let c = candidate_paths("package://pkg/meshes/x.stl", &dirs);
        assert_eq!(
            c,
            [
                "/a/pkg/meshes/x.stl",
                "/a/meshes/x.stl",
                "/b/pkg/pkg/meshes/x.stl",
                "/b/pkg/meshes/x.stl"
            ]
            .map(PathBuf::from)
        );
        assert_eq!(
            candidate_paths("file:///m/x.obj", &dirs),
            [PathBuf::from("/m/x.obj")]
        );
        assert_eq!(
            candidate_paths("m/x.obj", &dirs),
            [PathBuf::from("/a/m/x.obj"), PathBuf::from("/b/pkg/m/x.obj")]
        );
    }

    #[test]
    fn obj_faces_are_fanned_and_relative_indices_resolved() {
        let m = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1/1/1 2//1 3 4\nf -4 -3 -1\n")
            .unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 1, 3]]);
        assert!(parse_obj("v 0 0 0\nf 1 2 3\n").is_err());
    }

    #[test]
    fn stl_errors_are_messages() {
        assert!(parse_stl(b"garbage").is_err());
        assert!(
            parse_stl(
                b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n"
            )
            .is_err()
        );
    }
}
