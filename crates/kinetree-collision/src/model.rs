//! [`CollisionModel`]: the collision shapes of a [`Model`](kinetree_kinematics::model::Model)'s
//! links, where they sit on the moving bodies, and the candidate pairs to test.

use kinetree_kinematics::model::Geometry;
use kinetree_kinematics::spatial::Se3;
use parry3d_f64::math::Pose;
use parry3d_f64::shape::SharedShape;

/// One collision shape: a `<collision>` element of a link, turned into a parry shape.
#[derive(Clone, Debug)]
pub struct CollisionShape {
    pub(crate) name: String,
    pub(crate) link: usize,
    pub(crate) element: usize,
    pub(crate) body: usize,
    pub(crate) origin: Se3,
    pub(crate) body_from_shape: Pose,
    pub(crate) geometry: Geometry,
    pub(crate) shape: SharedShape,
    pub(crate) kind: crate::narrow::Kind,
}

impl CollisionShape {
    /// The shape's name, `<link>_<k>` with `k` the index of its `<collision>` element within the
    /// link (counting every element, skipped ones included), as Pinocchio names geometries.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The link carrying the shape (index into `model.links()`).
    #[must_use]
    pub fn link(&self) -> usize {
        self.link
    }

    /// Index of the shape's `<collision>` element within its link's `collisions`.
    #[must_use]
    pub fn element(&self) -> usize {
        self.element
    }

    /// The moving body carrying the shape (index into `model.bodies()`; 0 is the world).
    #[must_use]
    pub fn body(&self) -> usize {
        self.body
    }

    /// Pose of the geometry in its link's frame (the element's `<origin>`).
    #[must_use]
    pub fn origin(&self) -> &Se3 {
        &self.origin
    }

    /// Pose of the parry shape in its body's frame. For a cylinder this includes a quarter turn
    /// about x: parry's cylinders lie along their local y axis, URDF's along z.
    #[must_use]
    pub fn body_from_shape(&self) -> &Pose {
        &self.body_from_shape
    }

    /// The geometry as the model describes it.
    #[must_use]
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// The parry shape.
    #[must_use]
    pub fn shape(&self) -> &SharedShape {
        &self.shape
    }
}

impl CollisionShape {
    pub(crate) fn posed<'a>(&'a self, pose: &'a Pose) -> crate::narrow::Posed<'a> {
        crate::narrow::Posed {
            kind: &self.kind,
            shape: &*self.shape,
            pose,
        }
    }
}

/// A candidate pair of shapes, `shape_a < shape_b`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CollisionPair {
    /// First shape (index into [`CollisionModel::shapes`]).
    pub shape_a: usize,
    /// Second shape.
    pub shape_b: usize,
    /// The pair of links the two shapes belong to (index into [`CollisionModel::link_pairs`]).
    pub link_pair: usize,
}

/// A pair of links with at least one candidate shape pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LinkPair {
    /// The link whose shapes come first in shape order (index into `model.links()`).
    pub link_a: usize,
    /// The other link.
    pub link_b: usize,
}

/// A mesh that [`MissingMeshes::Skip`](crate::MissingMeshes::Skip) or
/// [`MeshMode::Ignore`](crate::MeshMode::Ignore) left out of the model.
#[derive(Clone, Debug, PartialEq)]
pub struct SkippedMesh {
    /// The link.
    pub link: String,
    /// Index of the `<collision>` element within the link.
    pub element: usize,
    /// The file name as written in the model.
    pub filename: String,
    /// Why it was left out (the error message, or "meshes ignored").
    pub reason: String,
}

/// One readable line: `mesh 'arm.stl' (link 'l', collision 0) left out: reason`.
impl core::fmt::Display for SkippedMesh {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "mesh '{}' (link '{}', collision {}) left out: {}",
            self.filename, self.link, self.element, self.reason
        )
    }
}

/// The collision shapes of a model and the pairs to test, after Pinocchio's `GeometryModel`.
///
/// Build it with [`CollisionModel::from_model`]; create a [`CollisionData`](crate::CollisionData)
/// for the queries. Shapes are ordered by link (the model's depth-first order), then by
/// `<collision>` element. Candidate pairs are every pair of shapes on different moving bodies
/// whose bodies are not parent and child, minus disabled link pairs (see
/// [`CollisionModel::from_model`]); they are sorted lexicographically by shape index.
#[derive(Clone, Debug)]
pub struct CollisionModel {
    pub(crate) shapes: Vec<CollisionShape>,
    pub(crate) pairs: Vec<CollisionPair>,
    /// `pairs[pair_start[a]..pair_start[a + 1]]` are the pairs whose first shape is `a`.
    pub(crate) pair_start: Vec<usize>,
    pub(crate) link_pairs: Vec<LinkPair>,
    pub(crate) skipped: Vec<SkippedMesh>,
    /// Parent body of every body of the model.
    pub(crate) body_parent: Vec<usize>,
    /// Disabled link pairs, as `(min, max)` link indices, sorted.
    pub(crate) disabled: Vec<(usize, usize)>,
    /// The pairs grouped by shape kinds for the distance query.
    pub(crate) plan: crate::plan::PairPlan,
    /// Relative tolerance of the distance queries' GJK/EPA.
    pub(crate) distance_tolerance: f64,
}

impl CollisionModel {
    /// Every collision shape.
    #[must_use]
    pub fn shapes(&self) -> &[CollisionShape] {
        &self.shapes
    }

    /// The shape with this name (`<link>_<k>`), if any.
    #[must_use]
    pub fn shape_index(&self, name: &str) -> Option<usize> {
        self.shapes.iter().position(|s| s.name == name)
    }

    /// The candidate shape pairs, sorted by `(shape_a, shape_b)`.
    #[must_use]
    pub fn pairs(&self) -> &[CollisionPair] {
        &self.pairs
    }

    /// The candidate pair of shapes `a` and `b` (in either order), if they are one.
    #[must_use]
    pub fn pair_index(&self, a: usize, b: usize) -> Option<usize> {
        let (a, b) = if a < b { (a, b) } else { (b, a) };
        let range = *self.pair_start.get(a)?..*self.pair_start.get(a + 1)?;
        let start = range.start;
        self.pairs[range]
            .binary_search_by_key(&b, |p| p.shape_b)
            .ok()
            .map(|k| start + k)
    }

    /// The link pairs with at least one candidate shape pair, in order of their first pair.
    #[must_use]
    pub fn link_pairs(&self) -> &[LinkPair] {
        &self.link_pairs
    }

    /// Meshes left out of the model (see [`MissingMeshes`](crate::MissingMeshes)).
    #[must_use]
    pub fn skipped_meshes(&self) -> &[SkippedMesh] {
        &self.skipped
    }

    /// The disabled link pairs, as sorted `(smaller, larger)` link indices.
    #[must_use]
    pub fn disabled_link_pairs(&self) -> &[(usize, usize)] {
        &self.disabled
    }

    /// The range [`set_distance_tolerance`](Self::set_distance_tolerance) accepts.
    pub const DISTANCE_TOLERANCE_RANGE: core::ops::RangeInclusive<f64> = 1e-12..=1e-3;

    /// The relative tolerance of the distance queries (1e-8 unless
    /// [`set_distance_tolerance`](Self::set_distance_tolerance) changed it).
    #[must_use]
    pub fn distance_tolerance(&self) -> f64 {
        self.distance_tolerance
    }

    /// Sets the relative tolerance `tol` at which the distance queries
    /// ([`compute_distances`](crate::compute_distances),
    /// [`compute_world_distances`](crate::compute_world_distances) and those built on them) stop
    /// the crate's GJK and EPA. The default is 1e-8; coal's (Pinocchio's) default is 1e-6,
    /// which is faster and less precise.
    ///
    /// What it bounds, for a reported signed distance `d` and the true one `d*`:
    /// - Separated pairs: GJK stops when the gap between its upper bound of the distance (the
    ///   length of the point `v` of its simplex nearest the origin) and its lower bound
    ///   (`v·w / |v|`, with `w` the support point of the shapes' difference along `-v`) is at
    ///   most `tol · |v|`, and reports the upper bound: `d - tol · d <= d* <= d`.
    /// - Overlapping pairs: EPA stops when the support point along the nearest face's normal is
    ///   within `tol · max(depth, 1e-3 m)` of that face, and reports the face's distance, a lower
    ///   bound of the depth: `d - tol · max(|d|, 1e-3 m) <= d* <= d`.
    ///
    /// So in both cases `0 <= d - d* <= tol · max(|d|, 1e-3 m)`, up to round-off.
    /// Pairs with a closed form (a sphere with any primitive, cylinders side by side) are exact
    /// up to round-off whatever `tol`; in the rare configurations where the crate's
    /// GJK/EPA do not settle (touching shapes, degenerate simplices), parry's GJK (relative
    /// tolerance about 5e-8) and EPA take over and `tol` does not apply.
    /// The collision queries ([`any_collision`](crate::any_collision) and the contact queries)
    /// do not use it.
    ///
    /// # Errors
    /// [`CollisionError::InvalidTolerance`](crate::CollisionError::InvalidTolerance) unless `tol`
    /// is finite and within [`Self::DISTANCE_TOLERANCE_RANGE`] (1e-12 to 1e-3); the model is then
    /// unchanged.
    pub fn set_distance_tolerance(&mut self, tol: f64) -> Result<(), crate::CollisionError> {
        if !Self::DISTANCE_TOLERANCE_RANGE.contains(&tol) {
            return Err(crate::CollisionError::InvalidTolerance { value: tol });
        }
        self.distance_tolerance = tol;
        Ok(())
    }

    /// Number of bodies of the model this collision model was built from.
    #[must_use]
    pub fn nbodies(&self) -> usize {
        self.body_parent.len()
    }
}
