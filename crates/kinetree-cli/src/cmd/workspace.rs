//! `kinetree workspace <model> --frame F`: where a frame can reach, sampled over the joints on
//! its path (random or grid), with bounds, maximum reach, voxel volume and manipulability.
//!
//! `--out` writes the samples as PLY, CSV or JSON (by extension); `--plot` draws an SVG with the
//! top, front and side projections of the cloud coloured by manipulability. A progress bar on
//! stderr (hidden when stderr is not a terminal) follows the sampling.

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
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
    /// Voxel size in metres for the reachable volume.
    #[arg(long, default_value_t = 0.02)]
    voxel: f64,
    /// Seed of the random samples (the same seed gives the same samples on any thread count).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Manipulability from the position rows of the Jacobian, or from all six rows (and keep
    /// orientations in the output).
    #[arg(long, value_enum, default_value_t = Task::Position)]
    task: Task,
    /// The point reach is measured from, `x,y,z` in metres.
    #[arg(long, value_parser = parse_point, default_value = "0,0,0", allow_hyphen_values = true)]
    base: DVec3,
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
    if !(args.voxel.is_finite() && args.voxel > 0.0) {
        bail!("--voxel {} is not a positive length in metres", args.voxel);
    }
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
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} sampling [{bar:40}] {pos}/{len} samples, {per_sec}, eta {eta}",
        )
        .map_or_else(
            |_| ProgressStyle::default_bar(),
            |s| s.progress_chars("=> "),
        ),
    );
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let start = Instant::now();
    let set = pool.install(|| sample_reachable_with_progress(&model, frame, &params, &progress));
    bar.finish_and_clear();
    let set = set.with_context(|| format!("cannot sample the workspace of '{}'", args.frame))?;
    let seconds = start.elapsed().as_secs_f64();
    let voxels = set.voxelize(args.voxel)?;
    let reach = set.max_reach(args.base)?;
    let file = args.model.file_name().map_or_else(
        || args.model.display().to_string(),
        |f| f.to_string_lossy().into_owned(),
    );
    let summary = Summary {
        file,
        threads: pool.current_num_threads(),
        seconds,
        reach,
        base: args.base,
        voxel: args.voxel,
        voxels: voxels.len(),
        volume: voxels.volume(),
    };
    say(out, &summary.report(&set))?;
    if let (Some(path), Some(format)) = (&args.out, format) {
        write_samples(&set, path, format)?;
        say(out, &format!("wrote        {}\n", path.display()))?;
    }
    if let Some(path) = &args.plot {
        std::fs::write(path, plot_svg(&set, &summary))
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
}

fn sampling_words(s: Sampling) -> String {
    match s {
        Sampling::Grid { per_coordinate } => format!("grid of {per_coordinate} per joint"),
        Sampling::Random { samples, seed } => format!("{samples} random samples, seed {seed}"),
    }
}

/// `n` with its digits in groups of three, `1 000 000`.
fn group_digits(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push('\u{2009}');
        }
        out.push(c);
    }
    out
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
    fn report(&self, set: &ReachableSet) -> String {
        let mut out = String::new();
        let b = set.bounds();
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
            let _ = writeln!(out, "bounds {axis}     [{lo:.4}, {hi:.4}] m");
        }
        let _ = writeln!(
            out,
            "max reach    {:.4} m from ({}, {}, {})",
            self.reach, self.base.x, self.base.y, self.base.z
        );
        let _ = writeln!(
            out,
            "voxels       {} of {} m hit: {:.4} m³ (a lower bound, growing with the samples)",
            self.voxels, self.voxel, self.volume
        );
        let _ = writeln!(
            out,
            "manipulability min {lo:.4e}, mean {mean:.4e}, max {hi:.4e} ({})",
            unit(set.task())
        );
        out
    }
}

/// Viridis at 9 evenly spaced stops (perceptually uniform, readable in grey and by most colour
/// blind readers).
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// The colour of `t` in [0, 1] as `#rrggbb`.
fn viridis(t: f64) -> String {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let c = |k: usize| {
        let (a, b) = (f64::from(VIRIDIS[i][k]), f64::from(VIRIDIS[i + 1][k]));
        (a + (b - a) * f).round() as u8
    };
    format!("#{:02x}{:02x}{:02x}", c(0), c(1), c(2))
}

/// A tick step of 1, 2, 2.5 or 5 times a power of ten giving at most `max_ticks` ticks over
/// `span`.
fn nice_step(span: f64, max_ticks: f64) -> f64 {
    let raw = (span / max_ticks).max(1e-9);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

/// Decimals needed to print multiples of `step`.
fn decimals(step: f64) -> usize {
    let mut d = 0;
    while d < 6
        && ((step * 10f64.powi(d as i32)).round() - step * 10f64.powi(d as i32)).abs() > 1e-9
    {
        d += 1;
    }
    d
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

// Layout of the picture, in SVG pixels.
const PANEL: f64 = 360.0;
const CELL: f64 = 4.0;
const LEFT: f64 = 70.0;
const GAP: f64 = 80.0;
const TOP: f64 = 110.0;
const BAR_WIDTH: f64 = 18.0;
/// Colour levels: neighbouring cells of the same level merge into one rectangle.
const LEVELS: f64 = 48.0;

/// Cells per panel side.
const CELLS: usize = (PANEL / CELL) as usize;

/// One view of the cloud: `CELLS x CELLS` cells, row 0 at the top, each holding the largest
/// manipulability (times `norm`) of the samples seen through it, or -1 where none is. The panel
/// is centred on `center` (its horizontal and vertical coordinates) at `scale` pixels per metre.
fn projection(
    set: &ReachableSet,
    view: &View,
    center: (f64, f64),
    scale: f64,
    norm: f64,
) -> Vec<f64> {
    let mut best = vec![-1.0_f64; CELLS * CELLS];
    for (p, &w) in set.positions().iter().zip(set.manipulability()) {
        let p = p.to_array();
        if let Some(k) = cell_of((p[view.h], p[view.v]), center, scale) {
            best[k] = best[k].max(w * norm);
        }
    }
    best
}

/// The index in a [`projection`] of the cell holding the point `(h, v)`, if inside the panel.
fn cell_of(point: (f64, f64), center: (f64, f64), scale: f64) -> Option<usize> {
    let n = CELLS as f64;
    let i = ((PANEL / 2.0 + (point.0 - center.0) * scale) / CELL).floor();
    let j = ((PANEL / 2.0 - (point.1 - center.1) * scale) / CELL).floor();
    ((0.0..n).contains(&i) && (0.0..n).contains(&j)).then(|| j as usize * CELLS + i as usize)
}

/// The colour level of a cell of [`projection`], `None` for an empty cell.
fn level_of(w: f64) -> Option<usize> {
    (w >= 0.0).then(|| (w.min(1.0) * LEVELS).round() as usize)
}

/// One projection: which coordinates go right and up, and its title.
struct View {
    title: &'static str,
    h: usize,
    v: usize,
}

const VIEWS: [View; 3] = [
    View {
        title: "Top view (from +z)",
        h: 0,
        v: 1,
    },
    View {
        title: "Front view (from +x)",
        h: 1,
        v: 2,
    },
    View {
        title: "Side view (from −y)",
        h: 0,
        v: 2,
    },
];

const AXIS_NAMES: [&str; 3] = ["x", "y", "z"];

/// The SVG picture: three projections of the cloud on a common scale, each cell coloured by the
/// largest manipulability among the samples seen through it, with the base, the max-reach circle,
/// axes in metres, titles and a colour bar.
fn plot_svg(set: &ReachableSet, summary: &Summary) -> String {
    let b = set.bounds();
    let center = b.center().to_array();
    // One scale for all views: the largest extent, padded, fills a panel.
    let span = (b.size().max_element() * 1.1).max(0.05);
    let scale = PANEL / span;
    let (_, _, w_max) = manipulability_range(set);
    let norm = if w_max > 0.0 { 1.0 / w_max } else { 0.0 };
    let width = LEFT + 3.0 * PANEL + 2.0 * GAP + 150.0;
    let height = TOP + PANEL + 110.0;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#
    );
    let _ = writeln!(
        s,
        r#"<rect width="{width}" height="{height}" fill="white"/>"#
    );
    let _ = writeln!(
        s,
        r#"<text x="{LEFT}" y="34" font-size="22" font-weight="bold">Reachable workspace of {} ({})</text>"#,
        xml_escape(set.frame_name()),
        xml_escape(&summary.file)
    );
    let _ = writeln!(
        s,
        r##"<text x="{LEFT}" y="60" font-size="14" fill="#333">{} over {} joints · max reach {:.3} m from ({}, {}, {}) · ≥ {:.3} m³ reached ({} m voxels hit)</text>"##,
        match set.sampling() {
            Sampling::Grid { per_coordinate } => format!(
                "{} samples (grid of {per_coordinate} per joint)",
                group_digits(set.len())
            ),
            Sampling::Random { samples, seed } =>
                format!("{} random samples (seed {seed})", group_digits(samples)),
        },
        set.joints().len(),
        summary.reach,
        summary.base.x,
        summary.base.y,
        summary.base.z,
        summary.volume,
        summary.voxel
    );
    let step = nice_step(span, 6.0);
    let dec = decimals(step);
    for (k, view) in VIEWS.iter().enumerate() {
        let x0 = LEFT + k as f64 * (PANEL + GAP);
        let (hc, vc) = (center[view.h], center[view.v]);
        // Pixel of a world coordinate pair.
        let px = |h: f64| x0 + PANEL / 2.0 + (h - hc) * scale;
        let py = |v: f64| TOP + PANEL / 2.0 - (v - vc) * scale;
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" font-size="16" font-weight="bold" text-anchor="middle">{}</text>"#,
            x0 + PANEL / 2.0,
            TOP - 14.0,
            view.title
        );
        // Grid lines and tick labels at multiples of the step.
        let _ = writeln!(s, r##"<g stroke="#e4e4e4" stroke-width="1">"##);
        let mut ticks = Vec::new();
        for (axis, c, horizontal) in [(view.h, hc, true), (view.v, vc, false)] {
            let lo = (c - span / 2.0) / step;
            let hi = (c + span / 2.0) / step;
            for i in lo.ceil() as i64..=hi.floor() as i64 {
                let value = i as f64 * step;
                if horizontal {
                    let x = px(value);
                    let _ = writeln!(
                        s,
                        r#"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{}"/>"#,
                        TOP + PANEL
                    );
                } else {
                    let y = py(value);
                    let _ = writeln!(
                        s,
                        r#"<line x1="{x0}" y1="{y:.1}" x2="{}" y2="{y:.1}"/>"#,
                        x0 + PANEL
                    );
                }
                ticks.push((axis, horizontal, value));
            }
        }
        let _ = writeln!(s, "</g>");
        // The cloud: one path per colour level, a rectangle per run of equal cells in a row.
        let best = projection(set, view, (hc, vc), scale, norm);
        let mut paths = vec![String::new(); LEVELS as usize + 1];
        for j in 0..CELLS {
            let mut i = 0;
            while i < CELLS {
                let Some(level) = level_of(best[j * CELLS + i]) else {
                    i += 1;
                    continue;
                };
                let run = (i..CELLS)
                    .take_while(|&n| level_of(best[j * CELLS + n]) == Some(level))
                    .count();
                let _ = write!(
                    paths[level],
                    "M{} {}h{}v{CELL}h-{}z",
                    x0 + i as f64 * CELL,
                    TOP + j as f64 * CELL,
                    run as f64 * CELL,
                    run as f64 * CELL
                );
                i += run;
            }
        }
        let _ = writeln!(s, r#"<g shape-rendering="crispEdges">"#);
        for (level, d) in paths.iter().enumerate() {
            if !d.is_empty() {
                let colour = viridis(level as f64 / LEVELS);
                let _ = writeln!(s, r#"<path fill="{colour}" d="{d}"/>"#);
            }
        }
        let _ = writeln!(s, "</g>");
        // The base and the sphere of maximum reach around it (a circle in every view).
        let base = summary.base.to_array();
        let (bx, by) = (px(base[view.h]), py(base[view.v]));
        let _ = writeln!(
            s,
            r#"<clipPath id="panel{k}"><rect x="{x0}" y="{TOP}" width="{PANEL}" height="{PANEL}"/></clipPath><g clip-path="url(#panel{k})">"#
        );
        let _ = writeln!(
            s,
            r##"<circle cx="{bx:.1}" cy="{by:.1}" r="{:.1}" fill="none" stroke="#d62728" stroke-width="1.5" stroke-dasharray="6 4"/>"##,
            summary.reach * scale
        );
        let _ = writeln!(
            s,
            r##"<path d="M{:.1} {by:.1}h12M{bx:.1} {:.1}v12" stroke="#d62728" stroke-width="2"/></g>"##,
            bx - 6.0,
            by - 6.0
        );
        // Frame, tick labels and axis names.
        let _ = writeln!(
            s,
            r##"<rect x="{x0}" y="{TOP}" width="{PANEL}" height="{PANEL}" fill="none" stroke="#444"/>"##
        );
        for (_, horizontal, value) in ticks {
            let label = format!("{value:.dec$}").replace('-', "−");
            if horizontal {
                let _ = writeln!(
                    s,
                    r#"<text x="{:.1}" y="{}" font-size="12" text-anchor="middle">{label}</text>"#,
                    px(value),
                    TOP + PANEL + 18.0
                );
            } else {
                let _ = writeln!(
                    s,
                    r#"<text x="{}" y="{:.1}" font-size="12" text-anchor="end" dominant-baseline="middle">{label}</text>"#,
                    x0 - 6.0,
                    py(value)
                );
            }
        }
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" font-size="14" text-anchor="middle">{} [m]</text>"#,
            x0 + PANEL / 2.0,
            TOP + PANEL + 40.0,
            AXIS_NAMES[view.h]
        );
        let (lx, ly) = (x0 - 48.0, TOP + PANEL / 2.0);
        let _ = writeln!(
            s,
            r#"<text x="{lx}" y="{ly}" font-size="14" text-anchor="middle" transform="rotate(-90 {lx} {ly})">{} [m]</text>"#,
            AXIS_NAMES[view.v]
        );
    }
    // The colour bar.
    let bx = LEFT + 3.0 * PANEL + 2.0 * GAP + 10.0;
    let _ = writeln!(
        s,
        r#"<defs><linearGradient id="viridis" x1="0" y1="1" x2="0" y2="0">"#
    );
    for (k, _) in VIRIDIS.iter().enumerate() {
        let t = k as f64 / (VIRIDIS.len() - 1) as f64;
        let _ = writeln!(s, r#"<stop offset="{t:.3}" stop-color="{}"/>"#, viridis(t));
    }
    let _ = writeln!(s, "</linearGradient></defs>");
    let _ = writeln!(
        s,
        r##"<rect x="{bx}" y="{TOP}" width="{BAR_WIDTH}" height="{PANEL}" fill="url(#viridis)" stroke="#444"/>"##
    );
    let bar_step = nice_step(w_max.max(1e-12), 5.0);
    let bar_dec = decimals(bar_step);
    let mut i = 0;
    while w_max > 0.0 && i as f64 * bar_step <= w_max * (1.0 + 1e-9) {
        let value = i as f64 * bar_step;
        let y = TOP + PANEL - value * norm * PANEL;
        let _ = writeln!(
            s,
            r##"<line x1="{}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#444"/><text x="{}" y="{y:.1}" font-size="12" dominant-baseline="middle">{value:.bar_dec$}</text>"##,
            bx + BAR_WIDTH,
            bx + BAR_WIDTH + 5.0,
            bx + BAR_WIDTH + 8.0
        );
        i += 1;
    }
    let (lx, ly) = (bx + BAR_WIDTH + 62.0, TOP + PANEL / 2.0);
    let label = match set.task() {
        TaskSpace::Position => "manipulability √det(J·Jᵀ) [m³]",
        TaskSpace::Pose => "manipulability √det(J·Jᵀ), 6 rows",
    };
    let _ = writeln!(
        s,
        r#"<text x="{lx}" y="{ly}" font-size="14" text-anchor="middle" transform="rotate(-90 {lx} {ly})">{label}</text>"#
    );
    let _ = writeln!(
        s,
        r##"<text x="{LEFT}" y="{}" font-size="13" fill="#333">Each {CELL}-pixel cell ({:.3} m) shows the highest manipulability among the samples seen through it; white: never reached.</text><text x="{LEFT}" y="{}" font-size="13" fill="#333">Dashed red: the sphere of maximum reach around the base point (red cross). Joint limits only: no self-collision or floor checks.</text>"##,
        TOP + PANEL + 72.0,
        CELL / scale,
        TOP + PANEL + 92.0
    );
    let _ = writeln!(s, "</svg>");
    s
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
    fn formats_follow_the_extension() {
        assert_eq!(format_of(Path::new("a/ws.PLY")).unwrap(), Format::Ply);
        assert_eq!(format_of(Path::new("ws.csv")).unwrap(), Format::Csv);
        assert_eq!(format_of(Path::new("ws.json")).unwrap(), Format::Json);
        let e = format_of(Path::new("ws.txt")).unwrap_err().to_string();
        assert!(e.contains(".ply, .csv or .json"), "{e}");
    }

    #[test]
    fn ticks_are_round() {
        assert!((nice_step(1.7, 6.0) - 0.5).abs() < 1e-12);
        assert!((nice_step(0.9, 6.0) - 0.2).abs() < 1e-12);
        assert!((nice_step(0.011, 5.0) - 0.0025).abs() < 1e-12);
        assert_eq!(decimals(0.25), 2);
        assert_eq!(decimals(2.0), 0);
        assert_eq!(group_digits(1_234_567), "1\u{2009}234\u{2009}567");
        assert_eq!(group_digits(999), "999");
        assert_eq!(viridis(0.0), "#440154");
        assert_eq!(viridis(1.0), "#fde725");
        assert_eq!(viridis(f64::NAN), "#440154");
    }

    #[test]
    fn the_plot_has_three_views_axes_and_a_colour_bar() {
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
        };
        let svg = plot_svg(&set, &summary);
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        for text in [
            "Top view",
            "Front view",
            "Side view",
            "x [m]",
            "y [m]",
            "z [m]",
            "linearGradient",
            "planar &lt;2r&gt;.urdf",
            "manipulability",
        ] {
            assert!(svg.contains(text), "no {text}");
        }
        assert!(svg.matches("<path fill=").count() > 3 * 10, "colour levels");
        // The top view: the annulus is drawn, its hole and the corners stay empty.
        let span = 3.0 * 1.1;
        let top = projection(&set, &VIEWS[0], (0.0, 0.0), PANEL / span, 1.0 / 0.5);
        let cell = |x: f64, y: f64| top[cell_of((x, y), (0.0, 0.0), PANEL / span).unwrap()];
        assert!(level_of(cell(0.0, 0.0)).is_none());
        assert!(level_of(cell(0.2, -0.2)).is_none());
        assert!(level_of(cell(1.6, 1.6)).is_none());
        // Every sample shows, at least as bright as itself; the best one at the top level.
        for (p, &w) in set.positions().iter().zip(set.manipulability()) {
            let level = level_of(cell(p.x, p.y)).unwrap();
            assert!(level >= level_of(w / 0.5).unwrap());
        }
        assert!(top.iter().any(|&w| w > 0.99));
        let report = summary.report(&set);
        assert!(report.contains("max reach    1.5000 m"), "{report}");
    }
}
