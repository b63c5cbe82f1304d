//! SDFormat import: the document and its `<include>`s (`include.rs`), then the models' frame
//! graph (`graph.rs`), then links, joints and frames handed to [`ModelBuilder`].

use super::SdfOptions;
use super::graph::{Graph, Kind, Node, Scope};
use super::include::{Files, expand_includes};
use crate::builder::{FrameSpec, JointSpec, ModelBuilder};
use crate::composite::{Axis, CompositeJointSpec, Factor};
use crate::error::ModelError;
use crate::joint::{JointDynamics, JointKind, JointLimits};
use crate::link::{Collision, Geometry, Inertial, Link, Visual};
use crate::model::{Model, RootJoint};
use crate::xml_tree::{self, Element, MAX_XML_DEPTH};
use glam::{DMat3, DQuat, DVec3};
use kinetree_spatial::{Se3, Symmetric3};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// Largest magnitude accepted for a length, mass or inertia: anything beyond is a typo or a
/// unit mistake, refused rather than loaded.
pub(crate) const ABSURD: f64 = 1e9;

/// SDFormat's "no limit" for joint positions (`<lower>`/`<upper>` defaults): bounds at or beyond
/// it are infinite.
const UNBOUNDED: f64 = 1e16;

/// A failure located at an element.
pub(crate) struct Located {
    pub(crate) file: usize,
    pub(crate) line: usize,
    pub(crate) element: String,
    pub(crate) message: String,
}

pub(crate) type Res<T> = Result<T, Located>;

pub(crate) fn fail<T>(e: &Element, message: impl Into<String>) -> Res<T> {
    Err(Located {
        file: e.file,
        line: e.line,
        element: e.name.clone(),
        message: message.into(),
    })
}

/// SDFormat's version, `(major, minor)`.
pub(crate) type Version = (u32, u32);

/// The newest version this reader knows; a document without one is read as it.
pub(crate) const NEWEST: Version = (1, 11);

pub(crate) fn parse_version(e: &Element) -> Res<Version> {
    let Some(v) = e.attr("version") else {
        return Ok(NEWEST);
    };
    let mut parts = v.trim().split('.');
    let major = parts.next().and_then(|x| x.parse::<u32>().ok());
    let minor = parts.next().map_or(Some(0), |x| x.parse::<u32>().ok());
    match (major, minor) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => fail(e, format!("version '{v}' is not a number like 1.7")),
    }
}

fn child<'a>(e: &'a Element, name: &str) -> Option<&'a Element> {
    e.children.iter().find(|c| c.name == name)
}

pub(crate) fn numbers(e: &Element) -> Res<Vec<f64>> {
    let mut out = Vec::new();
    for word in e.text.split_ascii_whitespace() {
        match word.parse::<f64>() {
            Ok(x) if x.is_finite() => out.push(x),
            Ok(_) => return fail(e, format!("'{word}' is not a finite number")),
            Err(_) => return fail(e, format!("'{word}' is not a number")),
        }
    }
    Ok(out)
}

fn exact<const N: usize>(e: &Element) -> Res<[f64; N]> {
    let v = numbers(e)?;
    match <[f64; N]>::try_from(v.as_slice()) {
        Ok(a) => Ok(a),
        Err(_) => fail(e, format!("needs {N} numbers, got {}", v.len())),
    }
}

/// The number in child `name` of `e`, or `default` when there is none.
fn number(e: &Element, name: &str, default: f64) -> Res<f64> {
    match child(e, name) {
        Some(c) => Ok(exact::<1>(c)?[0]),
        None => Ok(default),
    }
}

fn not_absurd(e: &Element, what: &str, values: &[f64]) -> Res<()> {
    match values.iter().find(|x| x.abs() > ABSURD) {
        Some(x) => fail(
            e,
            format!("{what} {x} is absurd (more than {ABSURD:e} in SI units)"),
        ),
        None => Ok(()),
    }
}

pub(crate) fn parse_bool(e: &Element) -> Res<bool> {
    match e.text.trim() {
        "true" | "1" => Ok(true),
        "false" | "0" => Ok(false),
        other => fail(e, format!("'{other}' is not true, false, 1 or 0")),
    }
}

/// A `<pose>`: the transform and the frame it is relative to (`None`: the element's default).
pub(crate) fn read_pose(p: &Element, version: Version) -> Res<(Se3, Option<String>)> {
    let v = numbers(p)?;
    let degrees = match p.attr("degrees") {
        None => false,
        Some("true" | "1") => true,
        Some("false" | "0") => false,
        Some(other) => return fail(p, format!("degrees '{other}' is not true or false")),
    };
    let pose = match p.attr("rotation_format").unwrap_or("euler_rpy") {
        "euler_rpy" => match v.len() {
            0 => Se3::IDENTITY,
            6 => {
                let k = if degrees { 1f64.to_radians() } else { 1.0 };
                Se3::from_xyz_rpy([v[0], v[1], v[2]], [v[3] * k, v[4] * k, v[5] * k])
            }
            n => {
                return fail(
                    p,
                    format!("a pose needs 6 numbers (x y z roll pitch yaw), got {n}"),
                );
            }
        },
        "quat_xyzw" => {
            if v.len() != 7 {
                return fail(
                    p,
                    format!("a quat_xyzw pose needs 7 numbers, got {}", v.len()),
                );
            }
            let q = DQuat::from_xyzw(v[3], v[4], v[5], v[6]);
            let n = q.length();
            if n < 1e-12 {
                return fail(p, "the quaternion is zero");
            }
            Se3::new(DMat3::from_quat(q / n), DVec3::new(v[0], v[1], v[2]))
        }
        other => {
            return fail(
                p,
                format!("rotation_format '{other}' is not euler_rpy or quat_xyzw"),
            );
        }
    };
    not_absurd(p, "pose value", &v[..v.len().min(3)])?;
    let relative_to = if version >= (1, 7) {
        p.attr("relative_to")
    } else {
        p.attr("frame")
    }
    .filter(|s| !s.is_empty())
    .map(str::to_string);
    Ok((pose, relative_to))
}

/// A link's visual or collision: its pose as written and its shape.
struct Shape<'a> {
    e: &'a Element,
    name: Option<String>,
    pose: Se3,
    relative_to: Option<String>,
    geometry: Option<Geometry>,
}

struct LinkData<'a> {
    node: usize,
    inertial: Option<(Inertial, Option<String>, &'a Element)>,
    visuals: Vec<Shape<'a>>,
    collisions: Vec<Shape<'a>>,
}

/// SDFormat joint types kinetree reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SdfJoint {
    Fixed,
    Revolute,
    Continuous,
    Prismatic,
    Ball,
    Universal,
}

/// One `<axis>` or `<axis2>`.
struct AxisData<'a> {
    e: &'a Element,
    xyz: DVec3,
    expressed_in: Option<String>,
    /// `use_parent_model_frame` (SDFormat ≤ 1.6).
    model_frame: bool,
    limits: JointLimits,
    dynamics: JointDynamics,
    /// `<mimic joint=…>` (SDFormat 1.11): the leader as written, the multiplier, and the offset
    /// with the reference folded in (`q = multiplier · q_leader + offset`).
    mimic: Option<(String, f64, f64, &'a Element)>,
}

struct JointData<'a> {
    node: usize,
    kind: SdfJoint,
    parent: (String, &'a Element),
    child: (String, &'a Element),
    axes: Vec<AxisData<'a>>,
}

/// Reads the document into the frame graph plus what each link and joint carries.
struct Reader<'a> {
    files: &'a Files,
    options: &'a SdfOptions,
    graph: Graph<'a>,
    links: Vec<LinkData<'a>>,
    joints: Vec<JointData<'a>>,
    ignored: BTreeMap<String, usize>,
    notes: Vec<String>,
    gravity: Option<DVec3>,
}

/// Model children read elsewhere or with no effect on kinematics and dynamics.
const MODEL_IGNORED: [&str; 6] = [
    "plugin",
    "self_collide",
    "allow_auto_disable",
    "enable_wind",
    "gripper",
    "gazebo",
];

/// Link children with no effect on kinematics and dynamics.
const LINK_IGNORED: [&str; 14] = [
    "sensor",
    "light",
    "projector",
    "audio_source",
    "audio_sink",
    "battery",
    "particle_emitter",
    "must_be_base_link",
    "gravity",
    "self_collide",
    "kinematic",
    "enable_wind",
    "velocity_decay",
    "visualize",
];

impl<'a> Reader<'a> {
    fn version(&self, e: &Element) -> Version {
        self.files.version(e.file)
    }

    fn ignore(&mut self, what: impl Into<String>) {
        *self.ignored.entry(what.into()).or_default() += 1;
    }

    /// The `<pose>` child of `e`, if any.
    fn pose_of(&self, e: &'a Element) -> Res<(Se3, Option<String>)> {
        let poses: Vec<&Element> = e.children.iter().filter(|c| c.name == "pose").collect();
        match poses.as_slice() {
            [] => Ok((Se3::IDENTITY, None)),
            [p] => read_pose(p, self.version(p)),
            [_, second, ..] => fail(second, format!("<{}> has more than one <pose>", e.name)),
        }
    }

    fn name_of(&self, e: &'a Element) -> Res<String> {
        match e.attr("name").map(str::trim) {
            Some(n) if !n.is_empty() => {
                if n == "world" || n.starts_with("__") && n.ends_with("__") {
                    return fail(e, format!("the name '{n}' is reserved"));
                }
                Ok(n.to_string())
            }
            _ => fail(e, format!("<{}> needs a name attribute", e.name)),
        }
    }

    /// Reads `<model>` `e` declared in `scope`, with `prefix` before its items' names.
    fn read_model(
        &mut self,
        e: &'a Element,
        scope: usize,
        prefix: String,
        parent_static: bool,
        depth: usize,
    ) -> Res<()> {
        if depth > MAX_XML_DEPTH {
            return fail(
                e,
                format!("models nested deeper than {MAX_XML_DEPTH} levels"),
            );
        }
        let name = self.name_of(e)?;
        let (pose, relative_to) = self.pose_of(e)?;
        let is_static = match child(e, "static") {
            Some(s) => parse_bool(s)? || parent_static,
            None => parent_static,
        };
        let node = self.graph.add_node(Node {
            kind: Kind::Model,
            scope,
            name: name.clone(),
            e,
            pose,
            relative_to,
            attached_to: None,
            parent: usize::MAX,
            inner: None,
        })?;
        let inner = self.graph.add_scope(Scope {
            e,
            node,
            prefix: prefix.clone(),
            names: HashMap::new(),
            links: Vec::new(),
            models: Vec::new(),
            is_static,
            canonical: e.attr("canonical_link").map(str::to_string),
            placement_frame: e.attr("placement_frame").map(str::to_string),
        });
        self.graph.nodes[node].inner = Some(inner);
        self.graph.scopes[scope].models.push(inner);
        for c in &e.children {
            match c.name.as_str() {
                "link" => self.read_link(c, inner)?,
                "joint" => self.read_joint(c, inner)?,
                "frame" => self.read_frame(c, inner)?,
                "model" => {
                    let nested = format!("{prefix}{}::", self.name_of(c)?);
                    self.read_model(c, inner, nested, is_static, depth + 1)?;
                }
                "pose" | "static" => {}
                other if MODEL_IGNORED.contains(&other) => self.ignore(format!("model/{other}")),
                other => self.ignore(format!("model/{other} (unknown element)")),
            }
        }
        Ok(())
    }

    fn read_frame(&mut self, e: &'a Element, scope: usize) -> Res<()> {
        let name = self.name_of(e)?;
        let (pose, relative_to) = self.pose_of(e)?;
        self.graph.add_node(Node {
            kind: Kind::Frame,
            scope,
            name,
            e,
            pose,
            relative_to,
            attached_to: e
                .attr("attached_to")
                .filter(|s| !s.is_empty())
                .map(str::to_string),
            parent: usize::MAX,
            inner: None,
        })?;
        Ok(())
    }

    fn read_link(&mut self, e: &'a Element, scope: usize) -> Res<()> {
        let name = self.name_of(e)?;
        let (pose, relative_to) = self.pose_of(e)?;
        let node = self.graph.add_node(Node {
            kind: Kind::Link,
            scope,
            name,
            e,
            pose,
            relative_to,
            attached_to: None,
            parent: usize::MAX,
            inner: None,
        })?;
        self.graph.scopes[scope].links.push(node);
        let mut link = LinkData {
            node,
            inertial: None,
            visuals: Vec::new(),
            collisions: Vec::new(),
        };
        for c in &e.children {
            match c.name.as_str() {
                "pose" => {}
                "inertial" => {
                    if link.inertial.is_some() {
                        return fail(c, "a link has at most one <inertial>");
                    }
                    let (inertial, relative_to) = self.read_inertial(c)?;
                    link.inertial = Some((inertial, relative_to, c));
                }
                "visual" => {
                    let s = self.read_shape(c)?;
                    link.visuals.push(s);
                }
                "collision" => {
                    let s = self.read_shape(c)?;
                    link.collisions.push(s);
                }
                other if LINK_IGNORED.contains(&other) => self.ignore(format!("link/{other}")),
                other => self.ignore(format!("link/{other} (unknown element)")),
            }
        }
        self.links.push(link);
        Ok(())
    }

    fn read_inertial(&mut self, e: &'a Element) -> Res<(Inertial, Option<String>)> {
        let mut mass = 1.0;
        let mut inertia = Symmetric3::from_diagonal(DVec3::ONE);
        let mut origin = Se3::IDENTITY;
        let mut relative_to = None;
        for c in &e.children {
            match c.name.as_str() {
                "mass" => {
                    mass = exact::<1>(c)?[0];
                    if mass < 0.0 {
                        return fail(c, format!("negative mass {mass}"));
                    }
                    not_absurd(c, "mass", &[mass])?;
                }
                "pose" => (origin, relative_to) = read_pose(c, self.version(c))?,
                "inertia" => {
                    let mut m = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
                    for (k, key) in ["ixx", "iyy", "izz", "ixy", "ixz", "iyz"]
                        .iter()
                        .enumerate()
                    {
                        m[k] = number(c, key, m[k])?;
                    }
                    if let Some(u) = c.children.iter().find(|u| {
                        !["ixx", "iyy", "izz", "ixy", "ixz", "iyz"].contains(&u.name.as_str())
                    }) {
                        return fail(u, format!("unknown element <{}> in <inertia>", u.name));
                    }
                    not_absurd(c, "inertia", &m)?;
                    let [xx, yy, zz, xy, xz, yz] = m;
                    inertia = Symmetric3::new(xx, xy, xz, yy, yz, zz);
                }
                "fluid_added_mass" => self.ignore("inertial/fluid_added_mass"),
                other => return fail(c, format!("unknown element <{other}> in <inertial>")),
            }
        }
        Ok((
            Inertial {
                origin,
                mass,
                inertia,
            },
            relative_to,
        ))
    }

    fn read_shape(&mut self, e: &'a Element) -> Res<Shape<'a>> {
        let (pose, relative_to) = self.pose_of(e)?;
        let mut geometry = None;
        for c in &e.children {
            match c.name.as_str() {
                "pose" => {}
                "geometry" => geometry = self.read_geometry(c)?,
                "material" => self.ignore(format!("{}/material", e.name)),
                "surface" | "laser_retro" | "max_contacts" | "transparency" | "cast_shadows"
                | "meta" | "visibility_flags" | "plugin" => {}
                other => self.ignore(format!("{}/{other} (unknown element)", e.name)),
            }
        }
        Ok(Shape {
            e,
            name: e.attr("name").map(str::to_string),
            pose,
            relative_to,
            geometry,
        })
    }

    fn positive(&self, e: &'a Element, name: &str) -> Res<f64> {
        let Some(c) = child(e, name) else {
            return fail(e, format!("<{}> needs <{name}>", e.name));
        };
        let x = exact::<1>(c)?[0];
        if x <= 0.0 {
            return fail(c, format!("<{name}> must be positive, got {x}"));
        }
        not_absurd(c, name, &[x])?;
        Ok(x)
    }

    fn read_geometry(&mut self, g: &'a Element) -> Res<Option<Geometry>> {
        let Some(s) = g.children.first() else {
            return Ok(None);
        };
        let shape = match s.name.as_str() {
            "box" => {
                let Some(size) = child(s, "size") else {
                    return fail(s, "<box> needs <size>");
                };
                let size = exact::<3>(size)?;
                if size.iter().any(|x| *x <= 0.0) {
                    return fail(s, format!("box sizes must be positive, got {size:?}"));
                }
                not_absurd(s, "box size", &size)?;
                Some(Geometry::Box { size })
            }
            "sphere" => Some(Geometry::Sphere {
                radius: self.positive(s, "radius")?,
            }),
            "cylinder" => Some(Geometry::Cylinder {
                radius: self.positive(s, "radius")?,
                length: self.positive(s, "length")?,
            }),
            "capsule" => Some(Geometry::Capsule {
                radius: self.positive(s, "radius")?,
                length: self.positive(s, "length")?,
            }),
            "ellipsoid" => {
                let Some(radii) = child(s, "radii") else {
                    return fail(s, "<ellipsoid> needs <radii>");
                };
                let r = exact::<3>(radii)?;
                if r.iter().any(|x| *x <= 0.0) {
                    return fail(radii, format!("radii must be positive, got {r:?}"));
                }
                self.ignore("geometry/ellipsoid (no collision shape yet)");
                None
            }
            "mesh" => Some(self.read_mesh(s)?),
            "plane" | "heightmap" | "image" | "polyline" | "empty" | "cone" => {
                self.ignore(format!("geometry/{}", s.name));
                None
            }
            other => return fail(s, format!("unknown geometry <{other}>")),
        };
        Ok(shape)
    }

    fn read_mesh(&mut self, m: &'a Element) -> Res<Geometry> {
        let Some(uri) = child(m, "uri") else {
            return fail(m, "<mesh> needs <uri>");
        };
        let text = uri.text.trim();
        if text.is_empty() {
            return fail(uri, "empty mesh URI");
        }
        let scale = match child(m, "scale") {
            Some(s) => {
                let v = exact::<3>(s)?;
                if v.contains(&0.0) {
                    return fail(s, format!("a mesh scale cannot be zero, got {v:?}"));
                }
                not_absurd(s, "scale", &v)?;
                v
            }
            None => [1.0; 3],
        };
        if child(m, "submesh").is_some() {
            self.ignore("mesh/submesh (the whole mesh is used)");
        }
        let filename = match self.files.resolve(text, uri.file, self.options) {
            Resolved::Found(p) => p.to_string_lossy().into_owned(),
            Resolved::Missing(p) => {
                return fail(
                    uri,
                    format!("mesh file '{text}' not found (looked for {})", p.display()),
                );
            }
            Resolved::Unresolved => {
                self.notes.push(format!(
                    "mesh '{text}' not found in the model search path (kept as written)"
                ));
                text.to_string()
            }
        };
        Ok(Geometry::Mesh { filename, scale })
    }

    fn read_axis(&mut self, a: &'a Element) -> Res<AxisData<'a>> {
        let mut axis = AxisData {
            e: a,
            xyz: DVec3::Z,
            expressed_in: None,
            model_frame: self.version(a) < (1, 5),
            limits: JointLimits::UNLIMITED,
            dynamics: JointDynamics::default(),
            mimic: None,
        };
        let (mut lower, mut upper) = (-UNBOUNDED, UNBOUNDED);
        for c in &a.children {
            match c.name.as_str() {
                "xyz" => {
                    let xyz = DVec3::from_array(exact::<3>(c)?);
                    let n = xyz.length();
                    if n < 1e-12 {
                        return fail(c, "the joint axis is zero");
                    }
                    axis.xyz = xyz / n;
                    axis.expressed_in = c
                        .attr("expressed_in")
                        .filter(|s| !s.is_empty())
                        .map(str::to_string);
                }
                "use_parent_model_frame" => axis.model_frame = parse_bool(c)?,
                "limit" => {
                    lower = number(c, "lower", lower)?;
                    upper = number(c, "upper", upper)?;
                    let effort = number(c, "effort", -1.0)?;
                    let velocity = number(c, "velocity", -1.0)?;
                    axis.limits.effort = if effort < 0.0 { f64::INFINITY } else { effort };
                    axis.limits.velocity = if velocity < 0.0 {
                        f64::INFINITY
                    } else {
                        velocity
                    };
                    if lower > upper {
                        return fail(c, format!("lower limit {lower} above upper limit {upper}"));
                    }
                }
                "dynamics" => {
                    axis.dynamics.damping = number(c, "damping", 0.0)?;
                    axis.dynamics.friction = number(c, "friction", 0.0)?;
                    if axis.dynamics.damping < 0.0 || axis.dynamics.friction < 0.0 {
                        return fail(c, "damping and friction cannot be negative");
                    }
                    let k = number(c, "spring_stiffness", 0.0)?;
                    if k != 0.0 {
                        self.notes.push(format!(
                            "joint axis spring_stiffness {k} (springs are not modelled)"
                        ));
                    }
                }
                "mimic" => {
                    let Some(leader) = c.attr("joint").filter(|j| !j.trim().is_empty()) else {
                        return fail(c, "<mimic> needs a joint attribute");
                    };
                    let multiplier = number(c, "multiplier", 1.0)?;
                    let offset = number(c, "offset", 0.0)?;
                    let reference = number(c, "reference", 0.0)?;
                    // SDFormat: q = offset + multiplier · (q_leader − reference).
                    axis.mimic = Some((
                        leader.trim().to_string(),
                        multiplier,
                        offset - multiplier * reference,
                        c,
                    ));
                }
                "initial_position" => self.ignore("axis/initial_position"),
                other => self.ignore(format!("axis/{other} (unknown element)")),
            }
        }
        axis.limits.lower = if lower <= -UNBOUNDED {
            f64::NEG_INFINITY
        } else {
            lower
        };
        axis.limits.upper = if upper >= UNBOUNDED {
            f64::INFINITY
        } else {
            upper
        };
        Ok(axis)
    }

    fn read_joint(&mut self, e: &'a Element, scope: usize) -> Res<()> {
        let name = self.name_of(e)?;
        let (pose, relative_to) = self.pose_of(e)?;
        let kind = match e.attr("type").unwrap_or("") {
            "fixed" => SdfJoint::Fixed,
            "revolute" => SdfJoint::Revolute,
            "continuous" => SdfJoint::Continuous,
            "prismatic" => SdfJoint::Prismatic,
            "ball" => SdfJoint::Ball,
            "universal" | "revolute2" => SdfJoint::Universal,
            "screw" => {
                return fail(
                    e,
                    format!(
                        "screw joint '{name}': kinetree has no helical joint (its translation is coupled to its rotation), so it cannot be loaded exactly"
                    ),
                );
            }
            "gearbox" => {
                return fail(
                    e,
                    format!("gearbox joint '{name}': coupled joints are not supported yet"),
                );
            }
            "" => return fail(e, format!("joint '{name}' needs a type attribute")),
            other => return fail(e, format!("joint '{name}': unknown type '{other}'")),
        };
        let link_name = |which: &str| -> Res<(String, &'a Element)> {
            match child(e, which) {
                Some(c) if !c.text.trim().is_empty() => Ok((c.text.trim().to_string(), c)),
                Some(c) => fail(c, format!("empty <{which}>")),
                None => fail(e, format!("joint '{name}' needs a <{which}>")),
            }
        };
        let parent = link_name("parent")?;
        let child_link = link_name("child")?;
        let mut axes = Vec::new();
        for c in &e.children {
            match c.name.as_str() {
                "pose" | "parent" | "child" => {}
                "axis" | "axis2" => {
                    let a = self.read_axis(c)?;
                    axes.push((c.name == "axis2", a));
                }
                "physics"
                | "sensor"
                | "thread_pitch"
                | "screw_thread_pitch"
                | "gearbox_ratio"
                | "gearbox_reference_body" => self.ignore(format!("joint/{}", c.name)),
                other => self.ignore(format!("joint/{other} (unknown element)")),
            }
        }
        axes.sort_by_key(|(second, _)| *second);
        let axes: Vec<AxisData<'a>> = axes.into_iter().map(|(_, a)| a).collect();
        let needed = match kind {
            SdfJoint::Fixed | SdfJoint::Ball => 0,
            SdfJoint::Revolute | SdfJoint::Continuous | SdfJoint::Prismatic => 1,
            SdfJoint::Universal => 2,
        };
        if axes.len() < needed {
            return fail(
                e,
                format!(
                    "joint '{name}' of type {} needs {}",
                    e.attr("type").unwrap_or_default(),
                    if needed == 1 {
                        "an <axis>"
                    } else {
                        "<axis> and <axis2>"
                    }
                ),
            );
        }
        let node = self.graph.add_node(Node {
            kind: Kind::Joint,
            scope,
            name,
            e,
            pose,
            relative_to,
            attached_to: Some(child_link.0.clone()),
            parent: usize::MAX,
            inner: None,
        })?;
        self.joints.push(JointData {
            node,
            kind,
            parent,
            child: child_link,
            axes,
        });
        Ok(())
    }

    fn read_world(&mut self, w: &'a Element) -> Res<()> {
        let models: Vec<&Element> = w.children.iter().filter(|c| c.name == "model").collect();
        for c in &w.children {
            match c.name.as_str() {
                "model" => {
                    let prefix = if models.len() > 1 {
                        format!("{}::", self.name_of(c)?)
                    } else {
                        String::new()
                    };
                    self.read_model(c, 0, prefix, false, 1)?;
                }
                "gravity" => {
                    let g = exact::<3>(c)?;
                    not_absurd(c, "gravity", &g)?;
                    self.gravity = Some(DVec3::from_array(g));
                }
                "frame" => self.read_frame(c, 0)?,
                other => self.ignore(format!("world/{other}")),
            }
        }
        Ok(())
    }
}

/// How a mesh or include URI resolved.
pub(crate) enum Resolved {
    /// An existing file.
    Found(PathBuf),
    /// A path that names no file.
    Missing(PathBuf),
    /// A `model://` or `package://` URI not found in the search path, or a remote URI.
    Unresolved,
}

impl Files {
    /// Resolves `uri`, written in file `file`: `model://` and `package://` through the search
    /// path, `file://` and plain paths relative to that file's folder.
    pub(crate) fn resolve(&self, uri: &str, file: usize, options: &SdfOptions) -> Resolved {
        let dir = self.dir(file);
        for scheme in ["model://", "package://"] {
            if let Some(rest) = uri.strip_prefix(scheme) {
                for d in self.search_path(options, &dir) {
                    let p = d.join(rest);
                    if p.exists() {
                        return Resolved::Found(p);
                    }
                }
                return Resolved::Unresolved;
            }
        }
        if uri.contains("://") && !uri.starts_with("file://") {
            return Resolved::Unresolved;
        }
        let path = Path::new(uri.strip_prefix("file://").unwrap_or(uri));
        let p = if path.is_absolute() {
            path.to_path_buf()
        } else {
            dir.join(path)
        };
        if p.exists() {
            Resolved::Found(p)
        } else {
            Resolved::Missing(p)
        }
    }

    /// The folders searched for `model://` URIs: the options' folders, `SDF_PATH`,
    /// `GZ_SIM_RESOURCE_PATH`, then `dir` (the referring file's folder) and the main file's.
    pub(crate) fn search_path(&self, options: &SdfOptions, dir: &Path) -> Vec<PathBuf> {
        let mut out: Vec<PathBuf> = options.search_path.clone();
        for var in ["SDF_PATH", "GZ_SIM_RESOURCE_PATH"] {
            if let Some(v) = std::env::var_os(var) {
                out.extend(std::env::split_paths(&v).filter(|p| !p.as_os_str().is_empty()));
            }
        }
        out.push(dir.to_path_buf());
        out.push(self.dir(0));
        out
    }
}

/// The kinetree name of a graph node (its scope's prefix and its name).
fn kname(graph: &Graph<'_>, node: usize) -> String {
    let n = &graph.nodes[node];
    format!("{}{}", graph.scopes[n.scope].prefix, n.name)
}

/// A name for a joint added by the loader for `link`: the link's name, unless an SDFormat joint
/// already has it.
fn added_joint_name(link: &str, joint_names: &std::collections::HashSet<String>) -> String {
    if joint_names.contains(link) {
        format!("{link}:root")
    } else {
        link.to_string()
    }
}

/// Everything read from the document, handed to the builder: links, joints, frames; the free
/// roots' poses for the initial configuration.
pub(crate) struct Loaded {
    pub(crate) model: Model,
    pub(crate) q0: Vec<f64>,
}

impl<'a> Reader<'a> {
    fn build(mut self, model_name: &str) -> Res<(ModelBuilder, Vec<(String, Se3)>)> {
        self.graph.resolve()?;
        let graph = &self.graph;
        let mut b = ModelBuilder::new(model_name);
        if let Some(g) = self.gravity {
            b.gravity(g);
        }
        // Links.
        for l in &self.links {
            let name = kname(graph, l.node);
            let mut link = Link::new(&name);
            let mut inertial = Inertial {
                origin: Se3::IDENTITY,
                mass: 1.0,
                inertia: Symmetric3::from_diagonal(DVec3::ONE),
            };
            if let Some((i, relative_to, ie)) = &l.inertial {
                inertial = *i;
                if let Some(r) = relative_to {
                    let target = graph.lookup_or_fail(graph.nodes[l.node].scope, r, ie)?;
                    inertial.origin = graph.relative(l.node, target) * inertial.origin;
                }
            }
            link.inertial = Some(inertial);
            let place = |s: &Shape<'_>| -> Res<Se3> {
                match &s.relative_to {
                    Some(r) => {
                        let target = graph.lookup_or_fail(graph.nodes[l.node].scope, r, s.e)?;
                        Ok(graph.relative(l.node, target) * s.pose)
                    }
                    None => Ok(s.pose),
                }
            };
            for s in &l.visuals {
                if let Some(g) = &s.geometry {
                    link.visuals.push(Visual {
                        name: s.name.clone(),
                        origin: place(s)?,
                        geometry: g.clone(),
                        material: None,
                        color: None,
                    });
                }
            }
            for s in &l.collisions {
                if let Some(g) = &s.geometry {
                    link.collisions.push(Collision {
                        name: s.name.clone(),
                        origin: place(s)?,
                        geometry: g.clone(),
                    });
                }
            }
            b.add_link(link);
        }
        // Joints: which link each attaches to which, checked for second parents and cycles.
        let mut parent_of: HashMap<usize, (usize, Option<usize>)> = HashMap::new();
        let mut joint_names = std::collections::HashSet::new();
        let mut resolved = Vec::new();
        for j in &self.joints {
            let node = &graph.nodes[j.node];
            if graph.scopes[node.scope].is_static {
                self.notes.push(format!(
                    "joint '{}' of a static model (its links are welded to the world)",
                    kname(graph, j.node)
                ));
                continue;
            }
            let parent = graph.joint_end(node.scope, &j.parent.0, j.parent.1, true)?;
            let child = graph.joint_end(node.scope, &j.child.0, j.child.1, false)?;
            let Some(child) = child else {
                return fail(j.child.1, "the child of a joint cannot be the world");
            };
            if parent == Some(child) {
                return fail(node.e, "a joint cannot connect a link to itself");
            }
            if let Some((other, _)) = parent_of.get(&child) {
                return fail(
                    node.e,
                    format!(
                        "link '{}' already has a parent joint, '{}': the links must form a tree",
                        kname(graph, child),
                        kname(graph, *other)
                    ),
                );
            }
            if graph.scopes[graph.nodes[child].scope].is_static {
                return fail(
                    node.e,
                    format!(
                        "the child link '{}' belongs to a static model",
                        kname(graph, child)
                    ),
                );
            }
            parent_of.insert(child, (j.node, parent));
            joint_names.insert(kname(graph, j.node));
            resolved.push((j, parent, child));
        }
        for &(_, _, start) in &resolved {
            let mut at = start;
            let mut steps = 0;
            while let Some(&(joint, Some(p))) = parent_of.get(&at) {
                steps += 1;
                if p == start || steps > parent_of.len() {
                    return fail(
                        graph.nodes[joint].e,
                        format!(
                            "joint '{}' closes a kinematic loop through link '{}'",
                            kname(graph, joint),
                            kname(graph, start)
                        ),
                    );
                }
                at = p;
            }
        }
        for (j, parent, child) in resolved {
            self.emit_joint(&mut b, j, parent, child)?;
        }
        // Roots: static links welded, free trees floating (or welded, as asked).
        let mut floating = Vec::new();
        for l in &self.links {
            if parent_of.contains_key(&l.node) {
                continue;
            }
            let graph = &self.graph;
            let name = kname(graph, l.node);
            let world_from_link = graph.relative(0, l.node);
            let jname = added_joint_name(&name, &joint_names);
            let is_static = graph.scopes[graph.nodes[l.node].scope].is_static;
            if is_static || self.options.free_trees == RootJoint::Fixed {
                b.add_joint(
                    JointSpec::new(jname, JointKind::Fixed, "world", &name)
                        .with_placement(world_from_link),
                );
            } else {
                b.add_joint(JointSpec::new(&jname, JointKind::Floating, "world", &name));
                floating.push((jname, world_from_link));
            }
        }
        // Frames.
        for (id, n) in self.graph.nodes.iter().enumerate() {
            if n.kind != Kind::Frame || n.scope == 0 {
                continue;
            }
            match self.graph.attached_link(id)? {
                Some(link) => {
                    b.add_frame(FrameSpec::new(
                        kname(&self.graph, id),
                        kname(&self.graph, link),
                        self.graph.relative(link, id),
                    ));
                }
                None => self.notes.push(format!(
                    "frame '{}' attached to the world",
                    kname(&self.graph, id)
                )),
            }
        }
        for (what, count) in &self.ignored {
            b.note_ignored(if *count == 1 {
                what.clone()
            } else {
                format!("{what} (×{count})")
            });
        }
        for note in &self.notes {
            b.note_ignored(note.clone());
        }
        Ok((b, floating))
    }

    /// The axis of `a` in the joint frame of `joint`.
    fn axis_in_joint(&self, joint: usize, a: &AxisData<'_>) -> Res<DVec3> {
        let g = &self.graph;
        let scope = g.nodes[joint].scope;
        let frame = match &a.expressed_in {
            Some(name) => Some(g.lookup_or_fail(scope, name, a.e)?),
            None if a.model_frame => Some(g.scopes[scope].node),
            None => None,
        };
        Ok(match frame {
            Some(f) => g.relative(joint, f).rotation * a.xyz,
            None => a.xyz,
        })
    }

    fn emit_joint(
        &self,
        b: &mut ModelBuilder,
        j: &JointData<'_>,
        parent: Option<usize>,
        child: usize,
    ) -> Res<()> {
        let g = &self.graph;
        let name = kname(g, j.node);
        let parent_name = parent.map_or_else(|| "world".to_string(), |p| kname(g, p));
        let child_name = kname(g, child);
        let parent_from_joint = g.relative(parent.unwrap_or(0), j.node);
        let joint_from_child = g.relative(j.node, child);
        let target = if joint_from_child == Se3::IDENTITY {
            child_name.clone()
        } else {
            let inner = format!("{name}:frame");
            b.add_link(Link::new(&inner));
            b.add_joint(
                JointSpec::new(
                    format!("{name}:child"),
                    JointKind::Fixed,
                    &inner,
                    &child_name,
                )
                .with_placement(joint_from_child),
            );
            inner
        };
        let first = j.axes.first();
        let (kind, limits) = match j.kind {
            SdfJoint::Fixed => (JointKind::Fixed, JointLimits::UNLIMITED),
            SdfJoint::Ball => (JointKind::Spherical, JointLimits::UNLIMITED),
            SdfJoint::Continuous => (
                JointKind::Continuous,
                first.map_or(JointLimits::UNLIMITED, |a| JointLimits {
                    lower: f64::NEG_INFINITY,
                    upper: f64::INFINITY,
                    ..a.limits
                }),
            ),
            SdfJoint::Revolute => {
                let l = first.map_or(JointLimits::UNLIMITED, |a| a.limits);
                if l.lower.is_infinite() && l.upper.is_infinite() {
                    (JointKind::Continuous, l)
                } else {
                    (JointKind::Revolute, l)
                }
            }
            SdfJoint::Prismatic => (
                JointKind::Prismatic,
                first.map_or(JointLimits::UNLIMITED, |a| a.limits),
            ),
            SdfJoint::Universal => {
                let a1 = self.axis_in_joint(j.node, &j.axes[0])?;
                let a2 = self.axis_in_joint(j.node, &j.axes[1])?;
                if a1.dot(a2).abs() > 1e-9 {
                    return fail(
                        g.nodes[j.node].e,
                        format!(
                            "joint '{name}': the two axes of a universal joint must be perpendicular (cos = {:e})",
                            a1.dot(a2)
                        ),
                    );
                }
                let a2 = (a2 - a1 * a1.dot(a2)).normalize();
                let r = DMat3::from_cols(a1, a2, a1.cross(a2));
                let q = DQuat::from_mat3(&r);
                let spec = CompositeJointSpec::new(
                    &name,
                    &parent_name,
                    &target,
                    [
                        Factor::Rotate(Axis::X, None),
                        Factor::Rotate(Axis::Y, None),
                        Factor::Rotation(q.conjugate()),
                    ],
                )
                .with_placement(parent_from_joint * Se3::new(r, DVec3::ZERO))
                .with_limits([j.axes[0].limits, j.axes[1].limits]);
                b.add_composite(spec);
                return Ok(());
            }
        };
        let axis = match first {
            Some(a) if kind.has_axis() => self.axis_in_joint(j.node, a)?,
            _ => DVec3::X,
        };
        let mut spec = JointSpec::new(&name, kind, &parent_name, &target)
            .with_placement(parent_from_joint)
            .with_axis(axis)
            .with_limits(
                if kind.has_position_limits() || kind == JointKind::Continuous {
                    limits
                } else {
                    JointLimits::UNLIMITED
                },
            );
        if let Some(a) = first.filter(|_| kind.is_moving()) {
            spec = spec.with_dynamics(a.dynamics);
            if let Some((leader, multiplier, offset, e)) = &a.mimic {
                let scope = g.nodes[j.node].scope;
                let n = g.lookup_or_fail(scope, leader, e)?;
                if g.nodes[n].kind != Kind::Joint {
                    return fail(e, format!("mimic joint '{leader}' is not a joint"));
                }
                spec = spec.with_mimic(kname(g, n), *multiplier, *offset);
            }
        }
        b.add_joint(spec);
        Ok(())
    }
}

/// Reads an SDFormat document; `path` is where it came from (for `<include>`s, meshes and error
/// messages).
pub(crate) fn from_sdf(
    text: &str,
    path: Option<&Path>,
    options: &SdfOptions,
) -> Result<Loaded, ModelError> {
    let mut root = xml_tree::parse(text, 0).map_err(|x| ModelError::Xml {
        file: path.map(Path::to_path_buf),
        line: x.line,
        column: x.column,
        message: x.message,
    })?;
    let mut files = Files::new(path);
    let result = read_document(&mut root, &mut files, options);
    xml_tree::drop_flat(root);
    let (b, floating) = result.map_err(|l| files.error(l))?;
    let model = b.build()?;
    let mut q0 = model.neutral_q();
    for (name, pose) in floating {
        if let Some(j) = model.joint_index(&name) {
            let r = model.joint_q_range(j);
            let q = DQuat::from_mat3(&pose.rotation).normalize();
            let q = if q.w < 0.0 { -q } else { q };
            q0[r.start..r.start + 3].copy_from_slice(&pose.translation.to_array());
            q0[r.start + 3..r.start + 7].copy_from_slice(&[q.x, q.y, q.z, q.w]);
        }
    }
    Ok(Loaded { model, q0 })
}

fn read_document(
    root: &mut Element,
    files: &mut Files,
    options: &SdfOptions,
) -> Res<(ModelBuilder, Vec<(String, Se3)>)> {
    if root.name != "sdf" {
        return fail(root, "the root element of an SDFormat file is <sdf>");
    }
    files.set_version(0, parse_version(root)?);
    expand_includes(root, files, options)?;
    let root: &Element = root;
    let mut reader = Reader {
        files,
        options,
        graph: Graph::new(root),
        links: Vec::new(),
        joints: Vec::new(),
        ignored: BTreeMap::new(),
        notes: Vec::new(),
        gravity: None,
    };
    let mut name = None;
    for c in &root.children {
        match c.name.as_str() {
            "model" => {
                if name.is_some() {
                    return fail(
                        c,
                        "an <sdf> file holds one <model> (use a <world> for several)",
                    );
                }
                name = Some(reader.name_of(c)?);
                reader.read_model(c, 0, String::new(), false, 1)?;
            }
            "world" => {
                if name.is_some() {
                    return fail(c, "an <sdf> file holds one <model> or one <world>");
                }
                name = Some(reader.name_of(c).unwrap_or_else(|_| "world".to_string()));
                reader.read_world(c)?;
            }
            "actor" | "light" => reader.ignore(format!("sdf/{}", c.name)),
            other => return fail(c, format!("unknown element <{other}> in <sdf>")),
        }
    }
    let Some(name) = name else {
        return fail(root, "no <model> or <world> in the file");
    };
    reader.build(&name)
}
