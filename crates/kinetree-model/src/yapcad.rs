//! yapCAD's kinematic-chain JSON, as `KinematicChain.export_json` writes it, read as it is.
//!
//! The file is `{"name", "parts": {NAME: {name, parent, parent_frame, joint: {name, type, axis,
//! value, limits, base_transform}, frames: {NAME: {name, transform, datum_source, datum_name,
//! description}}, stl_path, is_printable, material, color, description, world_transform}}}`,
//! in millimetres and degrees. [`Model::from_json_str`] and [`Model::from_file`] recognise it by
//! that shape (`parts` is an object of parts rather than kinetree's list of links);
//! [`Model::from_yapcad_str`] and [`Model::from_yapcad_file`] read it explicitly and also return
//! the joint values and the exported world poses.
//!
//! How yapCAD's conventions map to kinetree's:
//! - lengths (mm) and angles (deg) are converted to m and rad;
//! - a part is a link; a part whose parent is `GLOBAL_DATUM` (or missing) is a root part,
//!   attached to the world by its own joint ([`WORLD_NAMES`](crate::WORLD_NAMES));
//! - a part's joint attaches it to its parent's `parent_frame` (kept on the joint as
//!   [`Joint::parent_frame`](crate::Joint::parent_frame)); `ORIGIN` is the part's own frame. A
//!   parent frame the parent part does not define falls back to `ORIGIN`, as yapCAD does, with
//!   an [`Issue::ParentFrameFallback`] warning;
//! - a transform's 4×4 `matrix` is authoritative (its translation in mm); without one,
//!   `translation` and `rotation_xyz` (URDF roll-pitch-yaw, `R = Rz·Ry·Rx`, although yapCAD's docs
//!   call it intrinsic XYZ) are used;
//! - a joint moves its part by `base_transform · motion(axis, value)`;
//! - `limits` apply as written (yapCAD defaults them to ±180 for every joint type, so a
//!   prismatic joint left at its default is limited to ±180 mm);
//! - yapCAD's cylindrical joint only rotates (its `value` is an angle): it is read as a
//!   revolute joint, so that its value and limits keep their meaning (noted in
//!   [`Model::ignored`]); a spherical joint's `value` is ignored (identity rotation);
//! - frames other than an identity `ORIGIN` become named frames of their part (address them as
//!   `part/frame`); `stl_path`, `material`, `color`, `is_printable` and `description` become the
//!   part's [`LinkMetadata`];
//! - each part's `world_transform` is compared with the pose the joint values give; a
//!   difference over 1e-6 m or 1e-6 rad is reported as [`Issue::WorldPoseMismatch`] in
//!   [`Model::warnings`], naming the part and the distance.

use crate::builder::{FrameSpec, JointSpec, ModelBuilder};
use crate::error::{Issue, ModelError};
use crate::joint::{JointKind, JointLimits};
use crate::link::{Link, LinkMetadata};
use crate::model::Model;
use glam::DVec3;
use kinetree_spatial::{Se3, rotation};
use serde::Deserialize;
use serde::de::{MapAccess, Visitor};
use std::path::Path;

/// The tolerance of the `world_transform` check: metres for the position, radians for the
/// orientation.
pub const WORLD_POSE_TOLERANCE: f64 = 1e-6;

/// A yapCAD chain read by [`Model::from_yapcad_str`]: the model, the joint values stored in the
/// file and the world poses yapCAD exported.
#[derive(Clone, Debug)]
pub struct YapcadChain {
    /// The model (SI units).
    pub model: Model,
    /// The configuration the file's joint values give (length `model.nq()`; spherical joints at
    /// the identity).
    pub q: Vec<f64>,
    /// The `world_transform` yapCAD exported for each link (in link order; `None` when the part
    /// has none), in metres.
    pub world_poses: Vec<Option<Se3>>,
}

#[derive(Deserialize)]
struct TransformDoc {
    #[serde(default)]
    translation: Option<[f64; 3]>,
    #[serde(default)]
    rotation_xyz: Option<[f64; 3]>,
    #[serde(default)]
    matrix: Option<[[f64; 4]; 4]>,
}

#[derive(Deserialize)]
struct JointDoc {
    #[serde(default)]
    name: Option<String>,
    #[serde(rename = "type", default)]
    kind: Option<String>,
    #[serde(default)]
    axis: Option<[f64; 3]>,
    #[serde(default)]
    value: Option<f64>,
    #[serde(default)]
    limits: Option<[f64; 2]>,
    #[serde(default)]
    base_transform: Option<TransformDoc>,
}

#[derive(Deserialize)]
struct FrameDoc {
    #[serde(default)]
    transform: Option<TransformDoc>,
    #[serde(default)]
    datum_source: Option<String>,
    #[serde(default)]
    datum_name: Option<String>,
    #[serde(default)]
    description: Option<String>,
}

#[derive(Deserialize)]
struct PartDoc {
    #[serde(default)]
    parent: Option<String>,
    #[serde(default)]
    parent_frame: Option<String>,
    #[serde(default)]
    joint: Option<JointDoc>,
    #[serde(default)]
    frames: Option<Ordered<FrameDoc>>,
    #[serde(default)]
    stl_path: Option<String>,
    #[serde(default)]
    is_printable: Option<bool>,
    #[serde(default)]
    material: Option<String>,
    #[serde(default)]
    color: Option<Vec<f64>>,
    #[serde(default)]
    description: Option<String>,
    #[serde(default)]
    world_transform: Option<TransformDoc>,
}

#[derive(Deserialize)]
struct ChainDoc {
    #[serde(default)]
    name: Option<String>,
    parts: Ordered<PartDoc>,
}

/// A JSON object read in file order (yapCAD writes parts in the order they were added).
struct Ordered<T>(Vec<(String, T)>);

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Ordered<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V<T>(core::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for V<T> {
            type Value = Ordered<T>;
            fn expecting(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str("an object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Ordered<T>, A::Error> {
                let mut out = Vec::new();
                while let Some(entry) = map.next_entry()? {
                    out.push(entry);
                }
                Ok(Ordered(out))
            }
        }
        d.deserialize_map(V(core::marker::PhantomData))
    }
}

/// Whether `text` looks like a yapCAD export: a JSON object whose `parts` is an object of
/// objects that have a `joint` or a `parent` (kinetree's own schema has a list there).
#[must_use]
pub fn is_yapcad_json(text: &str) -> bool {
    let Ok(serde_json::Value::Object(doc)) = serde_json::from_str::<serde_json::Value>(text) else {
        return false;
    };
    match doc.get("parts") {
        Some(serde_json::Value::Object(parts)) => parts.values().all(|p| {
            p.as_object()
                .is_some_and(|p| p.contains_key("joint") || p.contains_key("parent"))
        }),
        _ => false,
    }
}

fn mm(x: f64) -> f64 {
    x / 1000.0
}

/// A yapCAD transform in SI: the matrix when it is a rigid transform, otherwise translation and
/// roll-pitch-yaw.
fn transform(t: Option<&TransformDoc>) -> Result<Se3, String> {
    let Some(t) = t else {
        return Ok(Se3::IDENTITY);
    };
    if let Some(m) = &t.matrix {
        let mut rows = *m;
        for row in rows.iter_mut().take(3) {
            row[3] = mm(row[3]);
        }
        if let Some(p) = Se3::from_rows(&rows) {
            return Ok(p);
        }
        // Tolerate rounding in a written matrix, as kinetree's own loader does.
        let r = glam::DMat3::from_cols(
            DVec3::new(rows[0][0], rows[1][0], rows[2][0]),
            DVec3::new(rows[0][1], rows[1][1], rows[2][1]),
            DVec3::new(rows[0][2], rows[1][2], rows[2][2]),
        );
        if rows[3] == [0.0, 0.0, 0.0, 1.0] && rotation::is_rotation(&r, 1e-4) {
            let r = rotation::orthonormalize(&r);
            return Ok(Se3::new(r, DVec3::new(rows[0][3], rows[1][3], rows[2][3])));
        }
        return Err("`matrix` is not a rigid transform".into());
    }
    let xyz = t.translation.unwrap_or([0.0; 3]).map(mm);
    let rpy = t.rotation_xyz.unwrap_or([0.0; 3]).map(f64::to_radians);
    let p = Se3::from_xyz_rpy(xyz, rpy);
    if p.is_finite() {
        Ok(p)
    } else {
        Err("non-finite translation or rotation".into())
    }
}

fn kind_of(name: &str) -> Option<JointKind> {
    Some(match name.to_ascii_lowercase().as_str() {
        "fixed" => JointKind::Fixed,
        "revolute" | "cylindrical" => JointKind::Revolute,
        "prismatic" => JointKind::Prismatic,
        "spherical" => JointKind::Spherical,
        _ => return None,
    })
}

fn chain_from_text(text: &str, file: Option<&Path>) -> Result<YapcadChain, ModelError> {
    let bad = |message: String| ModelError::Json {
        file: file.map(Path::to_path_buf),
        line: 0,
        column: 0,
        message: format!("yapCAD chain: {message}"),
    };
    let doc: ChainDoc = serde_json::from_str(text).map_err(|e| ModelError::Json {
        file: file.map(Path::to_path_buf),
        line: e.line(),
        column: e.column(),
        message: format!("yapCAD chain: {e}"),
    })?;
    let mut b = ModelBuilder::new(doc.name.clone().unwrap_or_else(|| "assembly".into()));
    let part_names: std::collections::HashSet<&str> =
        doc.parts.0.iter().map(|(n, _)| n.as_str()).collect();
    let mut joint_names = std::collections::HashSet::new();
    // (joint name, kind, value in SI) per part, for the configuration.
    let mut values = Vec::new();
    let mut exported = Vec::new();
    for (name, part) in &doc.parts.0 {
        let mut link = Link::new(name.clone());
        link.metadata = LinkMetadata {
            description: part.description.clone().filter(|d| !d.is_empty()),
            material: part.material.clone(),
            color: match part.color.as_deref() {
                Some(&[r, g, b]) => Some([r, g, b, 1.0]),
                Some(&[r, g, b, a]) => Some([r, g, b, a]),
                _ => None,
            },
            mesh: part.stl_path.clone(),
            printable: part.is_printable.unwrap_or(true),
        };
        b.add_link(link);
        for (fname, f) in part.frames.as_ref().map_or(&[][..], |f| &f.0[..]) {
            let pose = transform(f.transform.as_ref())
                .map_err(|m| bad(format!("frame '{fname}' of part '{name}': {m}")))?;
            if fname == crate::builder::ORIGIN_FRAME && pose == Se3::IDENTITY {
                continue; // the implicit part frame
            }
            if let (Some(file), Some(datum)) = (&f.datum_source, &f.datum_name) {
                b.note_ignored(format!(
                    "frame '{name}/{fname}': datum '{datum}' of '{file}' (its exported pose is used)"
                ));
            }
            let mut spec = FrameSpec::new(fname.clone(), name.clone(), pose);
            spec.description = f.description.clone().filter(|d| !d.is_empty());
            b.add_frame(spec);
        }
        let j = part.joint.as_ref();
        let kind_name = j
            .and_then(|j| j.kind.clone())
            .unwrap_or_else(|| "fixed".into());
        let kind = kind_of(&kind_name)
            .ok_or_else(|| bad(format!("part '{name}': unknown joint type '{kind_name}'")))?;
        let mut jname = j
            .and_then(|j| j.name.clone())
            .unwrap_or_else(|| format!("{name}_joint"));
        if !joint_names.insert(jname.clone()) {
            // yapCAD does not require unique joint names; kinetree does.
            jname = format!("{name}_{jname}");
            joint_names.insert(jname.clone());
        }
        if kind_name.eq_ignore_ascii_case("cylindrical") {
            b.note_ignored(format!(
                "joint '{jname}': yapCAD's cylindrical joint only rotates; read as revolute"
            ));
        }
        let parent = match part.parent.as_deref() {
            None | Some("GLOBAL_DATUM") => "GLOBAL_DATUM".to_string(),
            Some(p) => p.to_string(),
        };
        let base = transform(j.and_then(|j| j.base_transform.as_ref()))
            .map_err(|m| bad(format!("base_transform of joint '{jname}': {m}")))?;
        let [lo, hi] = j.and_then(|j| j.limits).unwrap_or([-180.0, 180.0]);
        let (limits, value) = match kind {
            JointKind::Prismatic => (
                JointLimits::position(mm(lo), mm(hi)),
                mm(j.and_then(|j| j.value).unwrap_or(0.0)),
            ),
            JointKind::Revolute => (
                JointLimits::position(lo.to_radians(), hi.to_radians()),
                j.and_then(|j| j.value).unwrap_or(0.0).to_radians(),
            ),
            _ => (JointLimits::UNLIMITED, 0.0),
        };
        let mut spec = JointSpec::new(jname.clone(), kind, parent.clone(), name.clone())
            .with_placement(base)
            .with_axis(j.and_then(|j| j.axis).map_or(DVec3::Z, DVec3::from_array))
            .with_limits(limits);
        if parent != "GLOBAL_DATUM" {
            let frame = part
                .parent_frame
                .clone()
                .unwrap_or_else(|| crate::builder::ORIGIN_FRAME.into());
            let defined = doc.parts.0.iter().any(|(n, p)| {
                n == &parent
                    && p.frames
                        .as_ref()
                        .is_some_and(|f| f.0.iter().any(|(f, _)| f == &frame))
            });
            if defined {
                spec = spec.at_frame(frame);
            } else if frame != crate::builder::ORIGIN_FRAME && part_names.contains(parent.as_str())
            {
                b.note_warning(Issue::ParentFrameFallback {
                    joint: jname.clone(),
                    frame,
                    link: parent.clone(),
                });
            }
        }
        b.add_joint(spec);
        values.push((jname, value));
        exported.push((
            name.clone(),
            part.world_transform
                .as_ref()
                .map(|t| transform(Some(t)))
                .transpose()
                .map_err(|m| bad(format!("world_transform of part '{name}': {m}")))?,
        ));
    }
    let model = b.build()?;
    let mut q = vec![0.0; model.nq()];
    for (jname, value) in values {
        let Some(ji) = model.joint_index(&jname) else {
            continue;
        };
        let range = model.joint_q_range(ji);
        match range.len() {
            1 => q[range.start] = value,
            4 => q[range.start + 3] = 1.0,
            _ => {}
        }
    }
    let mut world_poses = vec![None; model.links().len()];
    for (part, pose) in exported {
        if let Some(l) = model.link_index(&part) {
            world_poses[l] = pose;
        }
    }
    let mut model = model;
    let computed = world_placements(&model, &q);
    for (l, pose) in world_poses.iter().enumerate() {
        let Some(pose) = pose else { continue };
        let distance = (computed[l].translation - pose.translation).length();
        let angle = rotation::log3(&(computed[l].rotation.transpose() * pose.rotation)).length();
        if distance > WORLD_POSE_TOLERANCE || angle > WORLD_POSE_TOLERANCE {
            model.warnings.push(Issue::WorldPoseMismatch {
                part: model.link(l).name.clone(),
                distance,
                angle,
            });
        }
    }
    Ok(YapcadChain {
        model,
        q,
        world_poses,
    })
}

/// World pose of every link at `q` for the joint kinds a yapCAD chain has (fixed, revolute,
/// prismatic, spherical); the kinematics layer's forward kinematics agrees with it (tested
/// there).
fn world_placements(model: &Model, q: &[f64]) -> Vec<Se3> {
    let mut world = vec![Se3::IDENTITY; model.links().len()];
    for l in 0..model.links().len() {
        let Some(ji) = model.parent_joint(l) else {
            continue;
        };
        let j = model.joint(ji);
        let parent = j.parent_link.map_or(Se3::IDENTITY, |p| world[p]);
        let r = model.joint_q_range(ji);
        let motion = match j.kind {
            JointKind::Revolute | JointKind::Continuous => Se3::from_axis_angle(j.axis, q[r.start]),
            JointKind::Prismatic => Se3::from_translation(j.axis * q[r.start]),
            JointKind::Spherical => Se3::from_quat(glam::DQuat::from_xyzw(
                q[r.start],
                q[r.start + 1],
                q[r.start + 2],
                q[r.start + 3],
            )),
            _ => Se3::IDENTITY,
        };
        world[l] = parent * j.placement * motion;
    }
    world
}

impl Model {
    /// Reads a yapCAD chain (see the [module docs](crate::yapcad)): the model, the joint values
    /// stored in the file as a configuration, and the exported world poses; mismatches between
    /// those poses and the joint values are listed in [`Model::warnings`].
    ///
    /// # Errors
    /// [`ModelError::Json`] for malformed JSON, an unknown joint type or a transform that is
    /// not rigid (naming the part); [`ModelError::Invalid`] when the parts do not form a tree.
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::Model;
    /// # fn main() -> Result<(), kinetree_model::ModelError> {
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"),
    ///                    "/../../tests/data/yapcad/yap_quickstart.yapcad.json");
    /// let chain = Model::from_yapcad_file(path)?;
    /// assert_eq!(chain.model.nq(), 1);
    /// assert!((chain.q[0] - 45f64.to_radians()).abs() < 1e-15); // 45° in the file
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_yapcad_str(json: &str) -> Result<YapcadChain, ModelError> {
        chain_from_text(json, None)
    }

    /// Reads a yapCAD chain file (see [`Model::from_yapcad_str`]).
    ///
    /// # Errors
    /// [`ModelError::Io`] when the file cannot be read, otherwise as
    /// [`Model::from_yapcad_str`], with the file named.
    pub fn from_yapcad_file(path: impl AsRef<Path>) -> Result<YapcadChain, ModelError> {
        let path = path.as_ref();
        let text = crate::error::read_text(path)?;
        chain_from_text(&text, Some(path))
    }
}

/// The model of a yapCAD chain read from text, for the JSON loaders that recognise the shape.
pub(crate) fn model_from_text(text: &str, file: Option<&Path>) -> Result<Model, ModelError> {
    chain_from_text(text, file).map(|c| c.model)
}
