//! The paper's figures, drawn from the results of a run
//! ([`PaperResults`]): the effect panels (Figure 2) and the reward bands
//! (Figure 3).

use super::*;
use crate::world::GridSpec;

impl PaperResults {
    /// Figure 2 as SVG: the share of the terminal cells of all trials of
    /// all sessions (pooled), the uniform policy beside E3D, over the 3 x 6
    /// grid with its wall and door, on one colour scale with its bar and
    /// the target share 1/18 marked on it.
    pub fn fig2_svg(&self) -> Result<String, String> {
        let arms: Vec<&ArmResult> = self.arms.iter().filter(|a| a.arm.task == 1).collect();
        let peak = self.fig2_scale_max();
        let n = self.grid.num_cells();
        let target = 1.0 / n as f64;
        let means: Vec<String> = self
            .summary()
            .iter()
            .filter(|r| r.task == 1)
            .map(|r| format!("{} {:.3}", r.label, r.normalized_entropy.mean))
            .collect();
        let (sessions, trials, means) =
            (self.config.sessions, self.config.trials, means.join(", "));
        let all = sessions * trials;
        let title = format!(
            "two_rooms, task 1: where the trials end, {sessions} sessions x {trials} trials pooled"
        );
        let lines = [
            format!("Each cell: its share of all {all} trials of the {sessions} sessions, on one colour scale for both panels (the bar: target 1/{n})."),
            format!("H/log {n} here: of the pooled shares. The table gives the mean of the sessions' own ({means}),"),
            "lower: each session is uneven in different cells, and pooling evens that out.".to_string(),
        ];
        let panels: Vec<(String, Vec<f64>)> = arms
            .iter()
            .map(|arm| {
                let (label, h) = (arm.arm.label, self.pooled_entropy(arm));
                let caption = format!("{label}: H/log {n} = {h:.3} (pooled)");
                (caption, arm.effect_shares())
            })
            .collect();
        effect_panels_svg(&title, &lines, &self.spec, &panels, peak, target)
    }

    /// Figure 3 as SVG: cumulative reward against trials for each task-2
    /// learner, over the sessions: the mean as a line, mean +- sd as a
    /// dark band and min-max as a light one, the statistics of the table
    /// (`mean +- sd [min, max]`).
    pub fn fig3_svg(&self) -> Result<String, String> {
        let arms: Vec<&ArmResult> = self.arms.iter().filter(|a| a.arm.task == 2).collect();
        let bands: Vec<Vec<Stats>> = arms.iter().map(|a| a.cumulative_reward_bands()).collect();
        let top = bands
            .iter()
            .flat_map(|b| b.last().map(|s| s.max))
            .fold(1.0, f64::max);
        let trials = self.config.trials;
        plotted((1000, 640), |root| {
            let (head, body) = root.split_vertically(78);
            fig3_head(&head, self.config.sessions)?;
            let mut chart = fig3_chart(&body, trials, top)?;
            let colours = [RGBColor(200, 60, 40), RGBColor(40, 90, 180)];
            // thin the curves to at most ~1000 points: the figure, not the CSV
            let step = (trials / 1000).max(1);
            let idx: Vec<usize> = (0..trials).step_by(step).chain([trials - 1]).collect();
            draw_rewards(&mut chart, &arms, &bands, &idx, colours)?;
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .label_font(("sans-serif", 17))
                .background_style(WHITE.mix(0.9))
                .border_style(BLACK)
                .draw()?;
            Ok(())
        })
        .map_err(|e| e.to_string())
    }
}

/// Figure 3's head: its title and the line saying what the line and the
/// bands are over the `sessions`.
fn fig3_head(head: &Area<'_>, sessions: usize) -> Drawn {
    let style = |size, colour| text_style(size, &colour, HPos::Left, VPos::Top);
    let title = "two_rooms, task 2: cumulative reward".to_string();
    head.draw(&Text::new(title, (30, 12), style(26, BLACK)))?;
    let line = format!(
        "over {sessions} sessions: line, mean; dark band, mean \u{b1} sd; light band, min to max (the table's mean +- sd [min, max])"
    );
    head.draw(&Text::new(line, (30, 48), style(17, RGBColor(70, 70, 70))))?;
    Ok(())
}

/// Figure 3's chart on `body`: trials 0 to `trials` across, cumulative
/// reward 0 to 5% over `top` up, with its axes and light grid.
fn fig3_chart<'a, 'b>(body: &'a Area<'b>, trials: usize, top: f64) -> Drawn<Chart<'a, 'b>> {
    let mut chart = ChartBuilder::on(body)
        .margin(20)
        .margin_top(5)
        .x_label_area_size(60)
        .y_label_area_size(90)
        .build_cartesian_2d(0f64..trials as f64, 0f64..top * 1.05)?;
    chart
        .configure_mesh()
        .x_desc("trial")
        .y_desc("cumulative reward")
        .axis_desc_style(("sans-serif", 20))
        .label_style(("sans-serif", 18))
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_label_formatter(&|y| format!("{y:.0}"))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()?;
    Ok(chart)
}

/// The polygon between `lo` and `hi` of a learner's `band` at the trials
/// `idx` (trial t drawn at t + 1): along `hi`, then back along `lo`.
fn band_polygon(
    band: &[Stats],
    idx: &[usize],
    lo: &dyn Fn(&Stats) -> f64,
    hi: &dyn Fn(&Stats) -> f64,
) -> Vec<(f64, f64)> {
    let mut poly: Vec<(f64, f64)> = idx
        .iter()
        .map(|&t| ((t + 1) as f64, hi(&band[t])))
        .collect();
    poly.extend(idx.iter().rev().map(|&t| ((t + 1) as f64, lo(&band[t]))));
    poly
}

/// Each learner's bands, in its colour: min to max, light, and mean +- sd
/// (clipped at 0: a cumulative reward is not negative), darker; then each
/// learner's mean as a line, and its three legend entries: the line, the
/// sd band and the min-max band.
fn draw_rewards(
    chart: &mut Chart<'_, '_>,
    arms: &[&ArmResult],
    bands: &[Vec<Stats>],
    idx: &[usize],
    colours: [RGBColor; 2],
) -> Drawn {
    type Edge<'a> = &'a dyn Fn(&Stats) -> f64;
    let spans: [(Edge, Edge, f64); 2] = [
        (&|s| s.min, &|s| s.max, 0.13),
        (&|s| (s.mean - s.sd).max(0.0), &|s| s.mean + s.sd, 0.3),
    ];
    for (band, colour) in bands.iter().zip(colours) {
        for (lo, hi, mix) in spans {
            chart.draw_series([Polygon::new(
                band_polygon(band, idx, lo, hi),
                colour.mix(mix).filled(),
            )])?;
        }
    }
    for ((arm, band), colour) in arms.iter().zip(bands).zip(colours) {
        chart
            .draw_series(LineSeries::new(
                idx.iter().map(|&t| ((t + 1) as f64, band[t].mean)),
                colour.stroke_width(3),
            ))?
            .label(format!("{}: mean", arm.arm.label))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
            });
        for (label, mix) in [("  mean \u{b1} sd", 0.3), ("  min to max", 0.13)] {
            chart
                .draw_series(std::iter::empty::<Rectangle<(f64, f64)>>())?
                .label(label)
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 6), (x + 24, y + 6)], colour.mix(mix).filled())
                });
        }
    }
    Ok(())
}

/// The colour (red, green, blue) of a share on Figure 2's scale from 0
/// (white) to `peak` (dark blue), the same in every panel and on the
/// colour bar.
pub fn share_rgb(share: f64, peak: f64) -> [u8; 3] {
    let v = (share / peak).clamp(0.0, 1.0);
    [
        (255.0 - 215.0 * v).round() as u8,
        (255.0 - 165.0 * v).round() as u8,
        (255.0 - 75.0 * v).round() as u8,
    ]
}

fn share_colour(share: f64, peak: f64) -> RGBColor {
    let [r, g, b] = share_rgb(share, peak);
    RGBColor(r, g, b)
}

/// Two (or more) effect grids side by side on one colour scale, with a
/// colour bar marking `target`: Figure 2's layout, for any scene's grid
/// (`spec` gives the rows, columns, start cell and walls; a grid of more
/// than 60 cells has no percentages written in its cells). `panels` are
/// `(caption, share of each effect)`; `peak` tops the scale.
///
/// ```
/// use e3d::report::paper::effect_panels_svg;
/// use e3d::world::GridSpec;
/// let spec = GridSpec { rows: 2, cols: 2, start: (0, 0), walls: vec![], contexts: vec![] };
/// let panels = vec![("a".to_string(), vec![0.25; 4]), ("b".to_string(), vec![0.7, 0.1, 0.1, 0.1])];
/// let svg = effect_panels_svg("title", &[], &spec, &panels, 0.7, 0.25).unwrap();
/// assert!(svg.starts_with("<svg") && svg.contains("title") && svg.contains("70.0%"));
/// ```
pub fn effect_panels_svg(
    title: &str,
    lines: &[String],
    spec: &GridSpec,
    panels: &[(String, Vec<f64>)],
    peak: f64,
    target: f64,
) -> Result<String, String> {
    let n = spec.rows * spec.cols;
    plotted((1100, 530), |root| {
        let (title_area, body) = root.split_vertically(118);
        let text = |t: &str, at: (i32, i32), size: u32, colour: &RGBColor| {
            let style = text_style(size, colour, HPos::Left, VPos::Top);
            title_area.draw(&Text::new(t.to_string(), at, style))
        };
        text(title, (25, 12), 26, &BLACK)?;
        for (k, line) in lines.iter().enumerate() {
            text(line, (25, 48 + 21 * k as i32), 17, &RGBColor(70, 70, 70))?;
        }
        let (panels_area, bar_area) = body.split_horizontally(940);
        let areas = panels_area.split_evenly((1, panels.len().max(1)));
        for (area, (caption, shares)) in areas.iter().zip(panels) {
            draw_grid_panel(area, caption, spec, shares, peak, n <= 60)?;
        }
        let marks = (1.0 / target).round() as usize;
        draw_colour_bar(&bar_area, peak, target, marks)
    })
    .map_err(|e| e.to_string())
}

/// A heat map of `shares` over a grid world on the scale 0..`peak`, with
/// its walls and start (no reward: this is task 1).
fn draw_grid_panel(
    area: &Area<'_>,
    title: &str,
    spec: &GridSpec,
    shares: &[f64],
    peak: f64,
    labels: bool,
) -> Drawn {
    let (rows, cols) = (spec.rows, spec.cols);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 21))
        .margin(22)
        .margin_top(12)
        .build_cartesian_2d(0f64..cols as f64, 0f64..rows as f64)?;
    for r in 0..rows {
        for c in 0..cols {
            let s = shares[r * cols + c];
            let colour = share_colour(s, peak);
            let (x0, y1) = (c as f64, (rows - r) as f64);
            let (cell, grey) = ([(x0, y1 - 1.0), (x0 + 1.0, y1)], RGBColor(200, 200, 200));
            chart.draw_series([Rectangle::new(cell, colour.filled())])?;
            chart.draw_series([Rectangle::new(cell, grey.stroke_width(1))])?;
            if !labels {
                continue;
            }
            let text_colour = if s / peak > 0.6 { WHITE } else { BLACK };
            let style = text_style(19, &text_colour, HPos::Center, VPos::Center);
            let label = Text::new(format!("{:.1}%", 100.0 * s), (x0 + 0.5, y1 - 0.5), style);
            chart.draw_series([label])?;
        }
    }
    let (r, c) = spec.start;
    let colour = [RGBColor(90, 90, 90), WHITE][usize::from(shares[r * cols + c] / peak > 0.6)];
    let style = text_style(15, &colour, HPos::Left, VPos::Top);
    let at = (c as f64 + 0.06, (rows - r) as f64 - 0.06);
    chart.draw_series([Text::new("start", at, style)])?;
    let wall = BLACK.stroke_width(5);
    let (w, h) = (cols as f64, rows as f64);
    let frame = vec![(0.0, 0.0), (w, 0.0), (w, h), (0.0, h), (0.0, 0.0)];
    chart.draw_series([PathElement::new(frame, wall)])?;
    // a wall between two cells is drawn on their common edge
    chart.draw_series(spec.walls.iter().map(|&(a, b)| {
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        let top = (rows - a.0) as f64;
        let points = if a.0 == b.0 {
            let x = b.1 as f64;
            vec![(x, top - 1.0), (x, top)]
        } else {
            let y = top - 1.0;
            vec![(a.1 as f64, y), (a.1 as f64 + 1.0, y)]
        };
        PathElement::new(points, wall)
    }))?;
    Ok(())
}

/// Figure 2's colour bar: the scale from 0 to `peak` (percent ticks), the
/// target share 1/`n` marked across it.
fn draw_colour_bar(area: &Area<'_>, peak: f64, target: f64, n: usize) -> Drawn {
    let mut bar = ChartBuilder::on(area)
        .caption("share of trials", ("sans-serif", 17))
        .margin_top(14)
        .margin_bottom(28)
        .margin_left(62)
        .margin_right(4)
        .set_label_area_size(LabelAreaPosition::Right, 54)
        .build_cartesian_2d(0f64..1f64, 0f64..peak)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .label_style(("sans-serif", 16))
        .y_labels(8)
        .y_label_formatter(&|v| format!("{:.0}%", 100.0 * v))
        .draw()?;
    colour_steps(&mut bar, (0.0, peak), |_, a, b| {
        share_colour((a + b) / 2.0, peak)
    })?;
    bar.draw_series([Rectangle::new(
        [(0.0, 0.0), (1.0, peak)],
        RGBColor(120, 120, 120).stroke_width(1),
    )])?;
    // the target: every cell at 1/n would be this colour
    bar.draw_series([PathElement::new(
        vec![(-0.25, target), (1.0, target)],
        BLACK.stroke_width(2),
    )])?;
    // backend pixels, made relative to the bar's area
    let (px, py) = bar.backend_coord(&(-0.3, target));
    let (ox, oy) = area.get_base_pixel();
    let (px, py) = (px - ox, py - oy);
    let style = text_style(15, &BLACK, HPos::Right, VPos::Center);
    let (named, share) = (format!("target 1/{n}"), format!("= {:.1}%", 100.0 * target));
    area.draw(&Text::new(named, (px, py - 9), style.clone()))?;
    area.draw(&Text::new(share, (px, py + 9), style))?;
    Ok(())
}
