//! [`VoxelMap`]: the voxels hit by the samples of a [`ReachableSet`](crate::ReachableSet).

use kinetree_kinematics::spatial::DVec3;
use std::collections::HashMap;

/// Voxel indices stay below this magnitude, so that they and their centres are exact in `f64`
/// and fit in `i64`.
pub(crate) const VOXEL_INDEX_LIMIT: f64 = (1u64 << 52) as f64;

/// What a [`VoxelMap`] knows about one voxel hit by samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelStats {
    /// Number of samples in the voxel (at least 1).
    pub count: usize,
    /// The largest manipulability of those samples.
    pub max_manipulability: f64,
    /// The mean manipulability of those samples.
    pub mean_manipulability: f64,
}

/// The voxels hit by the samples of a [`ReachableSet`](crate::ReachableSet) (built by [`ReachableSet::voxelize`](crate::ReachableSet::voxelize)).
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelMap {
    pub(crate) size: f64,
    pub(crate) cells: HashMap<[i64; 3], VoxelStats>,
}

impl VoxelMap {
    /// The side of a voxel, in metres.
    #[must_use]
    pub fn voxel_size(&self) -> f64 {
        self.size
    }

    /// Number of voxels hit.
    #[must_use]
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether no voxel was hit (never true for a map built from a [`ReachableSet`](crate::ReachableSet)).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The volume of the voxels hit, in m³: an estimate of the reachable volume (exact as the
    /// sampling gets denser and the voxels smaller, for a solid workspace).
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.cells.len() as f64 * self.size.powi(3)
    }

    /// The index `(⌊x/s⌋, ⌊y/s⌋, ⌊z/s⌋)` of the voxel holding `point`, or `None` for a point
    /// with a NaN or infinite coordinate or too far from the origin for the index to fit.
    #[must_use]
    pub fn index_of(&self, point: DVec3) -> Option<[i64; 3]> {
        let i = (point / self.size).floor();
        if !(i.is_finite() && i.abs().max_element() < VOXEL_INDEX_LIMIT) {
            return None;
        }
        // Exact: `i` holds integers below 2^52 in magnitude.
        Some([i.x as i64, i.y as i64, i.z as i64])
    }

    /// The centre of voxel `index`, in metres.
    #[must_use]
    pub fn center_of(&self, index: [i64; 3]) -> DVec3 {
        (DVec3::new(index[0] as f64, index[1] as f64, index[2] as f64) + 0.5) * self.size
    }

    /// Whether the voxel holding `point` was hit by a sample (false for a non-finite point).
    #[must_use]
    pub fn is_reachable(&self, point: DVec3) -> bool {
        self.stats_at(point).is_some()
    }

    /// What is known about the voxel holding `point`, if it was hit.
    #[must_use]
    pub fn stats_at(&self, point: DVec3) -> Option<&VoxelStats> {
        self.index_of(point).and_then(|k| self.cells.get(&k))
    }

    /// Every voxel hit with its statistics, sorted by index (x, then y, then z).
    #[must_use]
    pub fn voxels(&self) -> Vec<([i64; 3], VoxelStats)> {
        let mut v: Vec<_> = self.cells.iter().map(|(k, s)| (*k, *s)).collect();
        v.sort_unstable_by_key(|(k, _)| *k);
        v
    }
}
