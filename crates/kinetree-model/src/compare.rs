//! Approximate comparison of two models, for round-trip checks through files and unit conversion.

use crate::joint::{Joint, JointLimits};
use crate::link::{Geometry, Inertial, Link};
use crate::model::Model;
use kinetree_spatial::{Se3, Symmetric3};

/// Whether `a` and `b` agree within `tolerance`, relative to their magnitude when it exceeds 1.
/// Infinities are equal when they have the same sign.
fn close(a: f64, b: f64, tolerance: f64) -> bool {
    if a == b {
        return true;
    }
    if !(a.is_finite() && b.is_finite()) {
        return false;
    }
    (a - b).abs() <= tolerance * a.abs().max(b.abs()).max(1.0)
}

fn close_all(a: &[f64], b: &[f64], tolerance: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| close(*x, *y, tolerance))
}

fn close_se3(a: &Se3, b: &Se3, tolerance: f64) -> bool {
    close_all(
        &a.rotation.to_cols_array(),
        &b.rotation.to_cols_array(),
        tolerance,
    ) && close_all(
        &a.translation.to_array(),
        &b.translation.to_array(),
        tolerance,
    )
}

fn close_sym(a: &Symmetric3, b: &Symmetric3, tolerance: f64) -> bool {
    close_all(&a.to_urdf_array(), &b.to_urdf_array(), tolerance)
}

fn close_geometry(a: &Geometry, b: &Geometry, tolerance: f64) -> bool {
    match (a, b) {
        (Geometry::Box { size: s }, Geometry::Box { size: t }) => close_all(s, t, tolerance),
        (
            Geometry::Cylinder {
                radius: r1,
                length: l1,
            },
            Geometry::Cylinder {
                radius: r2,
                length: l2,
            },
        )
        | (
            Geometry::Capsule {
                radius: r1,
                length: l1,
            },
            Geometry::Capsule {
                radius: r2,
                length: l2,
            },
        ) => close(*r1, *r2, tolerance) && close(*l1, *l2, tolerance),
        (Geometry::Sphere { radius: r1 }, Geometry::Sphere { radius: r2 }) => {
            close(*r1, *r2, tolerance)
        }
        (
            Geometry::Mesh {
                filename: f1,
                scale: s1,
            },
            Geometry::Mesh {
                filename: f2,
                scale: s2,
            },
        ) => f1 == f2 && close_all(s1, s2, tolerance),
        _ => false,
    }
}

fn close_inertial(a: Option<&Inertial>, b: Option<&Inertial>, tolerance: f64) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            close(a.mass, b.mass, tolerance)
                && close_se3(&a.origin, &b.origin, tolerance)
                && close_sym(&a.inertia, &b.inertia, tolerance)
        }
        _ => false,
    }
}

fn close_limits(a: &JointLimits, b: &JointLimits, tolerance: f64) -> bool {
    close_all(
        &[a.lower, a.upper, a.velocity, a.effort],
        &[b.lower, b.upper, b.velocity, b.effort],
        tolerance,
    )
}

fn link_difference(a: &Link, b: &Link, tolerance: f64) -> Option<String> {
    let name = &a.name;
    if a.name != b.name {
        return Some(format!("link name '{}' vs '{}'", a.name, b.name));
    }
    if !close_inertial(a.inertial.as_ref(), b.inertial.as_ref(), tolerance) {
        return Some(format!(
            "link '{name}': inertial {:?} vs {:?}",
            a.inertial, b.inertial
        ));
    }
    if a.visuals.len() != b.visuals.len() || a.collisions.len() != b.collisions.len() {
        return Some(format!(
            "link '{name}': {} visuals and {} collisions vs {} and {}",
            a.visuals.len(),
            a.collisions.len(),
            b.visuals.len(),
            b.collisions.len()
        ));
    }
    for (i, (v, w)) in a.visuals.iter().zip(&b.visuals).enumerate() {
        let colors = match (v.color, w.color) {
            (None, None) => true,
            (Some(c), Some(d)) => close_all(&c, &d, tolerance),
            _ => false,
        };
        if v.name != w.name
            || v.material != w.material
            || !colors
            || !close_se3(&v.origin, &w.origin, tolerance)
            || !close_geometry(&v.geometry, &w.geometry, tolerance)
        {
            return Some(format!("link '{name}': visual {i}: {v:?} vs {w:?}"));
        }
    }
    for (i, (c, d)) in a.collisions.iter().zip(&b.collisions).enumerate() {
        if c.name != d.name
            || !close_se3(&c.origin, &d.origin, tolerance)
            || !close_geometry(&c.geometry, &d.geometry, tolerance)
        {
            return Some(format!("link '{name}': collision {i}: {c:?} vs {d:?}"));
        }
    }
    let (m, n) = (&a.metadata, &b.metadata);
    let colors = match (m.color, n.color) {
        (None, None) => true,
        (Some(c), Some(d)) => close_all(&c, &d, tolerance),
        _ => false,
    };
    if m.description != n.description
        || m.material != n.material
        || m.mesh != n.mesh
        || m.printable != n.printable
        || !colors
    {
        return Some(format!("link '{name}': metadata {m:?} vs {n:?}"));
    }
    None
}

fn joint_difference(a: &Joint, b: &Joint, tolerance: f64) -> Option<String> {
    let name = &a.name;
    if a.name != b.name {
        return Some(format!("joint name '{}' vs '{}'", a.name, b.name));
    }
    if a.kind != b.kind {
        return Some(format!("joint '{name}': kind {} vs {}", a.kind, b.kind));
    }
    if a.parent_link != b.parent_link || a.child_link != b.child_link {
        return Some(format!(
            "joint '{name}': links {:?} -> {} vs {:?} -> {}",
            a.parent_link, a.child_link, b.parent_link, b.child_link
        ));
    }
    if !close_se3(&a.placement, &b.placement, tolerance) {
        return Some(format!(
            "joint '{name}': placement {:?} vs {:?}",
            a.placement, b.placement
        ));
    }
    if !close_all(&a.axis.to_array(), &b.axis.to_array(), tolerance) {
        return Some(format!("joint '{name}': axis {} vs {}", a.axis, b.axis));
    }
    if !close_limits(&a.limits, &b.limits, tolerance) {
        return Some(format!(
            "joint '{name}': limits {:?} vs {:?}",
            a.limits, b.limits
        ));
    }
    let (d, e) = (&a.dynamics, &b.dynamics);
    if !close_all(
        &[d.damping, d.friction, d.armature],
        &[e.damping, e.friction, e.armature],
        tolerance,
    ) {
        return Some(format!("joint '{name}': dynamics {d:?} vs {e:?}"));
    }
    let mimic = match (&a.mimic, &b.mimic) {
        (None, None) => true,
        (Some(m), Some(n)) => {
            m.joint == n.joint
                && close(m.multiplier, n.multiplier, tolerance)
                && close(m.offset, n.offset, tolerance)
        }
        _ => false,
    };
    if !mimic {
        return Some(format!(
            "joint '{name}': mimic {:?} vs {:?}",
            a.mimic, b.mimic
        ));
    }
    None
}

impl Model {
    /// Describes the first difference between two models, or `None` when they agree.
    ///
    /// Names, topology, kinds and strings must be identical; numbers must agree within
    /// `tolerance`, relative to their magnitude when it exceeds 1 (so `1e-12` suits a round
    /// trip through a text file, and `1e-9` one through millimetres and degrees). Unlike `==`,
    /// this ignores what a loader reported ([`Model::ignored`], [`Model::warnings`]), which
    /// depends on the source format rather than on the model.
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::{samples, JsonOptions, Model};
    /// # fn main() -> Result<(), kinetree_model::ModelError> {
    /// let arm = samples::six_axis();
    /// let json = arm.to_json_string(&JsonOptions::default())?;
    /// let back = Model::from_json_str(&json, None)?;
    /// assert_eq!(arm.first_difference(&back, 1e-12), None);
    /// # Ok(())
    /// # }
    /// ```
    #[must_use]
    pub fn first_difference(&self, other: &Model, tolerance: f64) -> Option<String> {
        if self.name != other.name {
            return Some(format!("model name '{}' vs '{}'", self.name, other.name));
        }
        if self.root_joint != other.root_joint {
            return Some(format!(
                "root joint {:?} vs {:?}",
                self.root_joint, other.root_joint
            ));
        }
        if (self.nq, self.nv) != (other.nq, other.nv) {
            return Some(format!(
                "nq/nv {}/{} vs {}/{}",
                self.nq, self.nv, other.nq, other.nv
            ));
        }
        if !close_all(
            &self.gravity.to_array(),
            &other.gravity.to_array(),
            tolerance,
        ) {
            return Some(format!("gravity {} vs {}", self.gravity, other.gravity));
        }
        if self.links.len() != other.links.len() {
            return Some(format!(
                "{} links vs {}",
                self.links.len(),
                other.links.len()
            ));
        }
        if self.joints.len() != other.joints.len() {
            return Some(format!(
                "{} joints vs {}",
                self.joints.len(),
                other.joints.len()
            ));
        }
        for (a, b) in self.links.iter().zip(&other.links) {
            if let Some(d) = link_difference(a, b, tolerance) {
                return Some(d);
            }
        }
        for (a, b) in self.joints.iter().zip(&other.joints) {
            if let Some(d) = joint_difference(a, b, tolerance) {
                return Some(d);
            }
        }
        if self.frames.len() != other.frames.len() {
            return Some(format!(
                "{} frames vs {}",
                self.frames.len(),
                other.frames.len()
            ));
        }
        for (f, g) in self.frames.iter().zip(&other.frames) {
            if f.name != g.name
                || f.link != g.link
                || f.description != g.description
                || f.datum != g.datum
                || !close_se3(&f.placement, &g.placement, tolerance)
            {
                return Some(format!("frame '{}': {f:?} vs {g:?}", f.name));
            }
        }
        let (ca, cb) = (self.composites(), other.composites());
        if ca.len() != cb.len() {
            return Some(format!("{} composite joints vs {}", ca.len(), cb.len()));
        }
        for (a, b) in ca.iter().zip(cb) {
            let (a, b) = (&a.spec, &b.spec);
            let same_factors = a.factors.len() == b.factors.len()
                && a.factors.iter().zip(&b.factors).all(|(x, y)| {
                    use crate::composite::Factor;
                    match (x, y) {
                        (Factor::Translate(p, Some(u)), Factor::Translate(q, Some(v)))
                        | (Factor::Rotate(p, Some(u)), Factor::Rotate(q, Some(v))) => {
                            p == q && close(*u, *v, tolerance)
                        }
                        (Factor::Rotation(r), Factor::Rotation(s)) => close_all(
                            &r.normalize().to_array(),
                            &s.normalize().to_array(),
                            tolerance,
                        ),
                        _ => x == y,
                    }
                });
            let same_limits = a.limits.len() == b.limits.len()
                && a.limits
                    .iter()
                    .zip(&b.limits)
                    .all(|(x, y)| close_limits(x, y, tolerance));
            if a.name != b.name
                || a.parent != b.parent
                || a.child != b.child
                || a.parent_frame != b.parent_frame
                || !same_factors
                || !same_limits
                || !close_se3(&a.placement, &b.placement, tolerance)
            {
                return Some(format!("composite joint '{}': {a:?} vs {b:?}", a.name));
            }
        }
        None
    }
}
