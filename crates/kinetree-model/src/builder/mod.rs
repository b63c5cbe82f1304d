//! [`ModelBuilder`]: the one place where a [`Model`]'s invariants are established.

use crate::checks::{check_link, check_placement, frame_index_map, unique_names};
use crate::error::{Issue, ItemKind, ModelError};
use crate::frame::Frame;
use crate::joint::{Joint, JointDynamics, JointKind, JointLimits};
use crate::link::Link;
use crate::model::{Body, BodyMimic, MimicMode, Model, ROOT_JOINT_NAME, RootJoint};
use crate::topology::{self, ParentRef};
use glam::DVec3;
use kinetree_spatial::{Inertia, Se3};
use std::collections::HashMap;

mod spec;

pub use spec::{FrameSpec, JointSpec};

/// The parent names that attach a part to the world datum instead of to a link (yapCAD's
/// `GLOBAL_DATUM`), unless a link has that name. Accepted by [`ModelBuilder`] and the JSON
/// loaders, not by the URDF loader (a URDF has one root link).
pub const WORLD_NAMES: [&str; 2] = ["world", "GLOBAL_DATUM"];

/// The implicit frame every part has: the part's own frame (yapCAD's `ORIGIN`). A joint's
/// `parent_frame` may name it, and `part/ORIGIN` addresses the part's frame wherever frames are
/// looked up by name; an explicit frame of that name on the part takes precedence.
pub const ORIGIN_FRAME: &str = "ORIGIN";

/// What [`ModelBuilder::check`] found.
struct Checked {
    issues: Vec<Issue>,
    warnings: Vec<Issue>,
    link_order: Vec<usize>,
    joint_order: Vec<usize>,
    link_names: HashMap<String, usize>,
    frame_names: HashMap<String, usize>,
}

/// Relative tolerance of the physical-validity check on link inertias (relative to the largest
/// principal moment).
pub const INERTIA_TOLERANCE: f64 = 1e-6;

/// What to do with a rotational inertia that is not physically valid (not positive
/// semi-definite, or principal moments violating the triangle inequality).
///
/// Negative masses and non-finite values are always errors. Real robot descriptions often carry
/// slightly impossible tensors (rounded CAD exports, placeholder values on tiny links), which
/// Pinocchio accepts; the default therefore keeps them and reports them in [`Model::warnings`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InertiaCheck {
    /// Keep the model and list each defect in [`Model::warnings`].
    #[default]
    Warn,
    /// Reject the model with [`Issue::InvalidInertia`] or [`Issue::MasslessInertia`].
    Strict,
}

/// Collects links, joints and frames, then validates everything at once in [`ModelBuilder::build`].
///
/// # Examples
/// ```
/// use kinetree_model::{JointKind, JointLimits, JointSpec, Link, ModelBuilder, FrameSpec};
/// use kinetree_spatial::{Se3, Symmetric3};
/// use glam::DVec3;
/// # fn main() -> Result<(), kinetree_model::ModelError> {
/// let mut b = ModelBuilder::new("arm");
/// b.add_link(Link::new("base"));
/// b.add_link(Link::new("upper").with_mass(1.0, DVec3::new(0.5, 0.0, 0.0), Symmetric3::from_diagonal(DVec3::splat(0.01))));
/// b.add_joint(
///     JointSpec::new("shoulder", JointKind::Revolute, "base", "upper")
///         .with_axis(DVec3::Z)
///         .with_limits(JointLimits::position(-1.5, 1.5)),
/// );
/// b.add_frame(FrameSpec::new("tip", "upper", Se3::from_translation(DVec3::X)));
/// let model = b.build()?;
/// assert_eq!((model.nq(), model.nv()), (1, 1));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default)]
pub struct ModelBuilder {
    name: String,
    links: Vec<Link>,
    joints: Vec<JointSpec>,
    frames: Vec<FrameSpec>,
    root_joint: RootJoint,
    gravity: Option<DVec3>,
    ignored: Vec<String>,
    warnings: Vec<Issue>,
    inertia_check: InertiaCheck,
    mimic_mode: MimicMode,
    world_parents: bool,
    composites: Vec<crate::composite::CompositeJointSpec>,
}

impl ModelBuilder {
    /// An empty builder for a model called `name`.
    #[must_use]
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            world_parents: true,
            ..Self::default()
        }
    }

    /// Adds a link (part).
    pub fn add_link(&mut self, link: Link) -> &mut Self {
        self.links.push(link);
        self
    }

    /// Adds a joint.
    pub fn add_joint(&mut self, joint: JointSpec) -> &mut Self {
        self.joints.push(joint);
        self
    }

    /// Adds a part and the joint attaching it to its parent in one call (yapCAD's `add_part`).
    pub fn add_part(&mut self, link: Link, joint: JointSpec) -> &mut Self {
        self.add_link(link);
        self.add_joint(joint)
    }

    /// Adds a named frame.
    pub fn add_frame(&mut self, frame: FrameSpec) -> &mut Self {
        self.frames.push(frame);
        self
    }

    /// Chooses how the root link is attached to the world (default: fixed).
    pub fn root_joint(&mut self, root: RootJoint) -> &mut Self {
        self.root_joint = root;
        self
    }

    /// Chooses whether a joint may name the world datum ([`WORLD_NAMES`]) as its parent (default
    /// yes). Such joints make several roots possible: each attaches its child part to the world
    /// by its own joint, of any kind. The URDF loader turns this off.
    pub fn world_parents(&mut self, allow: bool) -> &mut Self {
        self.world_parents = allow;
        self
    }

    /// Chooses whether physically invalid inertias are errors or warnings (default: warnings).
    pub fn inertia_check(&mut self, check: InertiaCheck) -> &mut Self {
        self.inertia_check = check;
        self
    }

    /// Chooses whether mimic joints are independent DoFs (default) or follow their leaders.
    pub fn mimic_mode(&mut self, mode: MimicMode) -> &mut Self {
        self.mimic_mode = mode;
        self
    }

    /// Sets gravity in the world frame (default `[0, 0, -9.81]`).
    pub fn gravity(&mut self, gravity: DVec3) -> &mut Self {
        self.gravity = Some(gravity);
        self
    }

    /// Records a source element that the model does not represent (reported by
    /// [`Model::ignored`]).
    pub fn note_ignored(&mut self, what: impl Into<String>) -> &mut Self {
        self.ignored.push(what.into());
        self
    }

    /// Records a composite joint's spec (its pieces are added by `add_composite`).
    pub(crate) fn add_composite_spec(&mut self, spec: crate::composite::CompositeJointSpec) {
        self.composites.push(spec);
    }

    /// Records a problem that a loader repaired instead of rejecting (reported by
    /// [`Model::warnings`]).
    pub(crate) fn note_warning(&mut self, issue: Issue) -> &mut Self {
        self.warnings.push(issue);
        self
    }

    /// Validates and builds the model.
    ///
    /// A builder without any link gives the empty model (no link, no joint, `nq = nv = 0`,
    /// [`Model::root_link`] `None`, root joint [`RootJoint::Fixed`] whatever was asked, since
    /// there is nothing to attach a floating joint to).
    ///
    /// # Errors
    /// [`ModelError::Invalid`] listing every problem found: unknown or duplicate names, several
    /// roots, cycles, zero or non-finite axes, `lower > upper`, NaN/∞ anywhere, physically invalid
    /// inertias, unknown mimic targets and parent frames.
    pub fn build(&self) -> Result<Model, ModelError> {
        let checked = self.check();
        if !checked.issues.is_empty() {
            return Err(self.invalid(checked.issues));
        }
        let mut model = self.assemble(
            &checked.link_order,
            &checked.joint_order,
            &checked.link_names,
            &checked.frame_names,
        );
        model.warnings = self.warnings.clone();
        model.warnings.extend(checked.warnings);
        model.user = crate::user_joints::resolve(&model, &self.composites);
        Ok(model)
    }

    /// Reports every problem [`ModelBuilder::build`] would reject, without building the model
    /// (yapCAD's `validate()`): an empty list means `build` succeeds. Repairs that `build`
    /// only warns about (see [`InertiaCheck::Warn`]) are not listed.
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::{Issue, JointKind, JointSpec, Link, ModelBuilder};
    /// let mut b = ModelBuilder::new("m");
    /// b.add_link(Link::new("base")).add_link(Link::new("arm"));
    /// b.add_joint(JointSpec::new("j", JointKind::Revolute, "bsae", "arm"));
    /// assert!(matches!(&b.validate()[..], [Issue::UnknownParent { link, .. }] if link == "bsae"));
    /// ```
    #[must_use]
    pub fn validate(&self) -> Vec<Issue> {
        self.check().issues
    }

    /// The parent link of joint `j`: `Some(Some(link))`, `Some(None)` for the world datum, `None`
    /// when the name is neither.
    fn parent_of(
        &self,
        j: &JointSpec,
        link_names: &HashMap<String, usize>,
    ) -> Option<Option<usize>> {
        match link_names.get(&j.parent) {
            Some(&l) => Some(Some(l)),
            None if self.world_parents && WORLD_NAMES.contains(&j.parent.as_str()) => Some(None),
            None => None,
        }
    }

    fn check(&self) -> Checked {
        let mut issues = crate::user_joints::check(&self.composites, &self.joints, &self.frames);

        let link_names = unique_names(
            self.links.iter().map(|l| l.name.as_str()),
            ItemKind::Link,
            &mut issues,
        );
        let joint_names = unique_names(
            self.joints.iter().map(|j| j.name.as_str()),
            ItemKind::Joint,
            &mut issues,
        );
        // Frame names are unique per link; `link/frame` is unique in the model.
        let frame_names = unique_names(
            self.frames.iter().map(|f| format!("{}/{}", f.link, f.name)),
            ItemKind::Frame,
            &mut issues,
        );
        if self.root_joint == RootJoint::Floating && joint_names.contains_key(ROOT_JOINT_NAME) {
            issues.push(Issue::InvalidRootJoint {
                joint: ROOT_JOINT_NAME.into(),
                reason: "the name is reserved for the floating root joint".into(),
            });
        }

        let mut warnings = Vec::new();
        for link in &self.links {
            check_link(link, &mut issues, &mut warnings);
        }
        if self.inertia_check == InertiaCheck::Strict {
            issues.append(&mut warnings);
        }
        for frame in &self.frames {
            if !link_names.contains_key(&frame.link) {
                issues.push(Issue::UnknownFrameLink {
                    frame: frame.name.clone(),
                    link: frame.link.clone(),
                });
            }
            check_placement(&frame.placement, ItemKind::Frame, &frame.name, &mut issues);
        }

        // Joints: references, axes, limits, placements.
        let mut parent_joint: Vec<Vec<usize>> = vec![Vec::new(); self.links.len()];
        for (ji, j) in self.joints.iter().enumerate() {
            let parent = self.parent_of(j, &link_names);
            if parent.is_none() {
                issues.push(Issue::UnknownParent {
                    joint: j.name.clone(),
                    link: j.parent.clone(),
                });
            }
            match link_names.get(&j.child) {
                Some(&c) => parent_joint[c].push(ji),
                None => issues.push(Issue::UnknownChild {
                    joint: j.name.clone(),
                    link: j.child.clone(),
                }),
            }
            if let Some(frame) = &j.parent_frame {
                let known = match parent {
                    Some(Some(_)) => {
                        frame == ORIGIN_FRAME
                            || frame_names.contains_key(&format!("{}/{frame}", j.parent))
                    }
                    Some(None) => frame == ORIGIN_FRAME,
                    None => true, // the unknown parent is reported already
                };
                if !known {
                    issues.push(Issue::UnknownParentFrame {
                        joint: j.name.clone(),
                        frame: frame.clone(),
                        link: j.parent.clone(),
                    });
                }
            }
            check_placement(&j.placement, ItemKind::Joint, &j.name, &mut issues);
            if j.kind.has_axis() && !(j.axis.is_finite() && unit_axis(j.axis).is_some()) {
                issues.push(Issue::InvalidAxis {
                    joint: j.name.clone(),
                    axis: j.axis.to_array(),
                });
            }
            let l = &j.limits;
            if l.lower.is_nan() || l.upper.is_nan() {
                issues.push(Issue::NonFinite {
                    kind: ItemKind::Joint,
                    name: j.name.clone(),
                    what: "position limit",
                });
            } else if l.lower > l.upper {
                issues.push(Issue::InvalidLimits {
                    joint: j.name.clone(),
                    lower: l.lower,
                    upper: l.upper,
                });
            }
            if l.velocity.is_nan() || l.effort.is_nan() {
                issues.push(Issue::NonFinite {
                    kind: ItemKind::Joint,
                    name: j.name.clone(),
                    what: "velocity or effort limit",
                });
            }
            let d = &j.dynamics;
            if !(d.damping.is_finite() && d.friction.is_finite() && d.armature.is_finite()) {
                issues.push(Issue::NonFinite {
                    kind: ItemKind::Joint,
                    name: j.name.clone(),
                    what: "damping, friction or armature",
                });
            }
            for (what, value) in [
                ("damping", d.damping),
                ("friction", d.friction),
                ("armature", d.armature),
            ] {
                if value < 0.0 {
                    issues.push(Issue::InvalidJointDynamics {
                        joint: j.name.clone(),
                        what,
                        value,
                    });
                }
            }
            if let Some(m) = &j.mimic {
                match joint_names.get(&m.joint) {
                    None => issues.push(Issue::UnknownMimicTarget {
                        joint: j.name.clone(),
                        target: m.joint.clone(),
                    }),
                    Some(&leader) if leader == ji => issues.push(Issue::InvalidMimic {
                        joint: j.name.clone(),
                        reason: "a joint cannot mimic itself".into(),
                    }),
                    Some(&leader) if self.joints[leader].kind.nv() != 1 || j.kind.nv() != 1 => {
                        issues.push(Issue::InvalidMimic {
                            joint: j.name.clone(),
                            reason: format!(
                                "mimic couples 1-DoF joints; '{}' is {} and '{}' is {}",
                                j.name, j.kind, m.joint, self.joints[leader].kind
                            ),
                        });
                    }
                    Some(_) => {}
                }
                // A mimic cycle (a follows c, c follows a) has no leader: in any mode it is an
                // error, reported once, at the cycle's first joint.
                let mut cycle = vec![ji];
                let mut next = joint_names.get(&m.joint).copied();
                while let Some(k) = next {
                    if k == ji || cycle.len() > self.joints.len() {
                        break;
                    }
                    cycle.push(k);
                    next = self.joints[k]
                        .mimic
                        .as_ref()
                        .and_then(|m| joint_names.get(&m.joint).copied());
                }
                if next == Some(ji) && cycle.len() > 1 && cycle.iter().all(|&k| k >= ji) {
                    let names: Vec<&str> = cycle
                        .iter()
                        .chain([&ji])
                        .map(|&k| self.joints[k].name.as_str())
                        .collect();
                    issues.push(Issue::InvalidMimic {
                        joint: j.name.clone(),
                        reason: format!("mimic cycle {}: no joint leads", names.join(" -> ")),
                    });
                }
                if self.mimic_mode == MimicMode::Coupled
                    && joint_names
                        .get(&m.joint)
                        .is_some_and(|&l| self.joints[l].mimic.is_some())
                {
                    issues.push(Issue::InvalidMimic {
                        joint: j.name.clone(),
                        reason: format!("its leader '{}' is itself a mimic joint", m.joint),
                    });
                }
                if !(m.multiplier.is_finite() && m.offset.is_finite()) {
                    issues.push(Issue::NonFinite {
                        kind: ItemKind::Joint,
                        name: j.name.clone(),
                        what: "mimic multiplier or offset",
                    });
                }
            }
        }

        // Topology: one parent per link, at most one parentless root, no cycle.
        let mut several_parents = false;
        for (li, joints) in parent_joint.iter().enumerate() {
            if joints.len() > 1 {
                several_parents = true;
                issues.push(Issue::MultipleParents {
                    link: self.links[li].name.clone(),
                    joints: joints
                        .iter()
                        .map(|&j| self.joints[j].name.clone())
                        .collect(),
                });
            }
        }
        let parent_ref = |j: usize| match self.parent_of(&self.joints[j], &link_names) {
            Some(Some(link)) => ParentRef::Link { joint: j, link },
            Some(None) => ParentRef::World { joint: j },
            None => ParentRef::Unknown { joint: j },
        };
        let parents: Vec<ParentRef> = parent_joint
            .iter()
            .map(|js| js.first().map_or(ParentRef::None, |&j| parent_ref(j)))
            .collect();
        // Child joints per link in declaration order (only joints whose ends both exist).
        let mut child_joints: Vec<Vec<usize>> = vec![Vec::new(); self.links.len()];
        let mut world_joints = Vec::new();
        let child_of: Vec<Option<usize>> = self
            .joints
            .iter()
            .map(|j| link_names.get(&j.child).copied())
            .collect();
        for (ji, j) in self.joints.iter().enumerate() {
            if child_of[ji].is_none() {
                continue;
            }
            match self.parent_of(j, &link_names) {
                Some(Some(p)) => child_joints[p].push(ji),
                Some(None) => world_joints.push(ji),
                None => {}
            }
        }
        let names: Vec<&str> = self.links.iter().map(|l| l.name.as_str()).collect();
        let order = topology::order(
            &names,
            &parents,
            &child_joints,
            &world_joints,
            &child_of,
            several_parents,
            &mut issues,
        );
        let (link_order, joint_order) = (order.links, order.joints);

        Checked {
            issues,
            warnings,
            link_order,
            joint_order,
            link_names,
            frame_names,
        }
    }

    fn invalid(&self, issues: Vec<Issue>) -> ModelError {
        ModelError::Invalid {
            model: self.name.clone(),
            issues,
        }
    }

    /// Builds the model from validated input in depth-first order.
    fn assemble(
        &self,
        link_order: &[usize],
        joint_order: &[usize],
        link_names_in: &HashMap<String, usize>,
        frame_names_in: &HashMap<String, usize>,
    ) -> Model {
        // A floating joint attaches the parentless root, when there is one (every other link
        // comes with its joint, so the parentless root is the one link more than joints).
        let floating =
            self.root_joint == RootJoint::Floating && joint_order.len() < link_order.len();
        // New link index of each input link.
        let mut new_link = vec![0usize; self.links.len()];
        for (new, &old) in link_order.iter().enumerate() {
            new_link[old] = new;
        }
        let links: Vec<Link> = link_order.iter().map(|&l| self.links[l].clone()).collect();
        let mut joints = Vec::with_capacity(joint_order.len() + usize::from(floating));
        if floating {
            joints.push(Joint {
                name: ROOT_JOINT_NAME.into(),
                kind: JointKind::Floating,
                parent_link: None,
                child_link: 0,
                placement: Se3::IDENTITY,
                axis: DVec3::X,
                limits: JointLimits::UNLIMITED,
                dynamics: JointDynamics::default(),
                mimic: None,
                parent_frame: None,
            });
        }
        for &ji in joint_order {
            let s = &self.joints[ji];
            let mut placement = s.placement;
            let parent_frame = s.parent_frame.as_ref().and_then(|frame| {
                frame_names_in
                    .get(&format!("{}/{frame}", s.parent))
                    .copied()
            });
            if let Some(f) = parent_frame {
                placement = self.frames[f].placement * placement;
            }
            let axis = if s.kind.has_axis() {
                unit_axis(s.axis).unwrap_or(s.axis)
            } else {
                s.axis
            };
            let mut limits = s.limits;
            if s.kind == JointKind::Continuous {
                limits.lower = f64::NEG_INFINITY;
                limits.upper = f64::INFINITY;
            }
            joints.push(Joint {
                name: s.name.clone(),
                kind: s.kind,
                parent_link: link_names_in.get(&s.parent).map(|&p| new_link[p]),
                parent_frame: s.parent_frame.clone(),
                child_link: new_link[link_names_in[&s.child]],
                placement,
                axis,
                limits,
                dynamics: s.dynamics,
                mimic: s.mimic.clone(),
            });
        }
        let frames: Vec<Frame> = self
            .frames
            .iter()
            .map(|f| Frame {
                name: f.name.clone(),
                link: new_link[link_names_in[&f.link]],
                placement: f.placement,
                description: f.description.clone(),
                datum: f.datum.clone(),
            })
            .collect();

        let nl = links.len();
        let mut link_parent_joint = vec![None; nl];
        let mut link_child_joints = vec![Vec::new(); nl];
        for (ji, j) in joints.iter().enumerate() {
            link_parent_joint[j.child_link] = Some(ji);
            if let Some(p) = j.parent_link {
                link_child_joints[p].push(ji);
            }
        }

        // Bodies: body 0 is the world; each moving joint starts a body. Joints are depth-first,
        // so a joint's parent link (and thus its parent body) is already placed.
        let mut bodies = vec![Body {
            joint: None,
            parent: 0,
            placement: Se3::IDENTITY,
            kind: JointKind::Fixed,
            axis: DVec3::X,
            idx_q: 0,
            idx_v: 0,
            nq: 0,
            nv: 0,
            inertia: Inertia::ZERO,
            subtree_end: 1,
            mimic: None,
        }];
        let mut link_body = vec![0usize; nl];
        let mut body_from_link = vec![Se3::IDENTITY; nl];
        let mut joint_body = vec![None; joints.len()];
        let (mut nq, mut nv) = (0, 0);
        for (ji, j) in joints.iter().enumerate() {
            let (pb, pb_from_parent) = match j.parent_link {
                Some(p) => (link_body[p], body_from_link[p]),
                None => (0, Se3::IDENTITY),
            };
            let c = j.child_link;
            if j.kind.is_moving() {
                let b = bodies.len();
                let coupled = self.mimic_mode == MimicMode::Coupled && j.mimic.is_some();
                let (own_nq, own_nv) = if coupled {
                    (0, 0)
                } else {
                    (j.kind.nq(), j.kind.nv())
                };
                bodies.push(Body {
                    joint: Some(ji),
                    parent: pb,
                    placement: pb_from_parent * j.placement,
                    kind: j.kind,
                    axis: j.axis,
                    idx_q: nq,
                    idx_v: nv,
                    nq: own_nq,
                    nv: own_nv,
                    inertia: Inertia::ZERO,
                    subtree_end: b + 1,
                    mimic: None,
                });
                nq += own_nq;
                nv += own_nv;
                joint_body[ji] = Some(b);
                link_body[c] = b;
                body_from_link[c] = Se3::IDENTITY;
            } else {
                link_body[c] = pb;
                body_from_link[c] = pb_from_parent * j.placement;
            }
        }
        // Coupled mimic bodies read their leader's block (leaders may come later in the tree).
        if self.mimic_mode == MimicMode::Coupled {
            for b in 1..bodies.len() {
                let Some(ji) = bodies[b].joint else { continue };
                let Some(m) = &joints[ji].mimic else { continue };
                let leader = joints.iter().position(|x| x.name == m.joint).unwrap_or(ji);
                let lb = joint_body[leader].unwrap_or(b);
                bodies[b].idx_q = bodies[lb].idx_q;
                bodies[b].idx_v = bodies[lb].idx_v;
                bodies[b].mimic = Some(BodyMimic {
                    leader,
                    multiplier: m.multiplier,
                    offset: m.offset,
                });
            }
        }
        for (l, link) in links.iter().enumerate() {
            let b = link_body[l];
            bodies[b].inertia += link.inertia().transformed(&body_from_link[l]);
        }
        for b in (1..bodies.len()).rev() {
            let (end, p) = (bodies[b].subtree_end, bodies[b].parent);
            bodies[p].subtree_end = bodies[p].subtree_end.max(end);
        }

        let quaternion_blocks = bodies
            .iter()
            .enumerate()
            .filter_map(|(b, body)| match body.kind {
                JointKind::Spherical => Some((b, body.idx_q)),
                JointKind::Floating => Some((b, body.idx_q + 3)),
                _ => None,
            })
            .collect();
        let index = |names: &mut dyn Iterator<Item = &String>| -> HashMap<String, usize> {
            names.enumerate().map(|(i, n)| (n.clone(), i)).collect()
        };
        Model {
            name: self.name.clone(),
            link_names: index(&mut links.iter().map(|l| &l.name)),
            joint_names: index(&mut joints.iter().map(|j| &j.name)),
            frame_names: frame_index_map(&links, &frames),
            links,
            joints,
            frames,
            root_joint: if floating {
                RootJoint::Floating
            } else {
                RootJoint::Fixed
            },
            link_parent_joint,
            link_child_joints,
            bodies,
            link_body,
            body_from_link,
            joint_body,
            nq,
            nv,
            quaternion_blocks,
            gravity: self.gravity.unwrap_or(DVec3::new(0.0, 0.0, -9.81)),
            ignored: self.ignored.clone(),
            warnings: Vec::new(),
            user: crate::user_joints::UserJoints::default(),
        }
    }
}

/// The unit vector along `axis`, scaled by its largest component first so that huge components
/// (1e308) do not overflow the norm; `None` for a zero (or vanishingly small, |a| ≤ 1e-12) or
/// non-finite axis.
fn unit_axis(axis: DVec3) -> Option<DVec3> {
    let m = axis.abs().max_element();
    if !(m.is_finite() && m > 1e-12) {
        return None;
    }
    let a = axis / m;
    Some(a / a.length())
}
