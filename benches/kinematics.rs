//! Criterion benchmarks of the kinematics hot paths on real robots: forward kinematics (all
//! links), FK + named frames, one frame Jacobian, all joint Jacobians.
//!
//! `cargo bench --bench kinematics`; compare runs with `--save-baseline` / `--baseline`.

use criterion::{Criterion, criterion_group, criterion_main};
use kinetree::kinematics::configuration::random_configuration;
use kinetree::kinematics::spatial::Motion;
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, compute_joint_jacobians,
    forward_kinematics, update_frame_placements,
};
use kinetree::model::{Model, RootJoint};
use rand::SeedableRng;
use std::hint::black_box;

/// The robots of the anchors, with the frame whose Jacobian is timed.
const ROBOTS: [(&str, RootJoint, &str); 4] = [
    ("panda", RootJoint::Fixed, "panda_hand_tcp"),
    ("ur5", RootJoint::Fixed, "tool0"),
    ("solo12", RootJoint::Floating, "FL_FOOT"),
    ("talos_reduced", RootJoint::Floating, "left_sole_link"),
];

fn load(name: &str, root: RootJoint) -> Model {
    let path = format!(
        "{}/tests/data/reference/urdf/{name}.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    Model::from_urdf_file(&path, root).expect("bundled reference URDF")
}

fn states(model: &Model) -> Vec<Vec<f64>> {
    let mut rng = rand::rngs::SmallRng::seed_from_u64(42);
    (0..1000)
        .map(|_| {
            let mut q = vec![0.0; model.nq()];
            random_configuration(model, &mut rng, &mut q).expect("length nq");
            q
        })
        .collect()
}

fn kinematics(c: &mut Criterion) {
    for (name, root, frame_name) in ROBOTS {
        let model = load(name, root);
        let qs = states(&model);
        let mut data = KinematicsData::new(&model);
        let frame = FrameId::find(&model, frame_name).expect("frame exists");
        let mut jac = vec![Motion::ZERO; model.nv()];
        let mut group = c.benchmark_group(name);
        let mut i = 0;
        let mut next = || {
            i = (i + 1) % qs.len();
            &qs[i]
        };
        group.bench_function("fk", |b| {
            b.iter(|| forward_kinematics(&model, &mut data, black_box(next())))
        });
        group.bench_function("fk_frames", |b| {
            b.iter(|| {
                forward_kinematics(&model, &mut data, black_box(next()))
                    .and_then(|()| update_frame_placements(&model, &mut data))
            })
        });
        group.bench_function("frame_jacobian", |b| {
            b.iter(|| {
                compute_frame_jacobian(
                    &model,
                    &mut data,
                    black_box(next()),
                    frame,
                    ReferenceFrame::LocalWorldAligned,
                    &mut jac,
                )
            })
        });
        group.bench_function("joint_jacobians", |b| {
            b.iter(|| compute_joint_jacobians(&model, &mut data, black_box(next())))
        });
        group.finish();
    }
}

criterion_group!(benches, kinematics);
criterion_main!(benches);
