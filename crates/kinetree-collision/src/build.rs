//! Building a [`CollisionModel`] from a model's `<collision>` elements.

use crate::error::CollisionError;
use crate::mesh::{read_mesh_file, resolve_mesh_path};
use crate::model::{CollisionModel, CollisionShape, SkippedMesh};
use crate::pose::se3_to_pose;
use glam::{DQuat, DVec3};
use kinetree_kinematics::model::{Geometry, Model};
use parry3d_f64::math::Pose;
use parry3d_f64::shape::{SharedShape, TriMesh, TriMeshFlags};
use std::path::PathBuf;

/// The largest size (m) of a shape: box sides, radii, lengths, and the coordinates of a scaled
/// mesh's vertices. Larger shapes are rejected where they are built
/// ([`CollisionError::InvalidGeometry`], [`CollisionError::InvalidObstacle`]): the squares of
/// sizes near 1e154 overflow, and parry's EPA panicked on them. A million kilometres leaves
/// room for any obstacle while the distance arithmetic stays far from overflowing.
pub const MAX_SHAPE_SIZE: f64 = 1e9;

/// How mesh geometries become parry shapes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeshMode {
    /// A triangle mesh (parry `TriMesh`, a surface): exact, but two meshes that interpenetrate
    /// report the depth between their surfaces, and one mesh inside another does not collide.
    /// Pinocchio/coal's default.
    #[default]
    TriMesh,
    /// The convex hull of the mesh's vertices (parry `ConvexPolyhedron`): conservative, faster,
    /// and with a true penetration depth.
    ConvexHull,
    /// Leave meshes out (listed in [`CollisionModel::skipped_meshes`]); only primitives
    /// collide, like the reference's `primitives_only` collision mode.
    Ignore,
}

/// What to do with a mesh that cannot be found or parsed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MissingMeshes {
    /// Fail with [`CollisionError::MeshNotFound`] or [`CollisionError::MeshParse`].
    #[default]
    Error,
    /// Leave the element out and list it in [`CollisionModel::skipped_meshes`].
    Skip,
}

/// Options of [`CollisionModel::from_model`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CollisionOptions {
    /// Directories where mesh files are looked up (see [`crate::mesh::candidate_paths`]):
    /// `package://pkg/x.stl` is tried as `dir/pkg/x.stl` and `dir/x.stl`, a relative name as
    /// `dir/name`; absolute paths are used as they are.
    pub mesh_search_paths: Vec<PathBuf>,
    /// Triangle meshes or convex hulls.
    pub mesh_mode: MeshMode,
    /// Error on, or skip, meshes that cannot be loaded.
    pub missing_meshes: MissingMeshes,
    /// Link pairs (by name, either order) that never need testing, e.g. from an SRDF file
    /// ([`crate::srdf::parse_disabled_pairs`]).
    pub disabled_link_pairs: Vec<(String, String)>,
}

impl CollisionOptions {
    /// Adds a directory to the mesh search paths.
    #[must_use]
    pub fn with_mesh_path(mut self, dir: impl Into<PathBuf>) -> Self {
        self.mesh_search_paths.push(dir.into());
        self
    }

    /// Sets the mesh search paths for a model read from `model_file`: the model file's
    /// directory first, then `extra` ([`crate::mesh::model_search_paths`], the rule every tool uses).
    #[must_use]
    pub fn with_model_file(mut self, model_file: &std::path::Path, extra: &[PathBuf]) -> Self {
        self.mesh_search_paths = crate::mesh::model_search_paths(model_file, extra);
        self
    }

    /// Sets the mesh mode.
    #[must_use]
    pub fn with_mesh_mode(mut self, mode: MeshMode) -> Self {
        self.mesh_mode = mode;
        self
    }

    /// Skips meshes that cannot be loaded instead of failing.
    #[must_use]
    pub fn skip_missing_meshes(mut self) -> Self {
        self.missing_meshes = MissingMeshes::Skip;
        self
    }
}

impl CollisionModel {
    /// The collision shapes of every link of `model`, and the candidate pairs.
    ///
    /// Each `<collision>` element becomes one shape named `<link>_<k>` placed at its origin on the
    /// link's moving body: boxes (full side lengths), spheres, cylinders (radius and full length
    /// along the element's z axis, centred), capsules (cylindrical length along z) and meshes
    /// (scaled per axis by any finite non-zero factors, a negative one mirroring the mesh with
    /// its winding reversed, see [`TriangleMesh::scaled`]; STL binary or ASCII, OBJ) as
    /// [`MeshMode`] says. A closed triangle mesh (every edge shared by two triangles, once
    /// identical vertices are merged) is a solid for balls and capsules: a ball whose centre
    /// is inside it penetrates by its radius plus the centre's depth ([`is_closed_trimesh`]).
    ///
    /// [`TriangleMesh::scaled`]: crate::mesh::TriangleMesh::scaled
    ///
    /// Candidate pairs: every pair of shapes whose links are on different moving bodies (links
    /// joined by fixed joints form one body), minus pairs whose bodies are parent and child
    /// through one joint, minus `options.disabled_link_pairs`, as Pinocchio's
    /// `addAllCollisionPairs` followed by removal of adjacent joints (the reference's
    /// `collision_conventions`).
    ///
    /// # Errors
    /// [`CollisionError::MeshNotFound`] / [`CollisionError::MeshParse`] naming the file (unless
    /// `options.missing_meshes` is [`MissingMeshes::Skip`]); [`CollisionError::InvalidGeometry`]
    /// for negative or non-finite sizes, or sizes beyond [`MAX_SHAPE_SIZE`];
    /// [`CollisionError::UnknownLink`] for a disabled pair
    /// naming no link.
    ///
    /// # Examples
    /// ```
    /// use kinetree_collision::{CollisionModel, CollisionOptions};
    /// use kinetree_collision::kinematics::model::{Model, RootJoint};
    /// # fn main() -> Result<(), kinetree_collision::CollisionError> {
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"),
    ///                    "/../../tests/data/reference/urdf/panda_collision.urdf");
    /// let model = Model::from_urdf_file(path, RootJoint::Fixed).map_err(kinetree_collision::kinematics::KinematicsError::from)?;
    /// let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default())?;
    /// assert_eq!(cmodel.shapes().len(), 39);
    /// assert_eq!(cmodel.pairs().len(), 513);
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_model(model: &Model, options: &CollisionOptions) -> Result<Self, CollisionError> {
        let mut shapes = Vec::new();
        let mut skipped = Vec::new();
        for (link_index, link) in model.links().iter().enumerate() {
            let (body, body_from_link) = model.link_body(link_index);
            for (element, collision) in link.collisions.iter().enumerate() {
                let built = match &collision.geometry {
                    Geometry::Mesh { filename, .. } if options.mesh_mode == MeshMode::Ignore => {
                        skipped.push(SkippedMesh {
                            link: link.name.clone(),
                            element,
                            filename: filename.clone(),
                            reason: "meshes ignored".to_string(),
                        });
                        continue;
                    }
                    geometry => shape_from_geometry(geometry, options, &link.name, element),
                };
                let (shape, geometry_from_shape) = match built {
                    Ok(s) => s,
                    Err(
                        e
                        @ (CollisionError::MeshNotFound { .. } | CollisionError::MeshParse { .. }),
                    ) if options.missing_meshes == MissingMeshes::Skip => {
                        let filename = match &collision.geometry {
                            Geometry::Mesh { filename, .. } => filename.clone(),
                            _ => String::new(),
                        };
                        skipped.push(SkippedMesh {
                            link: link.name.clone(),
                            element,
                            filename,
                            reason: e.to_string(),
                        });
                        continue;
                    }
                    Err(e) => return Err(e),
                };
                let body_from_geometry = *body_from_link * collision.origin;
                shapes.push(CollisionShape {
                    name: format!("{}_{element}", link.name),
                    link: link_index,
                    element,
                    body,
                    origin: collision.origin,
                    body_from_shape: se3_to_pose(&body_from_geometry) * geometry_from_shape,
                    geometry: collision.geometry.clone(),
                    kind: crate::narrow::Kind::of(&shape),
                    shape,
                });
            }
        }
        let mut cmodel = CollisionModel {
            shapes,
            pairs: Vec::new(),
            pair_start: Vec::new(),
            link_pairs: Vec::new(),
            skipped,
            // A body attached to the world datum by its own joint (a root part, or the floating
            // root) is not adjacent to the links welded to the world: with several roots those
            // belong to other parts.
            body_parent: model
                .bodies()
                .iter()
                .map(|b| match b.joint {
                    Some(j) if model.joint(j).parent_link.is_none() => usize::MAX,
                    _ => b.parent,
                })
                .collect(),
            disabled: Vec::new(),
            plan: crate::plan::PairPlan::default(),
            distance_tolerance: crate::gjk::DEFAULT_TOL,
        };
        cmodel.rebuild_pairs();
        cmodel.disable_link_pairs(
            model,
            options
                .disabled_link_pairs
                .iter()
                .map(|(a, b)| (a.as_str(), b.as_str())),
        )?;
        Ok(cmodel)
    }
}

/// The parry shape of a geometry and the pose of that shape in the geometry's frame (identity,
/// except a quarter turn about x for cylinders, which parry builds along y).
///
/// Meshes are looked up and loaded as `options` says. `owner` and `element` only name the
/// geometry in errors.
///
/// # Errors
/// [`CollisionError::InvalidGeometry`] for negative or non-finite sizes, sizes (or scaled mesh
/// coordinates) beyond [`MAX_SHAPE_SIZE`], or a degenerate mesh;
/// [`CollisionError::MeshNotFound`] / [`CollisionError::MeshParse`] for meshes.
pub fn shape_from_geometry(
    geometry: &Geometry,
    options: &CollisionOptions,
    owner: &str,
    element: usize,
) -> Result<(SharedShape, Pose), CollisionError> {
    let invalid = |reason: String| CollisionError::InvalidGeometry {
        link: owner.to_string(),
        index: element,
        reason,
    };
    let check = |what: &str, x: f64| {
        if !(x.is_finite() && x >= 0.0) {
            Err(invalid(format!(
                "{what} = {x} must be finite and non-negative"
            )))
        } else if x > MAX_SHAPE_SIZE {
            Err(invalid(format!(
                "{what} = {x} m is larger than {MAX_SHAPE_SIZE} m"
            )))
        } else {
            Ok(x)
        }
    };
    Ok(match geometry {
        Geometry::Box { size } => {
            let [x, y, z] = [
                check("size x", size[0])?,
                check("size y", size[1])?,
                check("size z", size[2])?,
            ];
            (
                SharedShape::cuboid(x / 2.0, y / 2.0, z / 2.0),
                Pose::IDENTITY,
            )
        }
        Geometry::Sphere { radius } => {
            (SharedShape::ball(check("radius", *radius)?), Pose::IDENTITY)
        }
        Geometry::Cylinder { radius, length } => (
            SharedShape::cylinder(check("length", *length)? / 2.0, check("radius", *radius)?),
            Pose::from_rotation(DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2)),
        ),
        Geometry::Capsule { radius, length } => (
            SharedShape::capsule_z(check("length", *length)? / 2.0, check("radius", *radius)?),
            Pose::IDENTITY,
        ),
        Geometry::Mesh { filename, scale } => {
            // Any finite non-zero factor: a negative one mirrors the mesh.
            let factor = |what: &str, x: f64| {
                if x.is_finite() && x != 0.0 {
                    Ok(x)
                } else {
                    Err(invalid(format!("{what} = {x} must be finite and non-zero")))
                }
            };
            let scale = DVec3::new(
                factor("scale x", scale[0])?,
                factor("scale y", scale[1])?,
                factor("scale z", scale[2])?,
            );
            let path = resolve_mesh_path(filename, &options.mesh_search_paths, owner)?;
            let mesh = read_mesh_file(&path)?.scaled(scale);
            let reach = mesh
                .vertices
                .iter()
                .map(|v| v.abs().max_element())
                .fold(0.0, f64::max);
            if reach > MAX_SHAPE_SIZE {
                return Err(invalid(format!(
                    "'{}' scaled reaches {reach} m from its origin, more than {MAX_SHAPE_SIZE} m",
                    path.display()
                )));
            }
            let vertices = mesh.vertices;
            let shape = match options.mesh_mode {
                MeshMode::ConvexHull => SharedShape::convex_hull(&vertices).ok_or_else(|| {
                    invalid(format!(
                        "the convex hull of '{}' is degenerate (flat or empty)",
                        path.display()
                    ))
                })?,
                MeshMode::TriMesh | MeshMode::Ignore => trimesh(vertices, mesh.triangles)
                    .map_err(|e| invalid(format!("'{}': {e}", path.display())))?,
            };
            (shape, Pose::IDENTITY)
        }
    })
}

/// A triangle mesh; a closed one (every edge shared by exactly two triangles that traverse it in
/// opposite directions, once identical vertices are merged) is built oriented outward with
/// parry's pseudo-normals, so that point queries tell inside from outside (see
/// [`is_closed_trimesh`]). Other meshes stay surfaces, built as before.
fn trimesh(
    vertices: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
) -> Result<SharedShape, parry3d_f64::shape::TriMeshBuilderError> {
    let merged = TriMesh::with_flags(
        vertices.clone(),
        triangles.clone(),
        TriMeshFlags::MERGE_DUPLICATE_VERTICES,
    )?;
    let Some(volume) = closed_volume(merged.vertices(), merged.indices()) else {
        return SharedShape::trimesh(vertices, triangles);
    };
    let mut indices = merged.indices().to_vec();
    if volume < 0.0 {
        // Wound inward: turn every triangle so the normals point out.
        for t in &mut indices {
            t.swap(1, 2);
        }
    }
    SharedShape::trimesh_with_flags(merged.vertices().to_vec(), indices, TriMeshFlags::ORIENTED)
}

/// The signed volume of a closed triangle mesh (positive when its triangles are wound
/// counter-clockwise seen from outside), or `None` when the mesh is not closed: some directed
/// edge is used twice, or its reverse is not used exactly once, or a triangle repeats a vertex.
fn closed_volume(vertices: &[DVec3], indices: &[[u32; 3]]) -> Option<f64> {
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(indices.len() * 3);
    let mut volume = 0.0;
    for &[a, b, c] in indices {
        if a == b || b == c || c == a {
            return None;
        }
        edges.extend([(a, b), (b, c), (c, a)]);
        let [pa, pb, pc] = [a, b, c].map(|i| vertices[i as usize]);
        volume += pa.dot(pb.cross(pc)) / 6.0;
    }
    if edges.is_empty() {
        return None;
    }
    edges.sort_unstable();
    if edges.windows(2).any(|w| w[0] == w[1]) {
        return None;
    }
    let closed = edges
        .iter()
        .all(|&(a, b)| edges.binary_search(&(b, a)).is_ok());
    (closed && volume != 0.0).then_some(volume)
}

/// Whether `shape` is a triangle mesh built closed (see [`CollisionModel::from_model`]): its
/// signed distances to a ball count the inside of the mesh as solid.
#[must_use]
pub fn is_closed_trimesh(shape: &SharedShape) -> bool {
    shape
        .as_trimesh()
        .is_some_and(|m| m.pseudo_normals_if_oriented().is_some())
}
