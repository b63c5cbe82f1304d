//! Mesh files: resolving `package://`, `file://`, relative and absolute names through search
//! paths, and reading STL (binary and ASCII) and Wavefront OBJ triangle meshes. The model layer
//! reads them for the masses MJCF infers from meshes; the collision layer for its shapes.
//!
//! The readers are small and dependency-free on purpose: a collision mesh needs vertex positions
//! and triangles only (no normals, colours, materials or texture coordinates), and the two
//! formats take a few dozen lines each, less than the build time of a general mesh crate on CI's
//! two cores.

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

impl TriangleMesh {
    /// The mesh scaled per axis by `scale` (URDF's `<mesh scale>`). A scale with an odd number of
    /// negative factors mirrors the mesh, which would turn its triangles inside out: their winding
    /// is then reversed, so that normals that pointed outward still do (and
    /// [`TriangleMesh::signed_volume`] keeps its sign).
    #[must_use]
    pub fn scaled(&self, scale: DVec3) -> Self {
        let mirrored = scale.x * scale.y * scale.z < 0.0;
        Self {
            vertices: self.vertices.iter().map(|v| *v * scale).collect(),
            triangles: self
                .triangles
                .iter()
                .map(|&[a, b, c]| if mirrored { [a, c, b] } else { [a, b, c] })
                .collect(),
        }
    }

    /// The volume enclosed by the mesh (m³ for a mesh in metres), by the divergence theorem:
    /// positive when the mesh is closed and its triangles are counter-clockwise seen from
    /// outside (outward normals), negative when they are all inside out. Indices out of range
    /// count as the origin.
    #[must_use]
    pub fn signed_volume(&self) -> f64 {
        let vertex = |i: u32| {
            self.vertices
                .get(i as usize)
                .copied()
                .unwrap_or(DVec3::ZERO)
        };
        self.triangles
            .iter()
            .map(|&[a, b, c]| vertex(a).dot(vertex(b).cross(vertex(c))))
            .sum::<f64>()
            / 6.0
    }
}

/// The candidate paths for a mesh name, in the order they are tried.
///
/// - `package://pkg/a/b/x.stl`: for every search path `dir`, `dir/pkg/a/b/x.stl`, then
///   `dir/a/b/x.stl` (the name within the package), then `dir/b/x.stl` (shorter tails that
///   keep at least one directory, longest first). So a search path may be the directory that contains the ROS packages, the
///   package directory itself, or any directory further down the package's tree, as when
///   example-robot-data's `package://example-robot-data/robots/panda_description/…` is found in
///   a directory that holds `panda_description/`.
/// - `file:///abs/path` and absolute paths: that path only.
/// - relative paths: `dir/path` for every search path, in order.
///
/// [`model_search_paths`] adds the model file's own directory, the one rule by which every
/// tool finds the meshes of a model file.
#[must_use]
pub fn candidate_paths(filename: &str, search_paths: &[PathBuf]) -> Vec<PathBuf> {
    if let Some(rest) = filename.strip_prefix("package://") {
        let parts: Vec<&str> = rest.split('/').filter(|p| !p.is_empty()).collect();
        let mut out = Vec::new();
        for dir in search_paths {
            // The whole name, the name within the package, then shorter tails that still
            // keep a directory.
            let tails = parts.len().saturating_sub(1).max(parts.len().min(2));
            for start in 0..tails {
                out.push(parts[start..].iter().fold(dir.clone(), |p, c| p.join(c)));
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

/// The mesh search paths for a model read from `model_file`: the directory that contains the
/// model file first (a relative name in a model file is relative to that file, as in any
/// document), then the user's directories (`extra`, in order).
///
/// This is the one rule by which the CLI's commands (`collide`, `compute`, `bench`, `view`)
/// find meshes: relative names and `package://` names are looked up next to the model file
/// with no flag, so the bundled `tests/data/robots/panda.urdf` finds
/// `tests/data/robots/panda_description/meshes/…`, and a `--mesh-path` directory supplies
/// what is not there.
#[must_use]
pub fn model_search_paths(model_file: &Path, extra: &[PathBuf]) -> Vec<PathBuf> {
    let dir = model_file
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let mut paths = vec![dir];
    for d in extra {
        if !paths.contains(d) {
            paths.push(d.clone());
        }
    }
    paths
}

/// Reads a mesh file, choosing the reader by extension (`.stl`, `.obj`, case-insensitive).
///
/// # Errors
/// A message when the file cannot be read, has another extension, is not valid for its format
/// or has no triangle.
pub fn read_mesh(path: &Path) -> Result<TriangleMesh, String> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let mesh = match ext.as_str() {
        "stl" => parse_stl(&bytes),
        "obj" => parse_obj(&String::from_utf8_lossy(&bytes)),
        "dae" => Err("COLLADA (.dae) meshes are not supported; convert to STL or OBJ".to_string()),
        _ => Err(format!(
            "unsupported mesh format '{ext}' (expected .stl or .obj)"
        )),
    }?;
    if mesh.triangles.is_empty() {
        return Err("the mesh has no triangle".to_string());
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
    fn package_uris_try_every_tail() {
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
            candidate_paths("package://erd/robots/panda/meshes/x.stl", &dirs[..1]),
            [
                "/a/erd/robots/panda/meshes/x.stl",
                "/a/robots/panda/meshes/x.stl",
                "/a/panda/meshes/x.stl",
                "/a/meshes/x.stl"
            ]
            .map(PathBuf::from)
        );
        assert_eq!(
            candidate_paths("package://pkg/x.stl", &dirs[..1]),
            ["/a/pkg/x.stl", "/a/x.stl"].map(PathBuf::from)
        );
        assert_eq!(
            candidate_paths("package://x.stl", &dirs[..1]),
            [PathBuf::from("/a/x.stl")]
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
    fn model_search_paths_start_with_the_model_directory() {
        let extra = [PathBuf::from("/m")];
        assert_eq!(
            model_search_paths(Path::new("/r/robot.urdf"), &extra),
            [PathBuf::from("/r"), PathBuf::from("/m")]
        );
        assert_eq!(
            model_search_paths(Path::new("robot.urdf"), &[]),
            [PathBuf::from(".")]
        );
        assert_eq!(
            model_search_paths(Path::new("/r/robot.urdf"), &[PathBuf::from("/r")]),
            [PathBuf::from("/r")]
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
