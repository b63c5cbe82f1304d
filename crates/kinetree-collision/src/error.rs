//! The collision layer's error type.

use kinetree_kinematics::KinematicsError;
use std::path::PathBuf;

/// Everything that can go wrong in the collision layer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CollisionError {
    /// An error from the kinematics (or model) layer.
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
    /// A state of a batch (see [`crate::batch`]) failed: `index` is the state's position in the
    /// batch and `source` says what was wrong with it.
    #[error("state {index} of the batch: {source}")]
    InBatchState {
        /// The state's index in the batch (0-based).
        index: usize,
        /// What went wrong with that state.
        #[source]
        source: Box<CollisionError>,
    },
    /// A mesh file named by a collision element was not found in any search path.
    #[error("mesh '{filename}' of link '{link}' not found (searched: {})", display_paths(.searched))]
    MeshNotFound {
        /// The link whose collision element names the mesh.
        link: String,
        /// The file name or URI as written in the model.
        filename: String,
        /// Every path tried, in order.
        searched: Vec<PathBuf>,
    },
    /// A mesh file exists but could not be read or parsed.
    #[error("mesh '{}': {reason}", .path.display())]
    MeshParse {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A collision element has a shape parry cannot represent (negative or non-finite sizes,
    /// sizes or mesh coordinates beyond [`MAX_SHAPE_SIZE`](crate::build::MAX_SHAPE_SIZE), an
    /// empty or degenerate mesh, an unsupported geometry for this call).
    #[error("collision element {index} of link '{link}': {reason}")]
    InvalidGeometry {
        /// The link (or obstacle) name.
        link: String,
        /// Index of the collision element within the link (0 for an obstacle).
        index: usize,
        /// Why.
        reason: String,
    },
    /// A world obstacle cannot be added: its shape is invalid (as [`Self::InvalidGeometry`] for a
    /// link) or its pose is not finite.
    #[error("obstacle '{name}': {reason}")]
    InvalidObstacle {
        /// The obstacle's name.
        name: String,
        /// Why.
        reason: String,
    },
    /// No link has this name (in an SRDF file, a disabled pair, …).
    #[error("unknown link '{name}'")]
    UnknownLink {
        /// The name looked up.
        name: String,
    },
    /// An SRDF document is not well-formed XML or misses a required attribute.
    #[error("SRDF, byte {position}: {message}")]
    Srdf {
        /// Byte offset in the document.
        position: u64,
        /// What is wrong.
        message: String,
    },
    /// An obstacle scene ([`ObstacleScene`](crate::ObstacleScene)) is not valid JSON, misses a
    /// field or has an unknown one.
    #[error("{message}")]
    InvalidScene {
        /// Line of the problem (1-based; 0 when unknown).
        line: usize,
        /// Column of the problem (1-based; 0 when unknown).
        column: usize,
        /// What is wrong, with its line and column.
        message: String,
    },
    /// A [`CollisionData`](crate::CollisionData) was created for another collision model.
    #[error(
        "the collision data was created for a collision model with {data_shapes} shapes and {data_pairs} pairs, not this one ({model_shapes} shapes, {model_pairs} pairs)"
    )]
    DataMismatch {
        /// Shapes of the data's model.
        data_shapes: usize,
        /// Candidate pairs of the data's model.
        data_pairs: usize,
        /// Shapes of the model passed in.
        model_shapes: usize,
        /// Candidate pairs of the model passed in.
        model_pairs: usize,
    },
    /// An obstacle id does not name a live obstacle of this data.
    #[error("unknown obstacle {id}")]
    UnknownObstacle {
        /// The index given.
        id: usize,
    },
    /// A shape index the collision model does not have.
    #[error("shape {index} is out of range (the model has {count} shapes)")]
    ShapeOutOfRange {
        /// The index given.
        index: usize,
        /// The number of shapes.
        count: usize,
    },
    /// A pose or size given at run time contains NaN or an infinity.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which input.
        what: &'static str,
    },
    /// A kinematics data does not belong to the model the collision model was built from.
    #[error(
        "the kinematics data has {data_bodies} bodies, the collision model was built for {model_bodies}"
    )]
    KinematicsMismatch {
        /// Bodies of the kinematics data.
        data_bodies: usize,
        /// Bodies of the collision model's model.
        model_bodies: usize,
    },
    /// A distance between two shapes is not finite although every input was: the shapes are
    /// placed so far out (a prismatic joint at 1e308 m, say) that the arithmetic overflows.
    #[error(
        "the distance between '{shape_a}' and '{shape_b}' overflowed: the shapes are placed beyond what double precision can measure"
    )]
    Overflow {
        /// Name of the first shape.
        shape_a: String,
        /// Name of the second shape (or obstacle).
        shape_b: String,
    },
    /// A distance tolerance (see
    /// [`CollisionModel::set_distance_tolerance`](crate::CollisionModel::set_distance_tolerance))
    /// that is not finite or is outside 1e-12 to 1e-3.
    #[error(
        "distance tolerance {value} is not a finite number between 1e-12 and 1e-3 (the default is 1e-8, coal's 1e-6)"
    )]
    InvalidTolerance {
        /// The value given.
        value: f64,
    },
    /// A query stopped on a panic inside a dependency (parry) instead of returning: a bug
    /// there, caught at the query's boundary. The query's results are not written; the
    /// collision data's buffers are reset, so the data (and the model) stay usable.
    #[error("the {query} query failed inside parry ({message}); the collision data was reset")]
    Panic {
        /// The query (`"compute_distances"`, …).
        query: &'static str,
        /// The panic's message.
        message: String,
    },
    /// parry cannot compute this query for this pair of shapes.
    #[error("parry does not support this query between '{shape_a}' and '{shape_b}'")]
    Unsupported {
        /// Name of the first shape.
        shape_a: String,
        /// Name of the second shape.
        shape_b: String,
    },
}

fn display_paths(paths: &[PathBuf]) -> String {
    if paths.is_empty() {
        return "no search path given".to_string();
    }
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
