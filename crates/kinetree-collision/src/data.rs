//! [`CollisionData`]: world poses of the shapes, world obstacles, and the results of the last
//! queries.

use crate::build::{CollisionOptions, shape_from_geometry};
use crate::error::CollisionError;
use crate::frames::Frame;
use crate::model::CollisionModel;
use crate::narrow::{Kind, Posed, Scratch};
use crate::pose::se3_to_pose;
use glam::DVec3;
use kinetree_kinematics::model::{Geometry, Model};
use kinetree_kinematics::spatial::Se3;
use kinetree_kinematics::{KinematicsData, forward_kinematics};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Pose;
use parry3d_f64::shape::SharedShape;

/// The signed distance between two shapes and where it is reached, in the world frame.
///
/// `distance > 0`: the shapes are apart by that much and `point_a`, `point_b` are the closest
/// points. `distance < 0`: they overlap, `-distance` is the penetration depth (the shortest
/// translation that separates them) and the points are the deepest points, each on its own
/// shape's surface. `normal` is a unit vector from `a` toward `b`: moving `b` along it increases
/// the distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Proximity {
    /// The first shape: a shape index (into [`CollisionModel::shapes`]).
    pub a: usize,
    /// The second shape: a shape index for self queries, an [`ObstacleId`] index for world
    /// queries.
    pub b: usize,
    /// Signed distance (m): positive separation, negative penetration depth.
    pub distance: f64,
    /// Witness point on `a`, world frame.
    pub point_a: DVec3,
    /// Witness point on `b`, world frame.
    pub point_b: DVec3,
    /// Unit vector from `a` toward `b`, world frame.
    pub normal: DVec3,
}

impl Proximity {
    pub(crate) const UNSET: Proximity = Proximity {
        a: usize::MAX,
        b: usize::MAX,
        distance: f64::INFINITY,
        point_a: DVec3::ZERO,
        point_b: DVec3::ZERO,
        normal: DVec3::X,
    };
}

/// The minimum signed distance between two links over their candidate shape pairs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkPairDistance {
    /// First link (index into `model.links()`).
    pub link_a: usize,
    /// Second link.
    pub link_b: usize,
    /// Minimum signed distance over the shape pairs (m).
    pub distance: f64,
    /// The shape of `link_a` reaching it.
    pub shape_a: usize,
    /// The shape of `link_b` reaching it.
    pub shape_b: usize,
}

/// Identifies a world obstacle of a [`CollisionData`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ObstacleId(pub usize);

/// A shape fixed in the world (not attached to the robot), moved at run time.
#[derive(Clone, Debug)]
pub struct Obstacle {
    pub(crate) name: String,
    pub(crate) shape: SharedShape,
    pub(crate) pose: Pose,
    pub(crate) aabb: Aabb,
    pub(crate) kind: Kind,
}

impl Obstacle {
    /// The obstacle's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The parry shape.
    #[must_use]
    pub fn shape(&self) -> &SharedShape {
        &self.shape
    }

    /// The shape's pose in the world frame.
    #[must_use]
    pub fn pose(&self) -> &Pose {
        &self.pose
    }
}

/// The buffers of the collision queries for one [`CollisionModel`], after Pinocchio's
/// `GeometryData`: world poses and bounding boxes of the shapes, the world obstacles, and the
/// results of the last queries.
///
/// Create it once with [`CollisionData::new`]. Queries then allocate nothing (see
/// [`crate::query`] for the exceptions inside parry). Adding obstacles allocates.
#[derive(Clone, Debug)]
pub struct CollisionData {
    pub(crate) npairs: usize,
    pub(crate) body_pose: Vec<Pose>,
    pub(crate) world_from_shape: Vec<Pose>,
    /// `world_from_shape` in matrix form, for the distance queries.
    pub(crate) frames: Vec<Frame>,
    pub(crate) aabbs: Vec<Aabb>,
    pub(crate) distances: Vec<Proximity>,
    pub(crate) link_pair_distances: Vec<LinkPairDistance>,
    pub(crate) contacts: Vec<Proximity>,
    pub(crate) obstacles: Vec<Option<Obstacle>>,
    pub(crate) world_contacts: Vec<Proximity>,
    pub(crate) world_distances: Vec<Proximity>,
    /// Broad-phase sort buffer: shape indices, then `nshapes + obstacle` for obstacles.
    pub(crate) order: Vec<usize>,
    pub(crate) scratch: Scratch,
}

impl CollisionData {
    /// Allocates every buffer for `cmodel`. Shape poses are the identity until
    /// [`CollisionData::update_placements`] or [`CollisionData::compute_placements`] runs.
    #[must_use]
    pub fn new(cmodel: &CollisionModel) -> Self {
        let n = cmodel.shapes.len();
        let npairs = cmodel.pairs.len();
        Self {
            npairs,
            body_pose: vec![Pose::IDENTITY; cmodel.nbodies()],
            world_from_shape: vec![Pose::IDENTITY; n],
            frames: vec![Frame::IDENTITY; n],
            aabbs: cmodel
                .shapes
                .iter()
                .map(|s| s.kind.aabb(&*s.shape, &s.body_from_shape))
                .collect(),
            distances: vec![Proximity::UNSET; npairs],
            link_pair_distances: cmodel
                .link_pairs
                .iter()
                .map(|lp| LinkPairDistance {
                    link_a: lp.link_a,
                    link_b: lp.link_b,
                    distance: f64::INFINITY,
                    shape_a: usize::MAX,
                    shape_b: usize::MAX,
                })
                .collect(),
            contacts: Vec::with_capacity(npairs),
            obstacles: Vec::new(),
            world_contacts: Vec::new(),
            world_distances: Vec::new(),
            order: Vec::with_capacity(n),
            scratch: Scratch::default(),
        }
    }

    /// Checks that this data was created for `cmodel`.
    ///
    /// # Errors
    /// [`CollisionError::DataMismatch`].
    pub fn check_model(&self, cmodel: &CollisionModel) -> Result<(), CollisionError> {
        if self.world_from_shape.len() != cmodel.shapes.len()
            || self.npairs != cmodel.pairs.len()
            || self.link_pair_distances.len() != cmodel.link_pairs.len()
            || self.body_pose.len() != cmodel.nbodies()
        {
            return Err(CollisionError::DataMismatch {
                data_shapes: self.world_from_shape.len(),
                data_pairs: self.npairs,
                model_shapes: cmodel.shapes.len(),
                model_pairs: cmodel.pairs.len(),
            });
        }
        Ok(())
    }

    /// Places every shape in the world from the body placements of a forward kinematics already
    /// run in `kinematics` ([`KinematicsData::world_from_body`]), and updates their bounding
    /// boxes. Allocates nothing.
    ///
    /// # Errors
    /// [`CollisionError::DataMismatch`], or [`CollisionError::KinematicsMismatch`] when
    /// `kinematics` belongs to another model.
    pub fn update_placements(
        &mut self,
        cmodel: &CollisionModel,
        kinematics: &KinematicsData,
    ) -> Result<(), CollisionError> {
        self.check_model(cmodel)?;
        let bodies = kinematics.world_from_body();
        if bodies.len() != self.body_pose.len() {
            return Err(CollisionError::KinematicsMismatch {
                data_bodies: bodies.len(),
                model_bodies: self.body_pose.len(),
            });
        }
        for (pose, x) in self.body_pose.iter_mut().zip(bodies) {
            *pose = se3_to_pose(x);
        }
        for (k, s) in cmodel.shapes.iter().enumerate() {
            let pose = self.body_pose[s.body] * s.body_from_shape;
            self.world_from_shape[k] = pose;
            self.frames[k] = Frame::of(&pose);
            self.aabbs[k] = s.kind.aabb(&*s.shape, &pose);
        }
        Ok(())
    }

    /// Runs [`forward_kinematics`] for `q` (length `model.nq()`) in `kinematics`, then
    /// [`CollisionData::update_placements`]. Allocates nothing.
    ///
    /// # Errors
    /// The kinematics errors for a bad `q` or a mismatched `kinematics`, and those of
    /// [`CollisionData::update_placements`].
    pub fn compute_placements(
        &mut self,
        model: &Model,
        cmodel: &CollisionModel,
        kinematics: &mut KinematicsData,
        q: &[f64],
    ) -> Result<(), CollisionError> {
        forward_kinematics(model, kinematics, q)?;
        self.update_placements(cmodel, kinematics)
    }

    /// World pose of shape `shape` (of its parry shape, see
    /// [`CollisionShape::body_from_shape`](crate::CollisionShape::body_from_shape)) after the
    /// last placement update.
    ///
    /// # Errors
    /// [`CollisionError::ShapeOutOfRange`] when `shape` is not a shape index of the model.
    pub fn shape_pose(&self, shape: usize) -> Result<&Pose, CollisionError> {
        self.world_from_shape
            .get(shape)
            .ok_or(CollisionError::ShapeOutOfRange {
                index: shape,
                count: self.world_from_shape.len(),
            })
    }

    /// World poses of every shape, in shape order.
    #[must_use]
    pub fn shape_poses(&self) -> &[Pose] {
        &self.world_from_shape
    }

    /// World-frame bounding boxes of every shape, in shape order.
    #[must_use]
    pub fn shape_aabbs(&self) -> &[Aabb] {
        &self.aabbs
    }

    /// The results of the last [`compute_distances`](crate::compute_distances): one per
    /// candidate pair, in pair order (`a`, `b` are shape indices).
    #[must_use]
    pub fn distances(&self) -> &[Proximity] {
        &self.distances
    }

    /// The per-link-pair minima of the last [`compute_distances`](crate::compute_distances), in
    /// the order of [`CollisionModel::link_pairs`].
    #[must_use]
    pub fn compute_link_pair_distances(&self) -> &[LinkPairDistance] {
        &self.link_pair_distances
    }

    /// The colliding pairs found by the last [`compute_self_collisions`](crate::compute_self_collisions).
    #[must_use]
    pub fn contacts(&self) -> &[Proximity] {
        &self.contacts
    }

    /// The shape–obstacle contacts found by the last
    /// [`compute_world_collisions`](crate::compute_world_collisions).
    #[must_use]
    pub fn world_contacts(&self) -> &[Proximity] {
        &self.world_contacts
    }

    /// The results of the last [`compute_world_distances`](crate::compute_world_distances).
    #[must_use]
    pub fn world_distances(&self) -> &[Proximity] {
        &self.world_distances
    }

    /// Adds a world obstacle from a model geometry (box, sphere, cylinder, capsule; a mesh is
    /// loaded through `options`) at `pose` (world frame) and returns its id.
    ///
    /// # Errors
    /// [`CollisionError::InvalidObstacle`] naming the obstacle for an invalid shape or a
    /// non-finite pose; otherwise as [`shape_from_geometry`] (a mesh that cannot be loaded).
    pub fn add_obstacle(
        &mut self,
        name: impl Into<String>,
        geometry: &Geometry,
        pose: &Se3,
        options: &CollisionOptions,
    ) -> Result<ObstacleId, CollisionError> {
        let name = name.into();
        // Name the obstacle as an obstacle, not as "collision element 0 of link '…'".
        let (shape, geometry_from_shape) = shape_from_geometry(geometry, options, &name, 0)
            .map_err(|e| match e {
                CollisionError::InvalidGeometry { link, reason, .. } => {
                    CollisionError::InvalidObstacle { name: link, reason }
                }
                e => e,
            })?;
        if !pose.is_finite() {
            return Err(CollisionError::InvalidObstacle {
                name,
                reason: "the pose is not finite".into(),
            });
        }
        let id = self.add_obstacle_shape(name, shape, &se3_to_pose(pose))?;
        if let Some(o) = self.obstacles[id.0].as_mut() {
            // Keep the geometry-to-shape offset (cylinders) in the stored pose.
            o.pose *= geometry_from_shape;
            o.aabb = o.kind.aabb(&*o.shape, &o.pose);
        }
        Ok(id)
    }

    /// Adds a world obstacle given as any parry shape at `pose` (world frame, parry's pose
    /// type; [`se3_to_pose`] converts) and returns its id. Ids stay valid until
    /// [`CollisionData::remove_obstacle`] or [`CollisionData::clear_obstacles`].
    ///
    /// # Errors
    /// [`CollisionError::NonFinite`] for a non-finite pose;
    /// [`CollisionError::InvalidObstacle`] naming the obstacle when the shape's bounding box is
    /// not finite or reaches beyond [`MAX_SHAPE_SIZE`](crate::build::MAX_SHAPE_SIZE) from its
    /// origin.
    pub fn add_obstacle_shape(
        &mut self,
        name: impl Into<String>,
        shape: SharedShape,
        pose: &Pose,
    ) -> Result<ObstacleId, CollisionError> {
        check_pose(pose)?;
        let name = name.into();
        let local = shape.compute_local_aabb();
        let reach = local.mins.abs().max(local.maxs.abs()).max_element();
        if reach.is_nan() || reach > crate::build::MAX_SHAPE_SIZE {
            return Err(CollisionError::InvalidObstacle {
                name,
                reason: format!(
                    "the shape reaches {reach} m from its origin, more than {} m",
                    crate::build::MAX_SHAPE_SIZE
                ),
            });
        }
        let kind = Kind::of(&shape);
        let aabb = kind.aabb(&*shape, pose);
        self.obstacles.push(Some(Obstacle {
            name,
            shape,
            pose: *pose,
            aabb,
            kind,
        }));
        let n = self.world_from_shape.len();
        let live = self.obstacles.iter().flatten().count();
        // Room for every shape–obstacle result, so the queries never grow these buffers.
        self.world_contacts.reserve(n * live);
        self.world_distances.reserve(n * live);
        self.order.reserve(n + self.obstacles.len());
        Ok(ObstacleId(self.obstacles.len() - 1))
    }

    /// Moves an obstacle to `pose` (world frame). Allocates nothing.
    ///
    /// # Errors
    /// [`CollisionError::UnknownObstacle`], [`CollisionError::NonFinite`].
    pub fn set_obstacle_pose(&mut self, id: ObstacleId, pose: &Pose) -> Result<(), CollisionError> {
        check_pose(pose)?;
        let o = self.obstacle_mut(id)?;
        o.pose = *pose;
        o.aabb = o.kind.aabb(&*o.shape, pose);
        Ok(())
    }

    /// Removes an obstacle; the ids of the others do not change.
    ///
    /// # Errors
    /// [`CollisionError::UnknownObstacle`].
    pub fn remove_obstacle(&mut self, id: ObstacleId) -> Result<Obstacle, CollisionError> {
        self.obstacle_mut(id)?;
        self.obstacles[id.0]
            .take()
            .ok_or(CollisionError::UnknownObstacle { id: id.0 })
    }

    /// Removes every obstacle.
    pub fn clear_obstacles(&mut self) {
        self.obstacles.clear();
    }

    /// The obstacle with this id.
    ///
    /// # Errors
    /// [`CollisionError::UnknownObstacle`].
    pub fn obstacle(&self, id: ObstacleId) -> Result<&Obstacle, CollisionError> {
        self.obstacles
            .get(id.0)
            .and_then(Option::as_ref)
            .ok_or(CollisionError::UnknownObstacle { id: id.0 })
    }

    /// The live obstacles and their ids.
    pub fn obstacles(&self) -> impl Iterator<Item = (ObstacleId, &Obstacle)> {
        self.obstacles
            .iter()
            .enumerate()
            .filter_map(|(i, o)| o.as_ref().map(|o| (ObstacleId(i), o)))
    }

    fn obstacle_mut(&mut self, id: ObstacleId) -> Result<&mut Obstacle, CollisionError> {
        self.obstacles
            .get_mut(id.0)
            .and_then(Option::as_mut)
            .ok_or(CollisionError::UnknownObstacle { id: id.0 })
    }
}

impl Obstacle {
    pub(crate) fn posed(&self) -> Posed<'_> {
        Posed {
            kind: &self.kind,
            shape: &*self.shape,
            pose: &self.pose,
        }
    }
}

fn check_pose(pose: &Pose) -> Result<(), CollisionError> {
    if pose.translation.is_finite() && pose.rotation.is_finite() {
        Ok(())
    } else {
        Err(CollisionError::NonFinite {
            what: "obstacle pose",
        })
    }
}
