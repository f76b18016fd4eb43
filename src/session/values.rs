//! Sessions of continuous commands: the trial loop with values in place
//! of symbols, and what it records.

use super::{Control, SessionConfig, TrialRecord};
use crate::command::ValueSpace;
use crate::learner::ContinuousLearner;
use crate::world::{ContinuousWorld, WorldError};
use std::io::{self, Write};

/// What a session of continuous commands recorded.
pub type ValueSessionRecord = TrialRecord<f64>;

impl ValueSessionRecord {
    /// A record of no trials yet, with room for `trials`.
    pub fn new(num_slots: usize, num_effects: usize, trials: usize) -> ValueSessionRecord {
        Self::with_room(num_slots, num_effects, trials)
    }

    /// Sets [`final_policy`](Self::final_policy) from `learner`'s policy now.
    pub fn set_policy<L: ContinuousLearner + ?Sized>(&mut self, learner: &L) {
        self.final_policy = (0..self.num_slots)
            .map(|s| learner.slot_gaussian(s))
            .collect();
    }

    /// Writes `trial,values,effect,reward,x,y` CSV, one row per trial
    /// (trial 1-based; the values as [`ValueSpace::format`] writes them,
    /// quoted, for they hold commas), with a first `session` column when
    /// `session` is given.
    pub fn write_trials_csv(
        &self,
        space: &ValueSpace,
        session: Option<usize>,
        header: bool,
        mut out: impl Write,
    ) -> io::Result<()> {
        let lead = |s: Option<usize>| s.map_or(String::new(), |s| format!("{s},"));
        if header {
            let h = if session.is_some() { "session," } else { "" };
            writeln!(out, "{h}trial,values,effect,reward,x,y")?;
        }
        for t in 0..self.trials() {
            let [x, y] = self.points[t];
            writeln!(
                out,
                "{}{},\"{}\",{},{},{},{}",
                lead(session),
                t + 1,
                space.format(self.values_of(t)),
                self.effects[t],
                self.rewards[t],
                x,
                y
            )?;
        }
        Ok(())
    }
}

/// Runs `config.trials` trials of a learner of continuous commands on a
/// continuous world ([`run_session_into`](super::run_session_into) into a
/// [`ValueSessionRecord`], with the learner's final policy).
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::{LearnerKind, Scene, SessionConfig};
/// use e3d::session::run_value_session;
/// let scene = Scene::builtin("arm7_continuous").unwrap();
/// let mut world = scene.as_continuous().unwrap().world(1);
/// let space = scene.value_space().unwrap();
/// let mut l = LearnerSetup::new(LearnerKind::E3d).values(&space, scene.num_effects()).unwrap();
/// let cfg = SessionConfig { trials: 20, seed: 1, use_reward: false };
/// let rec = run_value_session(&mut world, &mut l, &cfg).unwrap();
/// assert_eq!(rec.trials(), 20);
/// assert_eq!(rec.commands.len(), 20 * 7);
/// ```
pub fn run_value_session<W, L>(
    world: &mut W,
    learner: &mut L,
    config: &SessionConfig,
) -> Result<ValueSessionRecord, WorldError>
where
    W: ContinuousWorld + ?Sized,
    L: ContinuousLearner + ?Sized,
{
    let n = world.value_space().num_slots();
    let mut rec = ValueSessionRecord::new(n, world.num_effects(), config.trials);
    super::run_session_into(world, learner, config, &mut rec, &Control::default())?;
    rec.set_policy(learner);
    Ok(rec)
}
