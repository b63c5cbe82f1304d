//! The per-item checks of [`ModelBuilder`](crate::ModelBuilder) and the name indices it builds.

use crate::builder::INERTIA_TOLERANCE;
use crate::error::{Issue, ItemKind};
use crate::frame::Frame;
use crate::link::{Geometry, Link};
use glam::DVec3;
use kinetree_spatial::{Inertia, InertiaDefect, Se3, rotation};
use std::collections::HashMap;

/// Frame lookup by `link/frame` always, and by the bare name when it is unique in the model.
pub(crate) fn frame_index_map(links: &[Link], frames: &[Frame]) -> HashMap<String, usize> {
    let mut count: HashMap<&str, usize> = HashMap::new();
    for f in frames {
        *count.entry(f.name.as_str()).or_default() += 1;
    }
    let mut map = HashMap::with_capacity(2 * frames.len());
    for (i, f) in frames.iter().enumerate() {
        map.insert(format!("{}/{}", links[f.link].name, f.name), i);
        if count[f.name.as_str()] == 1 {
            map.entry(f.name.clone()).or_insert(i);
        }
    }
    map
}

pub(crate) fn unique_names<S: AsRef<str>>(
    names: impl Iterator<Item = S>,
    kind: ItemKind,
    issues: &mut Vec<Issue>,
) -> HashMap<String, usize> {
    let mut map = HashMap::new();
    for (i, n) in names.enumerate() {
        let n = n.as_ref();
        if map.contains_key(n) {
            if !issues.iter().any(
                |x| matches!(x, Issue::DuplicateName { kind: k, name } if *k == kind && name == n),
            ) {
                issues.push(Issue::DuplicateName {
                    kind,
                    name: n.to_string(),
                });
            }
        } else {
            map.insert(n.to_string(), i);
        }
    }
    map
}

pub(crate) fn check_placement(p: &Se3, kind: ItemKind, name: &str, issues: &mut Vec<Issue>) {
    if !p.is_finite() {
        issues.push(Issue::NonFinite {
            kind,
            name: name.to_string(),
            what: "origin",
        });
    } else if !rotation::is_rotation(&p.rotation, 1e-9) {
        issues.push(Issue::InvalidRotation {
            kind,
            name: name.to_string(),
        });
    }
}

pub(crate) fn check_link(link: &Link, issues: &mut Vec<Issue>, inertia_issues: &mut Vec<Issue>) {
    if let Some(inertial) = &link.inertial {
        if !inertial.origin.is_finite() {
            issues.push(Issue::NonFinite {
                kind: ItemKind::Link,
                name: link.name.clone(),
                what: "inertial origin",
            });
        }
        let inertia = Inertia::new(inertial.mass, DVec3::ZERO, inertial.inertia);
        match inertia.check(INERTIA_TOLERANCE) {
            Ok(()) if inertial.mass == 0.0 => {
                let largest = inertial
                    .inertia
                    .to_voigt()
                    .iter()
                    .fold(0.0f64, |m, x| m.max(x.abs()));
                if largest > 0.0 {
                    inertia_issues.push(Issue::MasslessInertia {
                        link: link.name.clone(),
                        largest,
                    });
                }
            }
            Ok(()) => {}
            // Negative and non-finite masses or tensors are never accepted.
            Err(defect @ InertiaDefect::NonFinite) => {
                issues.push(Issue::InvalidInertia {
                    link: link.name.clone(),
                    mass: inertial.mass,
                    defect,
                });
            }
            Err(defect) if inertial.mass < 0.0 => {
                issues.push(Issue::InvalidInertia {
                    link: link.name.clone(),
                    mass: inertial.mass,
                    defect,
                });
            }
            Err(defect) => {
                inertia_issues.push(Issue::InvalidInertia {
                    link: link.name.clone(),
                    mass: inertial.mass,
                    defect,
                });
            }
        }
    }
    let shapes = link
        .visuals
        .iter()
        .map(|v| (&v.origin, &v.geometry))
        .chain(link.collisions.iter().map(|c| (&c.origin, &c.geometry)));
    for (origin, geometry) in shapes {
        if !origin.is_finite() {
            issues.push(Issue::NonFinite {
                kind: ItemKind::Link,
                name: link.name.clone(),
                what: "geometry origin",
            });
        }
        let bad = match geometry {
            Geometry::Box { size } => size.iter().any(|s| !(s.is_finite() && *s >= 0.0)),
            Geometry::Cylinder { radius, length } | Geometry::Capsule { radius, length } => {
                !(radius.is_finite() && *radius >= 0.0 && length.is_finite() && *length >= 0.0)
            }
            Geometry::Sphere { radius } => !(radius.is_finite() && *radius >= 0.0),
            // Any finite non-zero factor: a negative one mirrors the mesh.
            Geometry::Mesh { scale, .. } => scale.iter().any(|s| !s.is_finite() || *s == 0.0),
        };
        if bad {
            let what = if matches!(geometry, Geometry::Mesh { .. }) {
                "zero or non-finite mesh scale"
            } else {
                "negative or non-finite size"
            };
            issues.push(Issue::InvalidGeometry {
                link: link.name.clone(),
                reason: format!("{what} in {geometry:?}"),
            });
        }
    }
}
