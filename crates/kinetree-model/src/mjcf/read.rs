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

/// Replaces every `<include file=…/>` below `e` by the children of the included document's root,
/// recursively, as MuJoCo: a file is looked up relative to the main model's folder first, then
/// relative to the including file's; including a file twice is an error.
fn expand_includes(
    e: &mut Element,
    files: &mut Files,
    model_dir: &Path,
    included: &mut HashSet<PathBuf>,
    depth: usize,
) -> Res<()> {
    if depth > MAX_XML_DEPTH {
        return fail(
            e,
            format!("elements nested deeper than {MAX_XML_DEPTH} levels"),
        );
    }
    let mut i = 0;
    while i < e.children.len() {
        if e.children[i].name != "include" {
            expand_includes(&mut e.children[i], files, model_dir, included, depth + 1)?;
            i += 1;
            continue;
        }
        let inc = &e.children[i];
        if !inc.children.is_empty() {
            return fail(inc, "an include element cannot have children");
        }
        let Some(name) = inc.attr("file") else {
            return fail(inc, "missing attribute 'file'");
        };
        let including_dir = files
            .paths
            .get(inc.file)
            .cloned()
            .flatten()
            .and_then(|p| p.parent().map(Path::to_path_buf))
            .unwrap_or_else(|| model_dir.to_path_buf());
        let first = model_dir.join(name);
        let path = if first.is_file() {
            first
        } else {
            including_dir.join(name)
        };
        let key = path.canonicalize().unwrap_or_else(|_| path.clone());
        if included.contains(&key) {
            return fail(inc, format!("file '{name}' is already included"));
        }
        if included.len() >= MAX_INCLUDES {
            return fail(inc, format!("more than {MAX_INCLUDES} included files"));
        }
        let text = match read_text(&path) {
            Ok(t) => t,
            Err(message) => return fail(inc, message),
        };
        let index = files.paths.len();
        files.paths.push(Some(path.clone()));
        let mut root = match xml_tree::parse(&text, index) {
            Ok(r) => r,
            Err(x) => {
                return Err(Located {
                    file: index,
                    line: x.line,
                    element: "include".to_string(),
                    message: format!("malformed XML: {}", x.message),
                });
            }
        };
        included.insert(key);
        expand_includes(&mut root, files, model_dir, included, depth + 1)?;
        let children = std::mem::take(&mut root.children);
        e.children.splice(i..=i, children.iter().cloned());
        i += children.len();
    }
    Ok(())
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

impl Default for Compiler {
    fn default() -> Self {
        Self {
            angle: Angle::Degree,
            eulerseq: *b"xyz",
            autolimits: true,
            inertia_from_geom: FromGeom::Auto,
            group_range: [0, 5],
            boundmass: 0.0,
            boundinertia: 0.0,
            balanceinertia: false,
            settotalmass: -1.0,
            meshdir: None,
            assetdir: None,
        }
    }
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

fn read_compiler(c: &Element, compiler: &mut Compiler) -> Res<()> {
    for (key, value) in &c.attrs {
        match key.as_str() {
            "angle" => {
                compiler.angle = match value.as_str() {
                    "degree" => Angle::Degree,
                    "radian" => Angle::Radian,
                    other => {
                        return fail(c, format!("angle '{other}' is not 'degree' or 'radian'"));
                    }
                }
            }
            "eulerseq" => {
                let b = value.as_bytes();
                if b.len() != 3 || !b.iter().all(|x| b"xyzXYZ".contains(x)) {
                    return fail(
                        c,
                        format!("eulerseq '{value}' must be three of x, y, z, X, Y, Z"),
                    );
                }
                compiler.eulerseq = [b[0], b[1], b[2]];
            }
            "autolimits" => compiler.autolimits = parse_bool(c, key, value)?,
            "inertiafromgeom" => {
                compiler.inertia_from_geom = match parse_tristate(c, key, value)? {
                    Some(true) => FromGeom::True,
                    Some(false) => FromGeom::False,
                    None => FromGeom::Auto,
                }
            }
            "inertiagrouprange" => {
                let [a, b] = exact::<2>(c, key, value)?;
                compiler.group_range = [a as i64, b as i64];
            }
            "boundmass" => compiler.boundmass = exact::<1>(c, key, value)?[0],
            "boundinertia" => compiler.boundinertia = exact::<1>(c, key, value)?[0],
            "balanceinertia" => compiler.balanceinertia = parse_bool(c, key, value)?,
            "settotalmass" => compiler.settotalmass = exact::<1>(c, key, value)?[0],
            "meshdir" => compiler.meshdir = Some(value.clone()),
            "assetdir" => compiler.assetdir = Some(value.clone()),
            "coordinate" if value != "local" => {
                return fail(
                    c,
                    "global coordinates are no longer supported by MuJoCo (coordinate=\"local\" only)",
                );
            }
            _ => {}
        }
    }
    Ok(())
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

impl Defaults {
    fn new() -> Self {
        Self {
            classes: vec![Class::default()],
            names: HashMap::from([("main".to_string(), 0)]),
        }
    }

    fn read(&mut self, d: &Element, parent: Option<usize>, depth: usize) -> Res<()> {
        if depth > MAX_XML_DEPTH {
            return fail(d, "default classes nested too deeply");
        }
        let class = match parent {
            None => {
                if d.attr("class").is_some_and(|name| name != "main") {
                    return fail(d, "the top-level default class 'main' cannot be renamed");
                }
                0
            }
            Some(p) => {
                let Some(name) = d.attr("class").filter(|n| !n.is_empty()) else {
                    return fail(d, "a nested default needs a class name");
                };
                if self.names.contains_key(name) {
                    return fail(d, format!("repeated default class name '{name}'"));
                }
                self.classes.push(Class {
                    parent: Some(p),
                    attrs: HashMap::new(),
                });
                let id = self.classes.len() - 1;
                self.names.insert(name.to_string(), id);
                id
            }
        };
        for child in &d.children {
            if child.name == "default" {
                self.read(child, Some(class), depth + 1)?;
            } else {
                let entry = self.classes[class]
                    .attrs
                    .entry(child.name.clone())
                    .or_default();
                for (k, v) in &child.attrs {
                    entry.retain(|(old, _)| old != k);
                    entry.push((k.clone(), v.clone()));
                }
            }
        }
        Ok(())
    }

    fn find(&self, e: &Element, name: &str) -> Res<usize> {
        match self.names.get(name) {
            Some(&c) => Ok(c),
            None => fail(e, format!("unknown default class '{name}'")),
        }
    }

    /// The classes from `main` down to `class`.
    fn chain(&self, class: usize) -> Vec<usize> {
        let mut chain = vec![class];
        let mut c = class;
        while let Some(p) = self.classes[c].parent {
            chain.push(p);
            c = p;
        }
        chain.reverse();
        chain
    }
}

/// An element read with its defaults: its own attributes first, then its class's, then the
/// class's ancestors'.
struct View<'a> {
    e: &'a Element,
    kind: &'a str,
    chain: Vec<usize>,
    defaults: &'a Defaults,
}

impl<'a> View<'a> {
    fn get(&self, attr: &str) -> Option<&'a str> {
        if let Some(v) = self.e.attr(attr) {
            return Some(v);
        }
        for &c in self.chain.iter().rev() {
            if let Some((_, v)) = self.defaults.classes[c]
                .attrs
                .get(self.kind)
                .and_then(|list| list.iter().find(|(k, _)| k == attr))
            {
                return Some(v.as_str());
            }
        }
        None
    }

    fn number(&self, attr: &str, default: f64) -> Res<f64> {
        match self.get(attr) {
            Some(t) => Ok(exact::<1>(self.e, attr, t)?[0]),
            None => Ok(default),
        }
    }

    fn array<const N: usize>(&self, attr: &str, default: [f64; N]) -> Res<[f64; N]> {
        match self.get(attr) {
            Some(t) => exact::<N>(self.e, attr, t),
            None => Ok(default),
        }
    }

    /// Up to `N` numbers that replace the leading entries of the value inherited from the
    /// classes (MuJoCo's partial `size`), applied from `main` down to the element.
    fn prefix<const N: usize>(&self, attr: &str) -> Res<[f64; N]> {
        let mut out = [0.0; N];
        let mut apply = |text: &str| -> Res<()> {
            let v = parse_numbers(self.e, attr, text)?;
            if v.len() > N {
                return fail(
                    self.e,
                    format!(
                        "attribute '{attr}' takes at most {N} numbers, got {}",
                        v.len()
                    ),
                );
            }
            out[..v.len()].copy_from_slice(&v);
            Ok(())
        };
        for &c in &self.chain {
            if let Some((_, v)) = self.defaults.classes[c]
                .attrs
                .get(self.kind)
                .and_then(|list| list.iter().find(|(k, _)| k == attr))
            {
                apply(v)?;
            }
        }
        if let Some(v) = self.e.attr(attr) {
            apply(v)?;
        }
        Ok(out)
    }

    fn flag(&self, attr: &str, default: bool) -> Res<bool> {
        match self.get(attr) {
            Some(t) => parse_bool(self.e, attr, t),
            None => Ok(default),
        }
    }

    fn int(&self, attr: &str, default: i64) -> Res<i64> {
        match self.get(attr) {
            Some(t) => match t.trim().parse::<i64>() {
                Ok(i) => Ok(i),
                Err(_) => fail(
                    self.e,
                    format!("attribute '{attr}': '{t}' is not an integer"),
                ),
            },
            None => Ok(default),
        }
    }
}

/// The orientation attributes of `e` (its own, else its classes'): at most one form.
fn orientation(v: &View<'_>, c: &Compiler) -> Res<DQuat> {
    const FORMS: [&str; 5] = ["quat", "axisangle", "euler", "xyaxes", "zaxis"];
    let own: Vec<&str> = FORMS
        .iter()
        .copied()
        .filter(|f| v.e.attr(f).is_some())
        .collect();
    if own.len() > 1 {
        return fail(
            v.e,
            format!("several orientations given ({}): use one", own.join(", ")),
        );
    }
    let form = own
        .first()
        .copied()
        .or_else(|| FORMS.iter().copied().find(|f| v.get(f).is_some()));
    let Some(form) = form else {
        return Ok(DQuat::IDENTITY);
    };
    let text = v.get(form).unwrap_or_default();
    let o = match form {
        "quat" => Orientation::Quat(exact::<4>(v.e, form, text)?),
        "axisangle" => Orientation::AxisAngle(exact::<4>(v.e, form, text)?),
        "euler" => Orientation::Euler(exact::<3>(v.e, form, text)?),
        "xyaxes" => Orientation::XyAxes(exact::<6>(v.e, form, text)?),
        _ => Orientation::ZAxis(exact::<3>(v.e, form, text)?),
    };
    match o.resolve(c.angle, &c.eulerseq) {
        Ok(q) => Ok(q),
        Err(m) => fail(v.e, format!("attribute '{form}': {m}")),
    }
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

impl<'a> Reader<'a> {
    fn view(&self, e: &'a Element, kind: &'a str, class: usize) -> Res<View<'a>> {
        let class = match e.attr("class") {
            Some(name) => self.defaults.find(e, name)?,
            None => class,
        };
        Ok(View {
            e,
            kind,
            chain: self.defaults.chain(class),
            defaults: self.defaults,
        })
    }

    fn ignore(&mut self, what: impl Into<String>) {
        *self.ignored.entry(what.into()).or_default() += 1;
    }

    fn childclass(&self, e: &Element, class: usize) -> Res<usize> {
        match e.attr("childclass") {
            Some(name) => self.defaults.find(e, name),
            None => Ok(class),
        }
    }

    fn read_joint(&mut self, e: &'a Element, scope: Scope, free: bool) -> Res<JointData> {
        // `<freejoint>` takes no defaults; `<joint type="free">` does.
        let v = if free {
            View {
                e,
                kind: "freejoint",
                chain: Vec::new(),
                defaults: self.defaults,
            }
        } else {
            self.view(e, "joint", scope.class)?
        };
        let kind = if free {
            MjJoint::Free
        } else {
            match v.get("type").unwrap_or("hinge") {
                "hinge" => MjJoint::Hinge,
                "slide" => MjJoint::Slide,
                "ball" => MjJoint::Ball,
                "free" => MjJoint::Free,
                other => return fail(e, format!("unknown joint type '{other}'")),
            }
        };
        let angle = |x: f64| match kind {
            MjJoint::Hinge | MjJoint::Ball => self.compiler.angle.to_radians(x),
            _ => x,
        };
        let range = v.array::<2>("range", [0.0, 0.0])?;
        let has_range = range != [0.0, 0.0];
        let limited = match v.get("limited") {
            Some(t) => parse_tristate(e, "limited", t)?,
            None => None,
        };
        let limited = match (kind, limited) {
            (MjJoint::Free, Some(true)) => {
                return fail(e, "a free joint cannot be limited");
            }
            (MjJoint::Free, _) => false,
            (_, Some(l)) => l,
            (_, None) => {
                if !self.compiler.autolimits && has_range {
                    return fail(
                        e,
                        "'range' is given but 'limited' is not (and <compiler autolimits=\"false\">)",
                    );
                }
                has_range
            }
        };
        let range = if limited {
            if kind == MjJoint::Ball {
                if range[0] != 0.0 {
                    return fail(e, "range[0] of a ball joint must be 0");
                }
            } else if range[0] >= range[1] {
                return fail(e, "range[0] must be smaller than range[1]");
            }
            Some([angle(range[0]), angle(range[1])])
        } else {
            None
        };
        let (pos, axis) = match kind {
            MjJoint::Free => (DVec3::ZERO, DVec3::Z),
            MjJoint::Ball => (
                scope
                    .frame
                    .transform_point(DVec3::from_array(v.array("pos", [0.0; 3])?)),
                DVec3::Z,
            ),
            _ => {
                let pos = scope
                    .frame
                    .transform_point(DVec3::from_array(v.array("pos", [0.0; 3])?));
                let axis = scope
                    .frame
                    .transform_vector(DVec3::from_array(v.array("axis", [0.0, 0.0, 1.0])?));
                let n = axis.length();
                if n < MJ_EPS {
                    return fail(e, "axis too small");
                }
                (pos, axis / n)
            }
        };
        let reference = if free { 0.0 } else { v.number("ref", 0.0)? };
        let reference = if kind == MjJoint::Hinge {
            angle(reference)
        } else {
            reference
        };
        let dynamics = if free {
            JointDynamics::default()
        } else {
            JointDynamics {
                damping: v.number("damping", 0.0)?,
                friction: v.number("frictionloss", 0.0)?,
                armature: v.number("armature", 0.0)?,
            }
        };
        let stiffness = if free {
            0.0
        } else {
            v.number("stiffness", 0.0)?
        };
        Ok(JointData {
            name: e.attr("name").map(str::to_string),
            kind,
            pos,
            axis,
            range,
            reference: if matches!(kind, MjJoint::Hinge | MjJoint::Slide) {
                reference
            } else {
                0.0
            },
            dynamics,
            stiffness,
        })
    }

    fn read_geom(&mut self, e: &'a Element, scope: Scope) -> Res<GeomData> {
        let v = self.view(e, "geom", scope.class)?;
        let type_name = v.get("type").unwrap_or("sphere").to_string();
        let mut size = v.prefix::<3>("size")?;
        let mut pos = DVec3::from_array(v.array("pos", [0.0; 3])?);
        let fromto = match v.get("fromto") {
            Some(t) => Some(exact::<6>(e, "fromto", t)?),
            None => None,
        };
        let quat = if let Some(ft) = fromto {
            if !matches!(
                type_name.as_str(),
                "capsule" | "cylinder" | "ellipsoid" | "box"
            ) {
                return fail(e, "fromto requires a capsule, cylinder, box or ellipsoid");
            }
            if pos != DVec3::ZERO {
                return fail(e, "both pos and fromto are given");
            }
            let from = DVec3::new(ft[0], ft[1], ft[2]);
            let to = DVec3::new(ft[3], ft[4], ft[5]);
            let vec = from - to;
            let half = vec.length() / 2.0;
            if half < MJ_EPS {
                return fail(e, "fromto points are too close");
            }
            size[1] = half;
            if matches!(type_name.as_str(), "ellipsoid" | "box") {
                size[2] = size[1];
                size[1] = size[0];
            }
            pos = (from + to) / 2.0;
            z_to(vec)
        } else {
            orientation(&v, &self.compiler)?
        };
        let mesh = v.get("mesh");
        let positive = |n: usize| -> Res<()> {
            if size[..n].iter().all(|s| *s > 0.0) {
                Ok(())
            } else {
                fail(
                    e,
                    format!(
                        "a {type_name} needs {n} positive size{} (got {:?})",
                        if n > 1 { "s" } else { "" },
                        &size[..n]
                    ),
                )
            }
        };
        let (solid, geometry) = match type_name.as_str() {
            "sphere" => {
                positive(1)?;
                (
                    Solid::Sphere(size[0]),
                    Some(Geometry::Sphere { radius: size[0] }),
                )
            }
            "capsule" => {
                positive(2)?;
                (
                    Solid::Capsule(size[0], size[1]),
                    Some(Geometry::Capsule {
                        radius: size[0],
                        length: 2.0 * size[1],
                    }),
                )
            }
            "cylinder" => {
                positive(2)?;
                (
                    Solid::Cylinder(size[0], size[1]),
                    Some(Geometry::Cylinder {
                        radius: size[0],
                        length: 2.0 * size[1],
                    }),
                )
            }
            "box" => {
                positive(3)?;
                (
                    Solid::Box(size),
                    Some(Geometry::Box {
                        size: [2.0 * size[0], 2.0 * size[1], 2.0 * size[2]],
                    }),
                )
            }
            "ellipsoid" => {
                positive(3)?;
                self.ignore("geom type ellipsoid (mass kept, no collision shape yet)");
                (Solid::Ellipsoid(size), None)
            }
            "plane" => {
                self.ignore("geom type plane (no collision shape yet)");
                (Solid::Empty, None)
            }
            "hfield" => {
                self.ignore("geom type hfield");
                (Solid::Box(size), None)
            }
            "mesh" => {
                let Some(name) = mesh else {
                    return fail(e, "a mesh geom needs a 'mesh' attribute");
                };
                let Some(asset) = self.meshes.get(name) else {
                    return fail(e, format!("unknown mesh '{name}'"));
                };
                (
                    Solid::Empty,
                    Some(Geometry::Mesh {
                        filename: asset.file.clone(),
                        scale: asset.scale,
                    }),
                )
            }
            "sdf" => {
                self.ignore("geom type sdf");
                (Solid::Empty, None)
            }
            other => return fail(e, format!("unknown geom type '{other}'")),
        };
        let mass = match v.get("mass") {
            Some(t) => Some(exact::<1>(e, "mass", t)?[0]),
            None => None,
        };
        let density = v.number("density", 1000.0)?;
        let spread = if v.flag("shellinertia", false)? {
            Spread::Shell
        } else {
            Spread::Volume
        };
        let contype = v.int("contype", 1)?;
        let conaffinity = v.int("conaffinity", 1)?;
        let rgba = match v.get("rgba") {
            Some(t) => Some(exact::<4>(e, "rgba", t)?),
            None => None,
        };
        Ok(GeomData {
            name: e.attr("name").map(str::to_string),
            pose: scope.frame * pose(pos, quat),
            geometry,
            solid,
            mass,
            density,
            spread,
            group: v.int("group", 0)?,
            collides: contype != 0 || conaffinity != 0,
            rgba,
            line: e.line,
            file: e.file,
            mesh: (type_name == "mesh").then(|| mesh.unwrap_or_default().to_string()),
        })
    }

    fn read_inertial(&self, e: &'a Element) -> Res<InertialData> {
        let v = self.view(e, "inertial", 0)?;
        let Some(pos) = e.attr("pos") else {
            return fail(e, "missing attribute 'pos'");
        };
        let pos = DVec3::from_array(exact::<3>(e, "pos", pos)?);
        let Some(mass) = e.attr("mass") else {
            return fail(e, "missing attribute 'mass'");
        };
        let mass = exact::<1>(e, "mass", mass)?[0];
        let q = orientation(&v, &self.compiler)?;
        let (rot, moments) = match (e.attr("fullinertia"), e.attr("diaginertia")) {
            (Some(_), Some(_)) => {
                return fail(e, "fullinertia and diaginertia cannot both be given");
            }
            (Some(full), None) => {
                if q != DQuat::IDENTITY {
                    return fail(
                        e,
                        "fullinertia and an inertial orientation cannot both be given",
                    );
                }
                let [xx, yy, zz, xy, xz, yz] = exact::<6>(e, "fullinertia", full)?;
                let (moments, rot) =
                    inertia::principal_axes(&Symmetric3::new(xx, xy, xz, yy, yz, zz));
                // MuJoCo's check.
                if moments.iter().any(|m| *m < MJ_EPS) {
                    return fail(e, "fullinertia must have positive eigenvalues");
                }
                (rot, moments)
            }
            (None, Some(diag)) => (DMat3::from_quat(q), exact::<3>(e, "diaginertia", diag)?),
            (None, None) => (DMat3::from_quat(q), [0.0; 3]),
        };
        Ok(InertialData {
            mass,
            pos,
            rot,
            moments,
        })
    }

    fn read_site(&self, e: &'a Element, scope: Scope) -> Res<SiteData> {
        let v = self.view(e, "site", scope.class)?;
        let pos = DVec3::from_array(v.array("pos", [0.0; 3])?);
        let q = orientation(&v, &self.compiler)?;
        Ok(SiteData {
            name: e.attr("name").map(str::to_string),
            pose: scope.frame * pose(pos, q),
        })
    }

    /// Reads the children of a `<body>`, `<frame>` or `<worldbody>` element into `body`.
    fn read_children(&mut self, e: &'a Element, scope: Scope, body: &mut BodyData<'a>) -> Res<()> {
        if scope.depth > MAX_XML_DEPTH {
            return fail(
                e,
                format!("bodies and frames nested deeper than {MAX_XML_DEPTH} levels"),
            );
        }
        let world = body.world;
        for c in &e.children {
            match c.name.as_str() {
                "inertial" => {
                    if world {
                        return fail(c, "the world body cannot have an inertial");
                    }
                    if body.inertial.is_some() {
                        return fail(c, "a body has at most one inertial");
                    }
                    body.inertial = Some(self.read_inertial(c)?);
                }
                "joint" | "freejoint" => {
                    if world {
                        return fail(c, "the world body cannot have joints");
                    }
                    let j = self.read_joint(c, scope, c.name == "freejoint")?;
                    body.joints.push(j);
                }
                "geom" => {
                    let g = self.read_geom(c, scope)?;
                    body.geoms.push(g);
                }
                "site" => {
                    let s = self.read_site(c, scope)?;
                    body.sites.push(s);
                }
                "frame" => {
                    let v = View {
                        e: c,
                        kind: "frame",
                        chain: Vec::new(),
                        defaults: self.defaults,
                    };
                    let pos = DVec3::from_array(v.array("pos", [0.0; 3])?);
                    let q = orientation(&v, &self.compiler)?;
                    let inner = Scope {
                        class: self.childclass(c, scope.class)?,
                        frame: scope.frame * pose(pos, q),
                        depth: scope.depth + 1,
                    };
                    self.read_children(c, inner, body)?;
                }
                "body" => {
                    let v = View {
                        e: c,
                        kind: "body",
                        chain: Vec::new(),
                        defaults: self.defaults,
                    };
                    let pos = DVec3::from_array(v.array("pos", [0.0; 3])?);
                    let q = orientation(&v, &self.compiler)?;
                    let name = c.attr("name").map(str::to_string);
                    if name.as_deref() == Some(WORLD_BODY) {
                        return fail(c, "a body cannot be called 'world'");
                    }
                    let mut child = BodyData {
                        e: c,
                        world: false,
                        name,
                        pose: scope.frame * pose(pos, q),
                        joints: Vec::new(),
                        geoms: Vec::new(),
                        sites: Vec::new(),
                        inertial: None,
                        children: Vec::new(),
                    };
                    let inner = Scope {
                        class: self.childclass(c, scope.class)?,
                        frame: Se3::IDENTITY,
                        depth: scope.depth + 1,
                    };
                    self.read_children(c, inner, &mut child)?;
                    body.children.push(child);
                }
                "camera" | "light" => self.ignore(format!("{} (visual only)", c.name)),
                "plugin" => self.ignore("body plugin"),
                "composite" | "flexcomp" | "replicate" | "attach" => {
                    return fail(
                        c,
                        format!(
                            "<{}> generates bodies and is not supported yet; expand it with MuJoCo (mj_saveLastXML) first",
                            c.name
                        ),
                    );
                }
                other => return fail(c, format!("unknown element <{other}> in a body")),
            }
        }
        Ok(())
    }
}

/// The top-level sections whose content kinetree does not model; their children are counted in
/// [`Model::ignored`].
const UNMODELLED: [&str; 9] = [
    "actuator",
    "tendon",
    "equality",
    "sensor",
    "contact",
    "keyframe",
    "deformable",
    "extension",
    "custom",
];

/// Sections that only affect rendering or the simulator's settings.
const PRESENTATION: [&str; 4] = ["visual", "statistic", "size", "option"];

impl<'a> Reader<'a> {
    fn read_meshes(&mut self, asset: &'a Element) -> Res<()> {
        for m in asset.children.iter().filter(|c| c.name == "mesh") {
            let v = self.view(m, "mesh", 0)?;
            let Some(file) = m.attr("file") else {
                if m.attr("vertex").is_some() {
                    self.ignore("mesh given by vertices in the file (no collision shape)");
                    continue;
                }
                return fail(m, "a mesh asset needs a 'file' attribute");
            };
            let name = match m.attr("name") {
                Some(n) => n.to_string(),
                None => Path::new(file)
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| file.to_string()),
            };
            let scale = v.array::<3>("scale", [1.0; 3])?;
            if scale.contains(&0.0) {
                return fail(m, "a mesh scale cannot be 0");
            }
            let inertia = match v.get("inertia").unwrap_or("legacy") {
                "legacy" => MeshInertia::Legacy,
                "exact" => MeshInertia::Exact,
                "shell" => MeshInertia::Shell,
                "convex" => {
                    self.ignore(
                        "mesh inertia=\"convex\" (computed as legacy, exact for convex meshes)",
                    );
                    MeshInertia::Legacy
                }
                other => return fail(m, format!("unknown mesh inertia '{other}'")),
            };
            for attr in ["refpos", "refquat"] {
                if m.attr(attr).is_some() {
                    return fail(
                        m,
                        format!("'{attr}' (deprecated in MuJoCo) is not supported"),
                    );
                }
            }
            let dir = self
                .compiler
                .meshdir
                .clone()
                .or_else(|| self.compiler.assetdir.clone());
            let file = match dir {
                Some(d) if !Path::new(file).is_absolute() => {
                    Path::new(&d).join(file).to_string_lossy().into_owned()
                }
                _ => file.to_string(),
            };
            if self
                .meshes
                .insert(
                    name.clone(),
                    MeshAsset {
                        file,
                        scale,
                        inertia,
                    },
                )
                .is_some()
            {
                return fail(m, format!("repeated mesh name '{name}'"));
            }
        }
        Ok(())
    }

    /// A mesh asset's mass properties per unit density (see [`inertia::mesh_mass`]), read from
    /// its file with MuJoCo's single-precision vertices.
    fn mesh_mass(&self, name: &str, g: &GeomData) -> Res<inertia::MeshMass> {
        let at = |message: String| Located {
            file: g.file,
            line: g.line,
            element: "geom".to_string(),
            message,
        };
        let Some(asset) = self.meshes.get(name) else {
            return Err(at(format!("unknown mesh '{name}'")));
        };
        let path = self.model_dir.join(&asset.file);
        let mesh = crate::mesh::read_mesh(&path)
            .map_err(|e| at(format!("mesh '{name}' ({}): {e}", path.display())))?;
        let single = crate::mesh::TriangleMesh {
            vertices: mesh
                .vertices
                .iter()
                .map(|v| v.as_vec3().as_dvec3())
                .collect(),
            triangles: mesh.triangles,
        }
        .scaled(DVec3::from_array(asset.scale));
        inertia::mesh_mass(&single.vertices, &single.triangles, asset.inertia)
            .map_err(|e| at(format!("mesh '{name}': {e}")))
    }

    /// The body's inertial frame, mass and principal moments as MuJoCo compiles them (before
    /// `settotalmass`).
    fn body_mass(&self, body: &BodyData<'a>) -> Res<BodyMass> {
        let zero = BodyMass {
            mass: 0.0,
            pos: DVec3::ZERO,
            rot: DMat3::IDENTITY,
            moments: [0.0; 3],
        };
        if body.world {
            return Ok(zero);
        }
        let explicit = body.inertial.as_ref().map(|i| BodyMass {
            mass: i.mass,
            pos: i.pos,
            rot: i.rot,
            moments: i.moments,
        });
        let c = &self.compiler;
        let infer = explicit.is_none() || c.inertia_from_geom == FromGeom::True;
        let use_geoms = c.inertia_from_geom == FromGeom::True
            || (explicit.is_none() && c.inertia_from_geom == FromGeom::Auto);
        let mut mass = if use_geoms {
            let mut geoms = Vec::new();
            for g in &body.geoms {
                if !infer || g.group < c.group_range[0] || g.group > c.group_range[1] {
                    continue;
                }
                let measure = g.solid.measure(g.spread);
                let m = match g.mass {
                    Some(0.0) => 0.0,
                    Some(m) if measure > MJ_EPS => m,
                    Some(_) => 0.0,
                    None if g.density == 0.0 => 0.0,
                    None => g.density * measure,
                };
                if m < 0.0 || g.density < 0.0 {
                    return Err(Located {
                        file: g.file,
                        line: g.line,
                        element: "geom".to_string(),
                        message: "mass or density is negative".to_string(),
                    });
                }
                match &g.mesh {
                    None => geoms.push(GeomMass {
                        mass: m,
                        pos: g.pose.translation,
                        rot: g.pose.rotation,
                        moments: g.solid.moments(m, g.spread),
                    }),
                    Some(mesh)
                        if g.mass.is_some_and(|m| m != 0.0)
                            || (g.mass.is_none() && g.density != 0.0) =>
                    {
                        let mm = self.mesh_mass(mesh, g)?;
                        let m = match g.mass {
                            Some(m) => m,
                            None => g.density * mm.measure,
                        };
                        let (eig, rot) = inertia::mesh_principal_axes(&mm.inertia);
                        geoms.push(GeomMass {
                            mass: m,
                            pos: g.pose.transform_point(mm.com),
                            rot: g.pose.rotation * rot,
                            moments: inertia::mesh_moments(eig, mm.measure, m),
                        });
                    }
                    Some(_) => {}
                }
            }
            match inertia::from_geoms(&geoms) {
                Ok(Some(total)) => total,
                Ok(None) => explicit.unwrap_or(zero),
                Err(m) => return fail(body.e, m),
            }
        } else {
            explicit.unwrap_or(zero)
        };
        mass.mass = mass.mass.max(c.boundmass);
        for m in &mut mass.moments {
            *m = m.max(c.boundinertia);
        }
        if mass.mass < 0.0 || mass.moments.iter().any(|m| *m < 0.0) {
            return fail(body.e, "mass and inertia cannot be negative");
        }
        let [a, b, cc] = mass.moments;
        // MuJoCo's check, with room for the last bits of the principal-axes decomposition.
        let slack = 1e-12 * (a + b + cc);
        if a + b + slack < cc || a + cc + slack < b || b + cc + slack < a {
            if c.balanceinertia {
                mass.moments = [(a + b + cc) / 3.0; 3];
            } else {
                return fail(
                    body.e,
                    format!(
                        "principal moments {:?} violate A + B >= C; use <compiler balanceinertia=\"true\"> to fix",
                        mass.moments
                    ),
                );
            }
        }
        Ok(mass)
    }

    /// Every body's mass properties in depth-first order (world first), `settotalmass` applied.
    fn masses(&self, world: &BodyData<'a>) -> Res<Vec<BodyMass>> {
        let mut out = Vec::new();
        let mut stack = vec![world];
        while let Some(b) = stack.pop() {
            out.push(self.body_mass(b)?);
            stack.extend(b.children.iter().rev());
        }
        if self.compiler.settotalmass > 0.0 {
            let total: f64 = out.iter().skip(1).map(|m| m.mass).sum();
            if total > MJ_EPS {
                let scale = self.compiler.settotalmass / total;
                for m in out.iter_mut().skip(1) {
                    m.mass *= scale;
                    for x in &mut m.moments {
                        *x *= scale;
                    }
                }
            }
        }
        Ok(out)
    }
}

/// Smallest mass and principal moment MuJoCo accepts on a moving body (`mjMINVAL`).
const MJ_MINVAL: f64 = 1e-15;

/// MuJoCo's check that every body with joints can move: it has mass and inertia, or one of its
/// welded (jointless) descendants reached without crossing a joint has. `next` is the body's id;
/// it is advanced past the subtree.
fn check_moving(body: &BodyData<'_>, masses: &[BodyMass], next: &mut usize) -> Res<()> {
    fn carries(body: &BodyData<'_>, masses: &[BodyMass], id: usize) -> bool {
        let m = &masses[id];
        if m.mass >= MJ_MINVAL && m.moments.iter().all(|x| *x >= MJ_MINVAL) {
            return true;
        }
        let mut child_id = id + 1;
        for c in &body.children {
            if c.joints.is_empty() && carries(c, masses, child_id) {
                return true;
            }
            child_id += subtree_size(c);
        }
        false
    }
    let id = *next;
    *next += 1;
    if !body.world && !body.joints.is_empty() && !carries(body, masses, id) {
        return fail(
            body.e,
            format!(
                "body '{}' has joints but no mass or inertia (mass {:e}, principal moments {:?}), which MuJoCo refuses",
                body.name.clone().unwrap_or_else(|| format!("body{id}")),
                masses[id].mass,
                masses[id].moments
            ),
        );
    }
    for c in &body.children {
        check_moving(c, masses, next)?;
    }
    Ok(())
}

fn subtree_size(body: &BodyData<'_>) -> usize {
    1 + body.children.iter().map(subtree_size).sum::<usize>()
}

/// Emits links, joints and frames for a body and its subtree, in MuJoCo's depth-first order.
struct Emitter<'m> {
    masses: &'m [BodyMass],
    body_id: usize,
    site_id: usize,
    notes: Vec<String>,
}

fn link_of(name: &str, body: &BodyData<'_>, mass: &BodyMass) -> Link {
    let mut link = Link::new(name);
    if mass.mass != 0.0 || mass.moments.iter().any(|m| *m != 0.0) {
        link.inertial = Some(Inertial {
            origin: Se3::new(mass.rot, mass.pos),
            mass: mass.mass,
            inertia: Symmetric3::from_diagonal(DVec3::from_array(mass.moments)),
        });
    }
    for g in &body.geoms {
        let Some(geometry) = &g.geometry else {
            continue;
        };
        link.visuals.push(Visual {
            name: g.name.clone(),
            origin: g.pose,
            geometry: geometry.clone(),
            material: None,
            color: g.rgba,
        });
        if g.collides {
            link.collisions.push(Collision {
                name: g.name.clone(),
                origin: g.pose,
                geometry: geometry.clone(),
            });
        }
    }
    link
}

impl Emitter<'_> {
    fn sites(&mut self, b: &mut ModelBuilder, body: &BodyData<'_>, link: &str) {
        for s in &body.sites {
            let name = s
                .name
                .clone()
                .unwrap_or_else(|| format!("site{}", self.site_id));
            self.site_id += 1;
            b.add_frame(FrameSpec::new(name, link, s.pose));
        }
    }

    fn body(
        &mut self,
        b: &mut ModelBuilder,
        body: &BodyData<'_>,
        parent: &str,
        parent_is_world: bool,
    ) -> Res<()> {
        let id = self.body_id;
        self.body_id += 1;
        let name = body.name.clone().unwrap_or_else(|| format!("body{id}"));
        b.add_link(link_of(&name, body, &self.masses[id]));
        let n = body.joints.len();
        let mut placement = body.pose;
        let mut prev = parent.to_string();
        if n == 0 {
            b.add_joint(
                JointSpec::new(format!("{name}:fixed"), JointKind::Fixed, &prev, &name)
                    .with_placement(placement),
            );
        }
        let free = body.joints.iter().any(|j| j.kind == MjJoint::Free);
        if free && (n > 1 || !parent_is_world) {
            return fail(
                body.e,
                "a free joint must be the only joint of a body whose parent is the world",
            );
        }
        let mut anchor = DVec3::ZERO;
        for (k, j) in body.joints.iter().enumerate() {
            let jname = j.name.clone().unwrap_or_else(|| format!("{name}:{k}"));
            let last = k + 1 == n;
            let child = if last && j.pos == DVec3::ZERO {
                name.clone()
            } else {
                let inner = format!("{name}:{k}");
                b.add_link(Link::new(&inner));
                inner
            };
            let (kind, limits) = match j.kind {
                MjJoint::Free => {
                    placement = Se3::IDENTITY;
                    (JointKind::Floating, JointLimits::UNLIMITED)
                }
                MjJoint::Ball => {
                    placement *= Se3::from_translation(j.pos);
                    if j.range.is_some() {
                        self.notes
                            .push(format!("joint '{jname}': ball joint cone limit (range)"));
                    }
                    (JointKind::Spherical, JointLimits::UNLIMITED)
                }
                MjJoint::Hinge => {
                    placement = placement
                        * Se3::from_translation(j.pos)
                        * Se3::from_axis_angle(j.axis, -j.reference);
                    match j.range {
                        Some([lo, hi]) => (JointKind::Revolute, JointLimits::position(lo, hi)),
                        None => (JointKind::Continuous, JointLimits::UNLIMITED),
                    }
                }
                MjJoint::Slide => {
                    placement = placement
                        * Se3::from_translation(j.pos)
                        * Se3::from_translation(-j.axis * j.reference);
                    match j.range {
                        Some([lo, hi]) => (JointKind::Prismatic, JointLimits::position(lo, hi)),
                        None => (JointKind::Prismatic, JointLimits::UNLIMITED),
                    }
                }
            };
            if j.stiffness != 0.0 {
                self.notes.push(format!(
                    "joint '{jname}': stiffness {} (springs are not modelled)",
                    j.stiffness
                ));
            }
            b.add_joint(
                JointSpec::new(jname, kind, &prev, &child)
                    .with_placement(placement)
                    .with_axis(j.axis)
                    .with_limits(limits)
                    .with_dynamics(j.dynamics),
            );
            prev = child;
            anchor = if j.kind == MjJoint::Free {
                DVec3::ZERO
            } else {
                j.pos
            };
            placement = Se3::from_translation(-anchor);
        }
        if n > 0 && anchor != DVec3::ZERO {
            b.add_joint(
                JointSpec::new(format!("{name}:anchor"), JointKind::Fixed, &prev, &name)
                    .with_placement(placement),
            );
        }
        self.sites(b, body, &name);
        for c in &body.children {
            self.body(b, c, &name, false)?;
        }
        Ok(())
    }
}

fn section_counts(root: &Element, ignored: &mut BTreeMap<String, usize>) -> Res<()> {
    const KNOWN: [&str; 6] = [
        "compiler",
        "default",
        "asset",
        "worldbody",
        "include",
        "plugin",
    ];
    for s in &root.children {
        let name = s.name.as_str();
        if UNMODELLED.contains(&name) {
            for c in &s.children {
                *ignored.entry(format!("{name}/{}", c.name)).or_default() += 1;
            }
        } else if !PRESENTATION.contains(&name) && !KNOWN.contains(&name) {
            return fail(s, format!("unknown element <{name}> in <mujoco>"));
        }
    }
    Ok(())
}

fn gravity(root: &Element) -> Res<DVec3> {
    let mut g = DVec3::new(0.0, 0.0, -9.81);
    let mut enabled = true;
    for o in root.children.iter().filter(|c| c.name == "option") {
        if let Some(t) = o.attr("gravity") {
            g = DVec3::from_array(exact::<3>(o, "gravity", t)?);
        }
        for f in o.children.iter().filter(|c| c.name == "flag") {
            if let Some(t) = f.attr("gravity") {
                enabled = match t {
                    "enable" => true,
                    "disable" => false,
                    other => {
                        return fail(
                            f,
                            format!("gravity flag '{other}' is not 'enable' or 'disable'"),
                        );
                    }
                };
            }
        }
    }
    Ok(if enabled { g } else { DVec3::ZERO })
}

fn compile(root: &Element, fallback_name: &str, model_dir: &Path) -> Res<ModelBuilder> {
    let mut compiler = Compiler::default();
    for c in root.children.iter().filter(|c| c.name == "compiler") {
        read_compiler(c, &mut compiler)?;
    }
    let mut defaults = Defaults::new();
    for d in root.children.iter().filter(|c| c.name == "default") {
        defaults.read(d, None, 0)?;
    }
    let mut ignored = BTreeMap::new();
    section_counts(root, &mut ignored)?;
    let mut reader = Reader {
        compiler,
        defaults: &defaults,
        meshes: HashMap::new(),
        model_dir: model_dir.to_path_buf(),
        ignored,
        notes: Vec::new(),
    };
    for a in root.children.iter().filter(|c| c.name == "asset") {
        reader.read_meshes(a)?;
    }
    let mut world = BodyData {
        e: root,
        world: true,
        name: Some(WORLD_BODY.to_string()),
        pose: Se3::IDENTITY,
        joints: Vec::new(),
        geoms: Vec::new(),
        sites: Vec::new(),
        inertial: None,
        children: Vec::new(),
    };
    for w in root.children.iter().filter(|c| c.name == "worldbody") {
        if let Some((k, _)) = w.attrs.first() {
            return fail(
                w,
                format!("the world body cannot have attributes (got '{k}')"),
            );
        }
        let scope = Scope {
            class: 0,
            frame: Se3::IDENTITY,
            depth: 0,
        };
        reader.read_children(w, scope, &mut world)?;
    }
    let masses = reader.masses(&world)?;
    check_moving(&world, &masses, &mut 0)?;
    let name = root.attr("model").unwrap_or(fallback_name);
    let mut b = ModelBuilder::new(name);
    b.gravity(gravity(root)?);
    b.add_link(link_of(WORLD_BODY, &world, &masses[0]));
    let mut emitter = Emitter {
        masses: &masses,
        body_id: 1,
        site_id: 0,
        notes: Vec::new(),
    };
    emitter.sites(&mut b, &world, WORLD_BODY);
    for c in &world.children {
        emitter.body(&mut b, c, WORLD_BODY, true)?;
    }
    for (what, count) in &reader.ignored {
        b.note_ignored(if *count == 1 {
            what.clone()
        } else {
            format!("{what} (×{count})")
        });
    }
    for note in reader.notes.iter().chain(&emitter.notes) {
        b.note_ignored(note.clone());
    }
    let _ = &reader.model_dir;
    Ok(b)
}

/// Reads an MJCF document; `path` is where it came from (for `<include>`, mesh folders and
/// error messages).
pub(crate) fn from_mjcf(text: &str, path: Option<&Path>) -> Result<Model, ModelError> {
    let mut files = Files {
        paths: vec![path.map(Path::to_path_buf)],
    };
    let mut root = xml_tree::parse(text, 0).map_err(|x| ModelError::Xml {
        file: path.map(Path::to_path_buf),
        line: x.line,
        column: x.column,
        message: x.message,
    })?;
    if root.name != "mujoco" {
        return Err(files.error(Located {
            file: 0,
            line: root.line,
            element: root.name.clone(),
            message: "the root element of an MJCF file is <mujoco>".to_string(),
        }));
    }
    let model_dir = path
        .and_then(Path::parent)
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let fallback = path
        .and_then(Path::file_stem)
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mujoco".to_string());
    let mut included = HashSet::new();
    if let Some(p) = path {
        included.insert(p.canonicalize().unwrap_or_else(|_| p.to_path_buf()));
    }
    let result = expand_includes(&mut root, &mut files, &model_dir, &mut included, 0)
        .and_then(|()| compile(&root, &fallback, &model_dir));
    xml_tree::drop_flat(root);
    result.map_err(|l| files.error(l))?.build()
}
