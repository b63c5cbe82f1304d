//! Criterion benchmarks of the batched entry points beside the one-state path: forward
//! kinematics (every link), one frame's Jacobian, RNEA, ABA, CRBA and the RNEA derivatives of
//! 1024 random states,
//! evaluated one state at a time (`one_state`), batched on one core (`batched`, SIMD lanes) and
//! batched on every thread of rayon's pool (`parallel`). Throughput is in states, so criterion
//! prints states per second.
//!
//! `cargo bench --bench batch`; `kinetree bench --batch N` prints the same comparison for any
//! model.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use kinetree::dynamics::batch::{DynamicsBatch, aba_batch, crba_batch, rnea_batch};
use kinetree::dynamics::{DynamicsData, aba, crba, rnea};
use kinetree::kinematics::batch::{
    KinematicsBatch, forward_kinematics_batch, forward_kinematics_matrices_batch,
    frame_jacobian_batch,
};
use kinetree::kinematics::configuration::random_configuration;
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, forward_kinematics,
};
use kinetree::model::{Model, RootJoint};
use kinetree::parallel::{self as par, Parallel};
use kinetree::spatial::{Motion, Se3};
use rand::{Rng, SeedableRng};
use std::hint::black_box;

const ROBOTS: [(&str, RootJoint); 2] = [
    ("panda", RootJoint::Fixed),
    ("talos_reduced", RootJoint::Floating),
];

/// States per batch.
const N: usize = 1024;

fn load(name: &str, root: RootJoint) -> Model {
    let path = format!(
        "{}/tests/data/reference/urdf/{name}.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    Model::from_urdf_file(&path, root).expect("bundled reference URDF")
}

/// `N` random states stacked: `q` within the limits, `v` and `a` (also used as `tau`) in
/// [-1, 1].
fn states(model: &Model) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = rand::rngs::SmallRng::seed_from_u64(42);
    let mut q = vec![0.0; N * model.nq()];
    for qk in q.chunks_mut(model.nq()) {
        random_configuration(model, &mut rng, qk).expect("length nq");
    }
    let mut uniform = || {
        (0..N * model.nv())
            .map(|_| rng.random_range(-1.0..1.0))
            .collect::<Vec<f64>>()
    };
    let v = uniform();
    let a = uniform();
    (q, v, a)
}

fn batch(c: &mut Criterion) {
    for (name, root) in ROBOTS {
        let model = load(name, root);
        let (nq, nv, nl) = (model.nq(), model.nv(), model.links().len());
        let (q, v, a) = states(&model);
        let frame = FrameId::Link(nl - 1);
        let lwa = ReferenceFrame::LocalWorldAligned;
        let mut data = KinematicsData::new(&model);
        let mut kb = KinematicsBatch::new(&model);
        let mut pk = Parallel::<KinematicsBatch>::new(&model);
        let mut dd = DynamicsData::new(&model);
        let mut db = DynamicsBatch::new(&model);
        let mut pd = Parallel::<DynamicsBatch>::new(&model);
        let mut links = vec![Se3::IDENTITY; N * nl];
        let mut jac = vec![Motion::ZERO; N * nv];
        let mut one_jac = vec![Motion::ZERO; nv];
        let mut out = vec![0.0; N * nv];
        let mut mass = vec![0.0; N * nv * nv];
        let qk = |k: usize| &q[k * nq..(k + 1) * nq];

        let mut g = c.benchmark_group(format!("batch/{name}"));
        g.throughput(Throughput::Elements(N as u64));
        g.bench_function(BenchmarkId::new("fk", "one_state"), |b| {
            b.iter(|| {
                for k in 0..N {
                    let _ = forward_kinematics(&model, &mut data, black_box(qk(k)));
                }
            })
        });
        g.bench_function(BenchmarkId::new("fk", "batched"), |b| {
            b.iter(|| forward_kinematics_batch(&model, &mut kb, black_box(&q), &mut links, None))
        });
        g.bench_function(BenchmarkId::new("fk", "parallel"), |b| {
            b.iter(|| {
                par::forward_kinematics_batch(&model, &mut pk, black_box(&q), &mut links, None)
            })
        });
        let mut matrices = vec![0.0; N * nl * 16];
        g.bench_function(BenchmarkId::new("fk_matrices", "batched"), |b| {
            b.iter(|| {
                forward_kinematics_matrices_batch(
                    &model,
                    &mut kb,
                    black_box(&q),
                    None,
                    &mut matrices,
                )
            })
        });
        g.bench_function(BenchmarkId::new("fk_matrices", "parallel"), |b| {
            b.iter(|| {
                par::forward_kinematics_matrices_batch(
                    &model,
                    &mut pk,
                    black_box(&q),
                    None,
                    &mut matrices,
                )
            })
        });
        g.bench_function(BenchmarkId::new("frame_jacobian", "one_state"), |b| {
            b.iter(|| {
                for k in 0..N {
                    let _ =
                        compute_frame_jacobian(&model, &mut data, qk(k), frame, lwa, &mut one_jac);
                }
            })
        });
        g.bench_function(BenchmarkId::new("frame_jacobian", "batched"), |b| {
            b.iter(|| frame_jacobian_batch(&model, &mut kb, black_box(&q), frame, lwa, &mut jac))
        });
        g.bench_function(BenchmarkId::new("frame_jacobian", "parallel"), |b| {
            b.iter(|| {
                par::frame_jacobian_batch(&model, &mut pk, black_box(&q), frame, lwa, &mut jac)
            })
        });
        g.bench_function(BenchmarkId::new("rnea", "one_state"), |b| {
            b.iter(|| {
                for k in 0..N {
                    let r = k * nv..(k + 1) * nv;
                    let _ = black_box(rnea(&model, &mut dd, qk(k), &v[r.clone()], &a[r]).is_ok());
                }
            })
        });
        g.bench_function(BenchmarkId::new("rnea", "batched"), |b| {
            b.iter(|| rnea_batch(&model, &mut db, black_box(&q), &v, &a, &mut out))
        });
        g.bench_function(BenchmarkId::new("rnea", "parallel"), |b| {
            b.iter(|| par::rnea_batch(&model, &mut pd, black_box(&q), &v, &a, &mut out))
        });
        g.bench_function(BenchmarkId::new("aba", "one_state"), |b| {
            b.iter(|| {
                for k in 0..N {
                    let r = k * nv..(k + 1) * nv;
                    let _ = black_box(aba(&model, &mut dd, qk(k), &v[r.clone()], &a[r]).is_ok());
                }
            })
        });
        g.bench_function(BenchmarkId::new("aba", "batched"), |b| {
            b.iter(|| aba_batch(&model, &mut db, black_box(&q), &v, &a, &mut out))
        });
        g.bench_function(BenchmarkId::new("aba", "parallel"), |b| {
            b.iter(|| par::aba_batch(&model, &mut pd, black_box(&q), &v, &a, &mut out))
        });
        g.bench_function(BenchmarkId::new("crba", "one_state"), |b| {
            b.iter(|| {
                for k in 0..N {
                    let _ = black_box(crba(&model, &mut dd, qk(k)).is_ok());
                }
            })
        });
        g.bench_function(BenchmarkId::new("crba", "batched"), |b| {
            b.iter(|| crba_batch(&model, &mut db, black_box(&q), &mut mass))
        });
        g.bench_function(BenchmarkId::new("crba", "parallel"), |b| {
            b.iter(|| par::crba_batch(&model, &mut pd, black_box(&q), &mut mass))
        });
        g.finish();
    }
}

/// The inverse- and forward-dynamics derivatives (the three `nv x nv` matrices of each state).
fn derivatives(c: &mut Criterion) {
    use kinetree::dynamics::batch::{
        DerivativesBatch, aba_derivatives_batch, rnea_derivatives_batch,
    };
    use kinetree::dynamics::{DerivativesData, aba_derivatives, rnea_derivatives};
    for (name, root) in ROBOTS {
        let model = load(name, root);
        let (nq, nv) = (model.nq(), model.nv());
        let (q, v, a) = states(&model);
        let mut data = DerivativesData::new(&model);
        let mut db = DerivativesBatch::new(&model);
        let mut pd = Parallel::<DerivativesBatch>::new(&model);
        let mut out = [
            vec![0.0; N * nv * nv],
            vec![0.0; N * nv * nv],
            vec![0.0; N * nv * nv],
        ];
        let [dq, dv, da] = &mut out;
        let mut g = c.benchmark_group(format!("batch_derivatives/{name}"));
        g.throughput(Throughput::Elements(N as u64));
        g.bench_function(BenchmarkId::new("rnea_derivatives", "one_state"), |b| {
            b.iter(|| {
                for k in 0..N {
                    let r = k * nv..(k + 1) * nv;
                    let qk = &q[k * nq..(k + 1) * nq];
                    let d = rnea_derivatives(&model, &mut data, qk, &v[r.clone()], &a[r]);
                    let _ = black_box(d.is_ok());
                }
            })
        });
        g.bench_function(BenchmarkId::new("rnea_derivatives", "batched"), |b| {
            b.iter(|| rnea_derivatives_batch(&model, &mut db, black_box(&q), &v, &a, dq, dv, da))
        });
        g.bench_function(BenchmarkId::new("rnea_derivatives", "parallel"), |b| {
            b.iter(|| {
                par::rnea_derivatives_batch(&model, &mut pd, black_box(&q), &v, &a, dq, dv, da)
            })
        });
        // `a` serves as the torques.
        g.bench_function(BenchmarkId::new("aba_derivatives", "one_state"), |b| {
            b.iter(|| {
                for k in 0..N {
                    let r = k * nv..(k + 1) * nv;
                    let qk = &q[k * nq..(k + 1) * nq];
                    let d = aba_derivatives(&model, &mut data, qk, &v[r.clone()], &a[r]);
                    let _ = black_box(d.is_ok());
                }
            })
        });
        g.bench_function(BenchmarkId::new("aba_derivatives", "batched"), |b| {
            b.iter(|| aba_derivatives_batch(&model, &mut db, black_box(&q), &v, &a, dq, dv, da))
        });
        g.bench_function(BenchmarkId::new("aba_derivatives", "parallel"), |b| {
            b.iter(|| {
                par::aba_derivatives_batch(&model, &mut pd, black_box(&q), &v, &a, dq, dv, da)
            })
        });
        g.finish();
    }
}

criterion_group!(benches, batch, derivatives);
criterion_main!(benches);
