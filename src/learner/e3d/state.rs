//! E3D's state from outside: reading and writing Q, the policy and the
//! effect model, and saving and loading the whole learner bit for bit.

use super::{has_avx2, E3d, Slot, SlotTables, Tables, STATE_MAGIC};
use crate::effect::EffectModel;
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
    /// use e3d::{CommandSpace, E3d, Params, Target};
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

    /// The learner's whole state as bytes: every table entry, the effect
    /// histogram, the target and the rates, bit for bit.
    /// [`from_bytes`](Self::from_bytes) reads it back as a learner that
    /// proposes and learns exactly as this one would (the same draws from
    /// the same generator, the same bits of Q).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(STATE_MAGIC);
        let put_u32 =
            |out: &mut Vec<u8>, v: usize| out.extend_from_slice(&(v as u32).to_le_bytes());
        let put_f64s = |out: &mut Vec<u8>, vs: &[f64]| {
            for v in vs {
                out.extend_from_slice(&v.to_bits().to_le_bytes());
            }
        };
        put_f64s(
            &mut out,
            &[
                self.alpha_lambda,
                self.decay,
                self.alpha_over_beta,
                self.beta,
            ],
        );
        put_u32(&mut out, self.sizes.len());
        for &k in &self.sizes {
            put_u32(&mut out, k);
        }
        let width = with_tables!(&self.slots, t => t.width());
        put_u32(&mut out, width);
        with_tables!(&self.slots, t => {
            for s in &t.slots {
                put_f64s(&mut out, &s.q);
                put_f64s(&mut out, &s.weights);
                put_f64s(&mut out, &s.cumulative);
                put_f64s(&mut out, &[s.shift]);
            }
        });
        let (q, scale, eta) = self.model.raw();
        put_u32(&mut out, q.len());
        put_f64s(&mut out, &[scale, eta]);
        put_f64s(&mut out, q);
        put_f64s(&mut out, &self.log_target);
        out
    }

    /// A learner from the bytes of [`to_bytes`](Self::to_bytes); an error
    /// saying what is wrong if they are not such bytes.
    pub fn from_bytes(bytes: &[u8]) -> Result<E3d, LearnerError> {
        let bad = |what: &str| LearnerError::State(format!("E3D state: {what}"));
        let mut r = bytes
            .strip_prefix(STATE_MAGIC)
            .ok_or_else(|| bad("not an E3D learner's state (no E3D state header)"))?;
        let mut take = |n: usize| -> Result<&[u8], LearnerError> {
            if r.len() < n {
                return Err(bad("the bytes end early"));
            }
            let (a, b) = r.split_at(n);
            r = b;
            Ok(a)
        };
        fn u32_of(b: &[u8]) -> usize {
            u32::from_le_bytes(b.try_into().expect("4 bytes")) as usize
        }
        fn f64s_of(b: &[u8]) -> Vec<f64> {
            b.chunks_exact(8)
                .map(|c| f64::from_bits(u64::from_le_bytes(c.try_into().expect("8 bytes"))))
                .collect()
        }
        let rates = f64s_of(take(32)?);
        let slots = u32_of(take(4)?);
        if slots == 0 || slots > 4096 {
            return Err(bad(&format!("{slots} slots")));
        }
        let mut sizes = Vec::with_capacity(slots);
        for _ in 0..slots {
            sizes.push(u32_of(take(4)?));
        }
        let width = u32_of(take(4)?);
        if !matches!(width, 4 | 8 | 16 | 64) || sizes.iter().any(|&k| k == 0 || k > width) {
            return Err(bad(&format!(
                "alphabet sizes {sizes:?} in tables of width {width}"
            )));
        }
        let mut raw = Vec::with_capacity(slots);
        for _ in 0..slots {
            raw.push(f64s_of(take((3 * width + 1) * 8)?));
        }
        fn fill<const W: usize>(raw: &[Vec<f64>]) -> SlotTables<W> {
            SlotTables {
                slots: raw
                    .iter()
                    .map(|v| Slot {
                        q: v[..W].try_into().expect("W values"),
                        weights: v[W..2 * W].try_into().expect("W values"),
                        cumulative: v[2 * W..3 * W].try_into().expect("W values"),
                        shift: v[3 * W],
                    })
                    .collect(),
            }
        }
        let tables = match width {
            4 => Tables::W4(fill(&raw)),
            8 => Tables::W8(fill(&raw)),
            16 => Tables::W16(fill(&raw)),
            _ => Tables::W64(fill(&raw)),
        };
        let n = u32_of(take(4)?);
        if n == 0 || n > (1 << 24) {
            return Err(bad(&format!("{n} effects")));
        }
        let model = f64s_of(take(16)?);
        let q = f64s_of(take(n * 8)?);
        let log_target = f64s_of(take(n * 8)?);
        if !r.is_empty() {
            return Err(bad(&format!("{} bytes after the state", r.len())));
        }
        let model = EffectModel::from_raw(q, model[0], model[1])
            .map_err(|e| bad(&format!("effect model: {e}")))?;
        Ok(E3d {
            slots: tables,
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
