//! `kinetree simulate <model> --duration 2 --dt 1e-3`: integrates the equations of motion from a
//! given state under constant torques and gravity, prints the final state and the energy
//! balance, and optionally plots joint positions and energy over time.

use crate::plot::{Series, chart, document};
use anyhow::{Context, Result, bail};
use kinetree::dynamics::{
    DynamicsData, Integrator, JointTerms, LimitModel, apply_hard_stops, limited_coordinates,
    mechanical_energy, step,
};
use kinetree::spatial::Readable;
use std::path::PathBuf;

/// Arguments of `kinetree simulate`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint named `root_joint`.
    #[arg(long)]
    floating: bool,
    /// Simulated time (s).
    #[arg(long, default_value_t = 2.0)]
    duration: f64,
    /// Time step (s).
    #[arg(long, default_value_t = 1e-3)]
    dt: f64,
    /// Initial joint positions `name=value,…` (neutral otherwise).
    #[arg(long)]
    q: Option<String>,
    /// Initial joint velocities `name=value,…` (zero otherwise).
    #[arg(long)]
    v: Option<String>,
    /// Constant joint torques `name=value,…` (zero otherwise).
    #[arg(long)]
    tau: Option<String>,
    /// `rk4` (default) or `euler` (semi-implicit).
    #[arg(long, default_value = "rk4")]
    integrator: String,
    /// Leave the joints' damping, friction and armature out (rigid-body dynamics only). By
    /// default a simulation uses them (URDF `<dynamics>`), as the real machine has them.
    #[arg(long, alias = "ignore-joint-dynamics")]
    no_joint_dynamics: bool,
    /// What happens at a joint's position limit: `ignore` (default: the limits are not part of
    /// the dynamics; every violation is reported) or `stop`, an inelastic hard stop after every
    /// step (the coordinate is put back on its limit and an impulse at that joint removes its
    /// outward velocity, restitution 0; the energy lost is reported).
    #[arg(long, default_value = "ignore", value_name = "ignore|stop")]
    joint_limits: String,
    /// Write an SVG plot of joint positions and mechanical energy over time.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Run even when --duration / --dt exceeds the limit of 10⁹ steps.
    #[arg(long)]
    no_limit: bool,
    /// Write the trajectory (about 1000 samples) as JSON for `kinetree view --trajectory`:
    /// `{"model": name, "trajectory": [{"t": s, "q": {"joint": value, …}}, …]}`.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// The most steps run without --no-limit.
const MAX_STEPS: f64 = 1e9;

/// Runs the simulation and reports.
pub(crate) fn run(args: &Args) -> Result<()> {
    if !(args.dt.is_finite() && args.dt > 0.0 && args.duration.is_finite() && args.duration >= 0.0)
    {
        bail!("--dt must be positive and --duration non-negative");
    }
    let steps = (args.duration / args.dt).round();
    if steps > MAX_STEPS && !args.no_limit {
        bail!(
            "--duration {:e} / --dt {:e} is {steps:.3e} steps, more than the limit of {MAX_STEPS:e}; lengthen --dt, shorten --duration, or pass --no-limit",
            args.duration,
            args.dt
        );
    }
    if steps >= usize::MAX as f64 {
        bail!("--duration / --dt is {steps:.3e} steps, more than this machine can count");
    }
    let integrator = match args.integrator.as_str() {
        "rk4" => Integrator::RungeKutta4,
        "euler" => Integrator::SemiImplicitEuler,
        other => bail!("unknown integrator '{other}' (rk4 or euler)"),
    };
    let limit_model = match args.joint_limits.as_str() {
        "ignore" => LimitModel::Ignore,
        "stop" => LimitModel::InelasticStop,
        other => bail!("unknown --joint-limits '{other}' (ignore or stop)"),
    };
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    let mut q = super::parse_named(&model, args.q.as_deref(), false)?;
    let mut v = super::parse_named(&model, args.v.as_deref(), true)?;
    let tau = super::parse_named(&model, args.tau.as_deref(), true)?;
    let terms = if args.no_joint_dynamics {
        JointTerms::Ignored
    } else {
        JointTerms::FromModel
    };
    let mut data = DynamicsData::with_joint_terms(&model, terms);
    // Finite, non-negative and below usize::MAX (checked above).
    let steps = steps as usize;
    let e0 = mechanical_energy(&model, &mut data, &q, &v)?;
    // Positions of the 1-DoF joints (the plot's curves) and energy, sampled about 1000 times.
    let every = (steps / 1000).max(1);
    // By user joint: a composite joint is one joint (its pieces are not listed on their own).
    let plotted: Vec<usize> = model
        .moving_user_joints()
        .filter(|&j| model.user_joint_q_range(j).len() == 1)
        .take(10)
        .collect();
    let mut curves: Vec<Vec<(f64, f64)>> = vec![Vec::new(); plotted.len()];
    let mut energy = vec![(0.0, e0)];
    let record = |t: f64, q: &[f64], curves: &mut Vec<Vec<(f64, f64)>>| {
        for (c, &j) in curves.iter_mut().zip(&plotted) {
            c.push((t, q[model.user_joint_q_range(j).start]));
        }
    };
    record(0.0, &q, &mut curves);
    let mut limits = LimitLog::new(&model, &q);
    let mut dissipated_by_stops = 0.0;
    let mut samples: Vec<(f64, Vec<f64>)> = Vec::new();
    if args.out.is_some() {
        samples.push((0.0, q.clone()));
    }
    let start = std::time::Instant::now();
    // Progress on a terminal (hidden otherwise), updated about 200 times.
    let bar = indicatif::ProgressBar::new(steps as u64);
    bar.set_style(super::progress_style(
        "simulating [{bar:40}] {pos}/{len} steps, {rate}, eta {eta}",
    ));
    let tick = (steps / 200).max(1);
    // Ctrl-C stops after the current step; what was simulated is still reported and written.
    crate::interrupt::watch();
    let mut done = steps;
    for k in 1..=steps {
        if k % tick == 0 {
            bar.set_position(k as u64);
        }
        if crate::interrupt::requested() {
            done = k - 1;
            let t = done as f64 * args.dt;
            if samples.last().is_some_and(|(last, _)| *last < t) {
                samples.push((t, q.clone()));
            }
            if energy.last().is_some_and(|(last, _)| *last < t) {
                record(t, &q, &mut curves);
                energy.push((t, mechanical_energy(&model, &mut data, &q, &v)?));
            }
            break;
        }
        if let Err(e) = step(&model, &mut data, integrator, &mut q, &mut v, &tau, args.dt) {
            let largest = |x: &[f64]| x.iter().fold(0.0f64, |m, y| m.max(y.abs()));
            let (qmax, vmax) = (largest(&q), largest(&v));
            let e = anyhow::Error::new(e);
            // A state that has run away makes the mass matrix numerically singular (or
            // overflows): say so rather than blaming massless links.
            // More than one radian (or metre) per step, or far beyond any joint range.
            let e = if qmax > 1e6 || vmax * args.dt > 1.0 || !(qmax.is_finite() && vmax.is_finite())
            {
                e.context(format!(
                    "the simulation diverged (largest |q| = {qmax:.3e}, largest |v| = {vmax:.3e}); try a smaller --dt or a smaller initial velocity"
                ))
            } else {
                e
            };
            return Err(e.context(format!(
                "step {k} (t = {:.6} s)",
                Readable(k as f64 * args.dt)
            )));
        }
        limits.record(k as f64 * args.dt, &q);
        if limit_model == LimitModel::InelasticStop {
            dissipated_by_stops += apply_hard_stops(&model, &mut data, &mut q, &mut v)
                .with_context(|| format!("hard stop after step {k}"))?
                .dissipated;
        }
        if k % every == 0 || k == steps {
            let t = k as f64 * args.dt;
            record(t, &q, &mut curves);
            if args.out.is_some() {
                samples.push((t, q.clone()));
            }
            energy.push((t, mechanical_energy(&model, &mut data, &q, &v)?));
        }
    }
    bar.finish_and_clear();
    let elapsed = start.elapsed();
    let e1 = mechanical_energy(&model, &mut data, &q, &v)?;
    outln!(
        "{}: {done} steps of {} s ({:?}) in {:.3} s wall ({:.2} µs/step)",
        model.name(),
        args.dt,
        integrator,
        elapsed.as_secs_f64(),
        elapsed.as_secs_f64() * 1e6 / done.max(1) as f64
    )?;
    outln!(
        "{}",
        if args.no_joint_dynamics {
            "joint damping, friction and armature: off (--no-joint-dynamics)".to_string()
        } else {
            joint_terms_line(&model)
        }
    )?;
    outln!(
        "mechanical energy: {e0:.9} J -> {e1:.9} J (change {:.3e} J, relative {:.3e})",
        e1 - e0,
        (e1 - e0) / e0.abs().max(1e-300)
    )?;
    limits.print(&model, limit_model, dissipated_by_stops)?;
    outln!("final q:")?;
    for j in model.moving_user_joints() {
        let x: Vec<String> = q[model.user_joint_q_range(j)]
            .iter()
            .map(|x| format!("{x:.6}"))
            .collect();
        outln!("  {:<28} {}", model.user_joints()[j].name, x.join(" "))?;
    }
    if let Some(path) = &args.out {
        let trajectory: Vec<serde_json::Value> = samples
            .iter()
            .map(|(t, q)| {
                // Every joint that owns coordinates: independent mimic joints included (a
                // coupled follower owns none and follows its leader on playback).
                let by_name: serde_json::Map<String, serde_json::Value> = model
                    .moving_user_joints()
                    .map(|j| {
                        let x = &q[model.user_joint_q_range(j)];
                        let value = if x.len() == 1 {
                            serde_json::json!(x[0])
                        } else {
                            serde_json::json!(x)
                        };
                        (model.user_joints()[j].name.clone(), value)
                    })
                    .collect();
                serde_json::json!({"t": t, "q": by_name})
            })
            .collect();
        let doc = serde_json::json!({"model": model.name(), "trajectory": trajectory});
        std::fs::write(path, doc.to_string())
            .with_context(|| format!("cannot write {}", path.display()))?;
        outln!("trajectory written to {}", path.display())?;
    }
    if let Some(path) = &args.plot {
        let names: Vec<&str> = plotted
            .iter()
            .map(|&j| model.user_joints()[j].name.as_str())
            .collect();
        let joints: Vec<Series<'_>> = names
            .iter()
            .zip(curves)
            .map(|(n, points)| Series { name: n, points })
            .collect();
        let svg = document(900.0, 620.0, |svg| {
            chart(
                svg,
                (0.0, 0.0, 900.0, 320.0),
                &format!("{}: joint positions", model.name()),
                "time (s)",
                "q (rad or m)",
                &joints,
            );
            chart(
                svg,
                (0.0, 320.0, 900.0, 300.0),
                "mechanical energy",
                "time (s)",
                "energy (J)",
                &[Series {
                    name: "kinetic + potential",
                    points: energy,
                }],
            );
        });
        std::fs::write(path, svg).with_context(|| format!("cannot write {}", path.display()))?;
        outln!("plot written to {}", path.display())?;
    }
    if done < steps {
        return Err(crate::interrupt::Interrupted {
            what: format!(
                "stopped after {done} of {steps} steps (t = {} s); the report{} cover those steps",
                Readable(done as f64 * args.dt),
                if args.out.is_some() || args.plot.is_some() {
                    " and the files written"
                } else {
                    ""
                }
            ),
        }
        .into());
    }
    Ok(())
}

/// The line saying that the joints' damping, friction and armature are on, and how many joints
/// have any.
fn joint_terms_line(model: &kinetree::model::Model) -> String {
    let with = model
        .moving_user_joints()
        .filter(|&u| {
            model.user_joints()[u].joints.clone().any(|j| {
                let d = model.joint(j).dynamics;
                d.damping != 0.0 || d.friction != 0.0 || d.armature != 0.0
            })
        })
        .count();
    format!(
        "joint damping, friction and armature: on, from the model ({with} of {} moving joints have some; --no-joint-dynamics for rigid-body dynamics only)",
        model.moving_user_joints().count()
    )
}

/// Every excursion of a limited coordinate beyond its position limits during a run.
struct LimitLog {
    /// Per limited coordinate: `(idx_q, lower, upper, joint)`.
    coordinates: Vec<(usize, f64, f64, usize)>,
    /// Per limited coordinate: `(first time out, steps out, largest excess, value at it)`.
    out: Vec<Option<(f64, usize, f64, f64)>>,
}

impl LimitLog {
    fn new(model: &kinetree::model::Model, q0: &[f64]) -> Self {
        let coordinates: Vec<_> = limited_coordinates(model)
            .map(|(iq, _, lo, hi, j)| (iq, lo, hi, j))
            .collect();
        let mut log = Self {
            out: vec![None; coordinates.len()],
            coordinates,
        };
        log.record(0.0, q0);
        log
    }

    /// Notes every coordinate of `q` outside its limits at time `t`.
    fn record(&mut self, t: f64, q: &[f64]) {
        for (&(iq, lo, hi, _), out) in self.coordinates.iter().zip(&mut self.out) {
            let excess = (lo - q[iq]).max(q[iq] - hi);
            if excess > 0.0 {
                let entry = out.get_or_insert((t, 0, 0.0, q[iq]));
                entry.1 += 1;
                if excess > entry.2 {
                    (entry.2, entry.3) = (excess, q[iq]);
                }
            }
        }
    }

    /// Prints one line per coordinate that left its limits (or that none did).
    fn print(
        &self,
        model: &kinetree::model::Model,
        limit_model: LimitModel,
        dissipated: f64,
    ) -> Result<()> {
        let count = self.out.iter().flatten().count();
        match limit_model {
            LimitModel::InelasticStop => outln!(
                "joint limits: inelastic hard stops (--joint-limits stop); {count} of {} limited coordinates reached a stop, {dissipated:.6e} J dissipated by the stops",
                self.coordinates.len()
            )?,
            _ => outln!(
                "joint limits: not enforced (--joint-limits stop adds hard stops); {count} of {} limited coordinates left their limits",
                self.coordinates.len()
            )?,
        }
        for (&(iq, lo, hi, j), out) in self.coordinates.iter().zip(&self.out) {
            let Some((first, steps, excess, value)) = out else {
                continue;
            };
            // Named by user joint: a composite joint's piece is `composite[k]`.
            let user = model.user_joint_of(j);
            let name = &model.user_joints()[user].name;
            let range = model.user_joint_q_range(user);
            let coordinate = if range.len() > 1 {
                format!("{name}[{}]", iq - range.start)
            } else {
                name.clone()
            };
            outln!(
                "  {coordinate:<28} limits [{lo}, {hi}]: out from t = {first:.4} s for {steps} steps, worst {value:.6} ({excess:.3e} beyond)"
            )?;
        }
        Ok(())
    }
}
