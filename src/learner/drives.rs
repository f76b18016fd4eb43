//! The drives beyond the paper on one per-slot softmax policy
//! ([`SoftmaxSlots`]: a table `Q` per slot, each slot drawn independently
//! from `softmax(beta Q[:, slot])`): [`RelaxedE3d`], [`CountBonus`] and
//! [`StateMarginalMatching`].
//!
//! Plain code (every weight recomputed at each draw): these learners are
//! for comparing drives, and cost about half a microsecond a trial on 7
//! slots of 4 symbols (E3D: 0.13 µs). [`E3d`](super::E3d) keeps its own, incremental tables.

use super::state::tables::{counts_of, log_target_of, model_tables, no_table, q_rows};
use super::state::tables::{set_model_table, target_of, StateTable};
use super::state::{check_finite, check_model, check_rates, ensure, sizes_of};
use super::state::{LearnerState, StateShape};
use super::{draw_weighted, slot_offsets, Learner, LearnerError, ParamError, Params};
use crate::command::{Command, CommandSpace};
use crate::effect::{log_floored, EffectModel, Target};
use crate::rng::SessionRng;
use crate::world::Outcome;
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// `Q` per slot, the inverse temperature `beta`, and the rates of the
/// paper's update (computed once).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct SoftmaxSlots {
    /// `Q[symbol, slot]` at `offsets[slot] + symbol`.
    pub q: Vec<f64>,
    pub offsets: Vec<usize>,
    pub beta: f64,
    /// `1 - alpha lambda`, `alpha lambda` and `alpha / beta`.
    pub decay: f64,
    pub alpha_lambda: f64,
    pub alpha_over_beta: f64,
}

impl SoftmaxSlots {
    /// `Q = 0` (every symbol equally likely), with `params.alpha`, `beta`
    /// and `lambda`.
    pub fn new(space: &CommandSpace, params: &Params) -> Self {
        let offsets = slot_offsets(space);
        SoftmaxSlots {
            q: vec![0.0; *offsets.last().unwrap_or(&0)],
            offsets,
            beta: params.beta,
            decay: 1.0 - params.alpha * params.lambda,
            alpha_lambda: params.alpha * params.lambda,
            alpha_over_beta: params.alpha / params.beta,
        }
    }

    /// The number of slots.
    pub fn num_slots(&self) -> usize {
        self.offsets.len() - 1
    }

    /// `Q[:, slot]`.
    pub fn slot(&self, slot: usize) -> &[f64] {
        &self.q[self.offsets[slot]..self.offsets[slot + 1]]
    }

    /// `softmax(beta q)`.
    pub fn probs_of(beta: f64, q: &[f64]) -> Vec<f64> {
        let m = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let w: Vec<f64> = q.iter().map(|&v| (beta * (v - m)).exp()).collect();
        let total: f64 = w.iter().sum();
        w.into_iter().map(|v| v / total).collect()
    }

    /// `softmax(beta Q[:, slot])`.
    pub fn policy(&self, slot: usize) -> Vec<f64> {
        Self::probs_of(self.beta, self.slot(slot))
    }

    /// Draws every slot of `command` from the softmax of `q` (a table laid
    /// out like `self.q`: the current one or an earlier copy), one uniform
    /// draw per slot.
    pub fn sample_from(&self, q: &[f64], rng: &mut SessionRng, command: &mut Command) {
        let n = self.num_slots();
        command.symbols.resize(n, 0);
        for slot in 0..n {
            let qs = &q[self.offsets[slot]..self.offsets[slot + 1]];
            let m = qs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let pick = draw_weighted(qs.iter().map(|&v| (self.beta * (v - m)).exp()), rng);
            command.symbols[slot] = pick as u8;
        }
    }

    /// The paper's update of every chosen symbol, with the learner's
    /// intrinsic `drive`:
    /// `Q[a_i, i] <- (1 - alpha lambda) Q[a_i, i] + alpha lambda r + (alpha / beta) drive`.
    pub fn update_chosen(&mut self, command: &Command, reward: f64, drive: f64) {
        let gain = self.alpha_lambda * reward + self.alpha_over_beta * drive;
        for (slot, &a) in command.symbols.iter().enumerate() {
            let q = &mut self.q[self.offsets[slot] + a as usize];
            *q = self.decay * *q + gain;
        }
    }

    /// The tables `q` and `policy` (both writable).
    pub fn tables(&self) -> Vec<StateTable> {
        let sizes = sizes_of(&self.offsets);
        vec![
            StateTable::slots("q", true, &sizes, |s| self.slot(s).to_vec()),
            StateTable::slots("policy", true, &sizes, |s| self.policy(s)),
        ]
    }

    /// Writes the table `q` or `policy` (Q becomes `log(policy) / beta`);
    /// `Ok(false)` if `name` is neither.
    pub fn set_table(&mut self, name: &str, values: &[f64]) -> Result<bool, LearnerError> {
        let Some(rows) = q_rows(name, values, &sizes_of(&self.offsets), self.beta)? else {
            return Ok(false);
        };
        for (s, r) in rows.iter().enumerate() {
            self.q[self.offsets[s]..self.offsets[s + 1]].copy_from_slice(r);
        }
        Ok(true)
    }

    /// Checks slots read from a state: their offsets, rates and `Q`.
    pub fn validate(&self) -> Result<(), String> {
        check_offsets(&self.offsets, self.q.len())?;
        check_rates(
            &[
                ("1 - alpha lambda", self.decay),
                ("alpha lambda", self.alpha_lambda),
                ("alpha / beta", self.alpha_over_beta),
            ],
            self.beta,
        )?;
        check_finite("q", &self.q)
    }
}

/// Checks offsets of slots read from a state: from 0 to `len`, each slot
/// 1 to 256 symbols.
pub(crate) fn check_offsets(offsets: &[usize], len: usize) -> Result<(), String> {
    let ok = offsets.len() >= 2
        && offsets[0] == 0
        && offsets.last() == Some(&len)
        && offsets
            .windows(2)
            .all(|w| w[0] < w[1] && w[1] - w[0] <= 256);
    ensure(ok, || {
        format!("slot offsets {offsets:?} for a table of {len} values")
    })
}

/// E3D that cannot lock: the paper's update of the chosen symbols, and
/// every value relaxing slowly towards 0.
///
/// After a trial with effect `e` and reward `r`, `p` is updated as in
/// [`E3d`](super::E3d), then for every slot `i`
///
/// ```text
/// Q[a, i] <- (1 - rho alpha lambda) Q[a, i]                 for every symbol a
/// Q[a_i, i] <- (1 - alpha lambda) Q[a_i, i] + alpha lambda r
///              - (alpha / beta) (log p(e) - log p*(e))
/// ```
///
/// with `rho` = [`RELAX`](Self::RELAX): a symbol a slot stopped choosing
/// climbs back towards 0 and is tried again, where E3D keeps its value
/// for ever (why and measures: docs/algorithms.md, "E3D that cannot lock").
///
/// ```
/// use e3d::learner::RelaxedE3d;
/// use e3d::{Command, Learner, Outcome, Params, Target};
/// use e3d::command::CommandSpace;
/// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
/// let mut l = RelaxedE3d::new(&space, 3, &Params::TASK1, &Target::Uniform).unwrap();
/// l.learn(&Command::new(vec![0, 1]), &Outcome { effect: 2, reward: 0.0, point: [0.0; 2] });
/// let pushed = l.q(0)[0];
/// assert!(pushed < 0.0);
/// // symbol 1 of slot 0 is chosen next: symbol 0 relaxes towards 0
/// l.learn(&Command::new(vec![1, 1]), &Outcome { effect: 0, reward: 0.0, point: [0.0; 2] });
/// let relaxed = (1.0 - RelaxedE3d::RELAX * 0.3 * 0.03) * pushed;
/// assert_eq!(l.q(0)[0], relaxed);
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RelaxedE3d {
    slots: SoftmaxSlots,
    model: EffectModel,
    log_target: Vec<f64>,
    /// `1 - rho alpha lambda`.
    relax: f64,
}

impl RelaxedE3d {
    /// The default rate `rho` of the relaxation, relative to `alpha lambda`.
    pub const RELAX: f64 = 0.02;

    /// A fresh learner (Q = 0, p uniform) with `params.alpha`, `beta`,
    /// `lambda` and `eta`, the target `p*`, and `rho` = [`RELAX`](Self::RELAX).
    pub fn new(
        space: &CommandSpace,
        num_effects: usize,
        params: &Params,
        target: &Target,
    ) -> Result<Self, LearnerError> {
        params.validate()?;
        Ok(RelaxedE3d {
            slots: SoftmaxSlots::new(space, params),
            model: EffectModel::new(num_effects, params.eta)?,
            log_target: target.log_probs(num_effects)?,
            relax: 1.0 - Self::RELAX * params.alpha * params.lambda,
        })
    }

    /// The same learner with another rate `rho` (0 gives the paper's E3D,
    /// in plain code); `rho` must be in `[0, 1 / (alpha lambda)]`.
    pub fn with_relax(mut self, rho: f64) -> Result<Self, ParamError> {
        let relax = 1.0 - rho * self.slots.alpha_lambda;
        if !(rho >= 0.0 && (0.0..=1.0).contains(&relax)) {
            return Err(ParamError {
                name: "rho",
                value: rho,
                expected: "a number in [0, 1 / (alpha lambda)]",
            });
        }
        self.relax = relax;
        Ok(self)
    }

    /// `Q[:, slot]`.
    pub fn q(&self, slot: usize) -> &[f64] {
        self.slots.slot(slot)
    }
}

impl Learner for RelaxedE3d {
    fn name(&self) -> &str {
        "e3d_relax"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        self.slots.sample_from(&self.slots.q, rng, command);
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        let e = outcome.effect;
        let pe = self.model.observe(e);
        // E3D's drive, log p*(e) - log p(e)
        let drive = self.log_target[e] - log_floored(pe);
        for q in &mut self.slots.q {
            *q *= self.relax;
        }
        self.slots.update_chosen(command, outcome.reward, drive);
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        Some(self.slots.policy(slot))
    }
}

impl LearnerState for RelaxedE3d {
    const KIND: &'static str = "e3d_relax";
    fn shape(&self) -> StateShape {
        StateShape::of(
            sizes_of(&self.slots.offsets),
            Some(self.model.num_effects()),
        )
    }
    fn validate(&self) -> Result<(), String> {
        self.slots.validate()?;
        check_model(&self.model, &self.log_target)
    }
    /// `q`, `policy`, `p` and `target`, all writable.
    fn tables(&self) -> Vec<StateTable> {
        let mut t = self.slots.tables();
        t.extend(model_tables(&self.model, &self.log_target));
        t
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        if set_model_table(name, values, &mut self.model, &mut self.log_target)?
            || self.slots.set_table(name, values)?
        {
            return Ok(());
        }
        Err(no_table(Self::KIND, name, &self.tables()))
    }
}

/// A count-based exploration bonus on effects (after Bellemare et al.
/// 2016, "Unifying count-based exploration and intrinsic motivation"):
/// the intrinsic reward of effect `e` is `1 / sqrt(N(e))`, `N(e)` the
/// number of trials that ended in `e` so far (this one included), added
/// to the extrinsic reward in the per-slot update of E3D:
///
/// ```text
/// N(e) <- N(e) + 1
/// Q[a_i, i] <- (1 - alpha lambda) Q[a_i, i] + alpha lambda r + (alpha / beta) / sqrt(N(e))
/// ```
///
/// with `a_i ~ softmax(beta Q[:, i])`; no target `p*`, no `eta`.
///
/// ```
/// use e3d::learner::CountBonus;
/// use e3d::{Command, Learner, Outcome, Params};
/// use e3d::command::CommandSpace;
/// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
/// let mut l = CountBonus::new(&space, 3, &Params::TASK1);
/// let c = Command::new(vec![0, 1]);
/// l.learn(&c, &Outcome { effect: 2, reward: 0.0, point: [0.0; 2] });
/// let first = l.q(0)[0];
/// assert!((first - 0.3).abs() < 1e-12); // alpha / beta / sqrt(1)
/// l.learn(&c, &Outcome { effect: 2, reward: 0.0, point: [0.0; 2] });
/// // the second visit earns 1 / sqrt(2)
/// let second = (1.0 - 0.3 * 0.03) * first + 0.3 / 2f64.sqrt();
/// assert!((l.q(0)[0] - second).abs() < 1e-12);
/// assert_eq!(l.count(2), 2);
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CountBonus {
    slots: SoftmaxSlots,
    counts: Vec<u64>,
}

impl CountBonus {
    /// A fresh learner (Q = 0, no effect seen) with `params.alpha`, `beta`
    /// and `lambda`.
    pub fn new(space: &CommandSpace, num_effects: usize, params: &Params) -> Self {
        CountBonus {
            slots: SoftmaxSlots::new(space, params),
            counts: vec![0; num_effects],
        }
    }

    /// `Q[:, slot]`.
    pub fn q(&self, slot: usize) -> &[f64] {
        self.slots.slot(slot)
    }

    /// `N(e)`: the trials that ended in `effect` so far.
    pub fn count(&self, effect: usize) -> u64 {
        self.counts[effect]
    }
}

impl Learner for CountBonus {
    fn name(&self) -> &str {
        "count"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        self.slots.sample_from(&self.slots.q, rng, command);
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        let n = &mut self.counts[outcome.effect];
        *n += 1;
        let bonus = 1.0 / (*n as f64).sqrt();
        self.slots.update_chosen(command, outcome.reward, bonus);
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        Some(self.slots.policy(slot))
    }
}

impl LearnerState for CountBonus {
    const KIND: &'static str = "count";
    fn shape(&self) -> StateShape {
        StateShape::of(sizes_of(&self.slots.offsets), Some(self.counts.len()))
    }
    fn validate(&self) -> Result<(), String> {
        self.slots.validate()?;
        ensure(!self.counts.is_empty(), || "no effect counted".into())
    }
    /// `q`, `policy` and `counts` (`N(e)`, integers), all writable.
    fn tables(&self) -> Vec<StateTable> {
        let mut t = self.slots.tables();
        let counts = self.counts.iter().map(|&n| n as f64).collect();
        t.push(StateTable::vector("counts", true, counts));
        t
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        match name {
            "counts" => self.counts = counts_of(values, self.counts.len())?,
            _ if self.slots.set_table(name, values)? => {}
            _ => return Err(no_table(Self::KIND, name, &self.tables())),
        }
        Ok(())
    }
}

/// State marginal matching (after Lee et al. 2019) on the effect
/// histogram: the intrinsic reward is `log p*(e) - log rho(e)`, `rho` the
/// marginal of every trial so far, and the behaviour the historical
/// average of the policies (SMM's fictitious play):
///
/// ```text
/// N(e) <- N(e) + 1;  t <- t + 1;  rho(e) = (N(e) + 1) / (t + |E|)
/// Q[a_i, i] <- (1 - alpha lambda) Q[a_i, i] + alpha lambda r
///              + (alpha / beta) (log p*(e) - log rho(e))
/// propose: draw k uniformly among the kept policies (the current one
///          included), then a_i ~ softmax(beta Q_k[:, i])
/// ```
///
/// A copy of `Q` is kept every [`SNAPSHOT_EVERY`](Self::SNAPSHOT_EVERY)
/// trials; past [`MAX_SNAPSHOTS`](Self::MAX_SNAPSHOTS) copies, every
/// other one is dropped and the interval doubles, so the kept policies
/// stay evenly spread over the session in bounded memory. The behaviour
/// (a mixture of product policies) is not a product itself:
/// [`slot_policy`](Learner::slot_policy) is `None`. No `eta`.
///
/// ```
/// use e3d::learner::StateMarginalMatching;
/// use e3d::{Command, Learner, Outcome, Params, Target};
/// use e3d::command::CommandSpace;
/// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
/// let mut l = StateMarginalMatching::new(&space, 4, &Params::TASK1, &Target::Uniform).unwrap();
/// l.learn(&Command::new(vec![0, 1]), &Outcome { effect: 3, reward: 0.0, point: [0.0; 2] });
/// // rho(3) = 2/5 > p*(3) = 1/4: the symbols that led there lose value
/// let expected = 0.3 * ((0.25f64).ln() - (0.4f64).ln());
/// assert!((l.q(0)[0] - expected).abs() < 1e-12);
/// assert_eq!(l.slot_policy(0), None);
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StateMarginalMatching {
    slots: SoftmaxSlots,
    counts: Vec<u64>,
    trials: u64,
    log_target: Vec<f64>,
    /// Earlier copies of `Q`, oldest first.
    snapshots: Vec<Vec<f64>>,
    /// The trials between two copies.
    every: u64,
}

impl StateMarginalMatching {
    /// Trials between two kept policies at the start.
    pub const SNAPSHOT_EVERY: u64 = 50;
    /// The most earlier policies kept.
    pub const MAX_SNAPSHOTS: usize = 256;

    /// A fresh learner (Q = 0, no effect seen) with `params.alpha`, `beta`
    /// and `lambda`, and the target `p*`.
    pub fn new(
        space: &CommandSpace,
        num_effects: usize,
        params: &Params,
        target: &Target,
    ) -> Result<Self, LearnerError> {
        params.validate()?;
        Ok(StateMarginalMatching {
            slots: SoftmaxSlots::new(space, params),
            counts: vec![0; num_effects],
            trials: 0,
            log_target: target.log_probs(num_effects)?,
            snapshots: Vec::new(),
            every: Self::SNAPSHOT_EVERY,
        })
    }

    /// `Q[:, slot]` of the current policy.
    pub fn q(&self, slot: usize) -> &[f64] {
        self.slots.slot(slot)
    }

    /// The number of earlier policies the behaviour averages over (the
    /// current one besides).
    pub fn num_snapshots(&self) -> usize {
        self.snapshots.len()
    }
}

impl Learner for StateMarginalMatching {
    fn name(&self) -> &str {
        "smm"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        let k = rng.random_range(0..=self.snapshots.len());
        let q = self.snapshots.get(k).unwrap_or(&self.slots.q);
        self.slots.sample_from(q, rng, command);
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        let e = outcome.effect;
        self.counts[e] += 1;
        self.trials += 1;
        let rho = (self.counts[e] + 1) as f64 / (self.trials + self.counts.len() as u64) as f64;
        let drive = self.log_target[e] - rho.ln();
        self.slots.update_chosen(command, outcome.reward, drive);
        if self.trials % self.every == 0 {
            self.snapshots.push(self.slots.q.clone());
            if self.snapshots.len() > Self::MAX_SNAPSHOTS {
                // keep every other copy (the later of each pair): still
                // evenly spread, at twice the interval
                let kept: Vec<Vec<f64>> = self.snapshots.drain(..).skip(1).step_by(2).collect();
                self.snapshots = kept;
                self.every *= 2;
            }
        }
    }
}

impl LearnerState for StateMarginalMatching {
    const KIND: &'static str = "smm";
    fn shape(&self) -> StateShape {
        StateShape::of(sizes_of(&self.slots.offsets), Some(self.counts.len()))
    }
    fn validate(&self) -> Result<(), String> {
        self.slots.validate()?;
        let (counts, n) = (self.counts.len(), self.slots.q.len());
        ensure(counts > 0 && counts == self.log_target.len(), || {
            format!(
                "{counts} counts for a target of {} effects",
                self.log_target.len()
            )
        })?;
        ensure(
            self.every > 0 && self.snapshots.iter().all(|s| s.len() == n),
            || {
                format!(
                    "policies kept every {} trials, of sizes other than {n}",
                    self.every
                )
            },
        )
    }
    /// `q` and `policy` (of the current policy) and `target`, writable;
    /// `counts` (the effects' visits, which the kept copies' schedule
    /// follows) read-only.
    fn tables(&self) -> Vec<StateTable> {
        let mut t = self.slots.tables();
        let counts = self.counts.iter().map(|&n| n as f64).collect();
        t.push(StateTable::vector("counts", false, counts));
        t.push(StateTable::vector(
            "target",
            true,
            target_of(&self.log_target),
        ));
        t
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        match name {
            "target" => self.log_target = log_target_of(values, self.counts.len())?,
            _ if self.slots.set_table(name, values)? => {}
            _ => return Err(no_table(Self::KIND, name, &self.tables())),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn draws_follow_the_softmax() {
        let space = CommandSpace::repeat(1, &['a', 'b', 'c']).unwrap();
        let params = Params {
            beta: 2.0,
            ..Params::TASK1
        };
        let mut s = SoftmaxSlots::new(&space, &params);
        s.q.copy_from_slice(&[0.0, 0.5, -1.0]);
        let p = SoftmaxSlots::probs_of(2.0, s.slot(0));
        let z = 1.0 + 1f64.exp() + (-2f64).exp();
        assert!((p[1] - 1f64.exp() / z).abs() < 1e-12);
        let mut rng = SessionRng::seed_from_u64(3);
        let mut c = space.first();
        let mut counts = [0usize; 3];
        for _ in 0..100_000 {
            s.sample_from(&s.q, &mut rng, &mut c);
            counts[c.symbols[0] as usize] += 1;
        }
        for a in 0..3 {
            let f = counts[a] as f64 / 100_000.0;
            // 4 standard errors at most
            assert!(
                (f - p[a]).abs() < 4.0 * (p[a] * (1.0 - p[a]) / 1e5).sqrt(),
                "{a}: {f}"
            );
        }
    }
}
