//! Running a sweep: one session, sessions in lockstep, all of them on a
//! thread pool, and resumably into a folder.

use super::factory::{mismatch, SweepScene};
use super::journal::{self, Journal, JournalHeader};
use super::plan::{Cell, SessionSpec, Shard, Sweep};
use super::results::{
    version_line, write_final, DirReport, SessionResult, JOURNAL, SWEEP_COPY, VERSION, VERSION_FILE,
};
use super::spec::MetricSpec;
use super::{io_err, BoxError, SweepError};
use crate::command::Command;
use crate::effect::Target;
use crate::hash::fnv1a64;
use crate::learner::Effort;
use crate::scene::Scene;
use crate::session::{
    self, run_group, run_planned, Control, Executes, Learns, RunningMetrics, SessionConfig,
};
use crate::world::{Executor, Workload, World, WorldError};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::panic::AssertUnwindSafe;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::mpsc::Sender;

impl Sweep {
    /// Runs one session on `world` (a world of the session's scene, or its
    /// outcome table), in constant memory. A world of another command
    /// space, or with another number of effects, is refused with an error
    /// naming both.
    ///
    /// ```
    /// use e3d::{Scene, Sweep};
    /// let sweep = Sweep::parse(r#"Sweep(scenes: ["two_rooms"], learners: [e3d], sessions: 1, trials: 50)"#, "s.ron", None).unwrap();
    /// let session = sweep.sessions()[0];
    /// let mut rooms = Scene::builtin("two_rooms").unwrap().build();
    /// assert!(sweep.run_session(&session, &mut *rooms).is_ok());
    /// let mut arm = Scene::builtin("arm7").unwrap().build();
    /// let e = sweep.run_session(&session, &mut *arm).unwrap_err().to_string();
    /// assert!(e.contains("whose commands are 7 slots of `ESWN` with 18 effects"), "{e}");
    /// assert!(e.contains("but the world's commands are 7 slots of `-0+`"), "{e}");
    /// ```
    pub fn run_session(
        &self,
        session: &SessionSpec,
        world: &mut dyn World,
    ) -> Result<SessionResult, SweepError> {
        let scene = &self.scenes[self.cells[session.cell].scene];
        if let Some(why) = mismatch(&scene.command_space(), scene.num_effects(), world) {
            return Err(SweepError::Other(format!(
                "session {} is of scene `{}`, {why}",
                session.index,
                scene.name()
            )));
        }
        let effort = scene.scene().map(Effort::of_scene);
        let (space, n) = (world.command_space(), world.num_effects());
        let learner = self.symbols_learner(session, space, n, effort.as_ref())?;
        let mut results = self.run_group_on(std::slice::from_ref(session), world, vec![learner]);
        Ok(results.remove(0))
    }

    /// Runs `sessions` (one group of one scene) with their `learners`
    /// together on `world`, a world of symbols or of values
    /// ([`run_group`]), each into its running metrics: their results, in
    /// order.
    fn run_group_on<C, W, L>(
        &self,
        sessions: &[SessionSpec],
        world: &mut W,
        mut learners: Vec<L>,
    ) -> Vec<SessionResult>
    where
        C: Clone + crate::learner::Effortful,
        W: Executes<C> + ?Sized,
        L: Learns<C>,
    {
        let configs: Vec<SessionConfig> = sessions.iter().map(|s| self.config(s)).collect();
        // the qd_score by the scene's effort (none for worlds made by code)
        let scene = sessions
            .first()
            .map(|s| &self.scenes[self.cells[s.cell].scene]);
        let effort = scene.and_then(|s| s.scene()).map(Effort::of_scene);
        let recorder = || match &effort {
            Some(e) => self.recorder(world.effects()).with_effort(e.clone()),
            None => self.recorder(world.effects()),
        };
        let mut recorders: Vec<RunningMetrics> = sessions.iter().map(|_| recorder()).collect();
        let count = |t| self.count_trials(t);
        let control = Control::default().with_progress(&count);
        let status = run_group(world, &mut learners, &configs, &mut recorders, &control);
        let repro = self
            .metrics
            .iter()
            .position(|m| *m == MetricSpec::Reproducibility);
        let options = session::RepeatOptions::default();
        (sessions.iter().zip(status).zip(&recorders).zip(&learners))
            .map(|(((s, st), m), learner)| {
                let mut result = self.result(s, st, m);
                if let (Some(k), None) = (repro, &result.failure) {
                    match session::reproducibility(world, learner, options, s.seed) {
                        Ok(r) => result.values[k] = r.map(|r| r.share),
                        Err(e) => {
                            result.values.iter_mut().for_each(|v| *v = None);
                            result.failure = Some(e.to_string());
                        }
                    }
                }
                result
            })
            .collect()
    }

    /// A learner of symbols for `session` on `space` and `n` effects,
    /// MAP-Elites' elites by `effort`.
    fn symbols_learner(
        &self,
        session: &SessionSpec,
        space: &crate::command::CommandSpace,
        n: usize,
        effort: Option<&Effort>,
    ) -> Result<Box<dyn crate::Learner + Send>, SweepError> {
        self.learner(session, |c| {
            let uniform = &Target::Uniform;
            (self.learners).make(&c.learner, &c.params, space, n, uniform, effort)
        })
    }

    /// What `make` makes for the cell of `session` (its learner), its
    /// error naming the learner.
    pub(super) fn learner<T>(
        &self,
        session: &SessionSpec,
        make: impl FnOnce(&Cell) -> Result<T, BoxError>,
    ) -> Result<T, SweepError> {
        let cell = &self.cells[session.cell];
        make(cell).map_err(|source| SweepError::Learner {
            learner: cell.learner.clone(),
            source,
        })
    }

    pub(super) fn config(&self, session: &SessionSpec) -> SessionConfig {
        SessionConfig {
            trials: self.spec.trials,
            seed: session.seed,
            use_reward: self.cells[session.cell].use_reward,
        }
    }

    /// The running metrics a session on a world of `num_effects` effects
    /// keeps: the cumulative reward at the trials the metrics name.
    pub(super) fn recorder(&self, num_effects: usize) -> RunningMetrics {
        let checkpoints: Vec<usize> = self
            .metrics
            .iter()
            .filter_map(|m| match *m {
                MetricSpec::CumulativeReward(t) => Some(t),
                _ => None,
            })
            .collect();
        RunningMetrics::with_checkpoints(num_effects, &checkpoints)
    }

    pub(super) fn result(
        &self,
        session: &SessionSpec,
        status: Result<(), WorldError>,
        running: &RunningMetrics,
    ) -> SessionResult {
        if let Err(e) = status {
            return SessionResult {
                session: *session,
                values: vec![None; self.metrics.len()],
                failure: Some(e.to_string()),
            };
        }
        let m = match self.reachable_effects(self.cells[session.cell].scene) {
            Some(k) => running.metrics_over_reachable(&Target::Uniform, k),
            None => running.metrics(&Target::Uniform),
        };
        let values = self
            .metrics
            .iter()
            .map(|spec| match *spec {
                MetricSpec::NormalizedEntropy => Some(m.normalized_entropy),
                MetricSpec::NormalizedEntropyLast1000 => Some(m.normalized_entropy_last_1000),
                MetricSpec::KlToTarget => Some(m.kl_to_target),
                MetricSpec::DistinctEffects => Some(m.distinct_effects as f64),
                MetricSpec::CumulativeReward(t) => running.cumulative_reward_at(t),
                MetricSpec::FirstRewardTrial => m.first_reward_trial.map(|t| t as f64),
                MetricSpec::Coverage => Some(m.coverage),
                MetricSpec::TrialsTo50Percent => m.trials_to_50_percent.map(|t| t as f64),
                MetricSpec::TrialsTo90Percent => m.trials_to_90_percent.map(|t| t as f64),
                MetricSpec::QdScore => m.qd_score,
                // set by run_episode_session
                MetricSpec::NormalizedEntropyContext(_)
                | MetricSpec::CumulativeRewardContext(_)
                | MetricSpec::FirstRewardTrialContext(_) => None,
                // set by run_group_on, which holds the world and learner
                MetricSpec::Reproducibility => None,
            })
            .collect();
        SessionResult {
            session: *session,
            values,
            failure: None,
        }
    }

    /// Runs `sessions` on a local pool of `threads` threads, calling
    /// `on_result` on the calling thread as each one finishes (in no
    /// particular order). Each scene's outcomes come from the [`Executor`]
    /// its workload chooses (told to [`with_notices`](Self::with_notices));
    /// the results are the same bytes whatever it chooses and whatever the
    /// threads. An error from `on_result` or from a session stops the
    /// sweep and is returned.
    pub fn run_with(
        &self,
        sessions: &[SessionSpec],
        threads: usize,
        mut on_result: impl FnMut(SessionResult) -> Result<(), SweepError>,
    ) -> Result<(), SweepError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.clamp(1, max_threads()))
            .build()
            .map_err(|e| SweepError::Other(format!("cannot start the threads: {e}")))?;
        let work = self.workloads(sessions, pool.current_num_threads());
        let executors: Vec<Option<Executor<'_>>> = pool.install(|| {
            self.scenes
                .iter()
                .zip(&work)
                .enumerate()
                .map(|(si, (scene, w))| self.scene_run(si, scene, w))
                .collect::<Result<_, SweepError>>()
        })?;
        let executors = &executors;
        let outcome = std::thread::scope(|scope| {
            let (tx, rx) = std::sync::mpsc::channel();
            let pool = &pool;
            scope.spawn(move || pool.install(|| self.run_scenes(executors, sessions, &tx)));
            let mut outcome = Ok(());
            while let Ok(r) = rx.recv() {
                if let Err(e) = r.and_then(&mut on_result) {
                    outcome = Err(e);
                    break;
                }
            }
            drop(rx);
            outcome
        });
        for exec in executors.iter().flatten() {
            if let Some(line) = Executor::finish(exec) {
                self.notice(&line);
            }
        }
        outcome
    }

    /// Runs `sessions`, every scene's groups in parallel through the
    /// engine ([`run_planned`]) on the one pool, sending each result, or
    /// the error that stops the sweep, to `tx`; stops once nobody listens.
    fn run_scenes(
        &self,
        executors: &[Option<Executor<'_>>],
        sessions: &[SessionSpec],
        tx: &Sender<Result<SessionResult, SweepError>>,
    ) {
        let gone = AtomicBool::new(false);
        executors.par_iter().enumerate().for_each(|(si, exec)| {
            let mine: Vec<SessionSpec> = sessions
                .iter()
                .filter(|s| self.cells[s.cell].scene == si)
                .copied()
                .collect();
            if mine.is_empty() || gone.load(Relaxed) {
                return;
            }
            let scene = &*self.scenes[si];
            let out = (tx, &gone);
            let space = scene.command_space();
            let effort = scene.scene().map(Effort::of_scene);
            let effort = effort.as_ref();
            let symbols = |s: &SessionSpec, n| self.symbols_learner(s, &space, n, effort);
            // sessions of episodes: all of a scene that runs them, and
            // per-move Q-learning's on any scene
            let (episodic, mine): (Vec<SessionSpec>, Vec<SessionSpec>) = (mine.into_iter())
                .partition(|s| self.runs_episodes(si) || self.per_move(s));
            episodic.par_iter().for_each(|s| {
                self.guarded(std::slice::from_ref(s), out, || {
                    let file = scene.scene().ok_or_else(|| {
                        SweepError::Other(format!(
                            "scene `{}` is made by code: a sweep of episodes runs scene files (their worlds start from contexts and states)",
                            scene.name()
                        ))
                    })?;
                    Ok(vec![self.run_episode_session(s, file)?])
                })
            });
            if mine.is_empty() {
            } else if let SweepScene::Live(live) = scene {
                self.run_scene(live, &mine, out, symbols);
            } else if let Some(values) = scene.scene().and_then(Scene::value_space) {
                let exec = exec.as_ref().expect("a scene with work");
                let worlds: &dyn session::Worlds<Vec<f64>> = exec;
                self.run_scene(worlds, &mine, out, |s, n| {
                    self.learner(s, |c| {
                        let uniform = &Target::Uniform;
                        let learners = &self.learners;
                        learners.make_continuous(&c.learner, &c.params, &values, n, uniform, effort)
                    })
                });
            } else {
                let exec = exec.as_ref().expect("a scene with work");
                let worlds: &dyn session::Worlds<Command> = exec;
                self.run_scene(worlds, &mine, out, symbols);
            }
        });
    }

    /// Runs `mine`, the sessions of one scene, in the groups `worlds`
    /// plans ([`run_planned`]), each with the learner `learner(session,
    /// effects)` makes, into `out`.
    fn run_scene<C: Clone + crate::learner::Effortful, L: Learns<C>>(
        &self,
        worlds: &(impl session::Worlds<C> + ?Sized),
        mine: &[SessionSpec],
        out: Out<'_>,
        learner: impl Fn(&SessionSpec, usize) -> Result<L, SweepError> + Sync,
    ) {
        let groups = worlds.session_groups(mine.len());
        let parts = groups.into_iter().map(|g| (g.len(), &mine[g])).collect();
        run_planned(worlds, parts, |unit, world| {
            self.guarded(unit, out, || {
                let world = world.map_err(|e| {
                    let name = self.scenes[self.cells[unit[0].cell].scene].name();
                    SweepError::Other(format!(
                        "session {} is of scene `{name}`, {e}",
                        unit[0].index
                    ))
                })?;
                let learners = unit
                    .iter()
                    .map(|s| learner(s, world.effects()))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(self.run_group_on(unit, world, learners))
            })
        });
    }

    /// Sends to `out` the results of `unit` that `run` gives, or the error
    /// that stops the sweep, unless nobody listens any more: a panic inside
    /// the engine fails the unit's sessions, recorded so, not the whole
    /// sweep.
    fn guarded(
        &self,
        unit: &[SessionSpec],
        (tx, gone): Out<'_>,
        run: impl FnOnce() -> Result<Vec<SessionResult>, SweepError>,
    ) {
        if gone.load(Relaxed) {
            return;
        }
        let results = std::panic::catch_unwind(AssertUnwindSafe(run)).unwrap_or_else(|p| {
            let why = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "no message".into());
            Ok(unit
                .iter()
                .map(|s| SessionResult {
                    session: *s,
                    values: vec![None; self.metrics.len()],
                    failure: Some(format!("the simulation panicked: {why}")),
                })
                .collect())
        });
        let sent = match results {
            Ok(rs) => rs.into_iter().try_for_each(|r| tx.send(Ok(r))),
            Err(e) => tx.send(Err(e)),
        };
        if sent.is_err() {
            gone.store(true, Relaxed);
        }
    }

    /// How scene `si` (`scene`, with workload `w`) runs, told to the
    /// notice callback: none without sessions, its episode worlds, live
    /// worlds made by code, or the cheapest of a table, a memo or live
    /// execution (its table's building told to the table progress).
    fn scene_run<'a>(
        &'a self,
        si: usize,
        scene: &'a SweepScene,
        w: &Workload,
    ) -> Result<Option<Executor<'a>>, SweepError> {
        if w.sessions == 0 {
            return Ok(None);
        }
        let file = match (scene, self.runs_episodes(si)) {
            (SweepScene::Scene(file), true) => {
                let (k, c) = (self.spec.commands, self.start_contexts(si));
                let plural = |n| if n == 1 { "" } else { "s" };
                let (name, ks, cs) = (&file.spec().name, plural(k), plural(c));
                self.notice(&format!(
                    "{name}: episodes of {k} command{ks} from {c} start context{cs}: each session on a live world of its own"
                ));
                return Ok(None);
            }
            (SweepScene::Live(_), _) => {
                self.notice(&format!(
                    "{}: live execution: each session on a fresh world of its own (a world made by code)",
                    scene.name()
                ));
                return Ok(None);
            }
            (SweepScene::Scene(file), false) => file,
        };
        // a table or memo forced on a continuous scene was refused by
        // Sweep::with_strategy
        let e = if file.spec().is_continuous() {
            Executor::for_values(file, w)?
        } else if let Some(f) = &self.table_progress {
            use std::sync::atomic::AtomicU64;
            let name = scene.name();
            let (told, size) = (AtomicBool::new(false), AtomicU64::new(0));
            let total = |n| size.store(n, Relaxed);
            let progress = |k| {
                told.store(true, Relaxed);
                f(name, k, size.load(Relaxed))
            };
            let control = Control {
                progress: &progress,
                total: &total,
                ..Control::default()
            };
            let e = Executor::with_control(file, w, &self.exec, &control);
            // the end of what was told, built or not
            if told.load(Relaxed) {
                f(name, 0, 0);
            }
            e?
        } else {
            Executor::with_control(file, w, &self.exec, &Control::default())?
        };
        self.notice(&e.plan().to_string());
        Ok(Some(e))
    }

    /// Runs every session on `threads` threads and returns the results in
    /// canonical order.
    pub fn run(&self, threads: usize) -> Result<Vec<SessionResult>, SweepError> {
        let sessions = self.sessions();
        let mut out: Vec<Option<SessionResult>> = vec![None; sessions.len()];
        self.run_with(&sessions, threads, |r| {
            let i = r.session.index;
            out[i] = Some(r);
            Ok(())
        })?;
        Ok(out.into_iter().flatten().collect())
    }

    /// Runs the sweep (or one shard of it) into the folder `dir`, resumably.
    ///
    /// The folder receives `sweep.ron` (a copy of the file), `version.txt`,
    /// `journal.txt` (every finished session, one checksummed line each,
    /// appended as they finish) and, once every session of the shard is in
    /// the journal, `results.csv` (one row per session, canonical order)
    /// and, for a whole sweep, `summary.csv` (one row per cell). The final
    /// files are written atomically from the journal, so that a run killed
    /// at any moment and resumed gives the same bytes as an uninterrupted
    /// one.
    ///
    /// Without `options.resume`, a folder that exists and is not empty is
    /// refused. With it, the folder must hold the same sweep file (byte for
    /// byte), the same e3d version and the same shard; only the missing
    /// sessions run. `progress(done, total)` is called after each session.
    pub fn run_to_dir(
        &self,
        dir: &Path,
        options: &DirOptions,
        mut progress: impl FnMut(usize, usize),
    ) -> Result<DirReport, SweepError> {
        let shard = options.shard;
        let journal_path = dir.join(JOURNAL);
        let header = self.journal_header(shard);
        Self::prepare_dir(dir, options.resume)?;
        self.copy_sweep_and_version(dir)?;
        let (mut journal, mut done) = open_journal(&journal_path, &header)?;
        let mine: Vec<SessionSpec> = (self.sessions().into_iter())
            .filter(|s| shard.contains(s.index))
            .collect();
        done.retain(|i, _| shard.contains(*i) && *i < header.total);
        let resumed = done.len();
        let todo: Vec<SessionSpec> = mine
            .iter()
            .filter(|s| !done.contains_key(&s.index))
            .copied()
            .collect();
        let total = mine.len();
        progress(done.len(), total);
        let mut count = done.len();
        self.run_with(&todo, options.threads, |r| {
            let row = self.result_row(&r);
            journal.push(r.session.index, &row)?;
            done.insert(r.session.index, row);
            count += 1;
            progress(count, total);
            Ok(())
        })?;
        journal.sync()?;
        drop(journal);
        write_final(dir, &header, &done)?;
        Ok(DirReport {
            sessions: total,
            resumed,
            ran: todo.len(),
        })
    }

    /// The journal's header for `shard` of this sweep.
    fn journal_header(&self, shard: Shard) -> JournalHeader {
        let scenes = self.scenes.iter();
        let scenes = scenes.map(|s| (s.name().to_string(), s.content_key()));
        JournalHeader {
            sweep_hash: fnv1a64(self.text.as_bytes()),
            shard,
            total: self.num_sessions(),
            per_cell: self.spec.sessions,
            scenes: scenes.collect(),
            version: VERSION.to_string(),
            columns: self.results_header(),
        }
    }

    /// Makes `dir`: a new or empty folder (temporary files of a killed
    /// copy removed), or with `resume` one that holds a sweep to complete.
    fn prepare_dir(dir: &Path, resume: bool) -> Result<(), SweepError> {
        let shown = dir.display();
        if dir.exists() && !dir.is_dir() {
            return Err(SweepError::Output(format!(
                "{shown}: exists and is not a folder"
            )));
        }
        // a folder that holds only temporary files of write_atomic (never
        // renamed, so never part of a sweep) was left by a run killed
        // while copying the sweep file: it counts as empty, and they go
        let mut non_empty = false;
        let mut temporaries = Vec::new();
        if dir.is_dir() {
            for entry in std::fs::read_dir(dir).map_err(io_err(dir))? {
                let entry = entry.map_err(io_err(dir))?;
                let name = entry.file_name().to_string_lossy().into_owned();
                match name.as_str() {
                    crate::io::LOCK_FILE => {}
                    _ if crate::io::is_temporary(&name) => temporaries.push(entry.path()),
                    _ => non_empty = true,
                }
            }
        }
        if !non_empty {
            for t in temporaries {
                let _ = std::fs::remove_file(t);
            }
        } else {
            // those of a run killed while writing its results (a process
            // that still runs keeps its own)
            crate::io::remove_stale_temps(dir);
        }
        if non_empty && !resume {
            return Err(SweepError::Output(format!(
                "{shown} exists and is not empty; pass --resume to complete the sweep it holds, or choose another --out"
            )));
        }
        if non_empty && !dir.join(SWEEP_COPY).exists() {
            return Err(SweepError::Output(format!(
                "{shown}: holds no {SWEEP_COPY}, so no sweep to resume; choose another --out"
            )));
        }
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        Ok(())
    }

    /// Writes the copy of the sweep and the version into `dir`, or checks
    /// that those it holds are the same.
    fn copy_sweep_and_version(&self, dir: &Path) -> Result<(), SweepError> {
        // the copy of the sweep and the version: the same, or refused
        for (name, bytes) in [
            (SWEEP_COPY, self.text.as_bytes().to_vec()),
            (VERSION_FILE, version_line().into_bytes()),
        ] {
            let p = dir.join(name);
            match crate::text::read_own_bytes(&p, crate::scene::MAX_FILE_BYTES, name) {
                Ok(old) if old == bytes => {}
                Ok(_) => {
                    return Err(SweepError::Output(format!(
                        "{}: differs from this run's ({}); the folder holds another sweep or was made by another e3d version; choose another --out",
                        p.display(),
                        if name == SWEEP_COPY { self.file.clone() } else { format!("e3d {VERSION}") }
                    )))
                }
                Err(e) if e.is_not_found() => {
                    crate::io::write_atomic(&p, &bytes).map_err(io_err(&p))?
                }
                Err(e) => return Err(SweepError::Output(format!("{e}; choose another --out"))),
            }
        }
        Ok(())
    }
}

/// Where a sweep's threads send their results, and whether anybody still
/// listens.
type Out<'a> = (
    &'a Sender<Result<SessionResult, SweepError>>,
    &'a AtomicBool,
);

/// The journal at `journal_path`: a new one for `header`, or the existing
/// one (written by the same run: same sweep, scenes, version and shard)
/// reopened for appending, with the rows it holds.
fn open_journal(
    journal_path: &Path,
    header: &JournalHeader,
) -> Result<(Journal, BTreeMap<usize, String>), SweepError> {
    Ok(if journal_path.exists() {
        let read = journal::read(journal_path)?;
        let path = journal_path.display();
        if let Some((name, now, then)) = header.changed_scene(&read.header) {
            if read.header.sweep_hash == header.sweep_hash {
                return Err(SweepError::Output(format!(
                    "{path}: scene `{name}` changed since this folder's sessions ran (content {then:016x}, now {now:016x}); one results file cannot mix two versions of a scene: restore it, or choose another --out"
                )));
            }
        }
        if read.header != *header {
            let other = read.header.describe();
            let (shard, hash, total) = (header.shard, header.sweep_hash, header.total);
            return Err(SweepError::Output(format!(
                "{path}: written by another run ({other}); this run is shard {shard} of sweep {hash:016x} with {total} sessions; choose another --out"
            )));
        }
        let j = Journal::append(journal_path, read.valid_len)?;
        (j, read.rows)
    } else {
        (Journal::create(journal_path, header)?, BTreeMap::new())
    })
}

/// How [`Sweep::run_to_dir`] runs.
#[derive(Debug, Clone, Copy)]
pub struct DirOptions {
    /// Threads of the local pool.
    pub threads: usize,
    /// Complete the sweep an existing folder holds.
    pub resume: bool,
    /// Which part of the sweep ([`Shard::ALL`]: all of it).
    pub shard: Shard,
}

/// How many threads per core a sweep may use at most.
pub const THREADS_PER_CORE: usize = 4;

/// The most threads a sweep runs on: [`THREADS_PER_CORE`] times the
/// cores this process may use. More only add switching and memory (4096
/// threads on 2 cores made a 1.3 s sweep take minutes); the results are
/// the same whatever the number.
pub fn max_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get()) * THREADS_PER_CORE
}

/// `requested` threads capped at [`max_threads`], with the warning to
/// give when it was capped.
pub fn cap_threads(requested: usize) -> (usize, Option<String>) {
    let most = max_threads();
    if requested > most {
        (
            most,
            Some(format!(
                "--threads {requested}: capped at {most} ({THREADS_PER_CORE} per core on {} cores); more would only slow the run down",
                most / THREADS_PER_CORE
            )),
        )
    } else {
        (requested.max(1), None)
    }
}
