//! The line plot of a sweep: one line per learner (and filter) against one
//! parameter, with 95% intervals.

use super::*;

/// One line of a line plot.
pub(super) struct Series {
    label: String,
    /// (x, mean, ci_low, ci_high); a single point with x = NaN is a
    /// horizontal line (a learner that does not use x).
    points: Vec<(f64, f64, Option<f64>, Option<f64>)>,
}

/// The series of a line plot of the mean in column `mi` (interval `lo` to
/// `hi`) against column `xi`: one per setting of the other cell columns
/// that vary, its points sorted by x.
pub(super) fn line_series(
    cells: &[String],
    rows: &[&Vec<String>],
    xi: usize,
    mi: usize,
    lo: usize,
    hi: usize,
) -> Result<Vec<Series>, PlotError> {
    // the cell columns that vary (besides x) name the series
    let varying: Vec<usize> = (0..cells.len())
        .filter(|&c| c != xi)
        .filter(|&c| rows.iter().any(|r| r[c] != rows[0][c]))
        .collect();
    let named = named_columns(rows, &varying);
    let mut series: Vec<Series> = Vec::new();
    let mut keys: Vec<String> = Vec::new();
    for r in rows {
        let key: Vec<&str> = varying.iter().map(|&c| r[c].as_str()).collect();
        let key = key.join(",");
        let Some(mean) = num(&r[mi]) else { continue };
        let x = match num(&r[xi]) {
            _ if r[xi].is_empty() => f64::NAN,
            Some(x) => x,
            None => return err(format!("{} = `{}` is not a number", cells[xi], r[xi])),
        };
        let p = (x, mean, num(&r[lo]), num(&r[hi]));
        match keys.iter().position(|k| *k == key) {
            Some(i) => series[i].points.push(p),
            None => {
                let label = Some(series_label(cells, r, &named)).filter(|l| !l.is_empty());
                keys.push(key);
                series.push(Series {
                    label: label.unwrap_or_else(|| "all".into()),
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
            cells[xi]
        ));
    }
    Ok(series)
}

/// The columns named in the series' labels: of the `varying` cell
/// columns, those with two or more distinct non-empty values (a parameter
/// only some learners use is not named); the learner when none is.
fn named_columns(rows: &[&Vec<String>], varying: &[usize]) -> Vec<usize> {
    let mut named: Vec<usize> = varying
        .iter()
        .copied()
        .filter(|&c| {
            let v = rows.iter().map(|r| r[c].as_str()).filter(|s| !s.is_empty());
            distinct(v).len() >= 2
        })
        .collect();
    if named.is_empty() {
        named.push(1); // the learner
    }
    named
}

/// The label of row `r`'s series, in words: its values of the `named`
/// columns that it has (`e3d, with reward, eta 0.003`).
fn series_label(cells: &[String], r: &[String], named: &[usize]) -> String {
    named
        .iter()
        .filter(|&&c| !r[c].is_empty())
        .map(|&c| match cells[c].as_str() {
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
        .join(", ")
}

pub(super) fn draw_lines(
    title: &str,
    x_name: &str,
    metric: &str,
    series: &[Series],
) -> Result<String, PlotError> {
    let Extents {
        log,
        xmin,
        xmax,
        x: (x0, x1),
        y: (y0, y1),
    } = extents(series);
    let tx = |x: f64| if log { x.log10() } else { x };

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
    plotted((w, h), |root| {
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
            .build_cartesian_2d(x0..x1, y0..y1)?;
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
            .draw()?;
        draw_x_ticks(&mut chart, &top, &ticks, log, (x0, x1), (y0, y1), &x_fmt)?;
        draw_series(&mut chart, &top, series, &tx, (x0, x1))?;
        draw_legend(&bottom, series, cols, col_w)
    })
    .map_err(draw_err)
}

/// The axes of a line plot: a log x axis when every x is positive and
/// they span a factor 20 or more, each range padded.
struct Extents {
    log: bool,
    xmin: f64,
    xmax: f64,
    /// The x range drawn, in axis units (log10 on a log axis).
    x: (f64, f64),
    y: (f64, f64),
}

fn extents(series: &[Series]) -> Extents {
    let points = || series.iter().flat_map(|s| s.points.iter());
    let (xmin, xmax) = range(points().map(|p| p.0).filter(|x| !x.is_nan()));
    let log = xmin > 0.0 && xmax / xmin >= 20.0;
    let tx = |x: f64| if log { x.log10() } else { x };
    let ys = points().flat_map(|p| [Some(p.1), p.2, p.3]).flatten();
    Extents {
        log,
        xmin,
        xmax,
        x: padded((tx(xmin), tx(xmax)), 0.04),
        y: padded(range(ys.filter(|y| y.is_finite())), 0.06),
    }
}

/// `(lo, hi)` widened by `by` of its span on each side (a span of
/// nothing made 1 first).
fn padded((mut lo, mut hi): (f64, f64), by: f64) -> (f64, f64) {
    if hi - lo < 1e-12 {
        lo -= 0.5;
        hi += 0.5;
    }
    let pad = by * (hi - lo);
    (lo - pad, hi + pad)
}

/// The x axis, drawn by hand: on a log axis light lines at 2..9 times
/// each decade, then a line, a mark and a label at each tick.
fn draw_x_ticks(
    chart: &mut Chart<'_, '_>,
    top: &Area<'_>,
    ticks: &[f64],
    log: bool,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    x_fmt: &dyn Fn(f64) -> String,
) -> Drawn {
    let grid = |t: f64, grey: u8| {
        let colour = RGBColor(grey, grey, grey);
        [PathElement::new(vec![(t, y0), (t, y1)], colour)]
    };
    // a log axis: light lines at 2..9 times each decade
    if log {
        let (a, b) = (x0.floor() as i32, x1.ceil() as i32);
        for k in a..=b {
            for m in 2..=9 {
                let t = (m as f64 * 10f64.powi(k)).log10();
                if t > x0 && t < x1 && !ticks.iter().any(|u| (u - t).abs() < 1e-9) {
                    chart.draw_series(grid(t, 242))?;
                }
            }
        }
    }
    // the x ticks, drawn by hand: decades (or 1-2-5) on a log axis,
    // round numbers on a linear one; the swept values are the markers
    for &t in ticks {
        chart.draw_series(grid(t, 215))?;
        let (px, py) = chart.backend_coord(&(t, y0));
        top.draw(&PathElement::new(vec![(px, py), (px, py + 5)], BLACK))?;
        let style = text_style(17, &BLACK, HPos::Center, VPos::Top);
        top.draw(&Text::new(x_fmt(t), (px, py + 8), style))?;
    }
    Ok(())
}

/// Each series: its band (the 95% interval), its line and its markers; a
/// learner that does not use x as a dashed line across with its band.
fn draw_series(
    chart: &mut Chart<'_, '_>,
    top: &Area<'_>,
    series: &[Series],
    tx: &dyn Fn(f64) -> f64,
    (x0, x1): (f64, f64),
) -> Drawn {
    for (i, s) in series.iter().enumerate() {
        let st = style(i);
        let c = st.colour;
        let pts: Vec<_> = s.points.iter().filter(|p| !p.0.is_nan()).collect();
        if pts.is_empty() {
            // a learner that does not use x: a dashed line across
            let p = s.points[0];
            if let (Some(l), Some(u)) = (p.2, p.3) {
                chart.draw_series([Rectangle::new([(x0, l), (x1, u)], c.mix(0.12).filled())])?;
            }
            let across = vec![(x0, p.1), (x1, p.1)];
            chart.draw_series(DashedLineSeries::new(across, 12, 6, c.stroke_width(2)))?;
            continue;
        }
        let band: Vec<(f64, f64, f64)> = (pts.iter())
            .filter_map(|p| Some((tx(p.0), p.2?, p.3?)))
            .collect();
        if band.len() >= 2 {
            let mut poly: Vec<(f64, f64)> = band.iter().map(|b| (b.0, b.1)).collect();
            poly.extend(band.iter().rev().map(|b| (b.0, b.2)));
            chart.draw_series([Polygon::new(poly, c.mix(0.15).filled())])?;
        } else if let Some(&(x, l, u)) = band.first() {
            chart.draw_series([PathElement::new(vec![(x, l), (x, u)], c.stroke_width(2))])?;
        }
        let line: Vec<(f64, f64)> = pts.iter().map(|p| (tx(p.0), p.1)).collect();
        if st.dashed {
            chart.draw_series(DashedLineSeries::new(line, 5, 4, c.stroke_width(2)))?;
        } else {
            chart.draw_series(LineSeries::new(line, c.stroke_width(2)))?;
        }
        for p in &pts {
            let at = chart.backend_coord(&(tx(p.0), p.1));
            draw_marker(top, at, st)?;
        }
    }
    Ok(())
}

/// The legend under the plot, `cols` columns of `col_w` pixels.
fn draw_legend(bottom: &Area<'_>, series: &[Series], cols: u32, col_w: u32) -> Drawn {
    for (i, s) in series.iter().enumerate() {
        let st = style(i);
        let c = st.colour;
        let (col, row) = (i as u32 % cols, i as u32 / cols);
        let x = 50 + (col * col_w) as i32;
        let y = 10 + 24 * row as i32;
        // a learner that does not use x: a dashed line alone
        let flat = s.points.iter().all(|p| p.0.is_nan());
        let (dashes, width): (&[(i32, i32)], u32) = if flat {
            (&[(0, 12), (18, 30)], 3)
        } else if st.dashed {
            (&[(0, 6), (12, 18), (24, 30)], 2)
        } else {
            (&[(0, 30)], 2)
        };
        for &(a, b) in dashes {
            let segment = vec![(x + a, y), (x + b, y)];
            bottom.draw(&PathElement::new(segment, c.stroke_width(width)))?;
        }
        if !flat {
            draw_marker(bottom, (x + 15, y), st)?;
        }
        let style = text_style(16, &BLACK, HPos::Left, VPos::Center);
        bottom.draw(&Text::new(s.label.clone(), (x + 38, y), style))?;
    }
    Ok(())
}
