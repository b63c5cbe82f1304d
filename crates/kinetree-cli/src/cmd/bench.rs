//! `kinetree bench <model>`: times each algorithm on random in-limit states of the user's own
//! robot (what MuJoCo's testspeed is to MuJoCo).
//!
//! Each algorithm runs `--calls` times, cycling through 1000 random states, after a warm-up of
//! as many calls; this is repeated `--repetitions` times and the median ns/call is
//! printed. With `--json` the output is
//! `{"model", "nq", "nv", "ns_per_call": {"fk", "fk_frames", "frame_jacobian", "joint_jacobians",
//! "rnea", "nle", "crba", "aba", "minv", "rnea_derivatives", "aba_derivatives", "collision_any",
//! "collision_distances"}}` (the collision keys
//! only for models with collision geometry; meshes are looked up next to the model file, then
//! in the `--mesh-path` directories, and skipped when missing); the keys stay stable so scripts can compare runs.
//! `"pinocchio_ns_per_call"` repeats the like-for-like timings under the names of Pinocchio's
//! anchor benchmark (`fk+frames`, `jacobians`, `rnea`, `nle`, `crba`, `aba`, `minverse`,
//! `rnea_derivatives`, `aba_derivatives`), so a side-by-side script needs no mapping. kinetree's
//! `fk` also places every link, so it has no Pinocchio twin (Pinocchio's `fk` places the joints
//! only); its `fk_frames` is Pinocchio's `fk+frames`.
//! Velocities, accelerations and torques are drawn uniformly in [-1, 1].

use anyhow::Result;
use kinetree::dynamics::{
    DerivativesData, DynamicsData, aba, aba_derivatives, crba, mass_matrix_inverse,
    nonlinear_effects, rnea, rnea_derivatives,
};
use kinetree::kinematics::configuration::random_configuration;
use kinetree::kinematics::spatial::Motion;
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, compute_joint_jacobians,
    forward_kinematics, update_frame_placements,
};
use kinetree::model::Model;
use rand::Rng;
use rand::SeedableRng;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `kinetree bench`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint named `root_joint`.
    #[arg(long)]
    floating: bool,
    /// Calls per timed repetition.
    #[arg(long, default_value_t = 100_000)]
    calls: usize,
    /// Timed repetitions (the median is reported).
    #[arg(long, default_value_t = 7)]
    repetitions: usize,
    /// Seed of the random states.
    #[arg(long, default_value_t = 42)]
    seed: u64,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// A directory where collision meshes are looked up (`package://` and relative names) after
    /// the model file's directory, as in `collide`; repeatable.
    #[arg(long = "mesh-path")]
    mesh_paths: Vec<PathBuf>,
    /// Run even when --calls × (--repetitions + 1) exceeds the limit of 10⁹ calls per algorithm.
    #[arg(long)]
    no_limit: bool,
}

/// kinetree's timings that time the same work as a case of Pinocchio's anchor benchmark, with
/// that case's name there.
const PINOCCHIO_NAMES: [(&str, &str); 9] = [
    ("fk_frames", "fk+frames"),
    ("joint_jacobians", "jacobians"),
    ("rnea", "rnea"),
    ("nle", "nle"),
    ("crba", "crba"),
    ("aba", "aba"),
    ("minv", "minverse"),
    ("rnea_derivatives", "rnea_derivatives"),
    ("aba_derivatives", "aba_derivatives"),
];

/// The most calls per algorithm (warm-up included) run without --no-limit.
const MAX_CALLS: usize = 1_000_000_000;

/// Refuses counts that time nothing (zero calls or repetitions would print invented timings)
/// and counts that cannot finish sensibly.
fn check_counts(args: &Args) -> Result<()> {
    if args.calls == 0 || args.repetitions == 0 {
        anyhow::bail!(
            "--calls and --repetitions must be at least 1 (got --calls {} --repetitions {}): zero calls time nothing",
            args.calls,
            args.repetitions
        );
    }
    let total = args
        .calls
        .saturating_mul(args.repetitions.saturating_add(1));
    if total > MAX_CALLS && !args.no_limit {
        anyhow::bail!(
            "--calls {} × (--repetitions {} + 1 warm-up) = {} calls per algorithm exceeds the limit of {MAX_CALLS}; lower them, or pass --no-limit to run anyway",
            args.calls,
            args.repetitions,
            if total == usize::MAX {
                "more than 1.8e19".to_string()
            } else {
                total.to_string()
            }
        );
    }
    Ok(())
}

/// Median ns/call of `f(i)` over `reps` repetitions of `calls` calls (after a warm-up).
fn time(calls: usize, reps: usize, mut f: impl FnMut(usize)) -> f64 {
    // Warm up for a whole repetition: caches, branch predictors and the clock settle.
    for i in 0..calls.max(1) {
        f(i);
    }
    let mut per_call: Vec<f64> = (0..reps.max(1))
        .map(|_| {
            let start = Instant::now();
            for i in 0..calls {
                f(i);
            }
            start.elapsed().as_secs_f64() * 1e9 / calls.max(1) as f64
        })
        .collect();
    per_call.sort_by(f64::total_cmp);
    per_call[per_call.len() / 2]
}

/// The link farthest from the root (most joints on its path): the frame whose Jacobian is timed.
fn deepest_link(model: &Model) -> usize {
    (0..model.links().len())
        .max_by_key(|&l| model.path_to_root(l).len())
        .unwrap_or(0)
}

/// Runs every timing and prints the results.
pub(crate) fn run(args: &Args) -> Result<()> {
    check_counts(args)?;
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    if model.nv() == 0 {
        anyhow::bail!(
            "model '{}' has no moving joint (nv = 0): there is nothing to time",
            model.name()
        );
    }
    let mut rng = rand::rngs::SmallRng::seed_from_u64(args.seed);
    let states: Vec<Vec<f64>> = (0..1000)
        .map(|_| {
            let mut q = vec![0.0; model.nq()];
            random_configuration(&model, &mut rng, &mut q).map(|()| q)
        })
        .collect::<Result<_, _>>()?;
    let vectors: Vec<Vec<f64>> = (0..1000)
        .map(|_| {
            (0..model.nv())
                .map(|_| rng.random_range(-1.0..1.0))
                .collect()
        })
        .collect();
    let mut data = KinematicsData::new(&model);
    let mut jac = vec![Motion::ZERO; model.nv()];
    let frame = FrameId::Link(deepest_link(&model));
    let (calls, reps) = (args.calls, args.repetitions);
    let q = |i: usize| &states[i % states.len()];
    let mut results: Vec<(&str, f64)> = Vec::new();
    results.push((
        "fk",
        time(calls, reps, |i| {
            let _ = forward_kinematics(&model, &mut data, black_box(q(i)));
            black_box(&data);
        }),
    ));
    results.push((
        "fk_frames",
        time(calls, reps, |i| {
            let _ = forward_kinematics(&model, &mut data, black_box(q(i)));
            let _ = update_frame_placements(&model, &mut data);
            black_box(&data);
        }),
    ));
    results.push((
        "frame_jacobian",
        time(calls, reps, |i| {
            let _ = compute_frame_jacobian(
                &model,
                &mut data,
                black_box(q(i)),
                frame,
                ReferenceFrame::LocalWorldAligned,
                &mut jac,
            );
            black_box(&jac);
        }),
    ));
    results.push((
        "joint_jacobians",
        time(calls, reps, |i| {
            let _ = compute_joint_jacobians(&model, &mut data, black_box(q(i)));
            black_box(&data);
        }),
    ));

    let mut dd = DynamicsData::new(&model);
    let x = |i: usize| &vectors[i % vectors.len()];
    let y = |i: usize| &vectors[(i + 500) % vectors.len()];
    results.push((
        "rnea",
        time(calls, reps, |i| {
            let _ = black_box(
                rnea(&model, &mut dd, black_box(q(i)), x(i), y(i)).map(|t| t.first().copied()),
            );
        }),
    ));
    results.push((
        "nle",
        time(calls, reps, |i| {
            let _ = black_box(
                nonlinear_effects(&model, &mut dd, black_box(q(i)), x(i))
                    .map(|t| t.first().copied()),
            );
        }),
    ));
    results.push((
        "crba",
        time(calls, reps, |i| {
            let _ = black_box(crba(&model, &mut dd, black_box(q(i))).map(|m| m.first().copied()));
        }),
    ));
    results.push((
        "aba",
        time(calls, reps, |i| {
            let _ = black_box(
                aba(&model, &mut dd, black_box(q(i)), x(i), y(i)).map(|a| a.first().copied()),
            );
        }),
    ));
    results.push((
        "minv",
        time(calls, reps, |i| {
            let _ = black_box(
                mass_matrix_inverse(&model, &mut dd, black_box(q(i))).map(|m| m.first().copied()),
            );
        }),
    ));

    let mut derivatives = DerivativesData::new(&model);
    results.push((
        "rnea_derivatives",
        time(calls, reps, |i| {
            let _ = black_box(
                rnea_derivatives(&model, &mut derivatives, black_box(q(i)), x(i), y(i))
                    .map(|d| d.dtau_dq[0]),
            );
        }),
    ));
    results.push((
        "aba_derivatives",
        time(calls, reps, |i| {
            let _ = black_box(
                aba_derivatives(&model, &mut derivatives, black_box(q(i)), x(i), y(i))
                    .map(|d| d.dddq_dq[0]),
            );
        }),
    ));

    let options = kinetree::collision::CollisionOptions::default()
        .with_model_file(&args.model, &args.mesh_paths)
        .skip_missing_meshes();
    if let Ok(cmodel) = kinetree::collision::CollisionModel::from_model(&model, &options)
        && !cmodel.pairs().is_empty()
    {
        let mut cd = kinetree::collision::CollisionData::new(&cmodel);
        results.push((
            "collision_any",
            time((calls / 10).max(1), reps, |i| {
                let _ = cd.compute_placements(&model, &cmodel, &mut data, black_box(q(i)));
                let _ = black_box(kinetree::collision::any_collision(&cmodel, &mut cd));
            }),
        ));
        results.push((
            "collision_distances",
            time((calls / 10).max(1), reps, |i| {
                let _ = cd.compute_placements(&model, &cmodel, &mut data, black_box(q(i)));
                let _ = black_box(
                    kinetree::collision::compute_distances(&cmodel, &mut cd).map(|d| d.len()),
                );
            }),
        ));
    }

    if args.json {
        let map: serde_json::Map<String, serde_json::Value> = results
            .iter()
            .map(|(k, v)| ((*k).to_string(), serde_json::json!(v)))
            .collect();
        let pinocchio: serde_json::Map<String, serde_json::Value> = PINOCCHIO_NAMES
            .iter()
            .filter_map(|(ours, theirs)| {
                results
                    .iter()
                    .find(|(k, _)| k == ours)
                    .map(|(_, v)| ((*theirs).to_string(), serde_json::json!(v)))
            })
            .collect();
        let out = serde_json::json!({"model": model.name(), "nq": model.nq(), "nv": model.nv(), "ns_per_call": map, "pinocchio_ns_per_call": pinocchio});
        outln!("{out}")?;
    } else {
        outln!(
            "{} (nq = {}, nv = {}), {calls} calls x {reps} repetitions, median ns/call",
            model.name(),
            model.nq(),
            model.nv()
        )?;
        outln!("frame_jacobian is timed on '{}'", frame.name(&model)?)?;
        for (name, ns) in &results {
            outln!("  {name:<18} {ns:>10.1}")?;
        }
    }
    Ok(())
}
