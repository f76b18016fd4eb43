//! `e3d run`: one session on a scene.

use super::{CliError, CliResult};
use clap::Args;
use e3d::{
    policy_effect_distribution, run_session_with, LearnerKind, Metrics, OutcomeTable, Params,
    Scene, SessionConfig, Target,
};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Arguments of `e3d run`.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// A scene file, or the name of a built-in scene.
    #[arg(default_value = e3d::scene::DEFAULT_SCENE)]
    pub scene: String,
    /// The learner: e3d, uniform or egreedy.
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
    /// Ignore the scene's reward (the paper's task 1).
    #[arg(long)]
    pub no_reward: bool,
    /// Write DIR/trials.csv and DIR/summary.json.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Overwrite the files of an earlier run in --out.
    #[arg(long)]
    pub force: bool,
    /// Keep the scene's outcome table (every command executed once) in DIR
    /// and reuse it; keyed by the scene's content and the e3d version.
    #[arg(long, value_name = "DIR")]
    pub table_cache: Option<PathBuf>,
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
        };
        p.validate()
            .map_err(|e| CliError::input(format!("--{e}")))?;
        Ok(p)
    }
}

/// What `summary.json` holds.
#[derive(Serialize)]
struct Summary<'a> {
    e3d_version: &'static str,
    scene: &'a str,
    learner: &'static str,
    #[serde(flatten)]
    params: Params,
    seed: u64,
    use_reward: bool,
    #[serde(flatten)]
    metrics: &'a Metrics,
    /// The exact effect distribution of the final policy (small command
    /// spaces only).
    policy_effect_distribution: Option<Vec<f64>>,
    effect_counts: Vec<f64>,
}

/// Loads a scene by path or built-in name, as a CLI error.
pub fn load_scene(name: &str) -> Result<Scene, CliError> {
    Scene::resolve(name).map_err(CliError::input)
}

/// Refuses to overwrite the given files in `dir` unless `force`; creates `dir`.
pub fn prepare_out(dir: &Path, files: &[&str], force: bool) -> CliResult {
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::output(format!(
            "{}: exists and is not a directory",
            dir.display()
        )));
    }
    if !force {
        if let Some(f) = files.iter().map(|f| dir.join(f)).find(|p| p.exists()) {
            return Err(CliError::output(format!(
                "{} exists; pass --force to overwrite it, or choose another --out",
                f.display()
            )));
        }
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| CliError::output(format!("{}: cannot create the folder: {e}", dir.display())))
}

/// Writes a file whole or not at all, as a CLI error.
pub fn write_file(path: &Path, bytes: &[u8]) -> CliResult {
    e3d::io::write_atomic(path, bytes)
        .map_err(|e| CliError::output(format!("{}: cannot write: {e}", path.display())))
}

pub fn run(a: RunArgs) -> CliResult {
    let params = a.params.params()?;
    let scene = load_scene(&a.scene)?;
    if let Some(dir) = &a.out {
        prepare_out(dir, &["trials.csv", "summary.json"], a.force)?;
    }
    let mut world = scene.build();
    let space = world.command_space().clone();
    let target = Target::Uniform;
    let mut learner = a
        .learner
        .make(&params, &space, world.num_effects(), &target)
        .map_err(CliError::input)?;
    let cfg = SessionConfig {
        trials: a.trials as usize,
        seed: a.seed,
        use_reward: !a.no_reward,
    };
    // a table some command of which blows up is not used: the session then
    // fails on the command it actually tried, and says which
    let table = if OutcomeTable::worthwhile(&scene, &*world, a.trials) {
        OutcomeTable::for_scene(&scene, a.table_cache.as_deref()).ok()
    } else {
        None
    };
    // a progress bar on a terminal (indicatif draws nothing otherwise)
    let bar = indicatif::ProgressBar::new(a.trials);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} trials, {eta} left")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(scene.name.clone());
    let tick = |t: usize| bar.set_position(t as u64);
    let record = match &table {
        Some(t) => run_session_with(&mut &*t, &mut learner, &cfg, tick),
        None => run_session_with(&mut world, &mut learner, &cfg, tick),
    }
    .map_err(CliError::simulation)?;
    bar.finish_and_clear();
    let metrics = record.metrics(&target);
    let exact = table
        .as_ref()
        .and_then(|t| policy_effect_distribution(t, &*learner));

    println!(
        "scene {} | learner {} | {} trials | seed {} | alpha {} beta {} lambda {} eta {} epsilon {}{}",
        scene.name,
        a.learner,
        a.trials,
        a.seed,
        params.alpha,
        params.beta,
        params.lambda,
        params.eta,
        params.epsilon,
        if a.no_reward { " | no reward" } else { "" }
    );
    println!(
        "normalized entropy {:.4} (last 1000: {:.4}) | KL to target {:.4} nats | {} of {} effects reached",
        metrics.normalized_entropy,
        metrics.normalized_entropy_last_1000,
        metrics.kl_to_target,
        metrics.distinct_effects,
        world.num_effects()
    );
    println!(
        "cumulative reward {} | first reward at trial {}",
        metrics.cumulative_reward,
        metrics
            .first_reward_trial
            .map_or("-".to_string(), |t| t.to_string())
    );
    if let Some(d) = &exact {
        let h = e3d::effect::entropy(d) / (d.len() as f64).ln();
        println!("exact effect distribution of the final policy: normalized entropy {h:.4}");
    }

    if let Some(dir) = &a.out {
        let mut csv = Vec::new();
        record
            .write_trials_csv(&space, &mut csv)
            .map_err(CliError::output)?;
        let summary = Summary {
            e3d_version: env!("CARGO_PKG_VERSION"),
            scene: &scene.name,
            learner: a.learner.as_str(),
            params,
            seed: a.seed,
            use_reward: !a.no_reward,
            metrics: &metrics,
            policy_effect_distribution: exact,
            effect_counts: record.effect_counts(0..record.trials()),
        };
        let mut json = serde_json::to_vec_pretty(&summary).map_err(CliError::output)?;
        json.push(b'\n');
        write_file(&dir.join("trials.csv"), &csv)?;
        write_file(&dir.join("summary.json"), &json)?;
        println!(
            "wrote {} and {}",
            dir.join("trials.csv").display(),
            dir.join("summary.json").display()
        );
    }
    Ok(())
}
