//! Sweeps of episodes (scenes with start contexts, or
//! [`SweepSpec::commands`], [`SweepSpec::observe`] or
//! [`SweepSpec::closed_loop`] set), and per-move Q-learning
//! (`qlearning_moves`) in any sweep: each session runs [`run_episodes`] with
//! the contextual form of its learner on a live world of its own; a trial
//! of the metrics is an episode (its terminal effect, its reward).
//! Per-move Q-learning runs on the scene of one-move commands
//! ([`Scene::with_moves`]), `commands x n` of them an episode (the moves
//! of `commands` commands of the scene's `n`), observing the current cell
//! unless the spec says otherwise.

use super::plan::{SessionSpec, Sweep};
use super::results::SessionResult;
use super::spec::MetricSpec;
#[cfg(doc)]
use super::spec::SweepSpec;
use super::SweepError;
use crate::episode::{run_episodes, EpisodeConfig, Observe};
use crate::learner::{ClosedLoopE3d, LearnerKind, LearnerSetup};
use crate::session::Recorder;
use crate::world::Outcome;
use crate::Scene;

impl Sweep {
    /// Whether the sessions of scene `scene` (its index in
    /// [`scenes`](Self::scenes)) run episodes: the sweep sets
    /// [`SweepSpec::runs_episodes`], or the scene has several start
    /// contexts.
    pub fn runs_episodes(&self, scene: usize) -> bool {
        self.spec.runs_episodes() || self.start_contexts(scene) > 1
    }

    /// The number of start contexts of scene `scene` (1 for a scene made
    /// by code).
    pub fn start_contexts(&self, scene: usize) -> usize {
        self.contexts[scene]
    }

    /// What the learners of a sweep of episodes observe: the spec's
    /// choice, else the current state with several commands per episode
    /// or a closed loop, and the start context otherwise.
    pub fn observe(&self) -> Observe {
        match self.spec.observe {
            Some(o) => o,
            None if self.spec.commands > 1 || self.spec.closed_loop => Observe::State,
            None => Observe::StartContext,
        }
    }

    /// Whether `session` is per-move Q-learning's (run as episodes
    /// whatever the scene).
    pub fn per_move(&self, session: &SessionSpec) -> bool {
        self.cells[session.cell].learner == LearnerKind::QlearningMoves.as_str()
    }

    /// Runs one session of episodes (a scene that runs them,
    /// [`runs_episodes`](Self::runs_episodes), or per-move Q-learning) on a
    /// world of `scene`.
    pub fn run_episode_session(
        &self,
        session: &SessionSpec,
        scene: &Scene,
    ) -> Result<SessionResult, SweepError> {
        let cell = &self.cells[session.cell];
        let kind: LearnerKind = cell.learner.parse().map_err(|_| {
            SweepError::Other(format!(
                "learner `{}`: a sweep of episodes runs built-in learners only",
                cell.learner
            ))
        })?;
        let (mut config, single) = (
            EpisodeConfig {
                episodes: self.spec.trials,
                commands: self.spec.commands,
                seed: session.seed,
                use_reward: cell.use_reward,
                observe: self.observe(),
            },
            None,
        );
        let single = match kind {
            LearnerKind::QlearningMoves => {
                let name = crate::text::echo(&scene.spec().name);
                let one = scene.with_moves(1).ok_or_else(|| {
                    SweepError::Other(format!(
                        "learner qlearning_moves on scene `{name}`: its command is not `Repeat` (one alphabet for every move), so it has no single move to choose"
                    ))
                })??;
                config.commands = self.spec.commands * scene.spec().num_slots();
                config.observe = self.spec.observe.unwrap_or(crate::episode::Observe::State);
                Some(one)
            }
            _ => single,
        };
        let mut world = single.as_ref().unwrap_or(scene).build();
        let world = &mut *world;
        // a closed-loop sweep runs closed-loop E3D and Q-learning, and the
        // contextual form of every other learner beside them
        let closed =
            self.spec.closed_loop && matches!(kind, LearnerKind::E3d | LearnerKind::Egreedy);
        let mut learner = self.learner(session, |c| {
            Ok(LearnerSetup::new(kind)
                .params(c.params)
                .effort_of(single.as_ref().unwrap_or(scene))
                .closed_loop(closed)
                .gamma(self.spec.gamma.unwrap_or(ClosedLoopE3d::GAMMA))
                .contexts(
                    world.command_space(),
                    world.num_effects(),
                    config.num_contexts(world),
                )?)
        })?;
        let mut running = self.recorder(world.num_effects());
        let control = crate::session::Control::default();
        let record = match run_episodes(world, &mut *learner, &config, &control) {
            Ok(r) => r,
            Err(e) => return Ok(self.result(session, Err(e), &running)),
        };
        self.count_trials(record.episodes() as u64);
        let any = world.command_space().first();
        for (effect, reward) in record.terminal_effects().zip(record.episode_rewards()) {
            let outcome = Outcome {
                effect,
                reward,
                point: [0.0; 2],
            };
            running.record(&any, &outcome);
        }
        let mut result = self.result(session, Ok(()), &running);
        let starts = self.start_contexts(cell.scene);
        let entropy = record.entropy_per_start(starts);
        let reward = record.reward_per_start(starts);
        let first = record.first_reward_per_start(starts);
        for (value, metric) in result.values.iter_mut().zip(&self.metrics) {
            match *metric {
                MetricSpec::NormalizedEntropyContext(i) => *value = entropy.get(i).copied(),
                MetricSpec::CumulativeRewardContext(i) => *value = reward.get(i).copied(),
                MetricSpec::FirstRewardTrialContext(i) => {
                    *value = first.get(i).copied().flatten().map(|t| t as f64)
                }
                MetricSpec::Reproducibility => {
                    let options = crate::session::RepeatOptions::default();
                    let r =
                        crate::session::episode_reproducibility(world, &*learner, &config, options);
                    match r {
                        Ok(r) => *value = r.map(|r| r.share),
                        Err(e) => return Ok(self.result(session, Err(e), &running)),
                    }
                }
                _ => {}
            }
        }
        Ok(result)
    }
}
