//! `e3d report DIR`: one self-contained HTML page (inline SVG and CSS, no
//! script, no network) for a run folder written by `e3d run --out DIR`.
//!
//! The page shows the share of trials per effect cell early (the first 10%
//! of trials) and late (the last 10%) as two heat maps, the cumulative
//! reward over trials, and the policy per slot over trials: the share of
//! each symbol in each slot, in windows of trials, from `trials.csv`.

use std::fmt::Write;

/// One row of `trials.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct TrialRow {
    /// The command, one character per slot.
    pub command: String,
    /// The terminal effect.
    pub effect: usize,
    /// The reward received.
    pub reward: f64,
}

/// Reads `trials.csv` (with or without a leading `session` column).
pub fn parse_trials(csv: &str) -> Result<Vec<TrialRow>, String> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or("trials.csv is empty")?
        .split(',')
        .collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.trim() == name)
            .ok_or(format!("trials.csv has no `{name}` column"))
    };
    let (c, e, r) = (col("command")?, col("effect")?, col("reward")?);
    let mut rows = Vec::new();
    for (k, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        let bad = || format!("trials.csv line {}: `{line}`", k + 2);
        rows.push(TrialRow {
            command: f.get(c).ok_or_else(bad)?.to_string(),
            effect: f
                .get(e)
                .ok_or_else(bad)?
                .trim()
                .parse()
                .map_err(|_| bad())?,
            reward: f
                .get(r)
                .ok_or_else(bad)?
                .trim()
                .parse()
                .map_err(|_| bad())?,
        });
    }
    Ok(rows)
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// A heat map of the share of `trials` ending in each of `rows x cols`
/// cells (effect `row * cols + col`), darker for more.
fn heat_map(out: &mut String, title: &str, trials: &[TrialRow], rows: usize, cols: usize) {
    let px = (360.0 / cols.max(rows) as f64).clamp(4.0, 40.0);
    let mut counts = vec![0usize; rows * cols];
    for t in trials {
        if let Some(c) = counts.get_mut(t.effect) {
            *c += 1;
        }
    }
    let max = counts.iter().copied().max().unwrap_or(0).max(1) as f64;
    let n = trials.len().max(1) as f64;
    let (w, h) = (cols as f64 * px, rows as f64 * px + 24.0);
    let _ = writeln!(
        out,
        r##"<figure><svg class="heat" xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}"><text x="0" y="14" font-size="13">{}</text>"##,
        esc(title)
    );
    for (i, &c) in counts.iter().enumerate() {
        let (r, col) = (i / cols, i % cols);
        // white (never) to dark blue (the most visited cell)
        let s = c as f64 / max;
        let shade = |lo: f64, hi: f64| (lo + (hi - lo) * s).round() as u8;
        let _ = writeln!(
            out,
            r##"<rect class="cell" x="{:.1}" y="{:.1}" width="{px:.1}" height="{px:.1}" fill="rgb({},{},{})" stroke="#ddd" stroke-width="0.5"><title>effect {i} (row {r}, col {col}): {:.2}%</title></rect>"##,
            col as f64 * px,
            24.0 + r as f64 * px,
            shade(255.0, 8.0),
            shade(255.0, 48.0),
            shade(255.0, 107.0),
            100.0 * c as f64 / n
        );
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
    let _ = writeln!(
        out,
        r##"<figure><svg class="chart" xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}"><text x="{pad}" y="14" font-size="13">{}</text><line x1="{pad}" y1="{}" x2="{}" y2="{}" stroke="#888"/><line x1="{pad}" y1="20" x2="{pad}" y2="{}" stroke="#888"/><text x="2" y="28" font-size="10">{top:.3}</text><text x="2" y="{}" font-size="10">0</text><text x="{}" y="{}" font-size="10" text-anchor="end">{}</text>"##,
        esc(title),
        h - pad,
        w - 10.0,
        h - pad,
        h - pad,
        h - pad,
        w - 10.0,
        h - pad + 14.0,
        n
    );
    for (k, (name, colour, ys)) in series.iter().enumerate() {
        let step = (ys.len() / 600).max(1);
        let pts: Vec<String> = ys
            .iter()
            .enumerate()
            .step_by(step)
            .map(|(i, y)| {
                format!(
                    "{:.1},{:.1}",
                    pad + (w - 10.0 - pad) * i as f64 / (n - 1) as f64,
                    h - pad - (h - pad - 20.0) * y / top
                )
            })
            .collect();
        let _ = writeln!(
            out,
            r##"<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{}"/><text x="{}" y="{}" font-size="11" fill="{colour}">{}</text>"##,
            pts.join(" "),
            pad + 8.0 + 90.0 * k as f64,
            h - 8.0,
            esc(name)
        );
    }
    out.push_str("</svg></figure>\n");
}

const PALETTE: [&str; 8] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

/// The HTML page for a run: `trials` in order, effects on a `rows x cols`
/// grid, `title` and `summary` (summary.json's text, shown as is).
pub fn run_page(
    title: &str,
    summary: &str,
    trials: &[TrialRow],
    rows: usize,
    cols: usize,
) -> String {
    let mut body = String::new();
    let n = trials.len();
    let tenth = (n / 10).max(1).min(n);
    body.push_str("<h2>Effects</h2>\n<div class=\"row\">\n");
    heat_map(
        &mut body,
        &format!("early: trials 1..{tenth}"),
        &trials[..tenth],
        rows,
        cols,
    );
    heat_map(
        &mut body,
        &format!("late: trials {}..{n}", n - tenth + 1),
        &trials[n - tenth..],
        rows,
        cols,
    );
    body.push_str("</div>\n<h2>Reward</h2>\n");
    let mut acc = 0.0;
    let cum: Vec<f64> = trials
        .iter()
        .map(|t| {
            acc += t.reward;
            acc
        })
        .collect();
    line_chart(
        &mut body,
        "cumulative reward",
        &[("reward", "#2ca02c", cum)],
    );
    body.push_str("<h2>Policy per slot</h2>\n");
    let slots = trials
        .iter()
        .map(|t| t.command.chars().count())
        .max()
        .unwrap_or(0);
    let windows = 50.min(n.max(1));
    let size = n.div_ceil(windows).max(1);
    for s in 0..slots {
        let mut symbols: Vec<char> = trials
            .iter()
            .filter_map(|t| t.command.chars().nth(s))
            .collect();
        symbols.sort_unstable();
        symbols.dedup();
        let series: Vec<(String, &str, Vec<f64>)> = symbols
            .iter()
            .enumerate()
            .map(|(k, &sym)| {
                let ys = trials
                    .chunks(size)
                    .map(|w| {
                        w.iter()
                            .filter(|t| t.command.chars().nth(s) == Some(sym))
                            .count() as f64
                            / w.len() as f64
                    })
                    .collect();
                (sym.to_string(), PALETTE[k % PALETTE.len()], ys)
            })
            .collect();
        let refs: Vec<(&str, &str, Vec<f64>)> = series
            .iter()
            .map(|(a, b, c)| (a.as_str(), *b, c.clone()))
            .collect();
        line_chart(
            &mut body,
            &format!("slot {s}: share of each symbol, windows of {size} trials"),
            &refs,
        );
    }
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{t}</title>\n<style>body{{font-family:Helvetica,Arial,sans-serif;margin:1em;background:#fafafa}}figure{{display:inline-block;margin:0.5em}}svg{{background:#fff}}pre{{background:#fff;padding:0.5em;overflow:auto;max-height:20em}}</style>\n</head>\n<body>\n<h1>{t}</h1>\n<p>{n} trials</p>\n{body}<h2>summary.json</h2>\n<pre>{}</pre>\n</body>\n</html>\n",
        esc(summary),
        t = esc(title)
    )
}
