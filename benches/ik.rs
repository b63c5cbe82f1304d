//! Criterion benchmarks of inverse kinematics: cold solves from random starts on the three arms
//! of the IK quality bar, warm solves (tracking: a start near the answer), a bounded single step,
//! and a three-target floating-base solve on talos.
//!
//! `cargo bench --bench ik`; `cargo xtask ik-report` gives the success rates and the
//! distribution of solve times.

use criterion::{Criterion, criterion_group, criterion_main};
use kinetree::kinematics::configuration::{neutral_configuration, random_configuration};
use kinetree::kinematics::ik::{IkParams, IkSolver, IkTarget};
use kinetree::kinematics::{FrameId, KinematicsData, forward_kinematics, update_frame_placements};
use kinetree::model::{Model, RootJoint};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use std::hint::black_box;

/// The arms of the quality bar and their end effectors.
const ARMS: [(&str, &str); 3] = [
    ("panda", "panda_hand_tcp"),
    ("ur5", "tool0"),
    ("kinova", "j2s6s200_end_effector"),
];

fn load(name: &str, root: RootJoint) -> Model {
    let path = format!(
        "{}/tests/data/reference/urdf/{name}.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    Model::from_urdf_file(&path, root).expect("bundled reference URDF")
}

/// `n` (targets at random configurations, a random start, a start near the answer).
fn cases(model: &Model, frames: &[FrameId], n: usize) -> Vec<(Vec<IkTarget>, Vec<f64>, Vec<f64>)> {
    let mut rng = SmallRng::seed_from_u64(7);
    let mut data = KinematicsData::new(model);
    (0..n)
        .map(|_| {
            let mut q = neutral_configuration(model);
            random_configuration(model, &mut rng, &mut q).expect("length nq");
            forward_kinematics(model, &mut data, &q).expect("valid q");
            update_frame_placements(model, &mut data).expect("same model");
            let targets = frames
                .iter()
                .map(|f| IkTarget::new(*f, *data.world_from(*f).unwrap()))
                .collect();
            let near: Vec<f64> = q.iter().map(|x| x + 0.02).collect();
            random_configuration(model, &mut rng, &mut q).expect("length nq");
            (targets, q, near)
        })
        .collect()
}

fn ik(c: &mut Criterion) {
    for (name, ee) in ARMS {
        let model = load(name, RootJoint::Fixed);
        let frame = FrameId::find(&model, ee).expect("end effector exists");
        let cases = cases(&model, &[frame], 200);
        let mut data = KinematicsData::new(&model);
        let mut solver = IkSolver::new(&model, IkParams::default());
        let mut one_step = IkSolver::new(
            &model,
            IkParams {
                max_iterations: 1,
                max_restarts: 0,
                ..IkParams::default()
            },
        );
        let mut group = c.benchmark_group(format!("ik_{name}"));
        let mut i = 0;
        let mut next = || {
            i = (i + 1) % cases.len();
            &cases[i]
        };
        group.bench_function("cold", |b| {
            b.iter(|| {
                let (t, q0, _) = next();
                solver
                    .solve_targets(&model, &mut data, t, black_box(q0))
                    .map(|r| r.iterations)
            })
        });
        group.bench_function("warm", |b| {
            b.iter(|| {
                let (t, _, near) = next();
                solver
                    .solve_targets(&model, &mut data, t, black_box(near))
                    .map(|r| r.iterations)
            })
        });
        group.bench_function("one_step", |b| {
            b.iter(|| {
                let (t, q0, _) = next();
                one_step
                    .solve_targets(&model, &mut data, t, black_box(q0))
                    .map(|r| r.iterations)
            })
        });
        group.finish();
    }
    let model = load("talos_reduced", RootJoint::Floating);
    let frames = [
        "left_sole_link",
        "right_sole_link",
        "gripper_left_base_link",
    ]
    .map(|n| FrameId::find(&model, n).expect("talos frame"));
    let cases = cases(&model, &frames, 50);
    let mut data = KinematicsData::new(&model);
    let mut solver = IkSolver::new(&model, IkParams::default());
    let q0 = neutral_configuration(&model);
    let mut i = 0;
    c.bench_function("ik_talos/feet_and_hand_from_neutral", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            solver
                .solve_targets(&model, &mut data, &cases[i].0, black_box(&q0))
                .map(|r| r.iterations)
        })
    });
}

criterion_group!(benches, ik);
criterion_main!(benches);
