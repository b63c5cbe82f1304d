//! Import: a model file (and its datum files) to a [`Model`], units converted to SI.

use super::schema::*;
use super::{JSON_SCHEMA_VERSION, json_error, json_location, schema_error};
use crate::builder::{FrameSpec, JointSpec, ModelBuilder};
use crate::error::ModelError;
use crate::joint::{JointDynamics, JointLimits, Mimic};
use crate::link::{Collision, Geometry, Inertial, Link, LinkMetadata, Visual};
use crate::model::{Model, RootJoint};
use crate::units::Units;
use glam::{DMat3, DQuat, DVec3};
use kinetree_spatial::{Se3, Symmetric3, rotation};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// An origin in file units to a pose in SI, or a message saying what is wrong.
pub(super) fn origin_to_se3(o: Option<&OriginDoc>, units: Units) -> Result<Se3, String> {
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

pub(super) fn geometry_to_si(g: &GeometryDoc, u: Units) -> Geometry {
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

/// Reads datum `name` of `file` (relative to `base` when given) for frame `frame`: the datum
/// module's entry point into the resolver.
pub(crate) fn resolve_one(
    base: Option<&Path>,
    frame: &str,
    file: &str,
    name: &str,
) -> Result<Se3, ModelError> {
    DatumResolver {
        base,
        files: HashMap::new(),
    }
    .resolve(
        frame,
        &DatumRefDoc {
            file: file.to_string(),
            name: name.to_string(),
        },
    )
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

pub(super) fn from_json(
    text: &str,
    root: Option<RootJoint>,
    file: Option<&Path>,
) -> Result<Model, ModelError> {
    if crate::dh_json::is_dh_document(text) {
        return dh_from_json(text, root, file);
    }
    if crate::yapcad::is_yapcad_json(text) {
        return crate::yapcad::model_from_text(text, file);
    }
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
        let kind = match jd.kind {
            KindDoc::Composite => {
                let placement = origin(jd.origin.as_ref(), &|| format!("joint '{name}'"))?;
                b.add_composite(
                    super::composite::spec_from_doc(jd, placement, units).map_err(bad)?,
                );
                continue;
            }
            KindDoc::Joint(kind) => kind,
        };
        if jd.factors.is_some() {
            return Err(bad(format!(
                "joint '{name}': only a composite joint has `factors` (this one is {kind})"
            )));
        }
        let lim = jd.limits.as_ref();
        let raw = JointLimits {
            lower: lim.and_then(|x| x.lower).unwrap_or(f64::NEG_INFINITY),
            upper: lim.and_then(|x| x.upper).unwrap_or(f64::INFINITY),
            velocity: lim.and_then(|x| x.velocity).unwrap_or(f64::INFINITY),
            effort: lim.and_then(|x| x.effort).unwrap_or(f64::INFINITY),
        };
        let limits = convert_limits(name, kind, raw, units, true).map_err(bad)?;
        let dynamics = jd
            .dynamics
            .as_ref()
            .map_or_else(JointDynamics::default, |d| JointDynamics {
                damping: d.damping,
                friction: d.friction,
                armature: d.armature,
            });
        let mut spec = JointSpec::new(name.clone(), kind, jd.parent.clone(), jd.child.clone())
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

/// A DH table document (see [`crate::dh_json`]) built into its arm.
fn dh_from_json(
    text: &str,
    root: Option<RootJoint>,
    file: Option<&Path>,
) -> Result<Model, ModelError> {
    if root == Some(RootJoint::Floating) {
        return Err(schema_error(
            file,
            "a Denavit-Hartenberg table describes a fixed-base arm; it cannot float".into(),
        ));
    }
    let table = crate::dh::DhTable::from_json_str(text).map_err(|e| match e {
        ModelError::Json {
            line,
            column,
            message,
            ..
        } => ModelError::Json {
            file: file.map(Path::to_path_buf),
            line,
            column,
            message,
        },
        other => other,
    })?;
    Model::from_dh(&table)
}
