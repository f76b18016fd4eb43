//! How the commands of a run or a sweep are executed, decided by cost: a
//! [`Strategy`] (table, memo or live, the same outcomes bit for bit).
//! [`ExecutionPlan::choose`] estimates the time of each from the size of
//! the command space, the trials, the sessions that can step together,
//! the threads, the scene's symmetry and what a table file holds, and
//! takes the cheapest; [`Executor`] carries the plan out.
//!
//! ```
//! use e3d::world::{ExecutionPlan, Strategy, Workload, DEFAULT_MEMO_CAP};
//! use e3d::Scene;
//! let puck = Scene::builtin("puck_rooms").unwrap();
//! let work = |trials, sessions| Workload { trials, sessions, threads: 2 };
//! // 5000 trials of one session: the 16384-command table is cheaper
//! let plan = ExecutionPlan::choose(&puck, &work(5000, 1), None, DEFAULT_MEMO_CAP);
//! assert_eq!(plan.strategy, Strategy::Table);
//! // 200 trials: simulate only what the session proposes
//! let plan = ExecutionPlan::choose(&puck, &work(200, 1), None, DEFAULT_MEMO_CAP);
//! assert_eq!(plan.strategy, Strategy::Memo);
//! ```

use super::{
    OutcomeTable, PhysicsWorld, World, DEFAULT_MEMO_CAP, MAX_TABLE_COMMANDS, TABLE_COPIES,
};
use crate::command::{Command, CommandSpace};
use crate::scene::physics::BodyKind;
use crate::scene::{Scene, WorldSpec};
use serde::Serialize;
use std::fmt;
use std::path::PathBuf;
use std::time::Instant;

/// How outcomes are obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Strategy {
    /// Every command executed once up front ([`OutcomeTable`], many
    /// copies per Rapier world), or read whole from a table file; then
    /// looked up.
    Table,
    /// Each command executed once, as sessions propose it
    /// ([`OutcomeMemo`](super::OutcomeMemo)), the new commands of sessions in lockstep batched
    /// into multi-copy worlds.
    Memo,
    /// Every proposal executed (worlds that are not deterministic, grids
    /// whose moves cost less than a look-up, spaces of more than 2^64
    /// commands, continuous commands).
    Live,
}

/// A name that is not a [`Strategy`]'s (`table`, `memo` or `live`): what
/// [`Strategy::from_str`](std::str::FromStr::from_str) refuses.
///
/// ```
/// use e3d::world::{ParseStrategyError, Strategy};
/// let e: ParseStrategyError = "tables".parse::<Strategy>().unwrap_err();
/// assert_eq!(e.to_string(), "`tables`: expected table, memo or live");
/// assert_eq!(e.input(), "tables");
/// ```
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
#[error("`{input}`: expected table, memo or live")]
pub struct ParseStrategyError {
    input: String,
}

impl ParseStrategyError {
    /// The name that was refused.
    pub fn input(&self) -> &str {
        &self.input
    }
}

/// Each strategy's name, in the order of [`Strategy`]'s variants.
const NAMES: [(Strategy, &str); 3] = [
    (Strategy::Table, "table"),
    (Strategy::Memo, "memo"),
    (Strategy::Live, "live"),
];

impl std::str::FromStr for Strategy {
    type Err = ParseStrategyError;
    fn from_str(s: &str) -> Result<Strategy, ParseStrategyError> {
        let input = s.to_string();
        let known = NAMES.iter().find(|(_, name)| *name == s);
        known.map(|&(k, _)| k).ok_or(ParseStrategyError { input })
    }
}

impl fmt::Display for Strategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(NAMES[*self as usize].1)
    }
}

/// How a run or a sweep may obtain outcomes: the table folder, the memo's
/// cap, and a strategy imposed instead of chosen.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExecOptions {
    /// The folder of table files (whole or partial), read and written.
    pub cache: Option<PathBuf>,
    /// The most outcomes the memo keeps (0: no memo).
    pub memo_cap: usize,
    /// A strategy to use whatever it costs (`None`: the cheapest). A table
    /// asked of a space too large for one falls back to the memo.
    pub force: Option<Strategy>,
}

impl Default for ExecOptions {
    fn default() -> Self {
        ExecOptions {
            cache: None,
            memo_cap: DEFAULT_MEMO_CAP,
            force: None,
        }
    }
}

/// The work a plan is for: all the sessions of one scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Workload {
    /// The trials of all sessions together.
    pub trials: u64,
    /// The number of sessions (they may step together in lockstep).
    pub sessions: usize,
    /// The threads available.
    pub threads: usize,
}

/// What a table file holds, as far as a plan is concerned.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "state", rename_all = "lowercase")]
pub enum OnDisk {
    /// No table folder was given.
    NoCache,
    /// The file is not there yet (it will be written).
    Missing {
        /// The file.
        path: PathBuf,
    },
    /// A whole table.
    Full {
        /// The file.
        path: PathBuf,
    },
    /// Some commands' outcomes (a memo saved by an earlier run).
    Partial {
        /// The file.
        path: PathBuf,
        /// How many commands it holds.
        entries: u64,
    },
    /// A file that cannot be used (another format, damaged): it will be
    /// replaced.
    Unusable {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The command space has more than 2^64 commands: no table file.
    TooLarge,
}

impl OnDisk {
    fn entries(&self, n: u64) -> u64 {
        match self {
            OnDisk::Full { .. } => n,
            OnDisk::Partial { entries, .. } => *entries,
            _ => 0,
        }
    }
}

/// The decision for one scene and its estimated costs (seconds, from a
/// fixed cost model measured on the development machine: see
/// `docs/benchmarks.md`; only their ratios decide).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExecutionPlan {
    /// What was chosen.
    pub strategy: Strategy,
    /// The scene.
    pub scene: String,
    /// The commands of the space (`None`: more than 2^64, or continuous).
    pub commands: Option<u64>,
    /// Whether the scene's commands are continuous (values, not symbols):
    /// always live, one trial one rollout. Written in JSON only when
    /// `true` (the summaries of scenes of symbols keep their bytes).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub continuous: bool,
    /// The commands a table simulates (one of each mirror-image pair under
    /// a symmetry), when a table is possible.
    pub simulated: Option<u64>,
    /// Copies per Rapier world: commands stepped together (1 for grids and
    /// for scenes whose copies are not bit-identical to a single world).
    pub copies: usize,
    /// Groups of sessions in lockstep (memo and live); each group steps
    /// its sessions' new commands together.
    pub groups: usize,
    /// Whether copies of the scene in one world give a single world's
    /// outcomes bit for bit (else each world holds one copy).
    pub exact_copies: bool,
    /// The table file, if a folder was given.
    pub on_disk: OnDisk,
    /// The memo's cap on entries.
    pub memo_cap: usize,
    /// The estimated seconds of the table, if possible.
    pub table_seconds: Option<f64>,
    /// The estimated seconds of the sessions' own executions (memo or live).
    pub sessions_seconds: f64,
    /// Why, in a few words.
    pub why: String,
}

/// The cost model: seconds of one rollout and how copies share a step.
#[derive(Debug, Clone, Copy)]
pub(super) struct Costs {
    /// One command in a single-copy world.
    rollout: f64,
    /// The part of a rollout that copies in one world share (the rest is
    /// paid per copy).
    shared: f64,
    /// Whether copies are exact (else: one copy per world).
    exact: bool,
    /// Grids: executing is about as cheap as a look-up.
    grid: bool,
}

/// Seconds per trial of a look-up in a table and in a memo.
const TABLE_LOOKUP: f64 = 4e-9;
const MEMO_LOOKUP: f64 = 60e-9;
/// Seconds per command of the table's own bookkeeping and of reading it.
const TABLE_ENTRY: f64 = 100e-9;
const TABLE_READ: f64 = 30e-9;
/// A table that costs less than this is always taken: it also gives the
/// exact effect distribution of the final policy.
const CHEAP_TABLE: f64 = 0.05;

impl Costs {
    pub(super) fn of(scene: &Scene) -> Costs {
        match &scene.spec().world {
            WorldSpec::Grid(_) => Costs {
                rollout: 2e-9 * scene.spec().num_slots() as f64 + 1e-9,
                shared: 0.0,
                exact: false,
                grid: true,
            },
            WorldSpec::Physics(p) => {
                let moving = p
                    .bodies
                    .iter()
                    .filter(|b| b.kind != BodyKind::Fixed)
                    .count() as f64;
                let joints = p.joints.len() as f64;
                // per single-copy step: 0.165 us that copies share, 0.2 us
                // per moving body, and the multibody algebra, quadratic in
                // the joints (fitted to `e3d bench puck_rooms arm7` on one
                // core: 0.36 us a puck step, 0.20 us a copy's step in a
                // world of 32, 10.9 us an arm7 step)
                let shared = 0.165e-6;
                let own = 0.2e-6 * moving + 0.19e-6 * joints * joints;
                let steps = p.schedule.total_steps(p.dt, scene.spec().num_slots()) as f64;
                Costs {
                    rollout: steps * (shared + own),
                    shared: steps * shared,
                    exact: p.copies_are_exact(),
                    grid: false,
                }
            }
        }
    }

    /// The copies per world of a table (and of lockstep groups).
    pub(super) fn copies(&self) -> usize {
        if self.exact {
            TABLE_COPIES
        } else {
            1
        }
    }

    /// Seconds per command when `k` commands step together in one world.
    fn per_command(&self, k: usize) -> f64 {
        if !self.exact || k <= 1 {
            return self.rollout;
        }
        self.shared / k as f64 + (self.rollout - self.shared)
    }
}

/// The cost model's seconds for one rollout of a command of `scene` in a
/// single-copy world on one thread (a grid's moves: nanoseconds). What the
/// long scene tools say they will cost before they start (`e3d scene check
/// --samples`, `scene exec`, `scene render --animate`), from the same
/// model that chooses between a table, a memo and live execution: fitted
/// to the development machine (`docs/benchmarks.md`), so an estimate, not
/// a promise.
///
/// ```
/// use e3d::world::rollout_seconds;
/// use e3d::Scene;
/// let arm = rollout_seconds(&Scene::builtin("arm7").unwrap());
/// let puck = rollout_seconds(&Scene::builtin("puck_rooms").unwrap());
/// let grid = rollout_seconds(&Scene::builtin("two_rooms").unwrap());
/// assert!(arm > puck && puck > 1000.0 * grid);
/// ```
pub fn rollout_seconds(scene: &Scene) -> f64 {
    Costs::of(scene).rollout
}

/// The seconds of one rollout of `scene` measured on this machine, now:
/// a few commands of the scene itself executed on this thread (at least
/// [`CALIBRATION_ROLLOUTS`], and until [`CALIBRATION_SECONDS`] have passed,
/// at most [`CALIBRATION_MAX_ROLLOUTS`]), in a single-copy world, spread
/// over the command space (for a continuous scene: values spread over the
/// ranges). A grid scene is not timed: its cost model is kept.
///
/// This is what the scene tools' cost lines scale the cost model by (see
/// [`calibration_on`]): the model gives the ratios (copies per world,
/// threads), the measure the speed of this machine as it is loaded now.
pub fn timed_rollout_seconds(scene: &Scene) -> f64 {
    let Some(mut world) = scene.physics_world() else {
        return rollout_seconds(scene);
    };
    let space = scene.command_space();
    let start = Instant::now();
    let done = timed(start, |k| {
        // the outcome does not matter (a command that blows up is timed
        // too: it ends early, as it would in the tool)
        let _ = match scene.values() {
            Some(v) => {
                let x: Vec<f64> = (0..v.num_slots())
                    .map(|i| {
                        let (lo, hi) = v.range(i);
                        // a fraction of the range that differs per slot
                        // and per rollout
                        let f = ((k * 7 + i as u64 * 3) % 11) as f64 / 10.0;
                        lo + f * (hi - lo)
                    })
                    .collect();
                world.execute_values(&x)
            }
            None => world.execute(&spread(&space, k)),
        };
    });
    start.elapsed().as_secs_f64() / f64::from(done)
}

/// Runs `each(k)` for `k = 0, 1, ...`: [`CALIBRATION_ROLLOUTS`] times,
/// then until [`CALIBRATION_SECONDS`] have passed since `start`, at most
/// [`CALIBRATION_MAX_ROLLOUTS`] times in all; returns how many times.
fn timed(start: Instant, mut each: impl FnMut(u64)) -> u32 {
    let mut k = 0;
    while k < CALIBRATION_MAX_ROLLOUTS
        && (k < CALIBRATION_ROLLOUTS || start.elapsed().as_secs_f64() < CALIBRATION_SECONDS)
    {
        each(u64::from(k));
        k += 1;
    }
    k
}

/// Command `k` of a sample spread over `space`.
fn spread(space: &CommandSpace, k: u64) -> Command {
    let n = space.num_commands().unwrap_or(u64::MAX);
    space.command_at(k.wrapping_mul(0x9E37_79B9_7F4A_7C15) % n)
}

/// What the cost model's seconds per command of `scene`, run `copies` to
/// a world on `threads` threads, are multiplied by to give this machine's
/// as it is loaded now: rollouts of the scene itself timed the way the
/// tools run them, on `threads` threads at once (each its own world of
/// `copies` copies stepping batches of commands spread over the space),
/// for at least [`CALIBRATION_ROLLOUTS`] batches per thread and
/// [`CALIBRATION_SECONDS`]. Wall time x threads / commands, over
/// [`batch_rollout_seconds`]: threads that do not get a core each (a
/// shared machine) count as slower, as they will in the tool. 1 for a
/// grid scene.
pub fn calibration_on(scene: &Scene, threads: usize, copies: usize) -> f64 {
    use rayon::prelude::*;
    let WorldSpec::Physics(spec) = &scene.spec().world else {
        return 1.0;
    };
    if scene.spec().is_continuous() {
        // a continuous scene runs one value vector at a time
        return timed_rollout_seconds(scene) / rollout_seconds(scene);
    }
    let space = scene.command_space();
    let threads = threads.max(1);
    let copies = if spec.copies_are_exact() {
        copies.clamp(1, super::MAX_COPIES)
    } else {
        1
    };
    let start = Instant::now();
    let done: u64 = (0..threads)
        .into_par_iter()
        .map(|t| {
            let mut world = PhysicsWorld::of(scene, spec, copies);
            let mut out = Vec::with_capacity(copies);
            let batches = timed(start, |b| {
                let batch: Vec<_> = (0..copies as u64)
                    .map(|i| spread(&space, (b * copies as u64 + i) * threads as u64 + t as u64))
                    .collect();
                out.clear();
                world.execute_batch(&batch, &mut out);
            });
            u64::from(batches) * copies as u64
        })
        .sum();
    let per_command = start.elapsed().as_secs_f64() * threads as f64 / done.max(1) as f64;
    per_command / batch_rollout_seconds(scene, copies)
}

/// Rollouts [`timed_rollout_seconds`] times at least.
pub const CALIBRATION_ROLLOUTS: u32 = 3;
/// Rollouts [`timed_rollout_seconds`] times at most.
pub const CALIBRATION_MAX_ROLLOUTS: u32 = 200;
/// Seconds [`timed_rollout_seconds`] keeps timing (after its first
/// [`CALIBRATION_ROLLOUTS`]).
pub const CALIBRATION_SECONDS: f64 = 0.1;

/// The cost model's seconds per command of `scene` when `copies` commands
/// step together in one world (one thread): a single rollout
/// ([`rollout_seconds`]) for one copy, or for a scene whose copies are not
/// exact (it runs one command per world whatever `copies` asks).
pub fn batch_rollout_seconds(scene: &Scene, copies: usize) -> f64 {
    Costs::of(scene).per_command(copies)
}

/// The number of lockstep groups for `sessions` sessions on `threads`
/// threads, each stepping at most `copies` commands together: enough
/// groups to keep every thread busy, as few as that allows.
pub fn lockstep_groups(sessions: usize, threads: usize, copies: usize) -> usize {
    let threads = threads.max(1);
    let per_thread = sessions.div_ceil(threads * copies.max(1)).max(1);
    (threads * per_thread).min(sessions).max(1)
}

impl ExecutionPlan {
    /// The cheapest way to run `work` on `scene`, given what the table
    /// folder holds (`on_disk`; `None`: no folder) and the memo's cap (0:
    /// no memo).
    pub fn choose(
        scene: &Scene,
        work: &Workload,
        on_disk: Option<&OnDisk>,
        memo_cap: usize,
    ) -> ExecutionPlan {
        let costs = Costs::of(scene);
        let on_disk = on_disk.cloned().unwrap_or(OnDisk::NoCache);
        let mut plan = ExecutionPlan::live(scene, work, on_disk, memo_cap, &costs);
        if scene.spec().is_continuous() {
            plan.why = "continuous commands: every trial is simulated (no table or memo)".into();
            return plan;
        }
        let Some(n) = plan.commands else {
            plan.why = "more than 2^64 commands: no table or memo can index them".into();
            return plan;
        };
        let use_memo = plan.consider_memo(work, n, &costs);
        if n > MAX_TABLE_COMMANDS {
            plan.why = format!("{n} commands: too many for a table (at most {MAX_TABLE_COMMANDS})");
            return plan;
        }
        plan.consider_table(scene, work, n, &costs, use_memo);
        if costs.grid && plan.strategy == Strategy::Live && plan.why.is_empty() {
            plan.why = "a grid move costs less than a look-up".into();
        }
        plan
    }

    /// The plan that simulates every trial: sessions in lockstep groups
    /// of as many copies as the scene's are exact, and its cost.
    fn live(
        scene: &Scene,
        work: &Workload,
        on_disk: OnDisk,
        memo_cap: usize,
        costs: &Costs,
    ) -> ExecutionPlan {
        let space = scene.command_space();
        // continuous commands cannot be enumerated: no table, no memo
        let n = space
            .num_commands()
            .filter(|_| !scene.spec().is_continuous());
        let threads = work.threads.max(1);
        let copies = costs.copies();
        let groups = lockstep_groups(work.sessions, threads, copies);
        let width = work.sessions.div_ceil(groups).clamp(1, copies);
        let parallel = groups.min(threads) as f64;
        let trials = work.trials as f64;
        ExecutionPlan {
            strategy: Strategy::Live,
            scene: scene.spec().name.clone(),
            commands: n,
            continuous: scene.spec().is_continuous(),
            simulated: None,
            copies: width,
            groups,
            exact_copies: costs.exact,
            on_disk,
            memo_cap,
            table_seconds: None,
            sessions_seconds: trials * costs.per_command(width) / parallel,
            why: String::new(),
        }
    }

    /// The memo, for `n` commands: at most one execution per distinct
    /// command, and a look-up per trial; how often commands repeat is not
    /// known ahead, so it is worth it wherever a look-up costs less than a
    /// rollout. Whether it replaces live execution.
    fn consider_memo(&mut self, work: &Workload, n: u64, costs: &Costs) -> bool {
        let (width, trials) = (self.copies, work.trials as f64);
        let parallel = self.groups.min(work.threads.max(1)) as f64;
        let known = self.on_disk.entries(n);
        let misses = work.trials.min(n - known.min(n)) as f64;
        let memo_seconds = misses * costs.per_command(width) / parallel + trials * MEMO_LOOKUP;
        let use_memo = self.memo_cap > 0 && costs.per_command(width) > 2.0 * MEMO_LOOKUP;
        if use_memo {
            self.strategy = Strategy::Memo;
            self.sessions_seconds = memo_seconds;
        }
        use_memo
    }

    /// The table of `n` commands (read whole from disk, or built on the
    /// threads), when it costs less than the trials otherwise
    /// (`use_memo`: memoised, else live) or next to nothing; why.
    fn consider_table(
        &mut self,
        scene: &Scene,
        work: &Workload,
        n: u64,
        costs: &Costs,
        use_memo: bool,
    ) {
        let threads = work.threads.max(1);
        let copies = costs.copies();
        let simulated = OutcomeTable::simulated_commands(scene).unwrap_or(n);
        self.simulated = Some(simulated);
        let full = matches!(self.on_disk, OnDisk::Full { .. });
        let table_seconds = if full {
            n as f64 * TABLE_READ
        } else {
            simulated as f64 * costs.per_command(copies) / threads as f64 + n as f64 * TABLE_ENTRY
        } + work.trials as f64 * TABLE_LOOKUP;
        self.table_seconds = Some(table_seconds);
        let alternative = self.sessions_seconds;
        let trials = format!(
            "{} trials {} (about {})",
            work.trials,
            if use_memo { "memoised" } else { "live" },
            seconds(alternative)
        );
        let table = seconds(table_seconds);
        self.why = if table_seconds > alternative && table_seconds >= CHEAP_TABLE {
            format!("{trials} cost less than the table of {n} commands (about {table})")
        } else if full {
            "the whole table is on disk".into()
        } else if table_seconds < CHEAP_TABLE {
            "a table costs next to nothing".into()
        } else {
            format!("the table (about {table}) costs less than the {trials}")
        };
        if table_seconds <= alternative || table_seconds < CHEAP_TABLE {
            self.strategy = Strategy::Table;
            self.copies = copies;
        }
    }
}

fn seconds(s: f64) -> String {
    if s < 0.01 {
        format!("{:.1} ms", s * 1e3)
    } else if s < 100.0 {
        format!("{s:.2} s")
    } else {
        format!("{:.0} min", s / 60.0)
    }
}

impl fmt::Display for ExecutionPlan {
    /// One line: what was chosen, how, and why.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.scene)?;
        match (self.strategy, &self.on_disk) {
            (Strategy::Table, OnDisk::Full { path }) => {
                write!(f, "outcome table read from {}", path.display())?
            }
            (Strategy::Table, _) => {
                let n = self.commands.unwrap_or(0);
                let sim = self.simulated.unwrap_or(n);
                write!(f, "outcome table of {n} commands")?;
                if sim < n {
                    write!(f, " ({sim} simulated, the others mirrored)")?;
                }
                if self.copies > 1 {
                    write!(f, ", {} copies per world", self.copies)?;
                }
            }
            (Strategy::Memo | Strategy::Live, _) => {
                write!(
                    f,
                    "{} ({}",
                    if self.strategy == Strategy::Memo {
                        "outcome memo: each proposed command simulated once"
                    } else {
                        "live: every proposal executed"
                    },
                    match self.commands {
                        Some(n) => format!("{n} commands"),
                        None if self.continuous => "continuous commands".into(),
                        None => "more than 2^64 commands".into(),
                    }
                )?;
                if self.copies > 1 {
                    write!(
                        f,
                        "; sessions in lockstep, {} group(s), up to {} commands per world",
                        self.groups, self.copies
                    )?;
                } else if self.groups > 1 && !self.exact_copies {
                    write!(
                        f,
                        "; {} group(s) of sessions, one command per world: copies of this scene are not bit-identical to one world",
                        self.groups
                    )?;
                }
                if self.strategy == Strategy::Memo {
                    write!(f, "; cap {} entries", self.memo_cap)?;
                }
                write!(f, ")")?;
            }
        }
        write!(f, ": {}", self.why)?;
        match &self.on_disk {
            OnDisk::Partial { path, entries } => {
                write!(f, "; {entries} outcomes read from {}", path.display())?
            }
            OnDisk::Unusable { path, reason } => {
                write!(f, "; table cache {} not used: {reason}", path.display())?
            }
            OnDisk::Missing { path }
                if self.strategy == Strategy::Table || self.strategy == Strategy::Memo =>
            {
                write!(f, "; will be kept in {}", path.display())?
            }
            OnDisk::TooLarge => write!(f, "; no table cache for more than 2^64 commands")?,
            _ => {}
        }
        Ok(())
    }
}

impl OutcomeTable {
    /// Whether a session or sweep running `trials` trials on `scene` should
    /// run on an outcome table: [`ExecutionPlan::choose`]
    /// picks [`Strategy::Table`] for it, with no
    /// table file at hand, one thread and one session.
    pub fn worthwhile(scene: &Scene, world: &dyn World, trials: u64) -> bool {
        let work = Workload {
            trials,
            sessions: 1,
            threads: 1,
        };
        world.is_deterministic()
            && ExecutionPlan::choose(scene, &work, None, DEFAULT_MEMO_CAP).strategy
                == Strategy::Table
    }
}
