//! What the commands that run sessions share (`e3d run` on commands of
//! symbols and of values, `e3d sweep`): their arguments, the summary lines
//! they print, and the streamed `trials.csv`.

use super::{cannot_write, CliError, CliResult};
use crate::cli::console::{errln, outln};
use clap::Args;
use e3d::command::CommandSpace;
use e3d::session::RepeatOptions;
use e3d::world::{ExecOptions, Strategy};
use e3d::{Command, LearnerKind, Metrics, Outcome, Params, Recorder};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Arguments of `e3d run`.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// A scene file, or the name of a built-in scene.
    #[arg(default_value = e3d::scene::DEFAULT_SCENE)]
    pub scene: String,
    /// The learner: e3d, uniform or egreedy (the paper's), or e3d_relax,
    /// count, smm, goal_babbling or archive (docs/algorithms.md), or
    /// qlearning_moves (per-move Q-learning: each move of an episode's
    /// commands a command of its own, chosen from the cell it starts in;
    /// `Repeat` scenes).
    #[arg(long, default_value = "e3d")]
    pub learner: LearnerKind,
    /// The number of trials.
    #[arg(long, default_value_t = 5000, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
    pub trials: u64,
    /// The session's seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    #[command(flatten)]
    pub params: ParamArgs,
    /// The hyper-parameters given on the command line, by name (set from
    /// clap's matches: a learner that reads none of them gets a note).
    #[arg(skip)]
    pub given_params: Vec<&'static str>,
    /// Ignore the scene's reward (the paper's task 1).
    #[arg(long)]
    pub no_reward: bool,
    /// Write DIR/trials.csv and DIR/summary.json.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Overwrite the files of an earlier run in --out.
    #[arg(long)]
    pub force: bool,
    /// Keep the scene's outcomes in DIR and reuse them: a whole table, or
    /// the commands executed so far (the file grows from run to run); keyed
    /// by the scene's content and the e3d version.
    #[arg(long, value_name = "DIR")]
    pub table_cache: Option<PathBuf>,
    /// Run N sessions, seeded --seed, --seed + 1, ..., in lockstep: each
    /// trial's new commands of all sessions are simulated together.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub sessions: u64,
    /// On a scene with a `noise` section: at the end, run each of 64
    /// commands drawn from each session's final policy R times and report
    /// the share whose effect holds in at least 90% of the runs (its
    /// reproducibility; docs/scenes.md, "Noise"); 0: do not.
    #[arg(long, value_name = "R", default_value_t = 20, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub repeat: u32,
    #[command(flatten)]
    pub memo: MemoArgs,
    /// Commands per episode (K): each trial is an episode of K commands,
    /// each starting where the last one ended (any scene of symbols, grid
    /// or physics; see docs/algorithms.md, "Contexts and closed loop").
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=64))]
    pub commands: u64,
    /// What the learner reads before each command: `start` (the index of
    /// the episode's start context), `state` (the current cell: the grid
    /// cell, or the effect cell of a physics state) or `blind`
    /// (nothing: one policy for every context); default
    /// `state` with --commands above 1 or --closed-loop, else `start`.
    #[arg(long, value_name = "start|state|blind")]
    pub observe: Option<ObserveArg>,
    /// The closed-loop learner of --learner: e3d becomes closed-loop E3D
    /// (Q_ref and the Bellman target), egreedy becomes epsilon-greedy
    /// Q-learning over whole commands.
    #[arg(long)]
    pub closed_loop: bool,
    #[command(flatten)]
    pub threads: ThreadsArg,
    /// Discount of closed-loop E3D's Q_ref and of Q-learning, in [0, 1]
    /// (with --closed-loop only: the open loop has no discount).
    #[arg(long, default_value_t = e3d::learner::ClosedLoopE3d::GAMMA, requires = "closed_loop")]
    pub gamma: f64,
    /// The support of the learner's uniform target p*: `all` (every cell
    /// of the scene, reachable or not) or `reachable` (the cells some
    /// command reaches, from the scene's outcome table; scenes of symbols
    /// run trial by trial). docs/algorithms.md, "E3D".
    #[arg(long, value_name = "all|reachable", default_value = "all")]
    pub target: TargetArg,
}

/// `--target`: the support of the uniform target `p*`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TargetArg {
    /// Every cell of the scene (`Target::Uniform`).
    All,
    /// The cells some command reaches (`OutcomeTable::reachable_target`).
    Reachable,
}

/// `--observe`: what a contextual learner reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ObserveArg {
    /// The index of the episode's start context.
    Start,
    /// The bin of the current state (on a grid, the cell).
    State,
    /// Nothing: one policy for every context.
    Blind,
}

/// The learners' hyper-parameters on the command line (defaults: task 1).
#[derive(Args, Debug, Clone)]
pub struct ParamArgs {
    /// Learning rate alpha (> 0).
    #[arg(long, default_value_t = Params::TASK1.alpha)]
    pub alpha: f64,
    /// Inverse temperature beta (> 0).
    #[arg(long, default_value_t = Params::TASK1.beta)]
    pub beta: f64,
    /// Reward weight lambda (>= 0).
    #[arg(long, default_value_t = Params::TASK1.lambda)]
    pub lambda: f64,
    /// Rate eta of the effect histogram, in (0, 1].
    #[arg(long, default_value_t = Params::TASK1.eta)]
    pub eta: f64,
    /// Exploration rate epsilon of egreedy, in [0, 1].
    #[arg(long, default_value_t = Params::TASK1.epsilon)]
    pub epsilon: f64,
    /// Slots a mutation resamples (goal_babbling, archive), >= 1.
    #[arg(long, default_value_t = Params::TASK1.k)]
    pub k: usize,
    /// Noise of a mutation of continuous values, in unit coordinates (> 0).
    #[arg(long, default_value_t = Params::TASK1.sigma)]
    pub sigma: f64,
    /// How strongly the archive favours rarely chosen cells (>= 0; 0: uniform).
    #[arg(long, default_value_t = Params::TASK1.rarity)]
    pub rarity: f64,
    /// Share of goal babbling's goals chosen by learning progress, in [0, 1].
    #[arg(long, default_value_t = Params::TASK1.goal_progress)]
    pub goal_progress: f64,
    /// The value every action-value of qlearning_moves starts at (1:
    /// optimistic; 0: the plain start).
    #[arg(long, default_value_t = Params::TASK1.initial)]
    pub initial: f64,
}

impl ParamArgs {
    /// The checked parameters.
    pub fn params(&self) -> Result<Params, CliError> {
        let p = Params {
            alpha: self.alpha,
            beta: self.beta,
            lambda: self.lambda,
            eta: self.eta,
            epsilon: self.epsilon,
            k: self.k,
            sigma: self.sigma,
            rarity: self.rarity,
            goal_progress: self.goal_progress,
            initial: self.initial,
        };
        p.validate()
            .map_err(|e| CliError::input(format!("--{e}")))?;
        Ok(p)
    }
}

/// The outcome memo's options, shared by `run` and `sweep`.
#[derive(Args, Debug, Clone)]
pub struct MemoArgs {
    /// The most command outcomes kept in memory by the outcome memo (each
    /// command simulated once; about 50-100 bytes an entry); 0 turns it off.
    #[arg(long, value_name = "N", default_value_t = e3d::world::DEFAULT_MEMO_CAP)]
    pub memo_cap: usize,
    /// How outcomes are obtained: auto (the cheapest by the cost rule),
    /// table (every command once, up front), memo (each proposed command
    /// once) or live (every proposal simulated). The results are the same.
    #[arg(long, value_name = "HOW", default_value = "auto", value_parser = parse_outcomes)]
    pub outcomes: Outcomes,
}

/// `--outcomes`: `auto` or a strategy.
#[derive(Debug, Clone, Copy)]
pub struct Outcomes(pub Option<Strategy>);

fn parse_outcomes(s: &str) -> Result<Outcomes, String> {
    match s {
        "auto" => Ok(Outcomes(None)),
        _ => s
            .parse::<Strategy>()
            .map(|st| Outcomes(Some(st)))
            .map_err(|_| format!("`{s}`: expected auto, table, memo or live")),
    }
}

impl MemoArgs {
    /// The options of an [`Executor`] with the table folder `cache`.
    pub fn options(&self, cache: Option<&Path>) -> ExecOptions {
        ExecOptions {
            cache: cache.map(Path::to_path_buf),
            memo_cap: self.memo_cap,
            force: self.outcomes.0,
        }
    }
}

/// One session's rows of a CSV file, streamed into a temporary file beside
/// the final one (joined by [`write_run`]), never held in memory; the first
/// write error is said by [`finish`](Self::finish).
pub(super) struct CsvPart {
    out: std::io::BufWriter<std::fs::File>,
    path: PathBuf,
    error: Option<std::io::Error>,
}

impl CsvPart {
    /// A new temporary file beside the final file `target` (created
    /// exclusively: never through a link planted under its name).
    pub(super) fn create(target: &Path) -> Result<Self, CliError> {
        let (path, f) = e3d::io::create_temp_beside(target).map_err(|e| cannot_write(target, e))?;
        Ok(CsvPart {
            out: std::io::BufWriter::with_capacity(1 << 16, f),
            path,
            error: None,
        })
    }

    /// Writes a row with `write` (nothing after a failed write).
    pub(super) fn row(
        &mut self,
        write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
    ) {
        if self.error.is_none() {
            self.error = write(&mut self.out).err();
        }
    }

    /// Flushes; the file's path, or why it could not be written.
    fn finish(mut self) -> Result<PathBuf, CliError> {
        use std::io::Write;
        match self.error.take().map_or_else(|| self.out.flush(), Err) {
            Ok(()) => Ok(self.path),
            Err(e) => Err(cannot_write(&self.path, e)),
        }
    }
}

/// Streams `trial,command,effect,reward` rows (with a leading `session`
/// column for several sessions) into a [`CsvPart`].
pub(super) struct TrialsCsv {
    pub(super) part: CsvPart,
    pub(super) space: CommandSpace,
    pub(super) session: Option<usize>,
    pub(super) trial: usize,
}

impl Recorder for TrialsCsv {
    fn record(&mut self, command: &Command, outcome: &Outcome) {
        use std::io::Write;
        self.trial += 1;
        let (trial, space, session) = (self.trial, &self.space, self.session);
        self.part.row(|out| {
            if let Some(s) = session {
                write!(out, "{s},")?;
            }
            let (effect, reward) = (outcome.effect, outcome.reward);
            writeln!(out, "{trial},{},{effect},{reward}", space.format(command))
        });
    }
}

/// Per session `i` of `n`, its `tally` and, with `--out DIR` (`out`), the
/// recorder `csv` makes of its part of DIR/trials.csv.
pub(super) fn recorders<T, C>(
    out: Option<&Path>,
    n: usize,
    tally: impl Fn() -> T,
    csv: impl Fn(CsvPart, usize) -> C,
) -> Result<Vec<(T, Option<C>)>, CliError> {
    let path = out.map(|d| d.join("trials.csv"));
    (0..n)
        .map(|i| {
            let part = path.as_deref().map(CsvPart::create).transpose()?;
            Ok((tally(), part.map(|p| csv(p, i))))
        })
        .collect()
}

/// The sessions' CSV parts (`parts`, in step with `status`), finished;
/// the first failed session fails the run with its error.
pub(super) fn finish_parts<E>(
    status: Vec<Result<(), E>>,
    parts: impl Iterator<Item = Option<CsvPart>>,
) -> Result<Vec<PathBuf>, CliError>
where
    CliError: From<E>,
{
    (status.into_iter().zip(parts))
        .filter_map(|(st, part)| match st {
            Ok(()) => part.map(CsvPart::finish),
            Err(e) => Some(Err(e.into())),
        })
        .collect()
}

/// Writes DIR/trials.csv whole or not at all (`header`, the sessions'
/// streamed `parts`, then what `rows` writes) and DIR/summary.json
/// (`summary`), and says so.
pub(super) fn write_run(
    dir: &Path,
    header: &str,
    parts: &[PathBuf],
    rows: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
    summary: &impl serde::Serialize,
) -> CliResult {
    use std::io::Write;
    let (csv, json_path) = (dir.join("trials.csv"), dir.join("summary.json"));
    let (tmp, file) = e3d::io::create_temp_beside(&csv).map_err(|e| cannot_write(&csv, e))?;
    let written = (|| -> std::io::Result<()> {
        let mut out = std::io::BufWriter::new(file);
        writeln!(out, "{header}")?;
        for p in parts {
            std::io::copy(&mut std::fs::File::open(p)?, &mut out)?;
        }
        rows(&mut out)?;
        out.into_inner().map_err(|e| e.into_error())?.sync_all()
    })();
    for p in parts {
        let _ = std::fs::remove_file(p);
    }
    e3d::io::finish_output(Some(tmp), &csv, written, |e| e).map_err(|e| cannot_write(&csv, e))?;
    let mut json = serde_json::to_vec_pretty(summary).map_err(CliError::output)?;
    json.push(b'\n');
    super::output::write_file(&json_path, &json)?;
    outln!("wrote {} and {}", csv.display(), json_path.display());
    Ok(())
}

/// Runs `work` with the progress of `sessions` sessions of `a.trials`
/// `unit` each shown on stderr (a bar on a terminal, a line every few
/// seconds otherwise).
pub(super) fn track_run<T>(
    a: &RunArgs,
    scene: &e3d::Scene,
    unit: &str,
    sessions: usize,
    work: impl FnOnce(&e3d::Control<'_>) -> T,
) -> T {
    let label = format!("run {}", scene.spec().name);
    let total = a.trials.saturating_mul(sessions as u64);
    super::progress::track_control(&label, unit, total, work)
}

/// A note on standard error for every hyper-parameter given on the command
/// line (`given`) that `learner` does not read: the run goes on (as a sweep
/// spans only the parameters its learner uses), but the flag does nothing.
pub(super) fn note_unused_params(learner: LearnerKind, given: &[&str]) {
    let reads = learner.params();
    let list = match reads {
        [] => "no hyper-parameter".to_string(),
        r => r.join(", "),
    };
    for name in given.iter().filter(|n| !reads.contains(n)) {
        let flag = name.replace('_', "-");
        errln!("note: --{flag} does nothing for learner {learner} (it reads {list})");
    }
}

/// The first line of a run's summary: scene, learner (`kind` after its
/// name: `" (continuous)"` or nothing), trials, sessions and seeds, and
/// ` | alpha 0.3 beta 1 ...`: the parameters the learner reads, in the
/// order of a sweep's columns (none for the uniform policy).
pub(super) fn print_header(a: &RunArgs, scene: &str, kind: &str, params: &Params, seeds: &[u64]) {
    let (first, last) = (seeds[0], seeds[seeds.len() - 1]);
    let (sessions, seed) = match seeds.len() {
        1 => (String::new(), first.to_string()),
        n => (format!(" x {n} sessions"), format!("{first}..={last}")),
    };
    let used: Vec<String> = (params.named().into_iter())
        .filter(|(name, _)| e3d::sweep::uses_param(a.learner, name))
        .map(|(name, v)| format!(" {name} {v}"))
        .collect();
    let used = match used.concat() {
        u if u.is_empty() => u,
        u => format!(" |{u}"),
    };
    let no_reward = if a.no_reward { " | no reward" } else { "" };
    let (learner, trials) = (a.learner, a.trials);
    outln!("scene {scene} | learner {learner}{kind} | {trials} trials{sessions} | seed {seed}{used}{no_reward}");
}

/// The metrics of each session (`seeds[i]` names session `i` when there
/// are several) and, for several, their mean.
pub(super) fn print_metrics(metrics: &[Metrics], seeds: &[u64], num_effects: usize) {
    let sessions = metrics.len();
    let at = |t: Option<usize>| t.map_or("-".to_string(), |t| t.to_string());
    for (m, seed) in metrics.iter().zip(seeds) {
        let who = match sessions {
            1 => String::new(),
            _ => format!("seed {seed}: "),
        };
        let Metrics {
            normalized_entropy: h,
            normalized_entropy_last_1000: h1000,
            kl_to_target: kl,
            distinct_effects: k,
            coverage,
            coverage_cells: cells,
            cumulative_reward: reward,
            ..
        } = *m;
        outln!("{who}normalised entropy {h:.4} (last 1000: {h1000:.4}) | KL to target {kl:.4} nats | {k} of {num_effects} effects reached");
        if let (Some(k), Some(h)) = (m.reachable_effects, m.normalized_entropy_reachable) {
            outln!("{who}over the {k} reachable cells: normalised entropy {h:.4}");
        }
        let (of, reachable) = match m.reachable_effects {
            Some(_) => ("the", " reachable"),
            None => ("all", ""),
        };
        let (t50, t90) = (at(m.trials_to_50_percent), at(m.trials_to_90_percent));
        let qd = m
            .qd_score
            .map_or(String::new(), |q| format!(" | qd_score {q:.4}"));
        outln!("{who}coverage {coverage:.4} of {of} {cells}{reachable} cells | 50% by trial {t50} | 90% by trial {t90}{qd}");
        let first = at(m.first_reward_trial);
        outln!("{who}cumulative reward {reward} | first reward at trial {first}");
    }
    if sessions > 1 {
        outln!("{}", mean_line(metrics));
    }
}

/// The last line of `e3d run` over several sessions: each measure's mean
/// and the half-width of its 95% Student t interval
/// ([`mean_ci95`](e3d::report::mean_ci95)), and the first rewarded
/// trial's median and quartiles (a skewed count: order statistics, a
/// session never rewarded later than all).
fn mean_line(metrics: &[Metrics]) -> String {
    let n = metrics.len();
    let ci = |f: fn(&Metrics) -> f64, digits: usize| {
        let xs: Vec<f64> = metrics.iter().map(f).collect();
        let c = e3d::report::mean_ci95(&xs).expect("two sessions or more");
        format!("{c:.digits$}")
    };
    let (h, coverage) = (ci(|m| m.normalized_entropy, 4), ci(|m| m.coverage, 4));
    let reward = ci(|m| m.cumulative_reward, 1);
    let firsts: Vec<usize> = metrics
        .iter()
        .filter_map(|m| m.first_reward_trial)
        .collect();
    let [q1, mid, q3] = e3d::report::order_quartiles(&firsts, n);
    let at = e3d::report::or_never;
    let (q1, mid, q3, k) = (at(q1), at(mid), at(q3), firsts.len());
    let qd = match metrics
        .iter()
        .map(|m| m.qd_score)
        .collect::<Option<Vec<f64>>>()
    {
        Some(_) => format!(" | qd_score {}", ci(|m| m.qd_score.unwrap_or(f64::NAN), 4)),
        None => String::new(),
    };
    format!("mean ± 95% (t) of {n} sessions: normalised entropy {h} | coverage {coverage} | cumulative reward {reward} | first reward: median {mid} (Q1..Q3 {q1}..{q3}), {k} of {n} rewarded{qd}")
}

/// `--threads N`: the threads a command runs on, shared by `run`,
/// `sweep`, `compare` and `closed-loop`.
#[derive(Args, Debug, Clone, Copy)]
pub struct ThreadsArg {
    /// Threads (default: every core).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=4096))]
    pub threads: Option<u16>,
}

impl ThreadsArg {
    /// `--threads`, or the threads of rayon's global pool (the cores, or
    /// `RAYON_NUM_THREADS`), capped (with a warning) at
    /// [`e3d::sweep::max_threads`].
    pub fn count(&self) -> usize {
        let threads = self
            .threads
            .map(usize::from)
            .unwrap_or_else(rayon::current_num_threads);
        let (threads, capped) = e3d::sweep::cap_threads(threads);
        if let Some(w) = capped {
            errln!("warning: {w}");
        }
        threads
    }

    /// Runs `work` on a pool of `--threads` threads (capped), or on
    /// rayon's global pool without the flag.
    pub fn install<R: Send>(
        &self,
        work: impl FnOnce() -> Result<R, CliError> + Send,
    ) -> Result<R, CliError> {
        match self.threads {
            None => work(),
            Some(_) => Self::pool_of(self.count())?.install(work),
        }
    }

    /// A pool of `threads` threads.
    pub fn pool_of(threads: usize) -> Result<rayon::ThreadPool, CliError> {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| CliError::input(format!("cannot start the threads: {e}")))
    }
}

/// The reproducibility of a session's final policy
/// ([`e3d::session::reproducibility`]), as `summary.json` holds it.
#[derive(Serialize, Clone, Copy)]
pub(super) struct Repro {
    /// The share of the likely commands whose effect holds in >= 90% of runs.
    share: f64,
    /// How many likely commands were drawn, and how many runs each had.
    commands: usize,
    runs: usize,
}

/// Prints each session's reproducibility (a line each, the seed named when
/// several): of `what` (commands, episodes) drawn from the final policy.
pub(super) fn print_repro(repro: &[Option<Repro>], seeds: &[u64], what: &str) {
    for (r, seed) in repro.iter().zip(seeds) {
        let who = if seeds.len() == 1 {
            String::new()
        } else {
            format!("seed {seed}: ")
        };
        match r {
            Some(r) => outln!("{who}reproducibility {:.4}: of {} {what} drawn from the final policy, the share whose effect holds in at least 90% of {} noisy runs", r.share, r.commands, r.runs),
            None => outln!("{who}reproducibility: - (the learner's policy cannot be drawn from)"),
        }
    }
}

impl Repro {
    /// The figure `summary.json` keeps of `r`, measured with `options`.
    pub(super) fn of(r: e3d::session::Reproducibility, options: RepeatOptions) -> Repro {
        Repro {
            share: r.share,
            commands: options.commands,
            runs: options.runs,
        }
    }
}
