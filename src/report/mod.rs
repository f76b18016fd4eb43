//! Reports: what the experiments ([`experiment`](crate::experiment)) and
//! runs produced, drawn as tables, SVG figures and HTML pages; nothing here
//! runs a session. Also the statistics they print: [`describe`],
//! [`median`], [`mean_ci95`] (Student's t), [`wilson95`] (a share of
//! sessions), [`quartiles`] and [`order_quartiles`] (skewed counts).
//! `paper` and `sweep_plot` draw with plotters (feature `plots`, on by
//! default); the other figures write their SVG themselves.

pub mod closed_loop;
pub mod drives;
pub mod html;
pub mod motion_svg;
#[cfg(feature = "plots")]
pub mod paper;
pub mod run_scene;
pub mod scene_svg;
mod svg;
#[cfg(feature = "plots")]
pub mod sweep_plot;

/// Mean, sample standard deviation, minimum and maximum of `xs`.
pub fn describe(xs: &[f64]) -> Stats {
    let n = xs.len() as f64;
    if xs.is_empty() {
        return Stats::default();
    }
    let mean = xs.iter().sum::<f64>() / n;
    let var = if xs.len() > 1 {
        xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    Stats {
        mean,
        sd: var.sqrt(),
        min: xs.iter().copied().fold(f64::INFINITY, f64::min),
        max: xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    }
}

/// The median of `xs` (mean of the two middle values for an even count),
/// `None` for no value.
pub fn median(xs: &[f64]) -> Option<f64> {
    if xs.is_empty() {
        return None;
    }
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    })
}

/// Summary statistics of a sample.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (n - 1).
    pub sd: f64,
    /// Minimum.
    pub min: f64,
    /// Maximum.
    pub max: f64,
}

/// The 97.5% quantile of Student's t with `df` degrees of freedom (the
/// half-width factor of a two-sided 95% interval; the one used by every
/// interval e3d prints: `compare`, `closed-loop`, `run`, a sweep's
/// `summary.csv`): tabulated to 9 digits up to 30, then the
/// Cornish-Fisher expansion in `1/df` around the normal's 1.959964
/// (within 1e-7 from 31 on). `df = 0` has no interval: infinity.
///
/// ```
/// use e3d::report::t_quantile_975;
/// assert!((t_quantile_975(1) - 12.706204736).abs() < 1e-9);
/// assert!((t_quantile_975(9) - 2.262157163).abs() < 1e-9);
/// assert!((t_quantile_975(99) - 1.98422).abs() < 1e-4);
/// assert!((t_quantile_975(1000) - 1.962339).abs() < 1e-6);
/// ```
pub fn t_quantile_975(df: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.706204736,
        4.302652730,
        3.182446305,
        2.776445105,
        2.570581836,
        2.446911851,
        2.364624252,
        2.306004135,
        2.262157163,
        2.228138852,
        2.200985160,
        2.178812830,
        2.160368656,
        2.144786688,
        2.131449546,
        2.119905299,
        2.109815578,
        2.100922040,
        2.093024054,
        2.085963447,
        2.079613845,
        2.073873068,
        2.068657610,
        2.063898562,
        2.059538553,
        2.055529439,
        2.051830516,
        2.048407142,
        2.045229642,
        2.042272456,
    ];
    if df == 0 {
        return f64::INFINITY;
    }
    match TABLE.get(df - 1) {
        Some(&t) => t,
        None => cornish_fisher_975(df),
    }
}

/// The 97.5% quantile of Student's t by the Cornish-Fisher expansion to
/// `1/df^4` around the normal's 1.959964 (within 1e-7 from `df = 31` on).
fn cornish_fisher_975(df: usize) -> f64 {
    let z: f64 = 1.959_963_984_540_054;
    let v = df as f64;
    let (z3, z5, z7, z9) = (z.powi(3), z.powi(5), z.powi(7), z.powi(9));
    z + (z3 + z) / (4.0 * v)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * v * v)
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * v.powi(3))
        + (79.0 * z9 + 776.0 * z7 + 1482.0 * z5 - 1920.0 * z3 - 945.0 * z) / (92160.0 * v.powi(4))
}

/// A mean and its two-sided 95% interval (Student's t on the sample
/// standard deviation: `mean ± t(n - 1) sd / sqrt n`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanCi {
    /// The mean.
    pub mean: f64,
    /// The half-width of the interval: `t_quantile_975(n - 1) * sd / sqrt(n)`.
    pub half: f64,
    /// The sample size.
    pub n: usize,
}

impl MeanCi {
    /// The lower end, `mean - half`.
    pub fn lo(&self) -> f64 {
        self.mean - self.half
    }
    /// The upper end, `mean + half`.
    pub fn hi(&self) -> f64 {
        self.mean + self.half
    }
}

/// `mean ± half`, both to the formatter's precision.
///
/// ```
/// let ci = e3d::report::mean_ci95(&[1.0, 2.0, 3.0, 4.0, 5.0]).unwrap();
/// assert_eq!(format!("{ci:.2}"), "3.00 ± 1.96");
/// ```
impl std::fmt::Display for MeanCi {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let d = f.precision().unwrap_or(4);
        write!(f, "{:.d$} ± {:.d$}", self.mean, self.half)
    }
}

/// A trial or episode number, or `never` (a first reward not reached).
pub fn or_never(at: Option<usize>) -> String {
    at.map_or("never".to_string(), |i| i.to_string())
}

/// The mean of `xs` with its 95% t interval; `None` for fewer than two
/// values (no interval).
///
/// ```
/// use e3d::report::mean_ci95;
/// // mean 3, sd sqrt(2.5), t(4) = 2.776445105: 3 ± 1.963
/// let ci = mean_ci95(&[1.0, 2.0, 3.0, 4.0, 5.0]).unwrap();
/// assert_eq!(ci.mean, 3.0);
/// assert!((ci.half - 2.776445105 * 2.5f64.sqrt() / 5f64.sqrt()).abs() < 1e-9);
/// assert_eq!(mean_ci95(&[1.0]), None);
/// ```
pub fn mean_ci95(xs: &[f64]) -> Option<MeanCi> {
    if xs.len() < 2 {
        return None;
    }
    let st = describe(xs);
    let n = xs.len();
    Some(MeanCi {
        mean: st.mean,
        half: t_quantile_975(n - 1) * st.sd / (n as f64).sqrt(),
        n,
    })
}

/// The Wilson score 95% interval `(lo, hi)` of a share of `k` successes in
/// `n` trials (z = 1.959964); `None` for `n = 0`. Unlike the normal
/// approximation it stays in [0, 1] and is not empty at 0 or `n`.
///
/// ```
/// use e3d::report::wilson95;
/// let (lo, hi) = wilson95(76, 100).unwrap();
/// assert!((lo - 0.6677).abs() < 1e-4 && (hi - 0.8331).abs() < 1e-4);
/// let (lo, hi) = wilson95(0, 20).unwrap();
/// assert!(lo.abs() < 1e-12);
/// assert!((hi - 0.1611).abs() < 1e-4);
/// ```
pub fn wilson95(k: usize, n: usize) -> Option<(f64, f64)> {
    if n == 0 {
        return None;
    }
    let z: f64 = 1.959_963_984_540_054;
    let (nf, p) = (n as f64, k as f64 / n as f64);
    let z2 = z * z;
    let centre = (p + z2 / (2.0 * nf)) / (1.0 + z2 / nf);
    let half = z * (p * (1.0 - p) / nf + z2 / (4.0 * nf * nf)).sqrt() / (1.0 + z2 / nf);
    Some(((centre - half).max(0.0), (centre + half).min(1.0)))
}

/// The quartiles `[q1, median, q3]` of `xs`, interpolated between order
/// statistics (position `(n - 1) p` of the sorted values: R's and numpy's
/// default, and the same median as [`median`]); `None` for no value.
///
/// ```
/// use e3d::report::quartiles;
/// assert_eq!(quartiles(&[4.0, 1.0, 3.0, 2.0]), Some([1.75, 2.5, 3.25]));
/// assert_eq!(quartiles(&[]), None);
/// ```
pub fn quartiles(xs: &[f64]) -> Option<[f64; 3]> {
    if xs.is_empty() {
        return None;
    }
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let at = |p: f64| {
        let h = (v.len() - 1) as f64 * p;
        let (i, f) = (h.floor() as usize, h - h.floor());
        if f == 0.0 {
            v[i]
        } else {
            v[i] + f * (v[i + 1] - v[i])
        }
    };
    Some([at(0.25), at(0.5), at(0.75)])
}

/// The quartiles of `n` sessions of which those in `done` (any order)
/// reached an event, at the given counts, and the others never did: each
/// is the order statistic at position `floor((n - 1) p)` of the sorted
/// counts, the sessions that never did counted as later than all (`None`
/// for such a quartile). `[q1, median, q3]`; the median is the one `e3d
/// closed-loop` prints.
///
/// ```
/// use e3d::report::order_quartiles;
/// // 5 sessions, 3 rewarded: positions 1, 2 and 3 of (10, 20, 30, never, never)
/// assert_eq!(order_quartiles(&[30, 10, 20], 5), [Some(20), Some(30), None]);
/// ```
pub fn order_quartiles(done: &[usize], n: usize) -> [Option<usize>; 3] {
    let mut v = done.to_vec();
    v.sort_unstable();
    let at = |p: usize| {
        let i = n.saturating_sub(1) * p / 4;
        v.get(i).copied()
    };
    [at(1), at(2), at(3)]
}
