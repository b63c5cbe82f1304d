//! The commands, one module each, and what they share: loading a model from a path.

pub(crate) mod bench;
pub(crate) mod bench_batch;
pub(crate) mod codegen;
pub(crate) mod collide;
pub(crate) mod compute;
pub(crate) mod convert;
pub(crate) mod dynamics;
pub(crate) mod ik;
pub(crate) mod inspect;
pub(crate) mod simulate;
pub(crate) mod view;
pub(crate) mod workspace;

use anyhow::{Context, Result};
use kinetree::model::{Model, RootJoint};
use std::path::Path;

/// Loads a model with [`Model::from_file`]: `.json` is kinetree JSON (or a yapCAD or DH table,
/// by its content), XML is URDF or MJCF by its root element, and any other file is told by its
/// first character.
///
/// `root`: `None` welds a URDF's root to the world and keeps a JSON file's own `root_joint`; an
/// MJCF file's bodies float by their own free joints (`--floating` is refused for it).
///
/// # Errors
/// The loader's error, with context naming the file.
pub(crate) fn load_model(path: &Path, root: impl Into<Option<RootJoint>>) -> Result<Model> {
    check_model_file(path)?;
    let root = root.into();
    let model =
        Model::from_file(path, root).with_context(|| format!("cannot load {}", path.display()))?;
    // A model whose roots are attached to the world by their own joints (yapCAD assemblies,
    // JSON with "parent": "world") gets no floating joint: say so rather than ignore the flag.
    if root == Some(RootJoint::Floating)
        && model
            .joint_index(kinetree::model::ROOT_JOINT_NAME)
            .is_none()
    {
        eprintln!(
            "note: --floating has no effect on {}: its roots are attached to the world by their own joints",
            path.display()
        );
    }
    Ok(model)
}

/// The largest model file read unless `KINETREE_MAX_MODEL_BYTES` says otherwise (256 MiB: a
/// 10 000-link URDF is about 5 MB).
const MAX_MODEL_BYTES: u64 = 256 << 20;

/// Refuses what is not a regular file (`/dev/zero`, a FIFO, a directory would be read forever or
/// fail obscurely) and files beyond the size limit.
fn check_model_file(path: &Path) -> Result<()> {
    let Ok(meta) = std::fs::metadata(path) else {
        // The loader names the file and the I/O error.
        return Ok(());
    };
    if !meta.is_file() {
        anyhow::bail!(
            "cannot load {}: not a regular file (a model must be a URDF, MJCF or JSON file)",
            path.display()
        );
    }
    let limit = std::env::var("KINETREE_MAX_MODEL_BYTES")
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
        .unwrap_or(MAX_MODEL_BYTES);
    if meta.len() > limit {
        anyhow::bail!(
            "cannot load {}: the file has {} bytes, more than the limit of {limit}; set KINETREE_MAX_MODEL_BYTES to a larger byte count to load it",
            path.display(),
            meta.len()
        );
    }
    Ok(())
}

/// The unit systems `--units` accepts for joint values and poses on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum UnitsArg {
    /// Metres and radians.
    #[default]
    Si,
    /// Millimetres and degrees (as CAD tools write).
    MmDeg,
}

impl UnitsArg {
    /// The units as the model layer names them.
    pub(crate) fn units(self) -> kinetree::model::Units {
        match self {
            Self::Si => kinetree::model::Units::SI,
            Self::MmDeg => kinetree::model::Units::MM_DEG,
        }
    }
}

/// As [`parse_named`], with the values given in `units` (each coordinate converted as what it
/// measures: a cylindrical joint's `slide:angle` is mm and degrees under `mm-deg`).
///
/// # Errors
/// As [`parse_named`].
pub(crate) fn parse_named_in(
    model: &Model,
    spec: Option<&str>,
    velocity: bool,
    units: UnitsArg,
) -> Result<Vec<f64>> {
    let mut x = parse_named(model, spec, velocity)?;
    if velocity {
        model.convert_v(&mut x, units.units(), true)?;
    } else {
        model.convert_q(&mut x, units.units(), true)?;
    }
    Ok(x)
}

/// Says on standard error which coordinates of `q` (SI) lie outside their joint's position
/// limits, as `what` gives them ("the neutral configuration", "--q"): an answer computed there
/// is for a state the robot cannot take, and a user should not find out by accident.
pub(crate) fn note_outside_limits(model: &Model, q: &[f64], what: &str) {
    for b in model.bodies().iter().skip(1) {
        let Some(j) = b.joint else { continue };
        let lim = &model.joint(j).limits;
        if !b.kind.has_position_limits() || lim.lower >= lim.upper {
            continue;
        }
        for &x in &q[b.idx_q..b.idx_q + b.nq] {
            if x < lim.lower || x > lim.upper {
                eprintln!(
                    "note: {what} puts joint '{}' at {x}, outside its limits [{}, {}]",
                    model.joint(j).name,
                    lim.lower,
                    lim.upper
                );
            }
        }
    }
}

/// The style of the CLI's progress bars, from an indicatif `template` that may use `{rate}`:
/// the items per second as a whole number (indicatif's `{per_sec}` prints four decimals and
/// thousands separators, `25,478.3167/s`).
pub(crate) fn progress_style(template: &str) -> indicatif::ProgressStyle {
    indicatif::ProgressStyle::with_template(template).map_or_else(
        |_| indicatif::ProgressStyle::default_bar(),
        |s| {
            s.progress_chars("=> ").with_key(
                "rate",
                |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = w.write_fmt(format_args!("{:.0}/s", state.per_sec()));
                },
            )
        },
    )
}

/// The root attachment asked for by a `--floating` flag: `None` leaves it to the file.
pub(crate) fn root_joint(floating: bool) -> Option<RootJoint> {
    floating.then_some(RootJoint::Floating)
}

/// Parses `name=value,name=value` into a configuration (`velocity = false`, starting from the
/// neutral configuration) or a velocity-space vector (`velocity = true`, starting from zero).
/// Multi-DoF joints take their values separated by `:` (e.g. `root_joint=0:0:1:0:0:0:1`).
///
/// # Errors
/// A malformed entry, an unknown joint, or a wrong number of values (naming the joint).
pub(crate) fn parse_named(model: &Model, spec: Option<&str>, velocity: bool) -> Result<Vec<f64>> {
    use kinetree::kinematics::configuration::{Space, from_named};
    let mut named = Vec::new();
    for entry in spec
        .unwrap_or_default()
        .split(',')
        .map(str::trim)
        .filter(|e| !e.is_empty())
    {
        let (name, values) = entry
            .split_once('=')
            .with_context(|| format!("'{entry}' is not name=value"))?;
        let values: Vec<f64> = values
            .split(':')
            .map(|x| {
                x.trim()
                    .parse::<f64>()
                    .with_context(|| format!("'{x}' in '{entry}' is not a number"))
            })
            .collect::<Result<_>>()?;
        named.push((name.trim(), values));
    }
    let space = if velocity {
        Space::Velocity
    } else {
        Space::Configuration
    };
    Ok(from_named(model, space, named, false)?)
}

/// Writes `values` keyed by the moving joints' names (a composite joint once), one line each, to
/// a string.
pub(crate) fn by_joint_lines(model: &Model, values: &[f64], unit: &str) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    for j in model.moving_user_joints() {
        let r = model.user_joint_v_range(j);
        let x: Vec<String> = values[r].iter().map(|x| format!("{x:>14.6}")).collect();
        let name = &model.user_joints()[j].name;
        let _ = writeln!(s, "  {name:<28} {} {unit}", x.join(" "));
    }
    s
}
