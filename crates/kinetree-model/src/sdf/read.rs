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

mod emit;
mod model;

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

/// Everything read from the document, handed to the builder: links, joints, frames; the free
/// roots' poses for the initial configuration.
pub(crate) struct Loaded {
    pub(crate) model: Model,
    pub(crate) q0: Vec<f64>,
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
