//! The distance tolerance: the default is the previous fixed 1e-8, a coarser one moves every
//! distance by no more than its stopping rule allows, and bad values are typed errors.

use crate::common::{panda, q_of};
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::kinematics::configuration::random_configuration;
use kinetree_collision::{
    CollisionData, CollisionError, CollisionModel, CollisionOptions, compute_distances,
};
use rand::SeedableRng;

/// The distances of every pair at `q`, with `cmodel`'s tolerance.
fn distances(
    model: &kinetree_collision::kinematics::model::Model,
    cmodel: &CollisionModel,
    q: &[f64],
) -> Vec<f64> {
    let mut kinematics = KinematicsData::new(model);
    let mut data = CollisionData::new(cmodel);
    data.compute_placements(model, cmodel, &mut kinematics, q)
        .unwrap();
    compute_distances(cmodel, &mut data)
        .unwrap()
        .iter()
        .map(|p| p.distance)
        .collect()
}

#[test]
fn the_default_is_1e_8_and_setting_it_changes_nothing() {
    let (reference, model) = panda();
    let default = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    assert_eq!(default.distance_tolerance(), 1e-8);
    let mut explicit = default.clone();
    explicit.set_distance_tolerance(1e-8).unwrap();
    // A data last used at another tolerance takes the model's again.
    let mut coarse = default.clone();
    coarse.set_distance_tolerance(1e-6).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&default);
    for s in reference["samples"].as_array().unwrap() {
        let q = q_of(&model, s);
        let ours = distances(&model, &default, &q);
        data.compute_placements(&model, &coarse, &mut kinematics, &q)
            .unwrap();
        compute_distances(&coarse, &mut data).unwrap();
        let again: Vec<f64> = compute_distances(&explicit, &mut data)
            .unwrap()
            .iter()
            .map(|p| p.distance)
            .collect();
        assert_eq!(ours.len(), 513);
        for (a, b) in ours.iter().zip(&again) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }
}

#[test]
fn a_coarser_tolerance_stays_within_its_bound() {
    let (_, model) = panda();
    let fine = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let mut coarse = fine.clone();
    coarse.set_distance_tolerance(1e-6).unwrap();
    let mut rng = rand::rngs::SmallRng::seed_from_u64(7);
    let (mut moved, mut largest) = (0, 0.0_f64);
    let mut q = vec![0.0; model.nq()];
    for _ in 0..200 {
        random_configuration(&model, &mut rng, &mut q).unwrap();
        let d8 = distances(&model, &fine, &q);
        let d6 = distances(&model, &coarse, &q);
        for (k, (&a, &b)) in d8.iter().zip(&d6).enumerate() {
            // The stopping rule bounds each result: d - tol·max(|d|, 1e-3) <= d* <= d for the
            // true distance d*, so the two intervals meet. 1e-12 m covers round-off.
            let slack = |d: f64, tol: f64| tol * d.abs().max(1e-3) + 1e-12;
            assert!(
                b - slack(b, 1e-6) <= a + 1e-12 && a - slack(a, 1e-8) <= b + 1e-12,
                "pair {k}: {a} at 1e-8, {b} at 1e-6"
            );
            moved += usize::from(a != b);
            largest = largest.max((a - b).abs());
        }
    }
    // The setting is used: some distances change.
    assert!(
        moved > 0 && largest > 1e-10,
        "{moved} moved, largest {largest}"
    );
}

#[test]
fn bad_tolerances_are_errors() {
    let (_, model) = panda();
    let mut cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    for bad in [0.0, -1e-6, 1e-13, 2e-3, 1.0, f64::NAN, f64::INFINITY] {
        match cmodel.set_distance_tolerance(bad) {
            Err(e @ CollisionError::InvalidTolerance { value }) => {
                assert!(value.to_bits() == bad.to_bits());
                assert!(e.to_string().contains(&format!("{bad}")), "{e}");
            }
            other => panic!("{bad}: {other:?}"),
        }
        assert_eq!(cmodel.distance_tolerance(), 1e-8);
    }
    for good in [1e-12, 1e-6, 1e-3] {
        cmodel.set_distance_tolerance(good).unwrap();
        assert_eq!(cmodel.distance_tolerance(), good);
    }
}
