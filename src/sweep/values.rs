//! Sweeps over scenes of continuous commands (slots that take values, such
//! as `arm7_continuous`).
//!
//! Such a scene has no outcome table or memo: every trial is simulated.
//! Its sessions run as `e3d run SCENE --sessions N` runs them
//! ([`Executor::for_values`]): cut into lockstep groups, each group's
//! values stepped together on one world of several copies where the
//! scene's copies are exact (one session per world elsewhere), the groups
//! in parallel. A session's results are those of
//! [`run_value_session`](crate::run_value_session) alone, whatever the
//! threads, the groups and the shards. Its learner is the continuous form
//! of the cell's learner ([`LearnerFactory::make_continuous`]); its
//! metrics are computed from its effects and rewards as for a session of
//! symbols.

use super::factory::{LearnerFactory, SceneRun, SweepScene};
use super::plan::{SessionSpec, Sweep};
use super::results::SessionResult;
use super::SweepError;
use crate::command::Command;
use crate::effect::Target;
use crate::learner::{ContinuousLearner, Params};
use crate::scene::Scene;
use crate::session::{run_value_lockstep, Recorder, SessionConfig};
use crate::world::{ContinuousWorld, ExecOptions, Executor, Outcome, Strategy, Workload, World};
use std::sync::Arc;

/// The executor of a continuous scene's sessions in a sweep: live, in the
/// lockstep groups of [`Executor::for_values`]. A forced table or memo is
/// refused (values cannot be tabled or memoised).
pub(super) fn prepare<'a>(
    scene: &'a Scene,
    work: &Workload,
    options: &ExecOptions,
) -> Result<Box<dyn SceneRun + 'a>, SweepError> {
    if let Some(s @ (Strategy::Table | Strategy::Memo)) = options.force {
        return Err(forced_error(&scene.name, s));
    }
    let exec = Executor::for_values(scene, work)?;
    Ok(Box::new(ValueRun(exec)))
}

/// The refusal of a table or memo forced on the continuous scene `scene`.
pub(super) fn forced_error(scene: &str, forced: Strategy) -> SweepError {
    SweepError::Other(format!(
        "scene `{scene}` takes continuous commands, which run live only (no table, no memo), but the sweep forces {forced}"
    ))
}

/// The worlds of a continuous scene during one run.
struct ValueRun<'a>(Executor<'a>);

impl SceneRun for ValueRun<'_> {
    fn session_groups(&self, sessions: usize) -> Vec<std::ops::Range<usize>> {
        self.0.session_groups(sessions)
    }
    /// The scene's world of symbols, whose placeholder space refuses every
    /// command (the sessions run on [`value_world`](Self::value_world)).
    fn world(&self, width: usize) -> Box<dyn World + Send + '_> {
        self.0.world(width)
    }
    fn value_world(&self, width: usize) -> Option<Box<dyn ContinuousWorld + Send + '_>> {
        Some(Box::new(self.0.value_world(width)))
    }
    fn describe(&self) -> Option<String> {
        Some(self.0.plan().to_string())
    }
}

/// Checks, while the sweep is planned, that every learner of the sweep
/// takes continuous commands on each continuous scene (a learner of
/// symbols only is refused with its reason) and that no continuous scene
/// runs episodes. `bad(field, anchor, expected)` places the error.
pub(super) fn check(
    scenes: &[Arc<dyn SweepScene>],
    learners: &dyn LearnerFactory,
    names: &[String],
    episodes: bool,
    bad: &dyn Fn(&str, Option<&str>, &str) -> SweepError,
) -> Result<(), SweepError> {
    for s in scenes {
        let Some(space) = s.scene().and_then(Scene::value_space) else {
            continue;
        };
        let anchor = format!("\"{}\"", s.name());
        if episodes {
            return Err(bad(
                "scenes",
                Some(&anchor),
                &format!("scenes of symbols in a sweep of episodes (commands, observe or closed_loop set), found `{}`, whose slots take values (`Continuous`)", s.name()),
            ));
        }
        for name in names {
            let made = learners.make_continuous(
                name,
                &Params::TASK1,
                &space,
                s.num_effects(),
                &Target::Uniform,
            );
            if let Err(e) = made {
                return Err(bad(
                    "learners",
                    None,
                    &format!(
                        "learners that take continuous commands on scene `{}`, found `{name}`: {e}",
                        s.name()
                    ),
                ));
            }
        }
    }
    Ok(())
}

impl Sweep {
    /// Runs `sessions` (all of one continuous scene) together on `world`
    /// ([`run_value_lockstep`]): at each trial the values of all of them
    /// are executed in one batch. The results are those of each session
    /// run alone on a world of one copy, in order, when `world`'s batches
    /// give each command's single-world outcome (the worlds of
    /// [`SceneRun::value_world`] do).
    pub fn run_value_sessions_lockstep(
        &self,
        sessions: &[SessionSpec],
        world: &mut dyn ContinuousWorld,
    ) -> Result<Vec<SessionResult>, SweepError> {
        let space = world.value_space().clone();
        let num_effects = world.num_effects();
        let mut learners = sessions
            .iter()
            .map(|s| {
                let cell = &self.cells[s.cell];
                self.learners
                    .make_continuous(
                        &cell.learner,
                        &cell.params,
                        &space,
                        num_effects,
                        &Target::Uniform,
                    )
                    .map_err(|source| SweepError::Learner {
                        learner: cell.learner.clone(),
                        source,
                    })
            })
            .collect::<Result<Vec<Box<dyn ContinuousLearner + Send>>, _>>()?;
        let configs: Vec<SessionConfig> = sessions.iter().map(|s| self.config(s)).collect();
        let records = run_value_lockstep(world, &mut learners, &configs, |t| self.count_trials(t));
        let none = Command::new(Vec::new());
        Ok(sessions
            .iter()
            .zip(records)
            .map(|(s, record)| {
                let mut running = self.recorder_of(num_effects);
                let record = match record {
                    Ok(r) => r,
                    Err(e) => return self.result(s, Err(e), &running),
                };
                for (&effect, &reward) in record.effects.iter().zip(&record.rewards) {
                    let outcome = Outcome {
                        effect,
                        reward,
                        point: [0.0; 2],
                    };
                    running.record(&none, &outcome);
                }
                self.result(s, Ok(()), &running)
            })
            .collect())
    }
}
