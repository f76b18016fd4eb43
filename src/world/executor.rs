//! The executor: carries out a scene's [`ExecutionPlan`] (its table, its
//! memo or live worlds) and hands out the worlds sessions run on.

use super::plan::{Costs, ExecOptions, ExecutionPlan, OnDisk, Strategy, Workload};
use super::{
    ContinuousScene, Memoized, Outcome, OutcomeMemo, OutcomeTable, PhysicsWorld, World, WorldError,
};
use crate::scene::physics::noise_refusal;
use crate::scene::{Scene, WorldSpec};
use crate::world::table::CachedOutcomes;
use crate::world::Control;
use std::path::{Path, PathBuf};

/// Carries out an [`ExecutionPlan`] for one scene: holds its table or its
/// memo, makes the worlds sessions run on, and keeps the outcomes in the
/// table folder at the end.
///
/// ```
/// use e3d::world::{ExecOptions, Executor, Strategy, Workload};
/// use e3d::{Scene, World};
/// let scene = Scene::builtin("puck_rooms").unwrap();
/// let work = Workload { trials: 100, sessions: 1, threads: 1 };
/// let exec = Executor::new(&scene, &work, &ExecOptions::default()).unwrap();
/// assert_eq!(exec.plan().strategy, Strategy::Memo);
/// let mut world = exec.world(1);
/// let c = world.command_space().parse("SEEEEES").unwrap();
/// assert_eq!(world.execute(&c).unwrap(), scene.build().execute(&c).unwrap());
/// ```
pub struct Executor<'s> {
    scene: &'s Scene,
    plan: ExecutionPlan,
    table: Option<OutcomeTable>,
    memo: Option<OutcomeMemo>,
    cache: Option<PathBuf>,
    /// Entries the memo held when read from disk.
    read: usize,
}

impl<'s> Executor<'s> {
    /// Reads the table folder of `options` if given, chooses the plan
    /// (or takes the one forced) and prepares it: the table read or built
    /// (on the current rayon pool), the memo filled from a partial file. A
    /// table that cannot be built (some command blows up) falls back to
    /// the memo or live execution: only the sessions that meet the failing
    /// command fail.
    pub fn new(
        scene: &'s Scene,
        work: &Workload,
        options: &ExecOptions,
    ) -> Result<Executor<'s>, WorldError> {
        Self::with_control(scene, work, options, &Control::default())
    }

    /// [`new`](Self::new) under `control`, while a table is built: told
    /// the `total` commands to simulate, then of each chunk simulated;
    /// asked before each chunk whether to stop (then the error is
    /// [`WorldError::Stopped`] and no executor is made). The executor is
    /// the same.
    pub fn with_control(
        scene: &'s Scene,
        work: &Workload,
        options: &ExecOptions,
        control: &Control<'_>,
    ) -> Result<Executor<'s>, WorldError> {
        scene
            .spec()
            .require_symbols("an executor (table, memo or lockstep)")
            .map_err(|e| WorldError::Other(e.to_string()))?;
        let memo_cap = options.memo_cap;
        let space = scene.command_space();
        let path = options
            .cache
            .as_deref()
            .map(|dir| OutcomeTable::cache_path(scene, dir));
        let (on_disk, mut file) = read_cache(path.as_deref(), scene);
        let deterministic = scene.build().is_deterministic();
        let mut plan = ExecutionPlan::choose(scene, work, Some(&on_disk), memo_cap);
        if let Some(force) = options.force {
            force_strategy(&mut plan, force, scene, memo_cap);
        }
        if let (WorldSpec::Physics(p), true) = (&scene.spec().world, !deterministic) {
            // a table or memo asked for is refused, not silently dropped
            let what = match options.force {
                Some(Strategy::Table) => Some("an outcome table (--outcomes table)"),
                Some(Strategy::Memo) => Some("a memo (--outcomes memo)"),
                _ if options.cache.is_some() => Some("a table cache"),
                _ => None,
            };
            if let (Some(what), Some(_)) = (what, p.active_noise()) {
                let name = &scene.spec().name;
                return Err(WorldError::Other(noise_refusal(name, what)));
            }
        }
        if !deterministic {
            plan.strategy = Strategy::Live;
            plan.why = match &scene.spec().world {
                WorldSpec::Physics(p) if p.active_noise().is_some() => {
                    "the scene's `noise` section draws anew at every execution".into()
                }
                _ => "the world is not deterministic".into(),
            };
        }
        let mut exec = Executor {
            scene,
            table: None,
            memo: None,
            cache: path,
            read: 0,
            plan,
        };
        if exec.plan.strategy == Strategy::Table {
            let built = match file {
                Some(CachedOutcomes::Full(t)) => {
                    file = None;
                    Ok(t)
                }
                // what a partial file holds is not simulated again
                Some(CachedOutcomes::Partial(ref known)) => exec.build_table(known, control),
                None => exec.build_table(&[], control),
            };
            match built {
                Ok(t) => exec.table = Some(t),
                // stopped: no fallback to a memo or live execution
                Err(e @ WorldError::Stopped) => return Err(e),
                Err(e) => {
                    exec.plan.strategy = if memo_cap > 0 {
                        Strategy::Memo
                    } else {
                        Strategy::Live
                    };
                    exec.plan.why = format!("no table: {e}");
                }
            }
        }
        if exec.plan.strategy == Strategy::Memo {
            let memo = OutcomeMemo::new(&space, scene.num_effects(), memo_cap)?;
            if let Some(CachedOutcomes::Partial(entries)) = file {
                memo.extend(entries);
            }
            exec.read = memo.len();
            exec.memo = Some(memo);
        }
        Ok(exec)
    }

    /// The executor of a scene of continuous commands: always live (values
    /// cannot be tabled or memoised), sessions in lockstep groups of
    /// `plan().copies` commands to a world where the scene's copies are
    /// exact, else one per world. A scene of symbols is an error (its
    /// executor is [`new`](Self::new)).
    ///
    /// ```
    /// use e3d::world::{Executor, Strategy, Workload};
    /// use e3d::Scene;
    /// let scene = Scene::builtin("arm7_continuous").unwrap();
    /// let work = Workload { trials: 5000, sessions: 4, threads: 2 };
    /// let exec = Executor::for_values(&scene, &work).unwrap();
    /// assert_eq!(exec.plan().strategy, Strategy::Live);
    /// // arm7's copies are not bit-identical: one session per world
    /// assert_eq!(exec.plan().copies, 1);
    /// assert_eq!(exec.session_groups(4), vec![0..1, 1..2, 2..3, 3..4]);
    /// let arm7 = Scene::builtin("arm7").unwrap();
    /// assert!(Executor::for_values(&arm7, &work).is_err());
    /// ```
    pub fn for_values(scene: &'s Scene, work: &Workload) -> Result<Executor<'s>, WorldError> {
        if scene.as_continuous().is_none() {
            return Err(WorldError::Other(format!(
                "scene `{}` takes symbols: its sessions run on Executor::new, not on an executor of continuous commands",
                scene.spec().name
            )));
        }
        Ok(Executor {
            scene,
            plan: ExecutionPlan::choose(scene, work, None, 0),
            table: None,
            memo: None,
            cache: None,
            read: 0,
        })
    }

    /// The executor's scene as a continuous scene (its slots take
    /// values); `None` for a scene of symbols, whose executor is
    /// [`new`](Self::new).
    pub fn continuous(&self) -> Option<ContinuousScene<'s>> {
        self.scene.as_continuous()
    }

    /// The copies of the world a group of `width` sessions steps on
    /// together: `min(width, plan copies)`, at least 1. The outcomes are
    /// the same, bit for bit, whatever the copies.
    pub fn copies_for(&self, width: usize) -> usize {
        width.clamp(1, self.plan.copies.max(1))
    }

    /// The table of the scene from the outcomes `known`, kept in the table
    /// folder if there is one (a failure to write is said in the plan).
    fn build_table(
        &mut self,
        known: &[(u64, Outcome)],
        control: &Control<'_>,
    ) -> Result<OutcomeTable, WorldError> {
        let n = self.plan.commands.unwrap_or(0);
        let total = self
            .plan
            .simulated
            .unwrap_or(n)
            .saturating_sub(known.len() as u64);
        (control.total)(total);
        let t = OutcomeTable::complete_with(self.scene, known, control)?;
        if let Some(p) = &self.cache {
            if let Err(e) = t.write_file(p, self.scene) {
                self.plan.why.push_str(&format!(
                    "; the table could not be kept in {}: {e}",
                    p.display()
                ));
                // the plan line then does not also say it "will be kept"
                self.plan.on_disk = OnDisk::NoCache;
            }
        }
        Ok(t)
    }

    /// The plan being carried out.
    pub fn plan(&self) -> &ExecutionPlan {
        &self.plan
    }

    /// The table, under [`Strategy::Table`].
    pub fn table(&self) -> Option<&OutcomeTable> {
        self.table.as_ref()
    }

    /// The memo, under [`Strategy::Memo`].
    pub fn memo(&self) -> Option<&OutcomeMemo> {
        self.memo.as_ref()
    }

    /// The groups of `sessions` sessions that step together on one world
    /// ([`world`](Self::world)), as ranges of session indices, in order:
    /// each session alone on a table (a look-up gains nothing from
    /// company), else the plan's [`groups`](ExecutionPlan::groups), as even
    /// as can be. The one rule of [`run_sessions`](crate::run_sessions)
    /// and the sweeps.
    ///
    /// ```
    /// use e3d::world::{ExecOptions, Executor, Strategy, Workload};
    /// use e3d::Scene;
    /// let scene = Scene::builtin("arm7").unwrap();
    /// let work = Workload { trials: 800, sessions: 4, threads: 2 };
    /// let memo = ExecOptions { force: Some(Strategy::Memo), ..ExecOptions::default() };
    /// let exec = Executor::new(&scene, &work, &memo).unwrap();
    /// // arm7's copies are not bit-identical: a world each, 4 groups
    /// assert_eq!(exec.plan().groups, 4);
    /// assert_eq!(exec.session_groups(4), vec![0..1, 1..2, 2..3, 3..4]);
    /// assert_eq!(exec.session_groups(6), vec![0..2, 2..4, 4..6]);
    /// assert_eq!(exec.session_groups(3), vec![0..1, 1..2, 2..3]);
    /// let table = ExecOptions { force: Some(Strategy::Table), ..ExecOptions::default() };
    /// let rooms = Scene::builtin("two_rooms").unwrap();
    /// let exec = Executor::new(&rooms, &work, &table).unwrap();
    /// assert_eq!(exec.session_groups(3), vec![0..1, 1..2, 2..3]);
    /// ```
    pub fn session_groups(&self, sessions: usize) -> Vec<std::ops::Range<usize>> {
        let groups = if self.table.is_some() {
            sessions
        } else {
            self.plan.groups.max(1)
        };
        let size = sessions.div_ceil(groups.max(1)).max(1);
        (0..sessions)
            .step_by(size)
            .map(|start| start..(start + size).min(sessions))
            .collect()
    }

    /// A world for a group of sessions stepping `width` commands together:
    /// the shared table, or a world of `min(width, plan copies)` copies
    /// (through the memo under [`Strategy::Memo`]). Its outcomes are the
    /// same, bit for bit, whatever the width.
    pub fn world(&self, width: usize) -> Box<dyn World + Send + '_> {
        if let Some(t) = &self.table {
            return Box::new(t);
        }
        let copies = self.copies_for(width);
        let inner: Box<dyn World + Send> = match &self.scene.spec().world {
            WorldSpec::Physics(p) if copies > 1 => {
                Box::new(PhysicsWorld::of(self.scene, p, copies))
            }
            _ => self.scene.build(),
        };
        match &self.memo {
            Some(m) => Box::new(Memoized::new(inner, m)),
            None => inner,
        }
    }

    /// Keeps the memo's outcomes in the table folder (merged with what
    /// the file holds now, written whole or not at all) and returns one
    /// line saying what was simulated and kept; `None` without a memo.
    pub fn finish(&self) -> Option<String> {
        let memo = self.memo.as_ref()?;
        let mut line = format!(
            "{}: {} commands simulated, {} looked up in the memo ({} kept{})",
            self.scene.spec().name,
            memo.misses(),
            memo.hits(),
            memo.len(),
            if memo.is_full() {
                "; the memo is full: raise --memo-cap to keep more"
            } else {
                ""
            }
        );
        let Some(path) = &self.cache else {
            return Some(line);
        };
        if memo.len() == self.read {
            return Some(line);
        }
        match memo.save(path, self.scene) {
            Ok(n) => line.push_str(&format!("; {n} outcomes kept in {}", path.display())),
            Err(e) => line.push_str(&format!("; could not write {}: {e}", path.display())),
        }
        Some(line)
    }
}

/// What the cache file at `path` (none: no cache) holds for `scene`: its
/// state for the plan, and the outcomes read.
fn read_cache(path: Option<&Path>, scene: &Scene) -> (OnDisk, Option<CachedOutcomes>) {
    let path = match (path, scene.command_space().num_commands()) {
        (None, _) => return (OnDisk::NoCache, None),
        (Some(_), None) => return (OnDisk::TooLarge, None),
        (Some(p), Some(_)) => p.to_path_buf(),
    };
    match OutcomeTable::read_file(&path, scene) {
        Ok(file) => {
            let on_disk = match &file {
                CachedOutcomes::Full(_) => OnDisk::Full { path },
                CachedOutcomes::Partial(e) => OnDisk::Partial {
                    path,
                    entries: e.len() as u64,
                },
            };
            (on_disk, Some(file))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => (OnDisk::Missing { path }, None),
        Err(e) => {
            let reason = e.to_string().rsplit(": ").next().unwrap_or("").to_string();
            (OnDisk::Unusable { path, reason }, None)
        }
    }
}

/// Forces `plan` to the strategy `force` when it can be used (a table
/// then of as many copies as the scene's are exact), else tells why not.
fn force_strategy(plan: &mut ExecutionPlan, force: Strategy, scene: &Scene, memo_cap: usize) {
    let possible = match force {
        Strategy::Table => plan.simulated.is_some(),
        Strategy::Memo => plan.commands.is_some() && memo_cap > 0,
        Strategy::Live => true,
    };
    if possible && force != plan.strategy {
        plan.why = format!("asked for (the cost rule chose {})", plan.strategy);
        plan.strategy = force;
        if force == Strategy::Table {
            plan.copies = Costs::of(scene).copies();
        }
    } else if !possible {
        plan.why = format!("{force} was asked for but cannot be used: {}", plan.why);
    }
}
