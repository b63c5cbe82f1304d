//! `kinetree dynamics <model> --q … --v … (--a … | --tau …)`: inverse dynamics τ, the mass matrix
//! M and forward dynamics q̈ of one state, by joint name.

use anyhow::{Result, bail};
use kinetree::dynamics::{DynamicsData, JointTerms, aba, crba, rnea};
use std::fmt::Write;
use std::path::PathBuf;

/// Arguments of `kinetree dynamics`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint named `root_joint`.
    #[arg(long)]
    floating: bool,
    /// Joint positions `name=value,…` (rad, m; multi-DoF joints `a:b:c`); unnamed joints are at
    /// their neutral value.
    #[arg(long)]
    q: Option<String>,
    /// Joint velocities `name=value,…` (default zero).
    #[arg(long)]
    v: Option<String>,
    /// Joint accelerations `name=value,…`: prints the torques τ = RNEA(q, v, a).
    #[arg(long)]
    a: Option<String>,
    /// Joint torques `name=value,…`: prints the accelerations q̈ = ABA(q, v, τ).
    #[arg(long)]
    tau: Option<String>,
    /// Add the joints' damping, friction and armature (URDF `<dynamics>`) to the dynamics. By
    /// default they are left out: the rigid-body quantities, as Pinocchio computes them.
    #[arg(long)]
    joint_dynamics: bool,
    /// The old spelling of the default (rigid-body dynamics), still accepted.
    #[arg(long, hide = true, conflicts_with = "joint_dynamics")]
    ignore_joint_dynamics: bool,
    /// Units of `--q`, `--v`, `--a` and the printed accelerations: `si` (m, rad) or `mm-deg`.
    /// Torques, forces and the mass matrix stay SI (N·m, N, kg·m²).
    #[arg(long, value_enum, default_value_t = super::UnitsArg::Si)]
    units: super::UnitsArg,
}

/// Computes and prints τ and/or q̈ and M.
pub(crate) fn run(args: &Args) -> Result<()> {
    if args.a.is_none() && args.tau.is_none() {
        bail!("give --a (for the torques) or --tau (for the accelerations), or both");
    }
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    let q = super::parse_named_in(&model, args.q.as_deref(), false, args.units)?;
    let v = super::parse_named_in(&model, args.v.as_deref(), true, args.units)?;
    let terms = if args.joint_dynamics {
        JointTerms::FromModel
    } else {
        JointTerms::Ignored
    };
    let mut data = DynamicsData::with_joint_terms(&model, terms);
    let mut out = String::new();
    if args.a.is_some() {
        let a = super::parse_named_in(&model, args.a.as_deref(), true, args.units)?;
        let tau = rnea(&model, &mut data, &q, &v, &a)?.to_vec();
        let _ = writeln!(out, "tau = RNEA(q, v, a) (N·m or N):");
        out.push_str(&super::by_joint_lines(&model, &tau, ""));
    }
    if args.tau.is_some() {
        let tau = super::parse_named(&model, args.tau.as_deref(), true)?;
        let mut ddq = aba(&model, &mut data, &q, &v, &tau)?.to_vec();
        let units = args.units.units();
        model.convert_v(&mut ddq, units, false)?;
        let _ = writeln!(
            out,
            "ddq = ABA(q, v, tau) ({}/s² or {}/s²):",
            units.angle.as_str(),
            units.length.as_str()
        );
        out.push_str(&super::by_joint_lines(&model, &ddq, ""));
    }
    let nv = model.nv();
    let m = crba(&model, &mut data, &q)?.to_vec();
    let _ = writeln!(
        out,
        "M(q) ({nv} x {nv}, rows and columns in the order above):"
    );
    for row in m.chunks(nv.max(1)).take(nv) {
        let cells: Vec<String> = row.iter().map(|x| format!("{x:>11.5}")).collect();
        let _ = writeln!(out, "  {}", cells.join(" "));
    }
    out!("{out}")?;
    Ok(())
}
