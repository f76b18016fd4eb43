//! `e3d plot`: figures of a sweep, from its summary.csv.

use super::output::{prepare_out, write_file};
use super::{CliError, CliResult};
use crate::cli::console::outln;
use clap::Args;
use e3d::csv::Summary;
use e3d::report::sweep_plot::{plot, PlotSpec};
use std::path::PathBuf;

/// Arguments of `e3d plot`.
#[derive(Args, Debug)]
pub struct PlotArgs {
    /// The output folder of `e3d sweep` or `e3d merge` (holding summary.csv).
    pub dir: PathBuf,
    /// The parameter on the x axis: alpha, beta, lambda, eta or epsilon, or a scene axis's path.
    #[arg(long)]
    pub x: String,
    /// A second parameter: draw a heat map of the mean over (x, y).
    #[arg(long)]
    pub y: Option<String>,
    /// The metric, as summary.csv names it: METRIC of its columns
    /// METRIC_mean, METRIC_ci_low, ... (normalized_entropy,
    /// cumulative_reward_at_5000, ...).
    #[arg(long)]
    pub metric: String,
    /// Keep only the cells where COLUMN reads VALUE (repeatable), for
    /// example --where use_reward=true --where learner=e3d.
    #[arg(long = "where", value_name = "COLUMN=VALUE")]
    pub filters: Vec<String>,
    /// The SVG file to write.
    #[arg(long, value_name = "FILE.svg")]
    pub out: PathBuf,
    /// Overwrite --out if it exists.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: PlotArgs) -> CliResult {
    super::output::check_format(&a.out, "--out", &["svg"], "")?;
    let filters = (a.filters.iter())
        .map(|f| {
            f.split_once('=')
                .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
                .ok_or_else(|| CliError::input(format!("--where {f}: expected COLUMN=VALUE")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let path = a.dir.join(e3d::sweep::SUMMARY);
    // a regular file of bounded size: a FIFO or a link to /dev/zero is refused
    let text = e3d::text::read_own_file(&path, e3d::csv::MAX_SUMMARY_CSV_BYTES, "summary.csv")
        .map_err(|e| {
            CliError::input(format!(
                "{e}; expected the --out folder of a finished `e3d sweep` or `e3d merge`"
            ))
        })?;
    let summary =
        Summary::parse(&text).map_err(|e| CliError::input(format!("{}/{e}", a.dir.display())))?;
    let spec = PlotSpec {
        x: a.x,
        y: a.y,
        metric: a.metric,
        filters,
    };
    let svg = plot(&summary, &spec).map_err(CliError::input)?;
    let dir =
        (a.out.parent().filter(|p| !p.as_os_str().is_empty())).unwrap_or(std::path::Path::new("."));
    let name = (a.out.file_name().and_then(|n| n.to_str())).unwrap_or("plot.svg");
    // a stream (`--out /dev/stdout`) is written through: no folder to claim
    if !e3d::io::is_stream(&a.out) {
        prepare_out(dir, &[name], a.force)?;
    }
    write_file(&a.out, svg.as_bytes())?;
    outln!("wrote {}", a.out.display());
    Ok(())
}
