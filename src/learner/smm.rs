use super::softmax::SoftmaxSlots;
use super::state::tables::{log_target_of, no_table, target_of, StateTable};
use super::state::{ensure, sizes_of, LearnerState, StateShape};
use super::{Learner, LearnerError, Params};
use crate::command::{Command, CommandSpace};
use crate::effect::Target;
use crate::rng::SessionRng;
use crate::world::Outcome;
use rand::RngExt;
use serde::{Deserialize, Serialize};

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
