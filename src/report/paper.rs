//! The paper's experiment on `two_rooms` (Daucé 2020, Figures 2 and 3).
//!
//! - Task 1 (exploration, no reward): E3D (alpha 0.3, beta 1, lambda 0.03,
//!   eta 0.01) against the uniform policy; Figure 2 shows where the terminal
//!   states fall over 5000 trials.
//! - Task 2 (sparse reward in the lower-right corner of room B): E3D with
//!   beta 100 against epsilon-greedy (epsilon 0.1); Figure 3 shows the
//!   cumulative reward over 5000 trials and 10 sessions.
//!
//! Session `i` of every learner uses seed `seed + i` (the same seeds for
//! every learner). Sessions run in parallel; the results do not depend on
//! the number of threads.

use super::{describe, median, Stats};
use crate::effect::{entropy, EffectGrid, Target};
use crate::learner::{LearnerKind, Params};
use crate::scene::Scene;
use crate::scene::WorldSpec;
use crate::session::{
    policy_effect_distribution, run_session_with, Metrics, SessionConfig, SessionRecord,
};
use crate::world::{GridSpec, OutcomeTable};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use rayon::prelude::*;
use std::fmt::Write as _;

/// The settings of a reproduction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperConfig {
    /// Sessions per learner (the paper: 10).
    pub sessions: usize,
    /// Trials per session (the paper: 5000).
    pub trials: usize,
    /// Session `i` uses seed `seed + i`.
    pub seed: u64,
}

impl Default for PaperConfig {
    fn default() -> Self {
        PaperConfig {
            sessions: 10,
            trials: 5000,
            seed: 0,
        }
    }
}

/// One learner in one task.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arm {
    /// A label for tables and figures.
    pub label: &'static str,
    /// The task (1: no reward, 2: sparse reward).
    pub task: u8,
    /// The learner.
    pub learner: LearnerKind,
    /// Its hyper-parameters.
    pub params: Params,
}

/// The four arms of the paper: task 1 uniform and E3D, task 2 E3D and
/// epsilon-greedy.
pub const ARMS: [Arm; 4] = [
    Arm {
        label: "uniform policy",
        task: 1,
        learner: LearnerKind::Uniform,
        params: Params::TASK1,
    },
    Arm {
        label: "E3D",
        task: 1,
        learner: LearnerKind::E3d,
        params: Params::TASK1,
    },
    Arm {
        label: "E3D (beta 100)",
        task: 2,
        learner: LearnerKind::E3d,
        params: Params::TASK2,
    },
    Arm {
        label: "epsilon-greedy (0.1)",
        task: 2,
        learner: LearnerKind::Egreedy,
        params: Params::TASK2,
    },
];

/// The sessions of one arm.
#[derive(Debug, Clone)]
pub struct ArmResult {
    /// The arm.
    pub arm: Arm,
    /// One record per session.
    pub records: Vec<SessionRecord>,
    /// One metrics row per session.
    pub metrics: Vec<Metrics>,
    /// The exact effect distribution of each session's final policy.
    pub final_policy: Vec<Vec<f64>>,
}

/// Everything the reproduction computed.
#[derive(Debug, Clone)]
pub struct PaperResults {
    /// The settings.
    pub config: PaperConfig,
    /// The cells of the grid.
    pub grid: EffectGrid,
    /// The grid world (walls, start).
    pub spec: GridSpec,
    /// The rewarded cells.
    pub reward_cells: Vec<(usize, usize)>,
    /// The four arms, in the order of [`ARMS`].
    pub arms: Vec<ArmResult>,
    /// The exact effect distribution of the uniform policy.
    pub uniform_exact: Vec<f64>,
}

/// The rewarded cell's column starts room B at column 3 of `two_rooms`.
const ROOM_B_FIRST_COL: usize = 3;

/// Runs the paper's experiment. `progress` is called (from worker threads)
/// with the number of trials just run, every 256 trials of a session and
/// at its end: the counts add up to `4 x sessions x trials`.
pub fn run_paper(config: PaperConfig, progress: &(dyn Fn(u64) + Sync)) -> PaperResults {
    let scene = Scene::builtin("two_rooms").expect("two_rooms is built in");
    let table = OutcomeTable::build(&mut scene.build()).expect("the grid cannot fail");
    let space = scene.command_space();
    let n_eff = scene.num_effects();
    let jobs: Vec<(usize, usize)> = (0..ARMS.len())
        .flat_map(|a| (0..config.sessions).map(move |s| (a, s)))
        .collect();
    let done: Vec<(SessionRecord, Vec<f64>)> = jobs
        .par_iter()
        .map(|&(a, s)| {
            let arm = &ARMS[a];
            let mut learner = arm
                .learner
                .make(&arm.params, &space, n_eff, &Target::Uniform)
                .expect("the paper's parameters are valid");
            let cfg = SessionConfig {
                trials: config.trials,
                seed: config.seed.wrapping_add(s as u64),
                use_reward: arm.task == 2,
            };
            let mut reported = 0;
            let rec = run_session_with(&mut &table, &mut learner, &cfg, |t| {
                progress((t - reported) as u64);
                reported = t;
            })
            .expect("the grid cannot fail");
            let exact = policy_effect_distribution(&table, &*learner)
                .expect("shipped learners have per-slot policies");
            (rec, exact)
        })
        .collect();
    let mut it = done.into_iter();
    let arms = ARMS
        .iter()
        .map(|arm| {
            let (records, final_policy): (Vec<_>, Vec<_>) =
                it.by_ref().take(config.sessions).unzip();
            let metrics = records
                .iter()
                .map(|r| r.metrics(&Target::Uniform))
                .collect();
            ArmResult {
                arm: *arm,
                records,
                metrics,
                final_policy,
            }
        })
        .collect();
    let uniform = LearnerKind::Uniform
        .make(&Params::TASK1, &space, n_eff, &Target::Uniform)
        .expect("valid");
    PaperResults {
        config,
        grid: scene.effect_grid(),
        spec: match &scene.world {
            WorldSpec::Grid(g) => g.clone(),
            #[allow(unreachable_patterns)]
            _ => unreachable!("two_rooms is a grid"),
        },
        reward_cells: scene.reward.cells.clone(),
        uniform_exact: policy_effect_distribution(&table, &*uniform).expect("uniform"),
        arms,
    }
}

/// One row of the summary table.
#[derive(Debug, Clone, PartialEq)]
pub struct SummaryRow {
    /// The arm's label.
    pub label: &'static str,
    /// The task.
    pub task: u8,
    /// Normalised entropy of the terminal cells over all trials.
    pub normalized_entropy: Stats,
    /// Normalised entropy of the exact distribution of the final policy.
    pub final_policy_entropy: Stats,
    /// Share of trials that ended in room B.
    pub room_b_share: Stats,
    /// Cumulative reward at each checkpoint of [`PaperResults::checkpoints`].
    pub cumulative_reward: Vec<Stats>,
    /// Median 1-based trial of the first reward over the sessions that got
    /// one, and how many sessions got none.
    pub median_first_reward: Option<f64>,
    /// Sessions that never got a reward.
    pub sessions_without_reward: usize,
}

impl ArmResult {
    /// Mean share of each effect over all trials of all sessions.
    pub fn effect_shares(&self) -> Vec<f64> {
        let n = self.records[0].num_effects;
        let mut shares = vec![0.0; n];
        let mut total = 0.0;
        for r in &self.records {
            for (s, c) in shares.iter_mut().zip(r.effect_counts(0..r.trials())) {
                *s += c;
                total += c;
            }
        }
        shares.iter_mut().for_each(|s| *s /= total);
        shares
    }

    /// Per trial: (mean, sd, min, max) of the cumulative reward over sessions.
    pub fn cumulative_reward_bands(&self) -> Vec<Stats> {
        let curves: Vec<Vec<f64>> = self
            .records
            .iter()
            .map(|r| r.cumulative_rewards())
            .collect();
        let trials = curves.first().map_or(0, Vec::len);
        let mut column = vec![0.0; curves.len()];
        (0..trials)
            .map(|t| {
                for (c, curve) in column.iter_mut().zip(&curves) {
                    *c = curve[t];
                }
                describe(&column)
            })
            .collect()
    }
}

impl PaperResults {
    /// The trials at which the cumulative reward is reported: 1000, 2000 and
    /// the last trial (5000), those within the session.
    pub fn checkpoints(&self) -> Vec<usize> {
        let t = self.config.trials;
        let mut c: Vec<usize> = [1000, 2000].into_iter().filter(|&c| c < t).collect();
        c.push(t);
        c
    }

    /// The summary table, one row per arm.
    pub fn summary(&self) -> Vec<SummaryRow> {
        let cols = self.grid.cols;
        let norm = (self.grid.num_cells() as f64).ln();
        self.arms
            .iter()
            .map(|a| {
                let get = |f: &dyn Fn(&SessionRecord, &Metrics) -> f64| {
                    let xs: Vec<f64> = a
                        .records
                        .iter()
                        .zip(&a.metrics)
                        .map(|(r, m)| f(r, m))
                        .collect();
                    describe(&xs)
                };
                let firsts: Vec<f64> = a
                    .metrics
                    .iter()
                    .filter_map(|m| m.first_reward_trial.map(|t| t as f64))
                    .collect();
                let exact: Vec<f64> = a.final_policy.iter().map(|d| entropy(d) / norm).collect();
                SummaryRow {
                    label: a.arm.label,
                    task: a.arm.task,
                    normalized_entropy: get(&|_, m| m.normalized_entropy),
                    final_policy_entropy: describe(&exact),
                    room_b_share: get(&|r, _| {
                        r.effects
                            .iter()
                            .filter(|&&e| e % cols >= ROOM_B_FIRST_COL)
                            .count() as f64
                            / r.trials() as f64
                    }),
                    cumulative_reward: self
                        .checkpoints()
                        .iter()
                        .map(|&c| get(&|r, _| r.rewards[..c].iter().sum()))
                        .collect(),
                    median_first_reward: median(&firsts),
                    sessions_without_reward: a.metrics.len() - firsts.len(),
                }
            })
            .collect()
    }

    /// The summary as a Markdown table (what `summary.md` holds).
    pub fn summary_markdown(&self) -> String {
        let cps = self.checkpoints();
        let mut s = String::new();
        let c = &self.config;
        let _ = writeln!(
            s,
            "# two_rooms: the paper's experiment\n\n{} sessions x {} trials per learner, session i seeded with {} + i. \
             Normalised entropy: H / log(18) of the terminal cells over all trials (the exact value for the uniform policy is {:.4}); \
             final policy: the same for the exact effect distribution of the policy after the last trial. \
             Cells give mean +- sd [min, max] over sessions.\n",
            c.sessions,
            c.trials,
            c.seed,
            entropy(&self.uniform_exact) / (self.grid.num_cells() as f64).ln()
        );
        let mut head =
            "| task | learner | normalised entropy | final policy entropy | share in room B |"
                .to_string();
        let mut rule = "|---|---|---|---|---|".to_string();
        for cp in &cps {
            let _ = write!(head, " reward at {cp} |");
            rule.push_str("---|");
        }
        head.push_str(" median first reward |");
        rule.push_str("---|");
        let _ = writeln!(s, "{head}\n{rule}");
        let fmt = |st: &Stats, d: usize| {
            format!(
                "{:.d$} +- {:.d$} [{:.d$}, {:.d$}]",
                st.mean, st.sd, st.min, st.max
            )
        };
        for r in self.summary() {
            let _ = write!(
                s,
                "| {} | {} | {} | {} | {} |",
                r.task,
                r.label,
                fmt(&r.normalized_entropy, 3),
                fmt(&r.final_policy_entropy, 3),
                fmt(&r.room_b_share, 3)
            );
            for st in &r.cumulative_reward {
                let cell = if r.task == 1 {
                    "-".to_string()
                } else {
                    fmt(st, 1)
                };
                let _ = write!(s, " {cell} |");
            }
            let first = match (r.median_first_reward, r.sessions_without_reward) {
                _ if r.task == 1 => "- (no reward in task 1)".to_string(),
                (None, _) => "never".to_string(),
                (Some(m), 0) => format!("{m}"),
                (Some(m), k) => format!("{m} ({k} sessions never)"),
            };
            let _ = writeln!(s, " {first} |");
        }
        s
    }

    /// The numbers behind Figure 2: `learner,row,col,effect,share,uniform_exact`.
    pub fn fig2_csv(&self) -> String {
        let mut s = String::from("learner,row,col,effect,share,uniform_exact\n");
        for a in self.arms.iter().filter(|a| a.arm.task == 1) {
            for (e, share) in a.effect_shares().iter().enumerate() {
                let _ = writeln!(
                    s,
                    "{},{},{},{},{},{}",
                    a.arm.learner,
                    e / self.grid.cols,
                    e % self.grid.cols,
                    e,
                    share,
                    self.uniform_exact[e]
                );
            }
        }
        s
    }

    /// The numbers behind Figure 3: per trial, mean, sd, min and max of the
    /// cumulative reward of each task-2 learner.
    pub fn fig3_csv(&self) -> String {
        let arms: Vec<&ArmResult> = self.arms.iter().filter(|a| a.arm.task == 2).collect();
        let mut s = String::from("trial");
        for a in &arms {
            for k in ["mean", "sd", "min", "max"] {
                let _ = write!(s, ",{}_{k}", a.arm.learner);
            }
        }
        s.push('\n');
        let bands: Vec<Vec<Stats>> = arms.iter().map(|a| a.cumulative_reward_bands()).collect();
        for t in 0..self.config.trials {
            let _ = write!(s, "{}", t + 1);
            for b in &bands {
                let st = b[t];
                let _ = write!(s, ",{},{},{},{}", st.mean, st.sd, st.min, st.max);
            }
            s.push('\n');
        }
        s
    }

    /// The top of Figure 2's colour scale: the largest share of any cell
    /// in either panel. Both panels share it, so that one colour means one
    /// share in both (uniform's 15.8% is darker than E3D's 8.0%).
    pub fn fig2_scale_max(&self) -> f64 {
        self.arms
            .iter()
            .filter(|a| a.arm.task == 1)
            .flat_map(|a| a.effect_shares())
            .fold(1e-12, f64::max)
    }

    /// Normalised entropy of the pooled shares of an arm (all trials of all
    /// sessions as one sample: what Figure 2 shows), beside the mean of
    /// the sessions' own values the table reports. Entropy is concave, so
    /// the pooled value is at least the mean: each session's unevenness
    /// falls in different cells and pooling evens it out.
    pub fn pooled_entropy(&self, arm: &ArmResult) -> f64 {
        entropy(&arm.effect_shares()) / (self.grid.num_cells() as f64).ln()
    }

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
        let c = &self.config;
        let title = format!(
            "two_rooms, task 1: where the trials end, {} sessions x {} trials pooled",
            c.sessions, c.trials
        );
        let lines = [
            format!(
                "Each cell: its share of all {} trials of the {} sessions, on one colour scale for both panels (the bar: target 1/{n}).",
                c.sessions * c.trials,
                c.sessions
            ),
            format!(
                "H/log {n} here: of the pooled shares. The table gives the mean of the sessions' own ({}),",
                means.join(", ")
            ),
            "lower: each session is uneven in different cells, and pooling evens that out.".to_string(),
        ];
        let panels: Vec<(String, Vec<f64>)> = arms
            .iter()
            .map(|arm| {
                let h = self.pooled_entropy(arm);
                (
                    format!("{}: H/log {n} = {h:.3} (pooled)", arm.arm.label),
                    arm.effect_shares(),
                )
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
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (1000, 640)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| e.to_string())?;
            let (head, body) = root.split_vertically(78);
            head.draw(&Text::new(
                "two_rooms, task 2: cumulative reward".to_string(),
                (30, 12),
                ("sans-serif", 26).into_font().color(&BLACK),
            ))
            .map_err(|e| e.to_string())?;
            head.draw(&Text::new(
                format!(
                    "over {} sessions: line, mean; dark band, mean \u{b1} sd; light band, min to max (the table's mean +- sd [min, max])",
                    self.config.sessions
                ),
                (30, 48),
                ("sans-serif", 17).into_font().color(&RGBColor(70, 70, 70)),
            ))
            .map_err(|e| e.to_string())?;
            let mut chart = ChartBuilder::on(&body)
                .margin(20)
                .margin_top(5)
                .x_label_area_size(60)
                .y_label_area_size(90)
                .build_cartesian_2d(0f64..trials as f64, 0f64..top * 1.05)
                .map_err(|e| e.to_string())?;
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
                .draw()
                .map_err(|e| e.to_string())?;
            let colours = [RGBColor(200, 60, 40), RGBColor(40, 90, 180)];
            // thin the curves to at most ~1000 points: the figure, not the CSV
            let step = (trials / 1000).max(1);
            let idx: Vec<usize> = (0..trials).step_by(step).chain([trials - 1]).collect();
            let band_of =
                |band: &[Stats], lo: &dyn Fn(&Stats) -> f64, hi: &dyn Fn(&Stats) -> f64| {
                    let mut poly: Vec<(f64, f64)> = idx
                        .iter()
                        .map(|&t| ((t + 1) as f64, hi(&band[t])))
                        .collect();
                    poly.extend(idx.iter().rev().map(|&t| ((t + 1) as f64, lo(&band[t]))));
                    poly
                };
            for (band, colour) in bands.iter().zip(colours) {
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        band_of(band, &|s| s.min, &|s| s.max),
                        colour.mix(0.13).filled(),
                    )))
                    .map_err(|e| e.to_string())?;
                // the sd band is clipped at 0: a cumulative reward is not negative
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        band_of(band, &|s| (s.mean - s.sd).max(0.0), &|s| s.mean + s.sd),
                        colour.mix(0.3).filled(),
                    )))
                    .map_err(|e| e.to_string())?;
            }
            for ((arm, band), colour) in arms.iter().zip(&bands).zip(colours) {
                chart
                    .draw_series(LineSeries::new(
                        idx.iter().map(|&t| ((t + 1) as f64, band[t].mean)),
                        colour.stroke_width(3),
                    ))
                    .map_err(|e| e.to_string())?
                    .label(format!("{}: mean", arm.arm.label))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
                    });
                chart
                    .draw_series(std::iter::empty::<Rectangle<(f64, f64)>>())
                    .map_err(|e| e.to_string())?
                    .label("  mean \u{b1} sd")
                    .legend(move |(x, y)| {
                        Rectangle::new([(x, y - 6), (x + 24, y + 6)], colour.mix(0.3).filled())
                    });
                chart
                    .draw_series(std::iter::empty::<Rectangle<(f64, f64)>>())
                    .map_err(|e| e.to_string())?
                    .label("  min to max")
                    .legend(move |(x, y)| {
                        Rectangle::new([(x, y - 6), (x + 24, y + 6)], colour.mix(0.13).filled())
                    });
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .label_font(("sans-serif", 17))
                .background_style(WHITE.mix(0.9))
                .border_style(BLACK)
                .draw()
                .map_err(|e| e.to_string())?;
            root.present().map_err(|e| e.to_string())?;
        }
        Ok(svg)
    }
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

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

/// A heat map of `shares` over a grid world on the scale 0..`peak`, with
/// its walls and start (no reward: this is task 1).
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
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1100, 530)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (title_area, body) = root.split_vertically(118);
        let text = |t: &str, at: (i32, i32), size: f64, colour: &RGBColor| {
            title_area.draw(&Text::new(
                t.to_string(),
                at,
                ("sans-serif", size).into_font().color(colour),
            ))
        };
        text(title, (25, 12), 26.0, &BLACK).map_err(|e| e.to_string())?;
        let grey = RGBColor(70, 70, 70);
        for (k, line) in lines.iter().enumerate() {
            text(line, (25, 48 + 21 * k as i32), 17.0, &grey).map_err(|e| e.to_string())?;
        }
        let (panels_area, bar_area) = body.split_horizontally(940);
        let areas = panels_area.split_evenly((1, panels.len().max(1)));
        for (area, (caption, shares)) in areas.iter().zip(panels) {
            draw_grid_panel(area, caption, spec, shares, peak, n <= 60)
                .map_err(|e| e.to_string())?;
        }
        let marks = (1.0 / target).round() as usize;
        draw_colour_bar(&bar_area, peak, target, marks).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

fn draw_grid_panel(
    area: &Area<'_>,
    title: &str,
    spec: &GridSpec,
    shares: &[f64],
    peak: f64,
    labels: bool,
) -> Result<(), Box<dyn std::error::Error>> {
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
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x0, y1 - 1.0), (x0 + 1.0, y1)],
                colour.filled(),
            )))?;
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x0, y1 - 1.0), (x0 + 1.0, y1)],
                RGBColor(200, 200, 200).stroke_width(1),
            )))?;
            if !labels {
                continue;
            }
            let text_colour = if s / peak > 0.6 { WHITE } else { BLACK };
            chart.draw_series(std::iter::once(Text::new(
                format!("{:.1}%", 100.0 * s),
                (x0 + 0.5, y1 - 0.5),
                ("sans-serif", 19)
                    .into_font()
                    .color(&text_colour)
                    .pos(Pos::new(HPos::Center, VPos::Center)),
            )))?;
        }
    }
    let (r, c) = spec.start;
    chart.draw_series(std::iter::once(Text::new(
        "start",
        (c as f64 + 0.06, (rows - r) as f64 - 0.06),
        ("sans-serif", 15)
            .into_font()
            .color(&if shares[r * cols + c] / peak > 0.6 {
                WHITE
            } else {
                RGBColor(90, 90, 90)
            }),
    )))?;
    let wall = BLACK.stroke_width(5);
    let (w, h) = (cols as f64, rows as f64);
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(0.0, 0.0), (w, 0.0), (w, h), (0.0, h), (0.0, 0.0)],
        wall,
    )))?;
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
fn draw_colour_bar(
    area: &Area<'_>,
    peak: f64,
    target: f64,
    n: usize,
) -> Result<(), Box<dyn std::error::Error>> {
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
    let steps = 100;
    bar.draw_series((0..steps).map(|k| {
        let a = peak * k as f64 / steps as f64;
        let b = peak * (k + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            share_colour((a + b) / 2.0, peak).filled(),
        )
    }))?;
    bar.draw_series(std::iter::once(Rectangle::new(
        [(0.0, 0.0), (1.0, peak)],
        RGBColor(120, 120, 120).stroke_width(1),
    )))?;
    // the target: every cell at 1/n would be this colour
    bar.draw_series(std::iter::once(PathElement::new(
        vec![(-0.25, target), (1.0, target)],
        BLACK.stroke_width(2),
    )))?;
    // backend pixels, made relative to the bar's area
    let (px, py) = bar.backend_coord(&(-0.3, target));
    let (ox, oy) = area.get_base_pixel();
    let (px, py) = (px - ox, py - oy);
    let style = ("sans-serif", 15)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Right, VPos::Center));
    area.draw(&Text::new(
        format!("target 1/{n}"),
        (px, py - 9),
        style.clone(),
    ))?;
    area.draw(&Text::new(
        format!("= {:.1}%", 100.0 * target),
        (px, py + 9),
        style,
    ))?;
    Ok(())
}
