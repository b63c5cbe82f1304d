//! MJCF import: the document (with `<include>`s), `<compiler>`, `<option>`, `<default>` classes,
//! `<asset>` meshes and the `<worldbody>` tree, compiled as MuJoCo's compiler does, then handed
//! to [`ModelBuilder`].

use super::inertia::{self, BodyMass, GeomMass, MeshInertia, Solid, Spread};
use super::orient::{Angle, Orientation, z_to};
use crate::builder::{FrameSpec, JointSpec, ModelBuilder};
use crate::error::ModelError;
use crate::joint::{JointDynamics, JointKind, JointLimits};
use crate::link::{Collision, Geometry, Inertial, Link, Visual};
use crate::model::Model;
use crate::xml_tree::{self, Element, MAX_XML_DEPTH};
use glam::{DMat3, DQuat, DVec3};
use kinetree_spatial::{Se3, Symmetric3};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

mod body;
mod compile;
mod defaults;
mod emit;
mod include;
mod mass;

pub(crate) use compile::from_mjcf;
use defaults::{orientation, read_compiler};
use emit::{check_moving, link_of};
use include::expand_includes;

/// The name of the link that stands for MuJoCo's world body.
pub(crate) const WORLD_BODY: &str = "world";

/// Upper bound on the number of files one model may include (`<include>` elements).
const MAX_INCLUDES: usize = 1000;

/// Smallest norm or mass MuJoCo's compiler treats as non-zero (`mjEPS`).
const MJ_EPS: f64 = 1e-14;

/// A failure located at an element.
struct Located {
    file: usize,
    line: usize,
    element: String,
    message: String,
}

type Res<T> = Result<T, Located>;

fn fail<T>(e: &Element, message: impl Into<String>) -> Res<T> {
    Err(Located {
        file: e.file,
        line: e.line,
        element: e.name.clone(),
        message: message.into(),
    })
}

/// The documents of one model: the main file first, then every included file.
struct Files {
    paths: Vec<Option<PathBuf>>,
}

impl Files {
    fn error(&self, l: Located) -> ModelError {
        ModelError::Mjcf {
            file: self.paths.get(l.file).cloned().flatten(),
            line: l.line,
            element: l.element,
            message: l.message,
        }
    }
}

fn read_text(path: &Path) -> Result<String, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    String::from_utf8(bytes).map_err(|_| format!("{} is not UTF-8 text", path.display()))
}

/// `<compiler inertiafromgeom=…>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FromGeom {
    False,
    True,
    Auto,
}

/// The `<compiler>` settings that change the compiled tree.
#[derive(Clone, Debug)]
struct Compiler {
    angle: Angle,
    eulerseq: [u8; 3],
    autolimits: bool,
    inertia_from_geom: FromGeom,
    group_range: [i64; 2],
    boundmass: f64,
    boundinertia: f64,
    balanceinertia: bool,
    settotalmass: f64,
    meshdir: Option<String>,
    assetdir: Option<String>,
}

fn parse_numbers(e: &Element, attr: &str, text: &str) -> Res<Vec<f64>> {
    let mut out = Vec::new();
    for word in text.split_ascii_whitespace() {
        match word.parse::<f64>() {
            Ok(x) if x.is_finite() => out.push(x),
            Ok(_) => {
                return fail(
                    e,
                    format!("attribute '{attr}': '{word}' is not a finite number"),
                );
            }
            Err(_) => return fail(e, format!("attribute '{attr}': '{word}' is not a number")),
        }
    }
    Ok(out)
}

fn parse_bool(e: &Element, attr: &str, text: &str) -> Res<bool> {
    match text.trim() {
        "true" => Ok(true),
        "false" => Ok(false),
        other => fail(
            e,
            format!("attribute '{attr}': '{other}' is not 'true' or 'false'"),
        ),
    }
}

/// `true`/`false`/`auto`.
fn parse_tristate(e: &Element, attr: &str, text: &str) -> Res<Option<bool>> {
    match text.trim() {
        "true" => Ok(Some(true)),
        "false" => Ok(Some(false)),
        "auto" => Ok(None),
        other => fail(
            e,
            format!("attribute '{attr}': '{other}' is not 'true', 'false' or 'auto'"),
        ),
    }
}

fn exact<const N: usize>(e: &Element, attr: &str, text: &str) -> Res<[f64; N]> {
    let v = parse_numbers(e, attr, text)?;
    match <[f64; N]>::try_from(v.as_slice()) {
        Ok(a) => Ok(a),
        Err(_) => fail(
            e,
            format!("attribute '{attr}' needs {N} numbers, got {}", v.len()),
        ),
    }
}

/// One `<default>` class: its parent and the attributes it sets per element kind.
#[derive(Debug, Default)]
struct Class {
    parent: Option<usize>,
    attrs: HashMap<String, Vec<(String, String)>>,
}

/// Every default class; class 0 is `main`.
#[derive(Debug)]
struct Defaults {
    classes: Vec<Class>,
    names: HashMap<String, usize>,
}

/// An element read with its defaults: its own attributes first, then its class's, then the
/// class's ancestors'.
struct View<'a> {
    e: &'a Element,
    kind: &'a str,
    chain: Vec<usize>,
    defaults: &'a Defaults,
}

fn pose(pos: DVec3, q: DQuat) -> Se3 {
    Se3::new(DMat3::from_quat(q), pos)
}

/// MuJoCo's joint types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum MjJoint {
    Free,
    Ball,
    Slide,
    Hinge,
}

#[derive(Debug)]
struct JointData {
    name: Option<String>,
    kind: MjJoint,
    /// Anchor in the body frame.
    pos: DVec3,
    /// Unit axis in the body frame.
    axis: DVec3,
    /// Position limits in qpos units (radians or metres), when limited.
    range: Option<[f64; 2]>,
    reference: f64,
    dynamics: JointDynamics,
    stiffness: f64,
}

#[derive(Debug)]
struct GeomData {
    name: Option<String>,
    /// Pose in the body frame.
    pose: Se3,
    geometry: Option<Geometry>,
    solid: Solid,
    /// `mass=` when given.
    mass: Option<f64>,
    density: f64,
    spread: Spread,
    group: i64,
    collides: bool,
    rgba: Option<[f64; 4]>,
    line: usize,
    file: usize,
    /// The mesh asset of a mesh geom.
    mesh: Option<String>,
}

#[derive(Debug)]
struct SiteData {
    name: Option<String>,
    pose: Se3,
}

#[derive(Debug)]
struct InertialData {
    mass: f64,
    pos: DVec3,
    rot: DMat3,
    moments: [f64; 3],
}

#[derive(Debug)]
struct BodyData<'a> {
    e: &'a Element,
    /// Whether this is the world body (`<worldbody>`).
    world: bool,
    name: Option<String>,
    /// Pose in the parent body's frame (enclosing `<frame>`s included).
    pose: Se3,
    joints: Vec<JointData>,
    geoms: Vec<GeomData>,
    sites: Vec<SiteData>,
    inertial: Option<InertialData>,
    children: Vec<BodyData<'a>>,
}

/// A mesh asset: the file (relative to the model's folder unless absolute), its scale and how
/// MuJoCo integrates its mass.
#[derive(Clone, Debug)]
struct MeshAsset {
    file: String,
    scale: [f64; 3],
    inertia: MeshInertia,
}

/// What a body walk needs besides the element: the default class in force and the pose of the
/// enclosing `<frame>`s in the body frame.
#[derive(Clone, Copy)]
struct Scope {
    class: usize,
    frame: Se3,
    depth: usize,
}

struct Reader<'a> {
    compiler: Compiler,
    defaults: &'a Defaults,
    meshes: HashMap<String, MeshAsset>,
    model_dir: PathBuf,
    /// Elements kinetree does not model, with counts.
    ignored: BTreeMap<String, usize>,
    /// Joint settings kinetree reads but does not use, as notes for [`Model::ignored`].
    notes: Vec<String>,
}

/// Emits links, joints and frames for a body and its subtree, in MuJoCo's depth-first order.
struct Emitter<'m> {
    masses: &'m [BodyMass],
    body_id: usize,
    site_id: usize,
    notes: Vec<String>,
}
