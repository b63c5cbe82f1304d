//! `kinetree compute <model> --states states.json`: evaluates many states at once and writes the
//! results as JSON, so any language can use kinetree through files. The format is documented in
//! `kinetree::batch`: link poses, requested Jacobians, and the dynamics quantities the given
//! inputs allow.

use anyhow::{Context, Result};
use kinetree::batch::{
    BatchOptions, FrameSelection, JointValue, NamedValues, SampleInput, evaluate,
};
use kinetree::model::Model;
use serde::Deserialize;
use serde_json::Value;
use std::path::PathBuf;

/// The part of `kinetree compute --help` that lists every output key.
pub(crate) const WHAT_IT_COMPUTES: &str = "\
Input: {\"samples\": [{\"name\": ..., \"q\": {joint: value}, \"v\": {...}, \"a\": {...}, \"tau\": {...}}]}
(or the same maps inside \"state\", as in a Pinocchio reference file). A joint left out of q is at
its neutral value and of v, a, tau at zero (--strict requires every joint); q may be left out.

Output: {\"model\": {name, nq, nv, joints: [{name, type, idx_q, idx_v, nq, nv}]}, \"samples\": [...]}
with, per sample (vectors in the model's v order, matrices row-major):
  name               the sample's name, when it has one
  link_poses         every link: translation [3] (m), rotation 3x3 (world frame)
  frame_poses        with --frames: the named frames' poses, the same way
  jacobians          each --jacobians link or frame: 6 x nv, LocalWorldAligned, [linear; angular]
  gravity_torque     g(q) (N·m or N)
  mass_matrix        M(q), nv x nv
  com                centre of mass of the moving bodies (m), null for a massless model
  total_mass         kg
  potential_energy   J
  nle                with v: C(q, v)·v + g(q)
  kinetic_energy     with v: J
  centroidal_momentum  with v: [linear; angular] about the centre of mass
  rnea               with v and a: τ = M·a + C·v + g
  aba                with v and tau: q̈ = M⁻¹·(τ - C·v - g), null when M is singular
  derivatives        with --derivatives, each matrix nv x nv (rows of nv), tangent space in q:
    gravity          {dg_dq}: ∂g/∂q
    rnea             with v and a: {dtau_dq, dtau_dv, dtau_da}: ∂τ/∂q, ∂τ/∂v, ∂τ/∂a = M
    aba              with v and tau: {dddq_dq, dddq_dv, dddq_dtau}: ∂q̈/∂q, ∂q̈/∂v, ∂q̈/∂τ = M⁻¹,
                     null when M is singular
  by_joint           gravity_torque, nle, rnea, aba again, keyed by joint name
  errors             why a quantity is null
  units              with --units mm-deg: {\"length\": \"mm\", \"angle\": \"deg\", \"converted\": [...],
                     \"si\": [...]}: translations, com, collision distances in mm; jacobians'
                     linear rows in mm/s and angular rows in deg/s per mm/s or deg/s of each
                     joint coordinate; aba in mm/s² or deg/s². Still SI (listed in \"si\"):
                     gravity_torque, mass_matrix, total_mass, energies, nle,
                     centroidal_momentum, rnea, derivatives and their by_joint copies; tau is
                     read in SI (N·m or N)
  collision          with --collision: [{link_a, link_b, distance}] per candidate pair (m; < 0 = penetration)
Dynamics are rigid-body (as Pinocchio's) unless --joint-dynamics adds the URDF's damping,
friction and armature.";

/// Arguments of `kinetree compute`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint named `root_joint`.
    #[arg(long)]
    floating: bool,
    /// The request: `{"samples": [{"q": {joint: value}, "v": {...}, "a": {...}, "tau": {...}}]}`
    /// (a reference file's samples, which wrap these maps in "state", work too).
    #[arg(long)]
    states: PathBuf,
    /// Named frames (or links) whose world pose is reported in `frame_poses`, comma separated
    /// (`part/frame` where two parts have a frame of that name), or `all` for every named frame.
    #[arg(long, value_delimiter = ',')]
    frames: Vec<String>,
    /// Links or frames whose LocalWorldAligned Jacobian (6 x nv) is reported, comma separated.
    #[arg(long, value_delimiter = ',')]
    jacobians: Vec<String>,
    /// Add the joints' damping, friction and armature (URDF `<dynamics>`) to the dynamics. By
    /// default they are left out: the rigid-body quantities, as Pinocchio computes them.
    #[arg(long)]
    joint_dynamics: bool,
    /// The old spelling of the default (rigid-body dynamics), still accepted.
    #[arg(long, hide = true, conflicts_with = "joint_dynamics")]
    ignore_joint_dynamics: bool,
    /// Require every moving joint in each sample's q (and in v, a, tau when given), as before
    /// the defaults existed; by default a joint left out is neutral (q) or zero.
    #[arg(long)]
    strict: bool,
    /// Add `derivatives` to each sample: the analytic derivatives of gravity, and of inverse
    /// (with v and a) and forward dynamics (with v and tau).
    #[arg(long)]
    derivatives: bool,
    /// Add `collision` to each sample: the minimum signed distance of every candidate link pair.
    #[arg(long)]
    collision: bool,
    /// A directory where collision meshes are looked up (`package://` and relative names) after
    /// the model file's directory; repeatable.
    #[arg(long = "mesh-path")]
    mesh_paths: Vec<PathBuf>,
    /// Drop collision meshes that cannot be found or read (they are listed on stderr).
    #[arg(long)]
    skip_missing_meshes: bool,
    /// Units of the samples' q, v and a and of every output with a length or an angle: `si`
    /// (m, rad) or `mm-deg`. Under `mm-deg`, poses' translations, com and collision distances
    /// are in mm, Jacobians in mm and deg per mm or deg of each joint coordinate, aba in mm/s²
    /// or deg/s²; forces, torques, energies, the mass matrix, momentum and derivatives stay SI
    /// (listed in the output's `units.si`), and tau is read in SI.
    #[arg(long, value_enum, default_value_t = super::UnitsArg::Si)]
    units: super::UnitsArg,
    /// Write the result here instead of standard output.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Loads the model and the request, evaluates, and writes the response.
pub(crate) fn run(args: &Args) -> Result<()> {
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    let text = std::fs::read_to_string(&args.states)
        .with_context(|| format!("cannot read {}", args.states.display()))?;
    let request: Value = serde_json::from_str(&text)
        .with_context(|| format!("cannot parse {} as JSON", args.states.display()))?;
    let (samples, names) = parse_request(&request)
        .with_context(|| format!("cannot read the samples of {}", args.states.display()))?;
    let mut samples = samples;
    if args.units != super::UnitsArg::Si {
        for sample in &mut samples {
            for (values, velocity) in [
                (&mut sample.q, false),
                (&mut sample.v, true),
                (&mut sample.a, true),
            ] {
                if let Some(values) = values {
                    named_to_si(&model, values, velocity, args.units);
                }
            }
        }
    }
    let options = BatchOptions {
        jacobians: args.jacobians.clone(),
        frames: match args.frames.as_slice() {
            [] => FrameSelection::None,
            [all] if all == "all" => FrameSelection::All,
            names => FrameSelection::Named(names.to_vec()),
        },
        no_dynamics: false,
        derivatives: args.derivatives,
        strict: args.strict,
        joint_dynamics: args.joint_dynamics,
        collision: args.collision.then(|| {
            let mut o = kinetree::collision::CollisionOptions::default()
                .with_model_file(&args.model, &args.mesh_paths);
            if args.skip_missing_meshes {
                o = o.skip_missing_meshes();
            }
            o
        }),
    };
    let output = evaluate(&model, &samples, &options)
        .with_context(|| format!("cannot evaluate {}", args.states.display()))?;
    for skipped in &output.model.skipped_meshes {
        eprintln!("skipped mesh: {skipped}");
    }
    let mut response = serde_json::to_value(&output)?;
    if args.units != super::UnitsArg::Si {
        outputs_from_si(&model, &mut response, args.units);
    }
    // A sample's name (any JSON value) is copied to its result.
    for (out, name) in response["samples"]
        .as_array_mut()
        .into_iter()
        .flatten()
        .zip(names)
    {
        if let (Some(out), Some(name)) = (out.as_object_mut(), name) {
            out.insert("name".into(), name);
        }
    }
    let mut json = serde_json::to_string(&response)?;
    json.push('\n');
    match &args.out {
        Some(path) => std::fs::write(path, json)
            .with_context(|| format!("cannot write {}", path.display()))?,
        None => out!("{json}")?,
    }
    Ok(())
}

/// Converts the named joint values of `values` from `units` to SI, coordinate by coordinate
/// (a cylindrical joint's slide and angle). Unknown joints and wrong value counts are left for
/// the evaluation to report.
fn named_to_si(model: &Model, values: &mut NamedValues, velocity: bool, units: super::UnitsArg) {
    let units = units.units();
    for (name, value) in values.iter_mut() {
        let Some(j) = model.user_joint_index(name) else {
            continue;
        };
        let coords = if velocity {
            model.user_joint_v_coordinates(j)
        } else {
            model.user_joint_q_coordinates(j)
        };
        match value {
            JointValue::Scalar(x) if coords.len() == 1 => *x = coords[0].to_si(*x, units),
            JointValue::Block(xs) if xs.len() == coords.len() => {
                for (x, c) in xs.iter_mut().zip(&coords) {
                    *x = c.to_si(*x, units);
                }
            }
            _ => {}
        }
    }
}

/// The fields of a response that `--units mm-deg` converts, and how.
pub(crate) const CONVERTED_FIELDS: [&str; 7] = [
    "link_poses.*.translation (mm)",
    "frame_poses.*.translation (mm)",
    "com (mm)",
    "jacobians (linear rows in mm/s, angular rows in deg/s, per mm/s or deg/s of each joint coordinate)",
    "aba (mm/s² or deg/s² per coordinate)",
    "by_joint.aba (the same)",
    "collision.*.distance (mm)",
];

/// The fields of a response that stay SI under `--units mm-deg` (forces, torques, energies,
/// inertias and their derivatives have no millimetre-degree form kinetree writes).
pub(crate) const SI_FIELDS: [&str; 12] = [
    "gravity_torque",
    "mass_matrix",
    "total_mass",
    "potential_energy",
    "nle",
    "kinetic_energy",
    "centroidal_momentum",
    "rnea",
    "derivatives",
    "by_joint.gravity_torque",
    "by_joint.nle",
    "by_joint.rnea",
];

/// Converts every length and angle of a response from SI to `units` (see [`CONVERTED_FIELDS`];
/// [`SI_FIELDS`] are left as they are), and says so in its `units` key.
fn outputs_from_si(model: &Model, response: &mut Value, units: super::UnitsArg) {
    let units = units.units();
    let scale = units.length.per_meter();
    let degrees = kinetree::model::state::Coordinate::Angle.from_si(1.0, units);
    // SI → units factor of each velocity coordinate (mm per m or deg per rad).
    let mut per_v = vec![1.0; model.nv()];
    if model.convert_v(&mut per_v, units, false).is_err() {
        return;
    }
    let scale_all = |v: &mut Value, s: f64| {
        for x in v.as_array_mut().into_iter().flatten() {
            if let Some(f) = x.as_f64() {
                *x = Value::from(f * s);
            }
        }
    };
    let scale_each = |v: &mut Value, s: &[f64]| {
        for (x, s) in v.as_array_mut().into_iter().flatten().zip(s) {
            if let Some(f) = x.as_f64() {
                *x = Value::from(f * s);
            }
        }
    };
    for sample in response["samples"].as_array_mut().into_iter().flatten() {
        for key in ["link_poses", "frame_poses"] {
            for pose in sample
                .get_mut(key)
                .and_then(Value::as_object_mut)
                .into_iter()
                .flat_map(|m| m.values_mut())
            {
                if let Some(t) = pose.get_mut("translation") {
                    scale_all(t, scale);
                }
            }
        }
        if let Some(com) = sample.get_mut("com") {
            scale_all(com, scale);
        }
        // J maps joint rates to [linear; angular] rates: row unit over column unit.
        for jac in sample
            .get_mut("jacobians")
            .and_then(Value::as_object_mut)
            .into_iter()
            .flat_map(|m| m.values_mut())
        {
            for (i, row) in jac.as_array_mut().into_iter().flatten().enumerate() {
                let out = if i < 3 { scale } else { degrees };
                let per: Vec<f64> = per_v.iter().map(|c| out / c).collect();
                scale_each(row, &per);
            }
        }
        if let Some(aba) = sample.get_mut("aba") {
            scale_each(aba, &per_v);
        }
        if let Some(by) = sample.pointer_mut("/by_joint/aba") {
            for u in model.moving_user_joints() {
                let name = &model.user_joints()[u].name;
                let r = model.user_joint_v_range(u);
                match by.get_mut(name.as_str()) {
                    Some(x @ Value::Array(_)) => scale_each(x, &per_v[r]),
                    Some(x) => {
                        if let Some(f) = x.as_f64() {
                            *x = Value::from(f * per_v[r.start]);
                        }
                    }
                    None => {}
                }
            }
        }
        for pair in sample
            .get_mut("collision")
            .and_then(Value::as_array_mut)
            .into_iter()
            .flatten()
        {
            if let Some(d) = pair.get_mut("distance")
                && let Some(f) = d.as_f64()
            {
                *d = Value::from(f * scale);
            }
        }
    }
    if let Some(obj) = response.as_object_mut() {
        obj.insert(
            "units".into(),
            serde_json::json!({
                "length": units.length.as_str(),
                "angle": units.angle.as_str(),
                "converted": CONVERTED_FIELDS,
                "si": SI_FIELDS,
            }),
        );
    }
}

/// The samples of a request (`{"samples": [...]}`; a sample may wrap its maps in `"state"`, as a
/// reference file's samples do) and each sample's `name`, if it has one.
fn parse_request(request: &Value) -> Result<(Vec<SampleInput>, Vec<Option<Value>>)> {
    let samples = request
        .get("samples")
        .and_then(Value::as_array)
        .context("the request has no 'samples' array")?;
    let mut inputs = Vec::with_capacity(samples.len());
    let mut names = Vec::with_capacity(samples.len());
    for (i, sample) in samples.iter().enumerate() {
        // A sample with a `state` object is a Pinocchio reference sample: its other keys are the
        // reference results and are ignored. Otherwise the sample itself is the state.
        let (state, allowed): (&Value, &[&str]) = match sample.get("state") {
            Some(state) if state.is_object() => (state, &["q", "v", "a", "tau"]),
            _ => (sample, &["name", "q", "v", "a", "tau"]),
        };
        // A typo ("tua", "qq") must not silently leave a quantity at its default, as the model
        // JSON refuses unknown fields.
        if let Some(key) = state
            .as_object()
            .and_then(|o| o.keys().find(|k| !allowed.contains(&k.as_str())))
        {
            anyhow::bail!(
                "sample {i}: unknown field '{key}' (expected one of {})",
                allowed.join(", ")
            );
        }
        let input = SampleInput::deserialize(state).with_context(|| format!("sample {i}"))?;
        inputs.push(input);
        names.push(sample.get("name").cloned());
    }
    Ok((inputs, names))
}
