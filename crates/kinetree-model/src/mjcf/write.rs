//! MJCF export ([`Model::to_mjcf_string`]): the model as a MuJoCo XML document that MuJoCo
//! compiles to the same tree, masses and coordinates.

use crate::error::ModelError;
use crate::joint::{Joint, JointKind, plane_basis};
use crate::link::{Geometry, Link};
use crate::model::{Model, RootJoint};
use crate::urdf::write::{num, nums};
use core::fmt::Write as _;
use glam::{DQuat, DVec3};
use kinetree_spatial::Se3;
use quick_xml::escape::escape;
use std::collections::{BTreeMap, HashSet};

use super::read::WORLD_BODY;

/// `pos="…" quat="…"` of a placement, leaving out the identity parts.
fn placement_attrs(p: &Se3) -> String {
    let mut s = String::new();
    if p.translation != DVec3::ZERO {
        let _ = write!(s, " pos=\"{}\"", nums(&p.translation.to_array()));
    }
    let q = DQuat::from_mat3(&p.rotation).normalize();
    if q != DQuat::IDENTITY {
        let _ = write!(s, " quat=\"{}\"", nums(&[q.w, q.x, q.y, q.z]));
    }
    s
}

fn name_attr(name: &str) -> String {
    format!(" name=\"{}\"", escape(name))
}

struct Writer<'m> {
    model: &'m Model,
    out: String,
    meshes: BTreeMap<(String, [u64; 3]), String>,
    sites: HashSet<String>,
    geom_names: HashSet<String>,
    equalities: Vec<String>,
}

impl Writer<'_> {
    fn mesh_name(&mut self, filename: &str, scale: [f64; 3]) -> String {
        let key = (filename.to_string(), scale.map(f64::to_bits));
        let n = self.meshes.len();
        self.meshes
            .entry(key)
            .or_insert_with(|| format!("mesh{n}"))
            .clone()
    }

    fn geoms(&mut self, link: &Link, indent: &str) {
        let collisions: Vec<(&Option<String>, &Se3, &Geometry, bool)> = link
            .collisions
            .iter()
            .map(|c| (&c.name, &c.origin, &c.geometry, true))
            .chain(
                link.visuals
                    .iter()
                    .map(|v| (&v.name, &v.origin, &v.geometry, false)),
            )
            .collect();
        let colors: Vec<Option<[f64; 4]>> = link
            .collisions
            .iter()
            .map(|_| None)
            .chain(link.visuals.iter().map(|v| v.color))
            .collect();
        for ((name, origin, geometry, collides), rgba) in collisions.into_iter().zip(colors) {
            let (kind, size) = match geometry {
                Geometry::Box { size } => ("box", nums(&size.map(|s| s / 2.0))),
                Geometry::Cylinder { radius, length } => {
                    ("cylinder", nums(&[*radius, length / 2.0]))
                }
                Geometry::Capsule { radius, length } => ("capsule", nums(&[*radius, length / 2.0])),
                Geometry::Sphere { radius } => ("sphere", num(*radius)),
                Geometry::Mesh { filename, scale } => {
                    let mesh = self.mesh_name(filename, *scale);
                    ("mesh", mesh)
                }
            };
            let shape = if kind == "mesh" {
                format!(" type=\"mesh\" mesh=\"{size}\"")
            } else {
                format!(" type=\"{kind}\" size=\"{size}\"")
            };
            let name = match name.as_deref() {
                Some(n) => {
                    let mut unique = format!("{}/{n}", link.name);
                    let mut k = 1;
                    while !self.geom_names.insert(unique.clone()) {
                        unique = format!("{}/{n}#{k}", link.name);
                        k += 1;
                    }
                    name_attr(&unique)
                }
                None => String::new(),
            };
            // Collision shapes in group 0; visuals in group 1 and out of collisions.
            let role = if collides {
                String::new()
            } else {
                " group=\"1\" contype=\"0\" conaffinity=\"0\"".to_string()
            };
            let color = rgba
                .map(|c| format!(" rgba=\"{}\"", nums(&c)))
                .unwrap_or_default();
            let _ = writeln!(
                self.out,
                "{indent}<geom{name}{shape}{}{role}{color}/>",
                placement_attrs(origin)
            );
        }
    }

    fn inertial(&mut self, link: &Link, indent: &str) {
        let Some(i) = &link.inertial else {
            return;
        };
        // The principal moments and axes (MuJoCo refuses a `fullinertia` with a zero moment,
        // which point masses and rods have; `diaginertia` takes it). Rounding can leave a zero
        // moment a hair below zero: it is written as 0.
        let (moments, axes) = super::inertia::principal_axes(&i.inertia.rotate(&i.origin.rotation));
        let frame = Se3::new(axes, i.origin.translation);
        let q = DQuat::from_mat3(&frame.rotation).normalize();
        let _ = writeln!(
            self.out,
            "{indent}<inertial pos=\"{}\" quat=\"{}\" mass=\"{}\" diaginertia=\"{}\"/>",
            nums(&i.origin.translation.to_array()),
            nums(&[q.w, q.x, q.y, q.z]),
            num(i.mass),
            nums(&moments.map(|m| m.max(0.0)))
        );
    }

    fn sites(&mut self, link: usize, indent: &str) {
        for f in self.model.frames().iter().filter(|f| f.link == link) {
            let mut name = f.name.clone();
            if !self.sites.insert(name.clone()) {
                name = format!("{}/{}", self.model.link(link).name, f.name);
                self.sites.insert(name.clone());
            }
            let _ = writeln!(
                self.out,
                "{indent}<site{}{}/>",
                name_attr(&name),
                placement_attrs(&f.placement)
            );
        }
    }

    /// The MuJoCo joint(s) of `j`, whose frame sits at `body_from_joint` in the body (the
    /// identity unless joints were merged into one body).
    fn joint(&mut self, j: &Joint, indent: &str, body_from_joint: &Se3) -> Result<(), ModelError> {
        let mut dynamics = String::new();
        if body_from_joint.translation != DVec3::ZERO {
            let _ = write!(
                dynamics,
                " pos=\"{}\"",
                nums(&body_from_joint.translation.to_array())
            );
        }
        for (attr, x) in [
            ("damping", j.dynamics.damping),
            ("frictionloss", j.dynamics.friction),
            ("armature", j.dynamics.armature),
        ] {
            if x != 0.0 {
                let _ = write!(dynamics, " {attr}=\"{}\"", num(x));
            }
        }
        let range = |lo: f64, hi: f64| {
            if lo.is_finite() && hi.is_finite() && lo < hi {
                format!(" limited=\"true\" range=\"{} {}\"", num(lo), num(hi))
            } else {
                " limited=\"false\"".to_string()
            }
        };
        let axis = |a: DVec3| {
            format!(
                " axis=\"{}\"",
                nums(&body_from_joint.transform_vector(a).to_array())
            )
        };
        let name = |suffix: &str| name_attr(&format!("{}{suffix}", j.name));
        let lines: Vec<String> = match j.kind {
            JointKind::Fixed => Vec::new(),
            JointKind::Revolute => vec![format!(
                "<joint{} type=\"hinge\"{}{}{dynamics}/>",
                name(""),
                axis(j.axis),
                range(j.limits.lower, j.limits.upper)
            )],
            JointKind::Continuous => vec![format!(
                "<joint{} type=\"hinge\"{} limited=\"false\"{dynamics}/>",
                name(""),
                axis(j.axis)
            )],
            JointKind::Prismatic => vec![format!(
                "<joint{} type=\"slide\"{}{}{dynamics}/>",
                name(""),
                axis(j.axis),
                range(j.limits.lower, j.limits.upper)
            )],
            JointKind::Spherical => {
                vec![format!("<joint{} type=\"ball\"{dynamics}/>", name(""))]
            }
            JointKind::Floating => vec![format!("<freejoint{}/>", name(""))],
            JointKind::Cylindrical => vec![
                format!(
                    "<joint{} type=\"slide\"{}{}{dynamics}/>",
                    name(":slide"),
                    axis(j.axis),
                    range(j.limits.lower, j.limits.upper)
                ),
                format!(
                    "<joint{} type=\"hinge\"{}{}{dynamics}/>",
                    name(":hinge"),
                    axis(j.axis),
                    range(j.limits.lower, j.limits.upper)
                ),
            ],
            JointKind::Planar => {
                let (u, w, n) = plane_basis(j.axis);
                vec![
                    format!(
                        "<joint{} type=\"slide\"{} limited=\"false\"{dynamics}/>",
                        name(":x"),
                        axis(u)
                    ),
                    format!(
                        "<joint{} type=\"slide\"{} limited=\"false\"{dynamics}/>",
                        name(":y"),
                        axis(w)
                    ),
                    format!(
                        "<joint{} type=\"hinge\"{} limited=\"false\"{dynamics}/>",
                        name(":angle"),
                        axis(n)
                    ),
                ]
            }
        };
        for line in lines {
            let _ = writeln!(self.out, "{indent}{line}");
        }
        if let Some(m) = &j.mimic {
            self.equalities.push(format!(
                "<joint joint1=\"{}\" joint2=\"{}\" polycoef=\"{} {} 0 0 0\"/>",
                escape(&j.name),
                escape(&m.joint),
                num(m.offset),
                num(m.multiplier)
            ));
        }
        Ok(())
    }

    /// The one child joint of `link` when MuJoCo can carry it in the same body as the joints in
    /// `chain` before it: `link` is an empty massless link (as the MJCF reader makes between a
    /// body's joints), the joint is not a free joint, no rotation follows a ball joint (MuJoCo
    /// forbids it, and a ball's axes must stay those of the body), and the body keeps at most
    /// six degrees of freedom.
    fn merged_next(&self, link: usize, chain: &[usize]) -> Option<usize> {
        let m = self.model;
        let l = m.link(link);
        let empty = l
            .inertial
            .is_none_or(|i| i.mass == 0.0 && i.inertia == kinetree_spatial::Symmetric3::ZERO)
            && l.visuals.is_empty()
            && l.collisions.is_empty()
            && !m.frames().iter().any(|f| f.link == link);
        let &[next] = m.child_joints(link) else {
            return None;
        };
        let j = m.joint(next);
        let after_ball = chain
            .iter()
            .any(|&c| m.joint(c).kind == JointKind::Spherical);
        let rotates = !matches!(j.kind, JointKind::Fixed | JointKind::Prismatic)
            || j.placement.rotation != glam::DMat3::IDENTITY;
        let dofs: usize = chain.iter().map(|&c| m.joint(c).kind.nv()).sum::<usize>() + j.kind.nv();
        (empty && j.kind != JointKind::Floating && !(after_ball && rotates) && dofs <= 6)
            .then_some(next)
    }

    /// The body of link `link`, entered through `joint` (none for the root link). Empty massless
    /// links between moving joints are merged away: their joints go into the body of the first
    /// link after them that has something of its own, each at its anchor in that body.
    fn body(&mut self, link: usize, joint: Option<usize>, depth: usize) -> Result<(), ModelError> {
        let indent = "  ".repeat(depth + 2);
        let m = self.model;
        let free = joint.is_some_and(|j| m.joint(j).kind == JointKind::Floating);
        if let Some(j) = joint.map(|j| m.joint(j))
            && free
            && (j.placement != Se3::IDENTITY || depth > 0)
        {
            return Err(ModelError::Unsupported {
                format: "MJCF",
                what: format!(
                    "floating joint '{}' is not attached to the world at the identity (a MuJoCo free joint is)",
                    j.name
                ),
            });
        }
        let mut chain: Vec<usize> = joint.into_iter().collect();
        let mut end = link;
        if joint.is_some() && !free {
            while let Some(next) = self.merged_next(end, &chain) {
                chain.push(next);
                end = m.joint(next).child_link;
            }
        }
        let moving = chain.iter().rev().find(|&&j| m.joint(j).kind.is_moving());
        if let Some(&j) = moving
            && !carries_mass(m, end)
        {
            return Err(ModelError::Unsupported {
                format: "MJCF",
                what: format!(
                    "joint '{}' moves link '{}', which has no mass and inertia of its own nor in a link welded to it (MuJoCo refuses such bodies)",
                    m.joint(j).name,
                    m.link(end).name
                ),
            });
        }
        let placement = chain
            .iter()
            .fold(Se3::IDENTITY, |acc, &j| acc * m.joint(j).placement);
        let _ = writeln!(
            self.out,
            "{indent}<body{}{}>",
            name_attr(&m.link(end).name),
            if free {
                String::new()
            } else {
                placement_attrs(&placement)
            }
        );
        let inner = format!("{indent}  ");
        for (k, &j) in chain.iter().enumerate() {
            // The joint's frame seen from the body: the placements after it, inverted.
            let after = chain[k + 1..]
                .iter()
                .fold(Se3::IDENTITY, |acc, &c| acc * m.joint(c).placement);
            let j = m.joint(j).clone();
            self.joint(&j, &inner, &after.inverse())?;
        }
        let l = m.link(end);
        self.inertial(l, &inner);
        self.geoms(l, &inner);
        self.sites(end, &inner);
        for &c in m.child_joints(end) {
            let child = m.joint(c).child_link;
            self.body(child, Some(c), depth + 1)?;
        }
        let _ = writeln!(self.out, "{indent}</body>");
        Ok(())
    }
}

/// Whether `link`, or a link welded to it by fixed joints, has a mass and principal moments of
/// at least MuJoCo's `mjMINVAL` (1e-15).
fn carries_mass(model: &Model, link: usize) -> bool {
    let own = model
        .link(link)
        .inertial
        .is_some_and(|i| i.mass >= 1e-15 && i.inertia.eigenvalues().iter().all(|m| *m >= 1e-15));
    own || model.child_joints(link).iter().any(|&j| {
        model.joint(j).kind == JointKind::Fixed && carries_mass(model, model.joint(j).child_link)
    })
}

impl Model {
    /// Writes the model as MJCF (MuJoCo XML) that MuJoCo compiles to the same tree: every link
    /// is a body with its name, every joint a MuJoCo joint with its name, limits, damping,
    /// friction loss and armature, named frames are sites, visuals and collision shapes are
    /// geoms (collision shapes in group 0, visuals in group 1 without contacts), and inertias are
    /// written out (`inertiafromgeom="false"`, so geoms add no mass). A root link called `world`
    /// is MuJoCo's world body; any other root link is a body under it, with a `<freejoint>` when
    /// the model floats. Mimic joints become `<equality><joint>` couplings.
    ///
    /// Joints MuJoCo has no single form for are written as several joints in one body, exactly:
    /// a cylindrical joint as a slide and a hinge (`<name>:slide`, `<name>:hinge`), a planar
    /// joint as two slides and a hinge (`<name>:x`, `<name>:y`, `<name>:angle`; `q` is the same,
    /// MuJoCo's velocities are the rates of `q`).
    ///
    /// # Errors
    /// [`ModelError::Unsupported`] for a floating joint that is not attached to the world at the
    /// identity (a MuJoCo free joint always is), and for a moving link that has no mass or
    /// inertia of its own nor in a link welded to it (MuJoCo refuses such bodies).
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::{Model, RootJoint};
    /// # fn main() -> Result<(), kinetree_model::ModelError> {
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/robots/panda.urdf");
    /// let panda = Model::from_urdf_file(path, RootJoint::Fixed)?;
    /// let back = Model::from_mjcf_str(&panda.to_mjcf_string()?)?;
    /// assert_eq!((back.nq(), back.nv()), (9, 9));
    /// # Ok(())
    /// # }
    /// ```
    pub fn to_mjcf_string(&self) -> Result<String, ModelError> {
        let mut w = Writer {
            model: self,
            out: String::new(),
            meshes: BTreeMap::new(),
            sites: HashSet::new(),
            geom_names: HashSet::new(),
            equalities: Vec::new(),
        };
        let mut body = String::new();
        std::mem::swap(&mut w.out, &mut body);
        for root in self.root_links() {
            let parent_joint = self.parent_joint(root);
            let is_world = self.link(root).name == WORLD_BODY
                && parent_joint.is_none()
                && self.root_joint() == RootJoint::Fixed;
            if is_world {
                let l = self.link(root);
                w.geoms(l, "    ");
                w.sites(root, "    ");
                for &c in self.child_joints(root) {
                    let child = self.joint(c).child_link;
                    w.body(child, Some(c), 0)?;
                }
            } else {
                w.body(root, parent_joint, 0)?;
            }
        }
        std::mem::swap(&mut w.out, &mut body);
        let mut out = String::new();
        let _ = writeln!(out, "<mujoco model=\"{}\">", escape(self.name()));
        let _ = writeln!(
            out,
            "  <compiler angle=\"radian\" autolimits=\"true\" inertiafromgeom=\"false\"/>"
        );
        let _ = writeln!(
            out,
            "  <option gravity=\"{}\"/>",
            nums(&self.gravity().to_array())
        );
        if !w.meshes.is_empty() {
            let _ = writeln!(out, "  <asset>");
            for ((file, scale), name) in &w.meshes {
                let _ = writeln!(
                    out,
                    "    <mesh name=\"{name}\" file=\"{}\" scale=\"{}\"/>",
                    escape(file),
                    nums(&scale.map(f64::from_bits))
                );
            }
            let _ = writeln!(out, "  </asset>");
        }
        let _ = writeln!(out, "  <worldbody>");
        out.push_str(&body);
        let _ = writeln!(out, "  </worldbody>");
        if !w.equalities.is_empty() {
            let _ = writeln!(out, "  <equality>");
            for e in &w.equalities {
                let _ = writeln!(out, "    {e}");
            }
            let _ = writeln!(out, "  </equality>");
        }
        let _ = writeln!(out, "</mujoco>");
        Ok(out)
    }
}
