//! `kinetree::parallel` against the one-core batched functions: the same numbers for any number
//! of blocks, and a bad state named by its index in the whole batch.

use kinetree::dynamics::DynamicsError;
use kinetree::dynamics::batch::{DynamicsBatch, aba_batch, crba_batch, rnea_batch};
use kinetree::kinematics::batch::{
    KinematicsBatch, forward_kinematics_batch, frame_jacobian_batch,
};
use kinetree::kinematics::configuration::random_configuration;
use kinetree::kinematics::{FrameId, KinematicsError, ReferenceFrame};
use kinetree::model::{Model, RootJoint};
use kinetree::parallel::{self as par, Parallel};
use kinetree::spatial::{Motion, Se3};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

fn robot(file: &str, root: RootJoint) -> Model {
    let path = format!(
        "{}/tests/data/reference/urdf/{file}",
        env!("CARGO_MANIFEST_DIR")
    );
    Model::from_urdf_file(path, root).unwrap()
}

fn states(model: &Model, n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = SmallRng::seed_from_u64(3);
    let mut q = vec![0.0; n * model.nq()];
    for qk in q.chunks_mut(model.nq()) {
        random_configuration(model, &mut rng, qk).unwrap();
    }
    let mut uniform = || -> Vec<f64> {
        (0..n * model.nv())
            .map(|_| rng.random_range(-2.0..2.0))
            .collect()
    };
    let v = uniform();
    let a = uniform();
    (q, v, a)
}

#[test]
fn every_split_gives_the_one_core_numbers() {
    for (file, root) in [
        ("panda.urdf", RootJoint::Fixed),
        ("solo12.urdf", RootJoint::Floating),
    ] {
        let model = robot(file, root);
        let n = 37;
        let (nl, nv) = (model.links().len(), model.nv());
        let (q, v, a) = states(&model, n);
        let frame = FrameId::Link(nl - 1);
        let mut kb = KinematicsBatch::new(&model);
        let mut links = vec![Se3::IDENTITY; n * nl];
        forward_kinematics_batch(&model, &mut kb, &q, &mut links, None).unwrap();
        let mut jac = vec![Motion::ZERO; n * nv];
        frame_jacobian_batch(&model, &mut kb, &q, frame, ReferenceFrame::Local, &mut jac).unwrap();
        let mut db = DynamicsBatch::new(&model);
        let (mut tau, mut ddq, mut mass) =
            (vec![0.0; n * nv], vec![0.0; n * nv], vec![0.0; n * nv * nv]);
        rnea_batch(&model, &mut db, &q, &v, &a, &mut tau).unwrap();
        aba_batch(&model, &mut db, &q, &v, &a, &mut ddq).unwrap();
        crba_batch(&model, &mut db, &q, &mut mass).unwrap();
        for threads in [1, 2, 3, 8] {
            let mut pk = Parallel::<KinematicsBatch>::with_threads(&model, threads);
            let mut pl = vec![Se3::IDENTITY; n * nl];
            par::forward_kinematics_batch(&model, &mut pk, &q, &mut pl, None).unwrap();
            assert_eq!(pl, links, "{file}: {threads} blocks");
            // The matrices of the last link and the root: the placements' numbers, in rows.
            let mut pm = vec![f64::NAN; n * 2 * 16];
            par::forward_kinematics_matrices_batch(
                &model,
                &mut pk,
                &q,
                Some(&[nl - 1, 0]),
                &mut pm,
            )
            .unwrap();
            for (k, state) in pm.chunks_exact(32).enumerate() {
                for (m, l) in [nl - 1, 0].into_iter().enumerate() {
                    let x = links[k * nl + l].to_mat4().transpose().to_cols_array();
                    assert_eq!(
                        state[m * 16..(m + 1) * 16],
                        x,
                        "{file}: {threads} blocks, matrices"
                    );
                }
            }
            let mut pj = vec![Motion::ZERO; n * nv];
            par::frame_jacobian_batch(&model, &mut pk, &q, frame, ReferenceFrame::Local, &mut pj)
                .unwrap();
            assert_eq!(pj, jac, "{file}: {threads} blocks");
            let mut pr = vec![f64::NAN; n * 6 * nv];
            par::frame_jacobian_rows_batch(
                &model,
                &mut pk,
                &q,
                frame,
                ReferenceFrame::Local,
                &mut pr,
            )
            .unwrap();
            for (k, state) in pr.chunks_exact(6 * nv).enumerate() {
                for (c, col) in jac[k * nv..(k + 1) * nv].iter().enumerate() {
                    for (r, x) in col.to_array().into_iter().enumerate() {
                        assert_eq!(state[r * nv + c], x, "{file}: {threads} blocks, rows");
                    }
                }
            }
            let mut pd = Parallel::<DynamicsBatch>::with_threads(&model, threads);
            let mut out = vec![0.0; n * nv];
            par::rnea_batch(&model, &mut pd, &q, &v, &a, &mut out).unwrap();
            assert_eq!(out, tau, "{file}: {threads} blocks");
            par::aba_batch(&model, &mut pd, &q, &v, &a, &mut out).unwrap();
            assert_eq!(out, ddq, "{file}: {threads} blocks");
            let mut pm = vec![0.0; n * nv * nv];
            par::crba_batch(&model, &mut pd, &q, &mut pm).unwrap();
            assert_eq!(pm, mass, "{file}: {threads} blocks");
        }
    }
}

#[test]
fn a_bad_state_keeps_its_index_across_blocks() {
    let model = robot("panda.urdf", RootJoint::Fixed);
    let n = 40;
    let (mut q, v, a) = states(&model, n);
    q[33 * model.nq() + 2] = f64::INFINITY;
    let mut pk = Parallel::<KinematicsBatch>::with_threads(&model, 2);
    let mut links = vec![Se3::IDENTITY; n * model.links().len()];
    let err = par::forward_kinematics_batch(&model, &mut pk, &q, &mut links, None).unwrap_err();
    assert!(
        matches!(err, KinematicsError::InBatchState { index: 33, .. }),
        "{err:?}"
    );
    let mut pd = Parallel::<DynamicsBatch>::with_threads(&model, 2);
    let mut tau = vec![0.0; n * model.nv()];
    let err = par::rnea_batch(&model, &mut pd, &q, &v, &a, &mut tau).unwrap_err();
    assert!(
        matches!(err, DynamicsError::InBatchState { index: 33, .. }),
        "{err:?}"
    );
    // Lengths that do not make whole states are reported as the one-core function does.
    let err = par::rnea_batch(&model, &mut pd, &q, &v[1..], &a, &mut tau).unwrap_err();
    assert!(
        matches!(err, DynamicsError::DimensionMismatch { what: "v", .. }),
        "{err:?}"
    );
}

/// From outside any pool a batch is cut in blocks that the threads take in whatever order they
/// come; inside a pool it is split once per thread. Either way the first bad state is named,
/// whichever block fails first, and the states that can be computed match the one-core numbers.
#[test]
fn the_first_bad_state_is_named_whichever_thread_gets_there_first() {
    let model = robot("panda.urdf", RootJoint::Fixed);
    let (n, nv) = (300, model.nv());
    let (mut q, v, a) = states(&model, n);
    let mut tau = vec![0.0; n * nv];
    rnea_batch(
        &model,
        &mut DynamicsBatch::new(&model),
        &q,
        &v,
        &a,
        &mut tau,
    )
    .unwrap();
    for bad in [250, 130, 41] {
        q[bad * model.nq() + 3] = f64::NAN;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap();
    for threads in [2, 3, 8] {
        let mut pd = Parallel::<DynamicsBatch>::with_threads(&model, threads);
        for round in 0..20 {
            let mut out = vec![f64::NAN; n * nv];
            let err = if round % 2 == 0 {
                par::rnea_batch(&model, &mut pd, &q, &v, &a, &mut out)
            } else {
                pool.install(|| par::rnea_batch(&model, &mut pd, &q, &v, &a, &mut out))
            }
            .unwrap_err();
            assert!(
                matches!(err, DynamicsError::InBatchState { index: 41, .. }),
                "{threads} threads, round {round}: {err:?}"
            );
            if round % 2 == 0 {
                // Blocks (16 or 24 states here) without a bad state were all computed, whatever
                // the order the threads took them in.
                assert_eq!(out[..24 * nv], tau[..24 * nv], "{threads} threads");
                assert_eq!(out[264 * nv..], tau[264 * nv..], "{threads} threads");
            }
        }
    }
}

/// `Parallel::for_each_block` runs every block once, whichever thread takes it, past the 64
/// blocks it keeps on the stack too, and reports the first failing block in the order given.
#[test]
fn every_block_runs_once_and_the_first_failure_is_reported() {
    use std::sync::atomic::{AtomicU32, Ordering};
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    for count in [0, 1, 63, 64, 65, 200] {
        for threads in [1, 2, 5] {
            for (round, failing) in [vec![], vec![0], vec![150, 70, 63], vec![199, 64]]
                .into_iter()
                .enumerate()
            {
                let runs: Vec<AtomicU32> = (0..count).map(|_| AtomicU32::new(0)).collect();
                let mut workers = Parallel::from_fn(threads, |_| ());
                let f = |_: &mut (), b: usize| {
                    runs[b].fetch_add(1, Ordering::Relaxed);
                    if failing.contains(&b) { Err(b) } else { Ok(()) }
                };
                let result = if round % 2 == 0 {
                    workers.for_each_block(0..count, &f)
                } else {
                    pool.install(|| workers.for_each_block(0..count, &f))
                };
                let what = format!("{count} blocks, {threads} threads, failing {failing:?}");
                assert!(
                    runs.iter().all(|r| r.load(Ordering::Relaxed) == 1),
                    "{what}"
                );
                let first = failing.iter().copied().filter(|&b| b < count).min();
                assert_eq!(result.err(), first, "{what}");
            }
        }
    }
}

#[test]
fn collision_batches_split_without_changing_a_number() {
    use kinetree::collision::batch::{CollisionBatch, distances_batch, min_distance_batch};
    use kinetree::collision::{CollisionError, CollisionModel, CollisionOptions};
    let model = robot("panda_collision.urdf", RootJoint::Fixed);
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let (n, np) = (37, cmodel.pairs().len());
    let (mut q, _, _) = states(&model, n);
    let mut one = CollisionBatch::new(&model, &cmodel);
    let (mut distances, mut min) = (vec![0.0; n * np], vec![0.0; n]);
    distances_batch(&model, &cmodel, &mut one, &q, &mut distances).unwrap();
    min_distance_batch(&model, &cmodel, &mut one, &q, &mut min).unwrap();
    for threads in 1..=4 {
        let mut pool = Parallel::from_fn(threads, |_| CollisionBatch::new(&model, &cmodel));
        let (mut d, mut m) = (vec![0.0; n * np], vec![0.0; n]);
        par::distances_batch(&model, &cmodel, &mut pool, &q, &mut d).unwrap();
        par::min_distance_batch(&model, &cmodel, &mut pool, &q, &mut m).unwrap();
        assert_eq!(d, distances, "{threads} blocks");
        assert_eq!(m, min, "{threads} blocks");
    }
    q[30 * model.nq() + 2] = f64::INFINITY;
    let mut pool = Parallel::from_fn(3, |_| CollisionBatch::new(&model, &cmodel));
    match par::min_distance_batch(&model, &cmodel, &mut pool, &q, &mut min) {
        Err(CollisionError::InBatchState { index: 30, .. }) => {}
        other => panic!("{other:?}"),
    }
}

#[test]
fn batched_derivatives_split_without_changing_a_number() {
    use kinetree::dynamics::batch::{
        DerivativesBatch, aba_derivatives_batch, rnea_derivatives_batch,
    };
    type One = fn(
        &Model,
        &mut DerivativesBatch,
        &[f64],
        &[f64],
        &[f64],
        &mut [f64],
        &mut [f64],
        &mut [f64],
    ) -> Result<(), DynamicsError>;
    type Par = fn(
        &Model,
        &mut Parallel<DerivativesBatch>,
        &[f64],
        &[f64],
        &[f64],
        &mut [f64],
        &mut [f64],
        &mut [f64],
    ) -> Result<(), DynamicsError>;
    let algorithms: [(&str, One, Par, &str); 2] = [
        (
            "rnea",
            rnea_derivatives_batch,
            par::rnea_derivatives_batch,
            "a",
        ),
        (
            "aba",
            aba_derivatives_batch,
            par::aba_derivatives_batch,
            "tau",
        ),
    ];
    for (name, one, parallel, third) in algorithms {
        for (file, root) in [
            ("panda.urdf", RootJoint::Fixed),
            ("solo12.urdf", RootJoint::Floating),
        ] {
            let model = robot(file, root);
            let n = 37;
            let nn = model.nv() * model.nv();
            let (mut q, v, a) = states(&model, n);
            let mut db = DerivativesBatch::new(&model);
            let mut want = [vec![0.0; n * nn], vec![0.0; n * nn], vec![0.0; n * nn]];
            let [dq, dv, da] = &mut want;
            one(&model, &mut db, &q, &v, &a, dq, dv, da).unwrap();
            for threads in [1, 2, 3, 8] {
                let mut pd = Parallel::<DerivativesBatch>::with_threads(&model, threads);
                let mut got = [vec![0.0; n * nn], vec![0.0; n * nn], vec![0.0; n * nn]];
                let [dq, dv, da] = &mut got;
                parallel(&model, &mut pd, &q, &v, &a, dq, dv, da).unwrap();
                assert_eq!(got, want, "{name} {file}: {threads} blocks");
            }
            // A bad state keeps its index in the whole batch.
            q[33 * model.nq()] = f64::NAN;
            let mut pd = Parallel::<DerivativesBatch>::with_threads(&model, 2);
            let [dq, dv, da] = &mut want;
            let err = parallel(&model, &mut pd, &q, &v, &a, dq, dv, da).unwrap_err();
            assert!(
                matches!(err, DynamicsError::InBatchState { index: 33, .. }),
                "{name} {file}: {err:?}"
            );
            let err = parallel(&model, &mut pd, &q, &v, &a[1..], dq, dv, da).unwrap_err();
            assert!(
                matches!(err, DynamicsError::DimensionMismatch { what, .. } if what == third),
                "{name} {file}: {err:?}"
            );
        }
    }
}
