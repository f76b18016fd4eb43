//! A session in one line: [`Session`], the front door of the engine.

use super::{run_sessions, Control, SessionConfig, SessionRecord};
use crate::effect::Target;
use crate::learner::{LearnerError, LearnerKind, LearnerSetup, Params};
use crate::scene::Scene;
use crate::world::{ExecOptions, Executor, Workload, WorldError};

/// Sessions of a scene of symbols set up in one line, with `e3d run`'s
/// defaults (E3D, the paper's task 1 parameters, 5000 trials, seed 0, the
/// scene's reward seen), run the way `e3d run` runs them: the cheapest of
/// an outcome table, a memo or live worlds, the sessions in lockstep
/// groups on every core of the current rayon pool. The records are those
/// of [`run_session`](super::run_session) on the scene's own world,
/// whatever is chosen.
///
/// ```
/// use e3d::prelude::*;
/// use e3d::Session;
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let record = Session::new(&scene, LearnerKind::E3d).trials(2000).seed(3).run()?;
/// assert_eq!(record.trials(), 2000);
/// // several sessions, seeded 3, 4, 5, in parallel
/// let three = Session::new(&scene, LearnerKind::Uniform).trials(500).seed(3).run_many(3)?;
/// assert_eq!(three.len(), 3);
/// # Ok::<(), e3d::session::SessionError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Session<'s> {
    scene: &'s Scene,
    setup: LearnerSetup,
    trials: usize,
    seed: u64,
    use_reward: bool,
    options: ExecOptions,
}

/// Why a [`Session`] did not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError {
    /// The learner cannot be made (a parameter out of its range, a scene
    /// of values for a learner of symbols).
    #[error(transparent)]
    Learner(#[from] LearnerError),
    /// The world failed (a command blew up, the run was stopped).
    #[error(transparent)]
    World(#[from] WorldError),
}

impl<'s> Session<'s> {
    /// A session of `learner` on `scene`, with `e3d run`'s defaults.
    pub fn new(scene: &'s Scene, learner: LearnerKind) -> Self {
        Session {
            scene,
            setup: LearnerSetup::new(learner).effort_of(scene),
            trials: 5000,
            seed: 0,
            use_reward: true,
            options: ExecOptions::default(),
        }
    }

    /// The learner's hyper-parameters (default [`Params::TASK1`]).
    pub fn params(mut self, params: Params) -> Self {
        self.setup.params = params;
        self
    }

    /// The target distribution of effects (default uniform).
    pub fn target(mut self, target: Target) -> Self {
        self.setup = self.setup.target(target);
        self
    }

    /// The number of trials (default 5000).
    pub fn trials(mut self, trials: usize) -> Self {
        self.trials = trials;
        self
    }

    /// The seed of the (first) session (default 0).
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Whether the learner sees the scene's reward (default `true`;
    /// `false` is the paper's task 1, `e3d run --no-reward`).
    pub fn reward(mut self, seen: bool) -> Self {
        self.use_reward = seen;
        self
    }

    /// How outcomes are obtained: a table folder, the memo's cap, a forced
    /// strategy (default: the cheapest, no folder).
    pub fn outcomes(mut self, options: ExecOptions) -> Self {
        self.options = options;
        self
    }

    /// Runs the session: its record.
    pub fn run(&self) -> Result<SessionRecord, SessionError> {
        let mut records = self.run_many(1)?;
        Ok(records.remove(0))
    }

    /// Runs `sessions` sessions seeded `seed`, `seed + 1`, ... (wrapping),
    /// in parallel: their records, in order. The first failure is the
    /// error.
    pub fn run_many(&self, sessions: usize) -> Result<Vec<SessionRecord>, SessionError> {
        let space = self.scene.command_space();
        let effects = self.scene.num_effects();
        let mut learners = (0..sessions)
            .map(|_| self.setup.symbols(&space, effects))
            .collect::<Result<Vec<_>, _>>()?;
        let configs: Vec<SessionConfig> = (0..sessions as u64)
            .map(|i| SessionConfig {
                trials: self.trials,
                seed: self.seed.wrapping_add(i),
                use_reward: self.use_reward,
            })
            .collect();
        let work = Workload {
            trials: (self.trials as u64).saturating_mul(sessions as u64),
            sessions,
            threads: rayon::current_num_threads(),
        };
        let exec = Executor::new(self.scene, &work, &self.options)?;
        let mut records: Vec<SessionRecord> = configs
            .iter()
            .map(|c| SessionRecord::with_room(space.num_slots(), effects, c.trials))
            .collect();
        let status = run_sessions(
            &exec,
            &mut learners,
            &configs,
            &mut records,
            &Control::default(),
        );
        exec.finish();
        for s in status {
            s?;
        }
        Ok(records)
    }
}
