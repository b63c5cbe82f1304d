//! The immutable [`Model`]: links, joints and frames in depth-first order, plus the moving-body
//! tree the algorithms sweep over.

use crate::frame::Frame;
use crate::joint::{Joint, JointKind};
use crate::link::Link;
use core::fmt;
use glam::DVec3;
use kinetree_spatial::{Inertia, Se3};
use std::collections::HashMap;

/// How the model's root link is attached to the world.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RootJoint {
    /// Welded to the world at the identity (yapCAD's GLOBAL_DATUM).
    #[default]
    Fixed,
    /// Attached by a 6-DoF floating joint named `root_joint` (q = [x, y, z, qx, qy, qz, qw],
    /// v = [linear; angular] in the root link's frame).
    Floating,
}

/// Name of the floating joint added by [`RootJoint::Floating`].
pub const ROOT_JOINT_NAME: &str = "root_joint";

/// A rigid group of links moved by one joint: the unit the algorithms sweep over.
///
/// Fixed joints do not create bodies: a link attached by a chain of fixed joints belongs to the
/// body of its nearest moving ancestor joint. Body 0 is the world (with the links welded to it);
/// every other body `i` has exactly one moving joint and `parent < i`.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// The moving joint that drives this body (`None` for body 0, the world).
    pub joint: Option<usize>,
    /// Parent body (0 for bodies attached to the world; body 0 is its own parent).
    pub parent: usize,
    /// Pose of the joint frame in the parent body's frame at zero configuration (fixed-joint chains
    /// between the two moving joints are folded in).
    pub placement: Se3,
    /// Joint kind.
    pub kind: JointKind,
    /// Unit joint axis in the body frame.
    pub axis: DVec3,
    /// Start of the joint's block in `q`.
    pub idx_q: usize,
    /// Start of the joint's block in `v`.
    pub idx_v: usize,
    /// Size of the joint's block in `q`.
    pub nq: usize,
    /// Size of the joint's block in `v`.
    pub nv: usize,
    /// Inertia of every link rigidly attached to this body, in the body frame.
    pub inertia: Inertia,
    /// One past the last body of this body's subtree (bodies `i..subtree_end` are the subtree).
    pub subtree_end: usize,
    /// Set when the joint is a coupled mimic joint ([`MimicMode::Coupled`]): it owns no
    /// coordinates (`nq = nv = 0`), and `idx_q`/`idx_v` point at its leader's block.
    pub mimic: Option<BodyMimic>,
}

/// How a coupled mimic body follows its leader: `q = multiplier · q_leader + offset`,
/// `v = multiplier · v_leader`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyMimic {
    /// The leading joint (index into [`Model::joints`]).
    pub leader: usize,
    /// Multiplier.
    pub multiplier: f64,
    /// Offset (rad or m).
    pub offset: f64,
}

impl Body {
    /// The joint coordinate of a 1-DoF body for configuration `q`: its own entry, or for a
    /// coupled mimic body `multiplier · q[idx_q] + offset`.
    #[inline]
    #[must_use]
    pub fn coordinate(&self, q: &[f64]) -> f64 {
        match &self.mimic {
            Some(m) => m.multiplier * q[self.idx_q] + m.offset,
            None => q[self.idx_q],
        }
    }
}

/// What a URDF `<mimic>` tag does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MimicMode {
    /// Every mimic joint is its own degree of freedom; the tag is kept for information
    /// (Pinocchio's default, and the reference data's convention).
    #[default]
    Independent,
    /// A mimic joint follows its leader, `q = multiplier · q_leader + offset`, and has no
    /// coordinate of its own; Jacobians account for the coupling.
    Coupled,
}

/// An articulated rigid-body model: links, joints and named frames, validated and immutable.
///
/// Build one with [`ModelBuilder`](crate::ModelBuilder), [`Model::from_urdf_file`],
/// [`Model::from_json_str`](crate::Model::from_json_str) or [`crate::dh`]. Links and joints are
/// stored depth-first from the root link (a joint comes right before its child link's subtree;
/// children in declaration order), so parents always precede children.
///
/// A model may be empty (a URDF `<robot>` without links): then it has no link, no joint,
/// `nq = nv = 0`, a single (world) body and [`Model::root_link`] returns `None`.
///
/// Methods that take a link, joint, frame or body index panic when the index is out of range, as
/// slice indexing does; indices come from this model's own lookups (`link_index`, …).
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub(crate) name: String,
    pub(crate) links: Vec<Link>,
    pub(crate) joints: Vec<Joint>,
    pub(crate) frames: Vec<Frame>,
    pub(crate) link_names: HashMap<String, usize>,
    pub(crate) joint_names: HashMap<String, usize>,
    pub(crate) frame_names: HashMap<String, usize>,
    pub(crate) root_joint: RootJoint,
    pub(crate) link_parent_joint: Vec<Option<usize>>,
    pub(crate) link_child_joints: Vec<Vec<usize>>,
    pub(crate) bodies: Vec<Body>,
    pub(crate) link_body: Vec<usize>,
    pub(crate) body_from_link: Vec<Se3>,
    pub(crate) joint_body: Vec<Option<usize>>,
    pub(crate) nq: usize,
    pub(crate) nv: usize,
    pub(crate) quaternion_blocks: Vec<(usize, usize)>,
    pub(crate) gravity: DVec3,
    pub(crate) ignored: Vec<String>,
    pub(crate) warnings: Vec<crate::error::Issue>,
    pub(crate) user: crate::user_joints::UserJoints,
}

impl Model {
    /// The model's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Size of the configuration vector `q`.
    #[inline]
    #[must_use]
    pub fn nq(&self) -> usize {
        self.nq
    }

    /// The unit quaternions of the configuration: `(body, start)` for every spherical or floating
    /// joint, its quaternion being `q[start..start + 4]` (x, y, z, w), in body order. What the
    /// configuration checks walk instead of every body.
    #[inline]
    #[must_use]
    pub fn quaternion_blocks(&self) -> &[(usize, usize)] {
        &self.quaternion_blocks
    }

    /// Size of the velocity vectors `v`, `a`, `tau`.
    #[inline]
    #[must_use]
    pub fn nv(&self) -> usize {
        self.nv
    }

    /// Gravity acceleration in the world frame (default `[0, 0, -9.81]` m/s²).
    #[inline]
    #[must_use]
    pub fn gravity(&self) -> DVec3 {
        self.gravity
    }

    /// How the root link is attached to the world.
    #[must_use]
    pub fn root_joint(&self) -> RootJoint {
        self.root_joint
    }

    /// All links, depth-first from the root (index 0).
    #[inline]
    #[must_use]
    pub fn links(&self) -> &[Link] {
        &self.links
    }

    /// All joints (fixed ones included), depth-first; with a floating root, `root_joint` is first.
    #[inline]
    #[must_use]
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// All named frames.
    #[inline]
    #[must_use]
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// The link at `index`.
    ///
    /// # Panics
    /// When `index >= links().len()`.
    #[must_use]
    pub fn link(&self, index: usize) -> &Link {
        &self.links[index]
    }

    /// The joint at `index`.
    ///
    /// # Panics
    /// When `index >= joints().len()`.
    #[must_use]
    pub fn joint(&self, index: usize) -> &Joint {
        &self.joints[index]
    }

    /// Index of the link named `name`.
    #[must_use]
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.link_names.get(name).copied()
    }

    /// Index of the joint named `name`.
    #[must_use]
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joint_names.get(name).copied()
    }

    /// Index of the named frame `name`: `part/frame` (the frame `frame` of link `part`), or a
    /// bare frame name when exactly one link has a frame of that name (frame names are unique per
    /// link, not per model). The implicit `part/ORIGIN` frame is the link itself, not an entry of
    /// [`Model::frames`]: look it up with [`Model::link_index`] (the kinematics layer's
    /// `FrameId::find` resolves both).
    #[must_use]
    pub fn frame_index(&self, name: &str) -> Option<usize> {
        self.frame_names.get(name).copied()
    }

    /// The first root link's index: `Some(0)`, or `None` for the empty model (a file without
    /// links). See [`Model::root_links`] for models with several roots.
    #[must_use]
    pub fn root_link(&self) -> Option<usize> {
        (!self.links.is_empty()).then_some(0)
    }

    /// Every root link (a link without a parent link), in storage order: the parentless root,
    /// then the parts attached to the world datum by their own joints.
    #[must_use]
    pub fn root_links(&self) -> Vec<usize> {
        (0..self.links.len())
            .filter(|&l| self.parent_link(l).is_none())
            .collect()
    }

    /// Whether joint `joint` is the floating joint added by [`RootJoint::Floating`].
    #[must_use]
    pub fn is_floating_root_joint(&self, joint: usize) -> bool {
        joint == 0 && self.root_joint == RootJoint::Floating
    }

    /// The joint whose child is `link` (`None` for the root link with a fixed root).
    #[must_use]
    pub fn parent_joint(&self, link: usize) -> Option<usize> {
        self.link_parent_joint[link]
    }

    /// The parent link of `link` (`None` for the root link).
    #[must_use]
    pub fn parent_link(&self, link: usize) -> Option<usize> {
        self.link_parent_joint[link].and_then(|j| self.joints[j].parent_link)
    }

    /// The joints whose parent is `link`, in declaration order.
    #[must_use]
    pub fn child_joints(&self, link: usize) -> &[usize] {
        &self.link_child_joints[link]
    }

    /// The links directly attached below `link`.
    pub fn children(&self, link: usize) -> impl Iterator<Item = usize> + '_ {
        self.link_child_joints[link]
            .iter()
            .map(|&j| self.joints[j].child_link)
    }

    /// Every link below `link` (not including it), depth-first.
    #[must_use]
    pub fn descendants(&self, link: usize) -> Vec<usize> {
        // Links are stored depth-first, so the subtree is a contiguous range.
        let mut end = link + 1;
        while end < self.links.len() && self.is_ancestor(link, end) {
            end += 1;
        }
        (link + 1..end).collect()
    }

    /// Whether `ancestor` is `link` or one of its ancestors.
    #[must_use]
    pub fn is_ancestor(&self, ancestor: usize, link: usize) -> bool {
        let mut l = Some(link);
        while let Some(i) = l {
            if i == ancestor {
                return true;
            }
            if i < ancestor {
                return false;
            }
            l = self.parent_link(i);
        }
        false
    }

    /// The links from `link` up to the root, both included.
    #[must_use]
    pub fn path_to_root(&self, link: usize) -> Vec<usize> {
        let mut path = vec![link];
        let mut l = link;
        while let Some(p) = self.parent_link(l) {
            path.push(p);
            l = p;
        }
        path
    }

    /// The deepest link that is an ancestor of (or equal to) both `a` and `b`, or `None` when
    /// they hang from different roots (only the world datum is common to them).
    #[must_use]
    pub fn common_ancestor(&self, a: usize, b: usize) -> Option<usize> {
        let (mut a, mut b) = (a, b);
        // Parents have smaller indices: walk the larger index up until they meet.
        while a != b {
            if a > b {
                a = self.parent_link(a)?;
            } else {
                b = self.parent_link(b)?;
            }
        }
        Some(a)
    }

    /// The moving-body tree: body 0 is the world, each other body is driven by one moving joint.
    #[inline]
    #[must_use]
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Number of bodies, the world included.
    #[inline]
    #[must_use]
    pub fn nbodies(&self) -> usize {
        self.bodies.len()
    }

    /// The body that carries `link` and the link's pose in that body's frame.
    #[inline]
    #[must_use]
    pub fn link_body(&self, link: usize) -> (usize, &Se3) {
        (self.link_body[link], &self.body_from_link[link])
    }

    /// The body a frame is attached to and the frame's pose in that body's frame.
    #[must_use]
    pub fn frame_body(&self, frame: usize) -> (usize, Se3) {
        let f = &self.frames[frame];
        (
            self.link_body[f.link],
            self.body_from_link[f.link] * f.placement,
        )
    }

    /// The body driven by joint `joint` (`None` for fixed joints).
    #[must_use]
    pub fn joint_body(&self, joint: usize) -> Option<usize> {
        self.joint_body[joint]
    }

    /// Whether some joint follows a leader ([`MimicMode::Coupled`]).
    #[must_use]
    pub fn has_coupled_mimics(&self) -> bool {
        self.bodies.iter().any(|b| b.mimic.is_some())
    }

    /// Start of joint `joint`'s block in `q` and its size (0 for fixed joints and coupled mimic
    /// joints, which own no coordinates).
    #[must_use]
    pub fn joint_q_range(&self, joint: usize) -> core::ops::Range<usize> {
        self.joint_body[joint].map_or(0..0, |b| {
            let b = &self.bodies[b];
            b.idx_q..b.idx_q + b.nq
        })
    }

    /// Start of joint `joint`'s block in `v` and its size (0 for fixed joints and coupled mimic
    /// joints).
    #[must_use]
    pub fn joint_v_range(&self, joint: usize) -> core::ops::Range<usize> {
        self.joint_body[joint].map_or(0..0, |b| {
            let b = &self.bodies[b];
            b.idx_v..b.idx_v + b.nv
        })
    }

    /// The moving joints that own coordinates, in body order (the order of their blocks in `q`
    /// and `v`). Coupled mimic joints are not included.
    pub fn moving_joints(&self) -> impl Iterator<Item = usize> + '_ {
        self.bodies
            .iter()
            .filter(|b| b.mimic.is_none())
            .filter_map(|b| b.joint)
    }

    /// Total mass of all links (kg), the links welded to the world included.
    #[must_use]
    pub fn total_mass(&self) -> f64 {
        self.links
            .iter()
            .map(|l| l.inertial.map_or(0.0, |i| i.mass))
            .sum()
    }

    /// Problems that did not prevent loading: physically invalid inertias under
    /// [`InertiaCheck::Warn`](crate::InertiaCheck), and URDF `<mimic>` tags naming a joint that
    /// does not exist ([`Issue::UnknownMimicTarget`](crate::Issue::UnknownMimicTarget); the tag is
    /// dropped and the joint stays an independent degree of freedom).
    #[must_use]
    pub fn warnings(&self) -> &[crate::error::Issue] {
        &self.warnings
    }

    /// Elements of the source file that kinetree does not model (transmissions, gazebo tags, …),
    /// one human-readable entry each.
    #[must_use]
    pub fn ignored(&self) -> &[String] {
        &self.ignored
    }
}

impl fmt::Display for Model {
    /// Prints the tree, one link per line, indented by depth, with the joint that attaches it.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} (nq = {}, nv = {})", self.name, self.nq, self.nv)?;
        let mut depth = vec![0usize; self.links.len()];
        for (i, link) in self.links.iter().enumerate() {
            // A composite joint's virtual links are not printed: its child hangs from its parent.
            let virtual_link = self.is_virtual_link(i);
            let d = self
                .parent_link(i)
                .map_or(0, |p| depth[p] + usize::from(!self.is_virtual_link(p)));
            depth[i] = d;
            if virtual_link {
                continue;
            }
            // Indented by depth up to MAX_INDENT levels, deeper links tagged with their depth
            // (a 100 000-link chain would otherwise print 10¹⁰ spaces).
            const MAX_INDENT: usize = 32;
            let mut indent = "  ".repeat(d.min(MAX_INDENT) + 1);
            if d > MAX_INDENT {
                indent.push_str(&format!("[depth {d}] "));
            }
            match self.link_parent_joint[i] {
                Some(j) if self.composite_of_joint(j).is_some() => {
                    let u = &self.user_joints()[self.user_joint_of(j)];
                    let vars = crate::composite::describe(
                        &self.composites()[u.composite.unwrap_or(0)].spec,
                    );
                    writeln!(f, "{indent}{} <- {} (composite: {vars})", link.name, u.name)?;
                }
                Some(j) => {
                    let joint = &self.joints[j];
                    writeln!(
                        f,
                        "{indent}{} <- {} ({})",
                        link.name, joint.name, joint.kind
                    )?;
                }
                None => writeln!(f, "{indent}{}", link.name)?,
            }
        }
        Ok(())
    }
}
