//! # kinetree-collision
//!
//! The collision layer of kinetree: collision shapes from a model's `<collision>` elements,
//! candidate pairs (adjacent bodies and disabled link pairs removed, SRDF import, a sampling
//! tool that proposes pairs to disable), and the queries: any collision, all colliding pairs with
//! contacts, signed distances with witness points, against the robot itself and against world
//! obstacles (added one by one, or read from a JSON [`ObstacleScene`]). It sits on `kinetree-kinematics` (re-exported as [`kinematics`]) and uses
//! [parry3d-f64](parry) for every geometric test.
//!
//! The split follows Pinocchio's `GeometryModel`/`GeometryData`: a [`CollisionModel`] is built
//! once from a [`Model`](kinematics::model::Model); a [`CollisionData`] holds the world poses of
//! the shapes, the obstacles and the query results, and no query allocates once it exists.
//!
//! ```
//! use kinetree_collision::{any_collision, compute_distances, CollisionData, CollisionModel,
//!                          CollisionOptions};
//! use kinetree_collision::kinematics::{configuration, KinematicsData};
//! use kinetree_collision::kinematics::model::{Geometry, Model, RootJoint};
//! use kinetree_collision::kinematics::spatial::Se3;
//! use glam::DVec3;
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let path = concat!(env!("CARGO_MANIFEST_DIR"),
//!                    "/../../tests/data/reference/urdf/panda_collision.urdf");
//! let model = Model::from_urdf_file(path, RootJoint::Fixed)?;
//! let options = CollisionOptions::default();
//! let cmodel = CollisionModel::from_model(&model, &options)?;
//! let mut kinematics = KinematicsData::new(&model);
//! let mut data = CollisionData::new(&cmodel);
//!
//! // A table top 20 cm below the base.
//! let table = data.add_obstacle("table", &Geometry::Box { size: [2.0, 2.0, 0.1] },
//!                               &Se3::from_translation(DVec3::new(0.0, 0.0, -0.25)), &options)?;
//!
//! let mut q = configuration::neutral_configuration(&model);
//! q[3] = -1.5; // bend the elbow (panda_joint4) to unfold the arm
//! data.compute_placements(&model, &cmodel, &mut kinematics, &q)?;
//! let colliding = any_collision(&cmodel, &mut data)?;
//! let closest = compute_distances(&cmodel, &mut data)?
//!     .iter()
//!     .map(|p| p.distance)
//!     .fold(f64::INFINITY, f64::min);
//! println!("colliding: {colliding}, closest pair {closest:.3} m apart");
//! # let _ = table;
//! # Ok(())
//! # }
//! ```
//!
//! ## Conventions
//! - SI units (m); `q` has `model.nq()` entries, as in the kinematics layer.
//! - **Signed distance:** positive = separation distance; negative = penetration depth (the
//!   shortest translation separating the shapes), as coal (Pinocchio's collision library)
//!   reports it. Two spheres, a sphere and a box, cylinder or capsule, two capsules, two
//!   cylinders side to side, parallel cylinders (and a capsule parallel to a cylinder), and
//!   overlapping boxes (or a capsule's segment in a box, by separating axes) are computed in
//!   closed form, so coincident, nested and very long shapes keep their exact depth; other
//!   convex pairs by GJK (separated) and EPA (penetrating) to a relative precision of 1e-8, with
//!   parry's GJK/EPA as the fallback; a triangle mesh against a convex shape triangle by
//!   triangle; two triangle meshes by a traversal of both bounding-volume trees that prunes
//!   with the closest pair found so far (a mesh is a surface: two overlapping meshes report
//!   their deepest crossing triangles).
//! - A closed triangle mesh (every edge shared by two triangles) is a solid for balls and
//!   capsules: a ball's distance is its centre's signed distance to the mesh (negative inside)
//!   less its radius, a capsule's that of its segment's deepest point when the segment reaches
//!   inside ([`is_closed_trimesh`]). Other shapes, and every shape against an open mesh, see the
//!   mesh as a surface.
//! - Witness points and normals ([`Proximity`]) are in the world frame; the normal points from
//!   the first shape toward the second.
//! - URDF shapes: box = full side lengths, cylinder = radius and full length along the
//!   element's z axis, centred on its origin; capsule = radius and cylindrical length along z.
//! - Shapes are named `<link>_<k>`, `k` the index of the `<collision>` element in its link.
//! - Candidate pairs: shapes on different moving bodies (links welded by fixed joints are one
//!   body) whose bodies are not parent and child, minus disabled link pairs: Pinocchio's
//!   `addAllCollisionPairs` followed by removal of adjacent joints.
//! - Poses: kinetree's [`Se3`](kinematics::spatial::Se3) (`world_from_*`) at the API edges where
//!   the model is involved, parry's [`Pose`](parry::math::Pose) for parry shapes;
//!   [`se3_to_pose`] and [`pose_to_se3`] convert.
//!
//! ## Errors
//! [`CollisionError`] names the offending file, link, shape or obstacle; kinematics errors are
//! wrapped. Shapes larger than [`MAX_SHAPE_SIZE`] are refused where they are built. A panic
//! inside parry during a query is caught at the query's boundary and returned as
//! [`CollisionError::Panic`]; the data stays usable.
//!
//! ## Modules
//! - `model`: [`CollisionModel`]; [`build`]: building it from the model's geometry
//!   ([`CollisionOptions`]); [`mesh`]: mesh files; `pairs`: candidate pairs; [`srdf`]: SRDF
//!   disabled pairs; [`sampling`]: proposing pairs to disable.
//! - `data`: [`CollisionData`] (shape poses, obstacles, results); `scene`: [`ObstacleScene`]
//!   files; `pose`: conversions to parry's poses.
//! - [`batch`]: signed distances of `N` configurations in one call ([`batch::CollisionBatch`]).
//! - [`query`]: the queries (`plan`: the candidate pairs grouped by shape kinds for the distance
//!   loops); `narrow`: the narrow phase (closed forms, `primitives`: the pairs of cylinders,
//!   boxes and capsules, `cylinders`: cylinder pairs solved on their closest features, then
//!   `gjk`, the crate's GJK/EPA, then parry).
//! - `error`: [`CollisionError`].
//!
//! ## Optional cargo features
//! None. Meshes are read by the crate's own small STL (binary and ASCII) and OBJ readers
//! ([`mesh`]); COLLADA is not supported.

pub mod batch;
pub mod build;
mod cylinders;
mod data;
mod error;
mod frames;
mod gjk;
pub mod mesh;
mod model;
mod narrow;
mod pairs;
mod plan;
mod pose;
mod primitives;
pub mod query;
pub mod sampling;
mod scene;
pub mod srdf;

pub use build::{
    CollisionOptions, MAX_SHAPE_SIZE, MeshMode, MissingMeshes, is_closed_trimesh,
    shape_from_geometry,
};
pub use data::{CollisionData, LinkPairDistance, Obstacle, ObstacleId, Proximity};
pub use error::CollisionError;
pub use kinetree_kinematics as kinematics;
pub use model::{CollisionModel, CollisionPair, CollisionShape, LinkPair, SkippedMesh};
pub use parry3d_f64 as parry;
pub use pose::{pose_to_se3, se3_to_pose};
pub use query::{
    any_collision, compute_distances, compute_link_pair_distances, compute_self_collisions,
    compute_world_collisions, compute_world_distances,
};
pub use sampling::{DisableReason, PairProposal, PairSampling, propose_disabled_pairs};
pub use scene::{ObstacleScene, SceneObstacle};
