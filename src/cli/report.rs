//! `e3d report DIR`: the HTML page of a run folder or a sweep folder.

use super::output::write_file;
use super::{CliError, CliResult};
use crate::cli::console::outln;
use clap::Args;
use e3d::report::html::{parse_trials, run_page, sweep_page};
use e3d::report::sweep_plot::Summary;
use e3d::sweep::{RESULTS, SUMMARY, SWEEP_COPY};
use std::path::{Path, PathBuf};

/// Arguments of `e3d report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// A folder written by `e3d run --out DIR` (trials.csv, summary.json)
    /// or by `e3d sweep --out DIR` / `e3d merge --out DIR` (summary.csv,
    /// results.csv, sweep.ron).
    pub dir: PathBuf,
    /// The page to write (default DIR/report.html).
    #[arg(long, value_name = "FILE.html")]
    pub out: Option<PathBuf>,
}

/// Writes the page: a run's if DIR holds trials.csv, a sweep's if it holds
/// summary.csv.
pub fn run(a: ReportArgs) -> CliResult {
    let dir = &a.dir;
    if !dir.is_dir() {
        return Err(CliError::input(format!(
            "{}: {}",
            dir.display(),
            if dir.exists() {
                "not a folder"
            } else {
                "no such folder"
            }
        )));
    }
    let (page, what) = if dir.join("trials.csv").is_file() {
        (run_report(dir)?, "run")
    } else if dir.join(SUMMARY).is_file() {
        (sweep_report(dir)?, "sweep")
    } else if dir.join(RESULTS).is_file() {
        return Err(CliError::input(format!(
            "{}: holds {RESULTS} but no {SUMMARY}: a shard of a sweep, or a sweep not finished; join the shards with `e3d merge DIR... --out DIR` (or finish it with `e3d sweep FILE --out DIR --resume`) and report that folder",
            dir.display()
        )));
    } else {
        return Err(CliError::input(format!(
            "{}: no results to report: expected trials.csv (a folder of `e3d run --out DIR`) or {SUMMARY} (of `e3d sweep --out DIR`)",
            dir.display()
        )));
    };
    let out = a.out.unwrap_or_else(|| dir.join("report.html"));
    write_file(&out, page.as_bytes())?;
    outln!("wrote {} ({what} report)", out.display());
    Ok(())
}

fn read(dir: &Path, name: &str) -> Result<String, CliError> {
    let p = dir.join(name);
    std::fs::read_to_string(&p).map_err(|e| CliError::input(format!("{}: {e}", p.display())))
}

/// The page of a run folder.
fn run_report(dir: &Path) -> Result<String, CliError> {
    let at = |e: String| CliError::input(format!("{}: {e}", dir.display()));
    let trials = parse_trials(&read(dir, "trials.csv")?).map_err(at)?;
    if trials.is_empty() {
        return Err(at("trials.csv has no trial".into()));
    }
    let summary = read(dir, "summary.json").unwrap_or_default();
    let scene_name = serde_json::from_str::<serde_json::Value>(&summary)
        .ok()
        .and_then(|v| v.get("scene").and_then(|s| s.as_str()).map(String::from));
    let (rows, cols) = match scene_name.as_deref().map(super::load_scene) {
        Some(Ok(s)) => {
            let g = s.effect_grid();
            (g.rows, g.cols)
        }
        _ => (1, trials.iter().map(|t| t.effect).max().unwrap_or(0) + 1),
    };
    let title = format!(
        "e3d run: {}",
        scene_name.unwrap_or_else(|| dir.display().to_string())
    );
    Ok(run_page(&title, &summary, &trials, rows, cols))
}

/// The page of a sweep folder: summary.csv, the failures of results.csv
/// (if it is there), sweep.ron.
fn sweep_report(dir: &Path) -> Result<String, CliError> {
    let path = dir.join(SUMMARY);
    let summary = Summary::parse(&read(dir, SUMMARY)?)
        .map_err(|e| CliError::input(format!("{}: {e}", path.display())))?;
    if summary.rows.is_empty() {
        return Err(CliError::input(format!(
            "{}: no cell to report",
            path.display()
        )));
    }
    let failures: Vec<String> = std::fs::read_to_string(dir.join(RESULTS))
        .map(|text| {
            text.lines()
                .skip(1)
                .filter_map(|l| l.rsplit(',').next())
                .filter(|f| !f.trim().is_empty())
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default();
    let ron = read(dir, SWEEP_COPY).unwrap_or_default();
    let name = e3d::sweep::SweepSpec::parse(&ron, SWEEP_COPY)
        .ok()
        .map(|s| s.name)
        .filter(|n| !n.is_empty())
        .unwrap_or_else(|| dir.display().to_string());
    Ok(sweep_page(
        &format!("e3d sweep: {name}"),
        &summary,
        &ron,
        &failures,
    ))
}
