//! [`Chain`]: a model, its kinematics data and the current configuration in one value, queried by
//! name, with world placements cached per body and recomputed only below a changed joint.

use crate::configuration::{neutral_configuration, set_joint_q};
use crate::data::{FrameId, KinematicsData};
use crate::error::{KinematicsError, check_q};
use kinetree_model::spatial::Se3;
use kinetree_model::{JointKind, JsonOptions, Model};

/// Degrees per radian.
const DEG_PER_RAD: f64 = 180.0 / core::f64::consts::PI;
/// Millimetres per metre.
const MM_PER_M: f64 = 1000.0;

/// Counters of the work a [`Chain`] has done to keep its world placements current.
///
/// They only grow; compare two snapshots to see what a query cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChainStats {
    /// World placements of bodies recomputed (each also recomputes the world placements of the
    /// body's links and named frames).
    pub body_updates: u64,
    /// Joint transforms (`parent_from_body`) recomputed because the joint's value changed.
    pub joint_updates: u64,
}

/// A [`Model`] with its [`KinematicsData`] and current configuration, queried by part, frame and
/// joint name: yapCAD's kinematic chain.
///
/// Setting a joint marks the bodies below it stale; asking for a pose recomputes only the stale
/// bodies it depends on ([`Chain::stats`] counts them). The poses always equal those of a full
/// [`forward_kinematics`](crate::forward_kinematics) at [`Chain::q`].
///
/// **Cache invariant:** a body is *stale* when its world placement (and those of its links and
/// frames) may differ from what the current configuration gives. The stale bodies always form a
/// union of subtrees: changing a joint marks its body's whole subtree (a contiguous range of
/// bodies, `i..Body::subtree_end`), and refreshing a body first refreshes its stale ancestors, top
/// down. So a body that is not stale has no stale ancestor, and a query recomputes only the stale
/// bodies between the queried one and its nearest up-to-date ancestor.
///
/// Values are SI (rad, m); [`Chain::set_joint_value_deg`] and [`Chain::set_joint_value_mm`]
/// convert at the edge. A `Chain` may allocate (name look-ups return vectors); the core functions
/// it sits on do not.
///
/// # Examples
/// ```
/// use kinetree_kinematics::Chain;
/// use kinetree_model::{FrameSpec, JointKind, JointSpec, Link, ModelBuilder};
/// use kinetree_model::spatial::Se3;
/// use glam::DVec3;
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let mut b = ModelBuilder::new("arm");
/// b.add_link(Link::new("base"));
/// b.add_part(Link::new("upper"), JointSpec::new("shoulder", JointKind::Revolute, "base", "upper"));
/// b.add_part(
///     Link::new("carriage"),
///     JointSpec::new("slide", JointKind::Prismatic, "upper", "carriage")
///         .with_axis(DVec3::X)
///         .with_placement(Se3::from_translation(DVec3::new(0.0, 0.0, 0.1))),
/// );
/// b.add_frame(FrameSpec::new("tool", "carriage", Se3::from_translation(DVec3::new(0.05, 0.0, 0.0))));
/// let mut chain = Chain::new(b.build()?);
///
/// chain.set_joint_value_deg("shoulder", 90.0)?;
/// chain.set_joint_value_mm("slide", 250.0)?;
/// assert!((chain.joint_value("slide")? - 0.25).abs() < 1e-15);
///
/// // The tool is 0.25 + 0.05 m along the upper arm's x axis, which now points along world y.
/// let tool = chain.world_from("tool")?;
/// assert!((tool.translation - DVec3::new(0.0, 0.3, 0.1)).length() < 1e-12);
/// let in_upper = chain.relative_transform("upper", "tool")?;
/// assert!((in_upper.translation - DVec3::new(0.3, 0.0, 0.1)).length() < 1e-12);
/// assert_eq!(chain.path_to_root("carriage")?, ["carriage", "upper", "base"]);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Chain {
    model: Model,
    data: KinematicsData,
    q: Vec<f64>,
    /// Per body: its world placement (and its links' and frames') may be out of date.
    stale: Vec<bool>,
    /// Per body: its joint transform `parent_from_body` may be out of date.
    joint_stale: Vec<bool>,
    /// Per body: the links it carries.
    body_links: Vec<Vec<usize>>,
    /// Per body: the named frames it carries.
    body_frames: Vec<Vec<usize>>,
    /// Scratch stack of bodies to refresh, reused across queries.
    path: Vec<usize>,
    stats: ChainStats,
}

impl From<Model> for Chain {
    fn from(model: Model) -> Self {
        Self::new(model)
    }
}

impl Chain {
    /// A chain at the model's neutral configuration
    /// ([`neutral_configuration`](crate::configuration::neutral_configuration)).
    ///
    /// Nothing is computed until the first pose query.
    #[must_use]
    pub fn new(model: Model) -> Self {
        let data = KinematicsData::new(&model);
        let q = neutral_configuration(&model);
        let nb = model.nbodies();
        let mut body_links = vec![Vec::new(); nb];
        for l in 0..model.links().len() {
            body_links[model.link_body(l).0].push(l);
        }
        let mut body_frames = vec![Vec::new(); nb];
        for (f, frame) in model.frames().iter().enumerate() {
            body_frames[model.link_body(frame.link).0].push(f);
        }
        let mut stale = vec![true; nb];
        let mut joint_stale = vec![true; nb];
        if let (Some(s), Some(j)) = (stale.first_mut(), joint_stale.first_mut()) {
            // Body 0 is the world: never stale. Its links and frames are placed below.
            *s = false;
            *j = false;
        }
        let mut chain = Self {
            model,
            data,
            q,
            stale,
            joint_stale,
            body_links,
            body_frames,
            path: Vec::new(),
            stats: ChainStats::default(),
        };
        if nb > 0 {
            chain.place_links_and_frames(0);
        }
        chain
    }

    /// The model.
    #[inline]
    #[must_use]
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Gives the model back.
    #[must_use]
    pub fn into_model(self) -> Model {
        self.model
    }

    /// The current configuration (length `model.nq()`).
    #[inline]
    #[must_use]
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// The cache counters (see [`ChainStats`]).
    #[inline]
    #[must_use]
    pub fn stats(&self) -> ChainStats {
        self.stats
    }

    /// Sets the whole configuration `q` (length `model.nq()`). Only the joints whose block of `q`
    /// changed invalidate their subtree.
    ///
    /// # Errors
    /// [`KinematicsError::DimensionMismatch`] or [`KinematicsError::NonFinite`] for a bad `q`; the
    /// chain is unchanged.
    pub fn set_q(&mut self, q: &[f64]) -> Result<(), KinematicsError> {
        check_q(&self.model, "q", q)?;
        for i in 1..self.model.nbodies() {
            let b = &self.model.bodies()[i];
            let r = b.idx_q..b.idx_q + b.nq;
            if self.q[r.clone()] != q[r.clone()] {
                self.q[r.clone()].copy_from_slice(&q[r]);
                self.invalidate(i);
            }
        }
        Ok(())
    }

    /// The configuration block of the joint named `name` (see
    /// [`JointKind`] for its layout).
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`]; [`KinematicsError::WrongJointKind`] for a fixed joint.
    pub fn joint_q(&self, name: &str) -> Result<&[f64], KinematicsError> {
        let (_, body) = self.moving_joint(name)?;
        let b = &self.model.bodies()[body];
        Ok(&self.q[b.idx_q..b.idx_q + b.nq])
    }

    /// Sets the configuration block of the joint named `name` (continuous joints by angle,
    /// spherical joints as quaternion x, y, z, w, floating joints as [x, y, z, qx, qy, qz, qw]) and
    /// invalidates the subtree below it.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`]; [`KinematicsError::InvalidJointValue`] for a fixed joint,
    /// a wrong number of values or a non-finite value. The chain is unchanged on error.
    pub fn set_joint_q(&mut self, name: &str, values: &[f64]) -> Result<(), KinematicsError> {
        set_joint_q(&self.model, &mut self.q, name, values)?;
        let (_, body) = self.moving_joint(name)?;
        self.invalidate(body);
        Ok(())
    }

    /// The value of the 1-DoF joint named `name`: an angle (rad) for revolute and continuous
    /// joints, a displacement (m) for prismatic ones.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`]; [`KinematicsError::WrongJointKind`] for a joint that is
    /// not revolute, continuous or prismatic.
    pub fn joint_value(&self, name: &str) -> Result<f64, KinematicsError> {
        let (_, idx_q) = self.scalar_joint(name, ONE_DOF, |_| true)?;
        Ok(self.q[idx_q])
    }

    /// Sets the 1-DoF joint named `name` to `value` (rad or m) and invalidates the subtree below
    /// it. Limits are not enforced (see [`Chain::set_joint_value_clamped`]).
    ///
    /// # Errors
    /// As [`Chain::joint_value`], and [`KinematicsError::InvalidJointValue`] for a non-finite
    /// value. The chain is unchanged on error.
    #[doc(alias = "set_joint_value_by_name")]
    pub fn set_joint_value(&mut self, name: &str, value: f64) -> Result<(), KinematicsError> {
        self.set_scalar(name, value, ONE_DOF, |_| true)
    }

    /// As [`Chain::set_joint_value`], with `value` clamped to the joint's position limits first
    /// (continuous joints have none). Returns the value set.
    ///
    /// # Errors
    /// As [`Chain::set_joint_value`].
    pub fn set_joint_value_clamped(
        &mut self,
        name: &str,
        value: f64,
    ) -> Result<f64, KinematicsError> {
        let (joint, _) = self.scalar_joint(name, ONE_DOF, |_| true)?;
        let j = self.model.joint(joint);
        let v = if j.kind.has_position_limits() && value.is_finite() {
            value.clamp(j.limits.lower, j.limits.upper)
        } else {
            value
        };
        self.set_joint_value(name, v)?;
        Ok(v)
    }

    /// The angle of the revolute or continuous joint named `name`, in degrees.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`]; [`KinematicsError::WrongJointKind`] for any other kind.
    pub fn joint_value_deg(&self, name: &str) -> Result<f64, KinematicsError> {
        let (_, idx_q) = self.scalar_joint(name, ANGULAR, is_angular)?;
        Ok(self.q[idx_q] * DEG_PER_RAD)
    }

    /// Sets the revolute or continuous joint named `name` to `degrees`.
    ///
    /// # Errors
    /// As [`Chain::joint_value_deg`], and [`KinematicsError::InvalidJointValue`] for a non-finite
    /// value.
    pub fn set_joint_value_deg(&mut self, name: &str, degrees: f64) -> Result<(), KinematicsError> {
        self.set_scalar(name, degrees / DEG_PER_RAD, ANGULAR, is_angular)
    }

    /// The displacement of the prismatic joint named `name`, in millimetres.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`]; [`KinematicsError::WrongJointKind`] for any other kind.
    pub fn joint_value_mm(&self, name: &str) -> Result<f64, KinematicsError> {
        let (_, idx_q) = self.scalar_joint(name, LINEAR, is_linear)?;
        Ok(self.q[idx_q] * MM_PER_M)
    }

    /// Sets the prismatic joint named `name` to `millimetres`.
    ///
    /// # Errors
    /// As [`Chain::joint_value_mm`], and [`KinematicsError::InvalidJointValue`] for a non-finite
    /// value.
    pub fn set_joint_value_mm(
        &mut self,
        name: &str,
        millimetres: f64,
    ) -> Result<(), KinematicsError> {
        self.set_scalar(name, millimetres / MM_PER_M, LINEAR, is_linear)
    }

    /// The world placement (`world_from_frame`) of the link or named frame called `name` (links
    /// are looked up first).
    ///
    /// Recomputes only the stale bodies between that frame's body and its nearest up-to-date
    /// ancestor.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownFrame`] when no link or frame has this name.
    #[doc(alias = "world_transform")]
    #[doc(alias = "get_world_transform")]
    pub fn world_from(&mut self, name: &str) -> Result<Se3, KinematicsError> {
        let id = FrameId::find(&self.model, name)?;
        self.world_from_id(id)
    }

    /// The world placement of a link or named frame given by id.
    ///
    /// # Errors
    /// [`KinematicsError::FrameOutOfRange`] when the index is out of range for this model.
    pub fn world_from_id(&mut self, frame: FrameId) -> Result<Se3, KinematicsError> {
        let (body, _) = frame.body(&self.model)?;
        self.refresh(body);
        Ok(*self.data.world_from(frame)?)
    }

    /// The pose of `b` in `a` (`a_from_b`), both links or named frames given by name.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownFrame`] naming the first unknown name.
    #[doc(alias = "get_relative_transform")]
    pub fn relative_transform(&mut self, a: &str, b: &str) -> Result<Se3, KinematicsError> {
        let world_from_a = self.world_from(a)?;
        let world_from_b = self.world_from(b)?;
        Ok(world_from_a.inv_mul(&world_from_b))
    }

    /// Brings every world placement up to date, recomputing only the stale bodies.
    pub fn update(&mut self) {
        for i in 1..self.model.nbodies() {
            if self.stale[i] {
                self.recompute(i);
            }
        }
    }

    /// The world placement of every link, indexed like [`Model::links`] (brought up to date
    /// first).
    pub fn world_from_link(&mut self) -> &[Se3] {
        self.update();
        self.data.world_from_link()
    }

    /// The world placement of every named frame, indexed like [`Model::frames`] (brought up to
    /// date first).
    pub fn world_from_frame(&mut self) -> &[Se3] {
        self.update();
        self.data.world_from_frame()
    }

    /// Every link's, then every named frame's, name and world placement (brought up to date
    /// first).
    #[doc(alias = "get_all_world_transforms")]
    pub fn world_from_all(&mut self) -> impl Iterator<Item = (&str, &Se3)> + '_ {
        self.update();
        let links = self
            .model
            .links()
            .iter()
            .map(|l| l.name.as_str())
            .zip(self.data.world_from_link());
        let frames = self
            .model
            .frames()
            .iter()
            .map(|f| f.name.as_str())
            .zip(self.data.world_from_frame());
        links.chain(frames)
    }

    /// The kinematics data, brought up to date: body, link and frame placements as a full
    /// [`forward_kinematics`](crate::forward_kinematics) followed by
    /// [`update_frame_placements`](crate::update_frame_placements) at [`Chain::q`] writes them.
    /// Velocities and Jacobians in it are not maintained by the chain.
    pub fn data(&mut self) -> &KinematicsData {
        self.update();
        self.data.q.copy_from_slice(&self.q);
        &self.data
    }

    /// Writes the model as kinetree JSON (see [`Model::to_json_string`]) with the chain's state:
    /// every link gets its current `world_pose` and every moving joint (except a floating root)
    /// its current `position`. Units and datum handling come from `options`; its `world_poses`
    /// and `positions` are replaced by the chain's.
    ///
    /// # Errors
    /// [`KinematicsError::Model`] when the model cannot be written in the requested units (see
    /// [`Model::to_json_string`]).
    ///
    /// # Examples
    /// ```
    /// use kinetree_kinematics::Chain;
    /// use kinetree_model::{samples, JsonOptions, Units};
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// let mut chain = Chain::new(samples::planar_2r(0.3, 0.2));
    /// let first = chain.model().joint(chain.model().moving_joints().next().unwrap()).name.clone();
    /// chain.set_joint_value_deg(&first, 90.0)?;
    /// let json = chain.to_json_string(&JsonOptions { units: Units::MM_DEG, ..JsonOptions::default() })?;
    /// let doc: serde_json::Value = serde_json::from_str(&json)?;
    /// let position = doc["joints"][0]["position"].as_f64().unwrap_or(f64::NAN);
    /// assert!((position - 90.0).abs() < 1e-12);
    /// assert!(doc["links"][1]["world_pose"].is_object());
    /// # Ok(())
    /// # }
    /// ```
    #[doc(alias = "export_json")]
    #[doc(alias = "to_dict")]
    pub fn to_json_string(&mut self, options: &JsonOptions<'_>) -> Result<String, KinematicsError> {
        self.update();
        let options = JsonOptions {
            world_poses: Some(self.data.world_from_link()),
            positions: Some(&self.q),
            ..*options
        };
        Ok(self.model.to_json_string(&options)?)
    }

    /// The links directly attached below the link `part`, in declaration order.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownLink`].
    #[doc(alias = "get_children")]
    pub fn children(&self, part: &str) -> Result<Vec<&str>, KinematicsError> {
        let l = self.link(part)?;
        Ok(self.model.children(l).map(|c| self.link_name(c)).collect())
    }

    /// Every link below the link `part` (not including it), depth-first.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownLink`].
    #[doc(alias = "get_all_descendants")]
    pub fn descendants(&self, part: &str) -> Result<Vec<&str>, KinematicsError> {
        let l = self.link(part)?;
        Ok(self
            .model
            .descendants(l)
            .into_iter()
            .map(|c| self.link_name(c))
            .collect())
    }

    /// The links from `part` up to the root link, both included.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownLink`].
    #[doc(alias = "get_chain_to_root")]
    pub fn path_to_root(&self, part: &str) -> Result<Vec<&str>, KinematicsError> {
        let l = self.link(part)?;
        Ok(self
            .model
            .path_to_root(l)
            .into_iter()
            .map(|c| self.link_name(c))
            .collect())
    }

    /// The deepest link that is an ancestor of (or equal to) both `a` and `b`; `None` when they
    /// hang from different roots (only the world datum is common to them).
    ///
    /// # Errors
    /// [`KinematicsError::UnknownLink`] naming the first unknown name.
    pub fn common_ancestor(&self, a: &str, b: &str) -> Result<Option<&str>, KinematicsError> {
        let (a, b) = (self.link(a)?, self.link(b)?);
        Ok(self.model.common_ancestor(a, b).map(|l| self.link_name(l)))
    }

    /// The parent link of `part` (`None` for the root link).
    ///
    /// # Errors
    /// [`KinematicsError::UnknownLink`].
    pub fn parent(&self, part: &str) -> Result<Option<&str>, KinematicsError> {
        let l = self.link(part)?;
        Ok(self.model.parent_link(l).map(|p| self.link_name(p)))
    }

    /// The name of the joint that attaches `part` to its parent (`None` for the root link with a
    /// fixed root): the joint to set to move a part, as yapCAD sets joints by part name.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownLink`].
    pub fn parent_joint(&self, part: &str) -> Result<Option<&str>, KinematicsError> {
        let l = self.link(part)?;
        Ok(self
            .model
            .parent_joint(l)
            .map(|j| self.model.joint(j).name.as_str()))
    }

    // --- internals ---

    fn link(&self, name: &str) -> Result<usize, KinematicsError> {
        self.model
            .link_index(name)
            .ok_or_else(|| KinematicsError::UnknownLink {
                name: name.to_string(),
            })
    }

    fn link_name(&self, l: usize) -> &str {
        &self.model.link(l).name
    }

    /// The joint named `name` and its body.
    fn moving_joint(&self, name: &str) -> Result<(usize, usize), KinematicsError> {
        let j = self
            .model
            .joint_index(name)
            .ok_or_else(|| KinematicsError::UnknownJoint {
                name: name.to_string(),
            })?;
        match self.model.joint_body(j) {
            Some(b) if self.model.bodies()[b].mimic.is_some() => {
                Err(KinematicsError::InvalidJointValue {
                    joint: name.to_string(),
                    reason: format!(
                        "it follows '{}' (coupled mimic) and has no coordinate of its own",
                        self.model
                            .joint(self.model.bodies()[b].mimic.map_or(j, |m| m.leader))
                            .name
                    ),
                })
            }
            Some(b) => Ok((j, b)),
            None => Err(KinematicsError::WrongJointKind {
                joint: name.to_string(),
                kind: self.model.joint(j).kind,
                expected: "a moving joint",
            }),
        }
    }

    /// The 1-DoF joint named `name` accepted by `accepts`, and its index in `q`.
    fn scalar_joint(
        &self,
        name: &str,
        expected: &'static str,
        accepts: fn(JointKind) -> bool,
    ) -> Result<(usize, usize), KinematicsError> {
        let (j, body) = self.moving_joint(name)?;
        let kind = self.model.joint(j).kind;
        if !(is_angular(kind) || is_linear(kind)) || !accepts(kind) {
            return Err(KinematicsError::WrongJointKind {
                joint: name.to_string(),
                kind,
                expected,
            });
        }
        Ok((j, self.model.bodies()[body].idx_q))
    }

    fn set_scalar(
        &mut self,
        name: &str,
        value: f64,
        expected: &'static str,
        accepts: fn(JointKind) -> bool,
    ) -> Result<(), KinematicsError> {
        let (j, idx_q) = self.scalar_joint(name, expected, accepts)?;
        if !value.is_finite() {
            return Err(KinematicsError::InvalidJointValue {
                joint: name.to_string(),
                reason: "value is not finite".into(),
            });
        }
        if self.q[idx_q] != value {
            self.q[idx_q] = value;
            if let Some(body) = self.model.joint_body(j) {
                self.invalidate(body);
            }
        }
        Ok(())
    }

    /// Marks body `i`'s joint transform and its whole subtree stale.
    fn invalidate(&mut self, i: usize) {
        self.joint_stale[i] = true;
        // Stale bodies form a union of subtrees: if `i` is already stale, so is everything below.
        if !self.stale[i] {
            let end = self.model.bodies()[i].subtree_end;
            self.stale[i..end].fill(true);
        }
        // Coupled mimic joints move with their leader.
        let leader = self.model.bodies()[i].joint;
        for f in 1..self.model.nbodies() {
            let b = &self.model.bodies()[f];
            if b.mimic.is_some_and(|m| Some(m.leader) == leader) {
                self.joint_stale[f] = true;
                if !self.stale[f] {
                    self.stale[f..b.subtree_end].fill(true);
                }
            }
        }
    }

    /// Makes body `i` up to date, refreshing its stale ancestors first (top down).
    fn refresh(&mut self, i: usize) {
        self.path.clear();
        let mut b = i;
        while b != 0 && self.stale[b] {
            self.path.push(b);
            b = self.model.bodies()[b].parent;
        }
        while let Some(b) = self.path.pop() {
            self.recompute(b);
        }
    }

    /// Recomputes body `i` from its parent, which must be up to date. The arithmetic is the same
    /// as in `forward_kinematics` and `update_frame_placements`, so the results are identical.
    fn recompute(&mut self, i: usize) {
        let body = &self.model.bodies()[i];
        debug_assert!(!self.stale[body.parent] || body.parent == 0);
        if self.joint_stale[i] {
            self.data.parent_from_body[i] =
                self.data.joint_models()[i].body_transform(body, &self.q);
            self.joint_stale[i] = false;
            self.stats.joint_updates += 1;
        }
        let local = self.data.parent_from_body[i];
        self.data.world_from_body[i] = if body.parent == 0 {
            local
        } else {
            self.data.world_from_body[body.parent] * local
        };
        self.place_links_and_frames(i);
        self.stale[i] = false;
        self.stats.body_updates += 1;
    }

    fn place_links_and_frames(&mut self, i: usize) {
        let world_from_body = self.data.world_from_body[i];
        for &l in &self.body_links[i] {
            let (_, body_from_link) = self.model.link_body(l);
            self.data.world_from_link[l] = world_from_body * *body_from_link;
        }
        for &f in &self.body_frames[i] {
            let frame = &self.model.frames()[f];
            self.data.world_from_frame[f] = self.data.world_from_link[frame.link] * frame.placement;
        }
    }
}

const ONE_DOF: &str = "a revolute, continuous or prismatic joint";
const ANGULAR: &str = "a revolute or continuous joint (degrees)";
const LINEAR: &str = "a prismatic joint (millimetres)";

fn is_angular(kind: JointKind) -> bool {
    matches!(kind, JointKind::Revolute | JointKind::Continuous)
}

fn is_linear(kind: JointKind) -> bool {
    matches!(kind, JointKind::Prismatic)
}

#[cfg(test)]
mod tests;
