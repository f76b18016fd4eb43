use super::{Learner, Params};
use crate::command::{Command, CommandSpace};
use crate::effect::{EffectModel, Target};
use crate::session::SessionRng;
use crate::world::Outcome;
use rand::RngExt;

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
/// softmax weights `exp(beta Q - m_slot)` and their running sums per slot,
/// and updates one weight per slot (one `exp`) per trial; the shift `m_slot`
/// is reset to the slot's largest logit only when the sum leaves
/// `[1e-100, 1e100]`. Sampling counts the running sums below a uniform draw
/// (no branch to mispredict). The histogram update is O(1)
/// ([`EffectModel`]). Tables have a fixed stride (the largest alphabet) so
/// that a slot is one slice; a shorter alphabet's padding has weight 0.
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
    /// `Q`, `stride` entries per slot.
    q: Vec<f64>,
    /// `exp(beta Q - shift[slot])`, laid out as `q` (0 on padding).
    weights: Vec<f64>,
    /// Running sums of `weights` within each slot, laid out as `q`; a
    /// slot's total is at its alphabet's last symbol.
    cumulative: Vec<f64>,
    /// Per slot: the shift of its logits.
    shift: Vec<f64>,
    /// Per slot: its alphabet size.
    sizes: Vec<usize>,
    stride: usize,
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
        let stride = space.max_alphabet();
        let sizes: Vec<usize> = space.sizes().collect();
        let total = stride * sizes.len();
        let mut weights = vec![0.0; total];
        let mut cumulative = vec![0.0; total];
        for (slot, &k) in sizes.iter().enumerate() {
            for a in 0..stride {
                weights[slot * stride + a] = if a < k { 1.0 } else { 0.0 };
                cumulative[slot * stride + a] = a.min(k - 1) as f64 + 1.0;
            }
        }
        Ok(E3d {
            q: vec![0.0; total],
            weights,
            cumulative,
            shift: vec![0.0; sizes.len()],
            sizes,
            stride,
            model: EffectModel::new(num_effects, params.eta)?,
            log_target: target.log_probs(num_effects)?,
            alpha: params.alpha,
            beta: params.beta,
            lambda: params.lambda,
        })
    }

    /// `Q[:, slot]`.
    pub fn q(&self, slot: usize) -> &[f64] {
        &self.q[slot * self.stride..slot * self.stride + self.sizes[slot]]
    }

    /// Recomputes a slot's weights with its largest logit as the shift.
    fn reshift(&mut self, slot: usize) {
        let (lo, k) = (slot * self.stride, self.sizes[slot]);
        let top = self.q[lo..lo + k]
            .iter()
            .map(|&q| self.beta * q)
            .fold(f64::NEG_INFINITY, f64::max);
        self.shift[slot] = top;
        for i in lo..lo + k {
            self.weights[i] = (self.beta * self.q[i] - top).exp();
        }
        let mut acc = 0.0;
        for i in lo..lo + self.stride {
            acc += self.weights[i];
            self.cumulative[i] = acc;
        }
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

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        let n = self.sizes.len();
        command.symbols.resize(n, 0);
        for ((sym, cum), &k) in command
            .symbols
            .iter_mut()
            .zip(self.cumulative.chunks_exact(self.stride))
            .zip(&self.sizes)
        {
            // the first symbol whose running sum exceeds u, counted without
            // branches: the draw is unpredictable by nature
            let u = rng.random::<f64>() * cum[k - 1];
            let pick: usize = cum[..k - 1].iter().map(|&c| usize::from(c <= u)).sum();
            *sym = pick as u8;
        }
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        let e = outcome.effect;
        self.model.observe(e);
        let surprise = self.model.log_prob(e) - self.log_target[e];
        let decay = 1.0 - self.alpha * self.lambda;
        let drive = self.alpha * self.lambda * outcome.reward - self.alpha / self.beta * surprise;
        let stride = self.stride;
        // first every slot's new Q and weight (independent: the exps overlap)
        for (slot, (&a, (q, w))) in command
            .symbols
            .iter()
            .zip(
                self.q
                    .chunks_exact_mut(stride)
                    .zip(self.weights.chunks_exact_mut(stride)),
            )
            .enumerate()
        {
            let a = a as usize;
            q[a] = decay * q[a] + drive;
            w[a] = (self.beta * q[a] - self.shift[slot]).exp();
        }
        // then the running sums from the changed symbol on
        let mut out_of_range = 0u64;
        for (slot, (&a, (w, cum))) in command
            .symbols
            .iter()
            .zip(
                self.weights
                    .chunks_exact(stride)
                    .zip(self.cumulative.chunks_exact_mut(stride)),
            )
            .enumerate()
        {
            let a = a as usize;
            let mut acc = if a > 0 { cum[a - 1] } else { 0.0 };
            for (c, &wk) in cum[a..].iter_mut().zip(&w[a..]) {
                acc += wk;
                *c = acc;
            }
            if !(1e-100..=1e100).contains(&acc) {
                out_of_range |= 1 << slot;
            }
        }
        while out_of_range != 0 {
            let slot = out_of_range.trailing_zeros() as usize;
            self.reshift(slot);
            out_of_range &= out_of_range - 1;
        }
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        let (lo, k) = (slot * self.stride, self.sizes[slot]);
        let total = self.cumulative[lo + k - 1];
        Some(self.weights[lo..lo + k].iter().map(|v| v / total).collect())
    }
}
