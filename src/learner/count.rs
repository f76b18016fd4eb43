use super::softmax::SoftmaxSlots;
use super::state::tables::{counts_of, no_table, StateTable};
use super::state::{ensure, sizes_of, LearnerState, StateShape};
use super::{Learner, LearnerError, Params};
use crate::command::{Command, CommandSpace};
use crate::rng::SessionRng;
use crate::world::Outcome;
use serde::{Deserialize, Serialize};

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
