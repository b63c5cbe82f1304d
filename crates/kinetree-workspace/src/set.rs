//! [`ReachableSet`], the samples, and what is computed from them: [`Bounds`], the maximum
//! reach and the voxel map.

use crate::voxel::VOXEL_INDEX_LIMIT;
use crate::{ReachableError, Sampling, TaskSpace, VoxelMap, VoxelStats};
use kinetree_kinematics::spatial::{DQuat, DVec3};
use std::collections::HashMap;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Smallest x, y and z.
    pub min: DVec3,
    /// Largest x, y and z.
    pub max: DVec3,
}

impl Bounds {
    /// `max - min`.
    #[must_use]
    pub fn size(&self) -> DVec3 {
        self.max - self.min
    }

    /// The middle of the box.
    #[must_use]
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Whether `p` is inside the box or on its boundary (false for NaN).
    #[must_use]
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// Samples of the poses a frame reaches, with their manipulability (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ReachableSet {
    pub(crate) frame: String,
    pub(crate) task: TaskSpace,
    pub(crate) sampling: Sampling,
    pub(crate) joints: Vec<String>,
    pub(crate) positions: Vec<DVec3>,
    pub(crate) orientations: Vec<DQuat>,
    pub(crate) manipulability: Vec<f64>,
    pub(crate) bounds: Bounds,
}

impl ReachableSet {
    /// Number of samples (never 0).
    #[must_use]
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Always false: a set holds at least one sample. Present for API symmetry.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Name of the sampled link or frame.
    #[must_use]
    pub fn frame_name(&self) -> &str {
        &self.frame
    }

    /// The task space used for the manipulability (and whether orientations were kept).
    #[must_use]
    pub fn task(&self) -> TaskSpace {
        self.task
    }

    /// The sampling that produced the set.
    #[must_use]
    pub fn sampling(&self) -> Sampling {
        self.sampling
    }

    /// Names of the sampled joints, root first (the joints on the frame's path, less floating
    /// joints).
    #[must_use]
    pub fn joints(&self) -> &[String] {
        &self.joints
    }

    /// World position of the frame origin at each sample.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// World orientation of the frame at each sample with [`TaskSpace::Pose`]; `None` with
    /// [`TaskSpace::Position`].
    #[must_use]
    pub fn orientations(&self) -> Option<&[DQuat]> {
        match self.task {
            TaskSpace::Position => None,
            TaskSpace::Pose => Some(&self.orientations),
        }
    }

    /// The manipulability index at each sample (see the module docs).
    #[must_use]
    pub fn manipulability(&self) -> &[f64] {
        &self.manipulability
    }

    /// The axis-aligned box of all sampled positions.
    #[must_use]
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// The largest distance from `base` to a sampled position (e.g. from the shoulder of an
    /// arm).
    ///
    /// # Errors
    /// [`ReachableError::NonFinite`] when `base` has a NaN or infinite coordinate.
    pub fn max_reach(&self, base: DVec3) -> Result<f64, ReachableError> {
        if !base.is_finite() {
            return Err(ReachableError::NonFinite { what: "base" });
        }
        Ok(self
            .positions
            .iter()
            .map(|p| p.distance(base))
            .fold(0.0, f64::max))
    }

    /// Bins the sampled positions into cubic voxels of side `voxel_size` (metres) on a grid
    /// anchored at the world origin: voxel `(i, j, k)` covers `[i·s, (i+1)·s) x …`. Each voxel
    /// hit by at least one sample records its sample count and the maximum and mean
    /// manipulability of those samples.
    ///
    /// # Errors
    /// [`ReachableError::InvalidVoxelSize`] when `voxel_size` is not positive and finite,
    /// [`ReachableError::VoxelSizeOutOfRange`] when the voxels' volume would not be a finite
    /// positive number (`1e308`), [`ReachableError::VoxelTooSmall`] when voxel indices would
    /// overflow.
    ///
    /// # Examples
    /// ```
    /// use kinetree_workspace::kinematics::FrameId;
    /// use kinetree_workspace::{ReachableError, ReachableParams, sample_reachable};
    /// use kinetree_workspace::kinematics::model::samples;
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// let model = samples::planar_2r(1.0, 1.0);
    /// let set = sample_reachable(&model, FrameId::find(&model, "tool")?, &ReachableParams::grid(50))?;
    /// assert!(matches!(set.voxelize(0.0), Err(ReachableError::InvalidVoxelSize { .. })));
    /// assert!(matches!(set.voxelize(1e308), Err(ReachableError::VoxelSizeOutOfRange { .. })));
    /// let voxels = set.voxelize(0.1)?;
    /// assert!(voxels.len() > 100);
    /// # Ok(())
    /// # }
    /// ```
    pub fn voxelize(&self, voxel_size: f64) -> Result<VoxelMap, ReachableError> {
        if !(voxel_size.is_finite() && voxel_size > 0.0) {
            return Err(ReachableError::InvalidVoxelSize { size: voxel_size });
        }
        // The volume is at most one voxel per sample: it must be finite, and a voxel's positive.
        let cell = voxel_size.powi(3);
        if !(cell > 0.0 && (cell * self.positions.len().max(1) as f64).is_finite()) {
            return Err(ReachableError::VoxelSizeOutOfRange { size: voxel_size });
        }
        let far = self
            .bounds
            .min
            .abs()
            .max(self.bounds.max.abs())
            .max_element();
        if far / voxel_size >= VOXEL_INDEX_LIMIT {
            return Err(ReachableError::VoxelTooSmall {
                size: voxel_size,
                distance: far,
            });
        }
        let mut map = VoxelMap {
            size: voxel_size,
            cells: HashMap::new(),
        };
        for (p, &w) in self.positions.iter().zip(&self.manipulability) {
            let Some(key) = map.index_of(*p) else {
                continue;
            };
            let cell = map.cells.entry(key).or_insert(VoxelStats {
                count: 0,
                max_manipulability: f64::NEG_INFINITY,
                mean_manipulability: 0.0,
            });
            cell.count += 1;
            cell.max_manipulability = cell.max_manipulability.max(w);
            // Running sum for now; divided by the count below.
            cell.mean_manipulability += w;
        }
        for cell in map.cells.values_mut() {
            cell.mean_manipulability /= cell.count as f64;
        }
        Ok(map)
    }
}
