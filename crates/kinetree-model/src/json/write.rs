//! Export: a [`Model`] to a model file in the units of [`JsonOptions`].

use super::schema::*;
use super::{DatumExport, JSON_SCHEMA_VERSION, JsonOptions, json_error, schema_error};
use crate::error::ModelError;
use crate::joint::{JointDynamics, JointKind};
use crate::link::{Geometry, LinkMetadata};
use crate::model::Model;
use crate::units::Units;
use kinetree_spatial::Se3;

pub(super) fn origin_doc(p: &Se3, u: Units) -> Option<OriginDoc> {
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

pub(super) fn geometry_doc(g: &Geometry, u: Units) -> GeometryDoc {
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
pub(super) fn position_doc(kind: JointKind, q: &[f64], u: Units) -> PositionDoc {
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

pub(super) fn to_json(model: &Model, o: &JsonOptions<'_>) -> Result<String, ModelError> {
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
        .filter(|&(li, _)| !model.is_virtual_link(li))
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
        if model.is_floating_root_joint(ji) {
            continue;
        }
        let (parent, parent_frame, origin) = joint_attachment(model, j);
        // A composite joint is written once, as itself, in place of its pieces.
        if let Some(c) = model.composite_of_joint(ji) {
            if model.composites()[c].joints.start == ji {
                let placement = origin_doc(&model.composites()[c].spec.placement, u);
                let at = (parent, parent_frame, placement);
                joints.push(super::composite::doc_from_composite(
                    model,
                    c,
                    at,
                    o.positions,
                    u,
                ));
            }
            continue;
        }
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
            kind: KindDoc::Joint(j.kind),
            parent,
            child: model.link(j.child_link).name.clone(),
            parent_frame,
            origin: origin_doc(&origin, u),
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
            factors: None,
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
pub(super) fn inline_number_arrays(pretty: &str) -> String {
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

/// How a joint is written: its parent's name (the world datum's for a root part), its parent
/// frame as declared, and its origin relative to that frame.
fn joint_attachment(model: &Model, j: &crate::joint::Joint) -> (String, Option<String>, Se3) {
    let Some(p) = j.parent_link else {
        let world = crate::builder::WORLD_NAMES
            .into_iter()
            .find(|n| model.link_index(n).is_none())
            .unwrap_or("world");
        return (world.to_string(), None, j.placement);
    };
    let parent = model.link(p).name.clone();
    let frame = j.parent_frame.as_ref().map(|f| {
        let pose = model
            .frame_index(&format!("{parent}/{f}"))
            .map_or(Se3::IDENTITY, |i| model.frames()[i].placement);
        (f.clone(), pose)
    });
    match frame {
        Some((f, pose)) => (parent, Some(f), pose.inverse() * j.placement),
        None => (parent, None, j.placement),
    }
}
