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
    weights: Vec<f64>,
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
            weights: vec![0.0; space.max_alphabet()],
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
            let q = &self.q[self.offsets[slot]..self.offsets[slot + 1]];
            let w = &mut self.weights[..q.len()];
            let top = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let mut z = 0.0;
            for (w, &v) in w.iter_mut().zip(q) {
                *w = (self.beta * (v - top)).exp();
                z += *w;
            }
            let mut u = rng.random::<f64>() * z;
            let mut pick = q.len() - 1;
            for (k, &wk) in w.iter().enumerate() {
                if u < wk {
                    pick = k;
                    break;
                }
                u -= wk;
            }
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
            let q = &mut self.q[self.offsets[slot] + a as usize];
            *q = decay * *q + drive;
        }
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        let q = self.q(slot);
        let top = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let w: Vec<f64> = q.iter().map(|&v| (self.beta * (v - top)).exp()).collect();
        let z: f64 = w.iter().sum();
        Some(w.into_iter().map(|v| v / z).collect())
    }
}
