//! The picture of `kinetree workspace --plot`: top, front and side projections of a
//! reachable-workspace cloud coloured by manipulability, with the base, the sphere of maximum
//! reach, axes in metres and a colour bar.

use super::{decimals, tick_step, xml_escape};
use kinetree::spatial::DVec3;
use kinetree::workspace::{ReachableSet, Sampling, TaskSpace};
use std::fmt::Write as _;

/// What the picture says besides the samples.
#[derive(Debug)]
pub(crate) struct Caption<'a> {
    /// The model file's name.
    pub(crate) file: &'a str,
    /// The maximum reach from `base` (m).
    pub(crate) reach: f64,
    /// The base point (m).
    pub(crate) base: DVec3,
    /// The voxel size (m).
    pub(crate) voxel: f64,
    /// The volume of the voxels hit (m³).
    pub(crate) volume: f64,
}

/// `n` with its digits in groups of three, `1 000 000`.
pub(crate) fn group_digits(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push('\u{2009}');
        }
        out.push(c);
    }
    out
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
pub(crate) fn cloud_svg(set: &ReachableSet, summary: &Caption<'_>) -> String {
    let b = set.bounds();
    let center = b.center().to_array();
    // One scale for all views: the largest extent, padded, fills a panel.
    let span = (b.size().max_element() * 1.1).max(0.05);
    let scale = PANEL / span;
    let w_max = set
        .manipulability()
        .iter()
        .fold(0.0_f64, |hi, &x| hi.max(x));
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
        xml_escape(summary.file)
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
    let step = tick_step(span, 6.0);
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
    let bar_step = tick_step(w_max.max(1e-12), 5.0);
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
    use kinetree::kinematics::FrameId;
    use kinetree::model::samples;
    use kinetree::workspace::{ReachableParams, sample_reachable};

    #[test]
    fn digits_are_grouped_by_three() {
        assert_eq!(group_digits(1_234_567), "1\u{2009}234\u{2009}567");
        assert_eq!(group_digits(999), "999");
    }

    #[test]
    fn viridis_runs_from_purple_to_yellow() {
        assert_eq!(viridis(0.0), "#440154");
        assert_eq!(viridis(1.0), "#fde725");
        assert_eq!(viridis(f64::NAN), "#440154");
    }

    #[test]
    fn the_plot_has_three_views_axes_and_a_colour_bar() {
        let model = samples::planar_2r(1.0, 0.5);
        let tool = FrameId::find(&model, "tool").unwrap();
        let set = sample_reachable(&model, tool, &ReachableParams::grid(61)).unwrap();
        let caption = Caption {
            file: "planar <2r>.urdf",
            reach: set.max_reach(DVec3::ZERO).unwrap(),
            base: DVec3::ZERO,
            voxel: 0.02,
            volume: 0.001,
        };
        let svg = cloud_svg(&set, &caption);
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
    }
}
