use super::exp::{exp_lane, exp_lanes, LANES};
use super::{Learner, Params};
use crate::command::{Command, CommandSpace};
use crate::effect::{log_floored, EffectModel, Target};
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
/// and updates one weight per slot per trial; the shift `m_slot` is reset
/// to the slot's largest logit only when the sum leaves `[1e-100, 1e100]`.
/// The slots' new weights are computed together, 8
/// exponentials at once by a portable, vectorised `exp` (`learner/exp.rs`:
/// the same bits on every machine; AVX2 is used where the processor has
/// it, with the same results). Each slot's table has a fixed width (4, 8,
/// 16 or 64, the smallest that holds the largest alphabet; padding has
/// weight 0), so that sampling counts the running sums below a uniform draw
/// over the whole width (no branch to mispredict) and the running sums are
/// recomputed over a fixed length. The histogram update is O(1)
/// ([`EffectModel`]); nothing is allocated per trial.
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
    slots: Tables,
    /// Per slot: its alphabet size.
    sizes: Vec<usize>,
    model: EffectModel,
    log_target: Vec<f64>,
    alpha: f64,
    beta: f64,
    lambda: f64,
    /// Whether `learn` runs its AVX2 build (same results, fewer
    /// instructions); decided once, from the processor.
    avx2: bool,
}

/// Every slot's tables, `W` entries per slot (`W` >= the largest alphabet).
#[derive(Debug, Clone)]
struct SlotTables<const W: usize> {
    /// `Q`.
    q: Vec<[f64; W]>,
    /// `exp(beta Q - shift[slot])` (0 on padding).
    weights: Vec<[f64; W]>,
    /// Running sums of `weights`; the last entry is the slot's total.
    cumulative: Vec<[f64; W]>,
    /// The shift of each slot's logits.
    shift: Vec<f64>,
}

/// A slot's weights are re-shifted when their total leaves this range.
const TOTAL_RANGE: std::ops::RangeInclusive<f64> = 1e-100..=1e100;

/// The slot tables at the smallest width that fits.
#[derive(Debug, Clone)]
enum Tables {
    W4(SlotTables<4>),
    W8(SlotTables<8>),
    W16(SlotTables<16>),
    W64(SlotTables<64>),
}

/// Runs `$body` with `$t` bound to the slot tables, whatever their width.
macro_rules! with_tables {
    ($tables:expr, $t:ident => $body:expr) => {
        match $tables {
            Tables::W4($t) => $body,
            Tables::W8($t) => $body,
            Tables::W16($t) => $body,
            Tables::W64($t) => $body,
        }
    };
}

/// A slot's running sums of `weights`, in symbol order; returns the total.
#[inline(always)]
fn running_sums<const W: usize>(weights: &[f64; W], cumulative: &mut [f64; W]) -> f64 {
    let mut acc = 0.0;
    for (c, &w) in cumulative.iter_mut().zip(weights) {
        acc += w;
        *c = acc;
    }
    acc
}

impl<const W: usize> SlotTables<W> {
    fn new(sizes: &[usize]) -> Self {
        let mut weights = vec![[0.0; W]; sizes.len()];
        let mut cumulative = vec![[0.0; W]; sizes.len()];
        for ((w, c), &k) in weights.iter_mut().zip(&mut cumulative).zip(sizes) {
            w[..k].fill(1.0);
            running_sums(w, c);
        }
        SlotTables {
            q: vec![[0.0; W]; sizes.len()],
            weights,
            cumulative,
            shift: vec![0.0; sizes.len()],
        }
    }

    /// Draws each slot's symbol: the number of running sums at or below
    /// `u * total`. Padding sums equal the total, which `u * total` never
    /// reaches (`u < 1`), and a symbol of weight 0 is skipped.
    #[inline(always)]
    fn propose(&self, rng: &mut SessionRng, symbols: &mut [u8]) {
        for (sym, cum) in symbols.iter_mut().zip(&self.cumulative) {
            let u = rng.random::<f64>() * cum[W - 1];
            let mut pick = 0u8;
            for &c in cum {
                pick += u8::from(c <= u);
            }
            *sym = pick;
        }
    }

    /// `Q[a_i, i] <- decay Q[a_i, i] + drive` for each slot `i`, with the
    /// new weights and running sums; returns whether a slot's total left
    /// [`TOTAL_RANGE`] (see [`out_of_range`](Self::out_of_range)).
    #[inline(always)]
    fn update(&mut self, symbols: &[u8], decay: f64, drive: f64, beta: f64) -> bool {
        // the smallest and largest totals, kept in registers (a NaN total
        // makes them NaN, which is out of range too)
        let (mut lo, mut hi) = (1.0f64, 1.0f64);
        for (chunk, symbols) in symbols.chunks(LANES).enumerate() {
            let first = chunk * LANES;
            let n = symbols.len();
            // every touched entry's new Q and logit, then their weights in
            // one vectorised call (the slots are independent)
            let mut x = [0.0; LANES];
            for (((&a, q), &m), xi) in symbols
                .iter()
                .zip(&mut self.q[first..first + n])
                .zip(&self.shift[first..first + n])
                .zip(&mut x)
            {
                let q = &mut q[a as usize];
                *q = decay * *q + drive;
                *xi = beta * *q - m;
            }
            let w = exp_lanes(&x);
            // then each slot's running sums over the whole width: a trip
            // count that does not depend on the symbol drawn (the same
            // bits as summing from the changed symbol on)
            for (((&a, &wi), weights), cum) in symbols
                .iter()
                .zip(&w)
                .zip(&mut self.weights[first..first + n])
                .zip(&mut self.cumulative[first..first + n])
            {
                weights[a as usize] = wi;
                let total = running_sums(weights, cum);
                lo = if total >= lo { lo } else { total };
                hi = if total <= hi { hi } else { total };
            }
        }
        !(TOTAL_RANGE.contains(&lo) && TOTAL_RANGE.contains(&hi))
    }

    /// Whether `slot`'s total is outside [`TOTAL_RANGE`] (or NaN).
    fn out_of_range(&self, slot: usize) -> bool {
        !TOTAL_RANGE.contains(&self.cumulative[slot][W - 1])
    }

    /// Recomputes a slot's weights with its largest logit as the shift.
    fn reshift(&mut self, slot: usize, k: usize, beta: f64) {
        let q = &self.q[slot][..k];
        let top = q
            .iter()
            .map(|&q| beta * q)
            .fold(f64::NEG_INFINITY, f64::max);
        self.shift[slot] = top;
        for (w, &q) in self.weights[slot].iter_mut().zip(q) {
            *w = exp_lane(beta * q - top);
        }
        running_sums(&self.weights[slot], &mut self.cumulative[slot]);
    }

    fn policy(&self, slot: usize, k: usize) -> Vec<f64> {
        let total = self.cumulative[slot][W - 1];
        self.weights[slot][..k].iter().map(|v| v / total).collect()
    }
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
        let sizes: Vec<usize> = space.sizes().collect();
        let slots = match space.max_alphabet() {
            0..=4 => Tables::W4(SlotTables::new(&sizes)),
            5..=8 => Tables::W8(SlotTables::new(&sizes)),
            9..=16 => Tables::W16(SlotTables::new(&sizes)),
            _ => Tables::W64(SlotTables::new(&sizes)),
        };
        Ok(E3d {
            slots,
            sizes,
            model: EffectModel::new(num_effects, params.eta)?,
            log_target: target.log_probs(num_effects)?,
            alpha: params.alpha,
            beta: params.beta,
            lambda: params.lambda,
            avx2: has_avx2(),
        })
    }

    /// `Q[:, slot]`.
    pub fn q(&self, slot: usize) -> &[f64] {
        let k = self.sizes[slot];
        with_tables!(&self.slots, t => &t.q[slot][..k])
    }

    /// The running effect histogram `p`.
    pub fn effect_model(&self) -> &EffectModel {
        &self.model
    }

    #[inline(always)]
    fn learn_inline(&mut self, command: &Command, outcome: &Outcome) {
        let e = outcome.effect;
        let p = self.model.observe(e);
        let surprise = log_floored(p) - self.log_target[e];
        let decay = 1.0 - self.alpha * self.lambda;
        let drive = self.alpha * self.lambda * outcome.reward - self.alpha / self.beta * surprise;
        let (beta, sizes) = (self.beta, &self.sizes);
        with_tables!(&mut self.slots, t => {
            if t.update(&command.symbols, decay, drive, beta) {
                for (slot, &k) in sizes.iter().enumerate() {
                    if t.out_of_range(slot) {
                        t.reshift(slot, k, beta);
                    }
                }
            }
        })
    }

    /// [`learn_inline`](Self::learn_inline) compiled for AVX2: wider
    /// vectors, the same IEEE operations, so the same bits.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn learn_avx2(&mut self, command: &Command, outcome: &Outcome) {
        self.learn_inline(command, outcome)
    }
}

/// Whether this processor runs AVX2 (see [`E3d`]).
fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

impl Learner for E3d {
    fn name(&self) -> &str {
        "e3d"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        command.symbols.resize(self.sizes.len(), 0);
        with_tables!(&self.slots, t => t.propose(rng, &mut command.symbols))
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is true only where the processor has AVX2
            unsafe { self.learn_avx2(command, outcome) };
            return;
        }
        self.learn_inline(command, outcome)
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        let k = self.sizes[slot];
        Some(with_tables!(&self.slots, t => t.policy(slot, k)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// Runs a session of `trials` on a made-up world and returns Q's bits.
    fn q_bits(sizes: &[usize], avx2: bool, params: &Params, trials: usize) -> Vec<u64> {
        let alphabet = |k: u32| (0..k).map(|i| char::from_u32(0x100 + i).unwrap()).collect();
        let space = CommandSpace::new(sizes.iter().map(|&k| alphabet(k as u32)).collect()).unwrap();
        let mut l = E3d::new(&space, 11, params, &Target::Uniform).unwrap();
        l.avx2 = avx2;
        let mut rng = SessionRng::seed_from_u64(5);
        let mut c = space.first();
        for _ in 0..trials {
            l.propose(&mut rng, &mut c);
            let sum: usize = c.symbols.iter().map(|&s| s as usize * 3 + 1).sum();
            let o = Outcome {
                effect: sum % 11,
                reward: f64::from(u8::from(sum % 7 == 0)),
                point: [0.0, 0.0],
            };
            l.learn(&c, &o);
        }
        (0..sizes.len())
            .flat_map(|s| l.q(s).iter().map(|v| v.to_bits()).collect::<Vec<_>>())
            .collect()
    }

    #[test]
    fn the_avx2_build_gives_the_same_bits() {
        if !has_avx2() {
            return;
        }
        // widths 4, 8, 16 and 64; more slots than lanes; both tasks
        for sizes in [
            &[4usize; 7][..],
            &[3, 5, 2, 7, 8, 1, 6, 4, 3][..],
            &[10, 2][..],
            &[9, 9, 9][..],
            &[40, 17, 3][..],
        ] {
            for params in [Params::TASK1, Params::TASK2] {
                let a = q_bits(sizes, false, &params, 3000);
                let b = q_bits(sizes, true, &params, 3000);
                assert_eq!(a, b, "{sizes:?}");
                assert!(a.iter().any(|&v| v != 0));
            }
        }
    }
}
