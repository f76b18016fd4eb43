use super::exp::{exp_lane, exp_lanes, exp_lanes_in, Splats, LANES, SPLATS};
use super::{Learner, LearnerError, Params};
use crate::command::{Command, CommandSpace};
use crate::effect::{log_floored, EffectModel, Target};
use crate::rng::SessionRng;
use crate::world::Outcome;
use rand::RngExt;
use serde::{Deserialize, Serialize};

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
/// Cost: a trial changes one entry of `Q` per slot, so the learner keeps
/// each slot's softmax weights `exp(beta Q - shift)` and their running sums
/// in a table of fixed width (4, 8, 16 or 64; padding weighs 0), updates
/// one weight per slot with a portable vectorised `exp` (`learner/exp.rs`:
/// the same bits on every machine, with or without AVX2), and re-shifts a
/// slot only when its total leaves `[1e-100, 1e100]`. Nothing is allocated
/// per trial.
///
/// `learn` takes a command of the learner's space (debug builds check it;
/// in release, a symbol outside its alphabet updates another entry).
///
/// ```
/// use e3d::{Command, Learner, Outcome, Params, Target};
/// use e3d::command::CommandSpace;
/// use e3d::learner::E3d;
/// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
/// let mut l = E3d::new(&space, 3, &Params::TASK1, &Target::Uniform).unwrap();
/// let c = Command::new(vec![0, 1]);
/// l.learn(&c, &Outcome { effect: 2, reward: 0.0, point: [0.0, 0.0] });
/// // p(2) rose above 1/3, so the symbols that led there lost value
/// assert!(l.q(0)[0] < 0.0 && l.q(1)[1] < 0.0);
/// assert_eq!(l.q(0)[1], 0.0);
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct E3d {
    slots: Tables,
    /// Per slot: its alphabet size.
    sizes: Vec<usize>,
    model: EffectModel,
    log_target: Vec<f64>,
    /// `alpha lambda`, `1 - alpha lambda` and `alpha / beta`, computed once
    /// (the same operations as in the update, so the same bits).
    alpha_lambda: f64,
    decay: f64,
    alpha_over_beta: f64,
    beta: f64,
    /// Whether `learn` and `propose` run their AVX2 builds (same results,
    /// fewer instructions); decided once, from the processor.
    #[serde(skip, default = "has_avx2")]
    avx2: bool,
}

/// One slot's tables, `W` entries (`W` >= the largest alphabet), kept
/// together so that a slot is one base address.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Slot<const W: usize> {
    /// `Q`.
    #[serde(with = "state::array")]
    q: [f64; W],
    /// `exp(beta Q - shift)` (0 on padding).
    #[serde(with = "state::array")]
    weights: [f64; W],
    /// Running sums of `weights`; the last entry is the slot's total.
    #[serde(with = "state::array")]
    cumulative: [f64; W],
    /// The shift of the slot's logits.
    shift: f64,
}

/// Every slot's tables.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct SlotTables<const W: usize> {
    slots: Vec<Slot<W>>,
}

/// A slot's weights are re-shifted when their total leaves this range.
const TOTAL_RANGE: std::ops::RangeInclusive<f64> = 1e-100..=1e100;

/// The slot tables at the smallest width that fits.
#[derive(Debug, Clone, Serialize, Deserialize)]
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
///
/// The sum starts at the first weight rather than at `0.0 + w[0]`: the
/// same bits, since no weight is `-0.0` (weights are `exp` values or the
/// padding's `+0.0`), the one value `0.0 +` changes.
#[inline(always)]
fn running_sums<const W: usize>(weights: &[f64; W], cumulative: &mut [f64; W]) -> f64 {
    let mut acc = weights[0];
    cumulative[0] = acc;
    for (c, &w) in cumulative[1..].iter_mut().zip(&weights[1..]) {
        acc += w;
        *c = acc;
    }
    acc
}

/// The table entry of symbol `a`: `a` itself for every symbol of the slot's
/// alphabet. Masked to the width rather than bounds-checked (one `and`
/// instead of a compare and a branch at each of the two uses per slot): a
/// symbol outside the alphabet is a caller's bug, caught by the debug
/// assertion of `E3d`'s [`Learner::learn`], and can never touch memory
/// outside the slot (a release build then updates a padding entry or
/// another symbol's).
#[inline(always)]
fn entry<const W: usize>(a: u8) -> usize {
    const { assert!(W.is_power_of_two()) };
    usize::from(a) & (W - 1)
}

/// `Q[a_i, i] <- decay Q[a_i, i] + drive` for at most [`LANES`] slots
/// (`slots` and `symbols` of the same length), with their new weights and
/// running sums; returns whether a new total is outside [`TOTAL_RANGE`]
/// (or NaN).
#[inline(always)]
fn update_lanes<const W: usize>(
    slots: &mut [Slot<W>],
    symbols: &[u8],
    (decay, drive, beta): (f64, f64, f64),
    splats: Option<&Splats>,
) -> bool {
    debug_assert!(slots.len() == symbols.len() && slots.len() <= LANES);
    // every touched entry's new Q and logit, then their weights in one
    // vectorised call (the slots are independent)
    let mut x = [0.0; LANES];
    let mut at = [0usize; LANES];
    for (((&a, s), xi), at) in symbols
        .iter()
        .zip(slots.iter_mut())
        .zip(&mut x)
        .zip(&mut at)
    {
        *at = entry::<W>(a);
        let q = &mut s.q[*at];
        *q = decay * *q + drive;
        *xi = beta * *q - s.shift;
    }
    let w = match splats {
        Some(k) => exp_lanes_in(&x, k),
        None => exp_lanes(&x),
    };
    // then each slot's running sums over the whole width: a trip count
    // that does not depend on the symbol drawn (the same bits as summing
    // from the changed symbol on)
    // (a fixed trip count with an early exit: unrolled)
    let mut totals = [1.0; LANES];
    let n = slots.len();
    for i in 0..LANES {
        if i == n {
            break;
        }
        let s = &mut slots[i];
        // `at[i]` is already masked; masking again (the same value) lets
        // the compiler see it is in bounds
        s.weights[at[i] & (W - 1)] = w[i];
        totals[i] = running_sums(&s.weights, &mut s.cumulative);
    }
    // the totals checked together: their smallest and largest (`minsd`,
    // `maxsd`), and their sum, NaN if any is (none is negative)
    let (mut small, mut large, mut sum) = (totals[0], totals[0], totals[0]);
    for &t in &totals[1..] {
        small = if small < t { small } else { t };
        large = if large > t { large } else { t };
        sum += t;
    }
    let (lo, hi) = (*TOTAL_RANGE.start(), *TOTAL_RANGE.end());
    !(small >= lo && large <= hi && !sum.is_nan())
}

impl<const W: usize> SlotTables<W> {
    fn new(sizes: &[usize]) -> Self {
        let slots = sizes
            .iter()
            .map(|&k| {
                let mut s = Slot {
                    q: [0.0; W],
                    weights: [0.0; W],
                    cumulative: [0.0; W],
                    shift: 0.0,
                };
                s.weights[..k].fill(1.0);
                running_sums(&s.weights, &mut s.cumulative);
                s
            })
            .collect();
        SlotTables { slots }
    }

    /// Draws each slot's symbol: the number of running sums at or below
    /// `u * total`. Padding sums equal the total, which `u * total` never
    /// reaches (`u < 1`), and a symbol of weight 0 is skipped.
    ///
    /// Not inlined: each width gets its own function, whose register saves
    /// are only those it needs.
    #[inline(never)]
    fn propose(&self, rng: &mut SessionRng, symbols: &mut [u8]) {
        self.propose_with(rng, symbols, Self::draw)
    }

    /// [`propose`](Self::propose) with AVX2, POPCNT and BMI2: each slot's
    /// count is a compare of 4 running sums at a time (`vcmppd`, the same
    /// `c <= u`, false with NaN as in [`draw`](Self::draw)), a mask and
    /// `popcnt`, and the generator's 128-bit products are `mulx` (no
    /// register moves); the same draws from the generator, so the same
    /// symbols and the same generator state.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,popcnt,bmi2")]
    #[inline(never)]
    fn propose_avx2(&self, rng: &mut SessionRng, symbols: &mut [u8]) {
        self.propose_with(rng, symbols, |r, cum| Self::draw_avx2(r, cum))
    }

    /// The loop over the slots of [`propose`](Self::propose), `draw` giving
    /// one slot's symbol.
    #[inline(always)]
    fn propose_with(
        &self,
        rng: &mut SessionRng,
        symbols: &mut [u8],
        draw: impl Fn(&mut SessionRng, &[f64; W]) -> u8,
    ) {
        let n = symbols.len().min(self.slots.len());
        let (symbols, slots) = (&mut symbols[..n], &self.slots[..n]);
        if n <= LANES {
            // at most 8 slots: a fixed trip count with an early exit, which
            // unrolls (no loop counter, no pointer increments); the
            // generator is a local copy, written back once
            let mut r = rng.clone();
            for i in 0..LANES {
                if i == n {
                    break;
                }
                symbols[i] = draw(&mut r, &slots[i].cumulative);
            }
            *rng = r;
        } else {
            for (sym, slot) in symbols.iter_mut().zip(slots) {
                *sym = draw(rng, &slot.cumulative);
            }
        }
    }

    /// One slot's symbol (see [`propose`](Self::propose)).
    #[inline(always)]
    fn draw(rng: &mut SessionRng, cum: &[f64; W]) -> u8 {
        let u = rng.random::<f64>() * cum[W - 1];
        let mut pick = 0u8;
        for &c in cum {
            pick += u8::from(c <= u);
        }
        pick
    }

    /// [`draw`](Self::draw) with AVX2: the running sums 4 at a time (every
    /// width is a multiple of 4). `u >= c` rather than `c <= u` (the same
    /// predicate, ordered: false with NaN) puts the sums in the memory
    /// operand of `vcmppd`, which saves their load.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,popcnt,bmi2")]
    #[inline]
    fn draw_avx2(rng: &mut SessionRng, cum: &[f64; W]) -> u8 {
        use std::arch::x86_64::{_mm256_cmp_pd, _mm256_loadu_pd, _mm256_movemask_pd};
        use std::arch::x86_64::{_mm256_set1_pd, _CMP_GE_OQ};
        const { assert!(W % 4 == 0 && W <= 64) };
        let u = _mm256_set1_pd(rng.random::<f64>() * cum[W - 1]);
        let mut below = 0u64;
        for (k, c) in cum.chunks_exact(4).enumerate() {
            // SAFETY: `c` is 4 `f64`s (an unaligned load)
            let c = unsafe { _mm256_loadu_pd(c.as_ptr()) };
            let m = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(u, c));
            below |= (m as u64) << (4 * k);
        }
        below.count_ones() as u8
    }

    /// `Q[a_i, i] <- decay Q[a_i, i] + drive` for each slot `i`, with the
    /// new weights and running sums; returns whether a slot's total left
    /// [`TOTAL_RANGE`] (see [`out_of_range`](Self::out_of_range)).
    #[inline(always)]
    fn update(&mut self, symbols: &[u8], c: (f64, f64, f64), splats: Option<&Splats>) -> bool {
        let n = symbols.len();
        let slots = &mut self.slots[..n];
        if n <= LANES {
            // one group: straight-line code
            update_lanes(slots, symbols, c, splats)
        } else {
            let mut bad = false;
            for (slots, symbols) in slots.chunks_mut(LANES).zip(symbols.chunks(LANES)) {
                bad |= update_lanes(slots, symbols, c, splats);
            }
            bad
        }
    }

    /// Whether `slot`'s total is outside [`TOTAL_RANGE`] (or NaN).
    fn out_of_range(&self, slot: usize) -> bool {
        !TOTAL_RANGE.contains(&self.slots[slot].cumulative[W - 1])
    }

    /// Recomputes a slot's weights with its largest logit as the shift.
    fn reshift(&mut self, slot: usize, k: usize, beta: f64) {
        let s = &mut self.slots[slot];
        let q = &s.q[..k];
        let top = q
            .iter()
            .map(|&q| beta * q)
            .fold(f64::NEG_INFINITY, f64::max);
        s.shift = top;
        for (w, &q) in s.weights.iter_mut().zip(q) {
            *w = exp_lane(beta * q - top);
        }
        running_sums(&s.weights, &mut s.cumulative);
    }

    fn width(&self) -> usize {
        W
    }

    fn q(&self, slot: usize, k: usize) -> &[f64] {
        &self.slots[slot].q[..k]
    }

    fn policy(&self, slot: usize, k: usize) -> Vec<f64> {
        let s = &self.slots[slot];
        let total = s.cumulative[W - 1];
        s.weights[..k].iter().map(|v| v / total).collect()
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
    ) -> Result<Self, LearnerError> {
        params.validate()?;
        let sizes: Vec<usize> = space.sizes().collect();
        let slots = match sizes.iter().copied().max().unwrap_or(0) {
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
            alpha_lambda: params.alpha * params.lambda,
            decay: 1.0 - params.alpha * params.lambda,
            alpha_over_beta: params.alpha / params.beta,
            beta: params.beta,
            avx2: has_avx2(),
        })
    }

    /// The update of [`Learner::learn`]; `splats`: where `exp` takes its
    /// constants from, if from memory (see [`exp_lanes_in`]).
    #[inline(always)]
    fn learn_inline(&mut self, command: &Command, outcome: &Outcome, splats: Option<&Splats>) {
        let e = outcome.effect;
        let p = self.model.observe(e);
        let surprise = log_floored(p) - self.log_target[e];
        let drive = self.alpha_lambda * outcome.reward - self.alpha_over_beta * surprise;
        let (decay, beta, sizes) = (self.decay, self.beta, &self.sizes);
        with_tables!(&mut self.slots, t => {
            if t.update(&command.symbols, (decay, drive, beta), splats) {
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
        self.learn_inline(command, outcome, Some(std::hint::black_box(&SPLATS)))
    }

    /// [`learn_inline`](Self::learn_inline) for the baseline instruction
    /// set; a function of its own, so that [`Learner::learn`] is a test and
    /// a jump (its register saves and stack frame are not paid on the AVX2
    /// path).
    #[inline(never)]
    fn learn_baseline(&mut self, command: &Command, outcome: &Outcome) {
        self.learn_inline(command, outcome, None)
    }
}

/// `symbols.resize(n, 0)`, for [`E3d::propose`]'s first call.
#[cold]
#[inline(never)]
fn resize_cold(symbols: &mut Vec<u8>, n: usize) {
    symbols.resize(n, 0);
}

/// Whether this processor runs AVX2, with POPCNT and BMI2 (see [`E3d`];
/// every processor with AVX2 has the other two, but they are not implied).
fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("popcnt")
            && std::arch::is_x86_feature_detected!("bmi2")
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
        if command.symbols.len() != self.sizes.len() {
            // out of line: the usual call (a command reused from trial to
            // trial) then needs no register saves
            resize_cold(&mut command.symbols, self.sizes.len());
        }
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is true only where the processor has AVX2,
            // POPCNT and BMI2
            with_tables!(&self.slots, t => unsafe { t.propose_avx2(rng, &mut command.symbols) });
            return;
        }
        with_tables!(&self.slots, t => t.propose(rng, &mut command.symbols))
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        debug_assert!(
            command.symbols.len() == self.sizes.len()
                && command
                    .symbols
                    .iter()
                    .zip(&self.sizes)
                    .all(|(&a, &k)| usize::from(a) < k),
            "learn: command {:?} is not in the command space (alphabet sizes {:?})",
            command.symbols,
            self.sizes
        );
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is true only where the processor has AVX2
            unsafe { self.learn_avx2(command, outcome) };
            return;
        }
        self.learn_baseline(command, outcome)
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        let k = self.sizes[slot];
        Some(with_tables!(&self.slots, t => t.policy(slot, k)))
    }
}

// after `with_tables!`, which it uses
mod state;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::learner::LearnerState;
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

    /// The slot tables (one group of 8 or chunks, the unrolled draws, `exp`
    /// from memory or not, the totals checked together) against a plain,
    /// slot-by-slot transcription: the same draws and the same bits.
    fn tables_match_the_plain_update<const W: usize>(sizes: &[usize], splats: Option<&Splats>) {
        let mut t = SlotTables::<W>::new(sizes);
        let mut plain = t.clone();
        let mut rng = SessionRng::seed_from_u64(9);
        let mut rng_plain = rng.clone();
        let mut symbols = vec![0u8; sizes.len()];
        for trial in 0..4000 {
            t.propose(&mut rng, &mut symbols);
            // plain: one slot after the other
            let drawn: Vec<u8> = plain
                .slots
                .iter()
                .map(|s| {
                    let u = rng_plain.random::<f64>() * s.cumulative[W - 1];
                    s.cumulative.iter().filter(|&&c| c <= u).count() as u8
                })
                .collect();
            assert_eq!(symbols, drawn, "trial {trial}");
            let drive = ((trial * 7919) % 101) as f64 / 50.0 - 1.0;
            let (decay, beta) = (0.991, if trial % 2 == 0 { 1.0 } else { 100.0 });
            let bad = t.update(&symbols, (decay, drive, beta), splats);
            let mut bad_plain = false;
            for (s, &a) in plain.slots.iter_mut().zip(&symbols) {
                let a = a as usize;
                s.q[a] = decay * s.q[a] + drive;
                s.weights[a] = exp_lane(beta * s.q[a] - s.shift);
                let mut acc = 0.0;
                for (c, &w) in s.cumulative.iter_mut().zip(&s.weights) {
                    acc += w;
                    *c = acc;
                }
                bad_plain |= !TOTAL_RANGE.contains(&acc);
            }
            assert_eq!(bad, bad_plain, "trial {trial}");
            for (slot, &k) in sizes.iter().enumerate() {
                if t.out_of_range(slot) {
                    t.reshift(slot, k, beta);
                    plain.reshift(slot, k, beta);
                }
            }
            for (a, b) in t.slots.iter().zip(&plain.slots) {
                let bits = |s: &Slot<W>| {
                    let mut v: Vec<u64> = s.q.iter().map(|x| x.to_bits()).collect();
                    v.extend(s.weights.iter().map(|x| x.to_bits()));
                    v.extend(s.cumulative.iter().map(|x| x.to_bits()));
                    v.push(s.shift.to_bits());
                    v
                };
                assert_eq!(bits(a), bits(b), "trial {trial}");
            }
        }
        assert_eq!(rng, rng_plain);
    }

    #[test]
    fn a_saved_state_goes_on_bit_for_bit() {
        for sizes in [&[4usize; 7][..], &[3, 9, 2], &[40, 5]] {
            let alphabet = |k: usize| {
                (0..k)
                    .map(|i| char::from_u32(0x100 + i as u32).unwrap())
                    .collect()
            };
            let space = CommandSpace::new(sizes.iter().map(|&k| alphabet(k)).collect()).unwrap();
            let mut l = E3d::new(&space, 11, &Params::TASK1, &Target::Uniform).unwrap();
            let mut rng = SessionRng::seed_from_u64(3);
            let mut c = space.first();
            let mut run = |l: &mut E3d, rng: &mut SessionRng, n: usize| {
                for _ in 0..n {
                    l.propose(rng, &mut c);
                    let sum: usize = c.symbols.iter().map(|&s| s as usize * 5 + 2).sum();
                    let o = Outcome {
                        effect: sum % 11,
                        reward: 0.0,
                        point: [0.0, 0.0],
                    };
                    l.learn(&c, &o);
                }
            };
            run(&mut l, &mut rng, 3000);
            let saved = l.to_bytes();
            let mut back = E3d::from_bytes(&saved).unwrap();
            assert_eq!(back.to_bytes(), saved);
            let mut rng2 = rng.clone();
            run(&mut l, &mut rng, 2000);
            run(&mut back, &mut rng2, 2000);
            assert_eq!(back.to_bytes(), l.to_bytes());
            assert_eq!(rng, rng2);
            assert!(E3d::from_bytes(&saved[..saved.len() - 1]).is_err());
        }
    }

    #[test]
    fn slot_tables_give_the_bits_of_a_plain_transcription() {
        let k = std::hint::black_box(&SPLATS);
        for splats in [None, Some(k)] {
            tables_match_the_plain_update::<4>(&[4; 7], splats);
            tables_match_the_plain_update::<4>(&[4, 2, 3, 4, 1, 4, 4, 3, 2, 4, 4], splats);
            tables_match_the_plain_update::<4>(&[3], splats);
            tables_match_the_plain_update::<8>(&[8, 5, 7, 8, 6, 8, 8, 2], splats);
            tables_match_the_plain_update::<16>(&[9, 16, 12], splats);
        }
    }

    /// Random-ish slot tables of width `W` for `sizes`: weights of 0 (and
    /// padding; all 0 too, a total of 0), tiny and huge ones, totals at
    /// both ends of [`TOTAL_RANGE`], and a slot whose total is NaN.
    fn odd_tables<const W: usize>(sizes: &[usize], seed: u64) -> SlotTables<W> {
        let mut t = SlotTables::<W>::new(sizes);
        let mut r = SessionRng::seed_from_u64(seed);
        for (i, (s, &k)) in t.slots.iter_mut().zip(sizes).enumerate() {
            for w in &mut s.weights[..k] {
                *w = match r.random_range(0..6) {
                    0 => 0.0,
                    1 => r.random::<f64>() * 1e-300,
                    2 => r.random::<f64>() * 1e300,
                    _ => r.random::<f64>(),
                };
            }
            let total = running_sums(&s.weights, &mut s.cumulative);
            // scale some slots' totals to the ends of the range
            let scale = match i % 4 {
                1 if total > 0.0 => *TOTAL_RANGE.start() / total,
                2 if total > 0.0 => *TOTAL_RANGE.end() / total,
                _ => 1.0,
            };
            for w in &mut s.weights[..k] {
                *w *= scale;
            }
            if i == 5 {
                s.weights[0] = f64::NAN;
            }
            running_sums(&s.weights, &mut s.cumulative);
        }
        t
    }

    /// `propose_avx2` against the portable `propose`: the same symbols and
    /// the same generator state after each call.
    fn avx2_draws_match<const W: usize>() {
        for n in [1, 3, 7, 8, 11] {
            for seed in 0..20 {
                let sizes: Vec<usize> = (0..n).map(|i| 1 + (i * 5 + seed) % W).collect();
                let t = odd_tables::<W>(&sizes, seed as u64);
                let mut rng = SessionRng::seed_from_u64(seed as u64 + 100);
                let mut rng_avx2 = rng.clone();
                let (mut a, mut b) = (vec![0u8; n], vec![0u8; n]);
                for call in 0..200 {
                    t.propose(&mut rng, &mut a);
                    // SAFETY: the caller checked `has_avx2`
                    unsafe { t.propose_avx2(&mut rng_avx2, &mut b) };
                    assert_eq!(a, b, "W {W}, {n} slots, seed {seed}, call {call}");
                    assert_eq!(rng, rng_avx2);
                }
            }
        }
    }

    #[test]
    fn the_avx2_draws_are_the_portable_ones() {
        if !has_avx2() {
            return;
        }
        avx2_draws_match::<4>();
        avx2_draws_match::<8>();
        avx2_draws_match::<16>();
        avx2_draws_match::<64>();
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

    /// A symbol outside its slot's alphabet is caught in debug builds (a
    /// release build masks it to the table's width, see `entry`).
    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "is not in the command space")]
    fn learn_rejects_a_symbol_outside_the_alphabet() {
        let space = CommandSpace::repeat(2, &['a', 'b', 'c']).unwrap();
        let mut l = E3d::new(&space, 3, &Params::TASK1, &Target::Uniform).unwrap();
        let o = Outcome {
            effect: 0,
            reward: 0.0,
            point: [0.0, 0.0],
        };
        l.learn(&Command::new(vec![0, 3]), &o);
    }
}
