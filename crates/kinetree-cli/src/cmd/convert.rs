//! `kinetree convert <in> <out>`: URDF ↔ JSON, each format chosen by its file extension.

use anyhow::{Context, Result, bail};
use kinetree::model::{JsonOptions, Model, RootJoint, Units};
use std::path::{Path, PathBuf};

/// Arguments of `kinetree convert`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model to read (.urdf, .xml or .json).
    input: PathBuf,
    /// The file to write; `.urdf` writes URDF, `.json` writes kinetree's JSON.
    output: PathBuf,
    /// Attach the root link by a 6-DoF floating joint (recorded in JSON; URDF cannot hold it).
    #[arg(long)]
    floating: bool,
    /// Units of lengths and angles in JSON output.
    #[arg(long, value_enum, default_value_t = UnitsArg::Si)]
    units: UnitsArg,
}

/// The unit systems `--units` accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum UnitsArg {
    /// Metres and radians.
    Si,
    /// Millimetres and degrees (as CAD tools write).
    MmDeg,
}

/// The output formats, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Urdf,
    Json,
}

/// Reads the input, writes the output, and says what was written and what the format dropped.
pub(crate) fn run(args: &Args) -> Result<()> {
    let format = output_format(&args.output)?;
    if format == Format::Urdf && args.units != UnitsArg::Si {
        bail!("--units applies to JSON output only (URDF is always metres and radians)");
    }
    let model = super::load_model(&args.input, super::root_joint(args.floating))?;
    let text = match format {
        Format::Urdf => model.to_urdf_string(),
        Format::Json => {
            let units = match args.units {
                UnitsArg::Si => Units::SI,
                UnitsArg::MmDeg => Units::MM_DEG,
            };
            model.to_json_string(&JsonOptions {
                units,
                ..JsonOptions::default()
            })
        }
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

/// The output format of `path`, from its extension.
fn output_format(path: &Path) -> Result<Format> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("urdf" | "xml") => Ok(Format::Urdf),
        Some("json") => Ok(Format::Json),
        _ => bail!(
            "cannot tell the output format of {}: use a .urdf or .json extension",
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
    notes
}
