//! `e3d report DIR`: a run folder's HTML page.

use super::output::write_file;
use super::{CliError, CliResult};
use clap::Args;
use e3d::report::html::{parse_trials, run_page};
use std::path::PathBuf;

/// Arguments of `e3d report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// A folder written by `e3d run --out DIR` (trials.csv, summary.json).
    pub dir: PathBuf,
    /// The page to write (default DIR/report.html).
    #[arg(long, value_name = "FILE.html")]
    pub out: Option<PathBuf>,
}

/// Writes the page.
pub fn run(a: ReportArgs) -> CliResult {
    let read = |name: &str| {
        std::fs::read_to_string(a.dir.join(name))
            .map_err(|e| CliError::input(format!("{}: {e}", a.dir.join(name).display())))
    };
    let trials = parse_trials(&read("trials.csv")?).map_err(CliError::input)?;
    if trials.is_empty() {
        return Err(CliError::input("trials.csv has no trial"));
    }
    let summary = read("summary.json").unwrap_or_default();
    let scene_name = serde_json::from_str::<serde_json::Value>(&summary)
        .ok()
        .and_then(|v| v.get("scene").and_then(|s| s.as_str()).map(String::from));
    let (rows, cols) = match scene_name.as_deref().map(super::run::load_scene) {
        Some(Ok(s)) => {
            let g = s.effect_grid();
            (g.rows, g.cols)
        }
        _ => (1, trials.iter().map(|t| t.effect).max().unwrap_or(0) + 1),
    };
    let title = format!(
        "e3d run: {}",
        scene_name.unwrap_or_else(|| a.dir.display().to_string())
    );
    let out = a.out.unwrap_or_else(|| a.dir.join("report.html"));
    write_file(
        &out,
        run_page(&title, &summary, &trials, rows, cols).as_bytes(),
    )?;
    println!("wrote {}", out.display());
    Ok(())
}
