//! Learners of continuous commands: a Gaussian E3D and the uniform sampler.

use super::mutation::{normal, random_values, to_unit};
use super::state::tables::{check_len, model_tables, no_table, set_model_table, StateTable};
use super::state::{check_model, check_values, ensure, LearnerState, StateShape};
use super::{ContinuousLearner, LearnerError, Params};
use crate::command::ValueSpace;
use crate::effect::{log_floored, EffectModel, Target};
use crate::rng::SessionRng;
use crate::world::Outcome;
use serde::{Deserialize, Serialize};

/// The standard deviation a [`GaussianE3d`] slot starts with, in the unit
/// coordinates of its range (`[-1, 1]`): `1 / sqrt(3)`, the uniform
/// sampler's.
pub const START_SD: f64 = 0.577_350_269_189_625_8;

/// The smallest and largest standard deviation of a slot, in unit
/// coordinates: a policy neither collapses onto one value (from which the
/// score would blow up) nor spreads far beyond its range.
pub const SD_RANGE: (f64, f64) = (0.02, 2.0);

/// How far outside its range a slot's mean may go, in unit coordinates
/// (`[-MEAN_BOUND, MEAN_BOUND]`): beyond the range, draws are clamped to its
/// ends, so a mean past 1.5 only makes the end value surer.
pub const MEAN_BOUND: f64 = 1.5;

/// The rate of the running baseline of the drive.
pub const BASELINE_RATE: f64 = 0.05;

/// The step of the policy is `POLICY_STEP x alpha` (a mean moves by at most
/// this times the advantage times the draw's distance from it).
pub const POLICY_STEP: f64 = 0.3;

/// E3D over continuous slots: a Gaussian policy per slot, updated by the
/// paper's intrinsic reward through the score function.
///
/// Each slot works in the unit coordinates of its range (`[-1, 1]`),
/// draws `x ~ N(mu, sigma^2)` and sends `clamp(x, -1, 1)`. After a trial,
/// `p` is updated as in E3D, the drive is `G = lambda r - (1 / beta) (log
/// p(e) - log p*(e))`, and with the advantage `A = G - b` over a running
/// baseline `b` each slot takes a natural-gradient REINFORCE step:
///
/// ```text
/// mu      <- mu      + 0.3 alpha A (x - mu)
/// log sig <- log sig + 0.3 alpha A ((x - mu)^2 / sig^2 - 1) / 2
/// ```
///
/// Derivation and bounds: docs/algorithms.md, "Gaussian E3D". `learn`
/// uses the draws of the last `propose` when given its values, else their
/// unit coordinates.
///
/// ```
/// use e3d::{ContinuousLearner, Outcome, Params, SessionRng, Target};
/// use e3d::command::ValueSpace;
/// use e3d::learner::GaussianE3d;
/// use rand::SeedableRng;
/// let space = ValueSpace::new(vec![(-1.8, 1.8); 2]).unwrap();
/// let mut l = GaussianE3d::new(&space, 4, &Params::TASK1, &Target::Uniform).unwrap();
/// let mut rng = SessionRng::seed_from_u64(1);
/// let mut v = Vec::new();
/// l.propose(&mut rng, &mut v);
/// assert!(v.iter().all(|x| (-1.8..=1.8).contains(x)));
/// assert_eq!(l.slot_gaussian(0), (0.0, 1.8 / 3f64.sqrt()));
/// l.learn(&v, &Outcome { effect: 1, reward: 0.0, point: [0.0, 0.0] });
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GaussianE3d {
    space: ValueSpace,
    mean: Vec<f64>,
    log_sd: Vec<f64>,
    /// The unclamped draws of the last proposal, and the values sent.
    draws: Vec<f64>,
    sent: Vec<f64>,
    model: EffectModel,
    log_target: Vec<f64>,
    baseline: f64,
    step: f64,
    lambda: f64,
    inv_beta: f64,
}

impl GaussianE3d {
    /// A fresh learner for `space`, `num_effects` effects, the
    /// hyper-parameters `params` (alpha, beta, lambda, eta) and the target
    /// `p*`.
    pub fn new(
        space: &ValueSpace,
        num_effects: usize,
        params: &Params,
        target: &Target,
    ) -> Result<Self, LearnerError> {
        params.validate()?;
        let n = space.num_slots();
        Ok(GaussianE3d {
            space: space.clone(),
            mean: vec![0.0; n],
            log_sd: vec![START_SD.ln(); n],
            draws: Vec::with_capacity(n),
            sent: Vec::with_capacity(n),
            model: EffectModel::new(num_effects, params.eta)?,
            log_target: target.log_probs(num_effects)?,
            baseline: 0.0,
            step: POLICY_STEP * params.alpha,
            lambda: params.lambda,
            inv_beta: 1.0 / params.beta,
        })
    }

    /// The running baseline `b` of the drive.
    pub fn baseline(&self) -> f64 {
        self.baseline
    }
}

impl ContinuousLearner for GaussianE3d {
    fn value_space(&self) -> Option<&ValueSpace> {
        Some(&self.space)
    }

    fn name(&self) -> &str {
        "e3d"
    }

    fn propose(&mut self, rng: &mut SessionRng, values: &mut Vec<f64>) {
        self.draws.clear();
        values.clear();
        for slot in 0..self.mean.len() {
            let x = self.mean[slot] + self.log_sd[slot].exp() * normal(rng);
            self.draws.push(x);
            values.push(self.space.from_unit(slot, x));
        }
        self.sent.clone_from(values);
    }

    fn learn(&mut self, values: &[f64], outcome: &Outcome) {
        if values != self.sent.as_slice() {
            // a command this learner did not propose: its unit coordinates
            self.draws.clear();
            let unit = values.iter().enumerate();
            self.draws
                .extend(unit.map(|(slot, &v)| to_unit(&self.space, slot, v)));
        }
        let e = outcome.effect;
        let p = self.model.observe(e);
        let drive =
            self.lambda * outcome.reward - self.inv_beta * (log_floored(p) - self.log_target[e]);
        let advantage = drive - self.baseline;
        self.baseline += BASELINE_RATE * (drive - self.baseline);
        let k = self.step * advantage;
        let (lo, hi) = (SD_RANGE.0.ln(), SD_RANGE.1.ln());
        for slot in 0..self.mean.len() {
            let sd = self.log_sd[slot].exp();
            let d = self.draws[slot] - self.mean[slot];
            let z2 = d * d / (sd * sd);
            self.mean[slot] = (self.mean[slot] + k * d).clamp(-MEAN_BOUND, MEAN_BOUND);
            self.log_sd[slot] = (self.log_sd[slot] + k * (z2 - 1.0) / 2.0).clamp(lo, hi);
        }
    }

    fn slot_gaussian(&self, slot: usize) -> (f64, f64) {
        let (lo, hi) = self.space.range(slot);
        let half = (hi - lo) / 2.0;
        (
            lo + (self.mean[slot] + 1.0) * half,
            self.log_sd[slot].exp() * half,
        )
    }
}

/// The uniform baseline of continuous commands: every slot's value drawn
/// uniformly in its range, independently; learns nothing.
///
/// ```
/// use e3d::{ContinuousLearner, SessionRng};
/// use e3d::command::ValueSpace;
/// use e3d::learner::UniformValues;
/// use rand::SeedableRng;
/// let space = ValueSpace::new(vec![(0.0, 2.0), (-1.0, 1.0)]).unwrap();
/// let mut l = UniformValues::new(&space);
/// let mut v = Vec::new();
/// l.propose(&mut SessionRng::seed_from_u64(0), &mut v);
/// assert!((0.0..2.0).contains(&v[0]) && (-1.0..1.0).contains(&v[1]));
/// assert_eq!(l.slot_gaussian(0), (1.0, 2.0 / 12f64.sqrt())); // its mean and sd
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct UniformValues {
    space: ValueSpace,
}

impl UniformValues {
    /// The sampler of `space`.
    pub fn new(space: &ValueSpace) -> Self {
        UniformValues {
            space: space.clone(),
        }
    }
}

impl ContinuousLearner for UniformValues {
    fn value_space(&self) -> Option<&ValueSpace> {
        Some(&self.space)
    }

    fn name(&self) -> &str {
        "uniform"
    }

    fn propose(&mut self, rng: &mut SessionRng, values: &mut Vec<f64>) {
        random_values(&self.space, rng, values);
    }

    fn learn(&mut self, _values: &[f64], _outcome: &Outcome) {}

    fn slot_gaussian(&self, slot: usize) -> (f64, f64) {
        let (lo, hi) = self.space.range(slot);
        ((lo + hi) / 2.0, (hi - lo) / 12f64.sqrt())
    }
}

impl LearnerState for GaussianE3d {
    const KIND: &'static str = "gaussian_e3d";
    fn shape(&self) -> StateShape {
        StateShape::of(
            vec![0; self.space.num_slots()],
            Some(self.model.num_effects()),
        )
    }
    fn validate(&self) -> Result<(), String> {
        check_values(&self.space)?;
        let n = self.space.num_slots();
        let fits = |v: &[f64]| v.is_empty() || v.len() == n;
        ensure(
            self.mean.len() == n && self.log_sd.len() == n && fits(&self.draws) && fits(&self.sent),
            || format!("a policy of other than {n} slots"),
        )?;
        check_model(&self.model, &self.log_target)
    }
    /// The policy's `mean` and standard deviation `sd` per slot (in the
    /// slot's unit coordinates, `[-1, 1]` mapped onto its range, as the
    /// policy draws them), `p` and `target`, writable; the drive's running `baseline` (shape `()`),
    /// read-only.
    fn tables(&self) -> Vec<StateTable> {
        let sd = self.log_sd.iter().map(|v| v.exp()).collect();
        let mut t = vec![
            StateTable::vector("mean", true, self.mean.clone()),
            StateTable::vector("sd", true, sd),
        ];
        t.extend(model_tables(&self.model, &self.log_target));
        let baseline = StateTable::vector("baseline", false, vec![self.baseline]);
        t.push(StateTable {
            shape: vec![],
            ..baseline
        });
        t
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        if set_model_table(name, values, &mut self.model, &mut self.log_target)? {
            return Ok(());
        }
        let positive = match name {
            "mean" => false,
            "sd" => true,
            _ => return Err(no_table(Self::KIND, name, &self.tables())),
        };
        check_len(name, values, self.space.num_slots())?;
        if let Some(v) = values
            .iter()
            .find(|v| !v.is_finite() || (positive && **v <= 0.0))
        {
            let expected = ["a finite number", "a finite number > 0"][usize::from(positive)];
            return Err(LearnerError::State(format!(
                "table `{name}`: {v} is not {expected}"
            )));
        }
        if positive {
            self.log_sd = values.iter().map(|v| v.ln()).collect();
        } else {
            self.mean = values.to_vec();
        }
        Ok(())
    }
}

impl LearnerState for UniformValues {
    const KIND: &'static str = "uniform_values";
    fn shape(&self) -> StateShape {
        StateShape::of(vec![0; self.space.num_slots()], None)
    }
    fn validate(&self) -> Result<(), String> {
        check_values(&self.space)
    }
}
