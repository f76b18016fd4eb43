use super::{slot_offsets, Learner, Params};
use crate::command::{Command, CommandSpace};
use crate::effect::{EffectModel, Target};
use crate::world::Outcome;
use rand::{Rng, RngExt};

/// End-Effect Exploration Drive: the paper's Algorithm 1.
///
/// The policy draws each slot independently, `a_i ~ softmax(beta Q[:, i])`.
/// After a trial with effect `e` and reward `r`, the running histogram is
/// updated first, `p <- (1 - eta) p + eta onehot(e)`, then for every slot
///
/// ```text
/// Q[a_i, i] <- (1 - alpha lambda) Q[a_i, i] + alpha lambda r
///              - (alpha / beta) (log p(e) - log p*(e))
/// ```
///
/// with the fresh `p(e)`. Without reward, `beta` cancels out: the logits are
/// `beta Q` and the change of `Q` is proportional to `1 / beta`.
///
/// Cost: a trial changes one entry of `Q` per slot, so the learner keeps the
/// softmax weights `exp(beta Q - m_slot)` and their sum per slot, and
/// updates one weight per slot (one `exp`) per trial; the shift `m_slot` is
/// reset to the slot's largest logit only when the sum leaves
/// `[1e-100, 1e100]`. The histogram update is O(1) ([`EffectModel`]).
///
/// ```
/// use e3d::{Command, CommandSpace, E3d, Learner, Outcome, Params, Target};
/// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
/// let mut l = E3d::new(&space, 3, &Params::TASK1, &Target::Uniform).unwrap();
/// let c = Command::new(vec![0, 1]);
/// l.learn(&c, &Outcome { effect: 2, reward: 0.0, point: [0.0, 0.0] });
/// // p(2) rose above 1/3, so the symbols that led there lost value
/// assert!(l.q(0)[0] < 0.0 && l.q(1)[1] < 0.0);
/// assert_eq!(l.q(0)[1], 0.0);
/// ```
#[derive(Debug, Clone)]
pub struct E3d {
    q: Vec<f64>,
    offsets: Vec<usize>,
    /// `exp(beta q - shift[slot])`, laid out as `q`.
    weights: Vec<f64>,
    /// Running sums of `weights` within each slot (the last one of a slot
    /// is the slot's total), laid out as `q`.
    cumulative: Vec<f64>,
    /// Per slot: the shift of its logits.
    shift: Vec<f64>,
    model: EffectModel,
    log_target: Vec<f64>,
    alpha: f64,
    beta: f64,
    lambda: f64,
}

impl E3d {
    /// A fresh learner (Q = 0, p uniform) for `space`, `num_effects`
    /// effects, the hyper-parameters `params` (epsilon unused) and the
    /// target `p*`.
    pub fn new(
        space: &CommandSpace,
        num_effects: usize,
        params: &Params,
        target: &Target,
    ) -> Result<Self, String> {
        params.validate().map_err(|e| e.to_string())?;
        let offsets = slot_offsets(space);
        let total = *offsets.last().unwrap_or(&0);
        Ok(E3d {
            q: vec![0.0; total],
            weights: vec![1.0; total],
            cumulative: space
                .sizes()
                .flat_map(|k| (1..=k).map(|i| i as f64))
                .collect(),
            shift: vec![0.0; space.num_slots()],
            offsets,
            model: EffectModel::new(num_effects, params.eta)?,
            log_target: target.log_probs(num_effects)?,
            alpha: params.alpha,
            beta: params.beta,
            lambda: params.lambda,
        })
    }

    /// `Q[:, slot]`.
    pub fn q(&self, slot: usize) -> &[f64] {
        &self.q[self.offsets[slot]..self.offsets[slot + 1]]
    }

    /// Recomputes a slot's weights with its largest logit as the shift.
    fn reshift(&mut self, slot: usize) {
        let (lo, hi) = (self.offsets[slot], self.offsets[slot + 1]);
        let top = self.q[lo..hi]
            .iter()
            .map(|&q| self.beta * q)
            .fold(f64::NEG_INFINITY, f64::max);
        self.shift[slot] = top;
        for i in lo..hi {
            self.weights[i] = (self.beta * self.q[i] - top).exp();
        }
        self.accumulate(slot, lo);
    }

    /// Recomputes the running sums of `slot` from entry `from` on; false if
    /// the total left `[1e-100, 1e100]` (time to reshift).
    #[inline]
    fn accumulate(&mut self, slot: usize, from: usize) -> bool {
        let (lo, hi) = (self.offsets[slot], self.offsets[slot + 1]);
        let mut acc = if from > lo {
            self.cumulative[from - 1]
        } else {
            0.0
        };
        for i in from..hi {
            acc += self.weights[i];
            self.cumulative[i] = acc;
        }
        (1e-100..=1e100).contains(&acc)
    }

    /// The running effect histogram `p`.
    pub fn effect_model(&self) -> &EffectModel {
        &self.model
    }
}

impl Learner for E3d {
    fn name(&self) -> &str {
        "e3d"
    }

    fn propose(&mut self, rng: &mut dyn Rng, command: &mut Command) {
        let n = self.offsets.len() - 1;
        command.symbols.resize(n, 0);
        for slot in 0..n {
            let cum = &self.cumulative[self.offsets[slot]..self.offsets[slot + 1]];
            let (last, below) = cum.split_last().expect("alphabets are not empty");
            // the first symbol whose running sum exceeds u: branch-free, as
            // the draw is unpredictable by nature
            let u = rng.random::<f64>() * last;
            let pick: usize = below.iter().map(|&c| usize::from(c <= u)).sum();
            command.symbols[slot] = pick as u8;
        }
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        let e = outcome.effect;
        self.model.observe(e);
        let surprise = self.model.log_prob(e) - self.log_target[e];
        let decay = 1.0 - self.alpha * self.lambda;
        let drive = self.alpha * self.lambda * outcome.reward - self.alpha / self.beta * surprise;
        for (slot, &a) in command.symbols.iter().enumerate() {
            let i = self.offsets[slot] + a as usize;
            self.q[i] = decay * self.q[i] + drive;
            self.weights[i] = (self.beta * self.q[i] - self.shift[slot]).exp();
            if !self.accumulate(slot, i) {
                self.reshift(slot);
            }
        }
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        let (lo, hi) = (self.offsets[slot], self.offsets[slot + 1]);
        let total = self.cumulative[hi - 1];
        Some(self.weights[lo..hi].iter().map(|v| v / total).collect())
    }
}
