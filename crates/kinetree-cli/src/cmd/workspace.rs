//! `kinetree workspace <model> --frame F`: where a frame can reach, sampled over the joints on
//! its path (random or grid), with bounds, maximum reach, voxel volume and manipulability.
//!
//! `--out` writes the samples as PLY, CSV or JSON (by extension); `--plot` draws an SVG with the
//! top, front and side projections of the cloud coloured by manipulability. A progress bar on
//! stderr (hidden when stderr is not a terminal) follows the sampling.

use crate::plot::workspace::{Caption, cloud_svg};
use anyhow::{Context, Result, bail};
use indicatif::ProgressBar;
use kinetree::kinematics::FrameId;
use kinetree::spatial::DVec3;
use kinetree::workspace::{
    ReachableParams, ReachableSet, Sampling, TaskSpace, sample_reachable_with_progress,
};
use std::fmt::Write as _;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `kinetree workspace`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// The link or frame whose reachable positions are sampled.
    #[arg(long)]
    frame: String,
    /// Attach the root link by a 6-DoF floating joint (held at the origin while sampling).
    #[arg(long)]
    floating: bool,
    /// Random samples, uniform within the joint limits [default: 100000].
    #[arg(long, conflicts_with = "grid")]
    samples: Option<usize>,
    /// A grid of K values on each sampled joint coordinate instead (K^joints samples).
    #[arg(long, value_name = "K")]
    grid: Option<usize>,
    /// Voxel size for the reachable volume, in metres (or millimetres with `--units mm-deg`).
    #[arg(long, default_value_t = 0.02)]
    voxel: f64,
    /// Seed of the random samples (the same seed gives the same samples on any thread count).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Manipulability from the position rows of the Jacobian, or from all six rows (and keep
    /// orientations in the output).
    #[arg(long, value_enum, default_value_t = Task::Position)]
    task: Task,
    /// The point reach is measured from, `x,y,z` in metres (or millimetres with `--units mm-deg`).
    #[arg(long, value_parser = parse_point, default_value = "0,0,0", allow_hyphen_values = true)]
    base: DVec3,
    /// Units of `--voxel`, `--base` and the printed bounds, reach and volume: `si` (m) or `mm-deg`
    /// (mm). Manipulability, the sample files and the plot stay in metres.
    #[arg(long, value_enum, default_value_t = super::UnitsArg::Si)]
    units: super::UnitsArg,
    /// Write the samples here: .ply (point cloud with a manipulability scalar), .csv or .json.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Draw the top, front and side projections coloured by manipulability into this SVG.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Worker threads [default: one per core].
    #[arg(long)]
    threads: Option<usize>,
    /// Start more than 1024 worker threads if asked.
    #[arg(long)]
    no_limit: bool,
}

/// The `--task` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Task {
    /// Positions only (3-row Jacobian).
    Position,
    /// Full pose (6-row Jacobian, orientations kept).
    Pose,
}

/// The output formats of `--out`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ply,
    Csv,
    Json,
}

fn format_of(path: &Path) -> Result<Format> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    Ok(match ext.as_deref() {
        Some("ply") => Format::Ply,
        Some("csv") => Format::Csv,
        Some("json") => Format::Json,
        _ => bail!(
            "cannot write {}: unknown format (expected .ply, .csv or .json)",
            path.display()
        ),
    })
}

fn parse_point(s: &str) -> Result<DVec3, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("expected x,y,z in metres: {e}"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(DVec3::new(x, y, z)),
        [_, _, _] => Err("coordinates must be finite".into()),
        _ => Err(format!(
            "expected 3 comma-separated numbers, got {}",
            v.len()
        )),
    }
}

/// Samples, summarises on stdout and writes the requested files.
pub(crate) fn run(args: &Args) -> Result<()> {
    report_to(args, &mut std::io::stdout().lock())
}

/// The most worker threads started without --no-limit (the sample count is bounded by the
/// library's own limit).
const MAX_THREADS: usize = 1024;

/// Refuses thread counts that cannot start sensibly (100 000 threads ran until killed).
fn check_limits(args: &Args) -> Result<()> {
    if args.no_limit {
        return Ok(());
    }
    if let Some(t) = args.threads.filter(|&t| t > MAX_THREADS) {
        bail!(
            "--threads {t} exceeds the limit of {MAX_THREADS} worker threads (this machine has {}); lower it, or pass --no-limit",
            std::thread::available_parallelism().map_or(1, usize::from)
        );
    }
    Ok(())
}

/// [`run`] with the summary written to `out`.
fn report_to(args: &Args, out: &mut dyn std::io::Write) -> Result<()> {
    // Check what can be checked before sampling, which may take a while.
    let length = args.units.units().length;
    let scale = length.per_meter();
    if !(args.voxel.is_finite() && args.voxel > 0.0) {
        bail!(
            "--voxel {} is not a positive length in {}",
            args.voxel,
            length.as_str()
        );
    }
    let (voxel, base) = (args.voxel / scale, args.base / scale);
    check_limits(args)?;
    let format = args.out.as_deref().map(format_of).transpose()?;
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    let frame = FrameId::find(&model, &args.frame)?;
    let sampling = match (args.grid, args.samples) {
        (Some(per_coordinate), _) => Sampling::Grid { per_coordinate },
        (None, samples) => Sampling::Random {
            samples: samples.unwrap_or(100_000),
            seed: args.seed,
        },
    };
    let task = match args.task {
        Task::Position => TaskSpace::Position,
        Task::Pose => TaskSpace::Pose,
    };
    let params = ReachableParams {
        sampling,
        task,
        q0: None,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    let bar = ProgressBar::new(0);
    bar.set_style(super::progress_style(
        "{spinner} sampling [{bar:40}] {pos}/{len} samples, {rate}, eta {eta}",
    ));
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let start = Instant::now();
    let set = pool.install(|| sample_reachable_with_progress(&model, frame, &params, &progress));
    bar.finish_and_clear();
    let set = set.with_context(|| format!("cannot sample the workspace of '{}'", args.frame))?;
    let seconds = start.elapsed().as_secs_f64();
    let voxels = set.voxelize(voxel)?;
    let reach = set.max_reach(base)?;
    let file = args.model.file_name().map_or_else(
        || args.model.display().to_string(),
        |f| f.to_string_lossy().into_owned(),
    );
    let summary = Summary {
        file,
        threads: pool.current_num_threads(),
        seconds,
        reach,
        base,
        voxel,
        voxels: voxels.len(),
        volume: voxels.volume(),
        scale,
        unit: length.as_str(),
    };
    say(out, &summary.report(&set))?;
    if let (Some(path), Some(format)) = (&args.out, format) {
        write_samples(&set, path, format)?;
        say(out, &format!("wrote        {}\n", path.display()))?;
    }
    if let Some(path) = &args.plot {
        std::fs::write(path, cloud_svg(&set, &summary.caption()))
            .with_context(|| format!("cannot write {}", path.display()))?;
        say(out, &format!("wrote        {}\n", path.display()))?;
    }
    Ok(())
}

/// Writes `text` to `out` (stdout); a closed pipe (`kinetree workspace … | head`) is not an
/// error, and the files are still written.
fn say(out: &mut dyn std::io::Write, text: &str) -> Result<()> {
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(e).context("cannot write to stdout")
        }
        _ => Ok(()),
    }
}

fn write_samples(set: &ReachableSet, path: &Path, format: Format) -> Result<()> {
    let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    match format {
        Format::Ply => set.write_ply(file),
        Format::Csv => set.write_csv(file),
        Format::Json => set.write_json(file),
    }
    .with_context(|| format!("cannot write {}", path.display()))
}

/// What the report and the picture say besides the samples.
#[derive(Debug)]
struct Summary {
    file: String,
    threads: usize,
    seconds: f64,
    reach: f64,
    base: DVec3,
    voxel: f64,
    voxels: usize,
    volume: f64,
    /// The printed lengths' unit per metre, and its name.
    scale: f64,
    unit: &'static str,
}

fn sampling_words(s: Sampling) -> String {
    match s {
        Sampling::Grid { per_coordinate } => format!("grid of {per_coordinate} per joint"),
        Sampling::Random { samples, seed } => format!("{samples} random samples, seed {seed}"),
    }
}

/// Smallest, mean and largest manipulability.
fn manipulability_range(set: &ReachableSet) -> (f64, f64, f64) {
    let w = set.manipulability();
    let (lo, hi) = w.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), &x| {
        (lo.min(x), hi.max(x))
    });
    (lo, w.iter().sum::<f64>() / w.len().max(1) as f64, hi)
}

fn unit(task: TaskSpace) -> &'static str {
    match task {
        TaskSpace::Position => "m³, from the 3 position rows of J",
        TaskSpace::Pose => "from the 6 rows of J, metres and radians mixed",
    }
}

impl Summary {
    /// What the picture says besides the samples.
    fn caption(&self) -> Caption<'_> {
        Caption {
            file: &self.file,
            reach: self.reach,
            base: self.base,
            voxel: self.voxel,
            volume: self.volume,
        }
    }

    fn report(&self, set: &ReachableSet) -> String {
        let mut out = String::new();
        let b = set.bounds();
        let (k, u) = (self.scale, self.unit);
        let (lo, mean, hi) = manipulability_range(set);
        let _ = writeln!(out, "frame        {} ({})", set.frame_name(), self.file);
        let _ = writeln!(
            out,
            "joints       {} ({})",
            set.joints().len(),
            set.joints().join(", ")
        );
        let _ = writeln!(
            out,
            "samples      {} ({}) in {:.3} s: {:.0} samples/s on {} thread(s)",
            set.len(),
            sampling_words(set.sampling()),
            self.seconds,
            set.len() as f64 / self.seconds.max(1e-9),
            self.threads
        );
        for (axis, lo, hi) in [
            ("x", b.min.x, b.max.x),
            ("y", b.min.y, b.max.y),
            ("z", b.min.z, b.max.z),
        ] {
            let _ = writeln!(out, "bounds {axis}     [{:.4}, {:.4}] {u}", lo * k, hi * k);
        }
        let _ = writeln!(
            out,
            "max reach    {:.4} {u} from ({}, {}, {})",
            self.reach * k,
            self.base.x * k,
            self.base.y * k,
            self.base.z * k
        );
        let _ = writeln!(
            out,
            "voxels       {} of {} {u} hit: {:.4} {u}³ (a lower bound, growing with the samples)",
            self.voxels,
            self.voxel * k,
            self.volume * k * k * k
        );
        let _ = writeln!(
            out,
            "manipulability min {lo:.4e}, mean {mean:.4e}, max {hi:.4e} ({})",
            unit(set.task())
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree::model::samples;
    use kinetree::workspace::sample_reachable;

    #[derive(Debug, clap::Parser)]
    struct Cli {
        #[command(flatten)]
        args: Args,
    }

    fn args(words: &[&str]) -> Result<Args, clap::Error> {
        let panda = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/robots/panda.urdf"
        );
        let all: Vec<&str> = ["workspace", panda].iter().chain(words).copied().collect();
        <Cli as clap::Parser>::try_parse_from(all).map(|c| c.args)
    }

    #[test]
    fn the_command_writes_every_format_and_the_plot() {
        let dir = std::env::temp_dir().join(format!("kinetree-ws-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (ext, starts) in [
            ("ply", "ply\n"),
            ("csv", "x,y,z,manipulability\n"),
            ("json", "{"),
        ] {
            let out = dir.join(format!("ws.{ext}"));
            let plot = dir.join("ws.svg");
            let a = args(&[
                "--frame",
                "panda_hand_tcp",
                "--samples",
                "3000",
                "--threads",
                "1",
                "--out",
                out.to_str().unwrap(),
                "--plot",
                plot.to_str().unwrap(),
            ])
            .unwrap();
            let mut report = Vec::new();
            report_to(&a, &mut report).unwrap();
            let report = String::from_utf8(report).unwrap();
            assert!(report.contains("samples      3000 (3000 random samples, seed 0)"));
            assert!(report.contains(&format!("wrote        {}", out.display())));
            let text = std::fs::read_to_string(&out).unwrap();
            assert!(text.starts_with(starts), "{ext}");
            assert!(
                std::fs::read_to_string(&plot)
                    .unwrap()
                    .contains("panda_hand_tcp")
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_arguments_are_errors_not_panics() {
        let e = |words: &[&str]| {
            let mut sink = Vec::new();
            let e = report_to(&args(words).unwrap(), &mut sink).unwrap_err();
            format!("{e:#}")
        };
        assert!(e(&["--frame", "nope"]).contains("unknown link or frame 'nope'"));
        assert!(e(&["--frame", "panda_hand", "--voxel", "0"]).contains("--voxel"));
        assert!(e(&["--frame", "panda_hand", "--out", "ws.txt"]).contains(".ply, .csv or .json"));
        assert!(e(&["--frame", "panda_hand", "--grid", "0"]).contains("cannot sample"));
        assert!(args(&["--frame", "panda_hand", "--grid", "3", "--samples", "9"]).is_err());
        assert!(args(&["--frame", "panda_hand", "--base", "1,2"]).is_err());
        let a = args(&["--frame", "panda_hand", "--base", "-1,0,0.5"]).unwrap();
        assert_eq!(a.base, DVec3::new(-1.0, 0.0, 0.5));
    }

    #[test]
    fn points_parse_or_say_why_not() {
        assert_eq!(parse_point("1, -2,3.5"), Ok(DVec3::new(1.0, -2.0, 3.5)));
        assert!(
            parse_point("1,2")
                .unwrap_err()
                .contains("3 comma-separated")
        );
        assert!(parse_point("1,x,2").is_err());
        assert!(parse_point("1,NaN,2").unwrap_err().contains("finite"));
    }

    #[test]
    fn millimetre_arguments_give_the_same_workspace() {
        let report = |words: &[&str]| {
            let mut out = Vec::new();
            report_to(&args(words).unwrap(), &mut out).unwrap();
            String::from_utf8(out).unwrap()
        };
        let line = |text: &str, key: &str| -> Vec<f64> {
            text.lines()
                .find(|l| l.starts_with(key))
                .unwrap_or_else(|| panic!("no {key} in {text}"))
                .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
                .filter_map(|x| x.parse().ok())
                .collect()
        };
        let common = ["--frame", "panda_hand_tcp", "--grid", "3", "--threads", "1"];
        let m = report(&[&common[..], &["--voxel", "0.05", "--base", "0,0,0.333"]].concat());
        let mm = report(
            &[
                &common[..],
                &["--voxel", "50", "--base", "0,0,333", "--units", "mm-deg"],
            ]
            .concat(),
        );
        let (rm, rmm) = (line(&m, "max reach"), line(&mm, "max reach"));
        assert!((rmm[0] - 1000.0 * rm[0]).abs() < 0.1, "{m}\n{mm}");
        assert_eq!(&rmm[1..], [0.0, 0.0, 333.0]);
        // The same voxels are hit.
        assert_eq!(line(&m, "voxels")[0], line(&mm, "voxels")[0]);
        assert!(
            line(&mm, "bounds z").len() == 2 && mm.contains("] mm"),
            "{mm}"
        );
    }

    #[test]
    fn formats_follow_the_extension() {
        assert_eq!(format_of(Path::new("a/ws.PLY")).unwrap(), Format::Ply);
        assert_eq!(format_of(Path::new("ws.csv")).unwrap(), Format::Csv);
        assert_eq!(format_of(Path::new("ws.json")).unwrap(), Format::Json);
        let e = format_of(Path::new("ws.txt")).unwrap_err().to_string();
        assert!(e.contains(".ply, .csv or .json"), "{e}");
    }

    #[test]
    fn the_report_gives_the_reach_and_the_caption_follows() {
        let model = samples::planar_2r(1.0, 0.5);
        let tool = FrameId::find(&model, "tool").unwrap();
        let set = sample_reachable(&model, tool, &ReachableParams::grid(61)).unwrap();
        let summary = Summary {
            file: "planar <2r>.urdf".into(),
            threads: 1,
            seconds: 0.1,
            reach: set.max_reach(DVec3::ZERO).unwrap(),
            base: DVec3::ZERO,
            voxel: 0.02,
            voxels: 10,
            volume: 0.001,
            scale: 1.0,
            unit: "m",
        };
        let report = summary.report(&set);
        assert!(report.contains("max reach    1.5000 m"), "{report}");
        // In millimetres: the same numbers scaled, the volume by a thousand cubed.
        let mm = Summary {
            scale: 1000.0,
            unit: "mm",
            ..summary
        };
        let report = mm.report(&set);
        assert!(report.contains("max reach    1500.0000 mm"), "{report}");
        assert!(
            report.contains("10 of 20 mm hit: 1000000.0000 mm³"),
            "{report}"
        );
        assert!(
            report.contains("bounds x     [-1500.0000, 1500.0000] mm"),
            "{report}"
        );
        let summary = Summary {
            scale: 1.0,
            unit: "m",
            ..mm
        };
        let caption = summary.caption();
        assert_eq!(caption.file, "planar <2r>.urdf");
        assert!((caption.reach - 1.5).abs() < 1e-9, "{}", caption.reach);
        assert_eq!((caption.voxel, caption.volume), (0.02, 0.001));
    }
}
