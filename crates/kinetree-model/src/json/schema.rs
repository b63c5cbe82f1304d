//! The file schema: the serde types of a model file and a datum file. The same types are read
//! ([`super::read`]) and written ([`super::write`]), so an exported file always loads.

use crate::error::ModelError;
use crate::joint::{JointKind, JointLimits};
use crate::model::RootJoint;
use crate::units::{AngleUnit, LengthUnit, Units};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;

/// Deserializes a JSON array of exactly `N` numbers, naming `field` when the length is wrong.
pub(super) fn fixed<'de, D: Deserializer<'de>, const N: usize>(
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

pub(super) fn de_size<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    fixed::<D, 3>(d, "size")
}

pub(super) fn de_scale<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    fixed::<D, 3>(d, "scale")
}

pub(super) fn de_matrix<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<[[f64; 4]; 4]>, D::Error> {
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
pub(super) struct Rgba(pub(super) [f64; 4]);

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
pub(super) struct ModelDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) version: Option<u32>,
    #[serde(default)]
    pub(super) name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) units: Option<UnitsDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) root_joint: Option<RootJoint>,
    #[serde(
        default,
        deserialize_with = "de_gravity",
        skip_serializing_if = "Option::is_none"
    )]
    pub(super) gravity: Option<[f64; 3]>,
    #[serde(default, alias = "parts")]
    pub(super) links: Vec<LinkDoc>,
    #[serde(default)]
    pub(super) joints: Vec<JointDoc>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) frames: Vec<FrameDoc>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct UnitsDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) length: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) angle: Option<String>,
}

impl UnitsDoc {
    pub(super) fn parse(&self) -> Result<Units, ModelError> {
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

    pub(super) fn from_units(u: Units) -> Self {
        Self {
            length: Some(u.length.as_str().into()),
            angle: Some(u.angle.as_str().into()),
        }
    }
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct OriginDoc {
    #[serde(
        default,
        deserialize_with = "de_xyz",
        skip_serializing_if = "Option::is_none"
    )]
    pub(super) xyz: Option<[f64; 3]>,
    #[serde(
        default,
        deserialize_with = "de_rpy",
        skip_serializing_if = "Option::is_none"
    )]
    pub(super) rpy: Option<[f64; 3]>,
    #[serde(
        default,
        deserialize_with = "de_quat",
        skip_serializing_if = "Option::is_none"
    )]
    pub(super) quat: Option<[f64; 4]>,
    #[serde(
        default,
        deserialize_with = "de_matrix",
        skip_serializing_if = "Option::is_none"
    )]
    pub(super) matrix: Option<[[f64; 4]; 4]>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InertiaDoc {
    #[serde(default)]
    pub(super) ixx: f64,
    #[serde(default)]
    pub(super) ixy: f64,
    #[serde(default)]
    pub(super) ixz: f64,
    #[serde(default)]
    pub(super) iyy: f64,
    #[serde(default)]
    pub(super) iyz: f64,
    #[serde(default)]
    pub(super) izz: f64,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InertialDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) origin: Option<OriginDoc>,
    pub(super) mass: f64,
    #[serde(default)]
    pub(super) inertia: InertiaDoc,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum GeometryDoc {
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

pub(super) fn unit_scale() -> [f64; 3] {
    [1.0; 3]
}

pub(super) fn is_unit_scale(s: &[f64; 3]) -> bool {
    *s == [1.0; 3]
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct VisualDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) origin: Option<OriginDoc>,
    pub(super) geometry: GeometryDoc,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) material: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) color: Option<Rgba>,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CollisionDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) origin: Option<OriginDoc>,
    pub(super) geometry: GeometryDoc,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MetadataDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) description: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) material: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) color: Option<Rgba>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) mesh: Option<String>,
    #[serde(default, skip_serializing_if = "core::ops::Not::not")]
    pub(super) printable: bool,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LinkDoc {
    pub(super) name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) inertial: Option<InertialDoc>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) visuals: Vec<VisualDoc>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) collisions: Vec<CollisionDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) metadata: Option<MetadataDoc>,
    /// Written on export when the caller gives world poses; ignored on import.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) world_pose: Option<OriginDoc>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LimitsDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) lower: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) upper: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) velocity: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) effort: Option<f64>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DynamicsDoc {
    #[serde(default)]
    pub(super) damping: f64,
    #[serde(default)]
    pub(super) friction: f64,
    #[serde(default)]
    pub(super) armature: f64,
}

pub(super) fn one() -> f64 {
    1.0
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MimicDoc {
    pub(super) joint: String,
    #[serde(default = "one")]
    pub(super) multiplier: f64,
    #[serde(default)]
    pub(super) offset: f64,
}

/// A joint's current value: informational, never stored in the model.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub(super) enum PositionDoc {
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
pub(super) struct JointDoc {
    pub(super) name: String,
    #[serde(rename = "type")]
    pub(super) kind: KindDoc,
    pub(super) parent: String,
    pub(super) child: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) parent_frame: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) origin: Option<OriginDoc>,
    #[serde(
        default,
        deserialize_with = "de_axis",
        skip_serializing_if = "Option::is_none"
    )]
    pub(super) axis: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) limits: Option<LimitsDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) dynamics: Option<DynamicsDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) mimic: Option<MimicDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) position: Option<PositionDoc>,
    /// A composite joint's factors, in order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) factors: Option<Vec<FactorDoc>>,
}

/// A joint's `type`: an elementary kind, or `"composite"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum KindDoc {
    Joint(JointKind),
    Composite,
}

impl Serialize for KindDoc {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Joint(k) => k.serialize(s),
            Self::Composite => s.serialize_str("composite"),
        }
    }
}

impl<'de> Deserialize<'de> for KindDoc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        const NAMES: [&str; 9] = [
            "fixed",
            "revolute",
            "continuous",
            "prismatic",
            "cylindrical",
            "spherical",
            "planar",
            "floating",
            "composite",
        ];
        let name = String::deserialize(d)?;
        if name == "composite" {
            return Ok(Self::Composite);
        }
        JointKind::from_name(&name)
            .map(Self::Joint)
            .ok_or_else(|| D::Error::unknown_variant(&name, &NAMES))
    }
}

/// One factor of a composite joint: `param` is `tx`, `ty`, `tz`, `rx`, `ry`, `rz` or `quat`;
/// with a `value` it is a constant (a number, or `[x, y, z, w]` for `quat`), without one a state
/// variable, which may have `limits`.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FactorDoc {
    pub(super) param: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) value: Option<PositionDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) limits: Option<LimitsDoc>,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DatumRefDoc {
    pub(super) file: String,
    pub(super) name: String,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FrameDoc {
    pub(super) name: String,
    pub(super) link: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) origin: Option<OriginDoc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) description: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) datum: Option<DatumRefDoc>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DatumFileDoc {
    #[serde(default)]
    #[expect(
        dead_code,
        reason = "documentation field of datum files, accepted and unused"
    )]
    pub(super) name: Option<String>,
    #[serde(default)]
    #[expect(
        dead_code,
        reason = "documentation field of datum files, accepted and unused"
    )]
    pub(super) description: Option<String>,
    #[serde(default)]
    pub(super) units: Option<UnitsDoc>,
    pub(super) datums: BTreeMap<String, OriginDoc>,
}

/// How a joint kind's position and velocity limits convert between units.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum LimitUnit {
    Angle,
    Length,
    /// Fixed joints: the values mean nothing and are passed through.
    Unconverted,
    /// Cylindrical, planar, floating: one value for coordinates of both kinds.
    Mixed,
}

pub(super) fn limit_unit(kind: JointKind) -> LimitUnit {
    match kind {
        JointKind::Revolute | JointKind::Continuous | JointKind::Spherical => LimitUnit::Angle,
        JointKind::Prismatic => LimitUnit::Length,
        JointKind::Fixed => LimitUnit::Unconverted,
        JointKind::Cylindrical | JointKind::Planar | JointKind::Floating => LimitUnit::Mixed,
    }
}

/// Converts a joint's position and velocity limits with `f(unit, value)`; mixed-unit kinds keep
/// 0 and ±∞ (unit-free) and reject anything else unless the units are SI.
pub(super) fn convert_limits(
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
