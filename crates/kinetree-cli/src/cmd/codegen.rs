//! `kinetree codegen <model> --frame F --lang rust|c|python`: the frame's forward kinematics as
//! straight-line source code (trip_kinematics' `get_symbolic_rep`), written to stdout or a file.

use anyhow::{Context, Result};
use kinetree::kinematics::FrameId;
use kinetree::kinematics::codegen::{Lang, generate, identifier};
use std::path::PathBuf;

/// Arguments of `kinetree codegen`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// The link or frame whose world pose the generated function returns.
    #[arg(long)]
    frame: String,
    /// The language: a Rust or C function of q returning the 4x4 pose, or Python building it
    /// from SymPy or CasADi symbols (and from plain floats).
    #[arg(long, value_enum)]
    lang: LangArg,
    /// The function's name [default: fk_<frame>].
    #[arg(long)]
    name: Option<String>,
    /// Attach the root link by a 6-DoF floating joint (its 7 coordinates come first in q).
    #[arg(long)]
    floating: bool,
    /// Write the source here instead of standard output.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// The `--lang` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum LangArg {
    /// `pub fn NAME(q: &[f64]) -> [[f64; 4]; 4]`.
    Rust,
    /// `void NAME(const double *q, double out[16])`, row-major.
    C,
    /// `NAME_expr(q, sin, cos, sqrt)`, `NAME(q)`, `NAME_sympy()`, `NAME_casadi()`.
    Python,
}

/// Generates and writes the source.
pub(crate) fn run(args: &Args) -> Result<()> {
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    let frame = FrameId::find(&model, &args.frame)?;
    let lang = match args.lang {
        LangArg::Rust => Lang::Rust,
        LangArg::C => Lang::C,
        LangArg::Python => Lang::Python,
    };
    // A name given is checked as it is; the default is made an identifier.
    let name = args
        .name
        .clone()
        .unwrap_or_else(|| identifier(&format!("fk_{}", args.frame)));
    let source = generate(&model, frame, lang, &name)?;
    match &args.out {
        Some(path) => std::fs::write(path, source)
            .with_context(|| format!("cannot write {}", path.display()))?,
        None => out!("{source}")?,
    }
    Ok(())
}
