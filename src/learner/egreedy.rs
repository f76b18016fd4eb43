use super::drives::check_offsets;
use super::state::tables::{no_table, slot_rows, StateTable};
use super::state::{sizes_of, LearnerState, StateShape};
use super::{slot_offsets, Learner, LearnerError, Params};
use crate::command::{Command, CommandSpace};
use crate::rng::SessionRng;
use crate::world::Outcome;
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// Epsilon-greedy, per slot and off-policy: with probability `epsilon` a
/// slot's symbol is drawn uniformly, otherwise it is the argmax of
/// `Q[:, slot]`, ties broken at random. After each trial
/// `Q[a_i, i] <- (1 - alpha) Q[a_i, i] + alpha r`.
///
/// Ties are broken at random on purpose: taking the first maximal symbol
/// would start the greedy policy on `EEEEEEE`, next to the goal of
/// `two_rooms`, and flatter the baseline.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EpsilonGreedy {
    q: Vec<f64>,
    offsets: Vec<usize>,
    alpha: f64,
    epsilon: f64,
}

impl EpsilonGreedy {
    /// A fresh learner (Q = 0) with `params.alpha` and `params.epsilon`.
    pub fn new(space: &CommandSpace, params: &Params) -> Self {
        let offsets = slot_offsets(space);
        EpsilonGreedy {
            q: vec![0.0; *offsets.last().unwrap_or(&0)],
            offsets,
            alpha: params.alpha,
            epsilon: params.epsilon,
        }
    }

    /// `Q[:, slot]`.
    pub fn q(&self, slot: usize) -> &[f64] {
        &self.q[self.offsets[slot]..self.offsets[slot + 1]]
    }
}

/// The index of a largest value of `q`, ties broken uniformly at random
/// (one `random_range` over the ties).
pub(crate) fn random_argmax(q: &[f64], rng: &mut SessionRng) -> usize {
    let best = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let ties = q.iter().filter(|&&v| v == best).count();
    let pick = rng.random_range(0..ties);
    let mut best_ones = q.iter().enumerate().filter(|(_, &v)| v == best);
    best_ones.nth(pick).map_or(0, |(i, _)| i)
}

impl Learner for EpsilonGreedy {
    fn name(&self) -> &str {
        "egreedy"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        let n = self.offsets.len() - 1;
        command.symbols.resize(n, 0);
        for slot in 0..n {
            let q = &self.q[self.offsets[slot]..self.offsets[slot + 1]];
            let explore: f64 = rng.random();
            command.symbols[slot] = if explore < self.epsilon {
                rng.random_range(0..q.len()) as u8
            } else {
                random_argmax(q, rng) as u8
            };
        }
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        for (slot, &a) in command.symbols.iter().enumerate() {
            let q = &mut self.q[self.offsets[slot] + a as usize];
            *q = (1.0 - self.alpha) * *q + self.alpha * outcome.reward;
        }
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        let q = self.q(slot);
        let k = q.len() as f64;
        let best = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let ties = q.iter().filter(|&&v| v == best).count() as f64;
        Some(
            q.iter()
                .map(|&v| {
                    self.epsilon / k
                        + if v == best {
                            (1.0 - self.epsilon) / ties
                        } else {
                            0.0
                        }
                })
                .collect(),
        )
    }
}

impl LearnerState for EpsilonGreedy {
    const KIND: &'static str = "egreedy";
    fn shape(&self) -> StateShape {
        StateShape::of(sizes_of(&self.offsets), None)
    }
    fn validate(&self) -> Result<(), String> {
        check_offsets(&self.offsets, self.q.len())
    }
    /// `q` (writable) and the `policy` it implies (read-only: the
    /// probability of each symbol, epsilon spread over the slot).
    fn tables(&self) -> Vec<StateTable> {
        let sizes = sizes_of(&self.offsets);
        vec![
            StateTable::slots("q", true, &sizes, |s| self.q(s).to_vec()),
            StateTable::slots("policy", false, &sizes, |s| {
                self.slot_policy(s).unwrap_or_default()
            }),
        ]
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        if name != "q" {
            return Err(no_table(Self::KIND, name, &self.tables()));
        }
        self.q = slot_rows(name, values, &sizes_of(&self.offsets), false)?.concat();
        Ok(())
    }
}
