//! What the figures share: escaped text, round ticks, the frame of a page,
//! and (feature `plots`) a plotters canvas drawn into a string.

pub(crate) use crate::text::xml_escape as esc;

/// A step of 1, 2 or 5 times a power of ten giving about 5 to 10 ticks
/// over `span` (positive).
pub(crate) fn tick_step(span: f64) -> f64 {
    let raw = span / 8.0;
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * mag)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * mag)
}

/// The multiples of `step` in `[lo, hi]`; `None` for a range that f64
/// cannot step through (ends too far apart, or too close for their size).
pub(crate) fn ticks(lo: f64, hi: f64, step: f64) -> Option<Vec<f64>> {
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    if !step.is_finite() || step <= 0.0 || last.saturating_sub(first) > 100 {
        return None;
    }
    Some((first..=last).map(|k| k as f64 * step).collect())
}

/// The CSS every page starts with.
pub(crate) const PAGE_STYLE: &str =
    "body{font-family:Helvetica,Arial,sans-serif;margin:1em;background:#fafafa}";

/// A self-contained HTML page (no script, no network): `title` (escaped)
/// as its title and heading, `style` (CSS) and `body` (HTML) as they are.
pub(crate) fn page(title: &str, style: &str, body: &str) -> String {
    let t = esc(title);
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{t}</title>\n<style>{PAGE_STYLE}{style}</style>\n</head>\n<body>\n<h1>{t}</h1>\n{body}</body>\n</html>\n"
    )
}

/// What drawing on a plotters canvas returns.
#[cfg(feature = "plots")]
pub(crate) type Drawn<T = ()> = Result<T, Box<dyn std::error::Error>>;

/// A plotters drawing area writing SVG.
#[cfg(feature = "plots")]
pub(crate) type Area<'a> =
    plotters::prelude::DrawingArea<plotters::prelude::SVGBackend<'a>, plotters::coord::Shift>;

/// A chart of two f64 axes on an SVG canvas.
#[cfg(feature = "plots")]
pub(crate) type Chart<'a, 'b> = plotters::prelude::ChartContext<
    'a,
    plotters::prelude::SVGBackend<'b>,
    plotters::prelude::Cartesian2d<
        plotters::coord::types::RangedCoordf64,
        plotters::coord::types::RangedCoordf64,
    >,
>;

/// Sans-serif text of `size` in `colour`, anchored at `(h, v)`.
#[cfg(feature = "plots")]
pub(crate) fn text_style(
    size: u32,
    colour: &plotters::style::RGBColor,
    h: plotters::style::text_anchor::HPos,
    v: plotters::style::text_anchor::VPos,
) -> plotters::style::TextStyle<'static> {
    use plotters::style::{text_anchor::Pos, IntoFont};
    ("sans-serif", size)
        .into_font()
        .color(colour)
        .pos(Pos::new(h, v))
}

/// The 100 steps of a colour bar on `bar` from `lo` to `lo + span`: step
/// `k`, from `a` to `b`, filled with `colour(k, a, b)`.
#[cfg(feature = "plots")]
pub(crate) fn colour_steps(
    bar: &mut Chart<'_, '_>,
    (lo, span): (f64, f64),
    colour: impl Fn(usize, f64, f64) -> plotters::style::RGBColor,
) -> Drawn {
    use plotters::prelude::*;
    bar.draw_series((0..100).map(|k| {
        let (a, b) = (
            lo + span * k as f64 / 100.0,
            lo + span * (k + 1) as f64 / 100.0,
        );
        Rectangle::new([(0.0, a), (1.0, b)], colour(k, a, b).filled())
    }))?;
    Ok(())
}

/// The SVG text of a white canvas of `size` pixels on which `draw` draws.
#[cfg(feature = "plots")]
pub(crate) fn plotted(size: (u32, u32), draw: impl FnOnce(&Area<'_>) -> Drawn) -> Drawn<String> {
    use plotters::prelude::*;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    Ok(svg)
}
