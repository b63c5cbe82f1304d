//! URDF import: the text is scanned for errors and ignored elements, then converted through
//! urdf-rs (see the [module docs](super)).

use crate::builder::{InertiaCheck, JointSpec, ModelBuilder};
use crate::error::{Issue, ModelError};
use crate::joint::{JointDynamics, JointKind, JointLimits, Mimic};
use crate::link::{Collision, Geometry, Inertial, Link, Visual};
use crate::model::{MimicMode, Model, RootJoint};
use glam::DVec3;
use kinetree_spatial::{Se3, Symmetric3};
use quick_xml::events::Event;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

impl Model {
    /// Loads a URDF file.
    ///
    /// Mesh file names (`package://…`, relative paths) are kept exactly as written.
    ///
    /// # Errors
    /// [`ModelError::Io`] when the file cannot be read, [`ModelError::Xml`] (with line and column)
    /// for malformed XML, [`ModelError::Urdf`] when urdf-rs rejects the content, and
    /// [`ModelError::Invalid`] when the robot is not a valid tree.
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::{Model, RootJoint};
    /// # fn main() -> Result<(), kinetree_model::ModelError> {
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/robots/panda.urdf");
    /// let panda = Model::from_urdf_file(path, RootJoint::Fixed)?;
    /// assert_eq!((panda.nq(), panda.nv()), (9, 9));
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_urdf_file(path: impl AsRef<Path>, root: RootJoint) -> Result<Model, ModelError> {
        let path = path.as_ref();
        let text = crate::error::read_text(path)?;
        from_urdf(&text, &LoadOptions::from(root), Some(path.to_path_buf()))
    }

    /// Loads a URDF document from a string.
    ///
    /// # Errors
    /// As [`Model::from_urdf_file`], without the file name.
    pub fn from_urdf_str(urdf: &str, root: RootJoint) -> Result<Model, ModelError> {
        from_urdf(urdf, &LoadOptions::from(root), None)
    }

    /// Loads a URDF file with explicit options (root joint, mimic coupling, inertia check).
    ///
    /// # Errors
    /// As [`Model::from_urdf_file`]; with [`MimicMode::Coupled`], a `<mimic>` naming a joint that
    /// does not exist is [`Issue::UnknownMimicTarget`](crate::Issue::UnknownMimicTarget).
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::{LoadOptions, MimicMode, Model, RootJoint};
    /// # fn main() -> Result<(), kinetree_model::ModelError> {
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/robots/panda.urdf");
    /// let options = LoadOptions { mimic: MimicMode::Coupled, ..LoadOptions::from(RootJoint::Fixed) };
    /// let panda = Model::from_urdf_file_with(path, &options)?;
    /// // The second finger follows the first: one coordinate fewer.
    /// assert_eq!((panda.nq(), panda.nv()), (8, 8));
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_urdf_file_with(
        path: impl AsRef<Path>,
        options: &LoadOptions,
    ) -> Result<Model, ModelError> {
        let path = path.as_ref();
        let text = crate::error::read_text(path)?;
        from_urdf(&text, options, Some(path.to_path_buf()))
    }

    /// Loads a URDF document from a string with explicit options.
    ///
    /// # Errors
    /// As [`Model::from_urdf_file_with`].
    pub fn from_urdf_str_with(urdf: &str, options: &LoadOptions) -> Result<Model, ModelError> {
        from_urdf(urdf, options, None)
    }
}

/// Options of the URDF loaders ([`Model::from_urdf_file_with`]). `From<RootJoint>` gives the
/// defaults for a root attachment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// How the root link is attached to the world.
    pub root_joint: RootJoint,
    /// What `<mimic>` tags do (default: independent DoFs, as in Pinocchio).
    pub mimic: MimicMode,
    /// Whether physically invalid inertias are warnings (default) or errors.
    pub inertia_check: InertiaCheck,
}

impl From<RootJoint> for LoadOptions {
    fn from(root_joint: RootJoint) -> Self {
        Self {
            root_joint,
            ..Self::default()
        }
    }
}

pub(crate) fn from_urdf(
    text: &str,
    options: &LoadOptions,
    file: Option<PathBuf>,
) -> Result<Model, ModelError> {
    let root = options.root_joint;
    let Scan {
        ignored,
        bad_numbers,
        textures,
        xacro,
    } = scan_xml(text, file.as_deref())?;
    if let Some(element) = xacro {
        return Err(xacro_error(file, &format!("it has a <{element}> element")));
    }
    // (Unexpanded xacro expressions are reported as such below.)
    let xacro_expressions = text.contains("${") || text.contains("$(");
    if !bad_numbers.is_empty() && !xacro_expressions {
        return Err(ModelError::Urdf {
            file,
            message: format!(
                "{} numeric attribute{} do{} not read as numbers: {}",
                bad_numbers.len(),
                if bad_numbers.len() == 1 { "" } else { "s" },
                if bad_numbers.len() == 1 { "es" } else { "" },
                bad_numbers.join("; ")
            ),
        });
    }
    let sanitized;
    let text = if textures.is_empty() {
        text
    } else {
        sanitized = remove_ranges(text, &textures);
        sanitized.as_str()
    };
    let robot = urdf_rs::read_from_string(text).map_err(|e| {
        if text.contains("${") || text.contains("$(") {
            // Unexpanded `${…}` or `$(arg …)` make urdf-rs complain about a number; the
            // real problem is that nobody ran xacro.
            xacro_error(
                file.clone(),
                &format!(
                    "it has ${{…}} or $(…) expressions, and reading it as URDF fails with: {e}"
                ),
            )
        } else {
            ModelError::Urdf {
                file: file.clone(),
                message: e.to_string(),
            }
        }
    })?;
    let mut b = ModelBuilder::new(robot.name.clone());
    b.root_joint(root)
        .world_parents(false)
        .mimic_mode(options.mimic)
        .inertia_check(options.inertia_check);
    for what in ignored {
        b.note_ignored(what);
    }
    let colors: HashMap<&str, [f64; 4]> = robot
        .materials
        .iter()
        .filter_map(|m| m.color.as_ref().map(|c| (m.name.as_str(), c.rgba.0)))
        .collect();
    for l in &robot.links {
        b.add_link(convert_link(l, &colors));
    }
    let joint_names: std::collections::HashSet<&str> =
        robot.joints.iter().map(|j| j.name.as_str()).collect();
    for j in &robot.joints {
        let mut spec = convert_joint(j);
        if spec.kind == JointKind::Fixed && spec.mimic.is_some() {
            // A fixed joint has nothing to couple; urdfdom and Pinocchio drop the tag too.
            spec.mimic = None;
            b.note_ignored(format!("<mimic> of fixed joint '{}'", spec.name));
        }
        let independent = options.mimic == MimicMode::Independent;
        if let Some(m) = spec
            .mimic
            .take_if(|m| independent && !joint_names.contains(m.joint.as_str()))
        {
            // Mimic joints are independent DoFs here, so a dangling tag is harmless: drop it.
            b.note_warning(Issue::UnknownMimicTarget {
                joint: spec.name.clone(),
                target: m.joint,
            });
        }
        b.add_joint(spec);
    }
    b.build()
}

fn pose(p: &urdf_rs::Pose) -> Se3 {
    Se3::from_xyz_rpy(p.xyz.0, p.rpy.0)
}

fn geometry(g: &urdf_rs::Geometry) -> Geometry {
    match g {
        urdf_rs::Geometry::Box { size } => Geometry::Box { size: size.0 },
        urdf_rs::Geometry::Cylinder { radius, length } => Geometry::Cylinder {
            radius: *radius,
            length: *length,
        },
        urdf_rs::Geometry::Capsule { radius, length } => Geometry::Capsule {
            radius: *radius,
            length: *length,
        },
        urdf_rs::Geometry::Sphere { radius } => Geometry::Sphere { radius: *radius },
        urdf_rs::Geometry::Mesh { filename, scale } => Geometry::Mesh {
            filename: filename.clone(),
            scale: scale.as_ref().map_or([1.0; 3], |s| s.0),
        },
    }
}

fn convert_link(l: &urdf_rs::Link, colors: &HashMap<&str, [f64; 4]>) -> Link {
    let i = &l.inertial;
    let inertia = Symmetric3::new(
        i.inertia.ixx,
        i.inertia.ixy,
        i.inertia.ixz,
        i.inertia.iyy,
        i.inertia.iyz,
        i.inertia.izz,
    );
    // urdf-rs fills a missing <inertial> with zeros: that is a massless link.
    let massless = i.mass.value == 0.0 && inertia == Symmetric3::ZERO;
    let inertial = (!massless).then(|| Inertial {
        origin: pose(&i.origin),
        mass: i.mass.value,
        inertia,
    });
    let visuals = l
        .visual
        .iter()
        .map(|v| {
            let material = v
                .material
                .as_ref()
                .map(|m| m.name.clone())
                .filter(|n| !n.is_empty());
            let color = v.material.as_ref().and_then(|m| {
                m.color
                    .as_ref()
                    .map(|c| c.rgba.0)
                    .or_else(|| colors.get(m.name.as_str()).copied())
            });
            Visual {
                name: v.name.clone(),
                origin: pose(&v.origin),
                geometry: geometry(&v.geometry),
                material,
                color,
            }
        })
        .collect();
    let collisions = l
        .collision
        .iter()
        .map(|c| Collision {
            name: c.name.clone(),
            origin: pose(&c.origin),
            geometry: geometry(&c.geometry),
        })
        .collect();
    Link {
        name: l.name.clone(),
        inertial,
        visuals,
        collisions,
        metadata: Default::default(),
    }
}

fn convert_joint(j: &urdf_rs::Joint) -> JointSpec {
    let kind = match j.joint_type {
        urdf_rs::JointType::Revolute => JointKind::Revolute,
        urdf_rs::JointType::Continuous => JointKind::Continuous,
        urdf_rs::JointType::Prismatic => JointKind::Prismatic,
        urdf_rs::JointType::Fixed => JointKind::Fixed,
        urdf_rs::JointType::Floating => JointKind::Floating,
        urdf_rs::JointType::Planar => JointKind::Planar,
        urdf_rs::JointType::Spherical => JointKind::Spherical,
    };
    let l = &j.limit;
    // Limits are kept as written (urdf-rs reads a missing <limit> as zeros, as urdfdom does).
    let limits = if kind.has_position_limits() {
        JointLimits {
            lower: l.lower,
            upper: l.upper,
            velocity: l.velocity,
            effort: l.effort,
        }
    } else {
        JointLimits {
            velocity: l.velocity,
            effort: l.effort,
            ..JointLimits::UNLIMITED
        }
    };
    let dynamics = j
        .dynamics
        .as_ref()
        .map_or_else(JointDynamics::default, |d| JointDynamics {
            damping: d.damping,
            friction: d.friction,
            armature: 0.0,
        });
    let mimic = j.mimic.as_ref().map(|m| Mimic {
        joint: m.joint.clone(),
        multiplier: m.multiplier.unwrap_or(1.0),
        offset: m.offset.unwrap_or(0.0),
    });
    let mut spec = JointSpec::new(
        j.name.clone(),
        kind,
        j.parent.link.clone(),
        j.child.link.clone(),
    )
    .with_placement(pose(&j.origin))
    .with_axis(DVec3::from_array(j.axis.xyz.0))
    .with_limits(limits)
    .with_dynamics(dynamics);
    spec.mimic = mimic;
    spec
}

/// What [`scan_xml`] found.
struct Scan {
    /// Human-readable descriptions of the elements kinetree does not model.
    ignored: Vec<String>,
    /// Every numeric attribute of a link, joint or material that does not read as its numbers,
    /// located (urdf-rs stops at the first, names no element, and drops a vector's bad tokens).
    bad_numbers: Vec<String>,
    /// Byte ranges of the `<texture>` elements, to be removed before urdf-rs parses the text.
    textures: Vec<std::ops::Range<usize>>,
    /// The first `<xacro:…>` element, if any: the file is xacro source, not a URDF.
    xacro: Option<String>,
}

/// Removes the byte ranges (sorted, disjoint) from `text`.
fn remove_ranges(text: &str, ranges: &[std::ops::Range<usize>]) -> String {
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    for r in ranges {
        out.push_str(&text[at..r.start]);
        at = r.end;
    }
    out.push_str(&text[at..]);
    out
}

/// Checks well-formedness and lists the elements kinetree does not model.
fn scan_xml(text: &str, file: Option<&Path>) -> Result<Scan, ModelError> {
    let mut reader = quick_xml::Reader::from_str(text);
    let mut ignored = Vec::new();
    let mut textures = Vec::new();
    // Start offset and stack depth of the `<texture>` element being skipped, if any.
    let mut open_texture: Option<(usize, usize)> = None;
    // Element names from the document root down to the current element.
    let mut stack: Vec<(String, Option<String>)> = Vec::new();
    let mut saw_robot = false;
    let mut xacro = None;
    let mut bad_numbers = Vec::new();
    loop {
        let event_start = usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX);
        let event = reader.read_event().map_err(|e| {
            let (line, column) = line_column(text, reader.error_position() as usize);
            ModelError::Xml {
                file: file.map(Path::to_path_buf),
                line,
                column,
                message: e.to_string(),
            }
        })?;
        let (start, empty) = match &event {
            Event::Start(s) => (Some(s), false),
            Event::Empty(s) => (Some(s), true),
            Event::End(_) => {
                stack.pop();
                if let Some((start, _)) = open_texture.filter(|&(_, d)| d == stack.len()) {
                    let end = usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX);
                    textures.push(start..end);
                    open_texture = None;
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let Some(s) = start else { continue };
        let tag = String::from_utf8_lossy(s.local_name().as_ref()).into_owned();
        if xacro.is_none() && s.name().as_ref().starts_with(b"xacro:") {
            xacro = Some(String::from_utf8_lossy(s.name().as_ref()).into_owned());
        }
        let name = s
            .try_get_attribute("name")
            .ok()
            .flatten()
            .and_then(|a| a.unescape_value().ok().map(|v| v.into_owned()));
        match stack.as_slice() {
            [] => saw_robot |= tag == "robot",
            [(_, _)] if !matches!(tag.as_str(), "link" | "joint" | "material") => {
                ignored.push(match &name {
                    Some(n) => format!("<{tag}> '{n}'"),
                    None => format!("<{tag}>"),
                });
            }
            [_, (parent, parent_name)] if parent == "joint" => {
                if matches!(tag.as_str(), "calibration" | "safety_controller") {
                    ignored.push(format!(
                        "<{tag}> of joint '{}'",
                        parent_name.as_deref().unwrap_or("?")
                    ));
                }
            }
            _ => {}
        }
        // The numbers of links, joints and materials (not of extension blocks like <gazebo>).
        if matches!(stack.get(1), Some((t, _)) if matches!(t.as_str(), "link" | "joint" | "material"))
        {
            for (attr, count) in numeric_attributes(&tag) {
                let Ok(Some(value)) = s.try_get_attribute(*attr) else {
                    continue;
                };
                let value = value.unescape_value().map(|v| v.into_owned());
                let value = value.unwrap_or_default();
                let tokens: Vec<&str> = value.split_whitespace().collect();
                if tokens.len() != *count || tokens.iter().any(|t| t.parse::<f64>().is_err()) {
                    let (line, column) = line_column(text, event_start);
                    let owner = stack
                        .get(1)
                        .map(|(t, n)| format!(" of {t} '{}'", n.as_deref().unwrap_or("?")))
                        .unwrap_or_default();
                    let what = if *count == 1 {
                        "a number".to_string()
                    } else {
                        format!("{count} numbers")
                    };
                    bad_numbers.push(format!(
                        "line {line}, column {column}: <{tag} {attr}=\"{value}\">{owner} is not {what}"
                    ));
                }
            }
        }
        if tag == "texture" && open_texture.is_none() && stack.len() >= 2 {
            // Textures are not modelled; urdf-rs rejects some valid ones, so they are cut out.
            let material = match stack.last() {
                Some((t, Some(n))) if t == "material" => format!(" of material '{n}'"),
                _ => String::new(),
            };
            ignored.push(format!("<texture>{material}"));
            if empty {
                let end = usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX);
                textures.push(event_start..end);
            } else {
                open_texture = Some((event_start, stack.len()));
            }
        }
        if !empty {
            // urdf-rs reads the document recursively: refuse deep nesting before it does.
            if stack.len() >= crate::MAX_XML_DEPTH {
                let (line, column) = line_column(text, event_start);
                return Err(ModelError::Xml {
                    file: file.map(Path::to_path_buf),
                    line,
                    column,
                    message: format!(
                        "elements nested deeper than {} levels",
                        crate::MAX_XML_DEPTH
                    ),
                });
            }
            stack.push((tag, name));
        }
    }
    if !saw_robot {
        return Err(ModelError::Urdf {
            file: file.map(Path::to_path_buf),
            message: "the document has no <robot> root element".into(),
        });
    }
    Ok(Scan {
        ignored,
        bad_numbers,
        textures,
        xacro,
    })
}

/// The numeric attributes of URDF element `tag` and how many numbers each holds.
fn numeric_attributes(tag: &str) -> &'static [(&'static str, usize)] {
    match tag {
        "origin" => &[("xyz", 3), ("rpy", 3)],
        "axis" => &[("xyz", 3)],
        "box" => &[("size", 3)],
        "mesh" => &[("scale", 3)],
        "color" => &[("rgba", 4)],
        "limit" => &[("lower", 1), ("upper", 1), ("effort", 1), ("velocity", 1)],
        "mass" => &[("value", 1)],
        "inertia" => &[
            ("ixx", 1),
            ("ixy", 1),
            ("ixz", 1),
            ("iyy", 1),
            ("iyz", 1),
            ("izz", 1),
        ],
        "cylinder" | "capsule" => &[("radius", 1), ("length", 1)],
        "sphere" => &[("radius", 1)],
        "dynamics" => &[("damping", 1), ("friction", 1)],
        "mimic" => &[("multiplier", 1), ("offset", 1)],
        _ => &[],
    }
}

/// The error for xacro source given as a URDF: `why` says what gave it away.
fn xacro_error(file: Option<PathBuf>, why: &str) -> ModelError {
    let how = match &file {
        Some(f) => {
            let name = f.display().to_string();
            let out = name.strip_suffix(".xacro").unwrap_or("expanded.urdf");
            format!("`xacro {name} > {out}`")
        }
        None => "`xacro file.urdf.xacro > file.urdf`".into(),
    };
    ModelError::Urdf {
        file,
        message: format!(
            "this looks like a xacro file, not a URDF ({why}): expand it first, e.g. {how}"
        ),
    }
}

fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text.as_bytes()[..offset.min(text.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = before.iter().rev().take_while(|&&b| b != b'\n').count() + 1;
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ModelBuilder;

    #[test]
    fn every_attribute_that_is_not_its_numbers_is_named_with_its_line() {
        let urdf = r#"<robot name="r">
  <link name="a"><inertial><mass value="one"/>
    <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <link name="b"/>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0 abc 0 0"/><axis xyz="0 0 1"/>
    <limit lower="abc" upper="1" effort="1" velocity="1"/></joint>
  <gazebo><origin xyz="not checked"/></gazebo>
</robot>"#;
        let e = from_urdf(urdf, &LoadOptions::default(), None).unwrap_err();
        let text = e.to_string();
        for needle in [
            "3 numeric attributes do not read as numbers",
            "line 2, column 28: <mass value=\"one\"> of link 'a' is not a number",
            // urdf-rs dropped the bad token and read (0, 0, 0).
            "line 6, column 5: <origin xyz=\"0 abc 0 0\"> of joint 'j' is not 3 numbers",
            "line 7, column 5: <limit lower=\"abc\"> of joint 'j' is not a number",
        ] {
            assert!(text.contains(needle), "{needle:?} in {text}");
        }
        assert!(!text.contains("not checked"), "{text}");
        // The same document with its numbers fixed loads.
        let fixed = urdf
            .replace("\"one\"", "\"1\"")
            .replace("0 abc 0 0", "0 0 0")
            .replace("lower=\"abc\"", "lower=\"-1\"");
        assert_eq!(
            from_urdf(&fixed, &LoadOptions::default(), None)
                .unwrap()
                .nq(),
            1
        );
    }

    #[test]
    fn deep_nesting_is_refused_before_urdf_rs_recurses_into_it() {
        // 20 000 levels overflowed the stack inside urdf-rs (the CLI aborted, Python crashed).
        let nested = |depth: usize| {
            format!(
                "<robot name=\"r\"><link name=\"a\"/>{}{}</robot>",
                "<x>".repeat(depth),
                "</x>".repeat(depth)
            )
        };
        for depth in [crate::MAX_XML_DEPTH, 20_000] {
            let e = from_urdf(&nested(depth), &LoadOptions::default(), None).unwrap_err();
            assert!(
                matches!(&e, ModelError::Xml { line: 1, message, .. } if message.contains("nested deeper than 500")),
                "{e}"
            );
        }
        // One level less is read (the unknown element is listed as ignored).
        let model = from_urdf(
            &nested(crate::MAX_XML_DEPTH - 1),
            &LoadOptions::default(),
            None,
        )
        .unwrap();
        assert_eq!(model.links().len(), 1);
    }

    const TEXTURED: &str = r#"<robot name="textured">
  <material name="skin"><texture filename="skin.png"></texture><color rgba="0 0 1 1"/></material>
  <link name="base">
    <visual>
      <geometry><box size="1 2 3"/></geometry>
      <material name="metal">
        <texture />
        <color rgba="0.5 0.5 0.5 1" />
      </material>
    </visual>
    <visual>
      <geometry><sphere radius="0.5"/></geometry>
      <material name="skin"/>
    </visual>
  </link>
</robot>"#;

    #[test]
    fn textures_are_removed_and_reported() {
        // urdf-rs alone rejects the `<texture />` without a file name.
        assert!(urdf_rs::read_from_string(TEXTURED).is_err());
        let m = Model::from_urdf_str(TEXTURED, RootJoint::Fixed).unwrap();
        let base = m.link(0);
        assert_eq!(base.visuals.len(), 2);
        assert_eq!(base.visuals[0].material.as_deref(), Some("metal"));
        assert_eq!(base.visuals[0].color, Some([0.5, 0.5, 0.5, 1.0]));
        // The colour of the global material survives the removal of its texture.
        assert_eq!(base.visuals[1].color, Some([0.0, 0.0, 1.0, 1.0]));
        assert_eq!(
            m.ignored(),
            [
                "<texture> of material 'skin'",
                "<texture> of material 'metal'"
            ]
        );
    }

    #[test]
    fn a_robot_without_links_is_the_empty_model() {
        let urdf = r#"<?xml version="1.0"?>
<robot xmlns:xacro="http://wiki.ros.org/xacro">
  <!-- nothing here, as in example-robot-data's ur3.urdf -->
</robot>"#;
        for root in [RootJoint::Fixed, RootJoint::Floating] {
            let m = Model::from_urdf_str(urdf, root).unwrap();
            assert_eq!((m.nq(), m.nv(), m.nbodies()), (0, 0, 1));
            assert!(m.links().is_empty() && m.joints().is_empty() && m.frames().is_empty());
            assert_eq!(m.root_link(), None);
            // There is nothing to attach a floating joint to.
            assert_eq!(m.root_joint(), RootJoint::Fixed);
            assert_eq!(m.total_mass(), 0.0);
            assert_eq!(m.moving_joints().count(), 0);
            assert_eq!(m.to_string(), " (nq = 0, nv = 0)\n");
            let back = Model::from_urdf_str(&m.to_urdf_string().unwrap(), root).unwrap();
            assert_eq!(m.first_difference(&back, 0.0), None);
            let json = m.to_json_string(&crate::JsonOptions::default()).unwrap();
            assert_eq!(Model::from_json_str(&json, None).unwrap(), m);
        }
    }

    const DANGLING_MIMIC: &str = r#"<robot name="hand">
  <link name="palm"/><link name="f1"/><link name="f2"/>
  <joint name="q1" type="revolute"><parent link="palm"/><child link="f1"/>
    <limit lower="0" upper="1" effort="1" velocity="1"/></joint>
  <joint name="q2" type="revolute"><parent link="f1"/><child link="f2"/>
    <limit lower="0" upper="1" effort="1" velocity="1"/>
    <mimic joint="index_q1" multiplier="1.05"/></joint>
</robot>"#;

    #[test]
    fn a_dangling_mimic_is_dropped_with_a_warning() {
        let m = Model::from_urdf_str(DANGLING_MIMIC, RootJoint::Fixed).unwrap();
        assert_eq!((m.nq(), m.nv()), (2, 2));
        let q2 = m.joint(m.joint_index("q2").unwrap());
        assert_eq!(q2.mimic, None);
        assert_eq!(
            m.warnings(),
            [Issue::UnknownMimicTarget {
                joint: "q2".into(),
                target: "index_q1".into()
            }]
        );
        assert_eq!(
            m.warnings()[0].to_string(),
            "joint 'q2' mimics unknown joint 'index_q1'"
        );
    }

    #[test]
    fn the_builder_still_rejects_an_unknown_mimic_target() {
        let mut b = ModelBuilder::new("hand");
        b.add_link(Link::new("palm")).add_link(Link::new("f1"));
        b.add_joint(
            JointSpec::new("q2", JointKind::Revolute, "palm", "f1")
                .with_mimic("index_q1", 1.0, 0.0),
        );
        let e = b.build().unwrap_err();
        assert_eq!(
            e.issues(),
            [Issue::UnknownMimicTarget {
                joint: "q2".into(),
                target: "index_q1".into()
            }]
        );
    }

    #[test]
    fn a_valid_mimic_is_kept() {
        let urdf = DANGLING_MIMIC.replace("index_q1", "q1");
        let m = Model::from_urdf_str(&urdf, RootJoint::Fixed).unwrap();
        let q2 = m.joint(m.joint_index("q2").unwrap());
        assert_eq!(
            q2.mimic,
            Some(Mimic {
                joint: "q1".into(),
                multiplier: 1.05,
                offset: 0.0
            })
        );
        assert!(m.warnings().is_empty());
    }
}
