//! [`ExternalForces`]: wrenches applied to links or frames by the environment.

use crate::error::DynamicsError;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::{Force, Se3};
use kinetree_kinematics::{FrameId, ReferenceFrame};

/// One applied wrench.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Entry {
    body: usize,
    body_from_frame: Se3,
    reference: ReferenceFrame,
    force: Force,
}

/// Wrenches (spatial forces `[force; torque]`) that the environment applies to links or named
/// frames, for [`rnea_with_external_forces`](crate::rnea_with_external_forces),
/// [`aba_with_external_forces`](crate::aba_with_external_forces) and the integrator.
///
/// Each wrench is given in a [`ReferenceFrame`]:
/// - [`ReferenceFrame::Local`]: in the frame's own axes, the torque about the frame origin;
/// - [`ReferenceFrame::LocalWorldAligned`]: in world axes, the torque about the frame origin
///   (e.g. a push of 10 N along world x at the hand: `Force::new(DVec3::X * 10.0, DVec3::ZERO)`);
/// - [`ReferenceFrame::World`]: in world axes, the torque about the world origin (the natural
///   spatial-algebra form).
///
/// The container is built for one model and reused: [`ExternalForces::clear`] empties it without
/// freeing memory. Up to `links + frames` wrenches fit without allocating.
///
/// # Examples
/// ```
/// use kinetree_dynamics::{ExternalForces, ReferenceFrame};
/// use kinetree_dynamics::spatial::{glam::DVec3, Force};
/// # use kinetree_dynamics::model::{Model, RootJoint};
/// # fn main() -> Result<(), kinetree_dynamics::DynamicsError> {
/// # let model = Model::from_urdf_str(r#"<robot name="r"><link name="base"/><link name="tip"/>
/// #   <joint name="j" type="continuous"><parent link="base"/><child link="tip"/></joint></robot>"#,
/// #   RootJoint::Fixed).map_err(kinetree_dynamics::kinematics::KinematicsError::from)?;
/// let mut fext = ExternalForces::new(&model);
/// fext.add_by_name(&model, "tip", ReferenceFrame::LocalWorldAligned,
///                  Force::new(DVec3::new(0.0, 0.0, -5.0), DVec3::ZERO))?;
/// assert_eq!(fext.len(), 1);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ExternalForces {
    nlinks: usize,
    nframes: usize,
    entries: Vec<Entry>,
}

impl ExternalForces {
    /// An empty set of wrenches for `model`.
    #[must_use]
    pub fn new(model: &Model) -> Self {
        let nlinks = model.links().len();
        let nframes = model.frames().len();
        Self {
            nlinks,
            nframes,
            entries: Vec::with_capacity(nlinks + nframes),
        }
    }

    /// Removes every wrench (keeps the memory).
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Number of wrenches added since the last [`clear`](Self::clear).
    #[must_use]
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether no wrench is applied.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Applies `force` (`[force; torque]`, N and N·m) to a link or named frame, expressed in
    /// `reference` (see the type's docs). Wrenches on the same link add up.
    ///
    /// # Errors
    /// [`DynamicsError::IndexOutOfRange`] for a link or frame index the model does not have;
    /// [`DynamicsError::DataMismatch`] when `self` was built for another model;
    /// [`DynamicsError::NonFinite`] for a NaN or infinite component.
    pub fn add(
        &mut self,
        model: &Model,
        frame: FrameId,
        reference: ReferenceFrame,
        force: Force,
    ) -> Result<(), DynamicsError> {
        self.check_model(model)?;
        match frame {
            FrameId::Link(l) if l >= self.nlinks => {
                return Err(DynamicsError::IndexOutOfRange {
                    what: "link",
                    index: l,
                    count: self.nlinks,
                });
            }
            FrameId::Frame(f) if f >= self.nframes => {
                return Err(DynamicsError::IndexOutOfRange {
                    what: "frame",
                    index: f,
                    count: self.nframes,
                });
            }
            _ => {}
        }
        if let Some(index) = force.to_array().iter().position(|x| !x.is_finite()) {
            return Err(DynamicsError::NonFinite {
                what: "external force",
                index,
            });
        }
        let (body, body_from_frame) = frame.body(model)?;
        self.entries.push(Entry {
            body,
            body_from_frame,
            reference,
            force,
        });
        Ok(())
    }

    /// As [`add`](Self::add), for the link or named frame called `name` (links first).
    ///
    /// # Errors
    /// [`DynamicsError::UnknownLink`] when no link or frame has that name; as [`add`](Self::add).
    pub fn add_by_name(
        &mut self,
        model: &Model,
        name: &str,
        reference: ReferenceFrame,
        force: Force,
    ) -> Result<(), DynamicsError> {
        let frame = FrameId::find(model, name).map_err(|_| DynamicsError::UnknownLink {
            name: name.to_string(),
        })?;
        self.add(model, frame, reference, force)
    }

    /// Checks that this container belongs to `model`.
    ///
    /// # Errors
    /// [`DynamicsError::DataMismatch`].
    pub fn check_model(&self, model: &Model) -> Result<(), DynamicsError> {
        if self.nlinks != model.links().len() || self.nframes != model.frames().len() {
            return Err(DynamicsError::DataMismatch {
                what: "external forces",
                data_bodies: self.nlinks,
                data_nv: self.nframes,
                model_bodies: model.links().len(),
                model_nv: model.frames().len(),
            });
        }
        Ok(())
    }

    /// Whether some wrench needs the bodies' world placements.
    pub(crate) fn needs_world(&self) -> bool {
        self.entries
            .iter()
            .any(|e| e.reference != ReferenceFrame::Local)
    }

    /// Calls `f(body, wrench in the body frame)` for every wrench, given the bodies' world
    /// placements (only read for wrenches not given in [`ReferenceFrame::Local`]).
    pub(crate) fn for_each_local(&self, world_from_body: &[Se3], mut f: impl FnMut(usize, Force)) {
        for e in &self.entries {
            let local = match e.reference {
                ReferenceFrame::Local => e.body_from_frame.act_force(&e.force),
                ReferenceFrame::World => world_from_body[e.body].act_inv_force(&e.force),
                ReferenceFrame::LocalWorldAligned => {
                    let x = &world_from_body[e.body];
                    world_from_body[e.body].act_inv_force(&aligned_to_world(x, e))
                }
            };
            f(e.body, local);
        }
    }

    /// Calls `f(body, wrench in the world frame at the world origin)` for every wrench.
    pub(crate) fn for_each_world(&self, world_from_body: &[Se3], mut f: impl FnMut(usize, Force)) {
        for e in &self.entries {
            let x = &world_from_body[e.body];
            let world = match e.reference {
                ReferenceFrame::Local => (*x * e.body_from_frame).act_force(&e.force),
                ReferenceFrame::World => e.force,
                ReferenceFrame::LocalWorldAligned => aligned_to_world(x, e),
            };
            f(e.body, world);
        }
    }
    /// Calls `f(body, wrench in the world frame at the world origin, reference, world position of
    /// the point of application)` for every wrench.
    pub(crate) fn for_each_world_with_point(
        &self,
        world_from_body: &[Se3],
        mut f: impl FnMut(usize, Force, ReferenceFrame, DVec3),
    ) {
        for e in &self.entries {
            let x = &world_from_body[e.body];
            let world = match e.reference {
                ReferenceFrame::Local => (*x * e.body_from_frame).act_force(&e.force),
                ReferenceFrame::World => e.force,
                ReferenceFrame::LocalWorldAligned => aligned_to_world(x, e),
            };
            let point = x.transform_point(e.body_from_frame.translation);
            f(e.body, world, e.reference, point);
        }
    }
}

/// A world-aligned wrench about the frame origin, moved to the world origin.
#[inline]
fn aligned_to_world(world_from_body: &Se3, e: &Entry) -> Force {
    let p = world_from_body.transform_point(e.body_from_frame.translation);
    Force::new(e.force.linear, e.force.angular + p.cross(e.force.linear))
}
