//! The contextual learners' saved states ([`LearnerState`]): a learner per
//! context, closed-loop E3D and Q-learning.

use super::{ActionValues, ClosedLoopE3d, PerContext, QLearning};
use crate::command::CommandSpace;
use crate::learner::state::{LearnerState, StateField, StateReader, StateShape, StateWriter};
use crate::learner::{Learner, LearnerError};

/// The learners of every context, after the kind of each.
impl<L: LearnerState + Learner> StateField for PerContext<L> {
    fn put(&self, w: &mut StateWriter) {
        w.put(&L::KIND.to_string())
            .put(&self.name)
            .put(&self.learners);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let kind: String = r.get()?;
        r.check(kind == L::KIND, || {
            format!("learners of kind `{kind}`, expected `{}`", L::KIND)
        })?;
        let name: String = r.get()?;
        let learners: Vec<L> = r.get()?;
        r.check(!learners.is_empty(), || "no context".into())?;
        Ok(PerContext { learners, name })
    }
}

impl<L: LearnerState + Learner> LearnerState for PerContext<L> {
    const KIND: &'static str = "per_context";
    fn shape(&self) -> StateShape {
        StateShape {
            contexts: Some(self.learners.len()),
            ..self.learners[0].shape()
        }
    }
}

impl StateField for ActionValues {
    fn put(&self, w: &mut StateWriter) {
        w.put(&self.q).put(&self.commands);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let v = ActionValues {
            q: r.get()?,
            commands: r.get()?,
        };
        r.check(
            v.commands > 0 && !v.q.is_empty() && v.q.len() % v.commands == 0,
            || format!("{} action-values over {} commands", v.q.len(), v.commands),
        )?;
        Ok(v)
    }
}

/// Checks that the action-values `v` are over the commands of `space`.
fn check_values(
    r: &StateReader<'_>,
    v: &ActionValues,
    space: &CommandSpace,
) -> Result<(), LearnerError> {
    r.check(space.num_commands() == Some(v.commands as u64), || {
        format!(
            "action-values over {} commands for a space of {}",
            v.commands,
            space.num_commands_text()
        )
    })
}

impl StateField for ClosedLoopE3d {
    fn put(&self, w: &mut StateWriter) {
        w.put(&self.policy).put(&self.reference).put(&self.space);
        w.put(&self.alpha).put(&self.gamma);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let l = ClosedLoopE3d {
            policy: r.get()?,
            reference: r.get()?,
            space: r.get()?,
            alpha: r.get()?,
            gamma: r.get()?,
        };
        check_values(r, &l.reference, &l.space)?;
        let contexts = l.reference.q.len() / l.reference.commands;
        r.check(l.policy.learners.len() == contexts, || {
            format!(
                "{} context policies for reference values over {contexts} contexts",
                l.policy.learners.len()
            )
        })?;
        Ok(l)
    }
}

impl LearnerState for ClosedLoopE3d {
    const KIND: &'static str = "e3d_closed_loop";
    fn shape(&self) -> StateShape {
        self.policy.shape()
    }
}

impl StateField for QLearning {
    fn put(&self, w: &mut StateWriter) {
        w.put(&self.values).put(&self.space).put(&self.alpha);
        w.put(&self.epsilon).put(&self.gamma);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let l = QLearning {
            values: r.get()?,
            space: r.get()?,
            alpha: r.get()?,
            epsilon: r.get()?,
            gamma: r.get()?,
        };
        check_values(r, &l.values, &l.space)?;
        Ok(l)
    }
}

impl LearnerState for QLearning {
    const KIND: &'static str = "qlearning";
    fn shape(&self) -> StateShape {
        StateShape {
            sizes: self.space.sizes().collect(),
            effects: None,
            contexts: Some(self.values.q.len() / self.values.commands),
        }
    }
}
