//! The model layer's error type.

use core::fmt;
use kinetree_spatial::{InertiaDefect, Readable};
use std::path::PathBuf;

/// Everything that can go wrong while loading or building a [`Model`](crate::Model).
///
/// Loading never returns a half-built model: either every check passes or an error comes back.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// A file could not be read or written.
    #[error("cannot access {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A model file is readable but is not UTF-8 text (UTF-16 from some editors, or binary).
    #[error("{} is {reason}", path.display())]
    Encoding {
        /// The file.
        path: PathBuf,
        /// What the bytes look like and how to convert them.
        reason: String,
    },
    /// The XML is malformed (before any URDF interpretation).
    #[error("malformed XML{}: {message}", location(.file.as_deref(), *.line, *.column))]
    Xml {
        /// The file, when loading from a path.
        file: Option<PathBuf>,
        /// 1-based line of the error.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// The XML is well formed but is not a URDF that urdf-rs can read (missing attributes,
    /// numbers that do not parse, …).
    #[error("invalid URDF{}: {message}", file.as_ref().map(|f| format!(" in {}", f.display())).unwrap_or_default())]
    Urdf {
        /// The file, when loading from a path.
        file: Option<PathBuf>,
        /// The parser's message.
        message: String,
    },
    /// The XML is well formed but is not an MJCF model that MuJoCo's compiler (or kinetree's
    /// reading of it) accepts: unknown elements or classes, missing or malformed attributes,
    /// impossible inertias, `<include>` loops, elements kinetree cannot load yet.
    #[error("invalid MJCF{}: <{element}>: {message}", location(.file.as_deref(), *.line, 0))]
    Mjcf {
        /// The file holding the element (an included file when it came from one).
        file: Option<PathBuf>,
        /// 1-based line of the element's start tag.
        line: usize,
        /// The element's name.
        element: String,
        /// What is wrong.
        message: String,
    },
    /// The XML is well formed but is not an SDFormat model kinetree can load: malformed values,
    /// unknown names in `relative_to`/`attached_to`/`<parent>`/`<child>`, pose-graph or joint
    /// cycles, `<include>` loops, missing included files or meshes, absurd numbers, joint types
    /// kinetree cannot express (screw, gearbox).
    #[error("invalid SDFormat{}: <{element}>: {message}", location(.file.as_deref(), *.line, 0))]
    Sdf {
        /// The file holding the element (an included file when it came from one).
        file: Option<PathBuf>,
        /// 1-based line of the element's start tag.
        line: usize,
        /// The element's name.
        element: String,
        /// What is wrong.
        message: String,
    },
    /// The JSON is malformed or does not follow the schema (unknown fields included).
    #[error("invalid JSON{}: {message}", location(.file.as_deref(), *.line, *.column))]
    Json {
        /// The file, when loading from a path.
        file: Option<PathBuf>,
        /// 1-based line (0 when unknown).
        line: usize,
        /// 1-based column (0 when unknown).
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// A unit name in a JSON `units` block is not known.
    #[error("unknown {quantity} unit '{unit}' (known: {known})")]
    UnknownUnit {
        /// `"length"` or `"angle"`.
        quantity: &'static str,
        /// The unit as written.
        unit: String,
        /// The accepted names.
        known: &'static str,
    },
    /// An external datum file or a datum in it is missing or malformed.
    #[error("frame '{frame}': datum '{datum}' in {}: {message}", file.display())]
    Datum {
        /// The frame that refers to the datum.
        frame: String,
        /// The datum file.
        file: PathBuf,
        /// The datum's name.
        datum: String,
        /// What went wrong.
        message: String,
    },
    /// The format of a model file cannot be told from its extension or its content.
    #[error("cannot tell the format of {}: expected a .urdf, .xml or .json file", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// A joint kind that the target format cannot express (URDF has no cylindrical joint).
    #[error("joint '{joint}' is {kind}, which {format} cannot express")]
    UnsupportedJoint {
        /// The target format, e.g. `"URDF"`.
        format: &'static str,
        /// The joint.
        joint: String,
        /// Its kind.
        kind: crate::JointKind,
    },
    /// A model feature the target format cannot express (several roots in a URDF).
    #[error("{format} cannot express this model: {what}")]
    Unsupported {
        /// The target format, e.g. `"URDF"`.
        format: &'static str,
        /// What cannot be written.
        what: String,
    },
    /// An input slice has the wrong length.
    #[error("{what}: expected length {expected}, got {actual}")]
    Length {
        /// What the slice holds.
        what: &'static str,
        /// The required length.
        expected: usize,
        /// The length given.
        actual: usize,
    },
    /// A Denavit–Hartenberg table is not usable.
    #[error("DH table row {row}: {message}")]
    DhTable {
        /// 0-based row.
        row: usize,
        /// What is wrong.
        message: String,
    },
    /// The model is inconsistent; every problem found is listed.
    #[error("invalid model '{model}': {}", Issues(.issues))]
    Invalid {
        /// The model's name.
        model: String,
        /// Every problem found, in the order checked.
        issues: Vec<Issue>,
    },
}

fn location(file: Option<&std::path::Path>, line: usize, column: usize) -> String {
    let mut s = String::new();
    if let Some(f) = file {
        s.push_str(&format!(" in {}", f.display()));
    }
    if line > 0 && column > 0 {
        s.push_str(&format!(" at line {line}, column {column}"));
    } else if line > 0 {
        s.push_str(&format!(" at line {line}"));
    }
    s
}

struct Issues<'a>(&'a [Issue]);

impl fmt::Display for Issues<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, issue) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str("; ")?;
            }
            write!(f, "{issue}")?;
        }
        Ok(())
    }
}

/// What kind of named item an [`Issue`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ItemKind {
    /// A link.
    Link,
    /// A joint.
    Joint,
    /// A frame.
    Frame,
}

impl fmt::Display for ItemKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Link => "link",
            Self::Joint => "joint",
            Self::Frame => "frame",
        })
    }
}

/// One problem found while validating a model.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Issue {
    /// Two items of the same kind share a name.
    DuplicateName {
        /// Links, joints or frames.
        kind: ItemKind,
        /// The repeated name.
        name: String,
    },
    /// A joint names a parent link that does not exist.
    UnknownParent {
        /// The joint.
        joint: String,
        /// The missing link.
        link: String,
    },
    /// A joint names a child link that does not exist.
    UnknownChild {
        /// The joint.
        joint: String,
        /// The missing link.
        link: String,
    },
    /// A joint attaches to a frame that does not exist on its parent link.
    UnknownParentFrame {
        /// The joint.
        joint: String,
        /// The missing frame.
        frame: String,
        /// The parent link.
        link: String,
    },
    /// A frame is attached to a link that does not exist.
    UnknownFrameLink {
        /// The frame.
        frame: String,
        /// The missing link.
        link: String,
    },
    /// A link is the child of more than one joint.
    MultipleParents {
        /// The link.
        link: String,
        /// The joints claiming it.
        joints: Vec<String>,
    },
    /// Several links have no parent joint.
    MultipleRoots {
        /// The parentless links.
        links: Vec<String>,
    },
    /// Every link has a parent joint, so there is no root.
    NoRoot,
    /// Links form a cycle (a closed chain cannot be a tree).
    Cycle {
        /// A link on the cycle.
        link: String,
    },
    /// A joint's axis is zero or not finite.
    InvalidAxis {
        /// The joint.
        joint: String,
        /// The axis as given.
        axis: [f64; 3],
    },
    /// A joint's lower limit exceeds its upper limit.
    InvalidLimits {
        /// The joint.
        joint: String,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// A number is NaN or infinite where a finite value is required.
    NonFinite {
        /// Link, joint or frame.
        kind: ItemKind,
        /// Its name.
        name: String,
        /// Which value (e.g. "origin", "mass", "axis", "limit velocity").
        what: &'static str,
    },
    /// A negative mass or physically impossible rotational inertia.
    InvalidInertia {
        /// The link.
        link: String,
        /// Mass as given.
        mass: f64,
        /// What fails.
        defect: InertiaDefect,
    },
    /// A link has zero mass but a non-zero rotational inertia, which no rigid body has (a
    /// warning by default, as [`Self::InvalidInertia`]; the inertia is used as given).
    MasslessInertia {
        /// The link.
        link: String,
        /// The largest absolute entry of the inertia tensor, kg·m².
        largest: f64,
    },
    /// A mimic joint follows a joint that does not exist.
    UnknownMimicTarget {
        /// The mimic joint.
        joint: String,
        /// The missing leader.
        target: String,
    },
    /// A mimic joint follows itself or a joint of a different dimension.
    InvalidMimic {
        /// The mimic joint.
        joint: String,
        /// Why.
        reason: String,
    },
    /// A placement's rotation is not a rotation matrix.
    InvalidRotation {
        /// Link, joint or frame.
        kind: ItemKind,
        /// Its name.
        name: String,
    },
    /// A geometry has a negative or non-finite size.
    InvalidGeometry {
        /// The link.
        link: String,
        /// What is wrong.
        reason: String,
    },
    /// A joint's damping, friction or armature is negative (it would feed energy into the motion).
    InvalidJointDynamics {
        /// The joint.
        joint: String,
        /// `"damping"`, `"friction"` or `"armature"`.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A part's exported world pose (yapCAD's `world_transform`) differs from the pose its
    /// joint values give (a warning: the joint values win).
    WorldPoseMismatch {
        /// The part (link).
        part: String,
        /// Distance between the two positions (m).
        distance: f64,
        /// Angle between the two orientations (rad).
        angle: f64,
    },
    /// A joint attaches to a frame its parent part does not define; the part's own frame
    /// (`ORIGIN`) is used instead, as yapCAD does (a warning).
    ParentFrameFallback {
        /// The joint.
        joint: String,
        /// The missing frame.
        frame: String,
        /// The parent part.
        link: String,
    },
    /// A floating or planar joint is attached below the root where the model does not support it,
    /// or a root joint is declared twice.
    InvalidRootJoint {
        /// The joint.
        joint: String,
        /// Why.
        reason: String,
    },
    /// A composite joint's spec is inconsistent (a state variable twice, a zero quaternion, a
    /// joint attached inside it, …).
    InvalidComposite {
        /// The composite joint.
        joint: String,
        /// Why.
        reason: String,
    },
}

impl fmt::Display for Issue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::DuplicateName { kind, name } => write!(f, "duplicate {kind} name '{name}'"),
            Self::UnknownParent { joint, link } => {
                write!(f, "joint '{joint}' has unknown parent link '{link}'")
            }
            Self::UnknownChild { joint, link } => {
                write!(f, "joint '{joint}' has unknown child link '{link}'")
            }
            Self::UnknownParentFrame { joint, frame, link } => {
                write!(
                    f,
                    "joint '{joint}' attaches to unknown frame '{frame}' of link '{link}'"
                )
            }
            Self::UnknownFrameLink { frame, link } => {
                write!(f, "frame '{frame}' is attached to unknown link '{link}'")
            }
            Self::MultipleParents { link, joints } => {
                write!(
                    f,
                    "link '{link}' is the child of several joints: {}",
                    joints.join(", ")
                )
            }
            Self::MultipleRoots { links } => {
                write!(
                    f,
                    "several root links (links without a parent joint): {}",
                    links.join(", ")
                )
            }
            Self::NoRoot => write!(f, "no root link: every link has a parent joint"),
            Self::Cycle { link } => write!(f, "the joints form a cycle through link '{link}'"),
            Self::InvalidAxis { joint, axis } => {
                write!(f, "joint '{joint}' has a zero or non-finite axis {axis:?}")
            }
            Self::InvalidLimits {
                joint,
                lower,
                upper,
            } => {
                write!(
                    f,
                    "joint '{joint}' has lower limit {} > upper limit {}",
                    Readable(*lower),
                    Readable(*upper)
                )
            }
            Self::NonFinite { kind, name, what } => {
                write!(f, "{kind} '{name}' has a non-finite {what}")
            }
            Self::InvalidInertia { link, mass, defect } => {
                write!(
                    f,
                    "link '{link}' has an invalid inertia (mass {}): {defect}",
                    Readable(*mass)
                )
            }
            Self::MasslessInertia { link, largest } => write!(
                f,
                "link '{link}' has mass 0 but a rotational inertia (largest entry {} kg·m²): no rigid body has one without the other",
                Readable(*largest)
            ),
            Self::UnknownMimicTarget { joint, target } => {
                write!(f, "joint '{joint}' mimics unknown joint '{target}'")
            }
            Self::InvalidMimic { joint, reason } => {
                write!(f, "joint '{joint}': invalid mimic: {reason}")
            }
            Self::InvalidRotation { kind, name } => {
                write!(
                    f,
                    "{kind} '{name}' has a placement whose rotation is not orthonormal"
                )
            }
            Self::InvalidGeometry { link, reason } => {
                write!(f, "link '{link}' has invalid geometry: {reason}")
            }
            Self::InvalidRootJoint { joint, reason } => write!(f, "joint '{joint}': {reason}"),
            Self::InvalidComposite { joint, reason } => {
                write!(f, "composite joint '{joint}': {reason}")
            }
            Self::InvalidJointDynamics { joint, what, value } => write!(
                f,
                "joint '{joint}' has a negative {what} ({}); it must be zero or positive",
                Readable(*value)
            ),
            Self::WorldPoseMismatch {
                part,
                distance,
                angle,
            } => write!(
                f,
                "part '{part}': exported world pose is {distance:.3e} m and {angle:.3e} rad away from the pose its joint values give"
            ),
            Self::ParentFrameFallback { joint, frame, link } => write!(
                f,
                "joint '{joint}' attaches to frame '{frame}', which part '{link}' does not define; its ORIGIN is used"
            ),
        }
    }
}

impl ModelError {
    /// The validation issues, when this is [`ModelError::Invalid`]; empty otherwise.
    #[must_use]
    pub fn issues(&self) -> &[Issue] {
        match self {
            Self::Invalid { issues, .. } => issues,
            _ => &[],
        }
    }
}

/// Reads a model file as UTF-8 text, telling an encoding problem (UTF-16, binary) apart from a
/// file that cannot be read.
pub(crate) fn read_text(path: &std::path::Path) -> Result<String, ModelError> {
    let bytes = std::fs::read(path).map_err(|source| ModelError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let utf16 = bytes.starts_with(&[0xFF, 0xFE])
            || bytes.starts_with(&[0xFE, 0xFF])
            // ASCII text in UTF-16 without a byte-order mark: every other byte is zero.
            || (bytes.len() >= 4 && (bytes[1] == 0 && bytes[3] == 0 || bytes[0] == 0 && bytes[2] == 0));
        let at = e.utf8_error().valid_up_to();
        let reason = if utf16 {
            format!(
                "UTF-16 text, but model files must be UTF-8: convert it, e.g. `iconv -f UTF-16 -t UTF-8 {} > converted{}`",
                path.display(),
                path.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default()
            )
        } else {
            format!("not UTF-8 text (invalid byte at offset {at}), but model files must be UTF-8")
        };
        ModelError::Encoding {
            path: path.to_path_buf(),
            reason,
        }
    })
}
