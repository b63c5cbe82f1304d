//! The error type of reachable-workspace sampling.

use kinetree_kinematics::KinematicsError;
use kinetree_kinematics::spatial::Readable;

/// What can go wrong while sampling a reachable workspace or querying it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReachableError {
    /// An error from the kinematics layer (unknown frame, wrong `q0` length, NaN in `q0`, …).
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
    /// The sampling asks for no samples at all.
    #[error("the sampling asks for no samples ({what} is 0)")]
    NoSamples {
        /// The parameter that is zero (`"samples"` or `"per_coordinate"`).
        what: &'static str,
    },
    /// The sampling asks for more than [`MAX_SAMPLES`](crate::MAX_SAMPLES) samples.
    #[error("{requested} samples exceed the limit of {limit}")]
    TooManySamples {
        /// The number asked for (saturated at `u128::MAX` for enormous grids).
        requested: u128,
        /// [`MAX_SAMPLES`](crate::MAX_SAMPLES).
        limit: usize,
    },
    /// A voxel size is zero, negative, NaN or infinite.
    #[error("voxel size {} is not a positive finite length", Readable(*size))]
    InvalidVoxelSize {
        /// The size given, in metres.
        size: f64,
    },
    /// A voxel size so large that the volume of the voxels overflows (or so small that one
    /// voxel's volume underflows to zero).
    #[error("voxel size {} m is out of range: the volume of the voxels is not a finite positive number", Readable(*size))]
    VoxelSizeOutOfRange {
        /// The size given, in metres.
        size: f64,
    },
    /// A voxel size is so small that voxel indices of the samples overflow.
    #[error(
        "voxel size {} m is too small for points {} m from the origin",
        Readable(*size),
        Readable(*distance)
    )]
    VoxelTooSmall {
        /// The size given, in metres.
        size: f64,
        /// The farthest coordinate that does not fit, in metres.
        distance: f64,
    },
    /// A query point is NaN or infinite.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which input.
        what: &'static str,
    },
}
