use super::mutation::random_symbols;
use super::state::{ensure, LearnerState, StateShape};
use super::Learner;
use crate::command::{Command, CommandSpace};
use crate::rng::SessionRng;
use crate::world::Outcome;
use serde::{Deserialize, Serialize};

/// The uniform policy: every symbol of every slot equally likely, always.
/// The paper's baseline for task 1.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct UniformPolicy {
    sizes: Vec<usize>,
}

impl UniformPolicy {
    /// A uniform policy over `space`.
    pub fn new(space: &CommandSpace) -> Self {
        UniformPolicy {
            sizes: space.sizes().collect(),
        }
    }
}

impl Learner for UniformPolicy {
    fn name(&self) -> &str {
        "uniform"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        random_symbols(self.sizes.iter().copied(), rng, &mut command.symbols);
    }

    fn learn(&mut self, _command: &Command, _outcome: &Outcome) {}

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        let k = self.sizes[slot];
        Some(vec![1.0 / k as f64; k])
    }
}

impl LearnerState for UniformPolicy {
    const KIND: &'static str = "uniform";
    fn shape(&self) -> StateShape {
        StateShape::of(self.sizes.clone(), None)
    }
    fn validate(&self) -> Result<(), String> {
        let sizes = &self.sizes;
        ensure(
            !sizes.is_empty() && sizes.iter().all(|k| (1..=256).contains(k)),
            || format!("alphabet sizes {sizes:?}"),
        )
    }
}
