use super::softmax::SoftmaxSlots;
use super::state::tables::{model_tables, no_table, set_model_table, StateTable};
use super::state::{check_model, sizes_of, LearnerState, StateShape};
use super::{Learner, LearnerError, ParamError, Params};
use crate::command::{Command, CommandSpace};
use crate::effect::{log_floored, EffectModel, Target};
use crate::rng::SessionRng;
use crate::world::Outcome;
use serde::{Deserialize, Serialize};

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
