//! Denavit–Hartenberg tables as JSON files (`arm.dh.json`), standard or modified, in any of the
//! JSON units.
//!
//! ```json
//! {
//!   "name": "planar",
//!   "convention": "standard",
//!   "units": { "length": "mm", "angle": "deg" },
//!   "base": "base",
//!   "dh": [
//!     { "type": "revolute", "a": 300, "alpha": 0, "d": 0, "theta": 0,
//!       "joint": "shoulder", "link": "upper", "limits": { "lower": -90, "upper": 90 },
//!       "inertial": { "mass": 1.2, "com": [-150, 0, 0], "inertia": { "ixx": 300, "iyy": 9000, "izz": 9000 } } },
//!     { "a": 200 }
//!   ],
//!   "tool": { "xyz": [50, 0, 0], "rpy": [0, 0, 0] }
//! }
//! ```
//!
//! - `dh` (required, the mark of the format): the rows, base to tip. Each row has `a` and `d`
//!   (lengths), `alpha` and `theta` (angles), each defaulting to 0; `type` is `revolute`
//!   (default), `continuous` or `prismatic`; `joint` and `link` name them (default `joint{i}`,
//!   `link{i}`); `limits` (`lower`, `upper`, `velocity`, `effort`: positions and velocities in
//!   the joint's unit, a missing bound unlimited); `inertial` (`mass` in kg, `com` in DH frame
//!   `i`, `inertia` about the centre of mass in DH frame `i`'s axes, in kg·length², entries
//!   defaulting to 0). With the modified convention a row's `a` and `alpha` are `aᵢ₋₁`, `αᵢ₋₁`.
//! - `convention`: `"standard"` (default) or `"modified"`; `units`: as in kinetree's JSON
//!   models (`length` m, cm or mm; `angle` rad or deg; default SI); `base`: the base link's name;
//!   `tool`: the pose of a `tool` frame in the last DH frame (`xyz`, `rpy`); `name`: the model's
//!   name, empty when left out (as in kinetree's JSON models and a URDF `<robot>`).
//!
//! Unknown fields are errors. [`Model::from_file`](crate::Model::from_file) and
//! [`Model::from_json_str`](crate::Model::from_json_str) recognise a document with a `dh` array
//! and build the arm with [`Model::from_dh`](crate::Model::from_dh).

use crate::dh::{DhConvention, DhRow, DhTable};
use crate::error::ModelError;
use crate::joint::{JointKind, JointLimits};
use crate::link::Inertial;
use crate::units::{AngleUnit, LengthUnit, Units};
use glam::DVec3;
use kinetree_spatial::{Se3, Symmetric3};
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TableDoc {
    #[serde(default)]
    name: String,
    #[serde(default)]
    convention: Option<String>,
    #[serde(default)]
    units: Option<UnitsDoc>,
    #[serde(default)]
    base: Option<String>,
    dh: Vec<RowDoc>,
    #[serde(default)]
    tool: Option<ToolDoc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct UnitsDoc {
    #[serde(default)]
    length: Option<String>,
    #[serde(default)]
    angle: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RowDoc {
    #[serde(default, rename = "type")]
    kind: Option<String>,
    #[serde(default)]
    a: f64,
    #[serde(default)]
    alpha: f64,
    #[serde(default)]
    d: f64,
    #[serde(default)]
    theta: f64,
    #[serde(default)]
    joint: Option<String>,
    #[serde(default)]
    link: Option<String>,
    #[serde(default)]
    limits: Option<LimitsDoc>,
    #[serde(default)]
    inertial: Option<InertialDoc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LimitsDoc {
    lower: Option<f64>,
    upper: Option<f64>,
    velocity: Option<f64>,
    effort: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct InertialDoc {
    mass: f64,
    #[serde(default)]
    com: [f64; 3],
    #[serde(default)]
    inertia: InertiaDoc,
}

#[derive(Deserialize, Default)]
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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ToolDoc {
    #[serde(default)]
    xyz: [f64; 3],
    #[serde(default)]
    rpy: [f64; 3],
}

/// Whether a JSON document is a DH table (a top-level object with a `dh` array).
pub(crate) fn is_dh_document(text: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(text)
        .is_ok_and(|v| v.get("dh").is_some_and(serde_json::Value::is_array))
}

fn json_error(e: &serde_json::Error) -> ModelError {
    let (line, column) = (e.line(), e.column());
    let full = e.to_string();
    let suffix = format!(" at line {line} column {column}");
    ModelError::Json {
        file: None,
        line,
        column,
        message: full.strip_suffix(&suffix).unwrap_or(&full).to_string(),
    }
}

impl DhTable {
    /// Reads a DH table from JSON (see the [module docs](crate::dh_json) for the format); lengths
    /// and angles are converted to SI.
    ///
    /// # Errors
    /// [`ModelError::Json`] for malformed JSON, unknown fields or wrong types (with line and
    /// column); [`ModelError::UnknownUnit`] for an unknown unit; [`ModelError::DhTable`] naming the
    /// row for an unknown joint type or convention.
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::dh::{DhConvention, DhTable};
    /// # fn main() -> Result<(), kinetree_model::ModelError> {
    /// let table = DhTable::from_json_str(r#"{"convention": "modified",
    ///   "units": {"length": "mm", "angle": "deg"},
    ///   "dh": [{"alpha": 90, "d": 100}, {"type": "prismatic", "a": 250}]}"#)?;
    /// assert_eq!(table.convention, DhConvention::Modified);
    /// assert!((table.rows[0].alpha - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    /// assert_eq!(table.rows[1].a, 0.25);
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_json_str(text: &str) -> Result<Self, ModelError> {
        let doc: TableDoc = serde_json::from_str(text).map_err(|e| json_error(&e))?;
        let units = match &doc.units {
            None => Units::SI,
            Some(u) => Units {
                length: u
                    .length
                    .as_deref()
                    .map_or(Ok(LengthUnit::Meter), LengthUnit::from_name)?,
                angle: u
                    .angle
                    .as_deref()
                    .map_or(Ok(AngleUnit::Radian), AngleUnit::from_name)?,
            },
        };
        let (len, ang) = (|x| units.length.to_si(x), |x| units.angle.to_si(x));
        let convention = match doc.convention.as_deref() {
            None | Some("standard") => DhConvention::Standard,
            Some("modified") => DhConvention::Modified,
            Some(other) => {
                return Err(ModelError::DhTable {
                    row: 0,
                    message: format!("unknown convention '{other}' (standard or modified)"),
                });
            }
        };
        let mut table = DhTable::new(doc.name, convention);
        table.base_name = doc.base;
        for (i, r) in doc.dh.into_iter().enumerate() {
            let kind = match r.kind.as_deref() {
                None | Some("revolute") => JointKind::Revolute,
                Some("continuous") => JointKind::Continuous,
                Some("prismatic") => JointKind::Prismatic,
                Some(other) => {
                    return Err(ModelError::DhTable {
                        row: i,
                        message: format!(
                            "unknown joint type '{other}' (revolute, continuous or prismatic)"
                        ),
                    });
                }
            };
            let position = |x: f64| {
                if kind == JointKind::Prismatic {
                    len(x)
                } else {
                    ang(x)
                }
            };
            let mut row = DhRow::new(kind, len(r.a), ang(r.alpha), len(r.d), ang(r.theta));
            if let Some(l) = r.limits {
                row.limits = JointLimits {
                    lower: l.lower.map_or(f64::NEG_INFINITY, position),
                    upper: l.upper.map_or(f64::INFINITY, position),
                    velocity: l.velocity.map_or(f64::INFINITY, position),
                    effort: l.effort.unwrap_or(f64::INFINITY),
                };
            }
            if let Some(inertial) = r.inertial {
                let s = units.length.per_meter().powi(2);
                let t = &inertial.inertia;
                row.inertial = Some(Inertial {
                    origin: Se3::from_translation(DVec3::from_array(inertial.com.map(len))),
                    mass: inertial.mass,
                    inertia: Symmetric3::new(t.ixx, t.ixy, t.ixz, t.iyy, t.iyz, t.izz) * (1.0 / s),
                });
            }
            row.joint_name = r.joint;
            row.link_name = r.link;
            table.rows.push(row);
        }
        table.tool = doc
            .tool
            .map(|t| Se3::from_xyz_rpy(t.xyz.map(len), t.rpy.map(ang)));
        Ok(table)
    }
}
