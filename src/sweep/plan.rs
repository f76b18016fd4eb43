//! The plan of a sweep: its cells, its sessions with their identities and
//! seeds, shards, and the work each scene gets.

use super::factory::{is_identifier, FactoryError, Learners, SweepScene, Worlds};
use super::spec::{invalid, set_param, MetricSpec, SweepSpec, Values, CODE_FILE, MAX_STEPS};
pub use super::summary::format_number;
use super::{SweepError, MAX_SESSIONS};
use crate::hash::session_seed;
use crate::learner::Params;
use crate::world::{ExecOptions, Strategy, Workload};
#[cfg(doc)]
use crate::world::{ExecutionPlan, Executor, OutcomeTable, DEFAULT_MEMO_CAP};
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Arc;

/// One cell of the grid: a scene, a learner, a reward setting and one value
/// of each hyper-parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// The cell's index in canonical order.
    pub index: usize,
    /// The index of the scene in [`Sweep::scenes`].
    pub scene: usize,
    /// The learner's name (one of the spec's `learners`).
    pub learner: String,
    /// Whether the learner sees the reward.
    pub use_reward: bool,
    /// The hyper-parameters (those the learner does not use hold the first
    /// value of their list; they have no effect).
    pub params: Params,
    /// Which of [`Params::SWEPT`] the learner uses.
    pub used: [bool; 5],
    /// The value of each scene axis ([`SweepSpec::axes`]), in the spec's
    /// order (empty without axes).
    pub axes: Vec<f64>,
}

/// One session of a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SessionSpec {
    /// The session's index in canonical order (`cell * sessions + replicate`).
    pub index: usize,
    /// The index of its cell.
    pub cell: usize,
    /// Which session of its cell (`0..sessions`).
    pub replicate: usize,
    /// Its seed ([`session_seed`]).
    pub seed: u64,
}

/// A shard `K/N` of a sweep: the sessions whose index `i` has
/// `i % N == K - 1` (K is 1-based, as Slurm array task ids usually are).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which part, `1..=n`.
    pub k: usize,
    /// How many parts.
    pub n: usize,
}

impl Shard {
    /// The whole sweep (`1/1`).
    pub const ALL: Shard = Shard { k: 1, n: 1 };

    /// Whether session `index` belongs to this shard.
    pub fn contains(&self, index: usize) -> bool {
        index % self.n == self.k - 1
    }

    /// How many of `total` sessions belong to this shard.
    pub fn count(&self, total: usize) -> usize {
        // the indices k-1, k-1+n, ... below total (no `total + n`: n may
        // be near usize::MAX)
        total
            .checked_sub(self.k)
            .map_or(0, |rest| rest / self.n + 1)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

/// A text that is not a shard `K/N` with `1 <= K <= N`: what
/// [`Shard::from_str`](std::str::FromStr::from_str) refuses.
///
/// ```
/// use e3d::sweep::{ParseShardError, Shard};
/// let e: ParseShardError = "0/3".parse::<Shard>().unwrap_err();
/// assert_eq!(e.to_string(), "`0/3`: expected K/N with 1 <= K <= N, for example 2/8");
/// assert_eq!(e.input(), "0/3");
/// ```
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
#[error("`{input}`: expected K/N with 1 <= K <= N, for example 2/8")]
pub struct ParseShardError {
    input: String,
}

impl ParseShardError {
    /// The text that was refused.
    pub fn input(&self) -> &str {
        &self.input
    }
}

impl FromStr for Shard {
    type Err = ParseShardError;
    /// `"K/N"` with `1 <= K <= N`.
    fn from_str(s: &str) -> Result<Shard, ParseShardError> {
        let bad = || ParseShardError {
            input: s.to_string(),
        };
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// A checked sweep: the spec, its scenes and learners as its factories
/// made them, and its cells.
#[derive(Clone)]
pub struct Sweep {
    /// The spec.
    pub spec: SweepSpec,
    /// The text of the sweep file, or [`SweepSpec::to_ron`] for a sweep
    /// built in code (copied into output folders, and compared on resume).
    pub text: String,
    /// The file's name, for messages (`<SweepSpec>` for a sweep built in
    /// code).
    pub file: String,
    pub(super) scenes: Vec<Arc<SweepScene>>,
    pub(super) learners: Arc<Learners>,
    pub(super) metrics: Vec<MetricSpec>,
    pub(super) cells: Vec<Cell>,
    pub(super) exec: ExecOptions,
    /// Where the sweep tells how it obtains outcomes (one line each).
    pub(super) notices: Option<Arc<Notice>>,
    pub(super) trials_done: Option<std::sync::Arc<std::sync::atomic::AtomicU64>>,
    /// Where the sweep tells the building of its scenes' outcome tables:
    /// `(scene, k more commands, of total)`.
    pub(super) table_progress: Option<Arc<TableProgress>>,
    /// Per scene, the effects some command reaches, when told
    /// ([`with_reachable_effects`](Self::with_reachable_effects)).
    pub(super) reachable: Vec<Option<usize>>,
    /// Per scene, its start contexts.
    pub(super) contexts: Vec<usize>,
}

type Notice = dyn Fn(&str) + Send + Sync;
type TableProgress = dyn Fn(&str, u64, u64) + Send + Sync;

impl fmt::Debug for Sweep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let scenes: Vec<&str> = self.scenes.iter().map(|s| s.name()).collect();
        f.debug_struct("Sweep")
            .field("spec", &self.spec)
            .field("file", &self.file)
            .field("scenes", &scenes)
            .field("learners", &self.learners.names())
            .field("metrics", &self.metrics)
            .field("cells", &self.cells.len())
            .field("exec", &self.exec)
            .finish_non_exhaustive()
    }
}

impl Sweep {
    /// Loads and checks a sweep file; scene paths are relative to its folder.
    pub fn load(path: impl AsRef<Path>) -> Result<Sweep, SweepError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = crate::scene::read_text(path, "sweep")?;
        Sweep::parse(&text, &file, path.parent())
    }

    /// Parses and checks sweep text; `file` names it in errors, `base`
    /// is the folder scene paths are relative to (the current folder when
    /// `None`). The scenes and learners are the built-in ones: [`Worlds::with_scene_files`] and
    /// [`Learners::builtin`].
    pub fn parse(text: &str, file: &str, base: Option<&Path>) -> Result<Sweep, SweepError> {
        let worlds = Worlds::new().with_scene_files(base);
        Sweep::parse_with(text, file, &worlds, Learners::builtin())
    }

    /// Parses and checks sweep text whose scenes `worlds` makes and whose
    /// learners `learners` makes; a name either does not know is refused
    /// at its place in the text.
    ///
    /// ```
    /// use e3d::learner::LearnerSetup;
    /// use e3d::sweep::{Learners, Sweep, Worlds};
    /// use e3d::{LearnerKind, Scene};
    /// // the uniform policy under another name, on a scene edited in code
    /// let mut spec = Scene::builtin("two_rooms").unwrap().into_spec();
    /// spec.name = "rooms".into();
    /// let scene = spec.validate().unwrap();
    /// let learners = Learners::new().with("blind", &[], |p, space, n, target| {
    ///     Ok(LearnerSetup::new(LearnerKind::Uniform).params(*p).target(target.clone()).symbols(space, n)?)
    /// });
    /// let text = r#"Sweep(scenes: ["rooms"], learners: [blind], sessions: 2, trials: 100)"#;
    /// let sweep = Sweep::parse_with(text, "code.ron", &Worlds::new().with_scene(scene), learners.clone()).unwrap();
    /// assert_eq!(sweep.identity(&sweep.cells()[0], 1),
    ///     "scene=rooms;learner=blind;use_reward=true;alpha=-;beta=-;lambda=-;eta=-;epsilon=-;session=1");
    /// let bad = r#"Sweep(scenes: ["rooms"], learners: [blnd], sessions: 2, trials: 100)"#;
    /// let e = Sweep::parse_with(bad, "bad.ron", &Worlds::new(), learners).unwrap_err();
    /// assert_eq!(e.to_string(), "bad.ron:1:37: unknown learner `blnd` (did you mean `blind`?); expected one of: blind");
    /// ```
    pub fn parse_with(
        text: &str,
        file: &str,
        worlds: &Worlds,
        learners: Learners,
    ) -> Result<Sweep, SweepError> {
        let (spec, text) = SweepSpec::from_text(text, file, &learners)?;
        let learners = Arc::new(learners);
        Sweep::build(spec, text.to_string(), file, text, worlds, learners)
    }

    /// A sweep built in code, with the built-in scenes and learners ([`Worlds::with_scene_files`]
    /// relative to the current folder, [`Learners::builtin`]).
    ///
    /// ```
    /// use e3d::sweep::{Sweep, SweepSpec};
    /// let sweep = Sweep::new(SweepSpec::new(["two_rooms"], ["e3d", "uniform"], 2, 100)).unwrap();
    /// assert_eq!(sweep.num_sessions(), 4);
    /// // the same sweep, and the same seeds, as the file it writes
    /// let file = Sweep::parse(&sweep.text, "copy.ron", None).unwrap();
    /// assert_eq!(file.sessions(), sweep.sessions());
    /// let e = Sweep::new(SweepSpec::new(["two_rooms"], ["e3d"], 0, 100)).unwrap_err();
    /// assert_eq!(e.to_string(), "<SweepSpec>: field `sessions`: expected at least 1 session per cell, found 0");
    /// ```
    pub fn new(spec: SweepSpec) -> Result<Sweep, SweepError> {
        let worlds = Worlds::new().with_scene_files(None);
        Sweep::with_factories(spec, &worlds, Learners::builtin())
    }

    /// A sweep built in code whose scenes `worlds` makes and whose
    /// learners `learners` makes (see [`factory`](super::factory)). Its
    /// [`text`](Self::text) is [`SweepSpec::to_ron`].
    pub fn with_factories(
        spec: SweepSpec,
        worlds: &Worlds,
        learners: Learners,
    ) -> Result<Sweep, SweepError> {
        let text = spec.to_ron();
        Sweep::build(spec, text, CODE_FILE, "", worlds, Arc::new(learners))
    }

    /// Checks `spec` (placing mistakes in `located`), makes its scenes and
    /// its cells.
    fn build(
        spec: SweepSpec,
        text: String,
        file: &str,
        located: &str,
        worlds: &Worlds,
        learners: Arc<Learners>,
    ) -> Result<Sweep, SweepError> {
        let bad = |field: &str, anchor: Option<&str>, expected: &str| {
            invalid(file, located, field, anchor, expected)
        };
        // the size first, from the counts of values alone: a sweep too
        // large to plan is refused before its ranges are expanded and
        // checked value by value (which takes seconds for 100000 steps)
        if let Some((counts, variants)) = value_counts(&spec) {
            let uses: Vec<[bool; 5]> = spec
                .learners
                .iter()
                .filter_map(|l| learners.uses(l))
                .collect();
            let scenes = spec.scenes.len().saturating_mul(variants);
            check_size(&spec, cells_of(&counts, &uses, &spec, scenes), &bad)?;
        }
        let checked = spec.check_in(file, located)?;
        let (axes, metrics) = (checked.axes, checked.metrics);
        let uses = learner_uses(&spec, &learners, &bad)?;
        let scenes = make_scenes(&spec, worlds, &bad)?;
        let (scenes, variants) =
            super::axes::derive_scenes(&spec, scenes, &checked.scene_axes, &bad)?;
        let episodes = spec.runs_episodes();
        check_values(&scenes, &learners, &spec.learners, episodes, &bad)?;
        let contexts = super::contexts::start_contexts(&scenes);
        let mut metrics = metrics;
        super::contexts::check(&spec, &contexts, &mut metrics, &bad)?;
        // the size, before making the cells (checked above already when
        // the counts of values were known before expanding them)
        let counts: [usize; 5] = std::array::from_fn(|i| axes[i].len());
        let num_cells = check_size(&spec, cells_of(&counts, &uses, &spec, scenes.len()), &bad)?;
        let cells = make_cells(&spec, &variants, &uses, &axes, num_cells);
        Ok(Sweep {
            spec,
            text,
            file: file.to_string(),
            scenes,
            learners,
            metrics,
            cells,
            exec: ExecOptions::default(),
            notices: None,
            trials_done: None,
            table_progress: None,
            reachable: Vec::new(),
            contexts,
        })
    }

    /// Keeps the outcome tables of the sweep's scenes in the folder `dir`
    /// (see [`OutcomeTable::cached`]): a physics scene's commands are then
    /// simulated once for every run, resume and shard that shares the
    /// folder. The results are the same bytes with or without it.
    pub fn with_table_cache(mut self, dir: impl Into<PathBuf>) -> Self {
        self.exec.cache = Some(dir.into());
        self
    }

    /// Caps the outcome memo of each scene at `cap` entries (0: no memo;
    /// default [`DEFAULT_MEMO_CAP`]). The results are the same bytes
    /// whatever the cap; only the time changes.
    pub fn with_memo_cap(mut self, cap: usize) -> Self {
        self.exec.memo_cap = cap;
        self
    }

    /// Uses `strategy` for every scene where it can be used, whatever it
    /// costs (`None`: the cheapest, the default). The results are the same
    /// bytes whatever the strategy.
    ///
    /// # Errors
    ///
    /// A table or a memo forced on a sweep with a scene of continuous
    /// commands (which run live only) is refused here, before anything is
    /// written.
    pub fn with_strategy(mut self, strategy: Option<Strategy>) -> Result<Self, SweepError> {
        if let Some(s @ (Strategy::Table | Strategy::Memo)) = strategy {
            let continuous = self
                .scenes
                .iter()
                .find(|sc| sc.scene().and_then(crate::Scene::value_space).is_some());
            if let Some(scene) = continuous {
                return Err(SweepError::Other(format!(
                    "scene `{}` takes continuous commands, which run live only (no table, no memo), but the sweep forces {s}",
                    scene.name()
                )));
            }
        }
        self.exec.force = strategy;
        Ok(self)
    }

    /// Tells the sweep how many effects some command of each scene
    /// reaches (`reachable[i]` for its `i`-th scene, `None`: unknown), for
    /// the coverage measures ([`MetricSpec::Coverage`] and the trials to
    /// 50% and 90%) and the entropy over the reachable cells. Without it,
    /// coverage counts against every effect of the scene. `e3d compare`
    /// gives the counts of the scenes' outcome tables.
    pub fn with_reachable_effects(mut self, reachable: Vec<Option<usize>>) -> Self {
        self.reachable = reachable;
        self
    }

    /// The effects some command of scene `scene` (its index) reaches, if
    /// the sweep was told ([`with_reachable_effects`](Self::with_reachable_effects)).
    pub fn reachable_effects(&self, scene: usize) -> Option<usize> {
        self.reachable.get(scene).copied().flatten()
    }

    /// Calls `f` with one line for each scene saying how its outcomes are
    /// obtained (table, memo or live, and why), and after the run what the
    /// memo simulated and kept. `e3d sweep` prints them on stderr.
    pub fn with_notices(mut self, f: impl Fn(&str) + Send + Sync + 'static) -> Self {
        self.notices = Some(Arc::new(f));
        self
    }

    /// Adds every trial run to `counter` as sessions go (from the worker
    /// threads, every 64 lockstep trials, or when a session on a table
    /// ends): progress finer than whole sessions, for sessions in lockstep
    /// that all end together.
    pub fn with_trial_counter(
        mut self,
        counter: std::sync::Arc<std::sync::atomic::AtomicU64>,
    ) -> Self {
        self.trials_done = Some(counter);
        self
    }

    /// Calls `f(scene, k, total)` from the worker threads while the
    /// outcome table of `scene` is built before its sessions run: `k` more
    /// commands simulated, of about `total` ([`Executor::with_control`]);
    /// then, once the building has ended (the table built, or given up
    /// for the memo), `f(scene, 0, 0)` once. Nothing is called for a
    /// scene whose table is read whole or not built. The results are the
    /// same bytes with or without it.
    pub fn with_table_progress(
        mut self,
        f: impl Fn(&str, u64, u64) + Send + Sync + 'static,
    ) -> Self {
        self.table_progress = Some(Arc::new(f));
        self
    }

    pub(super) fn count_trials(&self, n: u64) {
        if let Some(c) = &self.trials_done {
            c.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        }
    }

    pub(super) fn notice(&self, line: &str) {
        if let Some(f) = &self.notices {
            f(line);
        }
    }

    /// The scenes, in the order of the spec; with scene axes
    /// ([`SweepSpec::axes`]), each once per combination of the axes'
    /// values (the last axis varying fastest), derived from it.
    pub fn scenes(&self) -> &[Arc<SweepScene>] {
        &self.scenes
    }

    /// The cells, in canonical order.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// The kept metrics.
    pub fn metrics(&self) -> &[MetricSpec] {
        &self.metrics
    }

    /// The number of sessions.
    pub fn num_sessions(&self) -> usize {
        self.cells.len() * self.spec.sessions
    }

    /// The names of the cell columns: [`KEY_COLUMNS`](super::KEY_COLUMNS)
    /// up to `epsilon`, then each scene axis's path.
    pub fn cell_columns(&self) -> Vec<String> {
        let keys = super::KEY_COLUMNS[..super::CELL_COLUMNS].iter();
        let axes = self.spec.axes.iter().map(|(path, _)| path.clone());
        keys.map(|k| k.to_string()).chain(axes).collect()
    }

    /// The cell columns of `cell` (scene, learner, use_reward, the five
    /// parameters, empty when unused, then each scene axis's value), as
    /// written in the CSV files.
    pub fn cell_fields(&self, cell: &Cell) -> Vec<String> {
        let params = cell.params.named();
        let used = (0..5).map(|i| match cell.used[i] {
            true => format_number(params[i].1),
            false => String::new(),
        });
        let scene = self.scenes[cell.scene].name().to_string();
        let axes = cell.axes.iter().map(|&v| format_number(v));
        [scene, cell.learner.clone(), cell.use_reward.to_string()]
            .into_iter()
            .chain(used)
            .chain(axes)
            .collect()
    }

    /// The canonical identity text of session `replicate` of `cell` (see
    /// the module docs); its seed is `session_seed(base, identity)`.
    pub fn identity(&self, cell: &Cell, replicate: usize) -> String {
        let f = self.cell_fields(cell);
        let mut s = format!("scene={};learner={};use_reward={}", f[0], f[1], f[2]);
        for (i, name) in Params::SWEPT.iter().enumerate() {
            let v = if f[3 + i].is_empty() { "-" } else { &f[3 + i] };
            s.push_str(&format!(";{name}={v}"));
        }
        for ((path, _), v) in self.spec.axes.iter().zip(&f[8..]) {
            s.push_str(&format!(";{path}={v}"));
        }
        s + &format!(";session={replicate}")
    }

    /// Every session, in canonical order.
    pub fn sessions(&self) -> Vec<SessionSpec> {
        let per = self.spec.sessions;
        self.cells
            .iter()
            .flat_map(|c| {
                (0..per).map(move |r| SessionSpec {
                    index: c.index * per + r,
                    cell: c.index,
                    replicate: r,
                    seed: session_seed(self.spec.seed, &self.identity(c, r)),
                })
            })
            .collect()
    }

    /// How the outcomes of each scene will be obtained for `sessions` on
    /// `threads` threads (see [`ExecutionPlan::choose`]), without reading
    /// or building anything but the table folder's headers.
    pub fn workloads(&self, sessions: &[SessionSpec], threads: usize) -> Vec<Workload> {
        let mut work = vec![
            Workload {
                trials: 0,
                sessions: 0,
                threads: threads.max(1),
            };
            self.scenes.len()
        ];
        for s in sessions {
            let w = &mut work[self.cells[s.cell].scene];
            w.trials += self.spec.trials as u64;
            w.sessions += 1;
        }
        work
    }
}

/// What each learner of `spec` uses of the five parameters; an error
/// for a learner `learners` does not know, or whose name does not fit a
/// CSV field and a file.
fn learner_uses(
    spec: &SweepSpec,
    learners: &Learners,
    bad: &dyn Fn(&str, Option<&str>, &str) -> SweepError,
) -> Result<Vec<[bool; 5]>, SweepError> {
    let bad = |expected: String| Err(bad("learners", None, &expected));
    let uses = spec.learners.iter().map(|name| {
        let Some(used) = learners.uses(name) else {
            let names = learners.names().join(", ");
            return bad(format!("one of the learners ({names}), found `{name}`"));
        };
        if !is_identifier(name) {
            return bad(format!("learner names of ASCII letters, digits and `_`, not starting with a digit (for CSV files and sweep files), found `{name}`"));
        }
        Ok(used)
    });
    uses.collect()
}

/// The scenes of `spec`, made by `worlds`: each named as a scene file
/// must be, each once.
fn make_scenes(
    spec: &SweepSpec,
    worlds: &Worlds,
    bad: &dyn Fn(&str, Option<&str>, &str) -> SweepError,
) -> Result<Vec<Arc<SweepScene>>, SweepError> {
    let mut scenes: Vec<Arc<SweepScene>> = Vec::new();
    for name in &spec.scenes {
        let anchor = format!("\"{name}\"");
        let bad = |expected: &str| bad("scenes", Some(&anchor), expected);
        let scene = worlds.scene(name).map_err(|e| match e {
            FactoryError::Unknown(msg) => bad(&msg),
            FactoryError::Failed(e) => e,
        })?;
        // a scene made in code (a Scene or a LiveScene) gets the checks of
        // a scene file's name: it is printed, and written into CSV files
        if let Err(e) = crate::text::check_name(scene.name()) {
            return Err(bad(&format!("scenes whose name is {e}")));
        }
        if scenes.iter().any(|s| s.name() == scene.name()) {
            let twice = scene.name();
            return Err(bad(&format!(
                "each scene once, but `{twice}` appears twice"
            )));
        }
        scenes.push(scene);
    }
    Ok(scenes)
}

/// The cells of `spec` on `scenes` scenes, in canonical order: per scene,
/// learner (using `uses` of the parameters) and reward, every
/// combination of the parameters' values `axes` (`num_cells` in all).
fn make_cells(
    spec: &SweepSpec,
    variants: &[Vec<f64>],
    uses: &[[bool; 5]],
    axes: &[Vec<f64>],
    num_cells: usize,
) -> Vec<Cell> {
    let mut cells = Vec::with_capacity(num_cells);
    for (si, scene_axes) in variants.iter().enumerate() {
        for (learner, &used) in spec.learners.iter().zip(uses) {
            let dims: Vec<usize> = (0..5)
                .map(|i| if used[i] { axes[i].len() } else { 1 })
                .collect();
            let count: usize = dims.iter().product();
            for &use_reward in &spec.use_reward {
                for mut k in 0..count {
                    let mut params = spec.params.fixed(Params::TASK1);
                    // the last parameter varies fastest
                    for i in (0..5).rev() {
                        set_param(&mut params, i, axes[i][k % dims[i]]);
                        k /= dims[i];
                    }
                    cells.push(Cell {
                        index: cells.len(),
                        scene: si,
                        learner: learner.clone(),
                        use_reward,
                        params,
                        used,
                        axes: scene_axes.clone(),
                    });
                }
            }
        }
    }
    cells
}

/// The number of values of each of [`Params::SWEPT`] in `spec` without
/// making them (a range's `steps`); `None` when one of them is a count
/// that [`SweepSpec::check_in`] refuses (no values, too many steps), so
/// that its own message comes first.
fn value_counts(spec: &SweepSpec) -> Option<([usize; 5], usize)> {
    let count = |v: &Values| match v {
        Values::List(v) if v.is_empty() => None,
        Values::List(v) => Some(v.len()),
        Values::Range { steps, .. } if *steps > MAX_STEPS || *steps == 0 => None,
        Values::Range { steps, .. } => Some(*steps),
    };
    let mut variants: usize = 1;
    for (_, v) in &spec.axes {
        variants = variants.saturating_mul(count(v)?);
    }
    let mut counts = [1; 5];
    for (i, name) in Params::SWEPT.iter().enumerate() {
        counts[i] = match spec.params.get(name) {
            None => 1,
            Some(Values::List(v)) => v.len(),
            Some(Values::Range { steps, .. }) if *steps > MAX_STEPS => return None,
            Some(Values::Range { steps, .. }) => *steps,
        };
        if counts[i] == 0 {
            return None;
        }
    }
    Some((counts, variants))
}

/// The number of cells of `spec` on `scenes` scenes whose parameters
/// have `counts` values and whose learners use the parameters `uses`.
fn cells_of(counts: &[usize; 5], uses: &[[bool; 5]], spec: &SweepSpec, scenes: usize) -> usize {
    let mut num_cells: usize = 0;
    for used in uses {
        let per: usize = (0..5)
            .filter(|&i| used[i])
            .fold(1usize, |acc, i| acc.saturating_mul(counts[i]));
        num_cells = num_cells.saturating_add(per.saturating_mul(spec.use_reward.len()));
    }
    num_cells.saturating_mul(scenes)
}

/// `num_cells`, or the refusal of a sweep of more than [`MAX_SESSIONS`]
/// sessions.
fn check_size(
    spec: &SweepSpec,
    num_cells: usize,
    bad: &dyn Fn(&str, Option<&str>, &str) -> SweepError,
) -> Result<usize, SweepError> {
    if num_cells.saturating_mul(spec.sessions) > MAX_SESSIONS {
        let per_cell = spec.sessions;
        let expected = format!("at most {MAX_SESSIONS} sessions in all (a sweep's plan holds each one in memory), found {num_cells} cells x {per_cell}");
        return Err(bad("sessions", None, &expected));
    }
    Ok(num_cells)
}

/// Checks, while the sweep is planned, that every learner of the sweep
/// takes continuous commands on each continuous scene (a learner of
/// symbols only is refused with its reason) and that no continuous scene
/// runs episodes. `bad(field, anchor, expected)` places the error.
fn check_values(
    scenes: &[Arc<SweepScene>],
    learners: &Learners,
    names: &[String],
    episodes: bool,
    bad: &dyn Fn(&str, Option<&str>, &str) -> SweepError,
) -> Result<(), SweepError> {
    for s in scenes {
        let Some(space) = s.scene().and_then(crate::Scene::value_space) else {
            continue;
        };
        let (scene, n) = (s.name(), s.num_effects());
        if episodes {
            let expected = format!("scenes of symbols in a sweep of episodes (commands, observe or closed_loop set), found `{scene}`, whose slots take values (`Continuous`)");
            return Err(bad("scenes", Some(&format!("\"{scene}\"")), &expected));
        }
        let uniform = crate::effect::Target::Uniform;
        for name in names {
            let made = learners.make_continuous(name, &Params::TASK1, &space, n, &uniform, None);
            if let Err(e) = made {
                let expected = format!("learners that take continuous commands on scene `{scene}`, found `{name}`: {e}");
                return Err(bad("learners", None, &expected));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_sessions() {
        let total = 17;
        let shards: Vec<Shard> = (1..=3).map(|k| Shard { k, n: 3 }).collect();
        for i in 0..total {
            assert_eq!(shards.iter().filter(|s| s.contains(i)).count(), 1);
        }
        let counts: usize = shards.iter().map(|s| s.count(total)).sum();
        assert_eq!(counts, total);
        assert_eq!(shards[0].count(total), 6);
        assert_eq!(shards[2].count(total), 5);
        assert_eq!("2/3".parse::<Shard>().unwrap(), shards[1]);
        assert!("0/3".parse::<Shard>().is_err());
        // no overflow with the largest N
        let huge: Shard = "1/18446744073709551615".parse().unwrap();
        assert_eq!(huge.count(total), 1);
        assert_eq!(huge.count(0), 0);
        let last = Shard {
            k: usize::MAX,
            n: usize::MAX,
        };
        assert_eq!(last.count(total), 0);
        assert_eq!(last.count(usize::MAX), 1);
        assert_eq!(Shard { k: 3, n: 3 }.count(2), 0);
        assert!("4/3".parse::<Shard>().is_err());
    }
}
