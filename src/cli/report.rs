//! `e3d report DIR`: the HTML page of a run folder or a sweep folder.

use super::output::write_file;
use super::{CliError, CliResult};
use crate::cli::console::{errln, outln};
use clap::Args;
use e3d::csv::{failures, parse_trials, Summary, MAX_SUMMARY_CSV_BYTES, MAX_TRIALS_CSV_BYTES};
use e3d::report::html::{run_page, sweep_page};
use e3d::report::run_scene::{SceneRecord, MAX_SUMMARY_JSON_BYTES};
use e3d::sweep::MAX_RESULTS_BYTES;
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
    if let Some(out) = &a.out {
        super::output::check_format(out, "--out", &["html", "htm"], "")?;
    }
    let dir = &a.dir;
    if !dir.is_dir() {
        let what = if dir.exists() {
            "not a folder"
        } else {
            "no such folder"
        };
        return Err(CliError::input(format!("{}: {what}", dir.display())));
    }
    let (page, what) = if dir.join("trials.csv").exists() {
        (run_report(dir)?, "run")
    } else if dir.join(SUMMARY).exists() {
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
    // the folder the page goes in is claimed, as every output folder is:
    // a run or a sweep still writing there is named, not raced
    if !e3d::io::is_stream(&out) {
        let parent = out.parent().filter(|p| !p.as_os_str().is_empty());
        super::output::lock_out(parent.unwrap_or(Path::new(".")))?;
    }
    write_file(&out, page.as_bytes())?;
    outln!("wrote {} ({what} report)", out.display());
    Ok(())
}

/// Reads one of the folder's files: a regular file of at most `max`
/// bytes (a FIFO or a link to /dev/zero is refused, never read).
fn read(dir: &Path, name: &str, max: u64) -> Result<String, CliError> {
    e3d::text::read_own_file(&dir.join(name), max, name).map_err(CliError::input)
}

/// The page of a run folder. The effects are drawn on the grid that
/// summary.json records (`scene_record`), never on a grid looked up by
/// the scene's name; without a record, on a plain grid, which the page and
/// standard error say.
fn run_report(dir: &Path) -> Result<String, CliError> {
    let trials = parse_trials(&read(dir, "trials.csv", MAX_TRIALS_CSV_BYTES)?)
        .map_err(|e| CliError::input(format!("{}/{e}", dir.display())))?;
    if trials.is_empty() {
        return Err(CliError::input(format!(
            "{}: trials.csv has no trial",
            dir.display()
        )));
    }
    let summary = match read(dir, "summary.json", MAX_SUMMARY_JSON_BYTES) {
        Ok(s) => s,
        Err(_) if !dir.join("summary.json").exists() => String::new(),
        Err(e) => return Err(e),
    };
    let json = serde_json::from_str::<serde_json::Value>(&summary).ok();
    let scene_name = json.as_ref().and_then(|v| v.get("scene")?.as_str());
    let record = json.as_ref().and_then(|v| v.get("scene_record")).map(|r| {
        serde_json::from_value::<SceneRecord>(r.clone())
            .map_err(|e| e.to_string())
            .and_then(|r| r.check().map(|()| r))
    });
    // the scene itself, if it is still the one recorded (the elite map
    // needs its actions)
    let scene = match &record {
        Some(Ok(r)) => r.scene(),
        _ => None,
    };
    let (rows, cols, note) = match record {
        Some(Ok(r)) => {
            let g = &r.effect_grid;
            let mut outside = trials.iter().enumerate();
            if let Some((k, t)) = outside.find(|(_, t)| t.effect >= g.num_cells()) {
                let (d, trial, effect, rows, cols) =
                    (dir.display(), k + 1, t.effect, g.rows, g.cols);
                let (name, path) = (e3d::text::echo(&r.name), e3d::text::echo(&r.path));
                return Err(CliError::input(format!(
                    "{d}/trials.csv: trial {trial}: effect {effect} is outside the {rows} x {cols} effect grid of scene `{name}` ({path}) that summary.json records; the folder mixes two runs"
                )));
            }
            (g.rows, g.cols, String::new())
        }
        other => {
            let why = match other {
                Some(Err(e)) => format!("its scene record is damaged ({})", e3d::text::echo(&e)),
                _ => "it records no scene grid (written by an older e3d, or missing)".to_string(),
            };
            // the effects seen, on a near-square grid
            let n = trials.iter().map(|t| t.effect).max().unwrap_or(0) + 1;
            let cols = (n as f64).sqrt().ceil().max(1.0) as usize;
            let note = format!(
                "summary.json: {why}; the effects are drawn on a plain {} x {cols} grid in index order, not on the scene's grid",
                n.div_ceil(cols)
            );
            errln!("warning: {}: {note}", dir.display());
            (n.div_ceil(cols), cols, note)
        }
    };
    let title = match scene_name {
        Some(name) => format!("e3d run: {name}"),
        None => format!("e3d run: {}", dir.display()),
    };
    Ok(run_page(
        &title,
        &note,
        &summary,
        &trials,
        (rows, cols),
        scene.as_ref(),
    ))
}

/// The page of a sweep folder: summary.csv, the failures of results.csv
/// (if it is there), sweep.ron.
fn sweep_report(dir: &Path) -> Result<String, CliError> {
    let path = dir.join(SUMMARY);
    let summary = Summary::parse(&read(dir, SUMMARY, MAX_SUMMARY_CSV_BYTES)?)
        .map_err(|e| CliError::input(format!("{}/{e}", dir.display())))?;
    if summary.rows.is_empty() {
        return Err(CliError::input(format!(
            "{}: no cell to report",
            path.display()
        )));
    }
    let failures: Vec<String> = read(dir, RESULTS, MAX_RESULTS_BYTES)
        .map(|text| failures(&text))
        .unwrap_or_default();
    let ron = read(dir, SWEEP_COPY, e3d::scene::MAX_FILE_BYTES).unwrap_or_default();
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
