//! E3D's state from outside: reading and writing Q, the policy and the
//! effect model, and saving and loading the whole learner bit for bit
//! ([`LearnerState`]).

use super::{has_avx2, E3d, Slot, SlotTables, Tables};
use crate::effect::EffectModel;
use crate::learner::state::tables::{
    log_target_of, model_of, no_table, q_of_policy, slot_rows, target_of, StateTable,
};
use crate::learner::state::{
    check_target, LearnerState, StateField, StateReader, StateShape, StateWriter,
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

impl<const W: usize> SlotTables<W> {
    fn put(&self, w: &mut StateWriter) {
        for s in &self.slots {
            for v in s.q.iter().chain(&s.weights).chain(&s.cumulative) {
                w.put(v);
            }
            w.put(&s.shift);
        }
    }

    fn get(r: &mut StateReader<'_>, slots: usize) -> Result<Self, LearnerError> {
        let array = |r: &mut StateReader<'_>| -> Result<[f64; W], LearnerError> {
            let mut a = [0.0; W];
            for v in &mut a {
                *v = r.get()?;
            }
            Ok(a)
        };
        let mut out = Vec::with_capacity(slots.min(4096));
        for _ in 0..slots {
            let q = array(r)?;
            crate::learner::state::check_finite(r, "q", &q)?;
            out.push(Slot {
                q,
                weights: array(r)?,
                cumulative: array(r)?,
                shift: r.get()?,
            });
        }
        Ok(SlotTables { slots: out })
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
    /// `q`, `policy` (writing it sets Q to `log(policy) / beta`), `p` and
    /// `target`, all writable.
    fn tables(&self) -> Vec<StateTable> {
        vec![
            StateTable::slots("q", true, &self.sizes, |s| self.q(s).to_vec()),
            StateTable::slots("policy", true, &self.sizes, |s| self.policy(s)),
            StateTable::vector("p", true, self.model.probs()),
            StateTable::vector("target", true, target_of(&self.log_target)),
        ]
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        let rows: Vec<Vec<f64>> = match name {
            "p" => {
                self.model = model_of(values, &self.model)?;
                return Ok(());
            }
            "target" => {
                self.log_target = log_target_of(values, self.model.num_effects())?;
                return Ok(());
            }
            "q" => slot_rows(name, values, &self.sizes, false)?
                .into_iter()
                .map(<[f64]>::to_vec)
                .collect(),
            "policy" => slot_rows(name, values, &self.sizes, true)?
                .into_iter()
                .map(|r| q_of_policy(r, self.beta))
                .collect(),
            _ => return Err(no_table(Self::KIND, name, &self.tables())),
        };
        for (s, r) in rows.iter().enumerate() {
            self.set_q(s, r)?;
        }
        Ok(())
    }
}

impl StateField for E3d {
    fn put(&self, w: &mut StateWriter) {
        w.put(&self.alpha_lambda).put(&self.decay);
        w.put(&self.alpha_over_beta).put(&self.beta);
        w.put(&self.sizes);
        let width = with_tables!(&self.slots, t => t.width());
        w.put(&width);
        with_tables!(&self.slots, t => t.put(w));
        w.put(&self.model).put(&self.log_target);
    }

    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let rates: [f64; 4] = [r.get()?, r.get()?, r.get()?, r.get()?];
        crate::learner::state::check_rates(
            r,
            &[
                ("alpha lambda", rates[0]),
                ("1 - alpha lambda", rates[1]),
                ("alpha / beta", rates[2]),
            ],
            rates[3],
        )?;
        let sizes: Vec<usize> = r.get()?;
        let width: usize = r.get()?;
        r.check(
            !sizes.is_empty()
                && matches!(width, 4 | 8 | 16 | 64)
                && sizes.iter().all(|&k| k > 0 && k <= width),
            || format!("alphabet sizes {sizes:?} in tables of width {width}"),
        )?;
        let n = sizes.len();
        let slots = match width {
            4 => Tables::W4(SlotTables::get(r, n)?),
            8 => Tables::W8(SlotTables::get(r, n)?),
            16 => Tables::W16(SlotTables::get(r, n)?),
            _ => Tables::W64(SlotTables::get(r, n)?),
        };
        let model: EffectModel = r.get()?;
        let log_target: Vec<f64> = r.get()?;
        check_target(r, &log_target, &model)?;
        Ok(E3d {
            slots,
            sizes,
            model,
            log_target,
            alpha_lambda: rates[0],
            decay: rates[1],
            alpha_over_beta: rates[2],
            beta: rates[3],
            avx2: has_avx2(),
        })
    }
}
