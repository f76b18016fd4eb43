//! Sweeps over scenes of continuous commands (slots that take values, such
//! as `arm7_continuous`).
//!
//! Such a scene has no outcome table or memo: every trial is simulated.
//! Its sessions run as `e3d run SCENE --sessions N` runs them
//! ([`Executor::for_values`](crate::world::Executor::for_values)): cut into lockstep groups, each group's
//! values stepped together on one world of several copies where the
//! scene's copies are exact (one session per world elsewhere), the groups
//! in parallel. A session's results are those of
//! [`run_value_session`](crate::run_value_session) alone, whatever the
//! threads, the groups and the shards. Its learner is the continuous form
//! of the cell's learner
//! ([`LearnerFactory::make_continuous`](super::LearnerFactory::make_continuous)); its
//! metrics are computed from its effects and rewards as for a session of
//! symbols. The checks of such a sweep are made where it is planned
//! (`plan.rs`), the worlds of such a scene where scenes are prepared
//! (`factory.rs`).

use super::plan::{SessionSpec, Sweep};
use super::results::SessionResult;
use super::SweepError;
use crate::command::Command;
use crate::effect::Target;
use crate::learner::ContinuousLearner;
use crate::session::{run_value_lockstep, Recorder, SessionConfig};
use crate::world::{ContinuousWorld, Outcome};

impl Sweep {
    /// Runs `sessions` (all of one continuous scene) together on `world`
    /// ([`run_value_lockstep`]): at each trial the values of all of them
    /// are executed in one batch. The results are those of each session
    /// run alone on a world of one copy, in order, when `world`'s batches
    /// give each command's single-world outcome (the worlds of
    /// [`SceneRun::value_world`](super::factory::SceneRun::value_world) do).
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
