//! `e3d reproduce`: the paper's Figures 2 and 3 on two_rooms.

use super::output::{prepare_out, write_file};
use super::{CliError, CliResult};
use crate::cli::console::outln;
use clap::Args;
use e3d::experiment::paper::{run_paper, PaperConfig, ARMS};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `e3d reproduce`.
#[derive(Args, Debug)]
pub struct ReproduceArgs {
    /// The folder for fig2.svg, fig3.svg, their CSV and summary.md
    /// (created if needed).
    #[arg(long, default_value = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// Replace the files of an earlier reproduction in --out.
    #[arg(long)]
    pub force: bool,
    /// Sessions per learner.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub sessions: u64,
    /// Trials per session.
    #[arg(long, default_value_t = 5000, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub trials: u64,
    /// Session i uses seed SEED + i.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// The files `e3d reproduce` writes in its folder.
const FILES: [&str; 5] = ["fig2.svg", "fig2.csv", "fig3.svg", "fig3.csv", "summary.md"];

pub fn run(a: ReproduceArgs) -> CliResult {
    // session i uses seed SEED + i: wrapping round to 0 would silently
    // give the seeds of another run
    let last = a.sessions - 1;
    if a.seed.checked_add(last).is_none() {
        let (seed, sessions, most) = (a.seed, a.sessions, u64::MAX - last);
        return Err(CliError::input(format!(
            "--seed {seed} with --sessions {sessions}: session i uses seed SEED + i, which would pass 2^64 - 1; expected a seed of at most {most}"
        )));
    }
    let config = PaperConfig {
        sessions: a.sessions as usize,
        trials: a.trials as usize,
        seed: a.seed,
    };
    // as `run` and `plot`: an earlier result is replaced only with --force
    prepare_out(&a.out, &FILES, a.force)?;
    let start = Instant::now();
    // a bar on a terminal, a line every few seconds otherwise
    let trials = (ARMS.len() * config.sessions) as u64 * a.trials;
    let results = super::progress::track("reproduce two_rooms", "trials", trials, |p| {
        run_paper(config, &|k| p.add(k))
    });

    let fig2 = results.fig2_svg().map_err(CliError::output)?;
    let fig3 = results.fig3_svg().map_err(CliError::output)?;
    let summary = results.summary_markdown();
    let (fig2_csv, fig3_csv) = (results.fig2_csv(), results.fig3_csv());
    let bytes: [&[u8]; 5] = [
        fig2.as_bytes(),
        fig2_csv.as_bytes(),
        fig3.as_bytes(),
        fig3_csv.as_bytes(),
        summary.as_bytes(),
    ];
    for (name, bytes) in FILES.into_iter().zip(bytes) {
        write_file(&a.out.join(name), bytes)?;
    }
    outln!("{summary}");
    let (out, secs) = (a.out.display(), start.elapsed().as_secs_f64());
    outln!("wrote fig2.svg, fig2.csv, fig3.svg, fig3.csv and summary.md in {out} ({secs:.1} s)");
    Ok(())
}
