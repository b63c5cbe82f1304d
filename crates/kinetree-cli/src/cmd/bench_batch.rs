//! `kinetree bench --batch N`: ns/state of each batched algorithm beside the one-state path.
//!
//! Each algorithm evaluates the same `N` random states three ways: the one-state function in a
//! loop, the batched entry point on one core (vectorised across states), and
//! `kinetree::parallel` on every thread of the pool (`--threads`, default all cores). Each
//! repetition runs whole batches for at least `--calls` states; the median ns/state is
//! printed. With `--json`:
//! `{"model", "nq", "nv", "batch", "threads", "simd", "ns_per_state": {"fk": {"single",
//! "batched", "parallel"}, …}}` with the keys `fk`, `fk_matrices` (every link as a row-major
//! 4×4 matrix, the layout of numpy's poses; its one-state path converts `fk`'s placements),
//! `fk_frames`, `frame_jacobian`, `rnea`,
//! `aba`, `crba`, `rnea_derivatives` and `aba_derivatives` (the three matrices each), and `collision_distances` (all-pairs signed distances, placements included)
//! for models with collision geometry, timed on as many states as `--calls` states of 300 ns
//! would take (mesh pairs cost milliseconds a state), in batches cut down to that many states
//! (at least 16).

use anyhow::Result;
use kinetree::dynamics::batch::{DynamicsBatch, aba_batch, crba_batch, rnea_batch};
use kinetree::dynamics::{DynamicsData, aba, crba, rnea};
use kinetree::kinematics::batch::{
    KinematicsBatch, forward_kinematics_batch, forward_kinematics_matrices_batch,
    frame_jacobian_batch,
};
use kinetree::kinematics::spatial::{Motion, Se3};
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, forward_kinematics,
    update_frame_placements,
};
use kinetree::model::Model;
use kinetree::parallel::{self as par, Parallel};
use std::hint::black_box;
use std::time::Instant;

/// Median ns/state of `f()` (one whole batch of `n` states per call) over `reps` repetitions of
/// enough calls for `states` states, after a warm-up repetition.
fn time(n: usize, states: usize, reps: usize, mut f: impl FnMut()) -> f64 {
    let calls = states.div_ceil(n).max(1);
    for _ in 0..calls {
        f();
    }
    let mut per_state: Vec<f64> = (0..reps.max(1))
        .map(|_| {
            let start = Instant::now();
            for _ in 0..calls {
                f();
            }
            start.elapsed().as_secs_f64() * 1e9 / (calls * n) as f64
        })
        .collect();
    per_state.sort_by(f64::total_cmp);
    per_state[per_state.len() / 2]
}

/// The states and sizes of a run.
pub(crate) struct Setup<'a> {
    pub(crate) model: &'a Model,
    /// `n · nq` configurations.
    pub(crate) q: Vec<f64>,
    /// `n · nv` velocities.
    pub(crate) v: Vec<f64>,
    /// `n · nv` accelerations or torques.
    pub(crate) a: Vec<f64>,
    pub(crate) n: usize,
    pub(crate) states: usize,
    pub(crate) reps: usize,
    pub(crate) frame: FrameId,
}

/// One row: an algorithm's ns/state one state at a time, batched on one core, and batched on
/// every thread.
pub(crate) struct Row {
    pub(crate) name: &'static str,
    pub(crate) single: f64,
    pub(crate) batched: f64,
    pub(crate) parallel: f64,
}

/// Times every batched algorithm (rayon's current pool decides the threads).
pub(crate) fn rows(s: &Setup<'_>) -> Vec<Row> {
    let model = s.model;
    let (n, nq, nv, nl, nf) = (
        s.n,
        model.nq(),
        model.nv(),
        model.links().len(),
        model.frames().len(),
    );
    let (q, v, a) = (&s.q[..], &s.v[..], &s.a[..]);
    let t = |f: &mut dyn FnMut()| time(n, s.states, s.reps, f);
    let qk = |k: usize| &q[k * nq..(k + 1) * nq];
    let mut data = KinematicsData::new(model);
    let mut kb = KinematicsBatch::new(model);
    let mut pk = Parallel::<KinematicsBatch>::new(model);
    let mut links = vec![Se3::IDENTITY; n * nl];
    let mut frames = vec![Se3::IDENTITY; n * nf];
    let mut jac = vec![Motion::ZERO; n * nv];
    let mut one_jac = vec![Motion::ZERO; nv];
    let lwa = ReferenceFrame::LocalWorldAligned;
    let frame = s.frame;
    let mut rows = Vec::new();
    rows.push(Row {
        name: "fk",
        single: t(&mut || {
            for k in 0..n {
                let _ = forward_kinematics(model, &mut data, black_box(qk(k)));
                black_box(&data);
            }
        }),
        batched: t(&mut || {
            let _ = forward_kinematics_batch(model, &mut kb, black_box(q), &mut links, None);
            black_box(&links);
        }),
        parallel: t(&mut || {
            let _ = par::forward_kinematics_batch(model, &mut pk, black_box(q), &mut links, None);
            black_box(&links);
        }),
    });
    let mut matrices = vec![0.0; n * nl * 16];
    rows.push(Row {
        name: "fk_matrices",
        single: t(&mut || {
            for (k, out) in matrices.chunks_exact_mut((nl * 16).max(1)).enumerate() {
                let _ = forward_kinematics(model, &mut data, black_box(qk(k)));
                for (x, o) in data.world_from_link().iter().zip(out.chunks_exact_mut(16)) {
                    o.copy_from_slice(&x.to_mat4().transpose().to_cols_array());
                }
            }
            black_box(&matrices);
        }),
        batched: t(&mut || {
            let _ = forward_kinematics_matrices_batch(model, &mut kb, q, None, &mut matrices);
            black_box(&matrices);
        }),
        parallel: t(&mut || {
            let _ = par::forward_kinematics_matrices_batch(model, &mut pk, q, None, &mut matrices);
            black_box(&matrices);
        }),
    });
    rows.push(Row {
        name: "fk_frames",
        single: t(&mut || {
            for k in 0..n {
                let _ = forward_kinematics(model, &mut data, black_box(qk(k)));
                let _ = update_frame_placements(model, &mut data);
                black_box(&data);
            }
        }),
        batched: t(&mut || {
            let _ = forward_kinematics_batch(model, &mut kb, q, &mut links, Some(&mut frames));
            black_box(&frames);
        }),
        parallel: t(&mut || {
            let _ = par::forward_kinematics_batch(model, &mut pk, q, &mut links, Some(&mut frames));
            black_box(&frames);
        }),
    });
    rows.push(Row {
        name: "frame_jacobian",
        single: t(&mut || {
            for k in 0..n {
                let _ = compute_frame_jacobian(model, &mut data, qk(k), frame, lwa, &mut one_jac);
                black_box(&one_jac);
            }
        }),
        batched: t(&mut || {
            let _ = frame_jacobian_batch(model, &mut kb, q, frame, lwa, &mut jac);
            black_box(&jac);
        }),
        parallel: t(&mut || {
            let _ = par::frame_jacobian_batch(model, &mut pk, q, frame, lwa, &mut jac);
            black_box(&jac);
        }),
    });
    let mut dd = DynamicsData::new(model);
    let mut db = DynamicsBatch::new(model);
    let mut pd = Parallel::<DynamicsBatch>::new(model);
    let mut out = vec![0.0; n * nv];
    let mut mass = vec![0.0; n * nv * nv];
    rows.push(Row {
        name: "rnea",
        single: t(&mut || {
            for k in 0..n {
                let r = k * nv..(k + 1) * nv;
                let _ = black_box(rnea(model, &mut dd, qk(k), &v[r.clone()], &a[r]).map(|t| t[0]));
            }
        }),
        batched: t(&mut || {
            let _ = rnea_batch(model, &mut db, q, v, a, &mut out);
            black_box(&out);
        }),
        parallel: t(&mut || {
            let _ = par::rnea_batch(model, &mut pd, q, v, a, &mut out);
            black_box(&out);
        }),
    });
    rows.push(Row {
        name: "aba",
        single: t(&mut || {
            for k in 0..n {
                let r = k * nv..(k + 1) * nv;
                let _ = black_box(aba(model, &mut dd, qk(k), &v[r.clone()], &a[r]).map(|t| t[0]));
            }
        }),
        batched: t(&mut || {
            let _ = aba_batch(model, &mut db, q, v, a, &mut out);
            black_box(&out);
        }),
        parallel: t(&mut || {
            let _ = par::aba_batch(model, &mut pd, q, v, a, &mut out);
            black_box(&out);
        }),
    });
    rows.push(Row {
        name: "crba",
        single: t(&mut || {
            for k in 0..n {
                let _ = black_box(crba(model, &mut dd, qk(k)).map(|m| m[0]));
            }
        }),
        batched: t(&mut || {
            let _ = crba_batch(model, &mut db, q, &mut mass);
            black_box(&mass);
        }),
        parallel: t(&mut || {
            let _ = par::crba_batch(model, &mut pd, q, &mut mass);
            black_box(&mass);
        }),
    });
    rows.extend(derivatives_rows(s));
    rows
}

/// `rnea_derivatives` and `aba_derivatives`: the three `nv x nv` matrices of each state.
fn derivatives_rows(setup: &Setup<'_>) -> [Row; 2] {
    use kinetree::dynamics::batch::{aba_derivatives_batch, rnea_derivatives_batch};
    use kinetree::dynamics::{aba_derivatives, rnea_derivatives};
    [
        derivatives_row(
            setup,
            "rnea_derivatives",
            &mut |m, d, q, v, a| rnea_derivatives(m, d, q, v, a).map_or(0.0, |d| d.dtau_dq[0]),
            rnea_derivatives_batch,
            par::rnea_derivatives_batch,
        ),
        derivatives_row(
            setup,
            "aba_derivatives",
            &mut |m, d, q, v, t| aba_derivatives(m, d, q, v, t).map_or(0.0, |d| d.dddq_dq[0]),
            aba_derivatives_batch,
            par::aba_derivatives_batch,
        ),
    ]
}

/// A batched derivatives function: `(q, v, a or tau)` in, three `nv x nv` matrices per state out.
type Batched<W> = fn(
    &Model,
    &mut W,
    &[f64],
    &[f64],
    &[f64],
    &mut [f64],
    &mut [f64],
    &mut [f64],
) -> Result<(), kinetree::dynamics::DynamicsError>;

/// A one-state derivatives function (returning an entry, kept alive).
type Single =
    dyn FnMut(&Model, &mut kinetree::dynamics::DerivativesData, &[f64], &[f64], &[f64]) -> f64;

/// One derivatives row: `single` computes one state (and returns an entry, kept alive),
/// `batched` and `parallel` the whole batch.
fn derivatives_row(
    setup: &Setup<'_>,
    name: &'static str,
    single: &mut Single,
    batched: Batched<kinetree::dynamics::batch::DerivativesBatch>,
    parallel: Batched<Parallel<kinetree::dynamics::batch::DerivativesBatch>>,
) -> Row {
    use kinetree::dynamics::DerivativesData;
    use kinetree::dynamics::batch::DerivativesBatch;
    let Setup { model, n, .. } = *setup;
    let (q, v, a) = (&setup.q[..], &setup.v[..], &setup.a[..]);
    let (nq, nv) = (model.nq(), model.nv());
    let t = |f: &mut dyn FnMut()| time(n, setup.states, setup.reps, f);
    let mut data = DerivativesData::new(model);
    let mut batch = DerivativesBatch::new(model);
    let mut pool = Parallel::<DerivativesBatch>::new(model);
    let mut out = [
        vec![0.0; n * nv * nv],
        vec![0.0; n * nv * nv],
        vec![0.0; n * nv * nv],
    ];
    let [dq, dv, da] = &mut out;
    Row {
        name,
        single: t(&mut || {
            for k in 0..n {
                let r = k * nv..(k + 1) * nv;
                let qk = &q[k * nq..(k + 1) * nq];
                black_box(single(model, &mut data, qk, &v[r.clone()], &a[r]));
            }
        }),
        batched: t(&mut || {
            let _ = batched(model, &mut batch, q, v, a, dq, dv, da);
            black_box(&*da);
        }),
        parallel: t(&mut || {
            let _ = parallel(model, &mut pool, q, v, a, dq, dv, da);
            black_box(&*da);
        }),
    }
}

/// Runs `kinetree bench --batch`: random states, the timings, and the table or JSON.
pub(crate) fn run(args: &super::bench::Args, model: &Model, n: usize) -> Result<()> {
    use rand::{Rng, SeedableRng};
    if n == 0 {
        anyhow::bail!("--batch must be at least 1 state");
    }
    let mut rng = rand::rngs::SmallRng::seed_from_u64(args.seed);
    let mut q = vec![0.0; n * model.nq()];
    for qk in q.chunks_mut(model.nq().max(1)) {
        kinetree::kinematics::configuration::random_configuration(model, &mut rng, qk)?;
    }
    let mut uniform = || -> Vec<f64> {
        (0..n * model.nv())
            .map(|_| rng.random_range(-1.0..1.0))
            .collect()
    };
    let (v, a) = (uniform(), uniform());
    let setup = Setup {
        model,
        q,
        v,
        a,
        n,
        states: args.calls,
        reps: args.repetitions,
        frame: FrameId::Link(super::bench::deepest_link(model)),
    };
    let threads = args.threads.unwrap_or(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let options = kinetree::collision::CollisionOptions::default()
        .with_model_file(&args.model, &args.mesh_paths)
        .skip_missing_meshes();
    let cmodel = kinetree::collision::CollisionModel::from_model(model, &options).ok();
    let (rows, threads) = pool.install(|| {
        let mut rows = rows(&setup);
        rows.extend(
            cmodel
                .as_ref()
                .filter(|c| !c.pairs().is_empty())
                .map(|c| collision_row(&setup, c)),
        );
        (rows, rayon::current_num_threads())
    });
    let simd = KinematicsBatch::new(model).simd();
    if args.json {
        let map: serde_json::Map<String, serde_json::Value> = rows
            .iter()
            .map(|r| {
                (
                    r.name.to_string(),
                    serde_json::json!({"single": r.single, "batched": r.batched, "parallel": r.parallel}),
                )
            })
            .collect();
        let out = serde_json::json!({"model": model.name(), "nq": model.nq(), "nv": model.nv(),
            "batch": n, "threads": threads, "simd": format!("{simd:?}"), "ns_per_state": map});
        outln!("{out}")?;
    } else {
        outln!(
            "{} (nq = {}, nv = {}), batches of {n} states, {simd:?}, median ns/state",
            model.name(),
            model.nq(),
            model.nv()
        )?;
        outln!("frame_jacobian is timed on '{}'", setup.frame.name(model)?)?;
        let width = rows
            .iter()
            .map(|r| r.name.len())
            .chain([9])
            .max()
            .unwrap_or(9);
        outln!(
            "  {:<width$} {:>10} {:>10} {:>8} {:>12} {:>8}",
            "algorithm",
            "one-state",
            "batched",
            "speedup",
            format!("{threads} threads"),
            "speedup"
        )?;
        for r in &rows {
            outln!(
                "  {:<width$} {:>10.1} {:>10.1} {:>7.2}x {:>12.1} {:>7.2}x",
                r.name,
                r.single,
                r.batched,
                r.single / r.batched,
                r.parallel,
                r.single / r.parallel
            )?;
        }
    }
    Ok(())
}

/// The batched all-pairs signed distances beside the one-state query (placements included), on
/// as many states as `s.states` states of 300 ns would take, from a first estimate of the
/// one-state time (a model with meshes costs milliseconds a state), in batches no larger.
fn collision_row(s: &Setup<'_>, cmodel: &kinetree::collision::CollisionModel) -> Row {
    use kinetree::collision::batch::{CollisionBatch, distances_batch};
    use kinetree::collision::{CollisionData, compute_distances};
    let (model, n, nq) = (s.model, s.n, s.model.nq());
    let q = &s.q[..];
    let mut kinematics = KinematicsData::new(model);
    let mut data = CollisionData::new(cmodel);
    let probe = n.min(16);
    let start = Instant::now();
    for k in 0..probe {
        let _ = data.compute_placements(model, cmodel, &mut kinematics, &q[k * nq..(k + 1) * nq]);
        let _ = black_box(compute_distances(cmodel, &mut data).map(|d| d.len()));
    }
    let ns = (start.elapsed().as_secs_f64() * 1e9 / probe as f64).max(1.0);
    let states = ((s.states as f64 * 300.0 / ns) as usize).max(1);
    // A batch larger than that budget is cut down to it (at least 16 states, two blocks of lanes).
    let n = n.min(states.max(16));
    let q = &q[..n * nq];
    let t = |f: &mut dyn FnMut()| time(n, states, s.reps, f);
    let mut one = CollisionBatch::new(model, cmodel);
    let mut pool = Parallel::from_fn(rayon::current_num_threads(), |_| {
        CollisionBatch::new(model, cmodel)
    });
    let mut out = vec![0.0; n * cmodel.pairs().len()];
    Row {
        name: "collision_distances",
        single: t(&mut || {
            for k in 0..n {
                let qk = black_box(&q[k * nq..(k + 1) * nq]);
                let _ = data.compute_placements(model, cmodel, &mut kinematics, qk);
                let _ = black_box(compute_distances(cmodel, &mut data).map(|d| d.len()));
            }
        }),
        batched: t(&mut || {
            let _ = distances_batch(model, cmodel, &mut one, black_box(q), &mut out);
            black_box(&out);
        }),
        parallel: t(&mut || {
            let _ = par::distances_batch(model, cmodel, &mut pool, black_box(q), &mut out);
            black_box(&out);
        }),
    }
}
