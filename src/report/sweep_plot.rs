//! Figures of a sweep, from its `summary.csv`: a line plot with 95%
//! intervals against one parameter, or a heat map over two.
//!
//! ```
//! use e3d::report::sweep_plot::{plot, PlotSpec, Summary};
//! let csv = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions,h_mean,h_sd,h_ci_low,h_ci_high\n\
//!            g,e3d,false,0.3,1,0.03,0.01,,3,0.9,0.01,0.88,0.92\n\
//!            g,e3d,false,0.3,10,0.03,0.01,,3,0.8,0.01,0.78,0.82\n\
//!            g,uniform,false,,,,,,3,0.7,0.01,0.68,0.72\n";
//! let summary = Summary::parse(csv).unwrap();
//! let spec = PlotSpec { x: "beta".into(), y: None, metric: "h".into(), filters: vec![] };
//! let svg = plot(&summary, &spec).unwrap();
//! assert!(svg.starts_with("<svg") && svg.contains("uniform"));
//! ```

use crate::scene::did_you_mean;
use crate::sweep::{CELL_COLUMNS, KEY_COLUMNS, PARAM_NAMES};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A figure that cannot be drawn: why, and what was expected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct PlotError(pub String);

fn err<T>(m: impl Into<String>) -> Result<T, PlotError> {
    Err(PlotError(m.into()))
}

/// The largest `summary.csv` `e3d plot` and `e3d report` read (64 MiB;
/// one row per cell, a few hundred bytes each).
pub const MAX_SUMMARY_CSV_BYTES: u64 = 64 << 20;

/// A sweep's `summary.csv`, parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The column names.
    pub columns: Vec<String>,
    /// The rows, one field per column.
    pub rows: Vec<Vec<String>>,
}

impl Summary {
    /// Parses the text of a `summary.csv`.
    ///
    /// The parameters and every column after the cell's (sessions,
    /// failures, the metrics' means, sds and intervals) must be empty or a
    /// finite number: `inf`, `NaN` or a word is refused with
    /// `summary.csv:LINE:COL` and the column, since one infinite value
    /// would stretch a figure's axis without end. Linear in the text.
    pub fn parse(text: &str) -> Result<Summary, PlotError> {
        const FILE: &str = "summary.csv";
        let mut lines = text.lines();
        let columns: Vec<String> = match lines.next() {
            Some(h) => h.split(',').map(str::to_string).collect(),
            None => return err("the summary is empty"),
        };
        if columns.len() < CELL_COLUMNS + 1
            || columns[..CELL_COLUMNS] != KEY_COLUMNS[..CELL_COLUMNS]
        {
            return err("not a sweep summary: expected the columns scene, learner, use_reward, alpha, beta, lambda, eta, epsilon, sessions, ...");
        }
        let mut rows = Vec::new();
        for (i, l) in lines.enumerate() {
            let f: Vec<String> = l.split(',').map(str::to_string).collect();
            if f.len() != columns.len() {
                return err(format!(
                    "{FILE}:{}:1: {} fields, expected {}",
                    i + 2,
                    f.len(),
                    columns.len()
                ));
            }
            let mut col = 1;
            for (k, v) in f.iter().enumerate() {
                if k >= CELL_COLUMNS - PARAM_NAMES.len() && !v.is_empty() {
                    crate::text::parse_finite(v, FILE, i + 2, col, &columns[k])
                        .map_err(PlotError)?;
                }
                col += v.chars().count() + 1;
            }
            rows.push(f);
        }
        Ok(Summary { columns, rows })
    }

    /// The metrics summarised (the names `m` with an `m_mean` column).
    pub fn metrics(&self) -> Vec<&str> {
        self.columns
            .iter()
            .filter_map(|c| c.strip_suffix("_mean"))
            .collect()
    }

    fn col(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }
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
    let check_param = |p: &str| -> Result<usize, PlotError> {
        if PARAM_NAMES.contains(&p) {
            Ok(summary.col(p).expect("cell columns are checked"))
        } else {
            err(format!(
                "`{p}` is not a parameter{}; expected one of: {}",
                did_you_mean(p, &PARAM_NAMES),
                PARAM_NAMES.join(", ")
            ))
        }
    };
    let xi = check_param(&spec.x)?;
    let yi = spec.y.as_deref().map(check_param).transpose()?;
    if yi == Some(xi) {
        return err("--x and --y name the same parameter");
    }
    let cell_cols: Vec<&str> = KEY_COLUMNS[..CELL_COLUMNS].to_vec();
    let mut rows: Vec<&Vec<String>> = summary.rows.iter().collect();
    for (k, v) in &spec.filters {
        let Some(ci) = summary.col(k).filter(|&i| i < CELL_COLUMNS) else {
            return err(format!(
                "--where {k}={v}: `{k}` is not a cell column{}; expected one of: {}",
                did_you_mean(k, &cell_cols),
                cell_cols.join(", ")
            ));
        };
        let before = rows.clone();
        // a parameter a learner does not use (empty) passes any filter on it
        let is_param = PARAM_NAMES.contains(&k.as_str());
        rows.retain(|r| r[ci] == *v || (is_param && r[ci].is_empty()));
        if rows.is_empty() {
            let mut seen: Vec<&str> = before.iter().map(|r| r[ci].as_str()).collect();
            seen.sort();
            seen.dedup();
            return err(format!(
                "--where {k}={v}: no cell left; `{k}` takes the values: {}",
                seen.iter()
                    .map(|s| if s.is_empty() { "(empty)" } else { s })
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    }
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
    let num = |s: &str| s.parse::<f64>().ok();
    let metric = metric_label(&spec.metric);
    let mut title = match &spec.y {
        None => format!("{} against {}", capitalise(&metric), spec.x),
        Some(y) => format!("{}: mean over {} and {y}", capitalise(&metric), spec.x),
    };
    if !spec.filters.is_empty() {
        let f: Vec<String> = spec
            .filters
            .iter()
            .map(|(k, v)| filter_label(k, v))
            .collect();
        title.push_str(&format!(" ({})", f.join(", ")));
    }
    match yi {
        None => {
            let series = line_series(&rows, xi, mi, lo, hi, &num)?;
            draw_lines(&title, &spec.x, &metric, &series)
        }
        Some(yi) => {
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
            let varying: Vec<String> = (0..CELL_COLUMNS)
                .filter(|&c| c != xi && c != yi)
                .filter(|&c| rows.iter().any(|r| r[c] != rows[0][c]))
                .map(|c| {
                    let mut vals: Vec<&str> = rows.iter().map(|r| r[c].as_str()).collect();
                    vals.sort();
                    vals.dedup();
                    format!("{} ({})", KEY_COLUMNS[c], vals.join(", "))
                })
                .collect();
            if !varying.is_empty() {
                return err(format!(
                    "a heat map shows one setting, but these columns vary: {}; choose with --where COLUMN=VALUE",
                    varying.join("; ")
                ));
            }
            draw_heat(
                &title,
                &spec.x,
                spec.y.as_deref().unwrap_or_default(),
                rows,
                xi,
                yi,
                mi,
                &num,
            )
        }
    }
}

/// One line of a line plot.
struct Series {
    label: String,
    /// (x, mean, ci_low, ci_high); a single point with x = NaN is a
    /// horizontal line (a learner that does not use x).
    points: Vec<(f64, f64, Option<f64>, Option<f64>)>,
}

fn line_series(
    rows: &[&Vec<String>],
    xi: usize,
    mi: usize,
    lo: usize,
    hi: usize,
    num: &dyn Fn(&str) -> Option<f64>,
) -> Result<Vec<Series>, PlotError> {
    // the cell columns that vary (besides x) name the series
    let varying: Vec<usize> = (0..CELL_COLUMNS)
        .filter(|&c| c != xi)
        .filter(|&c| rows.iter().any(|r| r[c] != rows[0][c]))
        .collect();
    // the columns named in labels: those with two or more distinct
    // non-empty values (a parameter only some learners use is not named)
    let mut named: Vec<usize> = varying
        .iter()
        .copied()
        .filter(|&c| {
            let mut v: Vec<&str> = rows
                .iter()
                .map(|r| r[c].as_str())
                .filter(|s| !s.is_empty())
                .collect();
            v.sort();
            v.dedup();
            v.len() >= 2
        })
        .collect();
    if named.is_empty() {
        named.push(1); // the learner
    }
    let mut series: Vec<Series> = Vec::new();
    let mut keys: Vec<String> = Vec::new();
    for r in rows {
        let key: Vec<&str> = varying.iter().map(|&c| r[c].as_str()).collect();
        let key = key.join(",");
        let Some(mean) = num(&r[mi]) else { continue };
        let x = if r[xi].is_empty() {
            f64::NAN
        } else {
            match num(&r[xi]) {
                Some(x) => x,
                None => return err(format!("{} = `{}` is not a number", KEY_COLUMNS[xi], r[xi])),
            }
        };
        let p = (x, mean, num(&r[lo]), num(&r[hi]));
        match keys.iter().position(|k| *k == key) {
            Some(i) => series[i].points.push(p),
            None => {
                let label = named
                    .iter()
                    .filter(|&&c| !r[c].is_empty())
                    .map(|&c| match KEY_COLUMNS[c] {
                        "learner" | "scene" => r[c].clone(),
                        "use_reward" => {
                            if r[c] == "true" {
                                "with reward".into()
                            } else {
                                "without reward".into()
                            }
                        }
                        name => format!("{name} {}", short(num(&r[c]).unwrap_or(f64::NAN))),
                    })
                    .collect::<Vec<_>>()
                    .join(", ");
                keys.push(key);
                series.push(Series {
                    label: if label.is_empty() {
                        "all".into()
                    } else {
                        label
                    },
                    points: vec![p],
                });
            }
        }
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    if series.iter().all(|s| s.points.iter().all(|p| p.0.is_nan())) {
        return err(format!(
            "no cell has a value of {} (no learner in the selection uses it)",
            KEY_COLUMNS[xi]
        ));
    }
    Ok(series)
}

/// A number in 4 significant digits, without trailing zeros.
pub(crate) fn short(v: f64) -> String {
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
    let decimals = (3 - mag).max(0) as usize;
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

/// Round ticks of a linear axis over `[lo, hi]`: steps of 1, 2 or 5 times
/// a power of ten, about 5 to 10 of them.
fn linear_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let raw = (hi - lo).max(1e-12) / 8.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * mag)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    // a range that f64 cannot step through (ends too far apart, or too
    // close for their size) gets its two ends
    if !step.is_finite() || step <= 0.0 || last.saturating_sub(first) > 100 {
        return vec![lo, hi];
    }
    (first..=last)
        .map(|k| {
            let v = k as f64 * step;
            // 0.30000000000000004 is written 0.3
            format!("{v:.12}").parse().unwrap_or(v)
        })
        .collect()
}

/// How series `i` is drawn: a colour, a marker and a dash pattern, so that
/// past the 10 colours the series still differ (marker, then dashes).
#[derive(Clone, Copy)]
struct Style {
    colour: RGBColor,
    marker: Marker,
    dashed: bool,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
}

fn style(i: usize) -> Style {
    let markers = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Diamond,
    ];
    Style {
        colour: PALETTE[i % PALETTE.len()],
        marker: markers[(i / PALETTE.len()) % markers.len()],
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
        Marker::Circle => area.draw(&Circle::new((x, y), 4, c)),
        Marker::Square => area.draw(&Rectangle::new([(x - 4, y - 4), (x + 4, y + 4)], c)),
        Marker::Triangle => area.draw(&Polygon::new(
            vec![(x, y - 5), (x + 5, y + 4), (x - 5, y + 4)],
            c,
        )),
        Marker::Diamond => area.draw(&Polygon::new(
            vec![(x, y - 5), (x + 5, y), (x, y + 5), (x - 5, y)],
            c,
        )),
    }
}

/// A heat map's axis: one column (or row) per swept value, evenly spaced
/// whatever the values; the label says when they are log-spaced (a
/// constant ratio) or neither evenly nor log-spaced.
fn heat_axis_label(param: &str, values: &[f64]) -> String {
    let label = param_label(param);
    if values.len() < 3 {
        return label;
    }
    let even = |v: &[f64]| {
        let d: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
        d.iter()
            .all(|x| (x - d[0]).abs() <= 1e-6 * d[0].abs().max(1e-12))
    };
    if even(values) {
        label
    } else if values.iter().all(|&v| v > 0.0)
        && even(&values.iter().map(|v| v.ln()).collect::<Vec<_>>())
    {
        format!("{label}, log-spaced values")
    } else {
        format!("{label}, swept values (not to scale)")
    }
}

/// A number in 3 significant digits, without trailing zeros (the labels of
/// a heat map's columns: 3.16, 31.6).
fn short3(v: f64) -> String {
    if !v.is_finite() || v == 0.0 {
        return short(v);
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{v:.2e}");
    }
    let decimals = (2 - mag).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
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

fn draw_err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> PlotError {
    PlotError(format!("cannot draw: {e}"))
}

fn draw_lines(
    title: &str,
    x_name: &str,
    metric: &str,
    series: &[Series],
) -> Result<String, PlotError> {
    let xs: Vec<f64> = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0))
        .filter(|x| !x.is_nan())
        .collect();
    let (xmin, xmax) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let log = xmin > 0.0 && xmax / xmin >= 20.0;
    let tx = |x: f64| if log { x.log10() } else { x };
    let (mut x0, mut x1) = (tx(xmin), tx(xmax));
    if x1 - x0 < 1e-12 {
        x0 -= 0.5;
        x1 += 0.5;
    }
    let pad = 0.04 * (x1 - x0);
    let (x0, x1) = (x0 - pad, x1 + pad);
    let ys: Vec<f64> = series
        .iter()
        .flat_map(|s| s.points.iter().flat_map(|p| [Some(p.1), p.2, p.3]))
        .flatten()
        .filter(|y| y.is_finite())
        .collect();
    let (mut y0, mut y1) = ys
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| {
            (a.min(y), b.max(y))
        });
    if y1 - y0 < 1e-12 {
        y0 -= 0.5;
        y1 += 0.5;
    }
    let pad = 0.06 * (y1 - y0);
    let (y0, y1) = (y0 - pad, y1 + pad);

    // the legend under the plot, in as many columns as fit
    let w = 1000u32;
    let char_w = 7.4;
    let longest = series
        .iter()
        .map(|s| s.label.chars().count())
        .max()
        .unwrap_or(0);
    let col_w = (48.0 + char_w * longest as f64).ceil() as u32;
    let cols = ((w - 100) / col_w).clamp(1, series.len().max(1) as u32);
    let rows = (series.len() as u32).div_ceil(cols);
    let legend_h = 16 + 24 * rows;
    let h = 580 + legend_h;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let (top, bottom) = root.split_vertically(h - legend_h);
        let ticks: Vec<f64> = if log {
            log_ticks(xmin, xmax).into_iter().map(f64::log10).collect()
        } else {
            linear_ticks(x0, x1)
        };
        let mut chart = ChartBuilder::on(&top)
            .caption(title, (FONT, 24))
            .margin(15)
            .margin_right(25)
            .x_label_area_size(62)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(draw_err)?;
        let x_fmt = |v: f64| if log { short(10f64.powf(v)) } else { short(v) };
        let y_fmt = |v: &f64| short(*v);
        chart
            .configure_mesh()
            .x_desc(if log {
                format!("{}, log scale", param_label(x_name))
            } else {
                param_label(x_name)
            })
            .y_desc(format!("{metric}: mean, 95% CI of the mean"))
            .axis_desc_style((FONT, 19))
            .label_style((FONT, 17))
            .y_label_formatter(&y_fmt)
            .x_labels(0)
            .disable_x_mesh()
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()
            .map_err(draw_err)?;
        // a log axis: light lines at 2..9 times each decade
        if log {
            let (a, b) = (x0.floor() as i32, x1.ceil() as i32);
            for k in a..=b {
                for m in 2..=9 {
                    let t = (m as f64 * 10f64.powi(k)).log10();
                    if t > x0 && t < x1 && !ticks.iter().any(|u| (u - t).abs() < 1e-9) {
                        chart
                            .draw_series(std::iter::once(PathElement::new(
                                vec![(t, y0), (t, y1)],
                                RGBColor(242, 242, 242),
                            )))
                            .map_err(draw_err)?;
                    }
                }
            }
        }
        // the x ticks, drawn by hand: decades (or 1-2-5) on a log axis,
        // round numbers on a linear one; the swept values are the markers
        for &t in &ticks {
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(t, y0), (t, y1)],
                    RGBColor(215, 215, 215),
                )))
                .map_err(draw_err)?;
            let (px, py) = chart.backend_coord(&(t, y0));
            top.draw(&PathElement::new(vec![(px, py), (px, py + 5)], BLACK))
                .map_err(draw_err)?;
            let style = TextStyle::from((FONT, 17).into_font())
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top));
            top.draw(&Text::new(x_fmt(t), (px, py + 8), style))
                .map_err(draw_err)?;
        }
        for (i, s) in series.iter().enumerate() {
            let st = style(i);
            let c = st.colour;
            let pts: Vec<_> = s.points.iter().filter(|p| !p.0.is_nan()).collect();
            if pts.is_empty() {
                // a learner that does not use x: a dashed line across
                let p = s.points[0];
                if let (Some(l), Some(u)) = (p.2, p.3) {
                    chart
                        .draw_series(std::iter::once(Rectangle::new(
                            [(x0, l), (x1, u)],
                            c.mix(0.12).filled(),
                        )))
                        .map_err(draw_err)?;
                }
                chart
                    .draw_series(DashedLineSeries::new(
                        vec![(x0, p.1), (x1, p.1)],
                        12,
                        6,
                        c.stroke_width(2),
                    ))
                    .map_err(draw_err)?;
                continue;
            }
            let band: Vec<(f64, f64, f64)> = pts
                .iter()
                .filter_map(|p| Some((tx(p.0), p.2?, p.3?)))
                .collect();
            if band.len() >= 2 {
                let mut poly: Vec<(f64, f64)> = band.iter().map(|b| (b.0, b.1)).collect();
                poly.extend(band.iter().rev().map(|b| (b.0, b.2)));
                chart
                    .draw_series(std::iter::once(Polygon::new(poly, c.mix(0.15).filled())))
                    .map_err(draw_err)?;
            } else if let Some(&(x, l, u)) = band.first() {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(x, l), (x, u)],
                        c.stroke_width(2),
                    )))
                    .map_err(draw_err)?;
            }
            let line: Vec<(f64, f64)> = pts.iter().map(|p| (tx(p.0), p.1)).collect();
            if st.dashed {
                chart
                    .draw_series(DashedLineSeries::new(line, 5, 4, c.stroke_width(2)))
                    .map_err(draw_err)?;
            } else {
                chart
                    .draw_series(LineSeries::new(line, c.stroke_width(2)))
                    .map_err(draw_err)?;
            }
            for p in &pts {
                let at = chart.backend_coord(&(tx(p.0), p.1));
                draw_marker(&top, at, st).map_err(draw_err)?;
            }
        }
        // the legend: as each series is drawn (a dashed line alone for a
        // learner that does not use x)
        for (i, s) in series.iter().enumerate() {
            let st = style(i);
            let c = st.colour;
            let (col, row) = (i as u32 % cols, i as u32 / cols);
            let x = 50 + (col * col_w) as i32;
            let y = 10 + 24 * row as i32;
            let flat = s.points.iter().all(|p| p.0.is_nan());
            if flat {
                for (a, b) in [(x, x + 12), (x + 18, x + 30)] {
                    bottom
                        .draw(&PathElement::new(vec![(a, y), (b, y)], c.stroke_width(3)))
                        .map_err(draw_err)?;
                }
            } else {
                if st.dashed {
                    for (a, b) in [(x, x + 6), (x + 12, x + 18), (x + 24, x + 30)] {
                        bottom
                            .draw(&PathElement::new(vec![(a, y), (b, y)], c.stroke_width(2)))
                            .map_err(draw_err)?;
                    }
                } else {
                    bottom
                        .draw(&PathElement::new(
                            vec![(x, y), (x + 30, y)],
                            c.stroke_width(2),
                        ))
                        .map_err(draw_err)?;
                }
                draw_marker(&bottom, (x + 15, y), st).map_err(draw_err)?;
            }
            let style = TextStyle::from((FONT, 16).into_font())
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center));
            bottom
                .draw(&Text::new(s.label.clone(), (x + 38, y), style))
                .map_err(draw_err)?;
        }
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

/// Viridis, by linear interpolation between five of its colours.
fn viridis(t: f64) -> RGBColor {
    const C: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f64;
    let mix = |a: f64, b: f64| (a + (b - a) * f).round() as u8;
    RGBColor(
        mix(C[i].0, C[i + 1].0),
        mix(C[i].1, C[i + 1].1),
        mix(C[i].2, C[i + 1].2),
    )
}

#[allow(clippy::too_many_arguments)]
fn draw_heat(
    title: &str,
    x_name: &str,
    y_name: &str,
    rows: Vec<&Vec<String>>,
    xi: usize,
    yi: usize,
    mi: usize,
    num: &dyn Fn(&str) -> Option<f64>,
) -> Result<String, PlotError> {
    let axis = |c: usize| -> Result<Vec<f64>, PlotError> {
        let mut v: Vec<f64> = Vec::new();
        for r in &rows {
            let Some(x) = num(&r[c]) else {
                return err(format!("{} = `{}` is not a number", KEY_COLUMNS[c], r[c]));
            };
            if !v.contains(&x) {
                v.push(x);
            }
        }
        v.sort_by(f64::total_cmp);
        Ok(v)
    };
    let (xv, yv) = (axis(xi)?, axis(yi)?);
    let mut grid: Vec<Vec<Option<f64>>> = vec![vec![None; yv.len()]; xv.len()];
    for r in &rows {
        let i = xv.iter().position(|&x| Some(x) == num(&r[xi])).unwrap_or(0);
        let j = yv.iter().position(|&y| Some(y) == num(&r[yi])).unwrap_or(0);
        grid[i][j] = num(&r[mi]);
    }
    let vals: Vec<f64> = grid.iter().flatten().flatten().copied().collect();
    let (vmin, vmax) = vals
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if vals.is_empty() {
        return err("no value to draw");
    }
    let span = if vmax - vmin > 0.0 { vmax - vmin } else { 1.0 };
    let (w, h) = (900u32, 650u32);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let (left, right) = root.split_horizontally(w - 130);
        let (nx, ny) = (xv.len(), yv.len());
        let mut chart = ChartBuilder::on(&left)
            .caption(title, (FONT, 22))
            .margin(15)
            .x_label_area_size(56)
            .y_label_area_size(80)
            .build_cartesian_2d(0f64..nx as f64, 0f64..ny as f64)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_desc(heat_axis_label(x_name, &xv))
            .y_desc(heat_axis_label(y_name, &yv))
            .axis_desc_style((FONT, 19))
            .draw()
            .map_err(draw_err)?;
        for (i, col) in grid.iter().enumerate() {
            for (j, v) in col.iter().enumerate() {
                let (x, y) = (i as f64, j as f64);
                let t = v.map(|v| (v - vmin) / span);
                let fill = match t {
                    Some(t) => viridis(t).filled(),
                    None => RGBColor(230, 230, 230).filled(),
                };
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(x, y), (x + 1.0, y + 1.0)],
                        fill,
                    )))
                    .map_err(draw_err)?;
                let label = v.map(short).unwrap_or_else(|| "-".into());
                let color = if t.unwrap_or(1.0) < 0.6 { WHITE } else { BLACK };
                let style = TextStyle::from((FONT, 18).into_font())
                    .color(&color)
                    .pos(Pos::new(HPos::Center, VPos::Center));
                chart
                    .draw_series(std::iter::once(Text::new(label, (x + 0.5, y + 0.5), style)))
                    .map_err(draw_err)?;
            }
        }
        // tick labels at the centres of the cells, drawn by hand
        for (i, v) in xv.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(i as f64 + 0.5, 0.0));
            let style = TextStyle::from((FONT, 17).into_font())
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top));
            left.draw(&Text::new(short3(*v), (px, py + 6), style))
                .map_err(draw_err)?;
        }
        for (j, v) in yv.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(0.0, j as f64 + 0.5));
            let style = TextStyle::from((FONT, 17).into_font())
                .color(&BLACK)
                .pos(Pos::new(HPos::Right, VPos::Center));
            left.draw(&Text::new(short3(*v), (px - 6, py), style))
                .map_err(draw_err)?;
        }
        // the colour bar
        right
            .draw(&Text::new(
                "mean",
                (12, 22),
                (FONT, 18).into_font().color(&BLACK),
            ))
            .map_err(draw_err)?;
        let mut bar = ChartBuilder::on(&right)
            .margin_top(50)
            .margin_bottom(65)
            .margin_right(10)
            .y_label_area_size(70)
            .build_cartesian_2d(0f64..1f64, vmin..vmin + span)
            .map_err(draw_err)?;
        bar.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .label_style((FONT, 16))
            .y_label_formatter(&|v: &f64| short(*v))
            .draw()
            .map_err(draw_err)?;
        let steps = 100;
        bar.draw_series((0..steps).map(|k| {
            let a = vmin + span * k as f64 / steps as f64;
            let b = vmin + span * (k + 1) as f64 / steps as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                viridis(k as f64 / (steps - 1) as f64).filled(),
            )
        }))
        .map_err(draw_err)?;
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
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
        assert_eq!(short3(3.16227766017), "3.16");
        assert_eq!(short3(31.6227766017), "31.6");
        assert_eq!(short3(1000.0), "1000");
    }

    #[test]
    fn styles_differ_past_the_ten_colours() {
        let all: Vec<(RGBColor, Marker, bool)> = (0..40)
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
