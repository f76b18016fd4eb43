//! Reports: what the experiments and runs produced, drawn. Nothing here
//! runs a session: the experiments behind `e3d reproduce`, `e3d compare`
//! and `e3d closed-loop` run in [`experiment`](crate::experiment), and the
//! CSV files of runs and sweeps are read back by [`csv`](crate::csv).
//!
//! - [`paper`]: the tables and Figures 2 and 3 of Daucé (2020) on
//!   `two_rooms`, from [`experiment::paper`](crate::experiment::paper)
//!   (what `e3d reproduce` prints and draws);
//! - [`drives`]: every drive on the canonical scenes, as a table and a
//!   figure, from the sweep of
//!   [`experiment::drives`](crate::experiment::drives) (what `e3d compare`
//!   writes);
//! - [`closed_loop`]: the table of
//!   [`experiment::closed_loop`](crate::experiment::closed_loop) (what
//!   `e3d closed-loop` prints);
//! - [`html`]: the HTML page of a run folder or a sweep folder (`e3d
//!   report`);
//! - [`scene_svg`]: pictures of scenes, with a command's path;
//! - [`motion_svg`]: a command's rollout as an animated SVG or HTML page;
//! - [`run_scene`]: what a run folder records about its scene (its grid);
//! - [`sweep_plot`]: line plots and heat maps of a sweep's summary;
//! - [`describe`], [`median`], [`Stats`]: the statistics they print.
//!
//! `paper` and `sweep_plot` draw with plotters and need the feature
//! `plots` (on by default); `scene_svg` writes its SVG itself.

pub mod closed_loop;
pub mod drives;
pub mod html;
pub mod motion_svg;
#[cfg(feature = "plots")]
pub mod paper;
pub mod run_scene;
pub mod scene_svg;
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
