//! Batched signed distances: `N` configurations in one call, into buffers the caller owns.
//!
//! The states are stored one after another: `q` holds `N · model.nq()` numbers, state `k` at
//! `q[k·nq..(k+1)·nq]`. [`distances_batch`] writes `N · npairs` signed distances, state `k`'s at
//! `distances[k·npairs..(k+1)·npairs]` in the order of [`CollisionModel::pairs`];
//! [`min_distance_batch`] writes the smallest of them per state. A [`CollisionBatch`] holds the
//! one-state buffers; after [`CollisionBatch::new`] nothing allocates. Each state runs forward
//! kinematics, the placement update and the distance query of the one-state path, so the
//! results are the one-state results exactly. For all cores, `kinetree::parallel` splits a
//! batch over a rayon pool with the same signatures.
//!
//! # Examples
//! ```
//! use kinetree_collision::batch::{CollisionBatch, distances_batch, min_distance_batch};
//! use kinetree_collision::{CollisionModel, CollisionOptions};
//! use kinetree_collision::kinematics::model::{Model, RootJoint};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let path = concat!(env!("CARGO_MANIFEST_DIR"),
//!                    "/../../tests/data/reference/urdf/panda_collision.urdf");
//! let model = Model::from_urdf_file(path, RootJoint::Fixed)?;
//! let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default())?;
//! let mut batch = CollisionBatch::new(&model, &cmodel);
//! // Two states: the neutral one and the elbow (panda_joint4) bent.
//! let mut q = vec![0.0; 2 * model.nq()];
//! q[model.nq() + 3] = -1.5;
//! let mut distances = vec![0.0; 2 * cmodel.pairs().len()];
//! distances_batch(&model, &cmodel, &mut batch, &q, &mut distances)?;
//! let mut closest = [0.0; 2];
//! min_distance_batch(&model, &cmodel, &mut batch, &q, &mut closest)?;
//! // At q = 0 the forearm folds onto the upper arm; bending the elbow unfolds it.
//! assert!(closest[0] < 0.0 && closest[1] > closest[0]);
//! # Ok(())
//! # }
//! ```

use crate::data::CollisionData;
use crate::error::CollisionError;
use crate::model::CollisionModel;
use crate::query::compute_distances;
use kinetree_kinematics::batch::batch_size;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::{KinematicsData, KinematicsError};

/// The buffers of the batched distance queries for one [`Model`] and [`CollisionModel`] (see
/// the [module](self) docs).
///
/// Create it once per model (and per thread); the batched functions allocate nothing
/// afterwards. Obstacles are not part of the batched queries.
#[derive(Clone, Debug)]
pub struct CollisionBatch {
    kinematics: KinematicsData,
    data: CollisionData,
}

impl CollisionBatch {
    /// Allocates every buffer for `model` and `cmodel`.
    #[must_use]
    pub fn new(model: &Model, cmodel: &CollisionModel) -> Self {
        Self {
            kinematics: KinematicsData::new(model),
            data: CollisionData::new(cmodel),
        }
    }

    /// The one-state buffers, holding the placements and distances of the batch's last state.
    #[must_use]
    pub fn data(&self) -> &CollisionData {
        &self.data
    }
}

/// The number of states of a batch with `q_len` configuration numbers and `out_len` results of
/// `per_state` each, checking that both agree.
fn states(
    model: &Model,
    q_len: usize,
    out: &'static str,
    out_len: usize,
    per_state: usize,
) -> Result<usize, CollisionError> {
    let nq = model.nq();
    let n = if nq > 0 {
        batch_size("q", q_len, nq)?
    } else {
        batch_size(out, out_len, per_state)?
    };
    for (what, expected, actual) in [("q", n * nq, q_len), (out, n * per_state, out_len)] {
        if expected != actual {
            return Err(KinematicsError::DimensionMismatch {
                what,
                expected,
                actual,
            }
            .into());
        }
    }
    Ok(n)
}

/// Forward kinematics, placements and the signed distances of every candidate pair for state
/// `k` of the batch (`q` its configuration), with an error naming the state.
fn one_state(
    model: &Model,
    cmodel: &CollisionModel,
    batch: &mut CollisionBatch,
    q: &[f64],
    k: usize,
) -> Result<(), CollisionError> {
    let in_state = |e: CollisionError| match e {
        // Model mismatches are not about the state.
        e @ (CollisionError::DataMismatch { .. } | CollisionError::KinematicsMismatch { .. }) => e,
        e => CollisionError::InBatchState {
            index: k,
            source: Box::new(e),
        },
    };
    batch
        .data
        .compute_placements(model, cmodel, &mut batch.kinematics, q)
        .map_err(in_state)?;
    compute_distances(cmodel, &mut batch.data).map_err(in_state)?;
    Ok(())
}

/// The signed distance of every candidate pair (as [`compute_distances`]) for each state of
/// `q`: `distances` has `N · cmodel.pairs().len()` entries, state by state, in pair order.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] (wrapped) when the lengths of `q` and `distances` do
/// not describe the same number of states; [`CollisionError::DataMismatch`] or
/// [`CollisionError::KinematicsMismatch`] when `batch` was made for another model;
/// [`CollisionError::InBatchState`] naming the first state whose configuration or distances
/// fail (as in the one-state path). The results of the states before it are written.
pub fn distances_batch(
    model: &Model,
    cmodel: &CollisionModel,
    batch: &mut CollisionBatch,
    q: &[f64],
    distances: &mut [f64],
) -> Result<(), CollisionError> {
    let (nq, np) = (model.nq(), cmodel.pairs.len());
    let n = states(model, q.len(), "distances", distances.len(), np)?;
    for k in 0..n {
        one_state(model, cmodel, batch, &q[k * nq..(k + 1) * nq], k)?;
        let out = &mut distances[k * np..(k + 1) * np];
        for (d, p) in out.iter_mut().zip(&batch.data.distances) {
            *d = p.distance;
        }
    }
    Ok(())
}

/// The smallest signed distance over the candidate pairs for each state of `q` (`min` has `N`
/// entries; `+∞` for a model without candidate pairs): the robot's clearance, negative when it
/// is in self-collision.
///
/// # Errors
/// As [`distances_batch`], with `min` in place of `distances`.
pub fn min_distance_batch(
    model: &Model,
    cmodel: &CollisionModel,
    batch: &mut CollisionBatch,
    q: &[f64],
    min: &mut [f64],
) -> Result<(), CollisionError> {
    let nq = model.nq();
    let n = states(model, q.len(), "min", min.len(), 1)?;
    for k in 0..n {
        one_state(model, cmodel, batch, &q[k * nq..(k + 1) * nq], k)?;
        min[k] = batch
            .data
            .distances
            .iter()
            .map(|p| p.distance)
            .fold(f64::INFINITY, f64::min);
    }
    Ok(())
}
