//! `kinetree convert <in> <out>`: URDF ↔ JSON, each format chosen by its file extension.
//!
//! Joint values stored in the input (JSON `position`, yapCAD `value`) are written back to a JSON
//! output, `--positions` sets or overrides them, and `--world-poses` adds every link's world pose
//! at those values.

use super::UnitsArg;
use anyhow::{Context, Result, bail};
use kinetree::kinematics::{KinematicsData, forward_kinematics};
use kinetree::model::{JsonOptions, Model, RootJoint, state};
use std::path::{Path, PathBuf};

/// Arguments of `kinetree convert`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model to read (URDF, MJCF or JSON).
    input: PathBuf,
    /// The file to write; `.urdf` writes URDF, `.xml` writes MJCF (MuJoCo), `.json` writes
    /// kinetree's JSON.
    output: PathBuf,
    /// Attach the root link by a 6-DoF floating joint (recorded in JSON; URDF cannot hold it).
    #[arg(long)]
    floating: bool,
    /// Units of lengths and angles in JSON output (and of `--positions`).
    #[arg(long, value_enum, default_value_t = UnitsArg::Si)]
    units: UnitsArg,
    /// Joint values `name=value,…` written as the joints' `position` (in `--units`; multi-DoF
    /// joints take `a:b:…`); they override the values stored in the input.
    #[arg(long, allow_hyphen_values = true)]
    positions: Option<String>,
    /// Write every link's world pose at the joint values (`world_pose` in JSON).
    #[arg(long)]
    world_poses: bool,
}

/// The output formats, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Urdf,
    Mjcf,
    Json,
}

/// Reads the input, writes the output, and says what was written and what the format dropped.
pub(crate) fn run(args: &Args) -> Result<()> {
    let format = output_format(&args.output)?;
    if format != Format::Json && args.units != UnitsArg::Si {
        bail!("--units applies to JSON output only (URDF and MJCF are always metres and radians)");
    }
    if format != Format::Json && (args.positions.is_some() || args.world_poses) {
        bail!(
            "--positions and --world-poses apply to JSON output only (URDF and MJCF hold no state)"
        );
    }
    let model = super::load_model(&args.input, super::root_joint(args.floating))?;
    let (q, stored) = stored_positions(&model, &args.input)?;
    let q = override_positions(&model, q, args.positions.as_deref(), args.units)?;
    let poses = if args.world_poses {
        let mut data = KinematicsData::new(&model);
        forward_kinematics(&model, &mut data, &q)?;
        Some(data.world_from_link().to_vec())
    } else {
        None
    };
    let text = match format {
        Format::Urdf => model.to_urdf_string(),
        Format::Mjcf => model.to_mjcf_string(),
        Format::Json => model.to_json_string(&JsonOptions {
            units: args.units.units(),
            positions: (stored || args.positions.is_some()).then_some(q.as_slice()),
            world_poses: poses.as_deref(),
            ..JsonOptions::default()
        }),
    }
    .with_context(|| {
        format!(
            "cannot convert {} to {}",
            args.input.display(),
            args.output.display()
        )
    })?;
    std::fs::write(&args.output, text)
        .with_context(|| format!("cannot write {}", args.output.display()))?;

    outln!(
        "wrote {} ({}): {} links, {} joints, nq = {}, nv = {}",
        args.output.display(),
        match format {
            Format::Urdf => "URDF",
            Format::Mjcf => "MJCF",
            Format::Json => "JSON",
        },
        model.links().len(),
        model
            .joints()
            .iter()
            .filter(|j| j.parent_link.is_some())
            .count(),
        model.nq(),
        model.nv()
    )?;
    if format == Format::Urdf {
        for note in urdf_losses(&model) {
            outln!("note: {note}")?;
        }
    }
    Ok(())
}

/// The joint values stored in a JSON input (neutral otherwise), and whether it stored any.
fn stored_positions(model: &Model, input: &Path) -> Result<(Vec<f64>, bool)> {
    let text = std::fs::read_to_string(input)
        .with_context(|| format!("cannot read {}", input.display()))?;
    if !text.trim_start().starts_with('{') {
        return Ok((model.neutral_q(), false));
    }
    let q = state::positions_from_json(model, &text)
        .with_context(|| format!("cannot read the joint values of {}", input.display()))?;
    let stored =
        q != model.neutral_q() || text.contains("\"position\"") || text.contains("\"value\"");
    Ok((q, stored))
}

/// `q` with the joints named in `spec` (values in `units`) set.
fn override_positions(
    model: &Model,
    mut q: Vec<f64>,
    spec: Option<&str>,
    units: UnitsArg,
) -> Result<Vec<f64>> {
    let Some(spec) = spec else { return Ok(q) };
    let given = super::parse_named_in(model, Some(spec), false, units)?;
    for entry in spec.split(',').filter(|e| !e.trim().is_empty()) {
        let name = entry.split_once('=').map_or(entry, |(n, _)| n).trim();
        // A composite joint by its name (its whole block), or one elementary joint.
        let r = match (model.user_joint_index(name), model.joint_index(name)) {
            (Some(u), _) => model.user_joint_q_range(u),
            (None, Some(j)) => model.joint_q_range(j),
            (None, None) => continue,
        };
        q[r.clone()].copy_from_slice(&given[r]);
    }
    Ok(q)
}

/// The output format of `path`, from its extension.
fn output_format(path: &Path) -> Result<Format> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("urdf") => Ok(Format::Urdf),
        Some("xml") => Ok(Format::Mjcf),
        Some("json") => Ok(Format::Json),
        _ => bail!(
            "cannot tell the output format of {}: use a .urdf, .xml (MJCF) or .json extension",
            path.display()
        ),
    }
}

/// What a URDF file cannot hold of this model, one note each.
fn urdf_losses(model: &Model) -> Vec<String> {
    let mut notes = Vec::new();
    if model.root_joint() == RootJoint::Floating {
        notes.push(
            "the floating root joint is not written (URDF has none: load with --floating)".into(),
        );
    }
    if !model.frames().is_empty() {
        notes.push(format!(
            "{} named frame(s) are not written (URDF has no frames)",
            model.frames().len()
        ));
    }
    for c in model.composites() {
        notes.push(format!(
            "composite joint '{}' is written as its {} elementary joints and {} virtual links (URDF has no composite joint)",
            c.spec.name,
            c.joints.len(),
            c.links.len()
        ));
    }
    notes
}
