//! SVG pictures written by hand (no plotting dependency): line charts ([`chart`], for
//! `kinetree simulate`) and projections of a reachable-workspace cloud ([`workspace`], for
//! `kinetree workspace`), sharing one tick rule ([`tick_step`]), label precision and escaping.

pub(crate) mod chart;
pub(crate) mod workspace;

pub(crate) use chart::{Series, chart};

/// A tick step of 1, 2, 2.5 or 5 times a power of ten giving at most `max_ticks` ticks over
/// `span`.
pub(crate) fn tick_step(span: f64, max_ticks: f64) -> f64 {
    let raw = (span / max_ticks).max(1e-9);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

/// Decimals needed to print multiples of `step`.
pub(crate) fn decimals(step: f64) -> usize {
    let mut d = 0;
    while d < 6
        && ((step * 10f64.powi(d as i32)).round() - step * 10f64.powi(d as i32)).abs() > 1e-9
    {
        d += 1;
    }
    d
}

/// `s` with the XML special characters escaped, for SVG text and attributes.
pub(crate) fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A complete SVG document of `width` x `height` holding what `draw` appends.
pub(crate) fn document(width: f64, height: f64, draw: impl FnOnce(&mut String)) -> String {
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif"><rect width="100%" height="100%" fill="white"/>"#
    );
    svg.push('\n');
    draw(&mut svg);
    svg.push_str("</svg>\n");
    svg
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round() {
        assert!((tick_step(1.7, 6.0) - 0.5).abs() < 1e-12);
        assert!((tick_step(0.9, 6.0) - 0.2).abs() < 1e-12);
        assert!((tick_step(0.011, 5.0) - 0.0025).abs() < 1e-12);
        assert_eq!(decimals(0.25), 2);
        assert_eq!(decimals(2.0), 0);
    }
}
