//! Figures of a sweep, from its `summary.csv`: a line plot with 95%
//! intervals against one parameter, or a heat map over two.
//!
//! ```
//! use e3d::csv::Summary;
//! use e3d::report::sweep_plot::{plot, PlotSpec};
//! let csv = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions,h_mean,h_sd,h_ci_low,h_ci_high\n\
//!            g,e3d,false,0.3,1,0.03,0.01,,3,0.9,0.01,0.88,0.92\n\
//!            g,e3d,false,0.3,10,0.03,0.01,,3,0.8,0.01,0.78,0.82\n\
//!            g,uniform,false,,,,,,3,0.7,0.01,0.68,0.72\n";
//! let summary = Summary::parse(csv).unwrap();
//! let spec = PlotSpec { x: "beta".into(), y: None, metric: "h".into(), filters: vec![] };
//! let svg = plot(&summary, &spec).unwrap();
//! assert!(svg.starts_with("<svg") && svg.contains("uniform"));
//! ```

use super::svg::{colour_steps, plotted, text_style, Area, Chart, Drawn};
use crate::csv::Summary;
use crate::learner::Params;
use crate::scene::did_you_mean;
use crate::sweep::CELL_COLUMNS;
use plotters::prelude::*;

mod heat;
mod lines;

use heat::draw_heat;
use lines::{draw_lines, line_series};
use plotters::style::text_anchor::{HPos, VPos};

/// A figure that cannot be drawn: why, and what was expected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct PlotError(pub String);

fn err<T>(m: impl Into<String>) -> Result<T, PlotError> {
    Err(PlotError(m.into()))
}

/// What to draw.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotSpec {
    /// The parameter on the x axis.
    pub x: String,
    /// A second parameter: draw a heat map over (x, y).
    pub y: Option<String>,
    /// The metric (a column `METRIC_mean` of the summary).
    pub metric: String,
    /// Keep only the cells whose column `.0` reads `.1`.
    pub filters: Vec<(String, String)>,
}

/// Draws the figure `spec` asks for and returns it as SVG text.
///
/// Line plot (no `y`): one line per combination of the cell columns other
/// than `x` that vary, with its 95% interval as a band; a learner that
/// does not use `x` (an empty `x` column, the uniform policy for example)
/// is drawn as a dashed horizontal line with its band. The x axis is
/// logarithmic when every x is positive and they span a factor 20 or
/// more. Heat map (`y` given): the mean of the metric in each (x, y) cell;
/// the other columns must not vary (select with `filters`).
pub fn plot(summary: &Summary, spec: &PlotSpec) -> Result<String, PlotError> {
    // plotters escapes `<` and `&` but not control characters, which a
    // hand-edited summary may hold
    draw(summary, spec).map(crate::text::xml_forbidden_escaped)
}

fn draw(summary: &Summary, spec: &PlotSpec) -> Result<String, PlotError> {
    let metrics = summary.metrics();
    if !metrics.contains(&spec.metric.as_str()) {
        return err(format!(
            "no metric `{}` in the summary{}; expected one of: {}",
            spec.metric,
            did_you_mean(&spec.metric, &metrics),
            metrics.join(", ")
        ));
    }
    // a summary read by `Summary::parse` has every parameter's column and
    // rows of the header's length; one built in code may not
    let columns = summary.columns.len();
    let mut widths = summary.rows.iter().map(Vec::len).enumerate();
    if let Some((i, fields)) = widths.find(|&(_, n)| n != columns) {
        let row = i + 1;
        return err(format!(
            "row {row} of the summary has {fields} fields, expected {columns} (one per column)"
        ));
    }
    // the parameters, and the scene axes' paths
    let cells = summary.cell_columns();
    let axes = summary.columns[CELL_COLUMNS.min(cells)..cells].iter();
    let params: Vec<&str> = Params::SWEPT
        .into_iter()
        .chain(axes.map(String::as_str))
        .collect();
    let check_param = |p: &str| -> Result<usize, PlotError> {
        if !params.contains(&p) {
            return err(format!(
                "`{p}` is not a parameter{}; expected one of: {}",
                did_you_mean(p, &params),
                params.join(", ")
            ));
        }
        summary.col(p).ok_or_else(|| {
            PlotError(format!(
                "the summary has no `{p}` column; expected the columns e3d writes"
            ))
        })
    };
    let xi = check_param(&spec.x)?;
    let yi = spec.y.as_deref().map(check_param).transpose()?;
    if yi == Some(xi) {
        return err("--x and --y name the same parameter");
    }
    let rows = filtered_rows(summary, &spec.filters)?;
    // a summary written by e3d has the four; an edited one may not
    let col = |suffix: &str| {
        let name = format!("{}_{suffix}", spec.metric);
        summary.col(&name).ok_or_else(|| {
            PlotError(format!(
                "the summary has `{}_mean` but no `{name}` column; expected the columns e3d writes",
                spec.metric
            ))
        })
    };
    let (mi, lo, hi) = (col("mean")?, col("ci_low")?, col("ci_high")?);
    let metric = metric_label(&spec.metric);
    let title = plot_title(spec, &metric);
    match yi {
        None => {
            let series = line_series(&summary.columns[..cells], &rows, xi, mi, lo, hi)?;
            draw_lines(&title, &spec.x, &metric, &series)
        }
        Some(yi) => {
            let rows = one_setting(&summary.columns[..cells], rows, xi, yi, spec)?;
            let y = spec.y.as_deref().unwrap_or_default();
            draw_heat(&title, &spec.x, y, rows, xi, yi, mi)
        }
    }
}

/// The rows of `summary` that pass every filter (a parameter a learner
/// does not use, empty, passes any filter on it); an unknown column or no
/// row left is an error naming what there is.
fn filtered_rows<'a>(
    summary: &'a Summary,
    filters: &[(String, String)],
) -> Result<Vec<&'a Vec<String>>, PlotError> {
    let cells = summary.cell_columns();
    let cell_cols: Vec<&str> = summary.columns[..cells]
        .iter()
        .map(String::as_str)
        .collect();
    let mut rows: Vec<&Vec<String>> = summary.rows.iter().collect();
    for (k, v) in filters {
        let Some(ci) = summary.col(k).filter(|&i| i < cells) else {
            return err(format!(
                "--where {k}={v}: `{k}` is not a cell column{}; expected one of: {}",
                did_you_mean(k, &cell_cols),
                cell_cols.join(", ")
            ));
        };
        let before = rows.clone();
        // a parameter a learner does not use (empty) passes any filter on it
        let is_param = Params::SWEPT.contains(&k.as_str());
        rows.retain(|r| r[ci] == *v || (is_param && r[ci].is_empty()));
        if rows.is_empty() {
            let seen = distinct(before.iter().map(|r| r[ci].as_str()));
            let seen: Vec<&str> = (seen.iter())
                .map(|&s| if s.is_empty() { "(empty)" } else { s })
                .collect();
            return err(format!(
                "--where {k}={v}: no cell left; `{k}` takes the values: {}",
                seen.join(", ")
            ));
        }
    }
    Ok(rows)
}

/// The title: the metric against x (or over x and y), with the filters.
fn plot_title(spec: &PlotSpec, metric: &str) -> String {
    let mut title = match &spec.y {
        None => format!("{} against {}", capitalise(metric), spec.x),
        Some(y) => format!("{}: mean over {} and {y}", capitalise(metric), spec.x),
    };
    if !spec.filters.is_empty() {
        let f: Vec<String> = spec
            .filters
            .iter()
            .map(|(k, v)| filter_label(k, v))
            .collect();
        title.push_str(&format!(" ({})", f.join(", ")));
    }
    title
}

/// The rows of a heat map: those with both x and y, in which no other
/// cell column (named `cells`) varies.
fn one_setting<'a>(
    cells: &[String],
    rows: Vec<&'a Vec<String>>,
    xi: usize,
    yi: usize,
    spec: &PlotSpec,
) -> Result<Vec<&'a Vec<String>>, PlotError> {
    // one cell per (x, y): the other columns must be fixed
    let rows: Vec<&Vec<String>> = rows
        .into_iter()
        .filter(|r| !r[xi].is_empty() && !r[yi].is_empty())
        .collect();
    if rows.is_empty() {
        return err(format!(
            "no cell has both {} and {} (no learner uses both)",
            spec.x,
            spec.y.as_deref().unwrap_or_default()
        ));
    }
    let varying: Vec<String> = (0..cells.len())
        .filter(|&c| c != xi && c != yi)
        .filter(|&c| rows.iter().any(|r| r[c] != rows[0][c]))
        .map(|c| {
            let vals = distinct(rows.iter().map(|r| r[c].as_str()));
            format!("{} ({})", cells[c], vals.join(", "))
        })
        .collect();
    if !varying.is_empty() {
        return err(format!(
        "a heat map shows one setting, but these columns vary: {}; choose with --where COLUMN=VALUE",
        varying.join("; ")
    ));
    }
    Ok(rows)
}

/// A number in 4 significant digits, without trailing zeros.
pub(crate) fn short(v: f64) -> String {
    significant(v, 4)
}

/// A number in `digits` significant digits, without trailing zeros (3 for
/// the labels of a heat map's columns: 3.16, 31.6).
fn significant(v: f64, digits: i32) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{v:.2e}");
    }
    let decimals = (digits - 1 - mag).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A metric's name as a reader says it (`cumulative_reward_at_5000`:
/// "cumulative reward at trial 5000"); an unknown name with its
/// underscores as spaces.
pub fn metric_label(metric: &str) -> String {
    match metric {
        "normalized_entropy" => "normalised entropy".into(),
        "normalized_entropy_last_1000" => "normalised entropy of the last 1000 trials".into(),
        "kl_to_target" => "KL divergence to the target (nats)".into(),
        "distinct_effects" => "distinct effects reached".into(),
        "first_reward_trial" => "trial of the first reward".into(),
        "coverage" => "fraction of the reachable cells reached".into(),
        "trials_to_50_percent" => "trials to reach 50% of the reachable cells".into(),
        "trials_to_90_percent" => "trials to reach 90% of the reachable cells".into(),
        "reproducibility" => "share of the final commands keeping their effect".into(),
        "qd_score" => "QD-score (best effort quality summed over the reached cells)".into(),
        m => match m.strip_prefix("cumulative_reward_at_") {
            Some(t) => format!("cumulative reward at trial {t}"),
            None => m.replace('_', " "),
        },
    }
}

/// A parameter's name with what it is (`beta (inverse temperature)`).
pub fn param_label(param: &str) -> String {
    let what = match param {
        "alpha" => "learning rate",
        "beta" => "inverse temperature",
        "lambda" => "reward weight",
        "eta" => "rate of the effect histogram",
        "epsilon" => "exploration rate",
        _ => return param.replace('_', " "),
    };
    format!("{param} ({what})")
}

/// A `--where` filter in words: `use_reward=true` is "with reward".
fn filter_label(column: &str, value: &str) -> String {
    match (column, value) {
        ("use_reward", "true") => "with reward".into(),
        ("use_reward", "false") => "without reward".into(),
        ("learner" | "scene", v) => v.to_string(),
        (c, v) => format!("{c} {v}"),
    }
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => String::new(),
    }
}

/// The ticks of a log axis over `[lo, hi]` (values, not logarithms): the
/// decades, with 2 and 5 between them when fewer than three decades fall
/// inside (1-2-5), and if even that gives fewer than two, the ends.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let (a, b) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    if !(lo > 0.0 && hi.is_finite()) || b.saturating_sub(a) > 700 {
        return vec![lo, hi];
    }
    let inside = |v: f64| v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9);
    let decades: Vec<f64> = (a..=b)
        .map(|k| 10f64.powi(k))
        .filter(|&v| inside(v))
        .collect();
    if decades.len() >= 3 {
        return decades;
    }
    let mut t: Vec<f64> = (a..=b)
        .flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)))
        .filter(|&v| inside(v))
        .collect();
    if t.len() < 2 {
        t = vec![lo, hi];
    }
    t
}

/// A summary's field as a number (`None`: empty or not a number).
fn num(s: &str) -> Option<f64> {
    s.parse().ok()
}

/// The distinct `values`, sorted.
pub(super) fn distinct<'a>(values: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let mut v: Vec<&str> = values.collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// The smallest and the largest of `xs` (infinities for none).
fn range(xs: impl Iterator<Item = f64>) -> (f64, f64) {
    xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    })
}

/// Round ticks of a linear axis over `[lo, hi]` (its two ends when f64
/// cannot step through it).
fn linear_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let step = super::svg::tick_step((hi - lo).max(1e-12));
    let Some(ticks) = super::svg::ticks(lo, hi, step) else {
        return vec![lo, hi];
    };
    // 0.30000000000000004 is written 0.3
    ticks
        .into_iter()
        .map(|v| format!("{v:.12}").parse().unwrap_or(v))
        .collect()
}

/// How series `i` is drawn: a colour, a marker and a dash pattern, so that
/// past the 10 colours the series still differ (marker, then dashes).
#[derive(Clone, Copy)]
struct Style {
    colour: RGBColor,
    /// A circle, a square, a triangle or a diamond (0 to 3).
    marker: usize,
    dashed: bool,
}

fn style(i: usize) -> Style {
    Style {
        colour: PALETTE[i % PALETTE.len()],
        marker: (i / PALETTE.len()) % 4,
        dashed: (i / PALETTE.len()) % 2 == 1,
    }
}

/// A marker of `style` at `(x, y)` pixels of `area`.
fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    (x, y): (i32, i32),
    st: Style,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let c = st.colour.filled();
    match st.marker {
        0 => area.draw(&Circle::new((x, y), 4, c)),
        1 => area.draw(&Rectangle::new([(x - 4, y - 4), (x + 4, y + 4)], c)),
        2 => area.draw(&Polygon::new(
            vec![(x, y - 5), (x + 5, y + 4), (x - 5, y + 4)],
            c,
        )),
        _ => area.draw(&Polygon::new(
            vec![(x, y - 5), (x + 5, y), (x, y + 5), (x - 5, y)],
            c,
        )),
    }
}

/// Tableau's ten colours.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

const FONT: &str = "sans-serif";

fn draw_err(e: Box<dyn std::error::Error>) -> PlotError {
    PlotError(format!("cannot draw: {e}"))
}

#[cfg(test)]
mod tests {
    use super::heat::heat_axis_label;
    use super::*;

    #[test]
    fn log_axes_tick_at_decades_or_1_2_5() {
        assert_eq!(log_ticks(1.0, 1000.0), vec![1.0, 10.0, 100.0, 1000.0]);
        assert_eq!(log_ticks(0.003, 0.1), vec![0.005, 0.01, 0.02, 0.05, 0.1]);
        assert_eq!(log_ticks(3.0, 70.0), vec![5.0, 10.0, 20.0, 50.0]);
        // never the swept values 3.162, 31.62
        assert!(!log_ticks(1.0, 1000.0)
            .iter()
            .any(|t| short(*t).contains("3.162")));
        assert_eq!(linear_ticks(0.0, 1.0), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
        assert_eq!(linear_ticks(0.07, 0.33), vec![0.1, 0.15, 0.2, 0.25, 0.3]);
    }

    #[test]
    fn labels_are_words() {
        assert_eq!(metric_label("normalized_entropy"), "normalised entropy");
        assert_eq!(
            metric_label("cumulative_reward_at_5000"),
            "cumulative reward at trial 5000"
        );
        assert_eq!(metric_label("some_new_metric"), "some new metric");
        assert_eq!(param_label("beta"), "beta (inverse temperature)");
        assert_eq!(filter_label("use_reward", "true"), "with reward");
        assert_eq!(
            heat_axis_label("beta", &[1.0, 3.16227766017, 10.0, 31.6227766017, 100.0]),
            "beta (inverse temperature), log-spaced values"
        );
        assert_eq!(
            heat_axis_label("eta", &[0.01, 0.02, 0.03]),
            "eta (rate of the effect histogram)"
        );
        assert_eq!(significant(3.16227766017, 3), "3.16");
        assert_eq!(significant(31.6227766017, 3), "31.6");
        assert_eq!(significant(1000.0, 3), "1000");
    }

    #[test]
    fn styles_differ_past_the_ten_colours() {
        let all: Vec<(RGBColor, usize, bool)> = (0..40)
            .map(|i| {
                let s = style(i);
                (s.colour, s.marker, s.dashed)
            })
            .collect();
        for i in 0..40 {
            for j in 0..i {
                assert!(all[i] != all[j], "series {i} and {j} look the same");
            }
        }
    }

    #[test]
    fn short_numbers() {
        assert_eq!(short(3.16227766017), "3.162");
        assert_eq!(short(316.227766017), "316.2");
        assert_eq!(short(0.003), "0.003");
        assert_eq!(short(1000.0), "1000");
        assert_eq!(short(0.0), "0");
    }
}
