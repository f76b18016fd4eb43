//! Every drive on the canonical scenes: the sweep `scenes/sweeps/drives.ron`
//! summarised per scene and learner (task 1's entropy and coverage of the
//! reachable cells, task 2's reward, first reward and the share of
//! sessions that never reached the reward), as a table (Markdown, CSV)
//! and a figure (SVG). What `e3d compare` writes, and docs/reproducing.md
//! shows.
//!
//! ```
//! use e3d::experiment::drives::drives_sweep;
//! use e3d::report::drives::DriveComparison;
//! // a small version of the comparison: two_rooms only, 3 sessions of 500 trials
//! let sweep = drives_sweep(3, 500, &["two_rooms"], &[]).unwrap();
//! let results = sweep.run(1).unwrap();
//! let cmp = DriveComparison::new(&sweep, &results);
//! assert_eq!(cmp.rows.len(), 8); // one per learner
//! let e3d = cmp.row("two_rooms", "e3d").unwrap();
//! let uniform = cmp.row("two_rooms", "uniform").unwrap();
//! assert!(e3d.task1_entropy.stats.mean > uniform.task1_entropy.stats.mean);
//! assert!(cmp.markdown().contains("| two_rooms | e3d |"));
//! assert!(cmp.svg().starts_with("<svg"));
//! ```

use super::{describe, mean_ci95, median, quartiles, MeanCi, Stats};
use crate::learner::Params;
use crate::sweep::{SessionResult, Sweep};
use std::fmt::Write;

/// Task 1 is read at this inverse temperature, task 2 at the other.
const TASK1_BETA: f64 = 1.0;
/// Task 2's inverse temperature (the paper's).
const TASK2_BETA: f64 = 100.0;

/// A measure over sessions: its statistics, its mean with a 95% Student t
/// interval (`None` for fewer than two values) and how many sessions it
/// is over.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Measure {
    /// Mean, sd, min and max.
    pub stats: Stats,
    /// The mean with its 95% t interval.
    pub ci: Option<MeanCi>,
    /// The sessions measured.
    pub n: usize,
}

impl Measure {
    fn of(xs: &[f64]) -> Measure {
        Measure {
            stats: describe(xs),
            ci: mean_ci95(xs),
            n: xs.len(),
        }
    }
}

/// One scene and learner.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DriveRow {
    /// The scene's name.
    pub scene: String,
    /// The learner's name.
    pub learner: String,
    /// Task 1's sessions.
    pub task1_sessions: usize,
    /// Task 1 (no reward, beta 1): the normalised entropy of the effects.
    pub task1_entropy: Measure,
    /// Task 1: the fraction of the reachable cells reached by the last
    /// trial.
    pub task1_coverage: Measure,
    /// Task 1: the trials to reach 50% of the reachable cells, over the
    /// sessions that reached them (`n`).
    pub task1_trials_to_50: Measure,
    /// Task 1: the trials to reach 90%, over the sessions that did.
    pub task1_trials_to_90: Measure,
    /// Task 1: the QD-score (docs/algorithms.md, "QD-score"), over the
    /// sessions that have one (none where every command has the same
    /// effort).
    pub task1_qd_score: Measure,
    /// Task 2's sessions.
    pub task2_sessions: usize,
    /// Task 2 (reward, beta 100): the cumulative reward at the last trial.
    pub task2_reward: Measure,
    /// Task 2: the first rewarded trial over the sessions that were
    /// rewarded.
    pub task2_first_reward: Measure,
    /// Task 2: the median first rewarded trial of the sessions that were
    /// rewarded.
    pub task2_first_reward_median: Option<f64>,
    /// Task 2: the quartiles `[q1, median, q3]` of the first rewarded
    /// trial over the sessions that were rewarded (a skewed count: its
    /// median and interquartile range rather than a mean).
    pub task2_first_reward_quartiles: Option<[f64; 3]>,
    /// Task 2: the share of sessions never rewarded (for E3D on two_rooms,
    /// the sessions locked away from the far corner).
    pub task2_never_rewarded: f64,
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
    /// Per scene (in order), its name and the cells coverage counts
    /// against: the reachable ones when the sweep knew them
    /// ([`with_reachable_cells`](crate::experiment::drives::with_reachable_cells)),
    /// else all (`false`).
    pub coverage_cells: Vec<(String, usize, bool)>,
}

impl DriveComparison {
    /// Summarises `results` of `sweep` (the comparison's sweep, or any with
    /// the same metrics: `normalized_entropy`, `cumulative_reward_at_T`,
    /// `first_reward_trial`). Task 1 is read from the cells without reward
    /// at beta 1, task 2 from those with reward at beta 100 (learners that
    /// ignore beta: their one cell of each). Failed sessions are left out.
    pub fn new(sweep: &Sweep, results: &[SessionResult]) -> DriveComparison {
        let columns = sweep.metric_columns();
        let beta = Params::SWEPT.iter().position(|&p| p == "beta").unwrap_or(1);
        let mut rows = Vec::new();
        for (si, scene) in sweep.scenes().iter().enumerate() {
            for kind in &sweep.spec.learners {
                let pick = |task2: bool| task_sessions(sweep, results, si, kind, task2, beta);
                let (t1, t2) = (pick(false), pick(true));
                rows.push(DriveRow::of(scene.name(), kind, &t1, &t2, &columns));
            }
        }
        let coverage_cells = sweep
            .scenes()
            .iter()
            .enumerate()
            .map(|(i, s)| match sweep.reachable_effects(i) {
                Some(k) => (s.name().to_string(), k, true),
                None => (s.name().to_string(), s.num_effects(), false),
            })
            .collect();
        DriveComparison {
            rows,
            sessions: sweep.spec.sessions,
            trials: sweep.spec.trials,
            coverage_cells,
        }
    }

    /// Per scene, which learner is best on each measure: the highest task
    /// 1 entropy, the highest coverage and QD-score, the fewest mean trials to 50% and
    /// to 90% of the reachable cells (among the learners whose every
    /// session got there), the highest task 2 reward and the earliest
    /// median first reward (learners tied on a measure are all named).
    /// One line per scene.
    pub fn winners(&self) -> Vec<(String, Vec<(&'static str, String)>)> {
        // fewest trials among the learners whose every session got there
        let all = |r: &DriveRow, m: &Measure| {
            (m.n == r.task1_sessions && m.n > 0).then_some(m.stats.mean)
        };
        // a measure's name, whether higher is better, and its value in a row
        type Value<'a> = &'a dyn Fn(&DriveRow) -> Option<f64>;
        let qd = |r: &DriveRow| (r.task1_qd_score.n > 0).then_some(r.task1_qd_score.stats.mean);
        let measures: [(&str, bool, Value); 7] = [
            ("entropy", true, &|r| Some(r.task1_entropy.stats.mean)),
            ("coverage", true, &|r| Some(r.task1_coverage.stats.mean)),
            ("QD-score", true, &qd),
            ("trials to 50%", false, &|r| all(r, &r.task1_trials_to_50)),
            ("trials to 90%", false, &|r| all(r, &r.task1_trials_to_90)),
            ("task 2 reward", true, &|r| Some(r.task2_reward.stats.mean)),
            ("first reward", false, &|r| r.task2_first_reward_median),
        ];
        let mut out = Vec::new();
        for (scene, _, _) in &self.coverage_cells {
            let rows: Vec<&DriveRow> = self.rows.iter().filter(|r| &r.scene == scene).collect();
            if rows.is_empty() {
                continue;
            }
            // the best value, and every learner that has it (ties listed)
            let best = |key: &dyn Fn(&DriveRow) -> Option<f64>, high: bool| -> String {
                let better = |w: f64, v: f64| match (high && v > w) || (!high && v < w) {
                    true => v,
                    false => w,
                };
                let Some(b) = rows.iter().filter_map(|r| key(r)).reduce(better) else {
                    return "-".to_string();
                };
                let names: Vec<&str> = (rows.iter().filter(|r| key(r) == Some(b)))
                    .map(|r| r.learner.as_str())
                    .collect();
                names.join(", ")
            };
            let best_of = measures
                .iter()
                .map(|&(name, high, key)| (name, best(key, high)));
            out.push((scene.clone(), best_of.collect()));
        }
        out
    }

    /// The row of `scene` and `learner`.
    pub fn row(&self, scene: &str, learner: &str) -> Option<&DriveRow> {
        self.rows
            .iter()
            .find(|r| r.scene == scene && r.learner == learner)
    }

    /// The table in Markdown, with a line saying what was run.
    pub fn markdown(&self) -> String {
        let cells: Vec<String> = self
            .coverage_cells
            .iter()
            .map(|(scene, k, reachable)| {
                format!("{scene} {k}{}", if *reachable { "" } else { " (all)" })
            })
            .collect();
        let mut s = format!(
            "{} sessions per learner and task, {} trials each. Task 1: no reward, beta 1; \
             entropy of the terminal cells normalised by log(all cells); coverage: the \
             fraction of the reachable cells ({}) reached by the last trial; QD-score: the \
             sum over the reached cells of the best effort quality (- where every command \
             has the same effort); trials to reach 50% and 90% of them (over the sessions \
             that did, with their number when not all); mean ± sd. Task 2: reward, beta 100; cumulative reward at \
             trial {}, median first rewarded trial, share of sessions never rewarded. \
             95% intervals: of each mean, Student's t (mean ± t(n-1) sd / sqrt n, over the \
             sessions the mean is over); of the first rewarded trial, its quartiles Q1..Q3 \
             over the rewarded sessions.\n\n",
            self.sessions,
            self.trials,
            cells.join(", "),
            self.trials
        );
        s.push_str("| scene | learner | task 1 entropy | coverage | QD-score | trials to 50% | trials to 90% | task 2 reward | first reward (median) | never rewarded | entropy: 95% (t) | coverage: 95% (t) | QD-score: 95% (t) | to 50%: 95% (t) | to 90%: 95% (t) | reward: 95% (t) | first reward: Q1..Q3 |\n");
        s.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        let ci = |m: &Measure, d: usize| -> String {
            m.ci.map_or("-".to_string(), |c| {
                format!("{:.d$}..{:.d$}", c.lo(), c.hi())
            })
        };
        let pm = |m: &Measure, d: usize| format!("{:.d$} ± {:.d$}", m.stats.mean, m.stats.sd);
        let some = |m: &Measure, d: usize| if m.n == 0 { "-".to_string() } else { pm(m, d) };
        let reach = |m: &Measure, of: usize| match m.n {
            0 => "never".to_string(),
            n if n < of => format!("{} ({n}/{of})", pm(m, 0)),
            _ => pm(m, 0),
        };
        for r in &self.rows {
            let (median, q) = (r.task2_first_reward_median, r.task2_first_reward_quartiles);
            let cells = [
                r.scene.clone(),
                r.learner.clone(),
                pm(&r.task1_entropy, 3),
                pm(&r.task1_coverage, 3),
                some(&r.task1_qd_score, 2),
                reach(&r.task1_trials_to_50, r.task1_sessions),
                reach(&r.task1_trials_to_90, r.task1_sessions),
                pm(&r.task2_reward, 0),
                median.map_or("-".to_string(), |t| format!("{t:.0}")),
                format!("{:.1}%", 100.0 * r.task2_never_rewarded),
                ci(&r.task1_entropy, 3),
                ci(&r.task1_coverage, 3),
                ci(&r.task1_qd_score, 2),
                ci(&r.task1_trials_to_50, 0),
                ci(&r.task1_trials_to_90, 0),
                ci(&r.task2_reward, 0),
                q.map_or("-".to_string(), |[q1, _, q3]| format!("{q1:.0}..{q3:.0}")),
            ];
            let _ = writeln!(s, "| {} |", cells.join(" | "));
        }
        s.push_str("\nBest per scene (highest entropy, coverage, QD-score and reward; fewest mean trials to 50% and 90% among the learners whose every session got there; earliest median first reward):\n\n");
        s.push_str("| scene | entropy | coverage | QD-score | trials to 50% | trials to 90% | task 2 reward | first reward |\n");
        s.push_str("|---|---|---|---|---|---|---|---|\n");
        for (scene, best) in self.winners() {
            let names: Vec<&str> = best.iter().map(|(_, l)| l.as_str()).collect();
            let _ = writeln!(s, "| {scene} | {} |", names.join(" | "));
        }
        s
    }

    /// The table as CSV, one row per scene and learner.
    pub fn csv(&self) -> String {
        let line = |fields: Vec<(String, String)>, name: bool| {
            let f: Vec<String> = fields
                .into_iter()
                .map(|(n, v)| if name { n } else { v })
                .collect();
            f.join(",") + "\n"
        };
        let mut s = line(DriveRow::default().csv_fields(), true);
        for r in &self.rows {
            s.push_str(&line(r.csv_fields(), false));
        }
        s
    }

    /// Two panels of grouped bars, one group per scene, one bar per
    /// learner: task 1's entropy (with ± 1 sd) and task 2's reward per
    /// trial (the cumulative reward divided by the trials).
    pub fn svg(&self) -> String {
        let (scenes, learners) = self.scenes_and_learners();
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
        // both panels' axes run from 0 to ymax
        let ymax = 1.0;
        type Value<'a> = &'a dyn Fn(&DriveRow) -> (f64, f64);
        let panels: [(&str, Value); 2] = [
            (
                "task 1: normalised entropy of the terminal cells (mean ± sd)",
                &|r| (r.task1_entropy.stats.mean, r.task1_entropy.stats.sd),
            ),
            ("task 2: reward per trial (mean ± sd)", &|r| {
                let st = r.task2_reward.stats;
                (st.mean / trials, st.sd / trials)
            }),
        ];
        for (p, (title, value)) in panels.iter().enumerate() {
            let y0 = top + p as f64 * (ph + gap);
            // the frame: the title, 5 value lines and the base line
            let _ = writeln!(
                s,
                r#"<text x="{left}" y="{}" font-size="13" font-weight="bold">{title}</text>"#,
                y0 - 10.0
            );
            let (right, base) = (left + pw, y0 + ph);
            for k in 0..=4 {
                let v = ymax * k as f64 / 4.0;
                let y = y0 + ph - ph * v / ymax;
                let (tx, ty) = (left - 6.0, y + 4.0);
                let _ = writeln!(
                    s,
                    r##"<line x1="{left}" y1="{y:.1}" x2="{right}" y2="{y:.1}" stroke="#ddd"/><text x="{tx}" y="{ty:.1}" text-anchor="end">{v:.2}</text>"##
                );
            }
            let _ = writeln!(
                s,
                r#"<line x1="{left}" y1="{base}" x2="{right}" y2="{base}" stroke="black"/>"#
            );
            // a group per scene, a bar per learner that has a row there,
            // with its ± sd whisker
            for (gi, scene) in scenes.iter().enumerate() {
                let gx = left + gi as f64 * group + group * 0.1;
                let (tx, ty) = (gx + group * 0.4, base + 16.0);
                let _ = writeln!(
                    s,
                    r#"<text x="{tx:.1}" y="{ty}" text-anchor="middle">{scene}</text>"#
                );
                for (li, learner) in learners.iter().enumerate() {
                    let Some(r) = self.row(scene, learner) else {
                        continue;
                    };
                    let (v, sd) = value(r);
                    let x = gx + li as f64 * bar;
                    let h = (ph * v / ymax).clamp(0.0, ph);
                    let (y, w, fill) = (base - h, bar * 0.9, COLOURS[li % COLOURS.len()]);
                    let _ = writeln!(
                        s,
                        r#"<rect x="{x:.1}" y="{y:.1}" width="{w:.1}" height="{h:.1}" fill="{fill}"><title>{scene}, {learner}: {v:.3}</title></rect>"#
                    );
                    let (lo, hi) = ((v - sd).max(0.0), (v + sd).min(ymax));
                    let (cx, y1, y2) =
                        (x + bar * 0.45, base - ph * lo / ymax, base - ph * hi / ymax);
                    let _ = writeln!(
                        s,
                        r#"<line x1="{cx:.1}" y1="{y1:.1}" x2="{cx:.1}" y2="{y2:.1}" stroke="black"/>"#
                    );
                }
            }
        }
        // the legend right of the panels
        for (li, learner) in learners.iter().enumerate() {
            let y = top + 10.0 + li as f64 * 18.0;
            let (x, tx, box_y) = (left + pw + 20.0, left + pw + 38.0, y - 10.0);
            let fill = COLOURS[li % COLOURS.len()];
            let _ = writeln!(
                s,
                r#"<rect x="{x}" y="{box_y}" width="12" height="12" fill="{fill}"/><text x="{tx}" y="{y}">{learner}</text>"#
            );
        }
        let (y, sessions, trials) = (height - 12.0, self.sessions, self.trials);
        let _ = writeln!(
            s,
            r##"<text x="{left}" y="{y}" fill="#555">{sessions} sessions per learner and task, {trials} trials each</text>"##
        );
        s.push_str("</svg>\n");
        s
    }

    /// The scenes and the learners of the rows, each in the order of its
    /// first row: the groups of the figure and the bars of a group.
    fn scenes_and_learners(&self) -> (Vec<&str>, Vec<&str>) {
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
        (scenes, learners)
    }
}

/// The learners' colours in the figure, in the sweep's order.
const COLOURS: [&str; 8] = [
    "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#7f7f7f", "#d62728", "#8c564b", "#e377c2",
];

/// The sessions of learner `kind` on scene `si` in task 1 or (`task2`)
/// task 2, failures left out: those of its cells with (task 2) or without
/// reward at the task's beta (column `beta` of the parameters), or at any
/// beta when the learner ignores it.
fn task_sessions<'r>(
    sweep: &Sweep,
    results: &'r [SessionResult],
    si: usize,
    kind: &str,
    task2: bool,
    beta: usize,
) -> Vec<&'r SessionResult> {
    let wanted = if task2 { TASK2_BETA } else { TASK1_BETA };
    let ids: Vec<usize> = sweep
        .cells()
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
}

impl DriveRow {
    /// The row of `learner` on `scene`, from its task-1 sessions `t1` and
    /// its task-2 sessions `t2`, their metrics named by `columns`.
    fn of(
        scene: &str,
        learner: &str,
        t1: &[&SessionResult],
        t2: &[&SessionResult],
        columns: &[String],
    ) -> DriveRow {
        let values = |rs: &[&SessionResult], k: Option<usize>| -> Vec<f64> {
            rs.iter()
                .filter_map(|r| k.and_then(|k| r.values[k]))
                .collect()
        };
        let col = |name: &str| columns.iter().position(|c| c == name);
        let task1 = |name: &str| Measure::of(&values(t1, col(name)));
        let reward = columns
            .iter()
            .position(|c| c.starts_with("cumulative_reward_at_"));
        let rewarded = values(t2, col("first_reward_trial"));
        DriveRow {
            scene: scene.to_string(),
            learner: learner.to_string(),
            task1_sessions: t1.len(),
            task1_entropy: task1("normalized_entropy"),
            task1_coverage: task1("coverage"),
            task1_trials_to_50: task1("trials_to_50_percent"),
            task1_trials_to_90: task1("trials_to_90_percent"),
            task1_qd_score: task1("qd_score"),
            task2_sessions: t2.len(),
            task2_reward: Measure::of(&values(t2, reward)),
            task2_first_reward: Measure::of(&rewarded),
            task2_first_reward_median: median(&rewarded),
            task2_first_reward_quartiles: quartiles(&rewarded),
            task2_never_rewarded: if t2.is_empty() {
                0.0
            } else {
                (t2.len() - rewarded.len()) as f64 / t2.len() as f64
            },
        }
    }

    /// The row's CSV fields: (column, value).
    fn csv_fields(&self) -> Vec<(String, String)> {
        let one = |name: &str, value: String| vec![(name.to_string(), value)];
        let mean_sd = |name: &str, m: &Measure| {
            vec![
                (format!("{name}_mean"), m.stats.mean.to_string()),
                (format!("{name}_sd"), m.stats.sd.to_string()),
            ]
        };
        let ci = |name: &str, m: &Measure| {
            let end =
                |f: fn(&MeanCi) -> f64| m.ci.as_ref().map_or(String::new(), |c| f(c).to_string());
            vec![
                (format!("{name}_ci95_lo"), end(MeanCi::lo)),
                (format!("{name}_ci95_hi"), end(MeanCi::hi)),
            ]
        };
        let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
        // a measure of no session (the QD-score where effort does not vary): empty
        let none_if_empty = |m: &Measure, fields: Vec<(String, String)>| match m.n {
            0 => fields
                .into_iter()
                .map(|(k, _)| (k, String::new()))
                .collect(),
            _ => fields,
        };
        let q = |i: usize| opt(self.task2_first_reward_quartiles.map(|q| q[i]));
        let median = opt(self.task2_first_reward_median);
        let never = self.task2_never_rewarded.to_string();
        [
            one("scene", self.scene.clone()),
            one("learner", self.learner.clone()),
            mean_sd("task1_entropy", &self.task1_entropy),
            mean_sd("task2_reward", &self.task2_reward),
            one("task2_first_reward_median", median),
            one("task2_never_rewarded", never),
            one("task2_sessions", self.task2_sessions.to_string()),
            mean_sd("task1_coverage", &self.task1_coverage),
            mean_sd("task1_trials_to_50", &self.task1_trials_to_50),
            one("task1_reached_50", self.task1_trials_to_50.n.to_string()),
            mean_sd("task1_trials_to_90", &self.task1_trials_to_90),
            one("task1_reached_90", self.task1_trials_to_90.n.to_string()),
            one("task1_sessions", self.task1_sessions.to_string()),
            mean_sd("task2_first_reward", &self.task2_first_reward),
            ci("task1_entropy", &self.task1_entropy),
            ci("task1_coverage", &self.task1_coverage),
            ci("task2_reward", &self.task2_reward),
            one("task2_first_reward_q1", q(0)),
            one("task2_first_reward_q3", q(2)),
            ci("task1_trials_to_50", &self.task1_trials_to_50),
            ci("task1_trials_to_90", &self.task1_trials_to_90),
            none_if_empty(
                &self.task1_qd_score,
                mean_sd("task1_qd_score", &self.task1_qd_score),
            ),
            ci("task1_qd_score", &self.task1_qd_score),
            one("task1_qd_scored", self.task1_qd_score.n.to_string()),
        ]
        .concat()
    }
}
