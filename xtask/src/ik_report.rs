//! `cargo xtask ik-report [--targets N] [--seed S] [--set field=value]…`: the inverse-kinematics
//! quality bar.
//!
//! For panda (`panda_hand_tcp`, fingers excluded), ur5 (`tool0`) and kinova
//! (`j2s6s200_end_effector`): the reference files' `ik_targets` plus `N` (default 1000) seeded
//! random reachable targets (forward kinematics of random in-limit configurations; continuous
//! joints and joints with a range of 2π or more sampled in [-π, π]), each solved from its own
//! random in-limit start with `IkParams::default()` (5 ms budget). Success = position error
//! < 1e-6 m, orientation error < 1e-5 rad and every joint within its limits, all checked here
//! with a fresh forward kinematics. Prints per robot: success %, median / p95 / max time, mean
//! restarts and iterations (and the 99th percentile and maximum of the iterations, which do not
//! depend on the machine's load). `--set` overrides an `IkParams` field for experiments
//! (`time_budget_ms=0` removes the time budget).
//!
//! Timings need an optimised build: when xtask itself was built without optimisations, the task
//! re-runs itself through `cargo run --release`.

use anyhow::{Context, Result, bail};
use kinetree::kinematics::ik::{IkParams, IkSolver, IkTarget};
use kinetree::kinematics::spatial::rotation::log3;
use kinetree::kinematics::spatial::{DMat3, DVec3, Se3};
use kinetree::kinematics::{FrameId, KinematicsData, configuration, forward_kinematics};
use kinetree::model::{JointKind, Model, RootJoint};
use serde_json::Value;
use std::f64::consts::PI;
use std::time::{Duration, Instant};

/// The robots and their end effectors.
const ROBOTS: [&str; 3] = ["panda", "ur5", "kinova"];
/// The success test.
const POSITION_TOLERANCE: f64 = 1e-6;
const ORIENTATION_TOLERANCE: f64 = 1e-5;
/// The latency bar of the speed issue (#14): median and 95th percentile of one solve.
const MEDIAN_TARGET: Duration = Duration::from_micros(10);
const P95_TARGET: Duration = Duration::from_micros(100);

pub(crate) fn run(args: &[String]) -> Result<()> {
    let mut n = 1000usize;
    let mut seed = 1u64;
    let mut params = IkParams::default();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().context(format!("{a} needs a value"));
        match a.as_str() {
            "--targets" => n = value()?.parse().context("--targets")?,
            "--seed" => seed = value()?.parse().context("--seed")?,
            "--set" => set_param(&mut params, value()?)?,
            other => bail!(
                "unknown argument '{other}' (expected --targets N, --seed S, --set field=value)"
            ),
        }
    }
    if cfg!(debug_assertions) {
        // Timings of an unoptimised build mean nothing: run the optimised one.
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let status = std::process::Command::new(cargo)
            .current_dir(crate::project_root())
            .args([
                "run",
                "--quiet",
                "--release",
                "-p",
                "xtask",
                "--",
                "ik-report",
            ])
            .args(args)
            .status()
            .context("cannot run cargo")?;
        if !status.success() {
            bail!("the release ik-report failed");
        }
        return Ok(());
    }
    let changed = if params == IkParams::default() {
        "IkParams::default()".to_string()
    } else {
        format!("{params:?}")
    };
    println!(
        "IK report: reference targets + {n} random reachable targets per robot, random in-limit \
         starts, {changed}; success = position < 1e-6 m, orientation < 1e-5 rad, within limits\n"
    );
    println!(
        "| robot | targets | success % | median µs | p95 µs | max µs | mean restarts | mean iterations | p99 / max iterations | ns / iteration |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut all_ok = true;
    for robot in ROBOTS {
        let row = robot_report(robot, n, seed, &params)?;
        println!(
            "| {robot} | {} | {:.2} | {:.1} | {:.1} | {:.1} | {:.2} | {:.1} | {} / {} | {:.0} |",
            row.targets,
            100.0 * row.successes as f64 / row.targets as f64,
            micros(row.median),
            micros(row.p95),
            micros(row.max),
            row.mean_restarts,
            row.mean_iterations,
            row.p99_iterations,
            row.max_iterations,
            row.ns_per_iteration,
        );
        for f in &row.failures {
            println!("    failure: {f}");
        }
        all_ok &= row.successes * 1000 >= row.targets * 999
            && row.median <= MEDIAN_TARGET
            && row.p95 <= P95_TARGET;
    }
    println!(
        "\ntarget: >= 99.9 % success, median <= {} µs, p95 <= {} µs: {}",
        MEDIAN_TARGET.as_micros(),
        P95_TARGET.as_micros(),
        if all_ok { "met" } else { "NOT met" }
    );
    // Wall-clock times include the machine's scheduling pauses: say how busy it was.
    if let Ok(load) = std::fs::read_to_string("/proc/loadavg") {
        let load: Vec<&str> = load.split_whitespace().take(3).collect();
        println!(
            "load average {} (1, 5, 15 min) on {} CPUs",
            load.join(" "),
            std::thread::available_parallelism().map_or(1, usize::from)
        );
    }
    Ok(())
}

fn micros(d: Duration) -> f64 {
    d.as_secs_f64() * 1e6
}

/// One robot's results.
#[derive(Debug)]
pub(crate) struct RobotRow {
    pub(crate) targets: usize,
    pub(crate) successes: usize,
    median: Duration,
    p95: Duration,
    max: Duration,
    mean_restarts: f64,
    mean_iterations: f64,
    p99_iterations: usize,
    max_iterations: usize,
    /// Median over the solves of time / iterations (robust to the machine's hiccups).
    ns_per_iteration: f64,
    failures: Vec<String>,
}

/// Applies `--set field=value` to `params`.
fn set_param(params: &mut IkParams, assignment: &str) -> Result<()> {
    let (key, value) = assignment
        .split_once('=')
        .context("--set expects field=value")?;
    let float = || {
        value
            .parse::<f64>()
            .with_context(|| format!("{key}: not a number"))
    };
    let int = || {
        value
            .parse::<usize>()
            .with_context(|| format!("{key}: not an integer"))
    };
    match key {
        "position_tolerance" => params.position_tolerance = float()?,
        "orientation_tolerance" => params.orientation_tolerance = float()?,
        "max_iterations" => params.max_iterations = int()?,
        "max_iterations_per_try" => params.max_iterations_per_try = int()?,
        "max_restarts" => params.max_restarts = int()?,
        "time_budget_ms" => {
            let ms = float()?;
            params.time_budget = (ms > 0.0).then(|| Duration::from_secs_f64(ms * 1e-3));
        }
        "seed" => params.seed = value.parse().context("seed")?,
        "damping" => params.damping = float()?,
        "orientation_weight" => params.orientation_weight = float()?,
        "damping_floor" => params.damping_floor = float()?,
        "max_step" => params.max_step = float()?,
        "min_progress" => params.min_progress = float()?,
        "patience" => params.patience = int()?,
        other => bail!("unknown IkParams field '{other}'"),
    }
    Ok(())
}

/// SplitMix64: a tiny seeded generator, so the targets do not depend on any crate's RNG.
struct SplitMix(u64);

impl SplitMix {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A random configuration of the arm joints (the bodies in `arm`), the others neutral:
/// uniform within the limits; continuous joints and ranges of 2π or more in [-π, π].
fn random_arm_q(model: &Model, arm: &[usize], rng: &mut SplitMix) -> Result<Vec<f64>> {
    let mut q = configuration::neutral_configuration(model);
    for &b in arm {
        let body = &model.bodies()[b];
        let lim = &model.joint(body.joint.unwrap_or(0)).limits;
        let (lo, hi) = match body.kind {
            JointKind::Continuous => (-PI, PI),
            JointKind::Revolute if lim.upper - lim.lower >= 2.0 * PI || lim.upper <= lim.lower => {
                (-PI, PI)
            }
            JointKind::Revolute | JointKind::Prismatic => (lim.lower, lim.upper),
            other => bail!("ik-report samples 1-DoF arms only, found a {other} joint"),
        };
        q[body.idx_q] = lo + (hi - lo) * rng.next_f64();
    }
    Ok(q)
}

fn rotation_from_rows(v: &Value) -> Result<DMat3> {
    let r = |i: usize, j: usize| v[i][j].as_f64().context("rotation entry");
    Ok(DMat3::from_cols(
        DVec3::new(r(0, 0)?, r(1, 0)?, r(2, 0)?),
        DVec3::new(r(0, 1)?, r(1, 1)?, r(2, 1)?),
        DVec3::new(r(0, 2)?, r(1, 2)?, r(2, 2)?),
    ))
}

pub(crate) fn robot_report(
    robot: &str,
    n: usize,
    seed: u64,
    params: &IkParams,
) -> Result<RobotRow> {
    let dir = crate::project_root().join("tests/data/reference");
    let reference: Value = serde_json::from_str(&crate::read(&dir.join(format!("{robot}.json")))?)?;
    let urdf = dir.join(reference["urdf"].as_str().context("urdf")?);
    let model = Model::from_urdf_file(&urdf, RootJoint::Fixed)
        .with_context(|| format!("cannot load {}", urdf.display()))?;
    let ik = &reference["ik_targets"];
    let ee_name = ik["ee_link"].as_str().context("ee_link")?;
    let ee = FrameId::find(&model, ee_name)?;
    // The arm: the moving bodies on the path from the end effector to the root.
    let mut arm = Vec::new();
    let mut b = ee.body(&model)?.0;
    while b != 0 {
        if model.bodies()[b].nv > 0 {
            arm.push(b);
        }
        b = model.bodies()[b].parent;
    }
    arm.reverse();

    let mut data = KinematicsData::new(&model);
    let mut goals = Vec::new();
    for t in ik["targets"].as_array().context("targets")? {
        let p = &t["translation"];
        let translation = DVec3::new(
            p[0].as_f64().context("x")?,
            p[1].as_f64().context("y")?,
            p[2].as_f64().context("z")?,
        );
        goals.push(Se3::new(rotation_from_rows(&t["rotation"])?, translation));
    }
    let mut rng = SplitMix(
        seed ^ robot
            .bytes()
            .fold(0u64, |h, c| h.wrapping_mul(31) ^ c as u64),
    );
    for _ in 0..n {
        let q = random_arm_q(&model, &arm, &mut rng)?;
        forward_kinematics(&model, &mut data, &q)?;
        goals.push(*data.world_from(ee)?);
    }
    let starts = goals
        .iter()
        .map(|_| random_arm_q(&model, &arm, &mut rng))
        .collect::<Result<Vec<_>>>()?;

    let mut solver = IkSolver::new(&model, params.clone());
    let mut check = KinematicsData::new(&model);
    let mut times = Vec::with_capacity(goals.len());
    let mut iteration_counts = Vec::with_capacity(goals.len());
    let (mut successes, mut restarts, mut iterations) = (0usize, 0usize, 0usize);
    let mut failures = Vec::new();
    for (i, (goal, q0)) in goals.iter().zip(&starts).enumerate() {
        let target = IkTarget::new(ee, *goal);
        let t0 = Instant::now();
        let report = solver.solve(&model, &mut data, &target, q0)?;
        let dt = t0.elapsed();
        times.push(dt);
        restarts += report.restarts;
        iterations += report.iterations;
        iteration_counts.push(report.iterations);
        // Independent check of the answer.
        forward_kinematics(&model, &mut check, report.q)?;
        let x = check.world_from(ee)?;
        let pos = (x.translation - goal.translation).length();
        let ori = log3(&(goal.rotation.transpose() * x.rotation)).length();
        let within = configuration::is_within_limits(&model, report.q, 0.0)?;
        if pos < POSITION_TOLERANCE && ori < ORIENTATION_TOLERANCE && within {
            successes += 1;
        } else {
            failures.push(format!(
                "target {i}: {:?}, position {pos:.2e} m, orientation {ori:.2e} rad, within limits \
                 {within}, {} restarts, {:.0} µs",
                report.status,
                report.restarts,
                micros(dt)
            ));
        }
    }
    let mut sorted = times.clone();
    sorted.sort();
    let at = |f: f64| sorted[((sorted.len() as f64 - 1.0) * f).round() as usize];
    let per_solve_iterations = iteration_counts.clone();
    iteration_counts.sort_unstable();
    let p99 = iteration_counts[((iteration_counts.len() as f64 - 1.0) * 0.99).round() as usize];
    Ok(RobotRow {
        targets: goals.len(),
        successes,
        median: at(0.5),
        p95: at(0.95),
        max: *sorted.last().context("no targets")?,
        mean_restarts: restarts as f64 / goals.len() as f64,
        mean_iterations: iterations as f64 / goals.len() as f64,
        p99_iterations: p99,
        max_iterations: *iteration_counts.last().context("no targets")?,
        ns_per_iteration: {
            let mut per: Vec<f64> = times
                .iter()
                .zip(&per_solve_iterations)
                .map(|(t, i)| t.as_secs_f64() * 1e9 / (*i).max(1) as f64)
                .collect();
            per.sort_by(f64::total_cmp);
            per[per.len() / 2]
        },
        failures,
    })
}

#[cfg(test)]
mod tests {
    /// The reference targets converge on every arm (success rate only; timings are for the
    /// release report).
    #[test]
    fn reference_targets_converge() {
        for robot in super::ROBOTS {
            // No time budget: an unoptimised build under load must not fail on time.
            let params = super::IkParams {
                time_budget: None,
                ..Default::default()
            };
            let row = super::robot_report(robot, 0, 1, &params).unwrap();
            assert_eq!(row.successes, row.targets, "{robot}: {:?}", row.failures);
        }
    }
}
