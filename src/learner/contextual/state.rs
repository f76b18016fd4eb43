//! The contextual learners' saved states ([`LearnerState`]): a learner per
//! context, closed-loop E3D and Q-learning.

use super::{ActionValues, ClosedLoopE3d, PerContext, QLearning};
use crate::command::CommandSpace;
use crate::learner::state::tables::{check_len, no_table, StateTable};
use crate::learner::state::{check_space, decode, ensure, intact, per_context_kind};
use crate::learner::state::{LearnerState, StateShape};
use crate::learner::{Learner, LearnerError};
use serde::{de::Error, Deserialize, Deserializer, Serialize, Serializer};

/// The kind of the learners, then their name and the learners.
impl<L: LearnerState> Serialize for PerContext<L> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        (L::KIND, &self.name, &self.learners).serialize(s)
    }
}

impl<'de, L: LearnerState> Deserialize<'de> for PerContext<L> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (kind, name, learners) = <(String, String, Vec<L>)>::deserialize(d)?;
        if kind != L::KIND {
            return Err(D::Error::custom(format!("learners of kind `{kind}`")));
        }
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
    fn validate(&self) -> Result<(), String> {
        ensure(!self.learners.is_empty(), || "no context".into())?;
        self.learners.iter().try_for_each(L::validate)
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
    /// Also refuses an intact state of learners of another kind, naming
    /// both kinds.
    fn from_bytes(bytes: &[u8]) -> Result<Self, LearnerError> {
        match per_context_kind(bytes) {
            Ok(kind) if kind != L::KIND && intact(bytes) => Err(LearnerError::State(format!(
                "state of a `per_context` learner: learners of kind `{kind}`, expected `{}`",
                L::KIND
            ))),
            _ => decode(bytes),
        }
    }
}

impl ActionValues {
    /// Checks action-values read from a state, over the commands of `space`.
    fn validate(&self, space: &CommandSpace) -> Result<(), String> {
        check_space(space)?;
        let (q, commands) = (self.q.len(), self.commands);
        ensure(commands > 0 && q > 0 && q % commands == 0, || {
            format!("{q} action-values over {commands} commands")
        })?;
        ensure(space.num_commands() == Some(commands as u64), || {
            format!(
                "action-values over {commands} commands for a space of {}",
                space.num_commands_text()
            )
        })
    }

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
    fn validate(&self) -> Result<(), String> {
        self.policy.validate()?;
        self.reference.validate(&self.space)?;
        let contexts = self.reference.q.len() / self.reference.commands;
        ensure(self.policy.learners.len() == contexts, || {
            format!(
                "{} context policies for reference values over {contexts} contexts",
                self.policy.learners.len()
            )
        })
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

impl LearnerState for QLearning {
    const KIND: &'static str = "qlearning";
    fn shape(&self) -> StateShape {
        StateShape {
            sizes: self.space.sizes().collect(),
            effects: None,
            contexts: Some(self.values.q.len() / self.values.commands),
        }
    }
    fn validate(&self) -> Result<(), String> {
        self.values.validate(&self.space)
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
