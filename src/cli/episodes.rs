//! `e3d run` on episodes: a scene with start contexts, or `--commands K`
//! commands per episode (closed loop), with a contextual learner.

use super::session::{finish_parts, recorders, track_run, write_run, CsvPart, ObserveArg, RunArgs};
use super::{CliError, CliResult};
use crate::cli::console::{errln, outln};
use e3d::command::CommandSpace;
use e3d::episode::{EpisodeConfig, EpisodeRecorder, EpisodeTally, Observe};
use e3d::learner::{ContextualLearner, LearnerSetup};
use e3d::session::run_episode_sessions;
use e3d::world::{ContextMemoized, OutcomeMemo};
use e3d::{LearnerKind, Params, Scene};
use serde::Serialize;

/// Whether `e3d run` runs episodes: start contexts, several commands per
/// episode, or a closed-loop learner.
pub fn wanted(a: &RunArgs, scene: &Scene) -> bool {
    start_names(scene).len() > 1
        || a.commands > 1
        || a.closed_loop
        || a.observe.is_some()
        || a.learner == LearnerKind::QlearningMoves
}

/// The names of the scene's start contexts (`["start"]` without any).
fn start_names(scene: &Scene) -> Vec<String> {
    let names: Vec<String> = (e3d::world::start_contexts(scene).into_iter())
        .map(|c| c.name)
        .collect();
    match names.is_empty() {
        true => vec!["start".into()],
        false => names,
    }
}

#[derive(Serialize)]
struct OneSession {
    seed: u64,
    episodes: usize,
    first_reward_episode: Option<usize>,
    cumulative_reward: f64,
    /// Per start context, the normalised entropy of the episodes' terminal
    /// cells.
    entropy_per_start: Vec<f64>,
    /// On a noisy scene: the reproducibility of the final policy's
    /// episodes.
    #[serde(skip_serializing_if = "Option::is_none")]
    reproducibility: Option<super::session::Repro>,
}

#[derive(Serialize)]
struct Summary<'a> {
    e3d_version: &'static str,
    scene: &'a str,
    learner: &'a str,
    #[serde(flatten)]
    params: Params,
    use_reward: bool,
    commands_per_episode: usize,
    observe: &'static str,
    gamma: Option<f64>,
    start_contexts: Vec<String>,
    sessions: Vec<OneSession>,
    /// The scene's grid, for `e3d report`.
    scene_record: e3d::report::run_scene::SceneRecord,
}

pub fn run(a: &RunArgs, scene: &Scene, params: Params, seeds: &[u64]) -> CliResult {
    // per-move Q-learning: each of the K commands' n moves is a command of
    // its own, chosen from the cell it starts in
    let single;
    let (scene, commands) = match a.learner {
        LearnerKind::QlearningMoves => {
            let moves = scene.spec().num_slots();
            single = scene.with_moves(1).ok_or_else(|| {
                CliError::input(format!(
                    "scene `{}`: --learner qlearning_moves takes a scene whose command is `Repeat` (every move from one alphabet)",
                    scene.spec().name
                ))
            })?;
            let single = single.map_err(CliError::input)?;
            (single, a.commands as usize * moves)
        }
        _ => (scene.clone(), a.commands as usize),
    };
    let scene = &scene;
    // refused before any work: a continuous scene, more commands than a
    // record holds, a closed loop of another learner
    if scene.value_space().is_some() {
        return Err(CliError::input(format!(
            "scene `{}`: its slots take values (`Continuous`); start contexts and --commands, --observe, --closed-loop run on scenes of symbols",
            scene.spec().name
        )));
    }
    // a noisy scene's episodes run live: no memo, no table
    let noisy = matches!(&scene.spec().world, e3d::scene::WorldSpec::Physics(p) if p.active_noise().is_some());
    if let (Some(dir), true) = (&a.table_cache, noisy) {
        let why = e3d::scene::physics::noise_refusal(&scene.spec().name, "a table cache");
        return Err(CliError::input(format!(
            "--table-cache {}: {why}",
            dir.display()
        )));
    }
    e3d::episode::check_size(a.trials as usize, commands)
        .map_err(|e| CliError::input(format!("--trials with --commands: {e}")))?;
    let observe = observe_of(a, commands);
    let space = scene.command_space();
    let num_effects = scene.num_effects();
    let world = scene.build();
    let cfg = |seed| EpisodeConfig {
        episodes: a.trials as usize,
        commands,
        seed,
        use_reward: !a.no_reward,
        observe,
    };
    let contexts = cfg(0).num_contexts(&world);
    let closing = [
        LearnerKind::E3d,
        LearnerKind::Egreedy,
        LearnerKind::QlearningMoves,
    ];
    if a.closed_loop && !closing.contains(&a.learner) {
        return Err(CliError::input(format!(
            "--closed-loop takes --learner e3d (closed-loop E3D), egreedy (Q-learning) or qlearning_moves, not {}",
            a.learner
        )));
    }
    let make = || -> Result<Box<dyn ContextualLearner + Send>, CliError> {
        LearnerSetup::new(a.learner)
            .params(params)
            .effort_of(scene)
            .closed_loop(a.closed_loop)
            .gamma(a.gamma)
            .contexts(&space, num_effects, contexts)
            .map_err(CliError::input)
    };
    let name = make()?.name().to_string();
    describe(a, commands, seeds.len(), &name, contexts, observe);
    // one memo per start context (none with --memo-cap 0): commands from a
    // named start context are simulated once, whatever the session
    // (sampled starts and later commands run live)
    let memos: Vec<OutcomeMemo> = match a.memo.memo_cap {
        _ if noisy => Vec::new(),
        0 => Vec::new(),
        cap => (0..world.num_contexts())
            .map(|_| OutcomeMemo::new(&space, num_effects, cap))
            .collect::<Result<_, _>>()
            .map_err(CliError::input)?,
    };
    if let Some(dir) = &a.table_cache {
        preload_context_tables(&a.scene, scene, dir, &memos);
    }
    let configs: Vec<EpisodeConfig> = seeds.iter().map(|&s| cfg(s)).collect();
    let names = start_names(scene);
    let tally = || EpisodeTally::new(names.len());
    let mut recorders = recorders(a.out.as_deref(), seeds.len(), tally, |part, session| {
        EpisodeCsv {
            part,
            space: space.clone(),
            names: names.clone(),
            session,
            episode: 0,
            command: 0,
            start: 0,
        }
    })?;
    // what the episodes cost at most (every command simulated; the
    // memos cut it), said when long, as every run says it
    let total = (seeds.len() as u64) * a.trials * commands as u64;
    let threads = seeds.len().min(rayon::current_num_threads());
    let label = format!("run {}", scene.spec().name);
    super::scene::simulate::say_cost(&label, scene, total, threads, 1);
    // each session's learner, kept to the end for its reproducibility
    let learners: Vec<std::sync::Mutex<Option<_>>> =
        seeds.iter().map(|_| std::sync::Mutex::new(None)).collect();
    let status = track_run(a, scene, "episodes", seeds.len(), |control| {
        let make = |i: usize| -> Result<_, CliError> {
            let world = Box::new(ContextMemoized::new(scene.build(), &memos));
            let mut kept = crate::cli::locked(&learners[i]);
            *kept = Some(make()?);
            Ok((world, Held(kept)))
        };
        run_episode_sessions(&configs, make, &mut recorders, control)
    });
    let parts = recorders.iter_mut().map(|r| r.1.take().map(|c| c.part));
    let parts = finish_parts(status, parts)?;
    let repro = episode_reproducibility(a, scene, noisy, &configs, learners)?;
    let mut sessions: Vec<OneSession> = (recorders.iter().zip(seeds))
        .map(|((t, _), &seed)| OneSession {
            seed,
            episodes: t.episodes(),
            first_reward_episode: t.first_reward_episode(),
            cumulative_reward: t.cumulative_reward(),
            entropy_per_start: t.entropy_per_start(),
            reproducibility: None,
        })
        .collect();
    print_sessions(a, commands, scene, &name, &names, &sessions);
    super::session::print_repro(&repro, seeds, "episodes");
    for (s, r) in sessions.iter_mut().zip(repro) {
        s.reproducibility = r;
    }
    let Some(dir) = &a.out else {
        return Ok(());
    };
    let summary = Summary {
        e3d_version: env!("CARGO_PKG_VERSION"),
        scene: &scene.spec().name,
        learner: &name,
        params,
        use_reward: !a.no_reward,
        commands_per_episode: commands,
        observe: match observe {
            Observe::State => "state",
            _ => "start",
        },
        gamma: (a.closed_loop || a.learner == LearnerKind::QlearningMoves).then_some(a.gamma),
        start_contexts: names,
        sessions,
        scene_record: e3d::report::run_scene::SceneRecord::new(scene, &a.scene),
    };
    let header = "session,episode,command,context,start,symbols,effect,reward";
    write_run(dir, header, &parts, |_| Ok(()), &summary)
}

/// A session's learner, held in its place while the session runs.
struct Held<'a, L>(std::sync::MutexGuard<'a, Option<L>>);

impl<L> std::ops::Deref for Held<'_, L> {
    type Target = L;
    fn deref(&self) -> &L {
        self.0
            .as_ref()
            .expect("a learner is made before it is held")
    }
}

impl<L> std::ops::DerefMut for Held<'_, L> {
    fn deref_mut(&mut self) -> &mut L {
        self.0
            .as_mut()
            .expect("a learner is made before it is held")
    }
}

/// On a noisy scene with `--repeat R` (R > 0): per session, the
/// reproducibility of its final policy's episodes
/// ([`e3d::session::episode_reproducibility`], seeded by the session's
/// seed), the sessions in parallel; else nothing.
fn episode_reproducibility(
    a: &RunArgs,
    scene: &Scene,
    noisy: bool,
    configs: &[EpisodeConfig],
    learners: Vec<std::sync::Mutex<Option<Box<dyn ContextualLearner + Send>>>>,
) -> Result<Vec<Option<super::session::Repro>>, CliError> {
    use rayon::prelude::*;
    if !noisy || a.repeat == 0 {
        return Ok(Vec::new());
    }
    let options = e3d::session::RepeatOptions {
        runs: a.repeat as usize,
        ..e3d::session::RepeatOptions::default()
    };
    (learners.into_par_iter().zip(configs))
        .map(|(l, config)| {
            let l = l.into_inner().unwrap_or_else(|e| e.into_inner());
            let Some(l) = l else { return Ok(None) };
            let mut world = scene.build();
            let r = e3d::session::episode_reproducibility(&mut *world, &*l, config, options)
                .map_err(CliError::simulation)?;
            Ok(r.map(|r| super::session::Repro::of(r, options)))
        })
        .collect()
}

/// Tells (on stderr) what runs: sessions, episodes, learner, contexts
/// and what the learner observes.
fn describe(
    a: &RunArgs,
    commands: usize,
    sessions: usize,
    name: &str,
    contexts: usize,
    observe: Observe,
) {
    let how = match observe {
        Observe::State => "the current effect cell",
        Observe::StartContext => "the start context",
        Observe::Blind => "nothing (one policy)",
    };
    let (trials, s) = (a.trials, super::plural(commands));
    errln!("episodes: {sessions} sessions of {trials} episodes of {commands} command{s}, learner {name}, {contexts} contexts observed as {how}");
}

/// With `--table-cache DIR`: the outcome tables of the scene's named
/// contexts that DIR holds (`e3d scene table SCENE --cache DIR`) fill the
/// contexts' memos, so their commands are looked up, not simulated (the
/// same outcomes, bit for bit). Said on stderr; a context without its
/// table there runs as without the option.
fn preload_context_tables(
    given: &str,
    scene: &Scene,
    dir: &std::path::Path,
    memos: &[OutcomeMemo],
) {
    if memos.is_empty() {
        return; // --memo-cap 0: nothing is kept
    }
    let tables = e3d::world::ContextTables::read_cached(scene, dir);
    let names = start_names(scene);
    let mut read = Vec::new();
    for ((table, memo), name) in tables.iter().zip(memos).zip(&names) {
        if let Some(t) = table {
            memo.extend(t.outcomes().enumerate().map(|(i, o)| (i as u64, *o)));
            read.push(name.as_str());
        }
    }
    let (dir, read) = (dir.display(), read.join(", "));
    if read.is_empty() {
        errln!("note: no outcome table of a start context in {dir}; simulating the commands (`e3d scene table {given} --cache {dir}` writes them)");
    } else {
        errln!("outcomes: the tables of start contexts {read} read from {dir}");
    }
}

/// What the learner observes: `--observe`, else the default for the
/// commands per episode and the loop.
fn observe_of(a: &RunArgs, commands: usize) -> Observe {
    match a.observe {
        Some(ObserveArg::Start) => Observe::StartContext,
        Some(ObserveArg::State) => Observe::State,
        Some(ObserveArg::Blind) => Observe::Blind,
        None => Observe::default_for(commands, a.closed_loop),
    }
}

/// Prints the run's heading and a line per session: its first reward,
/// cumulative reward and entropy per start context (`names`).
fn print_sessions(
    a: &RunArgs,
    commands: usize,
    scene: &Scene,
    name: &str,
    names: &[String],
    sessions: &[OneSession],
) {
    let (first, last) = (sessions[0].seed, sessions[sessions.len() - 1].seed);
    let (scene, trials) = (&scene.spec().name, a.trials);
    outln!("scene {scene}, learner {name}, {trials} episodes of {commands} command(s), seeds {first}..={last}");
    for s in sessions {
        let ent: Vec<String> = (names.iter().zip(&s.entropy_per_start))
            .map(|(n, h)| format!("{n} {h:.4}"))
            .collect();
        let first = e3d::report::or_never(s.first_reward_episode);
        let (seed, reward, ent) = (s.seed, s.cumulative_reward, ent.join(", "));
        outln!("seed {seed}: first reward at episode {first}, cumulative reward {reward}, normalised entropy of the terminal cells per start context: {ent}");
    }
    if sessions.len() > 1 {
        outln!("{}", mean_line(names, sessions));
    }
}

/// The last line over several sessions: per start context, the mean
/// normalised entropy ± the half-width of its 95% Student t interval;
/// the same of the cumulative reward; the first rewarded episode's median
/// and quartiles (never-rewarded sessions later than all).
fn mean_line(names: &[String], sessions: &[OneSession]) -> String {
    let n = sessions.len();
    let ci = |xs: Vec<f64>, digits: usize| {
        let c = e3d::report::mean_ci95(&xs).expect("two sessions or more");
        format!("{c:.digits$}")
    };
    let ent: Vec<String> = (names.iter().enumerate())
        .map(|(i, name)| {
            let xs = sessions.iter().map(|s| s.entropy_per_start[i]).collect();
            format!("{name} {}", ci(xs, 4))
        })
        .collect();
    let reward = ci(sessions.iter().map(|s| s.cumulative_reward).collect(), 1);
    let firsts: Vec<usize> = sessions
        .iter()
        .filter_map(|s| s.first_reward_episode)
        .collect();
    let [q1, mid, q3] = e3d::report::order_quartiles(&firsts, n);
    let at = e3d::report::or_never;
    let (q1, mid, q3, k, ent) = (at(q1), at(mid), at(q3), firsts.len(), ent.join(", "));
    format!("mean ± 95% (t) of {n} sessions: cumulative reward {reward} | first reward: median episode {mid} (Q1..Q3 {q1}..{q3}), {k} of {n} rewarded | normalised entropy of the terminal cells per start context: {ent}")
}

/// A session's rows of `trials.csv`, written as its episodes run (a
/// [`CsvPart`]): a row per command.
struct EpisodeCsv {
    part: CsvPart,
    space: CommandSpace,
    /// The start contexts' names, as CSV fields.
    names: Vec<String>,
    session: usize,
    episode: usize,
    command: usize,
    start: usize,
}

impl EpisodeRecorder for EpisodeCsv {
    fn start(&mut self, start: usize) {
        self.episode += 1;
        self.command = 0;
        self.start = start;
    }
    fn record(&mut self, context: usize, command: &e3d::Command, outcome: &e3d::Outcome) {
        use std::io::Write;
        self.command += 1;
        let (session, episode, k) = (self.session, self.episode, self.command);
        let (name, command) = (&self.names[self.start], self.space.format(command));
        let (effect, reward) = (outcome.effect, outcome.reward);
        self.part.row(|out| {
            writeln!(
                out,
                "{session},{episode},{k},{context},{name},{command},{effect},{reward}"
            )
        });
    }
}
