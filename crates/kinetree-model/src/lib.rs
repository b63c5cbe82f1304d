//! # kinetree-model
//!
//! The model layer of kinetree: an immutable [`Model`] of links (parts), joints and named
//! frames, validated once by [`ModelBuilder`]. It sits on `kinetree-spatial` and below the
//! kinematics layer; the algorithms above it sweep over [`Model::bodies`], the moving-body tree
//! in which chains of fixed joints are merged.
//!
//! Models come from and go to:
//! - URDF: [`Model::from_urdf_file`], [`Model::from_urdf_str`], [`Model::to_urdf_string`];
//! - kinetree's own JSON schema (parts with metadata, named frames, external datum files, files
//!   in millimetres and degrees): [`Model::from_json_file`], [`Model::from_json_str`],
//!   [`Model::to_json_string`] — see [`json`] for the schema;
//! - yapCAD's chain JSON (`KinematicChain.export_json`), recognised by its shape or read
//!   explicitly with its joint values: [`Model::from_yapcad_file`] (see [`yapcad`]);
//! - MJCF (MuJoCo's XML), compiled as MuJoCo's compiler does (defaults, includes, frames,
//!   inertia from geoms, several joints per body), with the conversions between MuJoCo's
//!   `qpos`/`qvel`/`qacc`/`qfrc` and kinetree's vectors: [`Model::from_mjcf_file`],
//!   [`Model::from_mjcf_str`] — see [`mjcf`];
//! - SDFormat (Gazebo's and Drake's XML), with 1.7+ frame semantics, nested models and
//!   `<include>`s, worlds of several models, free bodies on floating joints:
//!   [`Model::from_sdf_file`], [`Model::from_sdf_str`] — see [`sdf`];
//! - any of these, by extension and content (`<robot>`, `<mujoco>`, `<sdf>`, JSON):
//!   [`Model::from_file`];
//! - Denavit–Hartenberg tables, standard or modified: [`Model::from_dh`] (see [`dh`]);
//! - code: [`ModelBuilder`], and the ready-made models of [`samples`].
//!
//! ```
//! use kinetree_model::{samples, JsonOptions, Model, Units};
//! # fn main() -> Result<(), kinetree_model::ModelError> {
//! let arm = samples::six_axis();
//! assert_eq!((arm.nq(), arm.nv()), (6, 6));
//! let elbow = arm.joint(arm.joint_index("elbow_joint").unwrap());
//! assert_eq!(elbow.axis.to_array(), [0.0, 0.0, 1.0]);
//!
//! // Out in millimetres and degrees, back in SI.
//! let json = arm.to_json_string(&JsonOptions { units: Units::MM_DEG, ..JsonOptions::default() })?;
//! let back = Model::from_json_str(&json, None)?;
//! assert_eq!(arm.first_difference(&back, 1e-12), None);
//! # Ok(())
//! # }
//! ```
//!
//! ## Conventions
//! - SI units inside (m, rad, kg). Degrees and millimetres exist only at the file edges.
//! - `q` has [`Model::nq`] entries and `v`/`a`/`tau` have [`Model::nv`]; each moving joint owns a
//!   contiguous block (see [`JointKind`] for the per-kind layout). Quaternions are x, y, z, w.
//! - A joint's `placement` is the pose of its frame in the parent link's frame at zero
//!   configuration; the child link's frame is the joint frame.
//! - Links and joints are stored depth-first from the root: parents precede children.
//! - A frame's `placement` is its pose in its link's frame (`link_from_frame`).
//! - Roll-pitch-yaw angles are URDF's fixed-axis angles: `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
//!
//! ## Errors
//! Every loader returns [`ModelError`], which names the offending link, joint, frame or file
//! (and gives line and column for malformed XML and JSON); a failed load returns nothing
//! half-built. Problems that real robot files commonly carry and that do not change the model's
//! meaning (slightly impossible inertias, dangling mimic tags) are repaired and listed in
//! [`Model::warnings`]; elements kinetree does not model are listed in [`Model::ignored`].
//!
//! ## Optional cargo features
//! None: URDF (urdf-rs) and JSON (serde) support are always built.
//!
//! ## Modules
//! - `model`: [`Model`] (links, joints, frames, the moving-body tree, `q`/`v` layout);
//!   `builder`: [`ModelBuilder`], which checks a whole tree and reports every problem at once;
//!   `link`, `joint`, `frame`: the items a model is made of; `error`: [`ModelError`] and
//!   [`Issue`]; `compare`: structural comparison of two models.
//! - [`urdf`]: URDF import (`urdf/read.rs`) and export (`urdf/write.rs`).
//! - [`mesh`]: STL and OBJ triangle meshes and the rules that find their files.
//! - [`mjcf`]: MJCF import (`mjcf/read.rs` and `mjcf/read/`: includes, defaults, the body tree, masses, the emitted tree;
//!   `mjcf/inertia.rs`: masses inferred from geoms; `mjcf/orient.rs`: orientation forms) and the
//!   MuJoCo coordinate conversions (`mjcf/mod.rs`); `xml_tree`: the owned, depth-limited XML tree
//!   it reads.
//! - [`sdf`]: SDFormat import (`sdf/read.rs`: models, links, joints and the tree;
//!   `sdf/graph.rs`: the frame graph of poses, `relative_to` and `attached_to`;
//!   `sdf/include.rs`: `<include>`s and the model search path).
//! - [`json`]: kinetree's JSON schema (`json/schema.rs`), import (`json/read.rs`) and export
//!   (`json/write.rs`); [`units`]: the length and angle units of model files.
//! - [`dh`]: Denavit–Hartenberg tables; [`dh_json`]: DH tables as JSON files; [`samples`]:
//!   ready-made models.
//! - `checks` and `topology`: the builder's per-item checks and its tree check (roots,
//!   depth-first order, cycles).
//! - [`yapcad`]: yapCAD `KinematicChain` exports; [`datum`]: external datum frames;
//!   [`state`]: joint values stored in model files.
//! - [`composite`]: composite joints (a product of elementary axis factors, as
//!   trip_kinematics' `Transformation`).

mod builder;
mod checks;
mod compare;
pub mod composite;
pub mod datum;
pub mod dh;
pub mod dh_json;
mod error;
mod frame;
mod joint;
pub mod json;
mod link;
pub mod mesh;
pub mod mjcf;
mod model;
pub mod samples;
pub mod sdf;
pub mod state;
mod topology;
pub mod units;
pub mod urdf;
mod user_joints;
mod xml_tree;
pub use xml_tree::MAX_XML_DEPTH;
pub mod yapcad;

pub use builder::{
    FrameSpec, INERTIA_TOLERANCE, InertiaCheck, JointSpec, ModelBuilder, ORIGIN_FRAME, WORLD_NAMES,
};
pub use error::{Issue, ItemKind, ModelError};
pub use frame::Frame;
pub use joint::{Joint, JointDynamics, JointKind, JointLimits, Mimic, plane_basis};
pub use json::{DatumExport, JSON_SCHEMA_VERSION, JsonOptions};
pub use kinetree_spatial as spatial;
pub use link::{Collision, Geometry, Inertial, Link, LinkMetadata, Visual};
pub use model::{Body, BodyMimic, MimicMode, Model, ROOT_JOINT_NAME, RootJoint};
pub use units::{AngleUnit, LengthUnit, Units};
pub use urdf::LoadOptions;
pub use user_joints::{CompositeJoint, UserJoint};
pub use yapcad::YapcadChain;
