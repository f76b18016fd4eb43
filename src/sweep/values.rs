//! Sweeps over scenes of continuous commands (slots that take values, such
//! as `arm7_continuous`).
//!
//! Such a scene has no outcome table or memo: every trial is simulated.
//! Its sessions run as `e3d run SCENE --sessions N` runs them
//! ([`Executor::for_values`](crate::world::Executor::for_values)): cut into lockstep groups, each group's
//! values stepped together on one world of several copies where the
//! scene's copies are exact (one session per world elsewhere), the groups
//! in parallel. A session's results are those of
//! [`run_value_session`](crate::session::run_value_session) alone, whatever the
//! threads, the groups and the shards. Its learner is the continuous form
//! of the cell's learner
//! ([`Learners::make_continuous`](super::Learners::make_continuous)); its
//! metrics are computed from its effects and rewards as for a session of
//! symbols. The checks of such a sweep are made where it is planned
//! (`plan.rs`), the worlds of such a scene where scenes are prepared
//! (`factory.rs`).

use super::plan::{SessionSpec, Sweep};
use super::SweepError;
use crate::effect::Target;
use crate::learner::ContinuousLearner;
use crate::world::ContinuousWorld;

impl Sweep {
    /// The learners of `sessions` (all of one continuous scene) on `world`:
    /// the continuous form of each cell's learner.
    pub(super) fn value_learners(
        &self,
        sessions: &[SessionSpec],
        world: &dyn ContinuousWorld,
    ) -> Result<Vec<Box<dyn ContinuousLearner + Send>>, SweepError> {
        sessions
            .iter()
            .map(|s| {
                let cell = &self.cells[s.cell];
                self.learners
                    .make_continuous(
                        &cell.learner,
                        &cell.params,
                        world.value_space(),
                        world.num_effects(),
                        &Target::Uniform,
                    )
                    .map_err(|source| SweepError::Learner {
                        learner: cell.learner.clone(),
                        source,
                    })
            })
            .collect()
    }
}
