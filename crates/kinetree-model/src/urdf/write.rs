//! URDF export: the XML written by hand (see the [module docs](super)).

use crate::error::ModelError;
use crate::joint::{Joint, JointKind};
use crate::link::Geometry;
use crate::model::Model;
use core::fmt::Write as _;
use kinetree_spatial::Se3;
use quick_xml::escape::escape;

/// Formats a number so that it reads back to the same `f64`.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 {
        // Also turns -0 into 0.
        return "0".into();
    }
    // `{:?}` is the shortest round-trip form and switches to exponents for tiny/huge values.
    let s = format!("{x:?}");
    s.strip_suffix(".0").map_or(s.clone(), str::to_string)
}

pub(crate) fn nums(xs: &[f64]) -> String {
    xs.iter().map(|&x| num(x)).collect::<Vec<_>>().join(" ")
}

fn origin(out: &mut String, indent: &str, p: &Se3) {
    if *p == Se3::IDENTITY {
        return;
    }
    let xyz = p.translation.to_array();
    let rpy = p.to_rpy();
    let mut attrs = String::new();
    if xyz != [0.0; 3] {
        let _ = write!(attrs, " xyz=\"{}\"", nums(&xyz));
    }
    if rpy != [0.0; 3] {
        let _ = write!(attrs, " rpy=\"{}\"", nums(&rpy));
    }
    let _ = writeln!(out, "{indent}<origin{attrs}/>");
}

fn geometry(out: &mut String, indent: &str, g: &Geometry) {
    let _ = writeln!(out, "{indent}<geometry>");
    let inner = format!("{indent}  ");
    let _ = match g {
        Geometry::Box { size } => writeln!(out, "{inner}<box size=\"{}\"/>", nums(size)),
        Geometry::Cylinder { radius, length } => writeln!(
            out,
            "{inner}<cylinder radius=\"{}\" length=\"{}\"/>",
            num(*radius),
            num(*length)
        ),
        Geometry::Capsule { radius, length } => writeln!(
            out,
            "{inner}<capsule radius=\"{}\" length=\"{}\"/>",
            num(*radius),
            num(*length)
        ),
        Geometry::Sphere { radius } => {
            writeln!(out, "{inner}<sphere radius=\"{}\"/>", num(*radius))
        }
        Geometry::Mesh { filename, scale } => {
            let scale = if *scale == [1.0; 3] {
                String::new()
            } else {
                format!(" scale=\"{}\"", nums(scale))
            };
            writeln!(
                out,
                "{inner}<mesh filename=\"{}\"{scale}/>",
                escape(filename.as_str())
            )
        }
    };
    let _ = writeln!(out, "{indent}</geometry>");
}

fn name_attr(name: Option<&String>) -> String {
    name.map_or(String::new(), |n| {
        format!(" name=\"{}\"", escape(n.as_str()))
    })
}

/// The `<limit>` values URDF can carry for a joint: `(lower, upper)` for kinds with position
/// limits, then velocity and effort.
fn limit_values(j: &Joint) -> (Option<(f64, f64)>, f64, f64) {
    let position = j
        .kind
        .has_position_limits()
        .then_some((j.limits.lower, j.limits.upper));
    (position, j.limits.velocity, j.limits.effort)
}

fn needs_v1_2(j: &Joint) -> bool {
    let (position, velocity, effort) = limit_values(j);
    position.is_some_and(|(lo, hi)| !(lo.is_finite() && hi.is_finite()))
        || !velocity.is_finite()
        || !effort.is_finite()
}

fn limit(out: &mut String, j: &Joint, v1_2: bool) {
    let (position, velocity, effort) = limit_values(j);
    if !v1_2 {
        // URDF 1.0 reads a missing <limit> as all zeros: write it only when it says more.
        let zero = position.is_none_or(|p| p == (0.0, 0.0)) && velocity == 0.0 && effort == 0.0;
        if zero {
            return;
        }
    }
    let mut attrs = String::new();
    let mut attr = |name: &str, x: f64| {
        if x.is_finite() {
            let _ = write!(attrs, " {name}=\"{}\"", num(x));
        }
    };
    if let Some((lo, hi)) = position {
        attr("lower", lo);
        attr("upper", hi);
    }
    attr("effort", effort);
    attr("velocity", velocity);
    let _ = writeln!(out, "    <limit{attrs}/>");
}

/// The root link a URDF gets when the model's root is attached to the world by a joint of its
/// own.
const WORLD_LINK: &str = "world";

impl Model {
    /// Writes the model as a URDF document that [`Model::from_urdf_str`] reads back to the same
    /// model (see the [module docs](crate::urdf) for what URDF cannot hold).
    ///
    /// A root attached to the world by a joint of its own (a yapCAD assembly's root part) is
    /// written with a massless root link named `world` holding that joint, as ROS does; it reads
    /// back with that extra link and the same kinematics and dynamics. Several such roots have
    /// no URDF form.
    ///
    /// URDF has no composite joint ([`crate::composite`]): a composite joint is written expanded,
    /// as its elementary pieces (`NAME.rz`, …) and massless virtual links (`NAME#1`, …), which
    /// read back as the same kinematics and dynamics but as separate joints. Use the JSON schema
    /// to keep it one joint.
    ///
    /// # Errors
    /// [`ModelError::UnsupportedJoint`] naming the first cylindrical joint;
    /// [`ModelError::Unsupported`] for several roots attached to the world.
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::{samples, Model, RootJoint};
    /// # fn main() -> Result<(), kinetree_model::ModelError> {
    /// let arm = samples::six_axis();
    /// let urdf = arm.to_urdf_string()?;
    /// let back = Model::from_urdf_str(&urdf, RootJoint::Fixed)?;
    /// assert_eq!(back.nq(), 6);
    /// assert_eq!(back.joint(1).limits, arm.joint(1).limits);
    /// # Ok(())
    /// # }
    /// ```
    pub fn to_urdf_string(&self) -> Result<String, ModelError> {
        // The floating root joint has no parent link: it is a load option, not written. One
        // other world-attached joint (a yapCAD assembly's root part) is written from a massless
        // root link named `world`, as ROS does; several have no URDF form (one root link).
        let world_joints: Vec<&Joint> = self
            .joints()
            .iter()
            .enumerate()
            .filter(|&(i, j)| j.parent_link.is_none() && !self.is_floating_root_joint(i))
            .map(|(_, j)| j)
            .collect();
        let world_link = match world_joints.as_slice() {
            [] => false,
            [_] if self.link_index(WORLD_LINK).is_none() => true,
            [j, ..] => {
                return Err(ModelError::Unsupported {
                    format: "URDF",
                    what: format!(
                        "joint '{}' attaches link '{}' to the world datum beside {} other root{} (a URDF has a single root link)",
                        j.name,
                        self.link(j.child_link).name,
                        world_joints.len() - 1,
                        if world_joints.len() == 2 { "" } else { "s" }
                    ),
                });
            }
        };
        let joints: Vec<&Joint> = self
            .joints()
            .iter()
            .filter(|j| j.parent_link.is_some())
            .chain(world_link.then(|| world_joints[0]))
            .collect();
        if let Some(j) = joints.iter().find(|j| j.kind == JointKind::Cylindrical) {
            return Err(ModelError::UnsupportedJoint {
                format: "URDF",
                joint: j.name.clone(),
                kind: j.kind,
            });
        }
        let v1_2 = joints.iter().any(|j| needs_v1_2(j));
        let mut out = String::from("<?xml version=\"1.0\"?>\n<!-- written by kinetree -->\n");
        let version = if v1_2 { " version=\"1.2\"" } else { "" };
        let _ = writeln!(out, "<robot name=\"{}\"{version}>", escape(self.name()));
        if world_link {
            let _ = writeln!(out, "  <link name=\"{WORLD_LINK}\"/>");
        }
        for link in self.links() {
            let name = escape(link.name.as_str());
            if link.inertial.is_none() && link.visuals.is_empty() && link.collisions.is_empty() {
                let _ = writeln!(out, "  <link name=\"{name}\"/>");
                continue;
            }
            let _ = writeln!(out, "  <link name=\"{name}\">");
            if let Some(i) = &link.inertial {
                let t = &i.inertia;
                let _ = writeln!(out, "    <inertial>");
                origin(&mut out, "      ", &i.origin);
                let _ = writeln!(out, "      <mass value=\"{}\"/>", num(i.mass));
                let _ = writeln!(
                    out,
                    "      <inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" iyz=\"{}\" izz=\"{}\"/>",
                    num(t.xx),
                    num(t.xy),
                    num(t.xz),
                    num(t.yy),
                    num(t.yz),
                    num(t.zz)
                );
                let _ = writeln!(out, "    </inertial>");
            }
            for v in &link.visuals {
                let _ = writeln!(out, "    <visual{}>", name_attr(v.name.as_ref()));
                origin(&mut out, "      ", &v.origin);
                geometry(&mut out, "      ", &v.geometry);
                if v.material.is_some() || v.color.is_some() {
                    let material = escape(v.material.as_deref().unwrap_or(""));
                    match v.color {
                        Some(c) => {
                            let _ = writeln!(
                                out,
                                "      <material name=\"{material}\">\n        <color rgba=\"{}\"/>\n      </material>",
                                nums(&c)
                            );
                        }
                        None => {
                            let _ = writeln!(out, "      <material name=\"{material}\"/>");
                        }
                    }
                }
                let _ = writeln!(out, "    </visual>");
            }
            for c in &link.collisions {
                let _ = writeln!(out, "    <collision{}>", name_attr(c.name.as_ref()));
                origin(&mut out, "      ", &c.origin);
                geometry(&mut out, "      ", &c.geometry);
                let _ = writeln!(out, "    </collision>");
            }
            let _ = writeln!(out, "  </link>");
        }
        for j in joints {
            let parent = match j.parent_link {
                Some(p) => self.link(p).name.as_str(),
                None => WORLD_LINK,
            };
            let _ = writeln!(
                out,
                "  <joint name=\"{}\" type=\"{}\">",
                escape(j.name.as_str()),
                j.kind.as_str()
            );
            origin(&mut out, "    ", &j.placement);
            let _ = writeln!(
                out,
                "    <parent link=\"{}\"/>\n    <child link=\"{}\"/>",
                escape(parent),
                escape(self.link(j.child_link).name.as_str())
            );
            // URDF's default axis is x; kinds without an axis keep whatever was read.
            if j.kind.has_axis() || j.axis != glam::DVec3::X {
                let _ = writeln!(out, "    <axis xyz=\"{}\"/>", nums(&j.axis.to_array()));
            }
            limit(&mut out, j, v1_2);
            let d = j.dynamics;
            if d.damping != 0.0 || d.friction != 0.0 {
                let _ = writeln!(
                    out,
                    "    <dynamics damping=\"{}\" friction=\"{}\"/>",
                    num(d.damping),
                    num(d.friction)
                );
            }
            if let Some(m) = &j.mimic {
                let _ = writeln!(
                    out,
                    "    <mimic joint=\"{}\" multiplier=\"{}\" offset=\"{}\"/>",
                    escape(m.joint.as_str()),
                    num(m.multiplier),
                    num(m.offset)
                );
            }
            let _ = writeln!(out, "  </joint>");
        }
        out.push_str("</robot>\n");
        Ok(out)
    }
}
