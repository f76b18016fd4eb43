//! The per-slot softmax policy shared by the drives beyond the paper
//! ([`RelaxedE3d`](super::RelaxedE3d), [`CountBonus`](super::CountBonus),
//! [`StateMarginalMatching`](super::StateMarginalMatching)): a table `Q`
//! per slot, each slot drawn independently from `softmax(beta Q[:, slot])`.
//!
//! Plain code (every weight recomputed at each draw): these learners are
//! for comparing drives, and cost about half a microsecond a trial on 7
//! slots of 4 symbols (E3D: 0.13 µs). [`E3d`](super::E3d) keeps its own, incremental tables.

use super::state::tables::{q_rows, StateTable};
use super::state::{check_finite, check_rates, ensure, sizes_of};
use super::{draw_weighted, slot_offsets, LearnerError, Params};
use crate::command::{Command, CommandSpace};
use crate::rng::SessionRng;
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
