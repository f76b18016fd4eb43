//! `e3d report DIR`: one self-contained HTML page (inline SVG and CSS, no
//! script, no network) for a run folder ([`run_page`]) or a sweep folder
//! ([`sweep_page`], feature `plots`).

use super::svg::{esc, page};
use crate::csv::TrialRow;
use crate::learner::Effort;
use crate::scene::Scene;
use std::fmt::Write;

/// The most cells a heat map draws one by one: above, only the cells
/// reached are drawn, over one white background.
const MAX_CELLS_DRAWN: usize = 16384;

/// (effect, count) of the `effects` below `cells`, in effect order.
fn reached(effects: &[usize], cells: usize) -> Vec<(usize, usize)> {
    let mut counts = std::collections::BTreeMap::new();
    for &e in effects.iter().filter(|&&e| e < cells) {
        *counts.entry(e).or_insert(0) += 1;
    }
    counts.into_iter().collect()
}

/// A heat map of the share of `effects` in each of `rows x cols`
/// cells (effect `row * cols + col`), darker for more, drawing every cell
/// only when there are at most `dense` cells (the per-context maps share
/// [`MAX_CELLS_DRAWN`] between them). Above, one background and the cells
/// reached: the work and the text are then linear in `effects`, whatever
/// the grid.
fn heat_map(out: &mut String, title: &str, effects: &[usize], grid: (usize, usize), dense: usize) {
    let reached = reached(effects, grid.0 * grid.1);
    let max = reached.iter().map(|r| r.1).max().unwrap_or(0).max(1) as f64;
    let n = effects.len().max(1) as f64;
    let shaded: Vec<(usize, f64, String)> = (reached.iter())
        .map(|&(i, c)| (i, c as f64 / max, format!("{:.2}%", 100.0 * c as f64 / n)))
        .collect();
    grid_map(out, title, &shaded, grid, dense, "0.00%");
}

/// The map of the elites of a run of symbols (docs/algorithms.md,
/// "QD-score"): each reached cell shaded by the best effort quality `1 -
/// effort / max` of the commands that reached it ([`Effort`], the
/// scene's), from light (0) to dark (1); the title gives their sum, the
/// QD-score. Nothing for commands of values, or where every command has
/// the same effort ([`Effort::varies`]).
fn elite_map(out: &mut String, trials: &[TrialRow], grid: (usize, usize), scene: &Scene) {
    let effort = Effort::of_scene(scene);
    if scene.spec().is_continuous() || !effort.varies() {
        return;
    }
    let space = scene.command_space();
    let cells = grid.0 * grid.1;
    let mut best: std::collections::BTreeMap<usize, f64> = Default::default();
    for t in trials.iter().filter(|t| t.effect < cells) {
        let Some(q) = space
            .parse(&t.command)
            .ok()
            .and_then(|c| effort.quality(&c))
        else {
            continue;
        };
        let b = best.entry(t.effect).or_insert(q);
        *b = b.max(q);
    }
    if best.is_empty() {
        return;
    }
    let qd: f64 = best.values().sum();
    let shaded: Vec<(usize, f64, String)> = (best.into_iter())
        .map(|(i, q)| (i, 0.15 + 0.85 * q, format!("elite quality {q:.3}")))
        .collect();
    let title = format!("elites: best effort quality per cell (qd_score {qd:.3})");
    grid_map(out, &title, &shaded, grid, MAX_CELLS_DRAWN, "not reached");
}

/// A map of `rows x cols` cells (effect `row * cols + col`), the cells
/// `shaded` (in effect order: effect, shade in `[0, 1]`, what its tooltip
/// says) from white to dark blue, the others white saying `empty`;
/// every cell drawn only when there are at most `dense`.
fn grid_map(
    out: &mut String,
    title: &str,
    shaded: &[(usize, f64, String)],
    (rows, cols): (usize, usize),
    dense: usize,
    empty: &str,
) {
    let px = (360.0 / cols.max(rows) as f64).clamp(4.0, 40.0);
    let cells = rows * cols;
    let (w, h) = (cols as f64 * px, rows as f64 * px + 24.0);
    let title = esc(title);
    let _ = writeln!(
        out,
        r##"<figure><svg class="heat" xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}"><text x="0" y="14" font-size="13">{title}</text>"##
    );
    // a large grid (up to 2^20 cells) gets one background and only its
    // reached cells: a cell each made a 390 MB page of a 50-trial run
    let sparse = cells > dense;
    if sparse {
        let below = h - 24.0;
        let _ = writeln!(
            out,
            r##"<rect x="0" y="24" width="{w:.1}" height="{below:.1}" fill="rgb(255,255,255)" stroke="#ddd" stroke-width="0.5"><title>{cells} cells; those never reached are not drawn one by one</title></rect>"##
        );
    }
    let mut cell = |i: usize, s: f64, tip: &str| {
        let (r, col) = (i / cols, i % cols);
        // white (never) to dark blue (the most visited cell)
        let shade = |lo: f64, hi: f64| (lo + (hi - lo) * s).round() as u8;
        let (red, green, blue) = (shade(255.0, 8.0), shade(255.0, 48.0), shade(255.0, 107.0));
        let (x, y) = (col as f64 * px, 24.0 + r as f64 * px);
        let _ = writeln!(
            out,
            r##"<rect class="cell" x="{x:.1}" y="{y:.1}" width="{px:.1}" height="{px:.1}" fill="rgb({red},{green},{blue})" stroke="#ddd" stroke-width="0.5"><title>effect {i} (row {r}, col {col}): {tip}</title></rect>"##
        );
    };
    if sparse {
        shaded.iter().for_each(|(i, s, tip)| cell(*i, *s, tip));
    } else {
        let mut next = shaded.iter().peekable();
        for i in 0..cells {
            match next.next_if(|c| c.0 == i) {
                Some((_, s, tip)) => cell(i, *s, tip),
                None => cell(i, 0.0, empty),
            }
        }
    }
    out.push_str("</svg></figure>\n");
}

/// A line chart of each series (name, colour, values over trials or windows).
fn line_chart(out: &mut String, title: &str, series: &[(&str, &str, Vec<f64>)]) {
    let (w, h, pad) = (640.0, 240.0, 40.0);
    let n = series.iter().map(|s| s.2.len()).max().unwrap_or(0).max(2);
    let top = series
        .iter()
        .flat_map(|s| s.2.iter().copied())
        .fold(0.0_f64, f64::max)
        .max(1e-9);
    let (title, base, right, below) = (esc(title), h - pad, w - 10.0, h - pad + 14.0);
    let _ = writeln!(
        out,
        r##"<figure><svg class="chart" xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}"><text x="{pad}" y="14" font-size="13">{title}</text><line x1="{pad}" y1="{base}" x2="{right}" y2="{base}" stroke="#888"/><line x1="{pad}" y1="20" x2="{pad}" y2="{base}" stroke="#888"/><text x="2" y="28" font-size="10">{top:.3}</text><text x="2" y="{base}" font-size="10">0</text><text x="{right}" y="{below}" font-size="10" text-anchor="end">{n}</text>"##
    );
    for (k, (name, colour, ys)) in series.iter().enumerate() {
        let step = (ys.len() / 600).max(1);
        let pts: Vec<String> = ys
            .iter()
            .enumerate()
            .step_by(step)
            .map(|(i, y)| {
                let x = pad + (w - 10.0 - pad) * i as f64 / (n - 1) as f64;
                format!("{x:.1},{:.1}", h - pad - (h - pad - 20.0) * y / top)
            })
            .collect();
        let (pts, name) = (pts.join(" "), esc(name));
        let (x, y) = (pad + 8.0 + 90.0 * k as f64, h - 8.0);
        let _ = writeln!(
            out,
            r##"<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{pts}"/><text x="{x}" y="{y}" font-size="11" fill="{colour}">{name}</text>"##
        );
    }
    out.push_str("</svg></figure>\n");
}

const PALETTE: [&str; 8] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

/// The HTML page for a run: `trials` in order, effects on a `rows x cols`
/// grid, `title`, `note` shown under it (empty: none; for example why the
/// effects are not drawn on the scene's grid), `summary` (summary.json's
/// text, shown as is) and the run's `scene` if known (for the map of
/// elites, which needs its actions: [`Effort::of_scene`]).
pub fn run_page(
    title: &str,
    note: &str,
    summary: &str,
    trials: &[TrialRow],
    (rows, cols): (usize, usize),
    scene: Option<&Scene>,
) -> String {
    let mut body = String::new();
    if !note.is_empty() {
        let _ = writeln!(body, "<p class=\"note\"><strong>{}</strong></p>", esc(note));
    }
    let n = trials.len();
    // the terminal effects: of every trial, or of each episode's last command
    let k = trials.iter().map(|t| t.step).max().unwrap_or(1);
    let terminal: Vec<usize> = trials
        .iter()
        .filter(|t| t.step == k)
        .map(|t| t.effect)
        .collect();
    let what = if k > 1 { "episodes" } else { "trials" };
    body.push_str("<h2>Effects</h2>\n<div class=\"row\">\n");
    body += &early_and_late("", what, &terminal, (rows, cols), MAX_CELLS_DRAWN);
    if let (1, Some(scene)) = (k, scene) {
        elite_map(&mut body, trials, (rows, cols), scene);
    }
    body.push_str("</div>\n");
    per_start_context(&mut body, trials, k, rows, cols);
    body.push_str("<h2>Reward</h2>\n");
    let cum: Vec<f64> = trials
        .iter()
        .scan(0.0, |acc, t| {
            *acc += t.reward;
            Some(*acc)
        })
        .collect();
    let reward = [("reward", "#2ca02c", cum)];
    line_chart(&mut body, "cumulative reward", &reward);
    body.push_str("<h2>Policy per slot</h2>\n");
    let windows = 50.min(n.max(1));
    let size = n.div_ceil(windows).max(1);
    value_charts(&mut body, trials, size);
    symbol_charts(&mut body, trials, size);
    page(
        title,
        "figure{display:inline-block;margin:0.5em}svg{background:#fff}pre{background:#fff;padding:0.5em;overflow:auto;max-height:20em}",
        &format!(
            "<p>{n} trials</p>\n{body}<h2>summary.json</h2>\n<pre>{}</pre>\n",
            esc(summary)
        ),
    )
}

/// Per slot of a continuous command: the spread of its values and their
/// mean magnitude, in windows of `size` trials.
fn value_charts(body: &mut String, trials: &[TrialRow], size: usize) {
    let value_slots = trials.iter().map(|t| t.values.len()).max().unwrap_or(0);
    for s in 0..value_slots {
        let windows: Vec<Vec<f64>> = (trials.chunks(size))
            .map(|w| w.iter().filter_map(|t| t.values.get(s).copied()).collect())
            .collect();
        let mean = |v: &[f64], f: &dyn Fn(f64) -> f64| {
            v.iter().map(|&x| f(x)).sum::<f64>() / v.len().max(1) as f64
        };
        let sd = |v: &Vec<f64>| {
            let m = mean(v, &|x| x);
            mean(v, &|x| (x - m) * (x - m)).sqrt()
        };
        let sds: Vec<f64> = windows.iter().map(sd).collect();
        let mags: Vec<f64> = windows.iter().map(|v| mean(v, &f64::abs)).collect();
        let title =
            format!("slot {s}: sd of the values and mean |value|, windows of {size} trials");
        let series = [("sd", PALETTE[0], sds), ("mean |value|", PALETTE[1], mags)];
        line_chart(body, &title, &series);
    }
}

/// Per slot of a command of symbols: the share of each symbol, in windows
/// of `size` trials.
fn symbol_charts(body: &mut String, trials: &[TrialRow], size: usize) {
    // each command's symbols once (a command holds at most 64), then per
    // slot one pass over the trials: linear in the trials
    let symbols_of: Vec<Vec<char>> = trials.iter().map(|t| t.command.chars().collect()).collect();
    let slots = symbols_of.iter().map(Vec::len).max().unwrap_or(0);
    for s in 0..slots {
        let mut symbols: Vec<char> = symbols_of
            .iter()
            .filter_map(|c| c.get(s).copied())
            .collect();
        symbols.sort_unstable();
        symbols.dedup();
        let mut ys = vec![Vec::new(); symbols.len()];
        for w in symbols_of.chunks(size) {
            let mut counts = vec![0usize; symbols.len()];
            for c in w {
                if let Some(k) = c.get(s).and_then(|x| symbols.binary_search(x).ok()) {
                    counts[k] += 1;
                }
            }
            for (y, c) in ys.iter_mut().zip(counts) {
                y.push(c as f64 / w.len() as f64);
            }
        }
        let names: Vec<String> = symbols.iter().map(char::to_string).collect();
        let refs: Vec<(&str, &str, Vec<f64>)> = (names.iter().zip(ys).enumerate())
            .map(|(k, (a, ys))| (a.as_str(), PALETTE[k % PALETTE.len()], ys))
            .collect();
        let title = format!("slot {s}: share of each symbol, windows of {size} trials");
        line_chart(body, &title, &refs);
    }
}

/// The heat maps of the first and the last 10% of `effects` ([`heat_map`]).
fn early_and_late(
    prefix: &str,
    what: &str,
    effects: &[usize],
    grid: (usize, usize),
    dense: usize,
) -> String {
    let (n, mut out) = (effects.len(), String::new());
    let tenth = (n / 10).max(1).min(n);
    let early = format!("{prefix}early: {what} 1..{tenth}");
    heat_map(&mut out, &early, &effects[..tenth], grid, dense);
    let late = format!("{prefix}late: {what} {}..{n}", n - tenth + 1);
    heat_map(&mut out, &late, &effects[n - tenth..], grid, dense);
    out
}

/// For a run of episodes from start contexts: per start context (in the
/// order first met), the normalised entropy of its episodes' terminal
/// effects over the `rows x cols` cells, their cumulative reward and the
/// heat maps of the first and last 10% of them. Linear in the trials; the
/// maps share [`MAX_CELLS_DRAWN`] cells drawn one by one.
fn per_start_context(out: &mut String, trials: &[TrialRow], k: usize, rows: usize, cols: usize) {
    let mut index: std::collections::HashMap<&str, usize> = Default::default();
    let mut groups: Vec<(&str, Vec<&TrialRow>)> = Vec::new();
    for t in trials.iter().filter(|t| !t.start.is_empty()) {
        let g = *index.entry(t.start.as_str()).or_insert_with(|| {
            groups.push((t.start.as_str(), Vec::new()));
            groups.len() - 1
        });
        groups[g].1.push(t);
    }
    if groups.is_empty() {
        return;
    }
    // two maps per start
    let dense = MAX_CELLS_DRAWN / (2 * groups.len());
    out.push_str("<h2>Per start context</h2>\n<table class=\"contexts\">\n<tr><th>start context</th><th>episodes</th><th>normalised entropy of the terminal cells</th><th>cumulative reward</th><th>first rewarded episode (of its own)</th></tr>\n");
    let mut maps = String::new();
    for (s, mine) in &groups {
        let last: Vec<&&TrialRow> = mine.iter().filter(|t| t.step == k).collect();
        let effects: Vec<usize> = last.iter().map(|t| t.effect).collect();
        // the counts of the cells reached (the others weigh nothing)
        let counts: Vec<f64> = reached(&effects, rows * cols)
            .iter()
            .map(|r| r.1 as f64)
            .collect();
        let h = crate::effect::normalized_entropy_over(&counts, rows * cols);
        let reward: f64 = mine.iter().map(|t| t.reward).sum();
        let first = last.iter().position(|t| t.reward > 0.0);
        let first = first.map_or("never".to_string(), |i| (i + 1).to_string());
        let (name, n) = (esc(s), effects.len());
        let _ = writeln!(
            out,
            "<tr><td>{name}</td><td class=\"n\">{n}</td><td class=\"n\">{h:.4}</td><td class=\"n\">{reward}</td><td class=\"n\">{first}</td></tr>"
        );
        maps.push_str("<div class=\"row\">\n");
        let prefix = format!("{s}, ");
        maps += &early_and_late(&prefix, "episodes", &effects, (rows, cols), dense);
        maps.push_str("</div>\n");
    }
    out.push_str("</table>\n");
    out.push_str(&maps);
}

/// The HTML page for a sweep folder (written by `e3d sweep` or `e3d
/// merge`): `summary` (its `summary.csv`) as a table, one row per cell, the
/// cell columns that vary and, per metric, the mean +- sd (the exact
/// values and the 95% interval in each cell's tooltip); then, for each
/// parameter that takes two or more values, the line plot of each metric
/// against it ([`sweep_plot::plot`](super::sweep_plot::plot), inline SVG);
/// then `sweep_ron` (the copy of the sweep file) as is. `failures` are the
/// sessions' failure messages (`results.csv`), listed when there are any.
///
/// ```
/// use e3d::report::html::sweep_page;
/// use e3d::csv::Summary;
/// let csv = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions,h_mean,h_sd,h_ci_low,h_ci_high\n\
///            g,e3d,false,0.3,1,0.03,0.01,,3,0.9,0.01,0.88,0.92\n\
///            g,e3d,false,0.3,10,0.03,0.01,,3,0.8,0.01,0.78,0.82\n";
/// let page = sweep_page("s", &Summary::parse(csv).unwrap(), "Sweep(...)", &[]);
/// assert!(page.contains("<th>beta</th>") && page.contains("h against beta"));
/// assert!(!page.contains("<script"));
/// ```
#[cfg(feature = "plots")]
pub fn sweep_page(
    title: &str,
    summary: &crate::csv::Summary,
    sweep_ron: &str,
    failures: &[String],
) -> String {
    use super::sweep_plot::distinct;
    let rows = &summary.rows;
    let values = |c: usize| distinct(rows.iter().map(|r| r[c].as_str()));
    // the cell columns that vary are the table's keys; the others are said once
    let (varying, fixed): (Vec<usize>, Vec<usize>) =
        (0..summary.cell_columns()).partition(|&c| values(c).len() > 1);
    let mut body = String::new();
    let total = |name: &str| -> usize {
        let sum = |c: usize| rows.iter().filter_map(|r| r[c].parse::<usize>().ok()).sum();
        summary.col(name).map_or(0, sum)
    };
    let (sessions, failed) = (total("sessions"), total("failed"));
    let (cells, metrics) = (rows.len(), summary.metrics().len());
    let _ = writeln!(
        body,
        "<p>{cells} cells, {sessions} sessions ({failed} failed), {metrics} metrics</p>"
    );
    let fixed_text: Vec<String> = fixed
        .iter()
        .map(|&c| {
            let v = rows.first().map_or("", |r| r[c].as_str());
            let v = if v.is_empty() { "(unused)" } else { v };
            format!("{} {v}", esc(&summary.columns[c]))
        })
        .collect();
    if !fixed_text.is_empty() {
        let fixed = fixed_text.join("; ");
        let _ = writeln!(body, "<p>the same in every cell: {fixed}</p>");
    }
    summary_table(&mut body, summary, &varying);
    failures_list(&mut body, failures);
    plots_against_params(&mut body, summary);
    let _ = writeln!(body, "<h2>sweep.ron</h2>\n<pre>{}</pre>", esc(sweep_ron));
    page(
        title,
        "table{border-collapse:collapse;background:#fff}td,th{border:1px solid #ddd;padding:2px 6px;font-size:13px}td.n{text-align:right;font-variant-numeric:tabular-nums}figure{margin:0.5em}svg{max-width:100%;height:auto;background:#fff}pre{background:#fff;padding:0.5em;overflow:auto;max-height:30em}.note{color:#666}.scroll{overflow-x:auto}",
        &body,
    )
}

/// The summary as a table: the cell columns that vary, the sessions (and
/// failures), each metric's mean ± sd (its interval in the tooltip).
#[cfg(feature = "plots")]
fn summary_table(body: &mut String, summary: &crate::csv::Summary, varying: &[usize]) {
    use super::sweep_plot::short;
    let rows = &summary.rows;
    let col = |name: &str| summary.col(name);
    let metrics = summary.metrics();
    body.push_str("<h2>Summary</h2>\n<div class=\"scroll\">\n<table class=\"summary\">\n<tr>");
    for &c in varying {
        let _ = write!(body, "<th>{}</th>", esc(&summary.columns[c]));
    }
    body.push_str("<th>sessions</th>");
    if col("failed").is_some() {
        body.push_str("<th>failed</th>");
    }
    for m in &metrics {
        let _ = write!(body, "<th>{}<br>mean ± sd</th>", esc(m));
    }
    body.push_str("</tr>\n");
    let num = |s: &str| s.parse::<f64>().ok();
    for r in rows {
        body.push_str("<tr>");
        for &c in varying {
            let _ = write!(body, "<td>{}</td>", esc(&r[c]));
        }
        for name in ["sessions", "failed"] {
            if let Some(c) = col(name) {
                let _ = write!(body, "<td class=\"n\">{}</td>", esc(&r[c]));
            }
        }
        for m in &metrics {
            let field = |suffix: &str| {
                let text = col(&format!("{m}_{suffix}")).map_or("", |c| r[c].as_str());
                (text, esc(text))
            };
            let (mean, sd) = (field("mean"), field("sd"));
            let (lo, hi) = (field("ci_low").1, field("ci_high").1);
            match num(mean.0) {
                None => body.push_str("<td class=\"n\">-</td>"),
                Some(v) => {
                    let sd_text = num(sd.0).map_or(String::new(), |s| format!(" ± {}", short(s)));
                    let (mean, sd, v) = (mean.1, sd.1, short(v));
                    let _ = write!(
                        body,
                        "<td class=\"n\" title=\"mean {mean}, sd {sd}, 95% interval [{lo}, {hi}]\">{v}{sd_text}</td>"
                    );
                }
            }
        }
        body.push_str("</tr>\n");
    }
    body.push_str("</table>\n</div>\n");
}

/// The first 20 failure messages, and how many more there are.
#[cfg(feature = "plots")]
fn failures_list(body: &mut String, failures: &[String]) {
    if !failures.is_empty() {
        let _ = writeln!(
            body,
            "<h2>Failures</h2>\n<p>{} sessions failed:</p>\n<ul>",
            failures.len()
        );
        for f in failures.iter().take(20) {
            let _ = writeln!(body, "<li>{}</li>", esc(f));
        }
        if failures.len() > 20 {
            let _ = writeln!(body, "<li>... and {} more</li>", failures.len() - 20);
        }
        body.push_str("</ul>\n");
    }
}

/// Each metric against each parameter that takes two values or more, as
/// a line plot, or a note saying why it is not drawn.
#[cfg(feature = "plots")]
fn plots_against_params(body: &mut String, summary: &crate::csv::Summary) {
    use super::sweep_plot::{distinct, plot, PlotSpec};
    use crate::learner::Params;
    let rows = &summary.rows;
    let col = |name: &str| summary.col(name);
    let values = |c: usize| distinct(rows.iter().map(|r| r[c].as_str()));
    let num = |s: &str| s.parse::<f64>().ok();
    let metrics = summary.metrics();
    // the parameters, then the scene axes' paths
    let cells = summary.cell_columns();
    let axes = summary.columns[crate::sweep::CELL_COLUMNS.min(cells)..cells].iter();
    for param in Params::SWEPT.into_iter().chain(axes.map(String::as_str)) {
        let Some(c) = col(param) else { continue };
        if values(c).iter().filter(|v| !v.is_empty()).count() < 2 {
            continue;
        }
        let _ = writeln!(body, "<h2>Against {param}</h2>");
        for m in &metrics {
            let spec = PlotSpec {
                x: param.to_string(),
                y: None,
                metric: m.to_string(),
                filters: vec![],
            };
            let name = esc(m);
            let _ = writeln!(body, "<h3>{name} against {param}</h3>");
            let mean = col(&format!("{m}_mean"));
            let drawable = rows
                .iter()
                .any(|r| !r[c].is_empty() && mean.is_some_and(|k| num(&r[k]).is_some()));
            let _ = match drawable.then(|| plot(summary, &spec)) {
                None => writeln!(
                    body,
                    "<p class=\"note\">not drawn: no cell with a value of {param} has a value of {name}</p>"
                ),
                Some(Ok(svg)) => writeln!(body, "<figure class=\"plot\">{svg}</figure>"),
                Some(Err(e)) => writeln!(body, "<p class=\"note\">not drawn: {}</p>", esc(&e.0)),
            };
        }
    }
}
