//! What a sweep's names become: the worlds of its scenes and its learners.
//!
//! A [`SweepSpec`] names its scenes and learners; [`Worlds`] turns each
//! scene name into a [`SweepScene`] (its command space, its effects, and
//! the worlds its sessions run on), and [`Learners`] turns each learner
//! name into fresh learners. `e3d sweep` uses
//! [`Worlds::with_scene_files`] (scene files and built-in scene names,
//! each run through an [`Executor`]: outcome table, memo or live
//! execution, sessions in lockstep) and [`Learners::builtin`]
//! ([`LearnerKind`]).
//!
//! Your own worlds and learners are registered beside them (a scene can
//! also be a [`Scene`] made or edited in code):
//!
//! ```
//! use e3d::sweep::{Learners, Sweep, SweepSpec, Worlds};
//! use e3d::{Command, Outcome, World, WorldError};
//! use e3d::command::CommandSpace;
//!
//! /// Effect = number of 'b' symbols.
//! struct CountB(CommandSpace);
//! impl World for CountB {
//!     fn command_space(&self) -> &CommandSpace { &self.0 }
//!     fn num_effects(&self) -> usize { self.0.num_slots() + 1 }
//!     fn execute(&mut self, c: &Command) -> Result<Outcome, WorldError> {
//!         let n = c.symbols.iter().filter(|&&s| s == 1).count();
//!         Ok(Outcome { effect: n, reward: 0.0, point: [n as f64, 0.0] })
//!     }
//! }
//!
//! let worlds = Worlds::new()
//!     .with_world("count_b", || CountB(CommandSpace::repeat(4, &['a', 'b']).unwrap()))
//!     .with_scene_files(None); // built-in scene names and files still work
//! let spec = SweepSpec::new(["count_b", "two_rooms"], ["uniform"], 2, 50);
//! let sweep = Sweep::with_factories(spec, &worlds, Learners::builtin()).unwrap();
//! let results = sweep.run(2).unwrap();
//! assert_eq!(results.len(), 4);
//! assert!(sweep.result_row(&results[0]).starts_with("count_b,uniform,true,"));
//! ```

#[cfg(doc)]
use super::SweepSpec;
use super::{BoxError, SweepError};
use crate::command::Command;
use crate::command::{CommandSpace, ValueSpace};
use crate::effect::Target;
use crate::hash::fnv1a64;
use crate::learner::{ContinuousLearner, Effort, Learner, LearnerKind, LearnerSetup, Params};
use crate::scene::Scene;
use crate::session;
#[cfg(doc)]
use crate::world::Executor;
use crate::world::{OutcomeTable, World, WorldError};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Whether `learner` uses the hyper-parameter `param` (one of
/// [`Params::SWEPT`]).
///
/// ```
/// use e3d::{sweep::uses_param, LearnerKind};
/// assert!(uses_param(LearnerKind::E3d, "eta"));
/// assert!(!uses_param(LearnerKind::Egreedy, "beta"));
/// assert!(!uses_param(LearnerKind::Uniform, "alpha"));
/// ```
pub fn uses_param(learner: LearnerKind, param: &str) -> bool {
    learner.params().contains(&param)
}

/// One scene of a sweep, as its [`Worlds`] made it: what its sessions
/// need to know, and where their worlds come from.
#[derive(Debug)]
#[allow(clippy::large_enum_variant)] // one per scene, shared in an Arc
pub enum SweepScene {
    /// A scene file, or a [`Scene`] made or edited in code: run through an
    /// [`Executor`] (outcome table, memo or live execution, chosen by
    /// cost, sessions in lockstep: exactly `e3d sweep`).
    Scene(Scene),
    /// Worlds a closure makes, each session alone on a fresh one.
    Live(LiveScene),
}

impl From<Scene> for SweepScene {
    fn from(scene: Scene) -> SweepScene {
        SweepScene::Scene(scene)
    }
}

impl From<LiveScene> for SweepScene {
    fn from(scene: LiveScene) -> SweepScene {
        SweepScene::Live(scene)
    }
}

impl SweepScene {
    /// The name written in `results.csv` and in the sessions' identities
    /// (so in their seeds). It must hold no comma, quote or line break.
    pub fn name(&self) -> &str {
        match self {
            SweepScene::Scene(s) => &s.spec().name,
            SweepScene::Live(l) => &l.name,
        }
    }

    /// The command space of every world of this scene (the learners are
    /// made for it; a world of another space is refused).
    pub fn command_space(&self) -> CommandSpace {
        match self {
            SweepScene::Scene(s) => s.command_space(),
            SweepScene::Live(l) => l.space.clone(),
        }
    }

    /// The number of effects of every world of this scene.
    pub fn num_effects(&self) -> usize {
        match self {
            SweepScene::Scene(s) => s.num_effects(),
            SweepScene::Live(l) => l.num_effects,
        }
    }

    /// A key of the scene's content, written in the journal of an output
    /// folder: a resume or a merge after it changed is refused, since one
    /// results file would mix two versions of the scene. For a scene,
    /// [`OutcomeTable::key`] (its canonical form and the e3d version); for
    /// a [`LiveScene`], [`LiveScene::with_key`].
    pub fn content_key(&self) -> u64 {
        match self {
            SweepScene::Scene(s) => OutcomeTable::key(s),
            SweepScene::Live(l) => l.key,
        }
    }

    /// The scene file behind this scene, if it has one.
    pub fn scene(&self) -> Option<&Scene> {
        match self {
            SweepScene::Scene(s) => Some(s),
            SweepScene::Live(_) => None,
        }
    }
}

/// Why [`Worlds::scene`] made no scene of a name.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FactoryError {
    /// The factory knows no such scene. The text says what it expected and
    /// what was found (`a scene file ... or a built-in scene (...), found
    /// `x``); the sweep reports it at the name in the sweep file.
    #[error("expected {0}")]
    Unknown(String),
    /// The scene is known but could not be made (a mistake in its file,
    /// a simulator that does not start, ...).
    #[error(transparent)]
    Failed(SweepError),
}

/// A scene named in a sweep: a path relative to `base` (or absolute), or a
/// built-in name.
fn resolve_scene(name: &str, base: Option<&Path>) -> Result<Scene, FactoryError> {
    let p = Path::new(name);
    let path = match base {
        Some(b) if p.is_relative() => b.join(p),
        _ => p.to_path_buf(),
    };
    if path.exists() {
        return Scene::load(&path).map_err(|e| FactoryError::Failed(SweepError::Input(e)));
    }
    if let Some(s) = Scene::builtin(name) {
        return Ok(s);
    }
    let names: Vec<&str> = crate::scene::BUILTIN.iter().map(|(n, _)| *n).collect();
    let (hint, path) = (crate::scene::did_you_mean(name, &names), path.display());
    Err(FactoryError::Unknown(format!(
        "a scene file (relative to the sweep file) or a built-in scene ({}), found `{name}`: no file {path}{hint}",
        names.join(", ")
    )))
}

/// A scene whose worlds a closure makes: each session runs alone on a
/// fresh world (live execution: no table, no memo, no lockstep), so a
/// deterministic world gives the same results whatever the threads.
///
/// ```
/// use e3d::sweep::{LiveScene, SweepScene};
/// use e3d::Scene;
/// let scene = SweepScene::from(LiveScene::new("rooms", || Scene::builtin("two_rooms").unwrap().build()));
/// assert_eq!(scene.name(), "rooms");
/// assert_eq!(scene.num_effects(), 18);
/// ```
pub struct LiveScene {
    name: String,
    space: CommandSpace,
    num_effects: usize,
    key: u64,
    make: MakeWorld,
}

type MakeWorld = Box<dyn Fn() -> Box<dyn World + Send> + Send + Sync>;

impl LiveScene {
    /// The scene `name` whose worlds `make` makes. One world is made at
    /// once, for its command space and number of effects. The content key
    /// is a hash of the name, the command space and the number of effects
    /// (see [`with_key`](Self::with_key)).
    pub fn new<F, W>(name: impl Into<String>, make: F) -> LiveScene
    where
        F: Fn() -> W + Send + Sync + 'static,
        W: World + Send + 'static,
    {
        let name = name.into();
        let world = make();
        let space = world.command_space().clone();
        let num_effects = world.num_effects();
        let alphabets: Vec<String> = (0..space.num_slots())
            .map(|i| space.alphabet(i).iter().collect())
            .collect();
        let key = fnv1a64(format!("{name};{};{num_effects}", alphabets.join("|")).as_bytes());
        LiveScene {
            name,
            space,
            num_effects,
            key,
            make: Box::new(move || Box::new(make())),
        }
    }

    /// Sets the content key ([`SweepScene::content_key`]): give a hash of
    /// whatever defines your world (its parameters, a version), so that a
    /// resume after it changed is refused.
    pub fn with_key(mut self, key: u64) -> LiveScene {
        self.key = key;
        self
    }
}

impl fmt::Debug for LiveScene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LiveScene")
            .field("name", &self.name)
            .field("space", &self.space)
            .field("num_effects", &self.num_effects)
            .field("key", &format_args!("{:016x}", self.key))
            .finish_non_exhaustive()
    }
}

/// Each session alone, on a fresh world checked against the scene.
impl session::Worlds<Command> for LiveScene {
    fn session_groups(&self, sessions: usize) -> Vec<Range<usize>> {
        (0..sessions).map(|i| i..i + 1).collect()
    }
    fn world_for(
        &self,
        _width: usize,
    ) -> Result<Box<dyn session::Executes<Command> + Send + '_>, WorldError> {
        let world = (self.make)();
        match mismatch(&self.space, self.num_effects, &*world) {
            Some(why) => Err(WorldError::Other(why)),
            None => Ok(Box::new(world)),
        }
    }
}

/// A world factory from scenes registered by name, and optionally scene
/// files and built-in names for the others.
///
/// A name is looked up among the registered scenes first (by
/// [`SweepScene::name`]; a later one replaces an earlier one of the same
/// name), then, with [`with_scene_files`](Self::with_scene_files), as a
/// scene file or a built-in scene.
#[derive(Clone, Default)]
pub struct Worlds {
    scenes: Vec<Arc<SweepScene>>,
    /// With scene files: the folder relative paths start from (`None`:
    /// the current folder).
    files: Option<Option<PathBuf>>,
}

impl Worlds {
    /// No scene at all.
    pub fn new() -> Worlds {
        Worlds::default()
    }

    /// Registers `name`, whose worlds `make` makes (a [`LiveScene`]).
    pub fn with_world<F, W>(self, name: impl Into<String>, make: F) -> Worlds
    where
        F: Fn() -> W + Send + Sync + 'static,
        W: World + Send + 'static,
    {
        self.with_scene(LiveScene::new(name, make))
    }

    /// Registers a scene under its [`SweepScene::name`]: a [`Scene`] made
    /// or edited in code (run as `e3d sweep` runs scene files) or a
    /// [`LiveScene`].
    pub fn with_scene(mut self, scene: impl Into<SweepScene>) -> Worlds {
        let scene = scene.into();
        self.scenes.retain(|s| s.name() != scene.name());
        self.scenes.push(Arc::new(scene));
        self
    }

    /// Makes the names that are not registered scene files relative to
    /// `base` (the current folder when `None`; for a sweep file, its
    /// folder) or else built-in scenes ([`Scene::builtin`]), each run
    /// through an [`Executor`]: `e3d sweep`'s scenes.
    pub fn with_scene_files(mut self, base: Option<&Path>) -> Worlds {
        self.files = Some(base.map(Path::to_path_buf));
        self
    }

    /// The registered scenes' names, in order.
    pub fn names(&self) -> Vec<&str> {
        self.scenes.iter().map(|s| s.name()).collect()
    }

    /// The scene the sweep names `name` (made once, before any session
    /// runs).
    pub fn scene(&self, name: &str) -> Result<Arc<SweepScene>, FactoryError> {
        if let Some(s) = self.scenes.iter().find(|s| s.name() == name) {
            return Ok(s.clone());
        }
        match &self.files {
            Some(base) => resolve_scene(name, base.as_deref()).map(|s| Arc::new(s.into())),
            None => {
                let names = self.names();
                Err(FactoryError::Unknown(format!(
                    "one of the scenes made by code ({}), found `{name}`{}",
                    names.join(", "),
                    crate::scene::did_you_mean(name, &names)
                )))
            }
        }
    }
}

impl fmt::Debug for Worlds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Worlds")
            .field("scenes", &self.names())
            .field("files", &self.files)
            .finish()
    }
}

/// How a custom learner is made: from its parameters, the command space,
/// the number of effects and the target.
pub type MakeLearner = dyn Fn(&Params, &CommandSpace, usize, &Target) -> Result<Box<dyn Learner + Send>, BoxError>
    + Send
    + Sync;

#[derive(Clone)]
enum Entry {
    Builtin(LearnerKind),
    Custom([bool; 5], Arc<MakeLearner>),
}

/// The learners a sweep names, registered by name and made afresh for
/// each session: the built-in ones ([`LearnerKind`], with
/// [`Learners::builtin`]) and your own.
///
/// A learner's name is written in `results.csv` and in the sessions'
/// identities (so in their seeds); it is a RON identifier (ASCII letters,
/// digits and `_`, not starting with a digit), to be written in a sweep
/// file. Its hyper-parameters are among [`Params::SWEPT`]: its grid spans
/// only those it uses, and the others are empty in the results.
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::sweep::Learners;
/// use e3d::{Learner, LearnerKind, Params};
/// // epsilon-greedy under another name, sweeping only epsilon
/// let learners = Learners::builtin().with("greedy", &["epsilon"], |p, space, n, target| {
///     let p = Params { alpha: 0.5, ..*p };
///     Ok(LearnerSetup::new(LearnerKind::Egreedy).params(p).target(target.clone()).symbols(space, n)?)
/// });
/// assert_eq!(learners.names(), ["e3d", "uniform", "egreedy", "e3d_relax", "count", "smm", "goal_babbling", "archive", "archive_reached", "map_elites", "qlearning_moves", "greedy"]);
/// assert_eq!(learners.uses("greedy"), Some([false, false, false, false, true]));
/// assert_eq!(learners.uses("e3d"), Some([true, true, true, true, false]));
/// assert_eq!(learners.uses("nope"), None);
/// ```
#[derive(Clone, Default)]
pub struct Learners {
    entries: Vec<(String, Entry)>,
}

impl Learners {
    /// No learner at all.
    pub fn new() -> Learners {
        Learners::default()
    }

    /// The built-in learners, `e3d sweep`'s: `e3d`, `uniform`, `egreedy`
    /// ([`LearnerSetup::symbols`](crate::learner::LearnerSetup::symbols), using the parameters of
    /// [`uses_param`]).
    pub fn builtin() -> Learners {
        Learners {
            entries: LearnerKind::ALL
                .into_iter()
                .map(|k| (k.as_str().to_string(), Entry::Builtin(k)))
                .collect(),
        }
    }

    /// Registers the learner `name`, which uses the hyper-parameters
    /// `uses` (among [`Params::SWEPT`]) and is made by `make`. It replaces
    /// any learner of that name registered before, built-in ones included.
    ///
    /// # Panics
    ///
    /// If `name` is not a RON identifier (ASCII letters, digits and `_`,
    /// not starting with a digit), or a parameter is not one of
    /// [`Params::SWEPT`]: mistakes in the program, not in its data.
    pub fn with<F>(mut self, name: &str, uses: &[&str], make: F) -> Learners
    where
        F: Fn(&Params, &CommandSpace, usize, &Target) -> Result<Box<dyn Learner + Send>, BoxError>
            + Send
            + Sync
            + 'static,
    {
        assert!(
            is_identifier(name),
            "learner `{name}`: a name of ASCII letters, digits and `_`, not starting with a digit"
        );
        for p in uses {
            assert!(
                Params::SWEPT.contains(p),
                "learner `{name}`: parameter `{p}` is not one of {}",
                Params::SWEPT.join(", ")
            );
        }
        let used = Params::SWEPT.map(|n| uses.contains(&n));
        let entry = Entry::Custom(used, Arc::new(make));
        match self.entries.iter_mut().find(|(n, _)| n == name) {
            Some(e) => e.1 = entry,
            None => self.entries.push((name.to_string(), entry)),
        }
        self
    }

    fn entry(&self, name: &str) -> Option<&Entry> {
        self.entries.iter().find(|(n, _)| n == name).map(|(_, e)| e)
    }

    /// The learners registered, in the order messages list them.
    pub fn names(&self) -> Vec<String> {
        self.entries.iter().map(|(n, _)| n.clone()).collect()
    }

    /// Which of [`Params::SWEPT`] learner `name` uses; `None` for a name
    /// not registered.
    pub fn uses(&self, name: &str) -> Option<[bool; 5]> {
        Some(match self.entry(name)? {
            Entry::Builtin(k) => std::array::from_fn(|i| uses_param(*k, Params::SWEPT[i])),
            Entry::Custom(used, _) => *used,
        })
    }

    /// A fresh learner `name` with `params` (those it does not use hold
    /// the first value of their list) for `space`, `num_effects` effects
    /// and the target `p*`; MAP-Elites keeps its elites by `effort` (the
    /// scene's, [`Effort::of_scene`]). An error stops the sweep.
    pub fn make(
        &self,
        name: &str,
        params: &Params,
        space: &CommandSpace,
        num_effects: usize,
        target: &Target,
        effort: Option<&Effort>,
    ) -> Result<Box<dyn Learner + Send>, BoxError> {
        let setup = |k| LearnerSetup {
            effort: effort.cloned(),
            ..LearnerSetup::new(k).params(*params).target(target.clone())
        };
        match self.entry(name) {
            Some(Entry::Builtin(k)) => Ok(setup(*k).symbols(space, num_effects)?),
            Some(Entry::Custom(_, make)) => make(params, space, num_effects, target),
            None => Err(unknown(name)),
        }
    }

    /// A fresh learner `name` of continuous commands (for a scene whose
    /// slots take values), as [`make`](Self::make) with the value space
    /// `space`: [`LearnerSetup::values`](crate::learner::LearnerSetup::values) for a built-in learner
    /// (e3d, uniform, goal_babbling, archive take values); a learner
    /// registered with [`with`](Learners::with) takes symbols only.
    pub fn make_continuous(
        &self,
        name: &str,
        params: &Params,
        space: &ValueSpace,
        num_effects: usize,
        target: &Target,
        effort: Option<&Effort>,
    ) -> Result<Box<dyn ContinuousLearner + Send>, BoxError> {
        let setup = |k| LearnerSetup {
            effort: effort.cloned(),
            ..LearnerSetup::new(k).params(*params).target(target.clone())
        };
        match self.entry(name) {
            Some(Entry::Builtin(k)) => Ok(setup(*k).values(space, num_effects)?),
            Some(Entry::Custom(..)) => Err(format!(
                "learner `{name}` (registered in code) takes symbols only, not continuous commands"
            )
            .into()),
            None => Err(unknown(name)),
        }
    }
}

impl fmt::Debug for Learners {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list()
            .entries(self.entries.iter().map(|(n, _)| n))
            .finish()
    }
}

/// The refusal of a learner no factory registered.
fn unknown(name: &str) -> BoxError {
    format!("no learner `{name}` in this factory").into()
}

/// Whether `name` is a RON identifier: ASCII letters, digits and `_`, not
/// starting with a digit (so also one CSV field, and unambiguous in an
/// identity).
pub(crate) fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Why a world was refused for a scene of commands `space` and
/// `effects` effects, naming both command spaces; `None` for a world of
/// that space and effects.
pub(super) fn mismatch(space: &CommandSpace, effects: usize, world: &dyn World) -> Option<String> {
    if world.command_space() == space && world.num_effects() == effects {
        return None;
    }
    let (ours, theirs) = (describe_space(space), describe_space(world.command_space()));
    let n = world.num_effects();
    Some(format!(
        "whose commands are {ours} with {effects} effects, but the world's commands are {theirs} with {n} effects"
    ))
}

/// A command space in a sentence: `7 slots of ESWN`, or each slot's
/// alphabet.
pub(crate) fn describe_space(space: &CommandSpace) -> String {
    let alphabet = |i: usize| -> String { space.alphabet(i).iter().collect() };
    let n = space.num_slots();
    crate::command::echo(&if (1..n).all(|i| space.alphabet(i) == space.alphabet(0)) {
        format!(
            "{n} slot{} of `{}`",
            if n == 1 { "" } else { "s" },
            alphabet(0)
        )
    } else {
        let each: Vec<String> = (0..n).map(|i| format!("`{}`", alphabet(i))).collect();
        format!("slots {}", each.join(", "))
    })
}
