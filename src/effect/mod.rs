//! Effects (integers in `0..num_effects`): the binning of terminal states
//! on an [`EffectGrid`] ([`Binning`]), the running effect model `p`
//! ([`EffectModel`]) and the target `p*` ([`Target`]).

use serde::{Deserialize, Serialize};

mod binning;

pub use binning::{wrap_angle, Axis, Binning, Feature};

/// The smallest probability used inside a logarithm: `log p` and `log p*`
/// are taken of `max(p, P_FLOOR)`, so that an effect never seen (or a target
/// of zero) gives a large but finite intrinsic reward.
pub const P_FLOOR: f64 = 1e-300;

/// A rectangular grid of cells over the plane, numbered `row * cols + col`
/// with row 0 at the top (largest y) and column 0 at the left.
///
/// ```
/// use e3d::effect::EffectGrid;
/// // arm7's grid: 15 x 15 cells of 0.25 m over [-1.875, 1.875]^2
/// let g = EffectGrid::new(15, 15, [-1.875, -1.875], [1.875, 1.875]).unwrap();
/// assert_eq!(g.effect_of([1.75, 0.0]), 119);
/// assert_eq!(g.cell_of([1.75, 0.0]), (7, 14));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectGrid {
    /// Number of rows (along y).
    pub rows: usize,
    /// Number of columns (along x).
    pub cols: usize,
    /// Lower-left corner `(x, y)` of the covered rectangle, in metres.
    pub min: [f64; 2],
    /// Upper-right corner `(x, y)` of the covered rectangle, in metres.
    pub max: [f64; 2],
}

/// The largest number of effects a scene may have.
pub const MAX_EFFECTS: usize = 1 << 20;

/// An effect grid ([`EffectGrid::new`], [`EffectGrid::validate`]) or an
/// effect model ([`EffectModel::new`]) that cannot be made.
///
/// ```
/// use e3d::effect::{EffectError, EffectGrid};
/// let e = EffectGrid::new(0, 6, [0.0, 0.0], [6.0, 3.0]).unwrap_err();
/// assert_eq!(e, EffectError::NoCells { rows: 0, cols: 6 });
/// assert_eq!(e.to_string(), "at least one cell, found 0 rows x 6 columns");
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EffectError {
    /// A grid without cells.
    #[error("at least one cell, found {rows} rows x {cols} columns")]
    NoCells {
        /// Rows asked for.
        rows: usize,
        /// Columns asked for.
        cols: usize,
    },
    /// A grid of more than [`MAX_EFFECTS`] cells.
    #[error("at most {MAX_EFFECTS} cells (effects), found {rows} x {cols}")]
    TooManyCells {
        /// Rows asked for.
        rows: usize,
        /// Columns asked for.
        cols: usize,
    },
    /// Corners that are not finite, or not `min < max` on both axes.
    #[error("finite corners with min < max, found min {min:?}, max {max:?}")]
    Corners {
        /// The lower-left corner given.
        min: [f64; 2],
        /// The upper-right corner given.
        max: [f64; 2],
    },
    /// Bins of an axis whose width overflows (a range from -1.7e308 to
    /// 1.7e308) or is too small to tell their edges apart (a range of
    /// 5e-324): see [`check_bins`].
    #[error("{0}")]
    Bins(String),
    /// An effect model over no effects.
    #[error("there must be at least one effect")]
    NoEffects,
    /// An effect model's rate outside (0, 1].
    #[error("eta must be in (0, 1], found {0}")]
    Eta(f64),
    /// Probabilities that are not weights >= 0 summing to 1
    /// ([`EffectModel::from_probs`]): their sum.
    #[error("finite weights >= 0 summing to 1, found a sum of {0}")]
    Probs(f64),
    /// A weight that is negative or not finite
    /// ([`EffectModel::from_probs`]): the effect and its weight.
    #[error("finite weights >= 0 summing to 1, found {value} for effect {effect}")]
    Weight {
        /// The effect whose weight is wrong.
        effect: usize,
        /// Its weight.
        value: f64,
    },
}

/// A [`Target`] that does not fit the effects.
///
/// ```
/// use e3d::effect::{Target, TargetError};
/// let e = Target::Weights(vec![1.0, 2.0]).probs(3).unwrap_err();
/// assert_eq!(e, TargetError::Length { weights: 2, effects: 3 });
/// assert_eq!(e.to_string(), "the target has 2 weights, expected one per effect (3)");
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TargetError {
    /// A target over no effects.
    #[error("there must be at least one effect")]
    NoEffects,
    /// Not one weight per effect.
    #[error("the target has {weights} weights, expected one per effect ({effects})")]
    Length {
        /// The weights given.
        weights: usize,
        /// The effects.
        effects: usize,
    },
    /// A weight that is negative or not finite.
    #[error("target weights must be finite and >= 0, found {0}")]
    Weight(f64),
    /// Weights whose sum is 0 or not finite.
    #[error("target weights must have a positive, finite sum")]
    Sum,
}

impl EffectGrid {
    /// A grid of `rows x cols` cells covering `[min, max]`.
    pub fn new(
        rows: usize,
        cols: usize,
        min: [f64; 2],
        max: [f64; 2],
    ) -> Result<Self, EffectError> {
        let g = EffectGrid {
            rows,
            cols,
            min,
            max,
        };
        g.validate()?;
        Ok(g)
    }

    /// Checks the grid: at least one cell, not more than [`MAX_EFFECTS`],
    /// finite corners with `min < max`.
    pub fn validate(&self) -> Result<(), EffectError> {
        let (rows, cols) = (self.rows, self.cols);
        if rows == 0 || cols == 0 {
            return Err(EffectError::NoCells { rows, cols });
        }
        if rows.saturating_mul(cols) > MAX_EFFECTS {
            return Err(EffectError::TooManyCells { rows, cols });
        }
        if !(self.min.iter().chain(&self.max).all(|v| v.is_finite())
            && self.min[0] < self.max[0]
            && self.min[1] < self.max[1])
        {
            return Err(EffectError::Corners {
                min: self.min,
                max: self.max,
            });
        }
        check_bins(cols, self.min[0], self.max[0])
            .map_err(|e| EffectError::Bins(format!("columns: {e}")))?;
        check_bins(rows, self.min[1], self.max[1])
            .map_err(|e| EffectError::Bins(format!("rows: {e}")))?;
        Ok(())
    }

    /// The number of cells (effects).
    pub fn num_cells(&self) -> usize {
        self.rows * self.cols
    }

    /// Cell width and height.
    pub fn cell_size(&self) -> [f64; 2] {
        [
            (self.max[0] - self.min[0]) / self.cols as f64,
            (self.max[1] - self.min[1]) / self.rows as f64,
        ]
    }

    /// The `(row, col)` of the cell holding `p`. Points outside the grid are
    /// clamped to the nearest border cell.
    pub fn cell_of(&self, p: [f64; 2]) -> (usize, usize) {
        let [w, h] = self.cell_size();
        let col = ((p[0] - self.min[0]) / w).floor();
        let row = ((self.max[1] - p[1]) / h).floor();
        let clamp = |v: f64, n: usize| {
            if v.is_nan() || v < 0.0 {
                0
            } else {
                (v as usize).min(n - 1)
            }
        };
        (clamp(row, self.rows), clamp(col, self.cols))
    }

    /// The effect index of the cell holding `p`.
    pub fn effect_of(&self, p: [f64; 2]) -> usize {
        let (r, c) = self.cell_of(p);
        r * self.cols + c
    }

    /// Whether `p` lies inside the covered rectangle.
    pub fn contains(&self, p: [f64; 2]) -> bool {
        p[0] >= self.min[0] && p[0] <= self.max[0] && p[1] >= self.min[1] && p[1] <= self.max[1]
    }

    /// The centre of cell `(row, col)`.
    pub fn center(&self, row: usize, col: usize) -> [f64; 2] {
        let [w, h] = self.cell_size();
        [
            self.min[0] + (col as f64 + 0.5) * w,
            self.max[1] - (row as f64 + 0.5) * h,
        ]
    }
}

/// The target distribution `p*` over effects.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Target {
    /// The same weight on every effect: explore everything.
    Uniform,
    /// Given weights, one per effect; normalised to sum 1. Zeros are allowed
    /// (an effect to avoid): its `log p*` is taken at [`P_FLOOR`].
    Weights(Vec<f64>),
}

impl Target {
    /// `log p*(e)` for every effect (taken at [`P_FLOOR`] for a weight
    /// of 0), checked against `num_effects` as [`probs`](Self::probs).
    pub fn log_probs(&self, num_effects: usize) -> Result<Vec<f64>, TargetError> {
        let p = self.probs(num_effects)?;
        Ok(match self {
            Target::Uniform => vec![-(num_effects as f64).ln(); num_effects],
            Target::Weights(_) => p.into_iter().map(log_floored).collect(),
        })
    }

    /// The target probabilities `p*(e)`, checked against `num_effects`:
    /// one finite weight >= 0 per effect, of a positive sum.
    pub fn probs(&self, num_effects: usize) -> Result<Vec<f64>, TargetError> {
        if num_effects == 0 {
            return Err(TargetError::NoEffects);
        }
        let Target::Weights(w) = self else {
            return Ok(vec![1.0 / num_effects as f64; num_effects]);
        };
        if w.len() != num_effects {
            return Err(TargetError::Length {
                weights: w.len(),
                effects: num_effects,
            });
        }
        if let Some(&bad) = w.iter().find(|v| !v.is_finite() || **v < 0.0) {
            return Err(TargetError::Weight(bad));
        }
        let sum: f64 = w.iter().sum();
        if sum <= 0.0 || !sum.is_finite() {
            return Err(TargetError::Sum);
        }
        Ok(w.iter().map(|v| v / sum).collect())
    }
}

/// `log p`, taken at [`P_FLOOR`] for a vanishing `p`.
#[inline]
pub(crate) fn log_floored(p: f64) -> f64 {
    p.max(P_FLOOR).ln()
}

/// The running effect histogram `p <- (1 - eta) p + eta onehot(e)`,
/// starting uniform.
///
/// The update is O(1): `p = scale * q`, so decaying every entry is one
/// multiplication of `scale`; `q` is rescaled (O(num_effects)) only when
/// `scale` falls below 1e-150, which keeps every value in range.
///
/// ```
/// use e3d::effect::EffectModel;
/// let mut p = EffectModel::new(4, 0.5).unwrap();
/// p.observe(2);
/// assert!((p.prob(2) - 0.625).abs() < 1e-15);
/// assert!((p.prob(0) - 0.125).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EffectModel {
    q: Vec<f64>,
    scale: f64,
    eta: f64,
}

impl EffectModel {
    /// A uniform histogram over `num_effects` effects with rate `eta` in (0, 1].
    pub fn new(num_effects: usize, eta: f64) -> Result<Self, EffectError> {
        if num_effects == 0 {
            return Err(EffectError::NoEffects);
        }
        if !(eta > 0.0 && eta <= 1.0) {
            return Err(EffectError::Eta(eta));
        }
        Ok(EffectModel {
            q: vec![1.0 / num_effects as f64; num_effects],
            scale: 1.0,
            eta,
        })
    }

    /// The number of effects.
    pub fn num_effects(&self) -> usize {
        self.q.len()
    }

    /// A histogram equal to `probs` (weights >= 0 summing to 1 within
    /// 1e-9, one per effect) with rate `eta`.
    ///
    /// ```
    /// use e3d::effect::EffectModel;
    /// let p = EffectModel::from_probs(&[0.25, 0.75], 0.1).unwrap();
    /// assert_eq!(p.probs(), [0.25, 0.75]);
    /// assert!(EffectModel::from_probs(&[0.5, 0.6], 0.1).is_err());
    /// let e = EffectModel::from_probs(&[-0.1, 1.1], 0.1).unwrap_err();
    /// assert_eq!(e.to_string(), "finite weights >= 0 summing to 1, found -0.1 for effect 0");
    /// ```
    pub fn from_probs(probs: &[f64], eta: f64) -> Result<Self, EffectError> {
        let mut m = EffectModel::new(probs.len(), eta)?;
        if let Some((effect, &value)) = probs
            .iter()
            .enumerate()
            .find(|(_, p)| !(p.is_finite() && **p >= 0.0))
        {
            return Err(EffectError::Weight { effect, value });
        }
        let total: f64 = probs.iter().sum();
        if (total - 1.0).abs() > 1e-9 {
            return Err(EffectError::Probs(total));
        }
        m.q.copy_from_slice(probs);
        Ok(m)
    }

    /// The raw state `(q, scale, eta)`, `p = scale * q` (for saving a
    /// learner bit for bit).
    pub(crate) fn raw(&self) -> (&[f64], f64, f64) {
        (&self.q, self.scale, self.eta)
    }

    /// A histogram from [`raw`](Self::raw)'s state, checked.
    pub(crate) fn from_raw(q: Vec<f64>, scale: f64, eta: f64) -> Result<Self, EffectError> {
        let mut m = EffectModel::new(q.len(), eta)?;
        if !(scale > 0.0 && scale <= 1.0) || q.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(EffectError::Probs(q.iter().sum::<f64>() * scale));
        }
        m.q = q;
        m.scale = scale;
        Ok(m)
    }

    /// The rate `eta`.
    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// Records an observed effect: `p <- (1 - eta) p + eta onehot(e)`;
    /// returns the new `p(e)` (the same bits as [`prob`](Self::prob), without
    /// reading it back from memory).
    #[inline]
    pub fn observe(&mut self, effect: usize) -> f64 {
        let keep = 1.0 - self.eta;
        if keep == 0.0 {
            // eta = 1: p becomes the one-hot of e.
            self.q.iter_mut().for_each(|v| *v = 0.0);
            self.q[effect] = 1.0;
            self.scale = 1.0;
            return 1.0;
        }
        self.scale *= keep;
        let v = self.q[effect] + self.eta / self.scale;
        self.q[effect] = v;
        if self.scale < 1e-150 {
            let s = self.scale;
            self.q.iter_mut().for_each(|v| *v *= s);
            self.scale = 1.0;
            return self.q[effect];
        }
        self.scale * v
    }

    /// `p(e)`.
    #[inline]
    pub fn prob(&self, effect: usize) -> f64 {
        self.scale * self.q[effect]
    }

    /// `log p(e)`, taken at [`P_FLOOR`] for a vanishing `p(e)`.
    #[inline]
    pub fn log_prob(&self, effect: usize) -> f64 {
        log_floored(self.prob(effect))
    }

    /// The whole distribution `p`.
    pub fn probs(&self) -> Vec<f64> {
        self.q.iter().map(|v| v * self.scale).collect()
    }
}

/// Shannon entropy (natural log) of a distribution given by counts or
/// weights; zeros contribute nothing.
pub fn entropy(weights: &[f64]) -> f64 {
    let total: f64 = weights.iter().sum();
    if total <= 0.0 {
        return 0.0;
    }
    let h = -weights
        .iter()
        .filter(|&&w| w > 0.0)
        .map(|&w| {
            let p = w / total;
            p * p.ln()
        })
        .sum::<f64>();
    // a single effect gives -0.0; report it as 0
    if h > 0.0 {
        h
    } else {
        0.0
    }
}

/// [`entropy`] divided by `log(cells)`: 1 when `weights` are spread
/// evenly over `cells` effects. With `cells` the reachable effects (an
/// [`OutcomeTable`](crate::OutcomeTable) knows them), this is the
/// entropy "over the reachable cells"; with every effect, the metric
/// sessions report.
///
/// ```
/// use e3d::effect::normalized_entropy_over;
/// // even over 2 of 4 cells: 0.5 over all 4, 1 over the 2 reachable
/// assert!((normalized_entropy_over(&[3.0, 3.0, 0.0, 0.0], 4) - 0.5).abs() < 1e-12);
/// assert!((normalized_entropy_over(&[3.0, 3.0, 0.0, 0.0], 2) - 1.0).abs() < 1e-12);
/// ```
pub fn normalized_entropy_over(weights: &[f64], cells: usize) -> f64 {
    let norm = (cells as f64).ln();
    entropy(weights) / if norm > 0.0 { norm } else { 1.0 }
}

/// `KL(q || p*)` of the distribution given by `weights` against the target
/// log-probabilities `log_target`.
pub fn kl_divergence(weights: &[f64], log_target: &[f64]) -> f64 {
    let total: f64 = weights.iter().sum();
    if total <= 0.0 {
        return 0.0;
    }
    weights
        .iter()
        .zip(log_target)
        .filter(|(&w, _)| w > 0.0)
        .map(|(&w, &lt)| {
            let q = w / total;
            q * (q.ln() - lt)
        })
        .sum()
}

/// Checks `n` equal bins over `[min, max]`, the one check of every binned
/// axis (an effect grid's rows and columns, a `Joint` or `Angle`
/// feature's `range`): finite ends with `min < max`, a finite width
/// `max - min` (`(-1.7e308, 1.7e308)` overflows to infinity), and bins
/// wide enough that their edges differ: each bin at least 2^-40 of the
/// ends' magnitude and a normal number (`(0, 5e-324)` over 3 bins made
/// bins of width 0). Returns a bin's width, or what was expected.
///
/// ```
/// use e3d::effect::check_bins;
/// assert_eq!(check_bins(4, 0.0, 2.0), Ok(0.5));
/// assert!(check_bins(3, -1.7e308, 1.7e308).unwrap_err().contains("finite width"));
/// assert!(check_bins(3, 0.0, 5e-324).unwrap_err().contains("too narrow"));
/// assert!(check_bins(0, 0.0, 1.0).is_err());
/// ```
pub fn check_bins(n: usize, min: f64, max: f64) -> Result<f64, String> {
    if n == 0 {
        return Err("at least one bin, found 0".into());
    }
    if !(min.is_finite() && max.is_finite() && min < max) {
        return Err(format!(
            "finite ends with min < max, found ({min:e}, {max:e})"
        ));
    }
    let width = max - min;
    if !width.is_finite() {
        return Err(format!(
            "a range of finite width (max - min), found ({min:e}, {max:e}), whose width overflows to infinity"
        ));
    }
    let bin = width / n as f64;
    let scale = min.abs().max(max.abs());
    if !(bin >= f64::MIN_POSITIVE && bin >= scale * (-40f64).exp2()) {
        return Err(format!(
            "bins wide enough to tell apart (each at least 2^-40 of the range's ends and 2.2e-308), found {n} bin(s) over ({min:e}, {max:e}): too narrow, each {bin:e} wide"
        ));
    }
    Ok(bin)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effect_model_matches_the_plain_update_over_many_steps() {
        let eta = 0.01;
        let mut m = EffectModel::new(5, eta).unwrap();
        let mut plain = [0.2; 5];
        for t in 0..100_000usize {
            let e = (t * 7 + t / 3) % 5;
            m.observe(e);
            for (i, v) in plain.iter_mut().enumerate() {
                *v = (1.0 - eta) * *v + if i == e { eta } else { 0.0 };
            }
        }
        for (i, want) in plain.iter().enumerate() {
            assert!((m.prob(i) - want).abs() < 1e-12, "{i}");
        }
        let sum: f64 = m.probs().iter().sum();
        assert!((sum - 1.0).abs() < 1e-12);
    }

    #[test]
    fn eta_one_gives_a_one_hot() {
        let mut m = EffectModel::new(3, 1.0).unwrap();
        m.observe(1);
        m.observe(2);
        assert_eq!(m.probs(), vec![0.0, 0.0, 1.0]);
        assert_eq!(m.log_prob(0), P_FLOOR.ln());
    }

    #[test]
    fn grid_bins_points_with_row_zero_at_the_top() {
        let g = EffectGrid::new(3, 6, [0.0, 0.0], [6.0, 3.0]).unwrap();
        assert_eq!(g.effect_of([0.5, 2.5]), 0);
        assert_eq!(g.effect_of([5.5, 0.5]), 17);
        assert_eq!(g.effect_of([-3.0, 10.0]), 0);
        assert_eq!(g.center(2, 5), [5.5, 0.5]);
        assert!(EffectGrid::new(0, 6, [0.0, 0.0], [6.0, 3.0]).is_err());
    }

    #[test]
    fn errors_are_typed() {
        assert_eq!(
            EffectGrid::new(1 << 11, 1 << 10, [0.0, 0.0], [6.0, 3.0]),
            Err(EffectError::TooManyCells {
                rows: 1 << 11,
                cols: 1 << 10
            })
        );
        let e = EffectGrid::new(3, 6, [0.0, f64::NAN], [6.0, 3.0]).unwrap_err();
        assert!(matches!(e, EffectError::Corners { .. }));
        assert_eq!(
            e.to_string(),
            "finite corners with min < max, found min [0.0, NaN], max [6.0, 3.0]"
        );
        assert_eq!(EffectModel::new(0, 0.5), Err(EffectError::NoEffects));
        assert_eq!(EffectModel::new(3, 0.0), Err(EffectError::Eta(0.0)));
        assert_eq!(
            EffectModel::new(3, 2.0).unwrap_err().to_string(),
            "eta must be in (0, 1], found 2"
        );
        assert_eq!(
            Target::Weights(vec![1.0, -2.0]).log_probs(2),
            Err(TargetError::Weight(-2.0))
        );
        assert_eq!(
            Target::Weights(vec![0.0, 0.0]).probs(2),
            Err(TargetError::Sum)
        );
    }

    #[test]
    fn a_single_point_bins_as_its_grid() {
        let g = EffectGrid::new(3, 6, [0.0, 0.0], [6.0, 3.0]).unwrap();
        let b = Binning::point(g.clone()).unwrap();
        for p in [[0.5, 2.5], [5.9, 0.1], [-1.0, 7.0], [3.0, 1.5]] {
            assert_eq!(b.locate(&p), (p, g.effect_of(p)));
        }
        assert_eq!(b.layout(), &g);
    }

    #[test]
    fn nested_products_are_blocks() {
        let obj = EffectGrid::new(2, 2, [0.0, 0.0], [2.0, 2.0]).unwrap();
        let hand = EffectGrid::new(2, 3, [0.0, 0.0], [3.0, 2.0]).unwrap();
        let b = Binning::new(vec![Axis::Plane(obj.clone()), Axis::Plane(hand)]).unwrap();
        assert_eq!((b.layout().rows, b.layout().cols), (4, 6));
        // object cell (1, 0), hand cell (0, 2): row 1*2+0, column 0*3+2
        let (p, e) = b.locate(&[0.5, 0.5, 2.5, 1.5]);
        assert_eq!(e, 2 * 6 + 2);
        assert_eq!(p, [2.5, 1.5]);
        // a strip after a point: one row of 3 per cell
        let s = Binning::new(vec![Axis::Plane(obj), line(3, 0.0, 3.0)]).unwrap();
        assert_eq!((s.layout().rows, s.layout().cols), (2, 6));
        assert_eq!(s.locate(&[1.5, 1.5, 2.9]).1, 5);
        assert!(!s.has_units());
    }

    fn line(bins: usize, min: f64, max: f64) -> Axis {
        Axis::Line { bins, min, max }
    }

    #[test]
    fn lines_bin_with_clamping() {
        let b = Binning::new(vec![line(4, -1.0, 1.0)]).unwrap();
        let e: Vec<usize> = [-5.0, -0.99, -0.4, 0.1, 0.6, 1.0, 9.0, f64::NAN]
            .iter()
            .map(|&v| b.locate(&[v]).1)
            .collect();
        assert_eq!(e, [0, 0, 1, 2, 3, 3, 3, 0]);
        assert!(Binning::new(vec![line(0, 0.0, 1.0)]).is_err());
        assert!(Binning::new(vec![line(2, 1.0, 1.0)]).is_err());
        assert_eq!(wrap_angle(std::f64::consts::PI), -std::f64::consts::PI);
        assert!((wrap_angle(7.0) - (7.0 - std::f64::consts::TAU)).abs() < 1e-12);
    }

    #[test]
    fn entropy_and_kl_of_simple_cases() {
        assert!((entropy(&[1.0, 1.0, 0.0, 0.0]) - 2f64.ln()).abs() < 1e-15);
        let lt = Target::Uniform.log_probs(4).unwrap();
        assert!((kl_divergence(&[1.0, 1.0, 1.0, 1.0], &lt)).abs() < 1e-15);
        assert!((kl_divergence(&[1.0, 0.0, 0.0, 0.0], &lt) - 4f64.ln()).abs() < 1e-15);
    }
}
