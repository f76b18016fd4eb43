//! The contextual learners' saved states ([`LearnerState`]): a learner per
//! context, closed-loop E3D and Q-learning.

use super::{ActionValues, ClosedLoopE3d, PerContext, QLearning};
use crate::command::CommandSpace;
use crate::learner::state::tables::{check_len, no_table, StateTable};
use crate::learner::state::{LearnerState, StateField, StateReader, StateShape, StateWriter};
use crate::learner::{Learner, LearnerError};

/// The learners of every context, after the kind of each.
impl<L: LearnerState + Learner + Clone> StateField for PerContext<L> {
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

impl<L: LearnerState + Learner + Clone> LearnerState for PerContext<L> {
    const KIND: &'static str = "per_context";
    fn shape(&self) -> StateShape {
        StateShape {
            contexts: Some(self.learners.len()),
            ..self.learners[0].shape()
        }
    }
    /// The tables of each context's learner, the context as first axis.
    fn tables(&self) -> Vec<StateTable> {
        StateTable::stack(self.learners.iter().map(|l| l.tables()).collect())
    }
    /// Writes each context's part of the table (all or none).
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        let tables = self.tables();
        let Some(t) = tables.iter().find(|t| t.name == name && t.writable) else {
            return Err(no_table(L::KIND, name, &tables));
        };
        check_len(name, values, t.values.len())?;
        let per = t.values.len() / self.learners.len();
        let mut next = self.learners.clone();
        for (c, l) in next.iter_mut().enumerate() {
            l.set_table(name, &values[c * per..(c + 1) * per])
                .map_err(|e| LearnerError::State(format!("context {c}: {e}")))?;
        }
        self.learners = next;
        Ok(())
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

impl ActionValues {
    /// The table `name` of shape `(contexts, commands)`.
    fn table(&self, name: &'static str) -> StateTable {
        StateTable {
            name,
            shape: vec![self.q.len() / self.commands, self.commands],
            values: self.q.clone(),
            writable: true,
        }
    }

    /// Replaces the values by `values` (as many, finite).
    fn set(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        check_len(name, values, self.q.len())?;
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(LearnerError::State(format!(
                "table `{name}`: {v} is not a finite number"
            )));
        }
        self.q.copy_from_slice(values);
        Ok(())
    }
}

impl LearnerState for ClosedLoopE3d {
    const KIND: &'static str = "e3d_closed_loop";
    fn shape(&self) -> StateShape {
        self.policy.shape()
    }
    /// The tables of each context's E3D (`q`, `policy`, `p`, `target`,
    /// the context first) and the `reference` action-values `Q_ref(s, a)`
    /// (`(contexts, commands)`), all writable.
    fn tables(&self) -> Vec<StateTable> {
        let mut t = self.policy.tables();
        t.push(self.reference.table("reference"));
        t
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        match name {
            "reference" => self.reference.set(name, values),
            _ => self.policy.set_table(name, values),
        }
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
    /// The action-values `q`, `(contexts, commands)`, writable.
    fn tables(&self) -> Vec<StateTable> {
        vec![self.values.table("q")]
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        match name {
            "q" => self.values.set(name, values),
            _ => Err(no_table(Self::KIND, name, &self.tables())),
        }
    }
}
