//! JSON import and export in kinetree's own schema, with units converted at the edge.
//!
//! # Schema
//!
//! A model file is one JSON object. Every field except the names is optional; unknown fields are
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

use crate::builder::{FrameSpec, JointSpec, ModelBuilder};
use crate::error::ModelError;
use crate::joint::{JointDynamics, JointKind, JointLimits, Mimic};
use crate::link::{Collision, Geometry, Inertial, Link, LinkMetadata, Visual};
use crate::model::{Model, RootJoint};
use glam::{DMat3, DQuat, DVec3};
use kinetree_spatial::{Se3, Symmetric3, rotation};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// The schema version written by [`Model::to_json_string`] and accepted on import.
pub const JSON_SCHEMA_VERSION: u32 = 1;

/// A length unit of a JSON file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LengthUnit {
    /// Metres (`"m"`), the SI unit.
    #[default]
    Meter,
    /// Centimetres (`"cm"`).
    Centimeter,
    /// Millimetres (`"mm"`), common in CAD exports.
    Millimeter,
}

impl LengthUnit {
    const KNOWN: &'static str = "m, cm, mm";

    /// The unit's name in files (`"m"`, `"cm"`, `"mm"`).
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Meter => "m",
            Self::Centimeter => "cm",
            Self::Millimeter => "mm",
        }
    }

    /// Parses a unit name (`"m"`, `"cm"`, `"mm"`).
    ///
    /// # Errors
    /// [`ModelError::UnknownUnit`] for any other name.
    pub fn from_name(name: &str) -> Result<Self, ModelError> {
        match name {
            "m" => Ok(Self::Meter),
            "cm" => Ok(Self::Centimeter),
            "mm" => Ok(Self::Millimeter),
            _ => Err(ModelError::UnknownUnit {
                quantity: "length",
                unit: name.to_string(),
                known: Self::KNOWN,
            }),
        }
    }

    /// How many of this unit make one metre (1, 100 or 1000).
    #[must_use]
    pub const fn per_meter(self) -> f64 {
        match self {
            Self::Meter => 1.0,
            Self::Centimeter => 100.0,
            Self::Millimeter => 1000.0,
        }
    }

    fn to_si(self, x: f64) -> f64 {
        x / self.per_meter()
    }

    fn si_to_unit(self, x: f64) -> f64 {
        x * self.per_meter()
    }
}

/// An angle unit of a JSON file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AngleUnit {
    /// Radians (`"rad"`), the SI unit.
    #[default]
    Radian,
    /// Degrees (`"deg"`).
    Degree,
}

impl AngleUnit {
    const KNOWN: &'static str = "rad, deg";

    /// The unit's name in files (`"rad"`, `"deg"`).
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Radian => "rad",
            Self::Degree => "deg",
        }
    }

    /// Parses a unit name (`"rad"`, `"deg"`).
    ///
    /// # Errors
    /// [`ModelError::UnknownUnit`] for any other name.
    pub fn from_name(name: &str) -> Result<Self, ModelError> {
        match name {
            "rad" => Ok(Self::Radian),
            "deg" => Ok(Self::Degree),
            _ => Err(ModelError::UnknownUnit {
                quantity: "angle",
                unit: name.to_string(),
                known: Self::KNOWN,
            }),
        }
    }

    fn to_si(self, x: f64) -> f64 {
        match self {
            Self::Radian => x,
            Self::Degree => x.to_radians(),
        }
    }

    fn si_to_unit(self, x: f64) -> f64 {
        match self {
            Self::Radian => x,
            Self::Degree => x.to_degrees(),
        }
    }
}

/// The length and angle units of a JSON file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Units {
    /// Unit of lengths.
    pub length: LengthUnit,
    /// Unit of angles.
    pub angle: AngleUnit,
}

impl Units {
    /// Metres and radians.
    pub const SI: Self = Self {
        length: LengthUnit::Meter,
        angle: AngleUnit::Radian,
    };

    /// Millimetres and degrees, as CAD tools (yapCAD among them) write.
    pub const MM_DEG: Self = Self {
        length: LengthUnit::Millimeter,
        angle: AngleUnit::Degree,
    };

    fn is_si(self) -> bool {
        self == Self::SI
    }
}

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

// ---------------------------------------------------------------------------------------------
// The file schema. The same types are read and written, so an exported file always loads.

/// Deserializes a JSON array of exactly `N` numbers, naming `field` when the length is wrong.
fn fixed<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
    field: &str,
) -> Result<[f64; N], D::Error> {
    let v = Vec::<f64>::deserialize(d)?;
    <[f64; N]>::try_from(v.as_slice()).map_err(|_| {
        D::Error::custom(format!(
            "`{field}` must have {N} numbers, found {}",
            v.len()
        ))
    })
}

macro_rules! named_arrays {
    ($($fn:ident: $name:literal [$n:literal]),* $(,)?) => {$(
        fn $fn<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; $n]>, D::Error> {
            fixed::<D, $n>(d, $name).map(Some)
        }
    )*};
}

named_arrays! {
    de_xyz: "xyz" [3],
    de_rpy: "rpy" [3],
    de_quat: "quat" [4],
    de_axis: "axis" [3],
    de_gravity: "gravity" [3],
}

fn de_size<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    fixed::<D, 3>(d, "size")
}

fn de_scale<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    fixed::<D, 3>(d, "scale")
}

fn de_matrix<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[[f64; 4]; 4]>, D::Error> {
    let rows = Vec::<Vec<f64>>::deserialize(d)?;
    let shape_ok = rows.len() == 4 && rows.iter().all(|r| r.len() == 4);
    if !shape_ok {
        let shape: Vec<usize> = rows.iter().map(Vec::len).collect();
        return Err(D::Error::custom(format!(
            "`matrix` must be 4 rows of 4 numbers, found rows of lengths {shape:?}"
        )));
    }
    let mut m = [[0.0; 4]; 4];
    for (dst, src) in m.iter_mut().zip(&rows) {
        dst.copy_from_slice(src);
    }
    Ok(Some(m))
}

/// An RGBA colour, read from 3 (alpha 1) or 4 numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
struct Rgba([f64; 4]);

impl<'de> Deserialize<'de> for Rgba {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        match *v.as_slice() {
            [r, g, b] => Ok(Self([r, g, b, 1.0])),
            [r, g, b, a] => Ok(Self([r, g, b, a])),
            _ => Err(D::Error::custom(format!(
                "`color` must have 3 (RGB) or 4 (RGBA) numbers, found {}",
                v.len()
            ))),
        }
    }
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    version: Option<u32>,
    #[serde(default)]
    name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    units: Option<UnitsDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    root_joint: Option<RootJoint>,
    #[serde(
        default,
        deserialize_with = "de_gravity",
        skip_serializing_if = "Option::is_none"
    )]
    gravity: Option<[f64; 3]>,
    #[serde(default, alias = "parts")]
    links: Vec<LinkDoc>,
    #[serde(default)]
    joints: Vec<JointDoc>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    frames: Vec<FrameDoc>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct UnitsDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    length: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    angle: Option<String>,
}

impl UnitsDoc {
    fn parse(&self) -> Result<Units, ModelError> {
        Ok(Units {
            length: self
                .length
                .as_deref()
                .map_or(Ok(LengthUnit::Meter), LengthUnit::from_name)?,
            angle: self
                .angle
                .as_deref()
                .map_or(Ok(AngleUnit::Radian), AngleUnit::from_name)?,
        })
    }

    fn from_units(u: Units) -> Self {
        Self {
            length: Some(u.length.as_str().into()),
            angle: Some(u.angle.as_str().into()),
        }
    }
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct OriginDoc {
    #[serde(
        default,
        deserialize_with = "de_xyz",
        skip_serializing_if = "Option::is_none"
    )]
    xyz: Option<[f64; 3]>,
    #[serde(
        default,
        deserialize_with = "de_rpy",
        skip_serializing_if = "Option::is_none"
    )]
    rpy: Option<[f64; 3]>,
    #[serde(
        default,
        deserialize_with = "de_quat",
        skip_serializing_if = "Option::is_none"
    )]
    quat: Option<[f64; 4]>,
    #[serde(
        default,
        deserialize_with = "de_matrix",
        skip_serializing_if = "Option::is_none"
    )]
    matrix: Option<[[f64; 4]; 4]>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct InertiaDoc {
    #[serde(default)]
    ixx: f64,
    #[serde(default)]
    ixy: f64,
    #[serde(default)]
    ixz: f64,
    #[serde(default)]
    iyy: f64,
    #[serde(default)]
    iyz: f64,
    #[serde(default)]
    izz: f64,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct InertialDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    origin: Option<OriginDoc>,
    mass: f64,
    #[serde(default)]
    inertia: InertiaDoc,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum GeometryDoc {
    Box {
        #[serde(deserialize_with = "de_size")]
        size: [f64; 3],
    },
    Cylinder {
        radius: f64,
        length: f64,
    },
    Sphere {
        radius: f64,
    },
    Capsule {
        radius: f64,
        length: f64,
    },
    Mesh {
        filename: String,
        #[serde(
            default = "unit_scale",
            deserialize_with = "de_scale",
            skip_serializing_if = "is_unit_scale"
        )]
        scale: [f64; 3],
    },
}

fn unit_scale() -> [f64; 3] {
    [1.0; 3]
}

fn is_unit_scale(s: &[f64; 3]) -> bool {
    *s == [1.0; 3]
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct VisualDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    origin: Option<OriginDoc>,
    geometry: GeometryDoc,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    material: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    color: Option<Rgba>,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CollisionDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    origin: Option<OriginDoc>,
    geometry: GeometryDoc,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct MetadataDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    description: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    material: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    color: Option<Rgba>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mesh: Option<String>,
    #[serde(default, skip_serializing_if = "core::ops::Not::not")]
    printable: bool,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LinkDoc {
    name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    inertial: Option<InertialDoc>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    visuals: Vec<VisualDoc>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    collisions: Vec<CollisionDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    metadata: Option<MetadataDoc>,
    /// Written on export when the caller gives world poses; ignored on import.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    world_pose: Option<OriginDoc>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LimitsDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    lower: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    upper: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    velocity: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    effort: Option<f64>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DynamicsDoc {
    #[serde(default)]
    damping: f64,
    #[serde(default)]
    friction: f64,
    #[serde(default)]
    armature: f64,
}

fn one() -> f64 {
    1.0
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct MimicDoc {
    joint: String,
    #[serde(default = "one")]
    multiplier: f64,
    #[serde(default)]
    offset: f64,
}

/// A joint's current value: informational, never stored in the model.
#[derive(Debug, Serialize)]
#[serde(untagged)]
enum PositionDoc {
    Scalar(f64),
    Vector(Vec<f64>),
}

impl<'de> Deserialize<'de> for PositionDoc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct PositionVisitor;
        impl<'de> serde::de::Visitor<'de> for PositionVisitor {
            type Value = PositionDoc;

            fn expecting(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str("a number or an array of numbers for `position`")
            }

            fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<PositionDoc, E> {
                Ok(PositionDoc::Scalar(x))
            }

            #[expect(clippy::cast_precision_loss, reason = "JSON integers as joint values")]
            fn visit_i64<E: serde::de::Error>(self, x: i64) -> Result<PositionDoc, E> {
                Ok(PositionDoc::Scalar(x as f64))
            }

            #[expect(clippy::cast_precision_loss, reason = "JSON integers as joint values")]
            fn visit_u64<E: serde::de::Error>(self, x: u64) -> Result<PositionDoc, E> {
                Ok(PositionDoc::Scalar(x as f64))
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<PositionDoc, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = seq.next_element::<f64>()? {
                    v.push(x);
                }
                Ok(PositionDoc::Vector(v))
            }
        }
        d.deserialize_any(PositionVisitor)
    }
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct JointDoc {
    name: String,
    #[serde(rename = "type")]
    kind: JointKind,
    parent: String,
    child: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    parent_frame: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    origin: Option<OriginDoc>,
    #[serde(
        default,
        deserialize_with = "de_axis",
        skip_serializing_if = "Option::is_none"
    )]
    axis: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    limits: Option<LimitsDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    dynamics: Option<DynamicsDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mimic: Option<MimicDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    position: Option<PositionDoc>,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DatumRefDoc {
    file: String,
    name: String,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FrameDoc {
    name: String,
    link: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    origin: Option<OriginDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    description: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    datum: Option<DatumRefDoc>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DatumFileDoc {
    #[serde(default)]
    #[expect(
        dead_code,
        reason = "documentation field of datum files, accepted and unused"
    )]
    name: Option<String>,
    #[serde(default)]
    #[expect(
        dead_code,
        reason = "documentation field of datum files, accepted and unused"
    )]
    description: Option<String>,
    #[serde(default)]
    units: Option<UnitsDoc>,
    datums: BTreeMap<String, OriginDoc>,
}

// ---------------------------------------------------------------------------------------------
// Import.

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

/// An origin in file units to a pose in SI, or a message saying what is wrong.
fn origin_to_se3(o: Option<&OriginDoc>, units: Units) -> Result<Se3, String> {
    let Some(o) = o else {
        return Ok(Se3::IDENTITY);
    };
    if let Some(m) = &o.matrix {
        if o.xyz.is_some() || o.rpy.is_some() || o.quat.is_some() {
            return Err("origin gives `matrix` together with `xyz`, `rpy` or `quat`".into());
        }
        if m[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(format!(
                "origin `matrix` last row must be [0, 0, 0, 1], found {:?}",
                m[3]
            ));
        }
        let r = DMat3::from_cols(
            DVec3::new(m[0][0], m[1][0], m[2][0]),
            DVec3::new(m[0][1], m[1][1], m[2][1]),
            DVec3::new(m[0][2], m[1][2], m[2][2]),
        );
        let r = if rotation::is_rotation(&r, 1e-9) {
            r
        } else if rotation::is_rotation(&r, 1e-4) {
            // CAD exports round their matrices; a nearly orthonormal block is what was meant.
            rotation::orthonormalize(&r)
        } else {
            return Err("origin `matrix` rotation block is not a rotation".into());
        };
        let t = DVec3::new(m[0][3], m[1][3], m[2][3]);
        return Ok(Se3::new(r, t / units.length.per_meter()));
    }
    let rot = match (o.rpy, o.quat) {
        (Some(_), Some(_)) => return Err("origin gives both `rpy` and `quat`".into()),
        (Some(rpy), None) => {
            let a = |x: f64| units.angle.to_si(x);
            rotation::from_rpy(a(rpy[0]), a(rpy[1]), a(rpy[2]))
        }
        (None, Some([x, y, z, w])) => {
            let q = DQuat::from_xyzw(x, y, z, w);
            let n = q.length();
            if !(n.is_finite() && n > 1e-9) {
                return Err(format!(
                    "origin `quat` {:?} is not a rotation",
                    [x, y, z, w]
                ));
            }
            DMat3::from_quat(q / n)
        }
        (None, None) => DMat3::IDENTITY,
    };
    let t = DVec3::from_array(o.xyz.unwrap_or([0.0; 3]));
    Ok(Se3::new(rot, t / units.length.per_meter()))
}

fn geometry_to_si(g: &GeometryDoc, u: Units) -> Geometry {
    let l = |x: f64| u.length.to_si(x);
    match g {
        GeometryDoc::Box { size } => Geometry::Box { size: size.map(l) },
        GeometryDoc::Cylinder { radius, length } => Geometry::Cylinder {
            radius: l(*radius),
            length: l(*length),
        },
        GeometryDoc::Sphere { radius } => Geometry::Sphere { radius: l(*radius) },
        GeometryDoc::Capsule { radius, length } => Geometry::Capsule {
            radius: l(*radius),
            length: l(*length),
        },
        GeometryDoc::Mesh { filename, scale } => Geometry::Mesh {
            filename: filename.clone(),
            scale: *scale,
        },
    }
}

/// How a joint kind's position and velocity limits convert between units.
#[derive(Clone, Copy, PartialEq, Eq)]
enum LimitUnit {
    Angle,
    Length,
    /// Fixed joints: the values mean nothing and are passed through.
    Unconverted,
    /// Cylindrical, planar, floating: one value for coordinates of both kinds.
    Mixed,
}

fn limit_unit(kind: JointKind) -> LimitUnit {
    match kind {
        JointKind::Revolute | JointKind::Continuous | JointKind::Spherical => LimitUnit::Angle,
        JointKind::Prismatic => LimitUnit::Length,
        JointKind::Fixed => LimitUnit::Unconverted,
        JointKind::Cylindrical | JointKind::Planar | JointKind::Floating => LimitUnit::Mixed,
    }
}

/// Converts a joint's position and velocity limits with `f(unit, value)`; mixed-unit kinds keep
/// 0 and ±∞ (unit-free) and reject anything else unless the units are SI.
fn convert_limits(
    name: &str,
    kind: JointKind,
    limits: JointLimits,
    units: Units,
    to_si: bool,
) -> Result<JointLimits, String> {
    let unit = limit_unit(kind);
    let convert = |x: f64| -> Result<f64, String> {
        if !x.is_finite() || x == 0.0 {
            return Ok(x);
        }
        Ok(match (unit, to_si) {
            (LimitUnit::Angle, true) => units.angle.to_si(x),
            (LimitUnit::Angle, false) => units.angle.si_to_unit(x),
            (LimitUnit::Length, true) => units.length.to_si(x),
            (LimitUnit::Length, false) => units.length.si_to_unit(x),
            (LimitUnit::Unconverted, _) => x,
            (LimitUnit::Mixed, _) if units.is_si() => x,
            (LimitUnit::Mixed, _) => {
                return Err(format!(
                    "joint '{name}': a {kind} joint's limits mix lengths and angles, so a finite \
                     non-zero limit cannot be converted to or from {}/{}; use m and rad",
                    units.length.as_str(),
                    units.angle.as_str()
                ));
            }
        })
    };
    Ok(JointLimits {
        lower: convert(limits.lower)?,
        upper: convert(limits.upper)?,
        velocity: convert(limits.velocity)?,
        effort: limits.effort,
    })
}

/// Reads datum files once each.
struct DatumResolver<'a> {
    base: Option<&'a Path>,
    files: HashMap<PathBuf, (Units, BTreeMap<String, OriginDoc>)>,
}

impl DatumResolver<'_> {
    fn resolve(&mut self, frame: &str, datum: &DatumRefDoc) -> Result<Se3, ModelError> {
        let path = match self.base {
            Some(base) => base.join(&datum.file),
            None => PathBuf::from(&datum.file),
        };
        let err = |message: String| ModelError::Datum {
            frame: frame.to_string(),
            file: path.clone(),
            datum: datum.name.clone(),
            message,
        };
        if !self.files.contains_key(&path) {
            let text = std::fs::read_to_string(&path)
                .map_err(|e| err(format!("cannot read the datum file: {e}")))?;
            let doc: DatumFileDoc = serde_json::from_str(&text).map_err(|e| {
                let (line, column, message) = json_location(&e);
                err(format!(
                    "malformed datum file at line {line}, column {column}: {message}"
                ))
            })?;
            let units = doc
                .units
                .as_ref()
                .map_or(Ok(Units::SI), UnitsDoc::parse)
                .map_err(|e| err(e.to_string()))?;
            self.files.insert(path.clone(), (units, doc.datums));
        }
        let (units, datums) = &self.files[&path];
        let Some(origin) = datums.get(&datum.name) else {
            let known: Vec<&str> = datums.keys().map(String::as_str).collect();
            return Err(err(format!(
                "the file has no datum of that name (it has: {})",
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            )));
        };
        origin_to_se3(Some(origin), *units).map_err(err)
    }
}

fn from_json(
    text: &str,
    root: Option<RootJoint>,
    file: Option<&Path>,
) -> Result<Model, ModelError> {
    let doc: ModelDoc = serde_json::from_str(text).map_err(|e| json_error(&e, file))?;
    if let Some(v) = doc.version.filter(|&v| v != JSON_SCHEMA_VERSION) {
        return Err(schema_error(
            file,
            format!(
                "unsupported schema version {v} (this reader knows version {JSON_SCHEMA_VERSION})"
            ),
        ));
    }
    let units = doc.units.as_ref().map_or(Ok(Units::SI), UnitsDoc::parse)?;
    let bad = |message: String| schema_error(file, message);
    let origin = |o: Option<&OriginDoc>, what: &dyn Fn() -> String| {
        origin_to_se3(o, units).map_err(|m| bad(format!("{}: {m}", what())))
    };

    let mut b = ModelBuilder::new(doc.name.clone());
    b.root_joint(root.or(doc.root_joint).unwrap_or_default());
    if let Some(g) = doc.gravity {
        b.gravity(DVec3::from_array(g));
    }
    for ld in &doc.links {
        let name = &ld.name;
        let mut link = Link::new(name.clone());
        if let Some(i) = &ld.inertial {
            let s = units.length.per_meter().powi(2);
            let t = &i.inertia;
            link.inertial = Some(Inertial {
                origin: origin(i.origin.as_ref(), &|| format!("link '{name}' inertial"))?,
                mass: i.mass,
                inertia: Symmetric3::new(
                    t.ixx / s,
                    t.ixy / s,
                    t.ixz / s,
                    t.iyy / s,
                    t.iyz / s,
                    t.izz / s,
                ),
            });
        }
        for (k, v) in ld.visuals.iter().enumerate() {
            link.visuals.push(Visual {
                name: v.name.clone(),
                origin: origin(v.origin.as_ref(), &|| format!("link '{name}' visual {k}"))?,
                geometry: geometry_to_si(&v.geometry, units),
                material: v.material.clone(),
                color: v.color.map(|c| c.0),
            });
        }
        for (k, c) in ld.collisions.iter().enumerate() {
            link.collisions.push(Collision {
                name: c.name.clone(),
                origin: origin(c.origin.as_ref(), &|| {
                    format!("link '{name}' collision {k}")
                })?,
                geometry: geometry_to_si(&c.geometry, units),
            });
        }
        if let Some(m) = &ld.metadata {
            link.metadata = LinkMetadata {
                description: m.description.clone(),
                material: m.material.clone(),
                color: m.color.map(|c| c.0),
                mesh: m.mesh.clone(),
                printable: m.printable,
            };
        }
        b.add_link(link);
    }
    for jd in &doc.joints {
        let name = &jd.name;
        let lim = jd.limits.as_ref();
        let raw = JointLimits {
            lower: lim.and_then(|x| x.lower).unwrap_or(f64::NEG_INFINITY),
            upper: lim.and_then(|x| x.upper).unwrap_or(f64::INFINITY),
            velocity: lim.and_then(|x| x.velocity).unwrap_or(f64::INFINITY),
            effort: lim.and_then(|x| x.effort).unwrap_or(f64::INFINITY),
        };
        let limits = convert_limits(name, jd.kind, raw, units, true).map_err(bad)?;
        let dynamics = jd
            .dynamics
            .as_ref()
            .map_or_else(JointDynamics::default, |d| JointDynamics {
                damping: d.damping,
                friction: d.friction,
                armature: d.armature,
            });
        let mut spec = JointSpec::new(name.clone(), jd.kind, jd.parent.clone(), jd.child.clone())
            .with_placement(origin(jd.origin.as_ref(), &|| format!("joint '{name}'"))?)
            .with_axis(jd.axis.map_or(DVec3::Z, DVec3::from_array))
            .with_limits(limits)
            .with_dynamics(dynamics);
        spec.parent_frame = jd.parent_frame.clone();
        spec.mimic = jd.mimic.as_ref().map(|m| Mimic {
            joint: m.joint.clone(),
            multiplier: m.multiplier,
            offset: m.offset,
        });
        b.add_joint(spec);
    }
    let mut datums = DatumResolver {
        base: file.map(|f| f.parent().unwrap_or(Path::new(""))),
        files: HashMap::new(),
    };
    for fd in &doc.frames {
        let name = &fd.name;
        let (placement, datum) = match &fd.datum {
            Some(d) => {
                if fd.origin.is_some() {
                    return Err(bad(format!(
                        "frame '{name}' gives both `origin` and `datum`; give one"
                    )));
                }
                (
                    datums.resolve(name, d)?,
                    Some((d.file.clone(), d.name.clone())),
                )
            }
            None => (
                origin(fd.origin.as_ref(), &|| format!("frame '{name}'"))?,
                None,
            ),
        };
        let mut spec = FrameSpec::new(name.clone(), fd.link.clone(), placement);
        spec.description = fd.description.clone();
        spec.datum = datum;
        b.add_frame(spec);
    }
    b.build()
}

// ---------------------------------------------------------------------------------------------
// Export.

fn origin_doc(p: &Se3, u: Units) -> Option<OriginDoc> {
    if *p == Se3::IDENTITY {
        return None;
    }
    // Adding 0 turns -0 into 0.
    let rpy = p.to_rpy().map(|a| u.angle.si_to_unit(a) + 0.0);
    let xyz = p
        .translation
        .to_array()
        .map(|x| u.length.si_to_unit(x) + 0.0);
    Some(OriginDoc {
        xyz: (xyz != [0.0; 3]).then_some(xyz),
        rpy: (rpy != [0.0; 3]).then_some(rpy),
        quat: None,
        matrix: None,
    })
}

fn geometry_doc(g: &Geometry, u: Units) -> GeometryDoc {
    let l = |x: f64| u.length.si_to_unit(x);
    match g {
        Geometry::Box { size } => GeometryDoc::Box { size: size.map(l) },
        Geometry::Cylinder { radius, length } => GeometryDoc::Cylinder {
            radius: l(*radius),
            length: l(*length),
        },
        Geometry::Sphere { radius } => GeometryDoc::Sphere { radius: l(*radius) },
        Geometry::Capsule { radius, length } => GeometryDoc::Capsule {
            radius: l(*radius),
            length: l(*length),
        },
        Geometry::Mesh { filename, scale } => GeometryDoc::Mesh {
            filename: filename.clone(),
            scale: *scale,
        },
    }
}

/// The joint's block of `q` in file units: lengths and angles converted, quaternions kept.
fn position_doc(kind: JointKind, q: &[f64], u: Units) -> PositionDoc {
    let l = |x: f64| u.length.si_to_unit(x);
    let a = |x: f64| u.angle.si_to_unit(x);
    let v: Vec<f64> = match kind {
        JointKind::Revolute | JointKind::Continuous => vec![a(q[0])],
        JointKind::Prismatic => vec![l(q[0])],
        JointKind::Cylindrical => vec![l(q[0]), a(q[1])],
        JointKind::Planar => vec![l(q[0]), l(q[1]), a(q[2])],
        JointKind::Spherical => q.to_vec(),
        JointKind::Floating => {
            let mut v = q.to_vec();
            for x in &mut v[..3] {
                *x = l(*x);
            }
            v
        }
        JointKind::Fixed => Vec::new(),
    };
    if v.len() == 1 {
        PositionDoc::Scalar(v[0])
    } else {
        PositionDoc::Vector(v)
    }
}

fn to_json(model: &Model, o: &JsonOptions<'_>) -> Result<String, ModelError> {
    let u = o.units;
    if let Some(p) = o.world_poses.filter(|p| p.len() != model.links().len()) {
        return Err(ModelError::Length {
            what: "world poses (one per link)",
            expected: model.links().len(),
            actual: p.len(),
        });
    }
    if let Some(q) = o.positions.filter(|q| q.len() != model.nq()) {
        return Err(ModelError::Length {
            what: "positions (q, length nq)",
            expected: model.nq(),
            actual: q.len(),
        });
    }
    let bad = |message: String| schema_error(None, message);
    let s = u.length.per_meter().powi(2);
    let links = model
        .links()
        .iter()
        .enumerate()
        .map(|(li, link)| LinkDoc {
            name: link.name.clone(),
            inertial: link.inertial.map(|i| {
                let t = i.inertia;
                InertialDoc {
                    origin: origin_doc(&i.origin, u),
                    mass: i.mass,
                    inertia: InertiaDoc {
                        ixx: t.xx * s,
                        ixy: t.xy * s,
                        ixz: t.xz * s,
                        iyy: t.yy * s,
                        iyz: t.yz * s,
                        izz: t.zz * s,
                    },
                }
            }),
            visuals: link
                .visuals
                .iter()
                .map(|v| VisualDoc {
                    name: v.name.clone(),
                    origin: origin_doc(&v.origin, u),
                    geometry: geometry_doc(&v.geometry, u),
                    material: v.material.clone(),
                    color: v.color.map(Rgba),
                })
                .collect(),
            collisions: link
                .collisions
                .iter()
                .map(|c| CollisionDoc {
                    name: c.name.clone(),
                    origin: origin_doc(&c.origin, u),
                    geometry: geometry_doc(&c.geometry, u),
                })
                .collect(),
            metadata: (link.metadata != LinkMetadata::default()).then(|| {
                let m = &link.metadata;
                MetadataDoc {
                    description: m.description.clone(),
                    material: m.material.clone(),
                    color: m.color.map(Rgba),
                    mesh: m.mesh.clone(),
                    printable: m.printable,
                }
            }),
            world_pose: o.world_poses.map(|p| {
                origin_doc(&p[li], u).unwrap_or(OriginDoc {
                    xyz: Some([0.0; 3]),
                    rpy: Some([0.0; 3]),
                    ..OriginDoc::default()
                })
            }),
        })
        .collect();
    let mut joints = Vec::with_capacity(model.joints().len());
    for (ji, j) in model.joints().iter().enumerate() {
        // The floating root joint is the `root_joint` option, not a joint of the file.
        let Some(parent) = j.parent_link else {
            continue;
        };
        let limits = convert_limits(&j.name, j.kind, j.limits, u, false).map_err(bad)?;
        let finite = |x: f64| x.is_finite().then_some(x);
        let limits_doc = LimitsDoc {
            lower: finite(limits.lower),
            upper: finite(limits.upper),
            velocity: finite(limits.velocity),
            effort: finite(limits.effort),
        };
        let has_limits = limits_doc.lower.is_some()
            || limits_doc.upper.is_some()
            || limits_doc.velocity.is_some()
            || limits_doc.effort.is_some();
        let d = j.dynamics;
        joints.push(JointDoc {
            name: j.name.clone(),
            kind: j.kind,
            parent: model.link(parent).name.clone(),
            child: model.link(j.child_link).name.clone(),
            parent_frame: None,
            origin: origin_doc(&j.placement, u),
            axis: Some(j.axis.to_array()),
            limits: has_limits.then_some(limits_doc),
            dynamics: (d != JointDynamics::default()).then_some(DynamicsDoc {
                damping: d.damping,
                friction: d.friction,
                armature: d.armature,
            }),
            mimic: j.mimic.as_ref().map(|m| MimicDoc {
                joint: m.joint.clone(),
                multiplier: m.multiplier,
                offset: m.offset,
            }),
            position: o
                .positions
                .filter(|_| j.kind.is_moving())
                .map(|q| position_doc(j.kind, &q[model.joint_q_range(ji)], u)),
        });
    }
    let frames = model
        .frames()
        .iter()
        .map(|f| {
            let datum = f
                .datum
                .as_ref()
                .filter(|_| o.datums == DatumExport::Reference);
            FrameDoc {
                name: f.name.clone(),
                link: model.link(f.link).name.clone(),
                origin: if datum.is_some() {
                    None
                } else {
                    origin_doc(&f.placement, u)
                },
                description: f.description.clone(),
                datum: datum.map(|(file, name)| DatumRefDoc {
                    file: file.clone(),
                    name: name.clone(),
                }),
            }
        })
        .collect();
    let doc = ModelDoc {
        version: Some(JSON_SCHEMA_VERSION),
        name: model.name().to_string(),
        units: Some(UnitsDoc::from_units(u)),
        root_joint: Some(model.root_joint()),
        gravity: Some(model.gravity().to_array()),
        links,
        joints,
        frames,
    };
    let pretty = serde_json::to_string_pretty(&doc).map_err(|e| json_error(&e, None))?;
    Ok(inline_number_arrays(&pretty))
}

/// Puts arrays of numbers (vectors, colours) on one line in `serde_json`'s pretty output, which
/// otherwise gives every number its own line.
fn inline_number_arrays(pretty: &str) -> String {
    let lines: Vec<&str> = pretty.lines().collect();
    let mut out = String::with_capacity(pretty.len());
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        if line.ends_with('[') {
            // Collect the elements up to the closing bracket if they are all numbers.
            let mut numbers = Vec::new();
            let mut j = i + 1;
            while j < lines.len() {
                let t = lines[j].trim();
                if t.starts_with(']') {
                    break;
                }
                let t = t.strip_suffix(',').unwrap_or(t);
                if t.parse::<f64>().is_err() {
                    break;
                }
                numbers.push(t);
                j += 1;
            }
            if j < lines.len() && lines[j].trim().starts_with(']') && !numbers.is_empty() {
                out.push_str(line);
                out.push_str(&numbers.join(", "));
                out.push_str(lines[j].trim());
                out.push('\n');
                i = j + 1;
                continue;
            }
        }
        out.push_str(line);
        out.push('\n');
        i += 1;
    }
    out
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
        let text = read(path)?;
        from_json(&text, root.into(), Some(path))
    }

    /// Loads a URDF or JSON file, chosen by extension (`.urdf`, `.xml` → URDF; `.json` → JSON;
    /// anything else by the first non-blank character, `<` or `{`).
    ///
    /// `root`: for URDF, `None` means [`RootJoint::Fixed`]; for JSON, `None` keeps the file's own
    /// `root_joint` and a value overrides it.
    ///
    /// # Errors
    /// [`ModelError::UnknownFormat`] when the format cannot be told, otherwise as
    /// [`Model::from_urdf_file`] or [`Model::from_json_file`].
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
        match ext.as_deref() {
            Some("urdf" | "xml") => Model::from_urdf_file(path, root.unwrap_or_default()),
            Some("json") => Model::from_json_file(path, root),
            _ => {
                let text = read(path)?;
                match text.trim_start().chars().next() {
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
        }
    }

    /// Writes the model as JSON in kinetree's schema (see the [module docs](crate::json)),
    /// pretty-printed, in the units of `options` (the file declares them).
    ///
    /// The floating root joint is written as `"root_joint": "floating"`, not as a joint. A joint
    /// attached through a `parent_frame` is written relative to its parent link (the frame is
    /// folded into its origin when the model is built).
    ///
    /// # Errors
    /// [`ModelError::Length`] when `world_poses` or `positions` have the wrong length;
    /// [`ModelError::Json`] naming the joint when non-SI units are asked for and a cylindrical,
    /// planar or floating joint has finite non-zero limits (they mix lengths and angles).
    pub fn to_json_string(&self, options: &JsonOptions<'_>) -> Result<String, ModelError> {
        to_json(self, options)
    }
}

fn read(path: &Path) -> Result<String, ModelError> {
    std::fs::read_to_string(path).map_err(|source| ModelError::Io {
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::samples;
    use core::f64::consts::FRAC_PI_2;

    /// The same model in metres and radians ...
    const SI: &str = r#"{
      "name": "units",
      "links": [
        { "name": "base" },
        { "name": "arm",
          "inertial": { "origin": { "xyz": [0.1, 0, 0.02], "rpy": [0, 1.5707963267948966, 0] },
                        "mass": 2.0,
                        "inertia": { "ixx": 0.001, "ixy": 0.0002, "iyy": 0.003, "izz": 0.0035 } },
          "visuals": [ { "origin": { "xyz": [0.2, 0, 0] },
                         "geometry": { "type": "cylinder", "radius": 0.02, "length": 0.4 } } ],
          "collisions": [ { "geometry": { "type": "box", "size": [0.4, 0.05, 0.06] } },
                          { "geometry": { "type": "mesh", "filename": "package://x/arm.stl",
                                          "scale": [0.001, 0.001, 0.001] } } ] },
        { "name": "slide", "inertial": { "mass": 0.5 },
          "collisions": [ { "geometry": { "type": "capsule", "radius": 0.01, "length": 0.1 } },
                          { "geometry": { "type": "sphere", "radius": 0.03 } } ] },
        { "name": "ball", "inertial": { "mass": 0.1 } }
      ],
      "joints": [
        { "name": "shoulder", "type": "revolute", "parent": "base", "child": "arm",
          "origin": { "xyz": [0, 0, 0.1], "rpy": [0, 0, 0.7853981633974483] },
          "limits": { "lower": -1.5707963267948966, "upper": 1.0471975511965976,
                      "velocity": 3.141592653589793, "effort": 12 } },
        { "name": "slider", "type": "prismatic", "parent": "arm", "child": "slide",
          "origin": { "xyz": [0.4, 0, 0] }, "axis": [1, 0, 0],
          "limits": { "lower": -0.05, "upper": 0.25, "velocity": 0.5, "effort": 100 } },
        { "name": "wrist", "type": "spherical", "parent": "slide", "child": "ball",
          "origin": { "xyz": [0.1, 0, 0], "quat": [0, 0, 0.7071067811865476, 0.7071067811865476] },
          "limits": { "velocity": 6.283185307179586 } }
      ],
      "frames": [ { "name": "tip", "link": "ball",
                    "origin": { "xyz": [0.05, 0, 0], "rpy": [3.141592653589793, 0, 0] } } ]
    }"#;

    /// ... and in millimetres and degrees (inertia in kg·mm²).
    const MM_DEG: &str = r#"{
      "name": "units",
      "units": { "length": "mm", "angle": "deg" },
      "links": [
        { "name": "base" },
        { "name": "arm",
          "inertial": { "origin": { "xyz": [100, 0, 20], "rpy": [0, 90, 0] },
                        "mass": 2.0,
                        "inertia": { "ixx": 1000, "ixy": 200, "iyy": 3000, "izz": 3500 } },
          "visuals": [ { "origin": { "xyz": [200, 0, 0] },
                         "geometry": { "type": "cylinder", "radius": 20, "length": 400 } } ],
          "collisions": [ { "geometry": { "type": "box", "size": [400, 50, 60] } },
                          { "geometry": { "type": "mesh", "filename": "package://x/arm.stl",
                                          "scale": [0.001, 0.001, 0.001] } } ] },
        { "name": "slide", "inertial": { "mass": 0.5 },
          "collisions": [ { "geometry": { "type": "capsule", "radius": 10, "length": 100 } },
                          { "geometry": { "type": "sphere", "radius": 30 } } ] },
        { "name": "ball", "inertial": { "mass": 0.1 } }
      ],
      "joints": [
        { "name": "shoulder", "type": "revolute", "parent": "base", "child": "arm",
          "origin": { "xyz": [0, 0, 100], "rpy": [0, 0, 45] },
          "limits": { "lower": -90, "upper": 60, "velocity": 180, "effort": 12 },
          "position": 30 },
        { "name": "slider", "type": "prismatic", "parent": "arm", "child": "slide",
          "origin": { "xyz": [400, 0, 0] }, "axis": [1, 0, 0],
          "limits": { "lower": -50, "upper": 250, "velocity": 500, "effort": 100 },
          "position": 12.5 },
        { "name": "wrist", "type": "spherical", "parent": "slide", "child": "ball",
          "origin": { "xyz": [100, 0, 0], "quat": [0, 0, 0.7071067811865476, 0.7071067811865476] },
          "limits": { "velocity": 360 }, "position": [0, 0, 0, 1] }
      ],
      "frames": [ { "name": "tip", "link": "ball",
                    "origin": { "xyz": [50, 0, 0], "rpy": [180, 0, 0] } } ]
    }"#;

    #[test]
    fn a_mm_deg_file_equals_the_same_model_in_m_rad() {
        let si = Model::from_json_str(SI, None).unwrap();
        let mm = Model::from_json_str(MM_DEG, None).unwrap();
        assert_eq!(si.first_difference(&mm, 1e-12), None);
        // Spot checks of the conversion, in SI.
        let slider = mm.joint(mm.joint_index("slider").unwrap());
        assert!((slider.limits.upper - 0.25).abs() < 1e-15);
        assert!((slider.limits.velocity - 0.5).abs() < 1e-15);
        assert_eq!(slider.limits.effort, 100.0);
        let shoulder = mm.joint(mm.joint_index("shoulder").unwrap());
        assert!((shoulder.limits.lower + FRAC_PI_2).abs() < 1e-15);
        let arm = mm.link(mm.link_index("arm").unwrap());
        let i = arm.inertial.unwrap();
        assert!((i.inertia.xx - 0.001).abs() < 1e-18 && (i.inertia.xy - 0.0002).abs() < 1e-18);
        assert_eq!(
            arm.collisions[0].geometry,
            Geometry::Box {
                size: [0.4, 0.05, 0.06]
            }
        );
        // Mesh scales are unitless.
        assert!(
            matches!(&arm.collisions[1].geometry, Geometry::Mesh { scale, .. } if *scale == [0.001; 3])
        );
        // The quaternion origin turns the ball 90° about z.
        let wrist = mm.joint(mm.joint_index("wrist").unwrap());
        assert!(wrist.placement.rotation.x_axis.abs_diff_eq(DVec3::Y, 1e-15));
        assert!((wrist.limits.velocity - core::f64::consts::TAU).abs() < 1e-15);
    }

    #[test]
    fn export_in_mm_deg_reads_back_and_writes_file_units() {
        let si = Model::from_json_str(SI, None).unwrap();
        let json = si
            .to_json_string(&JsonOptions {
                units: Units::MM_DEG,
                ..JsonOptions::default()
            })
            .unwrap();
        assert!(json.contains("\"upper\": 250.0"), "{json}");
        assert!(json.contains("\"rpy\": [0.0, 0.0, 45.0]"), "{json}");
        assert!(json.contains("\"ixx\": 1000.0"), "{json}");
        let back = Model::from_json_str(&json, None).unwrap();
        assert_eq!(si.first_difference(&back, 1e-12), None);
        // SI → JSON → SI is exact apart from the rpy conversion of origins.
        let json = si.to_json_string(&JsonOptions::default()).unwrap();
        let again = Model::from_json_str(&json, None).unwrap();
        assert_eq!(si.first_difference(&again, 1e-15), None);
    }

    #[test]
    fn origin_forms_agree() {
        let pose = |origin: &str| {
            let json = format!(
                r#"{{ "links": [{{"name": "a"}}], "frames": [{{"name": "f", "link": "a", "origin": {origin}}}] }}"#
            );
            Model::from_json_str(&json, None).unwrap().frames()[0].placement
        };
        let rpy = pose(r#"{"xyz": [1, 2, 3], "rpy": [0, 0, 1.5707963267948966]}"#);
        let quat =
            pose(r#"{"xyz": [1, 2, 3], "quat": [0, 0, 0.7071067811865476, 0.7071067811865476]}"#);
        let matrix =
            pose(r#"{"matrix": [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]}"#);
        // Rounded as CAD tools print it: re-orthonormalized.
        let rounded = pose(
            r#"{"matrix": [[0.707107, -0.707107, 0, 0], [0.707107, 0.707107, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}"#,
        );
        assert!(rpy.abs_diff_eq(&quat, 1e-15, 1e-15));
        assert!(rpy.abs_diff_eq(&matrix, 1e-15, 1e-15));
        assert!(rounded.abs_diff_eq(
            &Se3::from_rotation_z(core::f64::consts::FRAC_PI_4),
            1e-6,
            0.0
        ));
        assert!(rotation::is_rotation(&rounded.rotation, 1e-12));
        assert_eq!(pose("{}"), Se3::IDENTITY);
    }

    #[test]
    fn invalid_origins_name_the_item() {
        let load = |origin: &str| {
            let json = format!(
                r#"{{ "links": [{{"name": "a"}}, {{"name": "b"}}],
                    "joints": [{{"name": "j", "type": "fixed", "parent": "a", "child": "b", "origin": {origin}}}] }}"#
            );
            Model::from_json_str(&json, None).unwrap_err().to_string()
        };
        let e = load(r#"{"rpy": [0, 0, 1], "quat": [0, 0, 0, 1]}"#);
        assert!(
            e.contains("joint 'j'") && e.contains("both `rpy` and `quat`"),
            "{e}"
        );
        let e = load(r#"{"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]}"#);
        assert!(e.contains("joint 'j'") && e.contains("last row"), "{e}");
        let e = load(r#"{"matrix": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}"#);
        assert!(
            e.contains("joint 'j'") && e.contains("not a rotation"),
            "{e}"
        );
        let e = load(r#"{"quat": [0, 0, 0, 0]}"#);
        assert!(e.contains("joint 'j'") && e.contains("quat"), "{e}");
        let e = load(r#"{"matrix": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}"#);
        assert!(
            e.contains("`matrix` must be 4 rows of 4 numbers") && e.contains("line 2"),
            "{e}"
        );
    }

    #[test]
    fn the_root_joint_comes_from_the_file_unless_overridden() {
        let json =
            r#"{ "root_joint": "floating", "links": [{"name": "a", "inertial": {"mass": 1}}] }"#;
        assert_eq!(Model::from_json_str(json, None).unwrap().nq(), 7);
        let fixed = Model::from_json_str(json, RootJoint::Fixed).unwrap();
        assert_eq!((fixed.nq(), fixed.root_joint()), (0, RootJoint::Fixed));
        let plain = r#"{ "links": [{"name": "a"}] }"#;
        assert_eq!(
            Model::from_json_str(plain, None).unwrap().root_joint(),
            RootJoint::Fixed
        );
        let floating = Model::from_json_str(plain, Some(RootJoint::Floating)).unwrap();
        assert_eq!(floating.root_joint(), RootJoint::Floating);
        // Export writes the root joint as the option, not as a joint named root_joint.
        let out = floating.to_json_string(&JsonOptions::default()).unwrap();
        assert!(
            out.contains("\"root_joint\": \"floating\"")
                && !out.contains("\"name\": \"root_joint\"")
        );
    }

    #[test]
    fn world_poses_and_positions_are_written_in_file_units() {
        let arm = samples::planar_2r(0.5, 0.3);
        let q = [FRAC_PI_2, -0.5];
        let poses = [
            Se3::IDENTITY,
            Se3::from_rotation_z(q[0]),
            Se3::from_rotation_z(q[0])
                * Se3::from_translation(DVec3::X * 0.5)
                * Se3::from_rotation_z(q[1]),
        ];
        let json = arm
            .to_json_string(&JsonOptions {
                units: Units::MM_DEG,
                world_poses: Some(&poses),
                positions: Some(&q),
                ..JsonOptions::default()
            })
            .unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["joints"][0]["position"], 90.0);
        assert!(
            (v["joints"][1]["position"].as_f64().unwrap() - (-0.5f64).to_degrees()).abs() < 1e-12
        );
        let link2 = &v["links"][2]["world_pose"];
        let xyz: Vec<f64> = link2["xyz"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert!(
            (xyz[0] - 0.0).abs() < 1e-12 && (xyz[1] - 500.0).abs() < 1e-12,
            "{xyz:?}"
        );
        assert!((link2["rpy"][2].as_f64().unwrap() - (FRAC_PI_2 - 0.5).to_degrees()).abs() < 1e-12);
        assert_eq!(
            v["links"][0]["world_pose"]["xyz"],
            serde_json::json!([0.0, 0.0, 0.0])
        );
        // Positions are informational: the file still loads, to the same model.
        assert_eq!(
            arm.first_difference(&Model::from_json_str(&json, None).unwrap(), 1e-12),
            None
        );
        // Wrong lengths are typed errors.
        let e = arm
            .to_json_string(&JsonOptions {
                positions: Some(&[0.0]),
                ..JsonOptions::default()
            })
            .unwrap_err();
        assert!(
            matches!(
                e,
                ModelError::Length {
                    expected: 2,
                    actual: 1,
                    ..
                }
            ),
            "{e}"
        );
        let e = arm
            .to_json_string(&JsonOptions {
                world_poses: Some(&poses[..2]),
                ..JsonOptions::default()
            })
            .unwrap_err();
        assert!(
            matches!(
                e,
                ModelError::Length {
                    expected: 3,
                    actual: 2,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn mixed_unit_limits_refuse_non_si_units() {
        let json = r#"{ "links": [{"name": "a"}, {"name": "b", "inertial": {"mass": 1}}],
            "joints": [{"name": "screw", "type": "cylindrical", "parent": "a", "child": "b",
                        "limits": {"lower": -1, "upper": 1}}] }"#;
        let m = Model::from_json_str(json, None).unwrap();
        let e = m
            .to_json_string(&JsonOptions {
                units: Units::MM_DEG,
                ..JsonOptions::default()
            })
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("joint 'screw'") && e.contains("mix lengths and angles"),
            "{e}"
        );
        let mm = json.replace("\"links\"", "\"units\": {\"length\": \"mm\"}, \"links\"");
        let e = Model::from_json_str(&mm, None).unwrap_err().to_string();
        assert!(e.contains("joint 'screw'"), "{e}");
        // Unlimited cylindrical joints convert fine.
        let free = json.replace(
            r#""limits": {"lower": -1, "upper": 1}"#,
            r#""axis": [0, 0, 1]"#,
        );
        let free = free.replace("\"links\"", "\"units\": {\"length\": \"mm\"}, \"links\"");
        assert_eq!(Model::from_json_str(&free, None).unwrap().nq(), 2);
    }

    #[test]
    fn colours_take_three_or_four_numbers() {
        let json = r#"{ "links": [{"name": "a", "metadata": {"color": [1, 0.5, 0], "printable": true,
                                                           "mesh": "a.stl", "material": "PLA", "description": "a part"}}] }"#;
        let m = Model::from_json_str(json, None).unwrap();
        let md = &m.link(0).metadata;
        assert_eq!(md.color, Some([1.0, 0.5, 0.0, 1.0]));
        assert!(md.printable);
        assert_eq!(
            (md.mesh.as_deref(), md.material.as_deref()),
            (Some("a.stl"), Some("PLA"))
        );
        let bad = json.replace("[1, 0.5, 0]", "[1, 0.5]");
        let e = Model::from_json_str(&bad, None).unwrap_err();
        assert!(matches!(e, ModelError::Json { line: 1, .. }), "{e}");
        assert!(
            e.to_string()
                .contains("`color` must have 3 (RGB) or 4 (RGBA) numbers, found 2"),
            "{e}"
        );
    }

    /// A fresh directory under the system's temporary directory.
    fn temp_dir(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("kinetree-model-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    const WITH_DATUM: &str = r#"{ "name": "servo_mount",
      "links": [{"name": "bracket"}],
      "frames": [{"name": "horn", "link": "bracket", "description": "servo output",
                  "datum": {"file": "cots/servo.json", "name": "output_shaft"}}] }"#;

    #[test]
    fn datum_frames_resolve_relative_to_the_model_file() {
        let dir = temp_dir("datum");
        std::fs::create_dir_all(dir.join("cots")).unwrap();
        std::fs::write(
            dir.join("cots/servo.json"),
            r#"{ "name": "servo", "units": {"length": "mm", "angle": "deg"},
                 "datums": { "output_shaft": {"xyz": [0, 10, 25], "rpy": [0, 0, 90]},
                             "mount_face": {} } }"#,
        )
        .unwrap();
        let path = dir.join("model.json");
        std::fs::write(&path, WITH_DATUM).unwrap();
        let m = Model::from_json_file(&path, None).unwrap();
        let horn = &m.frames()[0];
        let expected =
            Se3::from_translation(DVec3::new(0.0, 0.01, 0.025)) * Se3::from_rotation_z(FRAC_PI_2);
        assert!(
            horn.placement.abs_diff_eq(&expected, 1e-15, 1e-15),
            "{:?}",
            horn.placement
        );
        assert_eq!(
            horn.datum,
            Some(("cots/servo.json".into(), "output_shaft".into()))
        );
        assert_eq!(horn.description.as_deref(), Some("servo output"));
        // By default the reference is written back; inline export writes the pose instead.
        let out = m.to_json_string(&JsonOptions::default()).unwrap();
        assert!(
            out.contains("\"file\": \"cots/servo.json\"") && !out.contains("\"origin\""),
            "{out}"
        );
        std::fs::write(dir.join("again.json"), &out).unwrap();
        assert_eq!(
            Model::from_json_file(dir.join("again.json"), None).unwrap(),
            m
        );
        let inline = m
            .to_json_string(&JsonOptions {
                datums: DatumExport::Inline,
                ..JsonOptions::default()
            })
            .unwrap();
        assert!(
            !inline.contains("datum") && inline.contains("\"origin\""),
            "{inline}"
        );
        let standalone = Model::from_json_str(&inline, None).unwrap();
        assert!(
            standalone.frames()[0]
                .placement
                .abs_diff_eq(&expected, 1e-15, 1e-15)
        );
        assert_eq!(standalone.frames()[0].datum, None);
        // From a string, the datum path is relative to the current directory: not found here.
        let e = Model::from_json_str(WITH_DATUM, None).unwrap_err();
        assert!(matches!(e, ModelError::Datum { .. }), "{e}");
        // `from_file` dispatches on the extension, or sniffs the content.
        assert_eq!(Model::from_file(&path, None).unwrap(), m);
        std::fs::write(dir.join("model.kt"), WITH_DATUM).unwrap();
        assert_eq!(Model::from_file(dir.join("model.kt"), None).unwrap(), m);
        std::fs::write(dir.join("model.txt"), "robot").unwrap();
        let e = Model::from_file(dir.join("model.txt"), None).unwrap_err();
        assert!(matches!(e, ModelError::UnknownFormat { .. }), "{e}");
        std::fs::write(
            dir.join("robot.model"),
            "<robot name=\"r\"><link name=\"a\"/></robot>",
        )
        .unwrap();
        assert_eq!(
            Model::from_file(dir.join("robot.model"), RootJoint::Floating)
                .unwrap()
                .nq(),
            7
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_frame_with_both_origin_and_datum_is_rejected() {
        let json = WITH_DATUM.replace("\"description\"", "\"origin\": {}, \"description\"");
        let e = Model::from_json_str(&json, None).unwrap_err().to_string();
        assert!(
            e.contains("frame 'horn'") && e.contains("both `origin` and `datum`"),
            "{e}"
        );
    }

    #[test]
    fn parent_frames_place_joints() {
        let json = r#"{ "links": [{"name": "base"}, {"name": "arm", "inertial": {"mass": 1}}],
            "frames": [{"name": "mount", "link": "base", "origin": {"xyz": [0, 0, 0.5], "rpy": [0, 0, 1.5707963267948966]}}],
            "joints": [{"name": "j", "type": "revolute", "parent": "base", "child": "arm",
                        "parent_frame": "mount", "origin": {"xyz": [0.1, 0, 0]}}] }"#;
        let m = Model::from_json_str(json, None).unwrap();
        let j = m.joint(0);
        // The mount turns x into y: 0.1 along the mount's x is 0.1 along the base's y.
        assert!(
            j.placement
                .translation
                .abs_diff_eq(DVec3::new(0.0, 0.1, 0.5), 1e-15)
        );
        assert_eq!(j.axis, DVec3::Z);
        assert_eq!(j.limits, JointLimits::UNLIMITED);
    }

    #[test]
    fn positions_are_numbers_or_arrays() {
        let json = |position: &str| {
            format!(
                r#"{{ "links": [{{"name": "a"}}, {{"name": "b"}}],
                    "joints": [{{"name": "j", "type": "revolute", "parent": "a", "child": "b", "position": {position}}}] }}"#
            )
        };
        for ok in ["1", "-2.5", "[0.1, 0.2]", "[]"] {
            assert!(Model::from_json_str(&json(ok), None).is_ok(), "{ok}");
        }
        let e = Model::from_json_str(&json("\"up\""), None).unwrap_err();
        assert!(
            e.to_string()
                .contains("expected a number or an array of numbers for `position`"),
            "{e}"
        );
    }

    #[test]
    fn parts_is_another_name_for_links() {
        let m = Model::from_json_str(
            r#"{"name": "kit", "parts": [{"name": "BASE"}, {"name": "LINK1"}],
                "joints": [{"name": "j1", "type": "revolute", "parent": "BASE", "child": "LINK1"}]}"#,
            None,
        )
        .unwrap();
        assert_eq!((m.name(), m.links().len(), m.nq()), ("kit", 2, 1));
        assert_eq!(m.link(1).name, "LINK1");
    }

    #[test]
    fn unsupported_versions_are_rejected() {
        let e = Model::from_json_str(r#"{"version": 2, "links": []}"#, None).unwrap_err();
        assert!(
            e.to_string().contains("unsupported schema version 2"),
            "{e}"
        );
        assert_eq!(
            Model::from_json_str(r#"{"version": 1}"#, None)
                .unwrap()
                .nq(),
            0
        );
    }
}
