//! The heat map of a sweep: one metric over two parameters.

use super::*;

/// A heat map's axis: one column (or row) per swept value, evenly spaced
/// whatever the values; the label says when they are log-spaced (a
/// constant ratio) or neither evenly nor log-spaced.
pub(super) fn heat_axis_label(param: &str, values: &[f64]) -> String {
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

/// Viridis, by linear interpolation between five of its colours.
pub(super) fn viridis(t: f64) -> RGBColor {
    const C: [[f64; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f64;
    let [r, g, b] = [0, 1, 2].map(|j| (C[i][j] + (C[i + 1][j] - C[i][j]) * f).round() as u8);
    RGBColor(r, g, b)
}

/// The sweep's swept values and the metric's mean at each: the columns
/// (x values) and rows (y values) of a heat map, sorted, and `cells[i][j]`
/// the mean at (x i, y j), `None` where no row has it.
struct HeatGrid {
    xv: Vec<f64>,
    yv: Vec<f64>,
    cells: Vec<Vec<Option<f64>>>,
}

impl HeatGrid {
    /// The grid of `rows`: x in column `xi`, y in column `yi`, the mean in
    /// column `mi`; a swept value that is not a number is an error.
    fn new(
        rows: &[&Vec<String>],
        (xi, x_name): (usize, &str),
        (yi, y_name): (usize, &str),
        mi: usize,
    ) -> Result<HeatGrid, PlotError> {
        let axis = |c: usize| -> Result<Vec<f64>, PlotError> {
            let name = if c == xi { x_name } else { y_name };
            let mut v: Vec<f64> = Vec::new();
            for r in rows {
                let Some(x) = num(&r[c]) else {
                    return err(format!("{name} = `{}` is not a number", r[c]));
                };
                if !v.contains(&x) {
                    v.push(x);
                }
            }
            v.sort_by(f64::total_cmp);
            Ok(v)
        };
        let (xv, yv) = (axis(xi)?, axis(yi)?);
        let mut cells: Vec<Vec<Option<f64>>> = vec![vec![None; yv.len()]; xv.len()];
        for r in rows {
            let i = xv.iter().position(|&x| Some(x) == num(&r[xi])).unwrap_or(0);
            let j = yv.iter().position(|&y| Some(y) == num(&r[yi])).unwrap_or(0);
            cells[i][j] = num(&r[mi]);
        }
        Ok(HeatGrid { xv, yv, cells })
    }

    /// The smallest value and the span of the values (1 when they are all
    /// equal): the range of the colour scale; no value is an error.
    fn range(&self) -> Result<(f64, f64), PlotError> {
        let vals: Vec<f64> = self.cells.iter().flatten().flatten().copied().collect();
        let (vmin, vmax) = range(vals.iter().copied());
        if vals.is_empty() {
            return err("no value to draw");
        }
        let span = if vmax - vmin > 0.0 { vmax - vmin } else { 1.0 };
        Ok((vmin, span))
    }
}

/// The heat map of the mean in column `mi` over x (column `xi`) and y
/// (column `yi`) of `rows`, with a colour bar, in SVG.
pub(super) fn draw_heat(
    title: &str,
    x_name: &str,
    y_name: &str,
    rows: Vec<&Vec<String>>,
    xi: usize,
    yi: usize,
    mi: usize,
) -> Result<String, PlotError> {
    let grid = HeatGrid::new(&rows, (xi, x_name), (yi, y_name), mi)?;
    let (vmin, span) = grid.range()?;
    let (w, h) = (900u32, 650u32);
    plotted((w, h), |root| {
        let (left, right) = root.split_horizontally(w - 130);
        let mut chart = heat_chart(&left, title, x_name, y_name, &grid)?;
        draw_cells(&mut chart, &grid.cells, vmin, span)?;
        draw_ticks(&left, &chart, &grid)?;
        draw_colour_bar(&right, vmin, span)
    })
    .map_err(draw_err)
}

/// The heat map's chart on `left`: its title and axis names, one unit per
/// cell, no mesh and no ticks (drawn by [`draw_ticks`]).
fn heat_chart<'a, 'b>(
    left: &'a Area<'b>,
    title: &str,
    x_name: &str,
    y_name: &str,
    grid: &HeatGrid,
) -> Drawn<Chart<'a, 'b>> {
    let (nx, ny) = (grid.xv.len(), grid.yv.len());
    let mut chart = ChartBuilder::on(left)
        .caption(title, (FONT, 22))
        .margin(15)
        .x_label_area_size(56)
        .y_label_area_size(80)
        .build_cartesian_2d(0f64..nx as f64, 0f64..ny as f64)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(0)
        .y_labels(0)
        .x_desc(heat_axis_label(x_name, &grid.xv))
        .y_desc(heat_axis_label(y_name, &grid.yv))
        .axis_desc_style((FONT, 19))
        .draw()?;
    Ok(chart)
}

/// Each cell: filled with the viridis colour of its value (grey when it has
/// none) and labelled with the value (`-` when none), in white on the dark
/// colours.
fn draw_cells(
    chart: &mut Chart<'_, '_>,
    cells: &[Vec<Option<f64>>],
    vmin: f64,
    span: f64,
) -> Drawn {
    for (i, col) in cells.iter().enumerate() {
        for (j, v) in col.iter().enumerate() {
            let (x, y) = (i as f64, j as f64);
            let t = v.map(|v| (v - vmin) / span);
            let fill = match t {
                Some(t) => viridis(t).filled(),
                None => RGBColor(230, 230, 230).filled(),
            };
            chart.draw_series([Rectangle::new([(x, y), (x + 1.0, y + 1.0)], fill)])?;
            let label = v.map(short).unwrap_or_else(|| "-".into());
            let color = if t.unwrap_or(1.0) < 0.6 { WHITE } else { BLACK };
            let style = text_style(18, &color, HPos::Center, VPos::Center);
            chart.draw_series([Text::new(label, (x + 0.5, y + 0.5), style)])?;
        }
    }
    Ok(())
}

/// The tick labels, the swept values, at the centres of the cells, drawn by
/// hand on `left`: under the columns and left of the rows.
fn draw_ticks(left: &Area<'_>, chart: &Chart<'_, '_>, grid: &HeatGrid) -> Drawn {
    for (i, v) in grid.xv.iter().enumerate() {
        let (px, py) = chart.backend_coord(&(i as f64 + 0.5, 0.0));
        let style = text_style(17, &BLACK, HPos::Center, VPos::Top);
        left.draw(&Text::new(significant(*v, 3), (px, py + 6), style))?;
    }
    for (j, v) in grid.yv.iter().enumerate() {
        let (px, py) = chart.backend_coord(&(0.0, j as f64 + 0.5));
        let style = text_style(17, &BLACK, HPos::Right, VPos::Center);
        left.draw(&Text::new(significant(*v, 3), (px - 6, py), style))?;
    }
    Ok(())
}

/// The colour bar on `right`: titled `mean`, viridis in 100 steps from
/// `vmin` to `vmin + span`, with its value axis.
fn draw_colour_bar(right: &Area<'_>, vmin: f64, span: f64) -> Drawn {
    let style = text_style(18, &BLACK, HPos::Left, VPos::Top);
    right.draw(&Text::new("mean", (12, 22), style))?;
    let mut bar = ChartBuilder::on(right)
        .margin_top(50)
        .margin_bottom(65)
        .margin_right(10)
        .y_label_area_size(70)
        .build_cartesian_2d(0f64..1f64, vmin..vmin + span)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .label_style((FONT, 16))
        .y_label_formatter(&|v: &f64| short(*v))
        .draw()?;
    colour_steps(&mut bar, (vmin, span), |k, _, _| viridis(k as f64 / 99.0))
}
