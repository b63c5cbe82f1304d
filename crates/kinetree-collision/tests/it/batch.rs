//! The batched distances equal the one-state path, state by state, and bad batches are errors
//! naming what is wrong.

use crate::common::{panda, stacked_samples};
use kinetree_collision::batch::{CollisionBatch, distances_batch, min_distance_batch};
use kinetree_collision::kinematics::{KinematicsData, KinematicsError};
use kinetree_collision::{
    CollisionData, CollisionError, CollisionModel, CollisionOptions, compute_distances,
};

#[test]
fn batched_distances_equal_the_one_state_path() {
    let (reference, model) = panda();
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let q: Vec<f64> = stacked_samples(&reference, &model);
    let (nq, np) = (model.nq(), cmodel.pairs().len());
    let n = q.len() / nq;
    assert!(n >= 5 && np == 513);
    let mut batch = CollisionBatch::new(&model, &cmodel);
    let mut distances = vec![f64::NAN; n * np];
    let mut min = vec![f64::NAN; n];
    distances_batch(&model, &cmodel, &mut batch, &q, &mut distances).unwrap();
    min_distance_batch(&model, &cmodel, &mut batch, &q, &mut min).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    for k in 0..n {
        data.compute_placements(&model, &cmodel, &mut kinematics, &q[k * nq..(k + 1) * nq])
            .unwrap();
        let one = compute_distances(&cmodel, &mut data).unwrap();
        for (p, d) in one.iter().zip(&distances[k * np..(k + 1) * np]) {
            assert_eq!(p.distance.to_bits(), d.to_bits(), "state {k}");
        }
        let closest = one.iter().map(|p| p.distance).fold(f64::INFINITY, f64::min);
        assert_eq!(closest.to_bits(), min[k].to_bits(), "state {k}");
    }
    // The minimum is a pair's distance (the samples' spheres at the elbow overlap).
    assert!(min.iter().all(|d| d.is_finite()) && min.iter().any(|d| *d < 0.0));
}

#[test]
fn bad_batches_are_errors_naming_the_problem() {
    let (_, model) = panda();
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let mut batch = CollisionBatch::new(&model, &cmodel);
    let nq = model.nq();
    let np = cmodel.pairs().len();
    // Three states, room for two.
    let q = vec![0.1; 3 * nq];
    let mut two = vec![0.0; 2 * np];
    match distances_batch(&model, &cmodel, &mut batch, &q, &mut two) {
        Err(CollisionError::Kinematics(KinematicsError::DimensionMismatch {
            what: "distances",
            expected,
            actual,
        })) => assert_eq!((expected, actual), (3 * np, 2 * np)),
        other => panic!("{other:?}"),
    }
    // A partial state.
    let mut min = vec![0.0; 3];
    assert!(matches!(
        min_distance_batch(&model, &cmodel, &mut batch, &q[..3 * nq - 1], &mut min),
        Err(CollisionError::Kinematics(
            KinematicsError::DimensionMismatch { what: "q", .. }
        ))
    ));
    // A non-finite state is named by its index.
    let mut bad = q.clone();
    bad[2 * nq + 1] = f64::NAN;
    match min_distance_batch(&model, &cmodel, &mut batch, &bad, &mut min) {
        Err(CollisionError::InBatchState { index: 2, source }) => {
            assert!(
                matches!(*source, CollisionError::Kinematics(_)),
                "{source:?}"
            );
        }
        other => panic!("{other:?}"),
    }
    // The states before it were computed.
    assert!(min[0].is_finite() && min[1].is_finite());
}
