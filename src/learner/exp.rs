//! The exponential behind E3D's softmax weights: several lanes at once,
//! portable and bit-reproducible.
//!
//! `std`'s `f64::exp` calls the platform's libm, one value per call, and its
//! last bit may differ between libm versions (glibc even picks an FMA or a
//! non-FMA variant at run time). E3D needs one exponential per slot per
//! trial, all independent: [`exp_lanes`] computes [`LANES`] of them with
//! plain IEEE additions and multiplications only (no fused multiply-add, no
//! table, no branch), so the compiler vectorises it and every machine gets
//! the same bits, whatever its instruction set.
//!
//! Method: `x = k ln 2 + r` with `k = round(x / ln 2)` and `|r| <= ln 2 / 2`
//! (Cody-Waite, `ln 2` in two parts), `exp(r)` by its Taylor polynomial of
//! degree 12 (truncation below 2e-16 relative) evaluated by Estrin's scheme,
//! then `2^k` put in the exponent bits. The relative error is below 5e-16 (about 2 ulps)
//! on `[-708, 709]` (tested against `f64::exp`); inputs are clamped to that
//! range, so `exp_lane(-1000.0)` is about `3e-308` rather than 0, which no
//! softmax weight can tell apart. `exp_lane(0.0)` is exactly 1. NaN is not
//! supported (the learner's logits are finite).

/// The number of exponentials [`exp_lanes`] computes at once.
pub(crate) const LANES: usize = 8;

const LOG2_E: f64 = std::f64::consts::LOG2_E;
/// `ln 2` split so that `k * LN2_HI` is exact for `|k| < 2^20` (fdlibm).
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// `1.5 * 2^52`: adding it rounds to an integer held in the low bits.
const SHIFTER: f64 = 6_755_399_441_055_744.0;
const LO: f64 = -708.0;
const HI: f64 = 709.0;

/// `1 / n!` for `n = 2..=12`.
const C: [f64; 11] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
    1.0 / 40320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
];

/// `exp(x)` for one value; the same bits as a lane of [`exp_lanes`].
#[inline(always)]
pub(crate) fn exp_lane(x: f64) -> f64 {
    exp_with(x, LO, HI, LOG2_E, SHIFTER, LN2_HI, LN2_LO, 1.0, C)
}

/// The method, with its constants as arguments (so that [`exp_lanes_in`]
/// can take them from memory); the same operations whatever the source.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn exp_with(
    x: f64,
    lo: f64,
    hi: f64,
    log2_e: f64,
    shifter: f64,
    ln2_hi: f64,
    ln2_lo: f64,
    one: f64,
    c: [f64; 11],
) -> f64 {
    // clamp (as comparisons, so that it compiles to min/max)
    let x = if x < lo { lo } else { x };
    let x = if x > hi { hi } else { x };
    let t = x * log2_e + shifter;
    let kf = t - shifter;
    let k = (t.to_bits() as i64).wrapping_sub(SHIFTER.to_bits() as i64);
    let r = (x - kf * ln2_hi) - kf * ln2_lo;
    // Estrin: 1 + r + r^2 (c2 + c3 r) + ... + c12 r^12
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    let p01 = one + r;
    let p23 = c[0] + c[1] * r;
    let p45 = c[2] + c[3] * r;
    let p67 = c[4] + c[5] * r;
    let p89 = c[6] + c[7] * r;
    let p1011 = c[8] + c[9] * r;
    let q0 = p01 + p23 * r2;
    let q1 = p45 + p67 * r2;
    let q2 = p89 + p1011 * r2;
    let s0 = q0 + q1 * r4;
    let s1 = q2 + c[10] * r4;
    let p = s0 + s1 * r8;
    // 2^k, k in [-1021, 1023] after the clamp
    let scale = f64::from_bits(((k + 1023) as u64) << 52);
    p * scale
}

/// `exp` of each of `x`; a lane of the result has the same bits as
/// [`exp_lane`] of it.
#[inline(always)]
pub(crate) fn exp_lanes(x: &[f64; LANES]) -> [f64; LANES] {
    let mut out = [0.0; LANES];
    for (o, &v) in out.iter_mut().zip(x) {
        *o = exp_lane(v);
    }
    out
}

/// The constants of the method, [`LANES`] copies of each, for
/// [`exp_lanes_in`].
#[repr(C, align(64))]
pub(crate) struct Splats {
    lo: [f64; LANES],
    hi: [f64; LANES],
    log2_e: [f64; LANES],
    shifter: [f64; LANES],
    ln2_hi: [f64; LANES],
    ln2_lo: [f64; LANES],
    one: [f64; LANES],
    c: [[f64; LANES]; 11],
}

/// The one [`Splats`].
pub(crate) static SPLATS: Splats = {
    let mut c = [[0.0; LANES]; 11];
    let mut i = 0;
    while i < 11 {
        c[i] = [C[i]; LANES];
        i += 1;
    }
    Splats {
        lo: [LO; LANES],
        hi: [HI; LANES],
        log2_e: [LOG2_E; LANES],
        shifter: [SHIFTER; LANES],
        ln2_hi: [LN2_HI; LANES],
        ln2_lo: [LN2_LO; LANES],
        one: [1.0; LANES],
        c,
    }
};

/// [`exp_lanes`] with the constants read from `k` (pass
/// `std::hint::black_box(&SPLATS)`): with AVX2, whose broadcasts cannot be
/// folded into an arithmetic instruction, the compiler otherwise spends
/// one broadcast per constant per vector; from memory, each constant is an
/// operand of the instruction that uses it. The same bits as
/// [`exp_lanes`].
#[inline(always)]
pub(crate) fn exp_lanes_in(x: &[f64; LANES], k: &Splats) -> [f64; LANES] {
    let mut out = [0.0; LANES];
    for i in 0..LANES {
        out[i] = exp_with(
            x[i],
            k.lo[i],
            k.hi[i],
            k.log2_e[i],
            k.shifter[i],
            k.ln2_hi[i],
            k.ln2_lo[i],
            k.one[i],
            std::array::from_fn(|j| k.c[j][i]),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel_err(x: f64) -> f64 {
        let want = x.exp();
        (exp_lane(x) - want).abs() / want
    }

    #[test]
    fn matches_std_exp_to_a_few_ulps_over_the_whole_range() {
        let mut worst = (0.0f64, 0.0f64);
        let n = 2_000_000;
        for i in 0..=n {
            let x = LO + (HI - LO) * i as f64 / n as f64;
            let e = rel_err(x);
            if e > worst.0 {
                worst = (e, x);
            }
        }
        assert!(
            worst.0 < 5e-16,
            "relative error {:e} at {}",
            worst.0,
            worst.1
        );
        // near 0, where the softmax weights live
        for i in -100_000..=100_000 {
            let x = i as f64 * 1e-4;
            assert!(rel_err(x) < 5e-16, "{x}");
        }
    }

    #[test]
    fn exact_where_it_matters_and_clamped_outside() {
        assert_eq!(exp_lane(0.0), 1.0);
        assert_eq!(exp_lane(-0.0), 1.0);
        assert!(exp_lane(-1000.0) > 0.0 && exp_lane(-1000.0) < 1e-307);
        assert!(exp_lane(f64::NEG_INFINITY) < 1e-307);
        assert!(exp_lane(1000.0).is_finite() && exp_lane(1000.0) > 8e307);
        assert!((exp_lane(1.0) - std::f64::consts::E).abs() <= f64::EPSILON * 3.0);
    }

    #[test]
    fn lanes_from_memory_have_the_bits_of_the_scalar() {
        let k = std::hint::black_box(&SPLATS);
        let mut x = [0.0; LANES];
        for t in 0..10_000 {
            for (i, v) in x.iter_mut().enumerate() {
                *v = ((t * LANES + i) as f64 * 0.4321).sin() * 800.0;
            }
            let y = exp_lanes_in(&x, k);
            for i in 0..LANES {
                assert_eq!(y[i].to_bits(), exp_lane(x[i]).to_bits());
            }
        }
    }

    #[test]
    fn lanes_have_the_bits_of_the_scalar() {
        let mut x = [0.0; LANES];
        for t in 0..10_000 {
            for (i, v) in x.iter_mut().enumerate() {
                *v = ((t * LANES + i) as f64 * 0.7123).sin() * 700.0;
            }
            let y = exp_lanes(&x);
            for i in 0..LANES {
                assert_eq!(y[i].to_bits(), exp_lane(x[i]).to_bits());
            }
        }
    }
}
