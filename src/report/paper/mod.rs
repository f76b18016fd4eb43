//! The figures and tables of the paper's experiment
//! ([`experiment::paper`](crate::experiment::paper), Daucé 2020, Figures 2
//! and 3 on `two_rooms`): the summary table, the CSV of both figures and
//! their SVG.

use super::svg::{colour_steps, plotted, text_style, Area, Chart, Drawn};
use super::{describe, median, Stats};
use crate::effect::entropy;
use crate::experiment::paper::{ArmResult, PaperConfig, PaperResults};
use crate::session::{Metrics, SessionRecord};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};
use std::fmt::Write as _;

mod figures;

pub use figures::{effect_panels_svg, share_rgb};

/// The rewarded cell's column starts room B at column 3 of `two_rooms`.
const ROOM_B_FIRST_COL: usize = 3;

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
        let column = |t: usize| curves.iter().map(|c| c[t]).collect::<Vec<f64>>();
        (0..trials).map(|t| describe(&column(t))).collect()
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
        let PaperConfig {
            sessions,
            trials,
            seed,
        } = self.config;
        let h = entropy(&self.uniform_exact) / (self.grid.num_cells() as f64).ln();
        let _ = writeln!(
            s,
            "# two_rooms: the paper's experiment\n\n{sessions} sessions x {trials} trials per learner, session i seeded with {seed} + i. \
             Normalised entropy: H / log(18) of the terminal cells over all trials (the exact value for the uniform policy is {h:.4}); \
             final policy: the same for the exact effect distribution of the policy after the last trial. \
             Cells give mean +- sd [min, max] over sessions.\n"
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
            let Stats { mean, sd, min, max } = *st;
            format!("{mean:.d$} +- {sd:.d$} [{min:.d$}, {max:.d$}]")
        };
        for r in self.summary() {
            let (task, label) = (r.task.to_string(), r.label.to_string());
            let stats = [
                &r.normalized_entropy,
                &r.final_policy_entropy,
                &r.room_b_share,
            ];
            let cells = [task, label].into_iter().chain(stats.map(|st| fmt(st, 3)));
            let _ = write!(s, "| {} |", cells.collect::<Vec<_>>().join(" | "));
            for st in &r.cumulative_reward {
                let cell = (r.task != 1).then(|| fmt(st, 1));
                let _ = write!(s, " {} |", cell.as_deref().unwrap_or("-"));
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
                let (row, col) = (e / self.grid.cols, e % self.grid.cols);
                let exact = self.uniform_exact[e];
                let _ = writeln!(s, "{},{row},{col},{e},{share},{exact}", a.arm.learner);
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
                let Stats { mean, sd, min, max } = b[t];
                let _ = write!(s, ",{mean},{sd},{min},{max}");
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
}
