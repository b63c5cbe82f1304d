//! Line charts (`kinetree simulate --plot`): axes with ticks, labels, a title and a legend.

use super::{decimals, tick_step, xml_escape};
use std::fmt::Write;

/// One named curve.
pub(crate) struct Series<'a> {
    pub(crate) name: &'a str,
    pub(crate) points: Vec<(f64, f64)>,
}

const PALETTE: [&str; 10] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

/// Appends one chart of size `w` x `h` at offset `(x0, y0)` to `svg`.
pub(crate) fn chart(
    svg: &mut String,
    (x0, y0, w, h): (f64, f64, f64, f64),
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series<'_>],
) {
    let (left, right, top, bottom) = (95.0, 170.0, 30.0, 45.0);
    let (pw, ph) = (w - left - right, h - top - bottom);
    let pts = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        (xmin, xmax, ymin, ymax) = (xmin.min(x), xmax.max(x), ymin.min(y), ymax.max(y));
    }
    if xmin > xmax {
        (xmin, xmax, ymin, ymax) = (0.0, 1.0, 0.0, 1.0);
    }
    if ymax - ymin < 1e-12 * ymax.abs().max(1.0) {
        let pad = 0.5 * ymax.abs().max(1e-9);
        (ymin, ymax) = (ymin - pad, ymax + pad);
    }
    if xmax == xmin {
        xmax = xmin + 1.0;
    }
    // Titles, labels and series names come from the model (joint names): escaped once here.
    let (title, x_label, y_label) = (xml_escape(title), xml_escape(x_label), xml_escape(y_label));
    let sx = |x: f64| x0 + left + (x - xmin) / (xmax - xmin) * pw;
    let sy = |y: f64| y0 + top + (1.0 - (y - ymin) / (ymax - ymin)) * ph;
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" font-size="15" font-weight="bold">{title}</text>"#,
        x0 + left,
        y0 + 20.0
    );
    let _ = writeln!(
        svg,
        r##"<rect x="{:.1}" y="{:.1}" width="{pw:.1}" height="{ph:.1}" fill="none" stroke="#444"/>"##,
        x0 + left,
        y0 + top
    );
    for (lo, hi, vertical) in [(xmin, xmax, true), (ymin, ymax, false)] {
        let step = tick_step(hi - lo, 6.0);
        let mut t = (lo / step).ceil() * step;
        while t <= hi + 1e-9 * step {
            // As many decimals as the tick step needs, so neighbouring labels differ.
            let label = format!("{:.*}", decimals(step), (t / step).round() * step);
            if vertical {
                let x = sx(t);
                let _ = writeln!(
                    svg,
                    r##"<line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" font-size="11" text-anchor="middle">{label}</text>"##,
                    y0 + top,
                    y0 + top + ph,
                    y0 + top + ph + 15.0
                );
            } else {
                let y = sy(t);
                let _ = writeln!(
                    svg,
                    r##"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" font-size="11" text-anchor="end">{label}</text>"##,
                    x0 + left,
                    x0 + left + pw,
                    x0 + left - 5.0,
                    y + 4.0
                );
            }
            t += step;
        }
    }
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" font-size="12" text-anchor="middle">{x_label}</text>"#,
        x0 + left + pw / 2.0,
        y0 + h - 8.0
    );
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" font-size="12" text-anchor="middle" transform="rotate(-90 {:.1} {:.1})">{y_label}</text>"#,
        x0 + 15.0,
        y0 + top + ph / 2.0,
        x0 + 15.0,
        y0 + top + ph / 2.0
    );
    for (k, s) in series.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let path: Vec<String> = s
            .points
            .iter()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|&(x, y)| format!("{:.1},{:.1}", sx(x), sy(y)))
            .collect();
        let _ = writeln!(
            svg,
            r#"<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{}"/>"#,
            path.join(" ")
        );
        let ly = y0 + top + 14.0 * k as f64 + 8.0;
        let lx = x0 + left + pw + 12.0;
        let _ = writeln!(
            svg,
            r#"<line x1="{lx:.1}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{colour}" stroke-width="2"/><text x="{:.1}" y="{:.1}" font-size="11">{}</text>"#,
            lx + 18.0,
            lx + 22.0,
            ly + 4.0,
            xml_escape(s.name)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every `&` of `svg` starts an entity, and no `<` or `>` stands inside a text element.
    fn assert_well_formed_text(svg: &str) {
        for (at, _) in svg.match_indices('&') {
            let rest = &svg[at..];
            assert!(
                ["&amp;", "&lt;", "&gt;", "&quot;"]
                    .iter()
                    .any(|e| rest.starts_with(e)),
                "a bare & at {at}: {}",
                &rest[..rest.len().min(20)]
            );
        }
        for text in svg.split("<text").skip(1) {
            let inner = &text[text.find('>').unwrap() + 1..text.find("</text>").unwrap()];
            assert!(!inner.contains(['<', '>']), "markup inside a text: {inner}");
        }
    }

    #[test]
    fn names_with_xml_characters_are_escaped() {
        let mut svg = String::new();
        let series = [
            Series {
                name: "a&b",
                points: vec![(0.0, 0.0), (1.0, 1.0)],
            },
            Series {
                name: "<joint \"2\">",
                points: vec![(0.0, 1.0), (1.0, 0.0)],
            },
        ];
        chart(
            &mut svg,
            (0.0, 0.0, 800.0, 300.0),
            "q of a&b <arm>",
            "t [s]",
            "q<rad>",
            &series,
        );
        assert!(svg.contains(">q of a&amp;b &lt;arm&gt;</text>"), "{svg}");
        assert!(svg.contains(">a&amp;b</text>"), "{svg}");
        assert!(svg.contains(">&lt;joint &quot;2&quot;&gt;</text>"), "{svg}");
        assert!(svg.contains(">q&lt;rad&gt;</text>"), "{svg}");
        assert_well_formed_text(&svg);
    }
}
