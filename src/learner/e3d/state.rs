//! E3D's state from outside: reading and writing Q, the policy and the
//! effect model, and saving and loading the whole learner bit for bit
//! ([`LearnerState`]).

use super::{E3d, Tables};
use crate::effect::EffectModel;
use crate::learner::state::tables::{model_tables, no_table, q_rows, set_model_table, StateTable};
use crate::learner::state::{
    check_finite, check_model, check_rates, ensure, LearnerState, StateShape,
};
use crate::learner::LearnerError;

impl E3d {
    /// `Q[:, slot]`.
    pub fn q(&self, slot: usize) -> &[f64] {
        let k = self.sizes[slot];
        with_tables!(&self.slots, t => t.q(slot, k))
    }

    /// The running effect histogram `p`.
    pub fn effect_model(&self) -> &EffectModel {
        &self.model
    }

    /// The number of slots.
    pub fn num_slots(&self) -> usize {
        self.sizes.len()
    }

    /// The inverse temperature `beta`.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// The policy of `slot`: `softmax(beta Q[:, slot])`, the probability
    /// of each of its symbols.
    pub fn policy(&self, slot: usize) -> Vec<f64> {
        let k = self.sizes[slot];
        with_tables!(&self.slots, t => t.policy(slot, k))
    }

    /// Replaces `Q[:, slot]` by `q` (one finite value per symbol of the
    /// slot), with the slot's softmax weights recomputed; the policy of
    /// the slot becomes `softmax(beta q)`.
    ///
    /// ```
    /// use e3d::{Params, Target};
    /// use e3d::command::CommandSpace;
    /// use e3d::learner::E3d;
    /// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
    /// let mut l = E3d::new(&space, 3, &Params::TASK1, &Target::Uniform).unwrap();
    /// l.set_q(1, &[0.0, 2f64.ln()]).unwrap(); // beta = 1
    /// assert!((l.policy(1)[1] - 2.0 / 3.0).abs() < 1e-15);
    /// assert!(l.set_q(1, &[0.0]).is_err() && l.set_q(2, &[0.0, 0.0]).is_err());
    /// ```
    pub fn set_q(&mut self, slot: usize, q: &[f64]) -> Result<(), LearnerError> {
        let Some(&k) = self.sizes.get(slot) else {
            return Err(LearnerError::State(format!(
                "slot {slot}: the learner has {} slots",
                self.sizes.len()
            )));
        };
        if q.len() != k {
            return Err(LearnerError::State(format!(
                "Q of slot {slot}: {} values given, the slot has {k} symbols",
                q.len()
            )));
        }
        if let Some(v) = q.iter().find(|v| !v.is_finite()) {
            return Err(LearnerError::State(format!(
                "Q of slot {slot}: {v} is not a finite number"
            )));
        }
        let beta = self.beta;
        with_tables!(&mut self.slots, t => {
            t.slots[slot].q[..k].copy_from_slice(q);
            t.reshift(slot, k, beta);
        });
        Ok(())
    }

    /// Replaces the running effect histogram `p` by `probs` (one weight
    /// >= 0 per effect, summing to 1 within 1e-9).
    pub fn set_effect_model(&mut self, probs: &[f64]) -> Result<(), LearnerError> {
        self.model = EffectModel::from_probs(probs, self.model.eta())
            .map_err(|e| LearnerError::State(format!("effect model: {e}")))?;
        Ok(())
    }
}

/// A table of `W` floats saved as a sequence (`serde` has no arrays of
/// 64).
pub(super) mod array {
    use serde::{de::Error, Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer, const W: usize>(a: &[f64; W], s: S) -> Result<S::Ok, S::Error> {
        a[..].serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>, const W: usize>(
        d: D,
    ) -> Result<[f64; W], D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        let n = v.len();
        v.try_into()
            .map_err(|_| D::Error::invalid_length(n, &"the width of the tables"))
    }
}

/// The whole state, every table entry, the effect histogram, the target
/// and the rates, bit for bit: a learner read back proposes and learns
/// exactly as this one would (the same draws from the same generator, the
/// same bits of Q).
///
/// ```
/// use e3d::{Params, Target};
/// use e3d::command::CommandSpace;
/// use e3d::learner::{E3d, LearnerState};
/// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
/// let l = E3d::new(&space, 3, &Params::TASK1, &Target::Uniform).unwrap();
/// let saved = l.to_bytes();
/// assert_eq!(E3d::from_bytes(&saved).unwrap().to_bytes(), saved);
/// assert!(E3d::from_bytes(&saved[..saved.len() - 1]).is_err());
/// ```
impl LearnerState for E3d {
    const KIND: &'static str = "e3d";
    fn shape(&self) -> StateShape {
        StateShape::of(self.sizes.clone(), Some(self.model.num_effects()))
    }
    fn validate(&self) -> Result<(), String> {
        check_rates(
            &[
                ("alpha lambda", self.alpha_lambda),
                ("1 - alpha lambda", self.decay),
                ("alpha / beta", self.alpha_over_beta),
            ],
            self.beta,
        )?;
        let (sizes, width) = (&self.sizes, with_tables!(&self.slots, t => t.width()));
        let slots = with_tables!(&self.slots, t => t.slots.len());
        ensure(
            !sizes.is_empty() && slots == sizes.len() && sizes.iter().all(|&k| k > 0 && k <= width),
            || format!("alphabet sizes {sizes:?} in {slots} tables of width {width}"),
        )?;
        with_tables!(&self.slots, t => t.slots.iter().try_for_each(|s| check_finite("q", &s.q)))?;
        check_model(&self.model, &self.log_target)
    }
    /// `q`, `policy` (writing it sets Q to `log(policy) / beta`), `p` and
    /// `target`, all writable.
    fn tables(&self) -> Vec<StateTable> {
        let mut t = vec![
            StateTable::slots("q", true, &self.sizes, |s| self.q(s).to_vec()),
            StateTable::slots("policy", true, &self.sizes, |s| self.policy(s)),
        ];
        t.extend(model_tables(&self.model, &self.log_target));
        t
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        if set_model_table(name, values, &mut self.model, &mut self.log_target)? {
            return Ok(());
        }
        let Some(rows) = q_rows(name, values, &self.sizes, self.beta)? else {
            return Err(no_table(Self::KIND, name, &self.tables()));
        };
        for (s, r) in rows.iter().enumerate() {
            self.set_q(s, r)?;
        }
        Ok(())
    }
}
