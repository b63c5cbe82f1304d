//! `kinetree bench <model>`: times each algorithm on random in-limit states of the user's own
//! robot (what MuJoCo's testspeed is to MuJoCo).
//!
//! Each algorithm runs `--calls` times, cycling through 1000 random states, after a warm-up of
//! as many calls; this is repeated `--repetitions` times and the median ns/call is
//! printed. With `--json` the output is
//! `{"model", "nq", "nv", "ns_per_call": {"fk", "fk_frames", "frame_jacobian", "joint_jacobians",
//! "joint_jacobians_without_links", "rnea", "nle", "crba", "aba", "minv", "rnea_derivatives", "aba_derivatives", "collision_any",
//! "collision_distances", "collision_distances_tol1e-6"}}` (the collision keys
//! only for models with collision geometry; the last is the same all-pairs distance call at
//! coal's default distance tolerance of 1e-6 instead of kinetree's 1e-8, see
//! `CollisionModel::set_distance_tolerance`; meshes are looked up next to the model file, then
//! in the `--mesh-path` directories, and skipped when missing); the keys stay stable so scripts can compare runs.
//! `"pinocchio_ns_per_call"` repeats the like-for-like timings under the names of Pinocchio's
//! anchor benchmark (`fk+frames`, `jacobians`, `rnea`, `nle`, `crba`, `aba`, `minverse`,
//! `rnea_derivatives`, `aba_derivatives`), so a side-by-side script needs no mapping. kinetree's
//! `fk` also places every link, so it has no Pinocchio twin (Pinocchio's `fk` places the joints
//! only); its `fk_frames` is Pinocchio's `fk+frames`. Likewise `joint_jacobians` also places every
//! link, and Pinocchio's `jacobians` (`computeJointJacobians`) is kinetree's
//! `joint_jacobians_without_links`, which places the bodies only.
//! Velocities, accelerations and torques are drawn uniformly in [-1, 1].
//! `--batch N` times the batched entry points instead (`bench_batch.rs`).

use anyhow::Result;
use kinetree::dynamics::{
    DerivativesData, DynamicsData, aba, aba_derivatives, crba, mass_matrix_inverse,
    nonlinear_effects, rnea, rnea_derivatives,
};
use kinetree::kinematics::configuration::random_configuration;
use kinetree::kinematics::spatial::Motion;
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, compute_joint_jacobians,
    compute_joint_jacobians_without_links, forward_kinematics, update_frame_placements,
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
    pub(crate) model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint named `root_joint`.
    #[arg(long)]
    floating: bool,
    /// Calls per timed repetition.
    #[arg(long, default_value_t = 100_000)]
    pub(crate) calls: usize,
    /// Timed repetitions (the median is reported).
    #[arg(long, default_value_t = 7)]
    pub(crate) repetitions: usize,
    /// Seed of the random states.
    #[arg(long, default_value_t = 42)]
    pub(crate) seed: u64,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
    /// A directory where collision meshes are looked up (`package://` and relative names) after
    /// the model file's directory, as in `collide`; repeatable.
    #[arg(long = "mesh-path")]
    pub(crate) mesh_paths: Vec<PathBuf>,
    /// Run even when --calls × (--repetitions + 1) exceeds the limit of 10⁹ calls per algorithm.
    #[arg(long)]
    no_limit: bool,
    /// Time the batched entry points on batches of this many states instead (ns/state beside
    /// the one-state path; `--calls` is then the states per repetition).
    #[arg(long, value_name = "N")]
    pub(crate) batch: Option<usize>,
    /// Threads of the parallel batched timings (default: every core).
    #[arg(long, value_name = "T")]
    pub(crate) threads: Option<usize>,
}

/// kinetree's timings that time the same work as a case of Pinocchio's anchor benchmark, with
/// that case's name there.
const PINOCCHIO_NAMES: [(&str, &str); 9] = [
    ("fk_frames", "fk+frames"),
    ("joint_jacobians_without_links", "jacobians"),
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

/// Calls `f(i)` for `i` in `0..calls`, in chunks, checking for Ctrl-C between chunks (not
/// between calls, so the timed loop stays bare); false when interrupted.
fn calls_until_interrupted(calls: usize, f: &mut impl FnMut(usize)) -> bool {
    const CHUNK: usize = 4096;
    let mut start = 0;
    while start < calls {
        let end = (start + CHUNK).min(calls);
        for i in start..end {
            f(i);
        }
        if crate::interrupt::requested() {
            return false;
        }
        start = end;
    }
    true
}

/// Median ns/call of `f(i)` over `reps` repetitions of `calls` calls (after a warm-up); `None`
/// when Ctrl-C stopped it.
fn time(calls: usize, reps: usize, mut f: impl FnMut(usize)) -> Option<f64> {
    // Warm up for a whole repetition: caches, branch predictors and the clock settle.
    if !calls_until_interrupted(calls.max(1), &mut f) {
        return None;
    }
    let mut per_call = Vec::with_capacity(reps.max(1));
    for _ in 0..reps.max(1) {
        let start = Instant::now();
        if !calls_until_interrupted(calls, &mut f) {
            return None;
        }
        per_call.push(start.elapsed().as_secs_f64() * 1e9 / calls.max(1) as f64);
    }
    per_call.sort_by(f64::total_cmp);
    Some(per_call[per_call.len() / 2])
}

/// The timings measured so far, in order, and the progress shown on a terminal.
struct Timings {
    results: Vec<(&'static str, f64)>,
    /// The algorithm Ctrl-C stopped, if any (later ones are skipped).
    interrupted: Option<&'static str>,
    bar: indicatif::ProgressBar,
}

impl Timings {
    fn new(algorithms: u64) -> Self {
        // On a terminal only (indicatif draws nothing when stderr is not one).
        let bar = indicatif::ProgressBar::new(algorithms);
        bar.set_style(
            indicatif::ProgressStyle::with_template("timing {msg:<20} [{bar:20}] {pos}/{len}")
                .map_or_else(
                    |_| indicatif::ProgressStyle::default_bar(),
                    |s| s.progress_chars("=> "),
                ),
        );
        Self {
            results: Vec::new(),
            interrupted: None,
            bar,
        }
    }

    /// Times `f` as `name` unless an earlier timing was interrupted.
    fn time(&mut self, name: &'static str, calls: usize, reps: usize, f: impl FnMut(usize)) {
        if self.interrupted.is_some() {
            return;
        }
        self.bar.set_message(name);
        match time(calls, reps, f) {
            Some(ns) => self.results.push((name, ns)),
            None => self.interrupted = Some(name),
        }
        self.bar.inc(1);
    }
}

/// The link farthest from the root (most joints on its path): the frame whose Jacobian is timed.
pub(crate) fn deepest_link(model: &Model) -> usize {
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
    if let Some(n) = args.batch {
        return super::bench_batch::run(args, &model, n);
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
    crate::interrupt::watch();
    let mut timings = Timings::new(12);
    timings.time("fk", calls, reps, |i| {
        let _ = forward_kinematics(&model, &mut data, black_box(q(i)));
        black_box(&data);
    });
    timings.time("fk_frames", calls, reps, |i| {
        let _ = forward_kinematics(&model, &mut data, black_box(q(i)));
        let _ = update_frame_placements(&model, &mut data);
        black_box(&data);
    });
    timings.time("frame_jacobian", calls, reps, |i| {
        let _ = compute_frame_jacobian(
            &model,
            &mut data,
            black_box(q(i)),
            frame,
            ReferenceFrame::LocalWorldAligned,
            &mut jac,
        );
        black_box(&jac);
    });
    timings.time("joint_jacobians", calls, reps, |i| {
        let _ = compute_joint_jacobians(&model, &mut data, black_box(q(i)));
        black_box(&data);
    });
    timings.time("joint_jacobians_without_links", calls, reps, |i| {
        let _ = compute_joint_jacobians_without_links(&model, &mut data, black_box(q(i)));
        black_box(&data);
    });

    let mut dd = DynamicsData::new(&model);
    let x = |i: usize| &vectors[i % vectors.len()];
    let y = |i: usize| &vectors[(i + 500) % vectors.len()];
    timings.time("rnea", calls, reps, |i| {
        let _ = black_box(
            rnea(&model, &mut dd, black_box(q(i)), x(i), y(i)).map(|t| t.first().copied()),
        );
    });
    timings.time("nle", calls, reps, |i| {
        let _ = black_box(
            nonlinear_effects(&model, &mut dd, black_box(q(i)), x(i)).map(|t| t.first().copied()),
        );
    });
    timings.time("crba", calls, reps, |i| {
        let _ = black_box(crba(&model, &mut dd, black_box(q(i))).map(|m| m.first().copied()));
    });
    timings.time("aba", calls, reps, |i| {
        let _ = black_box(
            aba(&model, &mut dd, black_box(q(i)), x(i), y(i)).map(|a| a.first().copied()),
        );
    });
    timings.time("minv", calls, reps, |i| {
        let _ = black_box(
            mass_matrix_inverse(&model, &mut dd, black_box(q(i))).map(|m| m.first().copied()),
        );
    });

    let mut derivatives = DerivativesData::new(&model);
    timings.time("rnea_derivatives", calls, reps, |i| {
        let _ = black_box(
            rnea_derivatives(&model, &mut derivatives, black_box(q(i)), x(i), y(i))
                .map(|d| d.dtau_dq[0]),
        );
    });
    timings.time("aba_derivatives", calls, reps, |i| {
        let _ = black_box(
            aba_derivatives(&model, &mut derivatives, black_box(q(i)), x(i), y(i))
                .map(|d| d.dddq_dq[0]),
        );
    });

    let options = kinetree::collision::CollisionOptions::default()
        .with_model_file(&args.model, &args.mesh_paths)
        .skip_missing_meshes();
    if let Ok(mut cmodel) = kinetree::collision::CollisionModel::from_model(&model, &options)
        && !cmodel.pairs().is_empty()
    {
        let mut cd = kinetree::collision::CollisionData::new(&cmodel);
        timings.bar.inc_length(3);
        timings.time("collision_any", (calls / 10).max(1), reps, |i| {
            let _ = cd.compute_placements(&model, &cmodel, &mut data, black_box(q(i)));
            let _ = black_box(kinetree::collision::any_collision(&cmodel, &mut cd));
        });
        timings.time("collision_distances", (calls / 10).max(1), reps, |i| {
            let _ = cd.compute_placements(&model, &cmodel, &mut data, black_box(q(i)));
            let _ = black_box(
                kinetree::collision::compute_distances(&cmodel, &mut cd).map(|d| d.len()),
            );
        });
        // The same call at coal's default tolerance, for a like-for-like comparison.
        cmodel.set_distance_tolerance(1e-6)?;
        timings.time(
            "collision_distances_tol1e-6",
            (calls / 10).max(1),
            reps,
            |i| {
                let _ = cd.compute_placements(&model, &cmodel, &mut data, black_box(q(i)));
                let _ = black_box(
                    kinetree::collision::compute_distances(&cmodel, &mut cd).map(|d| d.len()),
                );
            },
        );
    }

    timings.bar.finish_and_clear();
    let results = timings.results;
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
        let width = results
            .iter()
            .map(|(name, _)| name.len())
            .max()
            .unwrap_or(0);
        for (name, ns) in &results {
            outln!("  {name:<width$} {ns:>10.1}")?;
        }
    }
    if let Some(name) = timings.interrupted {
        return Err(crate::interrupt::Interrupted {
            what: format!(
                "printed the {} timing(s) finished before '{name}'; '{name}' and the rest were not measured",
                results.len()
            ),
        }
        .into());
    }
    Ok(())
}
