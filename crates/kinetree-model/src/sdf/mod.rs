//! SDFormat import: [`Model::from_sdf_file`], [`Model::from_sdf_str`], and [`load_sdf_file`] /
//! [`load_sdf_str`] with [`SdfOptions`] and the initial configuration.
//!
//! ## What is read
//!
//! - One `<model>`, or a `<world>` with one or more models (and its `<gravity>`); nested
//!   `<model>`s and `<include>`s of other models (`model://name` looked up in
//!   [`SdfOptions::search_path`], `SDF_PATH`, `GZ_SIM_RESOURCE_PATH`, then the including file's
//!   folder; a folder's `model.config` names its file, else `model.sdf`), with `<name>`,
//!   `<pose>`, `<static>` and `<placement_frame>` overrides; an include loop is an error.
//! - Poses with SDFormat 1.7+ frame semantics: `<pose relative_to=…>` naming the model frame
//!   (`__model__`), a link, a joint, a `<frame>`, a nested model or a path through nested models
//!   (`arm::link`); defaults as the specification says (a link's pose is in the model frame, a
//!   joint's in its child link's frame, a frame's in its `attached_to` frame, a model's in its
//!   parent model's); `rotation_format="quat_xyzw"` and `degrees="true"`; `placement_frame`.
//!   SDFormat ≤ 1.6 files are read with the same defaults (`<pose frame=…>` taken as
//!   `relative_to`), and their joint axes in the joint frame unless `use_parent_model_frame`
//!   (or in the model frame before 1.5). Pose-graph cycles are errors.
//! - `<link>` with `<inertial>` (`<pose>`, `<mass>`, `<inertia>`; a link without one has mass 1
//!   and identity inertia, as libsdformat and Drake give it), `<visual>` and `<collision>`
//!   geometry (box, cylinder, sphere, capsule, mesh with `<uri>` and `<scale>`).
//! - `<joint>` of type `revolute` (continuous when it has no finite limit), `continuous`,
//!   `prismatic`, `fixed`, `ball`, and `universal`/`revolute2` as a composite joint (two
//!   rotations about perpendicular axes, pieces `NAME.rx`, `NAME.ry`; see [`crate::composite`]);
//!   `<parent>` may be `world`; `<axis><xyz expressed_in=…>`, `<limit>` (bounds at ±1e16 are
//!   infinite; `effort`/`velocity` of −1 are unlimited) and `<dynamics>` damping and friction
//!   (kept as [`JointDynamics`](crate::JointDynamics), off in the dynamics by default, as for
//!   URDF), and SDFormat 1.11's `<mimic>` as a [`Mimic`](crate::Mimic) (its `reference`
//!   folded into the offset; independent by default, as URDF mimics). `screw` and `gearbox` joints are refused with an error naming them: kinetree has no
//!   joint coupling a translation to a rotation, and approximating one would be wrong.
//! - `<frame>`s as named frames of the link they are attached to.
//! - `<static>` models: every link welded to the world where the file puts it.
//!
//! What kinetree does not model is counted in [`Model::ignored`]: plugins, sensors, lights,
//! materials, ellipsoid and plane geometry, Gazebo-specific and unknown elements (converted
//! files carry many, so an unknown element in a model, link or joint is a note, not an error),
//! joint springs, and mesh URIs that the search path does not resolve (kept as written).
//!
//! ## The tree
//!
//! Links and joints keep their names; with several models in a `<world>` they get a `model::`
//! prefix, and nested models' items a `nested::` prefix. A tree of links that no joint attaches
//! to the world (a free body, or a converted URDF) gets a floating joint named after its root
//! link, with the identity placement, so its `q` block is the root link's pose in the world
//! (`[x, y, z, qx, qy, qz, qw]`); the file's pose is the initial configuration that
//! [`load_sdf_file`] returns ([`SdfModel::q0`]), as Drake starts such a body where the file
//! puts it. [`SdfOptions::free_trees`] = [`RootJoint::Fixed`] welds them there instead (the
//! `--floating` choice of URDF files). A joint whose frame is not its child link's frame (a
//! joint `<pose>`, or a link posed elsewhere) hangs from a massless link `JOINT:frame`, and a
//! fixed joint `JOINT:child` carries the child link, so link frames stay where the file puts
//! them; fixed joints cost nothing in the dynamics.
//!
//! ```
//! use kinetree_model::Model;
//! use kinetree_model::sdf::{SdfOptions, load_sdf_str};
//! # fn main() -> Result<(), kinetree_model::ModelError> {
//! let sdf = r#"<sdf version="1.9">
//!   <model name="pendulum">
//!     <pose>0 0 2 0 0 0</pose>
//!     <link name="base"/>
//!     <link name="bob">
//!       <pose relative_to="hinge">0 0 -1 0 0 0</pose>
//!       <inertial><mass>2</mass></inertial>
//!     </link>
//!     <joint name="hinge" type="revolute">
//!       <pose relative_to="base">0 0 0.5 0 0 0</pose>
//!       <parent>base</parent><child>bob</child>
//!       <axis><xyz>0 1 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis>
//!     </joint>
//!   </model>
//! </sdf>"#;
//! // `base` is attached to nothing: a floating joint named `base` carries the tree.
//! let loaded = load_sdf_str(sdf, &SdfOptions::default())?;
//! let model = &loaded.model;
//! assert_eq!((model.nq(), model.nv()), (8, 7));
//! assert!(model.joint_index("base").is_some());
//! // It starts where the file puts it: 2 m up.
//! assert_eq!(&loaded.q0[..3], &[0.0, 0.0, 2.0]);
//! // The bob's frame is 1 m below the hinge's, so the hinge carries it through `hinge:frame`.
//! assert!(model.link_index("hinge:frame").is_some());
//! # let _ = Model::from_sdf_str(sdf)?;
//! # Ok(())
//! # }
//! ```

mod graph;
mod include;
mod read;

use crate::error::ModelError;
use crate::model::{Model, RootJoint};
use std::path::{Path, PathBuf};

/// How an SDFormat file is loaded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SdfOptions {
    /// What attaches a tree of links that no joint attaches to the world:
    /// [`RootJoint::Floating`] (the default, SDFormat's meaning: a floating joint named after
    /// its root link) or [`RootJoint::Fixed`] (welded to the world where the file puts it).
    pub free_trees: RootJoint,
    /// Folders searched first for `model://` URIs (includes and meshes), before `SDF_PATH`,
    /// `GZ_SIM_RESOURCE_PATH` and the referring file's folder.
    pub search_path: Vec<PathBuf>,
}

impl Default for SdfOptions {
    fn default() -> Self {
        Self {
            free_trees: RootJoint::Floating,
            search_path: Vec::new(),
        }
    }
}

/// A loaded SDFormat file: the model and the configuration the file describes.
#[derive(Clone, Debug, PartialEq)]
pub struct SdfModel {
    /// The model.
    pub model: Model,
    /// The initial configuration (length `model.nq()`): every joint at 0, every floating joint
    /// at its root link's pose in the file.
    pub q0: Vec<f64>,
}

/// Loads an SDFormat file with `options`: the model and its initial configuration.
///
/// # Errors
/// As [`Model::from_sdf_file`].
pub fn load_sdf_file(path: impl AsRef<Path>, options: &SdfOptions) -> Result<SdfModel, ModelError> {
    let path = path.as_ref();
    let text = crate::error::read_text(path)?;
    let loaded = read::from_sdf(&text, Some(path), options)?;
    Ok(SdfModel {
        model: loaded.model,
        q0: loaded.q0,
    })
}

/// Loads an SDFormat document from a string with `options`; relative URIs are resolved from
/// the current folder.
///
/// # Errors
/// As [`Model::from_sdf_file`].
pub fn load_sdf_str(text: &str, options: &SdfOptions) -> Result<SdfModel, ModelError> {
    let loaded = read::from_sdf(text, None, options)?;
    Ok(SdfModel {
        model: loaded.model,
        q0: loaded.q0,
    })
}

impl Model {
    /// Loads an SDFormat file (`<sdf>` with a `<model>` or a `<world>`); free trees get
    /// floating joints. See [`crate::sdf`] for what is read and how items are named, and
    /// [`load_sdf_file`] for options and the initial configuration.
    ///
    /// # Errors
    /// [`ModelError::Io`]/[`ModelError::Encoding`] when the file cannot be read as text,
    /// [`ModelError::Xml`] for malformed XML, [`ModelError::Sdf`] naming the file, line and
    /// element for a malformed or unsupported document (unknown frame names, pose or joint
    /// cycles, include loops, missing files, absurd numbers, screw joints),
    /// [`ModelError::Invalid`] when the tree fails the builder's checks.
    pub fn from_sdf_file(path: impl AsRef<Path>) -> Result<Model, ModelError> {
        Ok(load_sdf_file(path, &SdfOptions::default())?.model)
    }

    /// Loads an SDFormat document from a string; free trees get floating joints.
    ///
    /// # Errors
    /// As [`Model::from_sdf_file`].
    pub fn from_sdf_str(text: &str) -> Result<Model, ModelError> {
        Ok(load_sdf_str(text, &SdfOptions::default())?.model)
    }
}

pub(crate) fn from_sdf_root(
    text: &str,
    path: &Path,
    root: Option<RootJoint>,
) -> Result<Model, ModelError> {
    let options = SdfOptions {
        free_trees: root.unwrap_or(RootJoint::Floating),
        ..SdfOptions::default()
    };
    Ok(read::from_sdf(text, Some(path), &options)?.model)
}
