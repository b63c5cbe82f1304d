//! The queries allocate nothing once the data exists: a counting global allocator for this test
//! binary (`kinetree-test-support`) counts allocations made by the current thread.

use crate::common::{panda, sample_states, stacked_samples};
use kinetree_collision::batch::{CollisionBatch, distances_batch, min_distance_batch};
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::kinematics::model::Geometry;
use kinetree_collision::kinematics::spatial::Se3;
use kinetree_collision::parry::math::Pose;
use kinetree_collision::{
    CollisionData, CollisionModel, CollisionOptions, any_collision, compute_distances,
    compute_self_collisions, compute_world_collisions, compute_world_distances,
};
use kinetree_test_support::{CountingAllocator, allocations_during};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn queries_do_not_allocate() {
    let (reference, model) = panda();
    let options = CollisionOptions::default();
    let cmodel = CollisionModel::from_model(&model, &options).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let table = data
        .add_obstacle(
            "table",
            &Geometry::Box {
                size: [1.0, 1.0, 0.1],
            },
            &Se3::IDENTITY,
            &options,
        )
        .unwrap();
    let samples = sample_states(&reference, &model);
    let mut run = |data: &mut CollisionData| {
        for (k, q) in samples.iter().enumerate() {
            data.compute_placements(&model, &cmodel, &mut kinematics, q)
                .unwrap();
            data.set_obstacle_pose(table, &Pose::translation(0.0, 0.0, 0.01 * k as f64))
                .unwrap();
            any_collision(&cmodel, data).unwrap();
            compute_self_collisions(&cmodel, data).unwrap();
            compute_world_collisions(&cmodel, data).unwrap();
            compute_distances(&cmodel, data).unwrap();
            compute_world_distances(&cmodel, data).unwrap();
        }
    };
    // Warm-up: parry's EPA buffers (reused afterwards) grow on the first penetrating convex
    // pairs.
    run(&mut data);
    let count = allocations_during(|| run(&mut data));
    assert_eq!(count, 0, "the collision queries allocated");
}

#[test]
fn batched_queries_do_not_allocate() {
    let (reference, model) = panda();
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let q: Vec<f64> = stacked_samples(&reference, &model);
    let n = q.len() / model.nq();
    let mut batch = CollisionBatch::new(&model, &cmodel);
    let mut distances = vec![0.0; n * cmodel.pairs().len()];
    let mut min = vec![0.0; n];
    let mut run = |batch: &mut CollisionBatch| {
        distances_batch(&model, &cmodel, batch, &q, &mut distances).unwrap();
        min_distance_batch(&model, &cmodel, batch, &q, &mut min).unwrap();
    };
    // Warm-up: the EPA buffers grow on the first penetrating pairs.
    run(&mut batch);
    let count = allocations_during(|| run(&mut batch));
    assert_eq!(count, 0, "the batched collision queries allocated");
}
