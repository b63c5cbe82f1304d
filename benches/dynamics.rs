//! Criterion benchmarks of the dynamics hot paths on real robots: inverse dynamics (`rnea`),
//! nonlinear effects (`nle`), the mass matrix (`crba`), forward dynamics (`aba`, and through the
//! mass matrix: `fd_crb`) and the inverse mass matrix (`minv`).
//!
//! As in the Pinocchio anchors (`shared/anchors/pinocchio`), each call takes the next of 1000
//! random states (in-limit `q`, `v`, `a`, `tau` uniform in [-1, 1]), and the joints' damping,
//! friction and armature are off (Pinocchio's algorithms ignore them).
//!
//! `cargo bench --bench dynamics`; compare runs with `--save-baseline` / `--baseline`.

use criterion::{Criterion, criterion_group, criterion_main};
use kinetree::dynamics::exudyn::forward_dynamics_crb;
use kinetree::dynamics::{
    DynamicsData, JointTerms, aba, crba, mass_matrix_inverse, nonlinear_effects, rnea,
};
use kinetree::kinematics::configuration::random_configuration;
use kinetree::model::{Model, RootJoint};
use rand::{Rng, SeedableRng};
use std::hint::black_box;

const ROBOTS: [(&str, RootJoint); 4] = [
    ("panda", RootJoint::Fixed),
    ("ur5", RootJoint::Fixed),
    ("solo12", RootJoint::Floating),
    ("talos_reduced", RootJoint::Floating),
];

fn load(name: &str, root: RootJoint) -> Model {
    let path = format!(
        "{}/tests/data/reference/urdf/{name}.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    Model::from_urdf_file(&path, root).expect("bundled reference URDF")
}

/// One random state: `q` within the limits, `v`, `a` (also used as `tau`) in [-1, 1].
struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

fn states(model: &Model) -> Vec<State> {
    let mut rng = rand::rngs::SmallRng::seed_from_u64(42);
    (0..1000)
        .map(|_| {
            let mut q = vec![0.0; model.nq()];
            random_configuration(model, &mut rng, &mut q).expect("length nq");
            let mut uniform = || {
                (0..model.nv())
                    .map(|_| rng.random_range(-1.0..1.0))
                    .collect::<Vec<f64>>()
            };
            let v = uniform();
            let a = uniform();
            State { q, v, a }
        })
        .collect()
}

fn dynamics(c: &mut Criterion) {
    for (name, root) in ROBOTS {
        let model = load(name, root);
        let all = states(&model);
        let mut data = DynamicsData::with_joint_terms(&model, JointTerms::Ignored);
        let mut group = c.benchmark_group(name);
        let mut i = 0;
        let mut next = || {
            i = (i + 1) % all.len();
            &all[i]
        };
        group.bench_function("rnea", |b| {
            b.iter(|| {
                let s = black_box(next());
                rnea(&model, &mut data, &s.q, &s.v, &s.a).map(|t| t[0])
            })
        });
        group.bench_function("nle", |b| {
            b.iter(|| {
                let s = black_box(next());
                nonlinear_effects(&model, &mut data, &s.q, &s.v).map(|t| t[0])
            })
        });
        group.bench_function("crba", |b| {
            b.iter(|| {
                let s = black_box(next());
                crba(&model, &mut data, &s.q).map(|m| m[0])
            })
        });
        group.bench_function("aba", |b| {
            b.iter(|| {
                let s = black_box(next());
                aba(&model, &mut data, &s.q, &s.v, &s.a).map(|x| x[0])
            })
        });
        group.bench_function("fd_crb", |b| {
            b.iter(|| {
                let s = black_box(next());
                forward_dynamics_crb(&model, &mut data, &s.q, &s.v, Some(&s.a), None).map(|x| x[0])
            })
        });
        group.bench_function("minv", |b| {
            b.iter(|| {
                let s = black_box(next());
                mass_matrix_inverse(&model, &mut data, &s.q).map(|m| m[0])
            })
        });
        group.finish();
    }
}

criterion_group!(benches, dynamics);
criterion_main!(benches);
