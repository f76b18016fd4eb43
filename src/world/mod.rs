//! Worlds: what executes a whole [`Command`] open loop and reports its
//! [`Outcome`]: [`GridWorld`], the Rapier [`PhysicsWorld`], the
//! [`OutcomeTable`] (every command once), the [`OutcomeMemo`] (every
//! proposed command once), and the [`Executor`] of an [`ExecutionPlan`]
//! chosen by cost. Implement [`World`] to plug in your own simulator.

mod accuracy;
mod context_memo;
mod control;
mod executor;
mod from_scene;
mod grid;
mod memo;
mod physics;
mod plan;
mod reach;
mod table;

pub use crate::scene::GridSpec;
pub use accuracy::{
    accuracy, AccuracyRow, ACCURACY_SETTINGS, CONVERGED_DT_DIVISOR, CONVERGED_ITERATIONS,
};
pub use context_memo::ContextMemoized;
pub use control::{Control, Observer};
pub use executor::Executor;
pub use from_scene::{ContinuousScene, PhysicsScene, ValueWorld};
pub use grid::GridWorld;
pub use memo::{Memoized, OutcomeMemo, DEFAULT_MEMO_CAP};
pub use physics::{
    BodyPose, Frame, Motion, PhysicsState, PhysicsWorld, RunStats, Trace, MAX_COPIES, PREFIX_STATES,
};
pub use plan::{
    batch_rollout_seconds, calibration_on, lockstep_groups, rollout_seconds, timed_rollout_seconds,
    ExecOptions, ExecutionPlan, OnDisk, ParseStrategyError, Strategy, Workload,
    CALIBRATION_MAX_ROLLOUTS, CALIBRATION_ROLLOUTS, CALIBRATION_SECONDS,
};
pub use reach::{
    farthest_reached_cell, sample_reach, sample_reach_with, FarthestCell, ReachSample,
};
pub use table::{
    seed0_start, start_contexts, table_copies, CachedOutcomes, ContextTables, OutcomeTable,
    StartContext, TabledContexts, MAX_TABLE_COMMANDS, TABLE_COPIES,
};

use crate::command::{Command, CommandSpace, ValueSpace};
use crate::scene::physics::DrawKey;
use serde::{Deserialize, Serialize};

/// The e3d version written into output folders and every outcome table's
/// key: the crate's version and [`PHYSICS_FINGERPRINT`]
/// (`0.1.0+physics.1a2b3c4d`).
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    "+physics.",
    env!("E3D_PHYSICS_FINGERPRINT")
);

/// A hash (8 hex digits) of the code that decides what a command does,
/// computed by `build.rs` (see ARCHITECTURE.md, "Reproducibility").
pub const PHYSICS_FINGERPRINT: &str = env!("E3D_PHYSICS_FINGERPRINT");

/// What the learner reads after a command: the terminal state, binned.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// The effect: the bin of the terminal state, in `0..num_effects`.
    pub effect: usize,
    /// The (extrinsic) reward.
    pub reward: f64,
    /// The terminal position `(x, y)` of the tracked point, in metres (on a
    /// grid: the centre of the terminal cell, cells being 1 x 1 with row 0
    /// at the top).
    pub point: [f64; 2],
}

/// A state of a world from which a command can start
/// ([`Episodic::execute_from`]), and the state a command leaves: what a
/// closed loop carries from one command to the next.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub enum WorldState {
    /// A grid cell, `row * cols + col`.
    Cell(usize),
    /// A state of a physics world: poses, velocities, joint coordinates
    /// and the snapshot of the Rapier sets it continues from.
    Physics(PhysicsState),
}

impl WorldState {
    /// The named start context this state is the start of, if any: the
    /// outcome of a command from it depends only on `(context, command)`
    /// (see [`ContextMemoized`]). `None` for a grid cell, a drawn start and
    /// the state a command left.
    pub fn context(&self) -> Option<usize> {
        match self {
            WorldState::Cell(_) => None,
            WorldState::Physics(s) => s.context,
        }
    }
}

/// A failure while executing a command.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WorldError {
    /// The command does not fit the world's command space.
    #[error("command {command} does not fit this world: {reason}")]
    BadCommand {
        /// The command, as symbol indices.
        command: String,
        /// Why.
        reason: String,
    },
    /// The simulation produced a non-finite or exploding state.
    #[error("scene `{scene}`, command `{command}`: the simulation blew up: {reason}")]
    Diverged {
        /// The scene's name.
        scene: String,
        /// The command, as symbols.
        command: String,
        /// What went wrong.
        reason: String,
    },
    /// The run was stopped ([`Control::stop`](Control)
    /// said so): a Ctrl-C, a cancelled call.
    #[error("stopped")]
    Stopped,
    /// Any other failure of a user's world.
    #[error("{0}")]
    Other(String),
}

/// `Ok` if `command` fits `space` (one symbol per slot, each in its
/// slot's alphabet), else the [`WorldError::BadCommand`] every world of
/// e3d returns for it. Call it from your own [`World::execute`] to behave
/// the same way.
///
/// ```
/// use e3d::world::check_command;
/// use e3d::{Command, WorldError};
/// use e3d::command::CommandSpace;
/// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
/// assert!(check_command(&space, &Command::new(vec![0, 1])).is_ok());
/// let e = check_command(&space, &Command::new(vec![0, 2])).unwrap_err();
/// assert!(matches!(e, WorldError::BadCommand { .. }));
/// assert_eq!(e.to_string(), "command [0, 2] does not fit this world: slot 1 has no symbol 2");
/// ```
pub fn check_command(space: &CommandSpace, command: &Command) -> Result<(), WorldError> {
    let symbols = &command.symbols;
    let reason = if command.len() != space.num_slots() {
        format!("expected {} slots", space.num_slots())
    } else if let Some(slot) =
        (symbols.iter().zip(space.sizes())).position(|(&s, k)| s as usize >= k)
    {
        format!("slot {slot} has no symbol {}", symbols[slot])
    } else {
        return Ok(());
    };
    let command = command.to_string();
    Err(WorldError::BadCommand { command, reason })
}

/// A world that executes commands open loop.
///
/// ```
/// use e3d::{Command, Outcome, World, WorldError};
/// use e3d::command::CommandSpace;
///
/// /// Effect = number of 'b' symbols.
/// struct CountB { space: CommandSpace }
///
/// impl World for CountB {
///     fn command_space(&self) -> &CommandSpace { &self.space }
///     fn num_effects(&self) -> usize { self.space.num_slots() + 1 }
///     fn execute(&mut self, c: &Command) -> Result<Outcome, WorldError> {
///         let n = c.symbols.iter().filter(|&&s| s == 1).count();
///         Ok(Outcome { effect: n, reward: 0.0, point: [n as f64, 0.0] })
///     }
/// }
///
/// let mut w = CountB { space: CommandSpace::repeat(3, &['a', 'b']).unwrap() };
/// let c = w.command_space().parse("bab").unwrap();
/// assert_eq!(w.execute(&c).unwrap().effect, 2);
/// ```
pub trait World {
    /// The commands this world accepts.
    fn command_space(&self) -> &CommandSpace;

    /// The number of effects: every outcome's effect is below it.
    fn num_effects(&self) -> usize;

    /// Executes `command` open loop from the start state and returns its
    /// terminal outcome. The world is back at its start state for the next
    /// call: commands do not influence each other.
    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError>;

    /// Whether the same command always gives the same outcome. Deterministic
    /// worlds with a small command space can be replaced by an
    /// [`OutcomeTable`], which executes each command only once.
    fn is_deterministic(&self) -> bool {
        true
    }

    /// The keys of the draws of the next commands executed, one per
    /// command of the next [`execute`](World::execute) (one key) or
    /// [`execute_batch`](World::execute_batch): a noisy world (a scene's
    /// `noise` section) draws each command's noise from its key, so that
    /// its outcome depends on the key, never on the batch or the thread.
    /// A key holds the session's key (numbers drawn once per session) and
    /// the execution's; the session engine gives
    /// [`DrawKey::trial`]`(session seed, trial)`. Deterministic worlds
    /// ignore it (the default).
    fn set_draw_keys(&mut self, _keys: &[DrawKey]) {}

    /// Executes several commands, each from the start state, and appends
    /// their outcomes to `out` in order: the same outcomes as calling
    /// [`execute`](World::execute) on each. Worlds that can run many
    /// commands at once (several copies of a scene stepped together)
    /// override it; the default executes them one by one.
    fn execute_batch(&mut self, commands: &[Command], out: &mut Vec<Result<Outcome, WorldError>>) {
        for c in commands {
            out.push(self.execute(c));
        }
    }

    /// Under a mirror symmetry: the command whose outcome, through
    /// [`mirror_outcome`](World::mirror_outcome), is `command`'s (its
    /// mirror image), when the world simulates that one in its place.
    /// `None` (the default) for a command simulated itself. An
    /// [`OutcomeMemo`] keeps only the simulated command of each pair.
    fn mirror_of(&self, _command: &Command) -> Option<Command> {
        None
    }

    /// The outcome of a command's mirror image from the command's outcome
    /// (see [`mirror_of`](World::mirror_of)); an involution, bit for bit.
    /// The default leaves it unchanged.
    fn mirror_outcome(&self, outcome: Outcome) -> Outcome {
        outcome
    }
}

/// A world whose commands can start from given states: its start
/// contexts, and the terminal state of one command carried on to the next
/// ([`run_episodes`](crate::episode::run_episodes): episodes of several
/// commands, closed loops). Every scene's world is one
/// ([`Scene::build`](crate::Scene::build)); an [`OutcomeTable`], which
/// keeps outcomes and no states, is not.
pub trait Episodic: World {
    /// The number of start contexts (1 unless the scene declares several;
    /// see [`draw_start`](Episodic::draw_start)).
    fn num_contexts(&self) -> usize {
        1
    }

    /// The start state of context `context` (`< num_contexts()`), drawn
    /// with `rng` when the context is a range of states.
    fn draw_start(
        &self,
        context: usize,
        rng: &mut crate::rng::SessionRng,
    ) -> Result<WorldState, WorldError>;

    /// The bin of a state (the effect a command ending there has): what a
    /// closed loop observes between commands.
    fn bin_state(&self, state: &WorldState) -> Result<usize, WorldError>;

    /// Executes `command` open loop from the state `from` and returns its
    /// outcome and the terminal state, from which the next command of a
    /// closed loop continues exactly: executing `c1` from `s`, then `c2`
    /// from the state it left, gives the terminal state of one continued
    /// execution of `c1` then `c2`.
    fn execute_from(
        &mut self,
        from: &WorldState,
        command: &Command,
    ) -> Result<(Outcome, WorldState), WorldError>;

    /// The outcome of [`execute_from`](Episodic::execute_from) without the
    /// terminal state, when no command follows (the last of an episode):
    /// wrappers that keep outcomes ([`ContextMemoized`]) look it up.
    fn execute_outcome_from(
        &mut self,
        from: &WorldState,
        command: &Command,
    ) -> Result<Outcome, WorldError> {
        self.execute_from(from, command).map(|(o, _)| o)
    }
}

/// A world whose commands are values (one per slot, in its range: a
/// [`ValueSpace`]) rather than symbols: continuous commands.
/// [`PhysicsWorld`] of a scene with `Continuous` slots is one; implement
/// it to plug in your own simulator.
pub trait ContinuousWorld {
    /// The ranges of the slots.
    fn value_space(&self) -> &ValueSpace;

    /// The number of effects: every outcome's effect is below it.
    fn num_effects(&self) -> usize;

    /// Executes `values` open loop from the start state and returns the
    /// terminal outcome (a [`WorldError::BadCommand`] for values that do
    /// not fit the space).
    fn execute_values(&mut self, values: &[f64]) -> Result<Outcome, WorldError>;

    /// The keys of the draws of the next commands, as
    /// [`World::set_draw_keys`]; deterministic worlds ignore it (the
    /// default).
    fn set_draw_keys(&mut self, _keys: &[DrawKey]) {}

    /// Whether the same values always give the same outcome (no `noise`),
    /// as [`World::is_deterministic`]; the default says no.
    fn is_deterministic(&self) -> bool {
        false
    }

    /// Executes several commands, each from the start state, appending
    /// their outcomes to `out` in order; the default runs them one by one.
    fn execute_values_batch(
        &mut self,
        commands: &[Vec<f64>],
        out: &mut Vec<Result<Outcome, WorldError>>,
    ) {
        for v in commands {
            out.push(self.execute_values(v));
        }
    }
}

/// The methods of [`World`] (`world`) or [`Episodic`] (`episodic`) that a
/// wrapper leaves to the world `$inner` it wraps, forwarded.
macro_rules! forward {
    (world $s:ident => $inner:expr) => {
        fn command_space(&$s) -> &CommandSpace {
            $inner.command_space()
        }
        fn num_effects(&$s) -> usize {
            $inner.num_effects()
        }
        fn execute(&mut $s, command: &Command) -> Result<Outcome, WorldError> {
            $inner.execute(command)
        }
        fn is_deterministic(&$s) -> bool {
            $inner.is_deterministic()
        }
        fn set_draw_keys(&mut $s, keys: &[$crate::scene::physics::DrawKey]) {
            $inner.set_draw_keys(keys)
        }
        fn execute_batch(
            &mut $s,
            commands: &[Command],
            out: &mut Vec<Result<Outcome, WorldError>>,
        ) {
            $inner.execute_batch(commands, out)
        }
        fn mirror_of(&$s, command: &Command) -> Option<Command> {
            $inner.mirror_of(command)
        }
        fn mirror_outcome(&$s, outcome: Outcome) -> Outcome {
            $inner.mirror_outcome(outcome)
        }
    };
    (episodic $s:ident => $inner:expr) => {
        fn num_contexts(&$s) -> usize {
            $inner.num_contexts()
        }
        fn draw_start(
            &$s,
            context: usize,
            rng: &mut crate::rng::SessionRng,
        ) -> Result<WorldState, WorldError> {
            $inner.draw_start(context, rng)
        }
        fn bin_state(&$s, state: &WorldState) -> Result<usize, WorldError> {
            $inner.bin_state(state)
        }
        fn execute_from(
            &mut $s,
            from: &WorldState,
            command: &Command,
        ) -> Result<(Outcome, WorldState), WorldError> {
            $inner.execute_from(from, command)
        }
    };
}
use forward;

impl<W: World + ?Sized> World for Box<W> {
    forward!(world self => (**self));
}

impl<W: Episodic + ?Sized> Episodic for Box<W> {
    forward!(episodic self => (**self));
    fn execute_outcome_from(
        &mut self,
        from: &WorldState,
        command: &Command,
    ) -> Result<Outcome, WorldError> {
        (**self).execute_outcome_from(from, command)
    }
}
