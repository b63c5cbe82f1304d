//! What to sample: [`Sampling`], [`TaskSpace`] and [`ReachableParams`].

/// Samples per parallel task. Each task allocates its buffers once; the random generator of a
/// task is seeded from the seed and the task's index, which is what makes results independent of
/// the thread count.
pub const CHUNK_SIZE: usize = 1024;

/// The largest number of samples one call may ask for (about 2 GiB of results with
/// orientations); larger requests are refused with [`ReachableError::TooManySamples`](crate::ReachableError::TooManySamples).
pub const MAX_SAMPLES: usize = 1 << 25;

/// How configurations are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampling {
    /// The product of linspaces: `per_coordinate` evenly spaced values (end points included) on
    /// each sampled coordinate, `per_coordinate^d` samples in all. Sample `i` is the `i`-th
    /// combination in row-major order, the first joint varying slowest.
    Grid {
        /// Values per coordinate (at least 1; 1 takes the middle of each range).
        per_coordinate: usize,
    },
    /// `samples` configurations uniform within the ranges, from `seed`.
    Random {
        /// How many samples (at least 1).
        samples: usize,
        /// Seed of the generator; the same seed gives the same samples on any thread count.
        seed: u64,
    },
}

/// Which part of the frame's motion the manipulability measures, and whether orientations are
/// kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TaskSpace {
    /// Positions only: the 3 linear rows of the Jacobian; orientations are not stored.
    #[default]
    Position,
    /// Full pose: all 6 rows `[linear; angular]`; orientations are stored.
    Pose,
}

impl TaskSpace {
    /// Number of Jacobian rows used (3 or 6).
    #[must_use]
    pub fn rows(self) -> usize {
        match self {
            TaskSpace::Position => 3,
            TaskSpace::Pose => 6,
        }
    }

    /// Lower-case name (`"position"` or `"pose"`), as written in exports.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            TaskSpace::Position => "position",
            TaskSpace::Pose => "pose",
        }
    }
}

/// Parameters of [`sample_reachable`](crate::sample_reachable).
#[derive(Clone, Debug, PartialEq)]
pub struct ReachableParams {
    /// How configurations are drawn. Default: 100 000 random samples with seed 0.
    pub sampling: Sampling,
    /// Position only or full pose. Default: [`TaskSpace::Position`].
    pub task: TaskSpace,
    /// The configuration of the joints that are not sampled (length `model.nq()`); `None` means
    /// the neutral configuration.
    pub q0: Option<Vec<f64>>,
}

impl Default for ReachableParams {
    fn default() -> Self {
        Self::random(100_000, 0)
    }
}

impl ReachableParams {
    /// A grid of `per_coordinate` values on each sampled coordinate, position task.
    #[must_use]
    pub fn grid(per_coordinate: usize) -> Self {
        Self {
            sampling: Sampling::Grid { per_coordinate },
            task: TaskSpace::Position,
            q0: None,
        }
    }

    /// `samples` random configurations from `seed`, position task.
    #[must_use]
    pub fn random(samples: usize, seed: u64) -> Self {
        Self {
            sampling: Sampling::Random { samples, seed },
            task: TaskSpace::Position,
            q0: None,
        }
    }

    /// The same parameters with another task space.
    #[must_use]
    pub fn with_task(mut self, task: TaskSpace) -> Self {
        self.task = task;
        self
    }

    /// The same parameters holding the non-sampled joints at `q0` (length `model.nq()`).
    #[must_use]
    pub fn with_q0(mut self, q0: Vec<f64>) -> Self {
        self.q0 = Some(q0);
        self
    }
}
