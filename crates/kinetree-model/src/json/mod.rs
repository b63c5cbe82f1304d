//! JSON import and export in kinetree's own schema, with units converted at the edge.
//!
//! # Schema
//!
//! A model file is one JSON object. Every field except the names of links, joints and frames is
//! optional (the model's own `name` too, as in a URDF `<robot>` or a DH table); unknown fields are
//! an error, so a typo never goes unnoticed.
//!
//! ```json
//! {
//!   "version": 1,
//!   "name": "arm",
//!   "units": { "length": "mm", "angle": "deg" },
//!   "root_joint": "fixed",
//!   "gravity": [0, 0, -9.81],
//!   "links": [
//!     { "name": "base" },
//!     { "name": "upper",
//!       "inertial": { "origin": { "xyz": [150, 0, 0] }, "mass": 1.2,
//!                     "inertia": { "ixx": 300, "iyy": 9000, "izz": 9000 } },
//!       "visuals": [ { "origin": { "xyz": [150, 0, 0], "rpy": [0, 90, 0] },
//!                      "geometry": { "type": "cylinder", "radius": 20, "length": 300 },
//!                      "material": "PETG", "color": [0.9, 0.5, 0.1] } ],
//!       "collisions": [ { "geometry": { "type": "mesh", "filename": "package://arm/upper.stl" } } ],
//!       "metadata": { "description": "upper arm", "material": "PETG", "mesh": "stl/upper.stl",
//!                     "printable": true } }
//!   ],
//!   "joints": [
//!     { "name": "shoulder", "type": "revolute", "parent": "base", "child": "upper",
//!       "origin": { "xyz": [0, 0, 100] }, "axis": [0, 0, 1],
//!       "limits": { "lower": -90, "upper": 90, "velocity": 180, "effort": 20 },
//!       "dynamics": { "damping": 0.1 }, "position": 30 }
//!   ],
//!   "frames": [
//!     { "name": "tip", "link": "upper", "origin": { "xyz": [300, 0, 0] }, "description": "tool point" },
//!     { "name": "horn", "link": "upper", "datum": { "file": "servo.json", "name": "output_shaft" } }
//!   ]
//! }
//! ```
//!
//! - `version`: the schema version, 1 (written on export).
//! - `name`: the model's name, empty when left out.
//! - `units`: `length` is `"m"` (default), `"cm"` or `"mm"`; `angle` is `"rad"` (default) or
//!   `"deg"`. Values are converted to SI on load and back on export. Lengths are: translations
//!   of every origin, centres of mass, geometry sizes, prismatic limits, velocities and
//!   positions; rotational inertias are in kg·length². Angles are: `rpy`, revolute, continuous and
//!   spherical limits, velocities and positions. Masses, efforts, damping, friction, armature,
//!   gravity and mesh scales are always SI (kg, N or N·m, m/s²) or unitless. Cylindrical, planar
//!   and floating joints mix lengths and angles in one limit value, so non-zero finite limits on
//!   them cannot be converted: with non-SI units they are an error.
//! - `root_joint`: `"fixed"` (default) or `"floating"`. A root given to the loader overrides it.
//! - `gravity`: in m/s², default `[0, 0, -9.81]`.
//! - `links` (also accepted as `parts`): `name`; `inertial` (`origin` of the centre-of-mass
//!   frame, `mass`, `inertia` about the centre of mass in that frame: `ixx`, `ixy`, `ixz`, `iyy`,
//!   `iyz`, `izz`, each defaulting to 0); no `inertial` means massless. `visuals` (`name`,
//!   `origin`, `geometry`, `material`, `color`) and `collisions` (`name`, `origin`, `geometry`).
//!   A `geometry` is `{"type": "box", "size": [x, y, z]}`, `{"type": "cylinder", "radius",
//!   "length"}` (along z), `{"type": "sphere", "radius"}`, `{"type": "capsule", "radius",
//!   "length"}` or `{"type": "mesh", "filename", "scale": [1, 1, 1]}` (file names are kept as
//!   written). `metadata`: `description`, `material`, `color`, `mesh`, `printable`. Colours are
//!   RGB or RGBA in [0, 1]. `world_pose` is written on export when the caller supplies world
//!   poses and ignored on import.
//! - `joints`: `name`, `type` (`fixed`, `revolute`, `continuous`, `prismatic`, `cylindrical`,
//!   `spherical`, `planar`, `floating`), `parent` and `child` link names, `parent_frame` (a frame
//!   of the parent link that `origin` is relative to), `origin` (joint frame in the parent at
//!   zero configuration), `axis` (default `[0, 0, 1]`), `limits` (`lower`, `upper`, `velocity`,
//!   `effort`; a missing bound is unlimited), `dynamics` (`damping`, `friction`, `armature`,
//!   default 0), `mimic` (`joint`, `multiplier` default 1, `offset` default 0), and `position`,
//!   the joint's current value (a number, or an array for multi-DoF joints, in the file's units),
//!   which is informational: it is accepted on import but not stored in the model.
//! - A joint of `"type": "composite"` ([`crate::composite`]) has `name`, `parent`, `child`,
//!   `parent_frame`, `origin`, `position` (its state variables' values) and `factors` instead of
//!   `axis`, `limits`, `dynamics` and `mimic`: a list applied in order, each `{"param": P}` (a
//!   state variable, optionally with `limits`) or `{"param": P, "value": x}` (a constant), where
//!   `P` is `tx`, `ty`, `tz` (lengths), `rx`, `ry`, `rz` (angles) or `quat` (a quaternion state,
//!   or a constant `[x, y, z, w]`). Export writes it back the same way, and leaves out its
//!   virtual links.
//! - `frames`: named frames on links: `name`, `link`, `description`, and either `origin` or
//!   `datum: {"file", "name"}`, which reads the pose from a datum file (a path relative to the
//!   model file's directory; relative to the current directory when loading from a string).
//!
//! An `origin` is `{"xyz": [x, y, z], "rpy": [roll, pitch, yaw]}` (URDF's fixed-axis
//! roll-pitch-yaw; either part may be left out), `{"xyz": [..], "quat": [x, y, z, w]}` or
//! `{"matrix": [[..], [..], [..], [0, 0, 0, 1]]}` (4x4, row-major; a rotation block within
//! 1e-4 of orthonormal is re-orthonormalized). Missing means the identity. Export always writes
//! `xyz` and `rpy`.
//!
//! A datum file holds named poses, in its own units:
//!
//! ```json
//! { "units": { "length": "mm", "angle": "deg" },
//!   "datums": { "output_shaft": { "xyz": [0, 0, 12.5], "rpy": [0, 0, 90] } } }
//! ```
//!
//! A missing datum file or datum is an error ([`ModelError::Datum`]), never an identity pose.

mod composite;
pub(crate) mod read;
mod schema;
#[cfg(test)]
mod tests;
mod write;

pub use crate::units::{AngleUnit, LengthUnit, Units};
use read::from_json;
use write::to_json;

use crate::error::ModelError;
use crate::model::{Model, RootJoint};
use kinetree_spatial::Se3;
use std::path::Path;

/// The schema version written by [`Model::to_json_string`] and accepted on import.
pub const JSON_SCHEMA_VERSION: u32 = 1;

/// How [`Model::to_json_string`] writes frames that were read from a datum file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DatumExport {
    /// Write the `datum` reference (`file`, `name`) as read: the exported file needs the datum
    /// file beside it, at the same relative path.
    #[default]
    Reference,
    /// Write the resolved pose as an `origin` and drop the reference: the file stands alone.
    Inline,
}

/// Options of [`Model::to_json_string`].
///
/// # Examples
/// ```
/// use kinetree_model::{samples, JsonOptions, Units};
/// # fn main() -> Result<(), kinetree_model::ModelError> {
/// let json = samples::planar_2r(0.3, 0.2)
///     .to_json_string(&JsonOptions { units: Units::MM_DEG, ..JsonOptions::default() })?;
/// assert!(json.contains("\"length\": \"mm\""));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct JsonOptions<'a> {
    /// Units to write lengths and angles in (default SI).
    pub units: Units,
    /// World pose of every link, in link order (length `model.links().len()`), computed by the
    /// caller (forward kinematics lives in the layer above). When given, every link gets a
    /// `world_pose` entry.
    pub world_poses: Option<&'a [Se3]>,
    /// A configuration `q` (length `model.nq()`): when given, every moving joint (except the
    /// floating root joint) gets its block of `q` as its `position`.
    pub positions: Option<&'a [f64]>,
    /// How to write frames read from datum files.
    pub datums: DatumExport,
}

impl Model {
    /// Loads a model from JSON text in kinetree's schema (see the [module docs](crate::json)).
    ///
    /// `root` overrides the file's `root_joint` when given; `None` uses the file's value, or
    /// [`RootJoint::Fixed`] when the file has none. Datum files are looked up relative to the
    /// current directory.
    ///
    /// # Errors
    /// [`ModelError::Json`] for malformed JSON, unknown fields, wrong types or array lengths (with
    /// line and column) and origins that are not rigid transforms (naming the item);
    /// [`ModelError::UnknownUnit`] for an unknown unit name; [`ModelError::Datum`] when a datum
    /// file or a datum in it is missing or malformed; [`ModelError::Invalid`] when the model is not
    /// a valid tree.
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::{Model, RootJoint};
    /// # fn main() -> Result<(), kinetree_model::ModelError> {
    /// let json = r#"{
    ///   "name": "slider",
    ///   "units": { "length": "mm", "angle": "deg" },
    ///   "links": [ { "name": "rail" }, { "name": "carriage", "inertial": { "mass": 0.5 } } ],
    ///   "joints": [ { "name": "x", "type": "prismatic", "parent": "rail", "child": "carriage",
    ///                 "axis": [1, 0, 0], "limits": { "lower": 0, "upper": 250 } } ]
    /// }"#;
    /// let model = Model::from_json_str(json, None)?;
    /// assert_eq!(model.root_joint(), RootJoint::Fixed);
    /// let x = model.joint(model.joint_index("x").unwrap());
    /// assert_eq!(x.limits.upper, 0.25); // metres inside
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_json_str(
        json: &str,
        root: impl Into<Option<RootJoint>>,
    ) -> Result<Model, ModelError> {
        from_json(json, root.into(), None)
    }

    /// Loads a JSON model file; datum files are looked up relative to its directory.
    ///
    /// `root` overrides the file's `root_joint` when given (see [`Model::from_json_str`]).
    ///
    /// # Errors
    /// [`ModelError::Io`] when the file cannot be read, otherwise as [`Model::from_json_str`],
    /// with the file named.
    pub fn from_json_file(
        path: impl AsRef<Path>,
        root: impl Into<Option<RootJoint>>,
    ) -> Result<Model, ModelError> {
        let path = path.as_ref();
        let text = read_file(path)?;
        from_json(&text, root.into(), Some(path))
    }

    /// Loads a model file of any format kinetree reads: `.json` files as JSON (kinetree's schema,
    /// a yapCAD chain or a DH table, by their content); XML files (any extension) by their root
    /// element: `<robot>` as URDF, `<mujoco>` as MJCF, `<sdf>` as SDFormat; anything else by its
    /// first non-blank character, `<` or `{`.
    ///
    /// `root`: for URDF, `None` means [`RootJoint::Fixed`]; for JSON, `None` keeps the file's own
    /// `root_joint` and a value overrides it. MJCF files say themselves how bodies attach to the
    /// world (free joints), so `root` must be `None` or [`RootJoint::Fixed`] for them. For
    /// SDFormat, `root` says what attaches the trees no joint attaches to the world
    /// ([`SdfOptions::free_trees`](crate::sdf::SdfOptions::free_trees)): `None` keeps SDFormat's
    /// meaning (floating).
    ///
    /// # Errors
    /// [`ModelError::UnknownFormat`] when the format cannot be told, [`ModelError::Unsupported`]
    /// for a floating root asked of an MJCF file, otherwise as [`Model::from_urdf_file`],
    /// [`Model::from_json_file`], [`Model::from_mjcf_file`] or [`Model::from_sdf_file`].
    pub fn from_file(
        path: impl AsRef<Path>,
        root: impl Into<Option<RootJoint>>,
    ) -> Result<Model, ModelError> {
        let path = path.as_ref();
        let root = root.into();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if ext.as_deref() == Some("json") {
            return Model::from_json_file(path, root);
        }
        let text = read_file(path)?;
        match text.trim_start().chars().next() {
            Some('<') if crate::xml_tree::root_name(&text).as_deref() == Some("mujoco") => {
                if root == Some(RootJoint::Floating) {
                    return Err(ModelError::Unsupported {
                        format: "MJCF",
                        what: "a floating root joint: an MJCF body floats by its own <freejoint>"
                            .to_string(),
                    });
                }
                crate::mjcf::from_mjcf(&text, Some(path))
            }
            Some('<') if crate::xml_tree::root_name(&text).as_deref() == Some("sdf") => {
                crate::sdf::from_sdf_root(&text, path, root)
            }
            Some('<') => crate::urdf::from_urdf(
                &text,
                &crate::urdf::LoadOptions::from(root.unwrap_or_default()),
                Some(path.into()),
            ),
            Some('{') => from_json(&text, root, Some(path)),
            _ => Err(ModelError::UnknownFormat {
                path: path.to_path_buf(),
            }),
        }
    }

    /// Writes the model as JSON in kinetree's schema (see the [module docs](crate::json)),
    /// pretty-printed, in the units of `options` (the file declares them).
    ///
    /// The floating root joint is written as `"root_joint": "floating"`, not as a joint; a part
    /// attached to the world datum by its own joint is written with the parent `"world"`. A
    /// joint attached through a `parent_frame` keeps it, with its origin relative to that frame.
    ///
    /// # Errors
    /// [`ModelError::Length`] when `world_poses` or `positions` have the wrong length;
    /// [`ModelError::Json`] naming the joint when non-SI units are asked for and a cylindrical,
    /// planar or floating joint has finite non-zero limits (they mix lengths and angles).
    pub fn to_json_string(&self, options: &JsonOptions<'_>) -> Result<String, ModelError> {
        to_json(self, options)
    }
}

pub(crate) fn read_file(path: &Path) -> Result<String, ModelError> {
    crate::error::read_text(path)
}

/// A JSON error without a position (a schema rule that serde cannot express).
fn schema_error(file: Option<&Path>, message: String) -> ModelError {
    ModelError::Json {
        file: file.map(Path::to_path_buf),
        line: 0,
        column: 0,
        message,
    }
}

/// A serde_json error's line, column and message (without serde_json's location suffix).
fn json_location(e: &serde_json::Error) -> (usize, usize, String) {
    let (line, column) = (e.line(), e.column());
    let full = e.to_string();
    let suffix = format!(" at line {line} column {column}");
    let message = full.strip_suffix(&suffix).unwrap_or(&full).to_string();
    (line, column, message)
}

/// Converts a serde_json error, keeping its line and column apart from the message.
fn json_error(e: &serde_json::Error, file: Option<&Path>) -> ModelError {
    let (line, column, message) = json_location(e);
    ModelError::Json {
        file: file.map(Path::to_path_buf),
        line,
        column,
        message,
    }
}
