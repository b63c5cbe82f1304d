//! `kinetree ik <model> --frame F --target x,y,z[,roll,pitch,yaw]`: inverse kinematics of one
//! frame; prints the solution by joint name and the solver's report.
//!
//! Only the joints on the path from the root to the frame move (the solver's default); the others
//! keep their start value.

use anyhow::{Context, Result, bail};
use kinetree::kinematics::ik::{IkParams, IkSolver, IkStatus, IkTarget};
use kinetree::kinematics::{FrameId, KinematicsData};
use kinetree::spatial::{DQuat, DVec3, Se3};
use std::path::PathBuf;

/// Arguments of `kinetree ik`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint named `root_joint`.
    #[arg(long)]
    floating: bool,
    /// The link or named frame to place.
    #[arg(long)]
    frame: String,
    /// Target position `x,y,z` (m, world frame), optionally followed by URDF `roll,pitch,yaw` (rad).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    target: Vec<f64>,
    /// Target orientation as a quaternion `x,y,z,w` (instead of roll, pitch, yaw).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    quat: Option<Vec<f64>>,
    /// Reach the position only; the orientation is free.
    #[arg(long)]
    position_only: bool,
    /// Seed of the random restarts (the answer depends only on the target, the start and this
    /// seed: the command has no wall-clock budget, its 10 000-step budget bounds a solve).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Start configuration `name=value,…` (otherwise the neutral configuration, clamped into the
    /// joint limits).
    #[arg(long)]
    start: Option<String>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Units of joint values and poses given and printed: `si` (m, rad) or `mm-deg`.
    #[arg(long, value_enum, default_value_t = super::UnitsArg::Si)]
    units: super::UnitsArg,
}

/// Solves and prints.
pub(crate) fn run(args: &Args) -> Result<()> {
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    let frame = FrameId::find(&model, &args.frame)?;
    let t = &args.target;
    if !(t.len() == 3 || t.len() == 6) {
        bail!(
            "--target takes x,y,z or x,y,z,roll,pitch,yaw (got {} numbers)",
            t.len()
        );
    }
    let units = args.units.units();
    let mm = units.length.per_meter();
    let angle = |x: f64| {
        if args.units == super::UnitsArg::MmDeg {
            x.to_radians()
        } else {
            x
        }
    };
    let position = DVec3::new(t[0], t[1], t[2]) / mm;
    let target = if args.position_only {
        IkTarget::position(frame, position)
    } else {
        let rotation = match (&args.quat, t.len()) {
            (Some(q), 3) if q.len() == 4 => {
                let quat = DQuat::from_xyzw(q[0], q[1], q[2], q[3]);
                if !(quat.length() > 0.0 && quat.is_finite()) {
                    bail!("--quat must be a nonzero quaternion x,y,z,w");
                }
                Se3::from_quat(quat.normalize()).rotation
            }
            (Some(_), 3) => bail!("--quat takes four numbers x,y,z,w"),
            (Some(_), _) => bail!(
                "give the orientation either as roll,pitch,yaw in --target or as --quat, not both"
            ),
            (None, 6) => Se3::from_rpy(angle(t[3]), angle(t[4]), angle(t[5])).rotation,
            (None, _) => bail!(
                "give an orientation (roll,pitch,yaw in --target, or --quat) or --position-only"
            ),
        };
        IkTarget::new(frame, Se3::new(rotation, position))
    };
    let mut q0 = super::parse_named_in(&model, args.start.as_deref(), false, args.units)?;
    if args.start.is_some() {
        super::note_outside_limits(&model, &q0, "--start");
    } else {
        // The neutral configuration can lie outside the limits (the Panda's joint 4): start from
        // the nearest configuration within them instead.
        let neutral = q0.clone();
        kinetree::kinematics::configuration::clamp(&model, &mut q0)?;
        if neutral != q0 {
            eprintln!(
                "note: the neutral configuration is outside the joint limits; starting from it clamped into them"
            );
        }
    }
    // No wall-clock budget: a budget makes the answer depend on the machine's load (the same
    // command could print another solution when the machine is busy).
    let params = IkParams {
        seed: args.seed,
        time_budget: None,
        ..IkParams::default()
    };
    let mut solver = IkSolver::new(&model, params);
    let mut data = KinematicsData::new(&model);
    let report = solver
        .solve(&model, &mut data, &target, &q0)
        .context("inverse kinematics failed")?;
    let status = match report.status {
        IkStatus::Converged => "converged".to_string(),
        IkStatus::BestEffort { residual } => format!("best_effort (residual {residual:.3e})"),
        IkStatus::Failed => "failed".to_string(),
    };
    let mut q_out = report.q.to_vec();
    model.convert_q(&mut q_out, units, false)?;
    let (position_error, orientation_error) = (
        report.position_error * mm,
        if args.units == super::UnitsArg::MmDeg {
            report.orientation_error.to_degrees()
        } else {
            report.orientation_error
        },
    );
    let (length_unit, angle_unit) = (units.length.as_str(), units.angle.as_str());
    let values: Vec<(String, Vec<f64>)> = model
        .moving_user_joints()
        .map(|j| {
            (
                model.user_joints()[j].name.clone(),
                q_out[model.user_joint_q_range(j)].to_vec(),
            )
        })
        .collect();
    if args.json {
        let q: serde_json::Map<String, serde_json::Value> = values
            .iter()
            .map(|(n, v)| {
                (
                    n.clone(),
                    if v.len() == 1 {
                        serde_json::json!(v[0])
                    } else {
                        serde_json::json!(v)
                    },
                )
            })
            .collect();
        let status_key = match report.status {
            IkStatus::Converged => "converged",
            IkStatus::BestEffort { .. } => "best_effort",
            IkStatus::Failed => "failed",
        };
        let out = serde_json::json!({
            "status": status_key, "q": q,
            "position_error": position_error, "orientation_error": orientation_error,
            "units": { "length": length_unit, "angle": angle_unit },
            "iterations": report.iterations, "restarts": report.restarts,
            "elapsed_us": report.elapsed.as_secs_f64() * 1e6,
        });
        outln!("{out}")?;
    } else {
        outln!("status: {status}")?;
        outln!(
            "position error {:.3e} {length_unit}, orientation error {:.3e} {angle_unit}, {} iterations, {} restart{}, {:.1} µs",
            position_error,
            orientation_error,
            report.iterations,
            report.restarts,
            if report.restarts == 1 { "" } else { "s" },
            report.elapsed.as_secs_f64() * 1e6
        )?;
        outln!("q:")?;
        for (n, v) in &values {
            let x: Vec<String> = v.iter().map(|x| format!("{x:.9}")).collect();
            outln!("  {n:<28} {}", x.join(" "))?;
        }
    }
    Ok(())
}
