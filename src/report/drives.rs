//! Every drive on the canonical scenes: the sweep `scenes/sweeps/drives.ron`
//! summarised per scene and learner (task 1's entropy, task 2's reward,
//! first reward and the share of sessions that never reached the reward),
//! as a table (Markdown, CSV) and a figure (SVG). What `e3d compare`
//! writes, and docs/reproducing.md shows.
//!
//! ```
//! use e3d::report::drives::{drives_sweep, DriveComparison};
//! // a small version of the comparison: two_rooms only, 3 sessions of 500 trials
//! let sweep = drives_sweep(3, 500, &["two_rooms"]).unwrap();
//! let results = sweep.run(1).unwrap();
//! let cmp = DriveComparison::new(&sweep, &results);
//! assert_eq!(cmp.rows.len(), 6); // one per learner
//! let e3d = cmp.row("two_rooms", "e3d").unwrap();
//! let uniform = cmp.row("two_rooms", "uniform").unwrap();
//! assert!(e3d.task1_entropy.mean > uniform.task1_entropy.mean);
//! assert!(cmp.markdown().contains("| two_rooms | e3d |"));
//! assert!(cmp.svg().starts_with("<svg"));
//! ```

use super::{describe, median, Stats};
use crate::sweep::{SessionResult, Sweep, SweepError, SweepSpec, PARAM_NAMES};
use std::fmt::Write;

/// The sweep file of the comparison, as shipped.
pub const DRIVES_SWEEP: &str = include_str!("../../scenes/sweeps/drives.ron");

/// Task 1 is read at this inverse temperature, task 2 at the other.
const TASK1_BETA: f64 = 1.0;
/// Task 2's inverse temperature (the paper's).
const TASK2_BETA: f64 = 100.0;

/// The comparison's sweep with `sessions` per cell and `trials` per
/// session, on `scenes` (built-in names; empty: the shipped four).
pub fn drives_sweep(sessions: usize, trials: usize, scenes: &[&str]) -> Result<Sweep, SweepError> {
    let mut spec = SweepSpec::parse(DRIVES_SWEEP, "drives.ron (built in)")?;
    spec.sessions = sessions;
    spec.trials = trials;
    if !scenes.is_empty() {
        spec.scenes = scenes.iter().map(|s| s.to_string()).collect();
    }
    Sweep::new(spec)
}

/// A panel of the figure: its title, the top of its axis, and the value
/// and spread of a row.
type Panel<'a> = (&'static str, f64, &'a dyn Fn(&DriveRow) -> (f64, f64));

/// One scene and learner.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveRow {
    /// The scene's name.
    pub scene: String,
    /// The learner's name.
    pub learner: String,
    /// Task 1 (no reward, beta 1): the normalised entropy of the effects,
    /// over the sessions.
    pub task1_entropy: Stats,
    /// Task 2 (reward, beta 100): the cumulative reward at the last trial.
    pub task2_reward: Stats,
    /// Task 2: the median first rewarded trial of the sessions that were
    /// rewarded.
    pub task2_first_reward: Option<f64>,
    /// Task 2: the share of sessions never rewarded (for E3D on two_rooms,
    /// the sessions locked away from the far corner).
    pub task2_never_rewarded: f64,
    /// Task 2's sessions.
    pub task2_sessions: usize,
}

/// The comparison: one row per scene and learner, in the sweep's order.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveComparison {
    /// The rows.
    pub rows: Vec<DriveRow>,
    /// Sessions per cell and trials per session.
    pub sessions: usize,
    /// Trials per session.
    pub trials: usize,
}

impl DriveComparison {
    /// Summarises `results` of `sweep` (the comparison's sweep, or any with
    /// the same metrics: `normalized_entropy`, `cumulative_reward_at_T`,
    /// `first_reward_trial`). Task 1 is read from the cells without reward
    /// at beta 1, task 2 from those with reward at beta 100 (learners that
    /// ignore beta: their one cell of each). Failed sessions are left out.
    pub fn new(sweep: &Sweep, results: &[SessionResult]) -> DriveComparison {
        let columns = sweep.metric_columns();
        let col = |name: &str| columns.iter().position(|c| c == name);
        let entropy = col("normalized_entropy");
        let reward = columns
            .iter()
            .position(|c| c.starts_with("cumulative_reward_at_"));
        let first = col("first_reward_trial");
        let cells = sweep.cells();
        let beta = PARAM_NAMES.iter().position(|&p| p == "beta").unwrap_or(1);
        let mut rows = Vec::new();
        for (si, scene) in sweep.scenes().iter().enumerate() {
            for kind in &sweep.spec.learners {
                let pick = |task2: bool| -> Vec<&SessionResult> {
                    let wanted = if task2 { TASK2_BETA } else { TASK1_BETA };
                    let ids: Vec<usize> = cells
                        .iter()
                        .filter(|c| {
                            c.scene == si
                                && c.learner == *kind
                                && c.use_reward == task2
                                && (!c.used[beta] || c.params.beta == wanted)
                        })
                        .map(|c| c.index)
                        .collect();
                    results
                        .iter()
                        .filter(|r| r.failure.is_none() && ids.contains(&r.session.cell))
                        .collect()
                };
                let values = |rs: &[&SessionResult], k: Option<usize>| -> Vec<Option<f64>> {
                    rs.iter().map(|r| k.and_then(|k| r.values[k])).collect()
                };
                let (t1, t2) = (pick(false), pick(true));
                let h: Vec<f64> = values(&t1, entropy).into_iter().flatten().collect();
                let rew: Vec<f64> = values(&t2, reward).into_iter().flatten().collect();
                let firsts = values(&t2, first);
                let rewarded: Vec<f64> = firsts.iter().flatten().copied().collect();
                rows.push(DriveRow {
                    scene: scene.name().to_string(),
                    learner: kind.clone(),
                    task1_entropy: describe(&h),
                    task2_reward: describe(&rew),
                    task2_first_reward: median(&rewarded),
                    task2_never_rewarded: if t2.is_empty() {
                        0.0
                    } else {
                        (t2.len() - rewarded.len()) as f64 / t2.len() as f64
                    },
                    task2_sessions: t2.len(),
                });
            }
        }
        DriveComparison {
            rows,
            sessions: sweep.spec.sessions,
            trials: sweep.spec.trials,
        }
    }

    /// The row of `scene` and `learner`.
    pub fn row(&self, scene: &str, learner: &str) -> Option<&DriveRow> {
        self.rows
            .iter()
            .find(|r| r.scene == scene && r.learner == learner)
    }

    /// The table in Markdown, with a line saying what was run.
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "{} sessions per learner and task, {} trials each. Task 1: no reward, beta 1; \
             entropy of the terminal cells normalised by log(all cells), mean ± sd. \
             Task 2: reward, beta 100; cumulative reward at trial {}, median first \
             rewarded trial, share of sessions never rewarded.\n\n",
            self.sessions, self.trials, self.trials
        );
        s.push_str("| scene | learner | task 1 entropy | task 2 reward | first reward (median) | never rewarded |\n");
        s.push_str("|---|---|---|---|---|---|\n");
        for r in &self.rows {
            let _ = writeln!(
                s,
                "| {} | {} | {:.3} ± {:.3} | {:.0} ± {:.0} | {} | {:.1}% |",
                r.scene,
                r.learner,
                r.task1_entropy.mean,
                r.task1_entropy.sd,
                r.task2_reward.mean,
                r.task2_reward.sd,
                r.task2_first_reward
                    .map_or("-".to_string(), |t| format!("{t:.0}")),
                100.0 * r.task2_never_rewarded
            );
        }
        s
    }

    /// The table as CSV, one row per scene and learner.
    pub fn csv(&self) -> String {
        let mut s = String::from(
            "scene,learner,task1_entropy_mean,task1_entropy_sd,task2_reward_mean,task2_reward_sd,task2_first_reward_median,task2_never_rewarded,task2_sessions\n",
        );
        for r in &self.rows {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{},{}",
                r.scene,
                r.learner,
                r.task1_entropy.mean,
                r.task1_entropy.sd,
                r.task2_reward.mean,
                r.task2_reward.sd,
                r.task2_first_reward
                    .map_or(String::new(), |t| t.to_string()),
                r.task2_never_rewarded,
                r.task2_sessions
            );
        }
        s
    }

    /// Two panels of grouped bars, one group per scene, one bar per
    /// learner: task 1's entropy (with ± 1 sd) and task 2's reward per
    /// trial (the cumulative reward divided by the trials).
    pub fn svg(&self) -> String {
        let mut scenes: Vec<&str> = Vec::new();
        let mut learners: Vec<&str> = Vec::new();
        for r in &self.rows {
            if !scenes.contains(&r.scene.as_str()) {
                scenes.push(&r.scene);
            }
            if !learners.contains(&r.learner.as_str()) {
                learners.push(&r.learner);
            }
        }
        const COLOURS: [&str; 8] = [
            "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#7f7f7f", "#d62728", "#8c564b", "#e377c2",
        ];
        let (pw, ph, left, top, gap) = (520.0, 230.0, 60.0, 40.0, 70.0);
        let width = left + pw + 150.0;
        let height = top + 2.0 * ph + gap + 50.0;
        let mut s = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">
<rect width="100%" height="100%" fill="white"/>
"#
        );
        let group = pw / scenes.len().max(1) as f64;
        let bar = group * 0.8 / learners.len().max(1) as f64;
        let trials = self.trials.max(1) as f64;
        let panels: [Panel; 2] = [
            (
                "task 1: normalised entropy of the terminal cells (mean ± sd)",
                1.0,
                &|r| (r.task1_entropy.mean, r.task1_entropy.sd),
            ),
            ("task 2: reward per trial (mean ± sd)", 1.0, &|r| {
                (r.task2_reward.mean / trials, r.task2_reward.sd / trials)
            }),
        ];
        for (p, (title, ymax, value)) in panels.iter().enumerate() {
            let y0 = top + p as f64 * (ph + gap);
            let _ = writeln!(
                s,
                r#"<text x="{left}" y="{}" font-size="13" font-weight="bold">{title}</text>"#,
                y0 - 10.0
            );
            for k in 0..=4 {
                let v = *ymax * k as f64 / 4.0;
                let y = y0 + ph - ph * v / ymax;
                let _ = writeln!(
                    s,
                    r##"<line x1="{left}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">{v:.2}</text>"##,
                    left + pw,
                    left - 6.0,
                    y + 4.0
                );
            }
            let _ = writeln!(
                s,
                r#"<line x1="{left}" y1="{}" x2="{}" y2="{}" stroke="black"/>"#,
                y0 + ph,
                left + pw,
                y0 + ph
            );
            for (gi, scene) in scenes.iter().enumerate() {
                let gx = left + gi as f64 * group + group * 0.1;
                let _ = writeln!(
                    s,
                    r#"<text x="{:.1}" y="{}" text-anchor="middle">{scene}</text>"#,
                    gx + group * 0.4,
                    y0 + ph + 16.0
                );
                for (li, learner) in learners.iter().enumerate() {
                    let Some(r) = self.row(scene, learner) else {
                        continue;
                    };
                    let (v, sd) = value(r);
                    let x = gx + li as f64 * bar;
                    let h = (ph * v / ymax).clamp(0.0, ph);
                    let _ = writeln!(
                        s,
                        r#"<rect x="{x:.1}" y="{:.1}" width="{:.1}" height="{h:.1}" fill="{}"><title>{scene}, {learner}: {v:.3}</title></rect>"#,
                        y0 + ph - h,
                        bar * 0.9,
                        COLOURS[li % COLOURS.len()]
                    );
                    let (lo, hi) = ((v - sd).max(0.0), (v + sd).min(*ymax));
                    let cx = x + bar * 0.45;
                    let _ = writeln!(
                        s,
                        r#"<line x1="{cx:.1}" y1="{:.1}" x2="{cx:.1}" y2="{:.1}" stroke="black"/>"#,
                        y0 + ph - ph * lo / ymax,
                        y0 + ph - ph * hi / ymax
                    );
                }
            }
        }
        for (li, learner) in learners.iter().enumerate() {
            let y = top + 10.0 + li as f64 * 18.0;
            let _ = writeln!(
                s,
                r#"<rect x="{}" y="{}" width="12" height="12" fill="{}"/><text x="{}" y="{}">{learner}</text>"#,
                left + pw + 20.0,
                y - 10.0,
                COLOURS[li % COLOURS.len()],
                left + pw + 38.0,
                y
            );
        }
        let _ = writeln!(
            s,
            r##"<text x="{left}" y="{}" fill="#555">{} sessions per learner and task, {} trials each</text>"##,
            height - 12.0,
            self.sessions,
            self.trials
        );
        s.push_str("</svg>\n");
        s
    }
}
