//! Criterion benchmarks of the collision queries on panda_collision (39 primitive shapes, 513
//! candidate pairs), as Pinocchio + coal are measured in `shared/anchors/pinocchio/collision.md`:
//! every call includes forward kinematics and the shape placement update, over 200 random
//! configurations.
//!
//! The batched rows time the 200 states as one batch (divide by 200 for ns/state), on one core
//! and on every core.
//!
//! `cargo bench --bench collision`; compare runs with `--save-baseline` / `--baseline`.

use criterion::{Criterion, criterion_group, criterion_main};
use kinetree::collision::batch::{CollisionBatch, distances_batch};
use kinetree::collision::kinematics::KinematicsData;
use kinetree::collision::kinematics::configuration::random_configuration;
use kinetree::collision::{
    CollisionData, CollisionModel, CollisionOptions, any_collision, compute_distances,
    compute_self_collisions,
};
use kinetree::model::{Model, RootJoint};
use kinetree::parallel::{self as par, Parallel};
use rand::SeedableRng;
use std::hint::black_box;

fn collision(c: &mut Criterion) {
    let path = format!(
        "{}/tests/data/reference/urdf/panda_collision.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    let model = Model::from_urdf_file(&path, RootJoint::Fixed).expect("bundled reference URDF");
    let cmodel =
        CollisionModel::from_model(&model, &CollisionOptions::default()).expect("primitive shapes");
    let mut rng = rand::rngs::SmallRng::seed_from_u64(42);
    let qs: Vec<Vec<f64>> = (0..200)
        .map(|_| {
            let mut q = vec![0.0; model.nq()];
            random_configuration(&model, &mut rng, &mut q).expect("length nq");
            q
        })
        .collect();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % qs.len();
        &qs[i]
    };
    let mut group = c.benchmark_group("panda_collision");
    group.bench_function("collision_any", |b| {
        b.iter(|| {
            data.compute_placements(&model, &cmodel, &mut kinematics, black_box(next()))
                .expect("valid q");
            any_collision(&cmodel, &mut data).expect("same model")
        })
    });
    group.bench_function("collision_all", |b| {
        b.iter(|| {
            data.compute_placements(&model, &cmodel, &mut kinematics, black_box(next()))
                .expect("valid q");
            compute_self_collisions(&cmodel, &mut data)
                .expect("same model")
                .len()
        })
    });
    group.bench_function("collision_distances", |b| {
        b.iter(|| {
            data.compute_placements(&model, &cmodel, &mut kinematics, black_box(next()))
                .expect("valid q");
            compute_distances(&cmodel, &mut data)
                .expect("same model")
                .len()
        })
    });
    // The 200 states as one batch: ns per state is the time divided by 200.
    let flat: Vec<f64> = qs.iter().flatten().copied().collect();
    let mut batch = CollisionBatch::new(&model, &cmodel);
    let mut pool = Parallel::from_fn(rayon::current_num_threads(), |_| {
        CollisionBatch::new(&model, &cmodel)
    });
    let mut out = vec![0.0; qs.len() * cmodel.pairs().len()];
    group.bench_function("collision_distances_batch_200", |b| {
        b.iter(|| {
            distances_batch(&model, &cmodel, &mut batch, black_box(&flat), &mut out)
                .expect("valid states");
            out[0]
        })
    });
    group.bench_function("collision_distances_batch_200_parallel", |b| {
        b.iter(|| {
            par::distances_batch(&model, &cmodel, &mut pool, black_box(&flat), &mut out)
                .expect("valid states");
            out[0]
        })
    });
    group.finish();
}

criterion_group!(benches, collision);
criterion_main!(benches);
