//! The queries allocate nothing once the data exists: a counting global allocator for this test
//! binary counts allocations made by the current thread.

#![allow(
    unsafe_code,
    reason = "a counting global allocator has to implement GlobalAlloc"
)]

use crate::common::{panda, q_of};
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::kinematics::model::Geometry;
use kinetree_collision::kinematics::spatial::Se3;
use kinetree_collision::parry::math::Pose;
use kinetree_collision::{
    CollisionData, CollisionModel, CollisionOptions, any_collision, compute_distances,
    compute_self_collisions, compute_world_collisions, compute_world_distances,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: delegates every call unchanged to the system allocator; it only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

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
    let samples: Vec<_> = reference["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| q_of(&model, s))
        .collect();
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
