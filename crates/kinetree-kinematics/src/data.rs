//! [`KinematicsData`]: every buffer the kinematics algorithms write, allocated once per model.

use crate::error::KinematicsError;
use crate::joint::JointModel;
use kinetree_model::Model;
use kinetree_model::spatial::{Motion, Se3};

/// Identifies a place whose pose the kinematics layer can report: a link or a named frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FrameId {
    /// A link (index into [`Model::links`]).
    Link(usize),
    /// A named frame (index into [`Model::frames`]).
    Frame(usize),
}

impl FrameId {
    /// Looks `name` up among links first, then named frames: `part/frame`, or a frame name
    /// unique in the model. `part/ORIGIN` is the part's own frame unless the part declares a
    /// frame called `ORIGIN` ([`kinetree_model::ORIGIN_FRAME`]).
    ///
    /// # Errors
    /// [`KinematicsError::AmbiguousFrame`] for a bare frame name that several links' frames
    /// share (listing each as `link/frame`), [`KinematicsError::UnknownFrame`] when neither
    /// exists.
    pub fn find(model: &Model, name: &str) -> Result<FrameId, KinematicsError> {
        let origin_of = |name: &str| {
            let part = name
                .strip_suffix(kinetree_model::ORIGIN_FRAME)?
                .strip_suffix('/')?;
            model.link_index(part).map(FrameId::Link)
        };
        model
            .link_index(name)
            .map(FrameId::Link)
            .or_else(|| model.frame_index(name).map(FrameId::Frame))
            .or_else(|| origin_of(name))
            .ok_or_else(|| {
                // A bare name that several links' frames share is kept only as `link/frame`.
                let candidates: Vec<String> = model
                    .frames()
                    .iter()
                    .filter(|f| f.name == name)
                    .map(|f| format!("{}/{}", model.links()[f.link].name, f.name))
                    .collect();
                if candidates.len() > 1 {
                    KinematicsError::AmbiguousFrame {
                        name: name.to_string(),
                        candidates,
                    }
                } else {
                    KinematicsError::UnknownFrame {
                        name: name.to_string(),
                    }
                }
            })
    }

    /// Checks that this link or frame index exists in `model`.
    ///
    /// # Errors
    /// [`KinematicsError::FrameOutOfRange`] when the index is not below the model's number of
    /// links (or named frames).
    pub fn check(self, model: &Model) -> Result<FrameId, KinematicsError> {
        self.check_counts(model.links().len(), model.frames().len())
    }

    /// [`FrameId::check`] against given link and frame counts.
    pub(crate) fn check_counts(
        self,
        links: usize,
        frames: usize,
    ) -> Result<FrameId, KinematicsError> {
        let (what, index, count) = match self {
            FrameId::Link(l) => ("link", l, links),
            FrameId::Frame(f) => ("frame", f, frames),
        };
        if index < count {
            Ok(self)
        } else {
            Err(KinematicsError::FrameOutOfRange { what, index, count })
        }
    }

    /// The body carrying this frame and the frame's pose in that body's frame.
    ///
    /// # Errors
    /// [`KinematicsError::FrameOutOfRange`] for an index `model` does not have.
    pub fn body(&self, model: &Model) -> Result<(usize, Se3), KinematicsError> {
        Ok(match self.check(model)? {
            FrameId::Link(l) => {
                let (b, p) = model.link_body(l);
                (b, *p)
            }
            FrameId::Frame(f) => model.frame_body(f),
        })
    }

    /// The frame's name.
    ///
    /// # Errors
    /// [`KinematicsError::FrameOutOfRange`] for an index `model` does not have.
    pub fn name<'m>(&self, model: &'m Model) -> Result<&'m str, KinematicsError> {
        Ok(match self.check(model)? {
            FrameId::Link(l) => &model.link(l).name,
            FrameId::Frame(f) => &model.frames()[f].name,
        })
    }
}

/// The buffers of the kinematics algorithms for one [`Model`]: body, link and frame placements,
/// body velocities and accelerations, joint Jacobians.
///
/// Create it once with [`KinematicsData::new`]; no algorithm of this crate allocates afterwards.
/// A `KinematicsData` must only be used with the model it was created for (checked at entry of
/// every algorithm by comparing sizes).
#[derive(Clone, Debug)]
pub struct KinematicsData {
    pub(crate) nq: usize,
    pub(crate) nv: usize,
    pub(crate) joint_models: Vec<JointModel>,
    /// Body of each velocity coordinate.
    pub(crate) dof_body: Vec<usize>,
    pub(crate) parent_from_body: Vec<Se3>,
    pub(crate) world_from_body: Vec<Se3>,
    pub(crate) body_velocity: Vec<Motion>,
    pub(crate) body_acceleration: Vec<Motion>,
    pub(crate) world_from_link: Vec<Se3>,
    /// Per link: its body, and whether the link frame is the body frame (placement copied, not
    /// multiplied).
    pub(crate) link_on_body_frame: Vec<bool>,
    /// Per body: its joint is revolute about x, y or z (0, 1, 2) and its placement does not
    /// rotate, so forward kinematics turns the parent's rotation about that axis; 3 otherwise.
    pub(crate) turn_axis: Vec<u8>,
    pub(crate) world_from_frame: Vec<Se3>,
    /// Joint Jacobian columns in the world frame (twists at the world origin), one per DoF.
    pub(crate) jacobian: Vec<Motion>,
    /// Time derivatives of `jacobian`'s columns.
    pub(crate) jacobian_dot: Vec<Motion>,
    /// Per body: the world-frame Jacobian column of a coupled mimic body's own joint (unscaled),
    /// and its time derivative. Unused for other bodies.
    pub(crate) mimic_jacobian: Vec<Motion>,
    pub(crate) mimic_jacobian_dot: Vec<Motion>,
    /// Body velocities in the world frame (at the world origin), for `jacobian_dot`.
    pub(crate) world_velocity: Vec<Motion>,
    /// The configuration of the last forward kinematics (for consumers such as the Chain API).
    pub(crate) q: Vec<f64>,
}

/// Mutable views of the per-body buffers of a [`KinematicsData`], for the sweeps of the layers
/// above (the dynamics algorithms) that compute the same quantities as forward kinematics and
/// store them here, so that one `KinematicsData` is the one source of placements and velocities.
/// A sweep that writes `q` writes `parent_from_body` for it too;
/// [`update_world_placements`](crate::update_world_placements) completes the world placements
/// from them.
#[derive(Debug)]
#[non_exhaustive]
pub struct BodyBuffers<'a> {
    /// The specialised joint model of each body (read only).
    pub joint_models: &'a [JointModel],
    /// The configuration of the last sweep.
    pub q: &'a mut [f64],
    /// `parent_from_body` of each body.
    pub parent_from_body: &'a mut [Se3],
    /// `world_from_body` of each body.
    pub world_from_body: &'a mut [Se3],
    /// Spatial velocity of each body in its own frame.
    pub body_velocity: &'a mut [Motion],
}

impl KinematicsData {
    /// Allocates every buffer for `model`. Placements start at the model's zero configuration
    /// only after a forward kinematics call.
    #[must_use]
    pub fn new(model: &Model) -> Self {
        let nb = model.nbodies();
        let mut dof_body = vec![0; model.nv()];
        for (i, b) in model.bodies().iter().enumerate() {
            for d in dof_body[b.idx_v..b.idx_v + b.nv].iter_mut() {
                *d = i;
            }
        }
        Self {
            nq: model.nq(),
            nv: model.nv(),
            joint_models: model.bodies().iter().map(JointModel::from_body).collect(),
            dof_body,
            parent_from_body: vec![Se3::IDENTITY; nb],
            world_from_body: vec![Se3::IDENTITY; nb],
            body_velocity: vec![Motion::ZERO; nb],
            body_acceleration: vec![Motion::ZERO; nb],
            world_from_link: vec![Se3::IDENTITY; model.links().len()],
            link_on_body_frame: (0..model.links().len())
                .map(|l| *model.link_body(l).1 == Se3::IDENTITY)
                .collect(),
            turn_axis: model
                .bodies()
                .iter()
                .enumerate()
                .map(|(i, b)| match JointModel::from_body(b).axis_index() {
                    Some((k, true))
                        if i > 0
                            && b.parent != 0
                            && b.mimic.is_none()
                            && b.placement.rotation == glam::DMat3::IDENTITY =>
                    {
                        k as u8
                    }
                    _ => 3,
                })
                .collect(),
            world_from_frame: vec![Se3::IDENTITY; model.frames().len()],
            jacobian: vec![Motion::ZERO; model.nv()],
            jacobian_dot: vec![Motion::ZERO; model.nv()],
            mimic_jacobian: vec![Motion::ZERO; nb],
            mimic_jacobian_dot: vec![Motion::ZERO; nb],
            world_velocity: vec![Motion::ZERO; nb],
            q: vec![0.0; model.nq()],
        }
    }

    /// Checks that this data belongs to `model`.
    ///
    /// # Errors
    /// [`KinematicsError::DataMismatch`].
    pub fn check_model(&self, model: &Model) -> Result<(), KinematicsError> {
        if self.joint_models.len() != model.nbodies()
            || self.nv != model.nv()
            || self.nq != model.nq()
            || self.world_from_link.len() != model.links().len()
            || self.world_from_frame.len() != model.frames().len()
        {
            return Err(KinematicsError::DataMismatch {
                data_bodies: self.joint_models.len(),
                data_nv: self.nv,
                model_bodies: model.nbodies(),
                model_nv: model.nv(),
            });
        }
        Ok(())
    }

    /// Mutable views of the per-body buffers (see [`BodyBuffers`]), for the sweeps of the layers
    /// above that store their placements and velocities here.
    #[inline]
    #[must_use]
    pub fn body_buffers_mut(&mut self) -> BodyBuffers<'_> {
        BodyBuffers {
            joint_models: &self.joint_models,
            q: &mut self.q,
            parent_from_body: &mut self.parent_from_body,
            world_from_body: &mut self.world_from_body,
            body_velocity: &mut self.body_velocity,
        }
    }

    /// The specialised joint model of each body (index 0 is the world).
    #[inline]
    #[must_use]
    pub fn joint_models(&self) -> &[JointModel] {
        &self.joint_models
    }

    /// The body that owns each velocity coordinate.
    #[inline]
    #[must_use]
    pub fn dof_body(&self) -> &[usize] {
        &self.dof_body
    }

    /// `parent_from_body` of each body at the last configuration (Pinocchio's `liMi`).
    #[inline]
    #[must_use]
    pub fn parent_from_body(&self) -> &[Se3] {
        &self.parent_from_body
    }

    /// `world_from_body` of each body at the last configuration (Pinocchio's `oMi`).
    #[inline]
    #[must_use]
    pub fn world_from_body(&self) -> &[Se3] {
        &self.world_from_body
    }

    /// World placement of every link, written by forward kinematics.
    #[inline]
    #[must_use]
    pub fn world_from_link(&self) -> &[Se3] {
        &self.world_from_link
    }

    /// World placement of every named frame, written by
    /// [`update_frame_placements`](crate::update_frame_placements).
    #[inline]
    #[must_use]
    pub fn world_from_frame(&self) -> &[Se3] {
        &self.world_from_frame
    }

    /// World placement (`world_from_frame`) of a link or named frame (named frames need
    /// [`update_frame_placements`](crate::update_frame_placements) first).
    ///
    /// # Errors
    /// [`KinematicsError::FrameOutOfRange`] for an index this data's model does not have.
    #[inline]
    pub fn world_from(&self, frame: FrameId) -> Result<&Se3, KinematicsError> {
        Ok(
            match frame.check_counts(self.world_from_link.len(), self.world_from_frame.len())? {
                FrameId::Link(l) => &self.world_from_link[l],
                FrameId::Frame(f) => &self.world_from_frame[f],
            },
        )
    }

    /// Spatial velocity of each body in its own frame (written when forward kinematics is given `v`).
    #[inline]
    #[must_use]
    pub fn body_velocity(&self) -> &[Motion] {
        &self.body_velocity
    }

    /// Spatial acceleration of each body in its own frame (written when forward kinematics is
    /// given `v` and `a`). This is the derivative of the body twist, not the classical
    /// acceleration of the body origin.
    #[inline]
    #[must_use]
    pub fn body_acceleration(&self) -> &[Motion] {
        &self.body_acceleration
    }

    /// Joint Jacobian columns in the world frame (written by
    /// [`compute_joint_jacobians`](crate::compute_joint_jacobians)): column `k` is the twist, at
    /// the world origin in world axes, of the joint that owns coordinate `k` for a unit velocity of
    /// `k` (the motion of coupled mimic followers is added by the frame Jacobians, not here).
    #[inline]
    #[must_use]
    pub fn joint_jacobians(&self) -> &[Motion] {
        &self.jacobian
    }

    /// The configuration of the last forward kinematics call.
    #[inline]
    #[must_use]
    pub fn q(&self) -> &[f64] {
        &self.q
    }
}
