//! The metrics of a session: kept as it runs ([`RunningMetrics`]) or
//! computed from its record ([`Metrics`]), coverage, and the exact effect
//! distribution of a policy.

use super::Recorder;
use crate::effect::{entropy, kl_divergence, normalized_entropy_over, Target};
use crate::learner::{Effort, Effortful, Learner};
use crate::world::{Outcome, OutcomeTable};
use serde::{Deserialize, Serialize};

/// The trials the last-trials entropy covers.
const LAST: usize = 1000;

/// The metrics of a session, kept as it runs, in constant memory: effect
/// counts, the last 1000 effects, the reward so far and at chosen trials.
/// Its [`metrics`](Self::metrics) equal [`SessionRecord::metrics`](super::SessionRecord::metrics) bit for
/// bit.
#[derive(Debug, Clone, PartialEq)]
pub struct RunningMetrics {
    counts: Vec<u64>,
    /// The last [`LAST`] effects, a ring (`trials % LAST` is the next).
    last: Vec<u32>,
    trials: usize,
    cumulative: f64,
    first_reward: Option<usize>,
    /// The 1-based trial at which each effect was first reached, in order.
    discoveries: Vec<usize>,
    /// Trials (1-based, increasing) at which the cumulative reward is kept.
    checkpoints: Vec<usize>,
    at_checkpoints: Vec<f64>,
    /// The effort the `qd_score` is measured by, if given.
    effort: Option<Effort>,
    /// Per cell, the best effort quality of the commands that reached it
    /// (`-inf`: none).
    elites: Vec<f64>,
}

impl RunningMetrics {
    /// Nothing recorded yet, for a world of `num_effects` effects.
    pub fn new(num_effects: usize) -> Self {
        Self::with_checkpoints(num_effects, &[])
    }

    /// The same, keeping the cumulative reward after each of the trials
    /// `checkpoints` (1-based) for [`cumulative_reward_at`](Self::cumulative_reward_at).
    pub fn with_checkpoints(num_effects: usize, checkpoints: &[usize]) -> Self {
        let mut checkpoints = checkpoints.to_vec();
        checkpoints.sort_unstable();
        checkpoints.dedup();
        RunningMetrics {
            counts: vec![0; num_effects],
            last: Vec::with_capacity(LAST),
            trials: 0,
            cumulative: 0.0,
            first_reward: None,
            discoveries: Vec::new(),
            at_checkpoints: Vec::with_capacity(checkpoints.len()),
            checkpoints,
            effort: None,
            elites: Vec::new(),
        }
    }

    /// The same, measuring the `qd_score` ([`Metrics::qd_score`]) by the
    /// effort `effort` of the recorded commands (the scene's:
    /// [`Effort::of_scene`]). An effort that does not vary
    /// ([`Effort::varies`]: every command the same) is not kept, and the
    /// `qd_score` stays `None`.
    ///
    /// ```
    /// use e3d::learner::Effort;
    /// use e3d::command::CommandSpace;
    /// use e3d::session::RunningMetrics;
    /// use e3d::{Outcome, Recorder, Target};
    /// let space = CommandSpace::repeat(2, &['-', '0', '+']).unwrap();
    /// let effort = Effort::Symbols(vec![vec![1.0, 0.0, 1.0], vec![2.0, 0.0, 2.0]]);
    /// let mut m = RunningMetrics::new(3).with_effort(effort);
    /// for (c, e) in [("++", 0), ("+0", 0), ("+-", 2)] {
    ///     let o = Outcome { effect: e, reward: 0.0, point: [0.0; 2] };
    ///     m.record(&space.parse(c).unwrap(), &o);
    /// }
    /// // cell 0's elite "+0" (quality 1 - 1/3), cell 2's "+-" (0)
    /// assert_eq!(m.metrics(&Target::Uniform).qd_score, Some(1.0 - 1.0 / 3.0));
    /// let flat = Effort::Symbols(vec![vec![1.0, 1.0]; 2]);
    /// assert_eq!(RunningMetrics::new(3).with_effort(flat).metrics(&Target::Uniform).qd_score, None);
    /// ```
    pub fn with_effort(self, effort: Effort) -> Self {
        if !effort.varies() {
            return self;
        }
        RunningMetrics {
            elites: vec![f64::NEG_INFINITY; self.counts.len()],
            effort: Some(effort),
            ..self
        }
    }

    /// The number of trials recorded.
    pub fn trials(&self) -> usize {
        self.trials
    }

    /// How many trials ended in each effect.
    pub fn effect_counts(&self) -> Vec<f64> {
        self.counts.iter().map(|&c| c as f64).collect()
    }

    /// The sum of the rewards after trial `t` (1-based), if `t` was one of
    /// the checkpoints and has been reached.
    pub fn cumulative_reward_at(&self, t: usize) -> Option<f64> {
        let k = self.checkpoints.iter().position(|&c| c == t)?;
        self.at_checkpoints.get(k).copied()
    }

    /// The session's metrics against the target `p*`.
    pub fn metrics(&self, target: &Target) -> Metrics {
        self.metrics_given(target, None)
    }

    /// The same, with the entropy over the `reachable_effects` effects
    /// some command reaches (see [`SessionRecord::metrics_over_reachable`](super::SessionRecord::metrics_over_reachable)).
    pub fn metrics_over_reachable(&self, target: &Target, reachable_effects: usize) -> Metrics {
        self.metrics_given(target, Some(reachable_effects))
    }

    fn metrics_given(&self, target: &Target, reachable: Option<usize>) -> Metrics {
        let all = self.effect_counts();
        let mut last = vec![0.0; all.len()];
        for &e in &self.last {
            last[e as usize] += 1.0;
        }
        let num_effects = all.len();
        // the cells coverage counts against: the reachable ones if known
        let cells = reachable.unwrap_or(num_effects).max(1);
        let distinct = all.iter().filter(|&&c| c > 0.0).count();
        let norm = (num_effects as f64).ln();
        let norm = if norm > 0.0 { norm } else { 1.0 };
        let log_target = target
            .log_probs(num_effects)
            .unwrap_or_else(|_| vec![-norm; num_effects]);
        let discoveries = &self.discoveries;
        Metrics {
            normalized_entropy: entropy(&all) / norm,
            normalized_entropy_last_1000: entropy(&last) / norm,
            kl_to_target: kl_divergence(&all, &log_target),
            distinct_effects: distinct,
            cumulative_reward: self.cumulative,
            first_reward_trial: self.first_reward,
            trials: self.trials,
            reachable_effects: reachable,
            normalized_entropy_reachable: reachable.map(|k| normalized_entropy_over(&all, k)),
            coverage_cells: cells,
            coverage: distinct as f64 / cells as f64,
            trials_to_50_percent: trials_to_fraction(discoveries, cells, 0.5),
            trials_to_90_percent: trials_to_fraction(discoveries, cells, 0.9),
            discovery_trials: discoveries.clone(),
            qd_score: self.effort.as_ref().map(|_| {
                let filled = self.elites.iter().filter(|q| q.is_finite());
                filled.sum()
            }),
        }
    }
}

impl<C: Effortful + ?Sized> Recorder<C> for RunningMetrics {
    fn record(&mut self, command: &C, outcome: &Outcome) {
        if let Some(effort) = &self.effort {
            let q = effort.quality(command).unwrap_or(0.0);
            let best = &mut self.elites[outcome.effect];
            *best = best.max(q);
        }
        if self.counts[outcome.effect] == 0 {
            self.discoveries.push(self.trials + 1);
        }
        self.counts[outcome.effect] += 1;
        if self.last.len() < LAST {
            self.last.push(outcome.effect as u32);
        } else {
            self.last[self.trials % LAST] = outcome.effect as u32;
        }
        self.trials += 1;
        self.cumulative += outcome.reward;
        if self.first_reward.is_none() && outcome.reward > 0.0 {
            self.first_reward = Some(self.trials);
        }
        if self.checkpoints.get(self.at_checkpoints.len()) == Some(&self.trials) {
            self.at_checkpoints.push(self.cumulative);
        }
    }
}

/// The numbers that summarise a session.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Entropy of the terminal effects over all trials, divided by
    /// `log(num_effects)` (1 = perfectly uniform over every effect).
    pub normalized_entropy: f64,
    /// The same over the last 1000 trials (all trials if fewer).
    pub normalized_entropy_last_1000: f64,
    /// `KL(empirical || target)` of the terminal effects over all trials, in nats.
    pub kl_to_target: f64,
    /// The number of distinct effects reached.
    pub distinct_effects: usize,
    /// The sum of the rewards over all trials.
    pub cumulative_reward: f64,
    /// The 1-based trial of the first positive reward, if any.
    pub first_reward_trial: Option<usize>,
    /// The number of trials.
    pub trials: usize,
    /// The number of effects some command reaches, when it is known (an
    /// [`OutcomeTable`] knows it: [`OutcomeTable::reachable_effects`]) and
    /// given to [`SessionRecord::metrics_over_reachable`](super::SessionRecord::metrics_over_reachable) or
    /// [`RunningMetrics::metrics_over_reachable`]; `None` otherwise.
    pub reachable_effects: Option<usize>,
    /// The entropy of the terminal effects over all trials divided by
    /// `log(reachable_effects)`: 1 = uniform over what can be reached
    /// (see [`crate::effect::normalized_entropy_over`]).
    /// `None` when the reachable effects are not known.
    pub normalized_entropy_reachable: Option<f64>,
    /// The cells the coverage measures count against: the reachable
    /// effects when they are known ([`reachable_effects`](Self::reachable_effects)),
    /// else every effect.
    pub coverage_cells: usize,
    /// The fraction of [`coverage_cells`](Self::coverage_cells) reached by
    /// the last trial: `distinct_effects / coverage_cells`.
    pub coverage: f64,
    /// The 1-based trial by which 50% of the coverage cells were reached
    /// (`ceil(0.5 coverage_cells)` distinct effects), if they were.
    pub trials_to_50_percent: Option<usize>,
    /// The same for 90% (`ceil(0.9 coverage_cells)` distinct effects).
    pub trials_to_90_percent: Option<usize>,
    /// The 1-based trial at which each distinct effect was first reached,
    /// in order: the fraction of the coverage cells found by trial `t` is
    /// the number of these `<= t` over [`coverage_cells`](Self::coverage_cells)
    /// ([`coverage_at`](Self::coverage_at)).
    pub discovery_trials: Vec<usize>,
    /// The QD-score (pyribs' and QDax's): the sum, over the reached
    /// cells, of the best effort quality `1 - effort / max` among the
    /// commands that reached the cell ([`Effort`]; the quality `-effort /
    /// max` with the offset 1, so that each cell adds a number in
    /// `[0, 1]`). `None` when the commands' effort is unknown
    /// ([`RunningMetrics::with_effort`]; a [`SessionRecord`](super::SessionRecord)
    /// keeps no command), for episodes, and where every command has the
    /// same effort ([`Effort::varies`]: the puck and grid scenes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub qd_score: Option<f64>,
}

impl Metrics {
    /// The fraction of the coverage cells reached by trial `t` (1-based;
    /// 0 before the first trial).
    ///
    /// ```
    /// use e3d::{Command, Outcome, Recorder, Target};
    /// use e3d::session::RunningMetrics;
    /// let mut m = RunningMetrics::new(4);
    /// for e in [0, 0, 1, 0, 3] {
    ///     m.record(&Command::new(vec![0]), &Outcome { effect: e, reward: 0.0, point: [0.0; 2] });
    /// }
    /// let m = m.metrics(&Target::Uniform);
    /// assert_eq!(m.discovery_trials, [1, 3, 5]);
    /// assert_eq!((m.coverage_at(2), m.coverage_at(3), m.coverage), (0.25, 0.5, 0.75));
    /// assert_eq!((m.trials_to_50_percent, m.trials_to_90_percent), (Some(3), None));
    /// ```
    pub fn coverage_at(&self, t: usize) -> f64 {
        let found = self.discovery_trials.partition_point(|&d| d <= t);
        found as f64 / self.coverage_cells.max(1) as f64
    }
}

/// The trial by which `ceil(fraction x cells)` distinct effects were
/// reached, given the trials of the discoveries (in order); `None` if
/// they were not.
///
/// ```
/// use e3d::session::trials_to_fraction;
/// assert_eq!(trials_to_fraction(&[1, 4, 9, 30], 4, 0.5), Some(4));
/// assert_eq!(trials_to_fraction(&[1, 4, 9, 30], 4, 0.9), Some(30));
/// assert_eq!(trials_to_fraction(&[1, 4, 9], 4, 0.9), None);
/// // ceil: 50% of 5 cells is 3 of them
/// assert_eq!(trials_to_fraction(&[1, 4, 9], 5, 0.5), Some(9));
/// ```
pub fn trials_to_fraction(discoveries: &[usize], cells: usize, fraction: f64) -> Option<usize> {
    let need = ((fraction * cells as f64) - 1e-9).ceil().max(1.0) as usize;
    discoveries.get(need - 1).copied()
}

/// The exact distribution of effects under `learner`'s current policy:
/// the sum, over every command, of its probability times the indicator of
/// its effect. `None` if the learner's policy is not a product of per-slot
/// distributions. The cost is `table.len() x num_slots`.
pub fn policy_effect_distribution(table: &OutcomeTable, learner: &dyn Learner) -> Option<Vec<f64>> {
    let space = crate::world::World::command_space(&table);
    let n = space.num_slots();
    let slot_probs: Vec<Vec<f64>> = (0..n)
        .map(|s| learner.slot_policy(s))
        .collect::<Option<_>>()?;
    let mut dist = vec![0.0; crate::world::World::num_effects(&table)];
    let mut c = space.first();
    for (i, o) in table.outcomes().enumerate() {
        space.write_command_at(i as u64, &mut c);
        let p: f64 = c
            .symbols
            .iter()
            .zip(&slot_probs)
            .map(|(&s, ps)| ps[s as usize])
            .product();
        dist[o.effect] += p;
    }
    Some(dist)
}
