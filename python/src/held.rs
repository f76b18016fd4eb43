//! `Held`: a built-in learner of either kind of command as its concrete
//! type, what an `e3d.Learner` holds.

use crate::scene::PyScene;
use e3d::learner::state::tables::StateTable;
use e3d::learner::state::{per_context_kind, state_kind, StateShape};
use e3d::learner::{
    Archive, ArchiveValues, ClosedLoopE3d, ContextualLearner, CountBonus, GoalBabbling,
    GoalBabblingValues, PerContext, QLearning, RelaxedE3d, StateMarginalMatching,
};
use e3d::learner::{
    E3d, EpsilonGreedy, GaussianE3d, LearnerError, LearnerState, UniformPolicy, UniformValues,
};
use e3d::{ContinuousLearner, Learner, LearnerKind, Params};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A built-in learner of either kind of command, as its concrete type.
#[derive(Clone)]
pub(crate) enum Held {
    E3d(E3d),
    Relaxed(RelaxedE3d),
    Count(CountBonus),
    Smm(StateMarginalMatching),
    Egreedy(EpsilonGreedy),
    Uniform(UniformPolicy),
    Gaussian(GaussianE3d),
    UniformValues(UniformValues),
    GoalBabbling(GoalBabbling),
    GoalBabblingValues(GoalBabblingValues),
    Archive(Archive),
    ArchiveValues(ArchiveValues),
    /// Contextual: a learner per context, closed-loop E3D, Q-learning.
    PerE3d(PerContext<E3d>),
    PerRelaxed(PerContext<RelaxedE3d>),
    PerCount(PerContext<CountBonus>),
    PerSmm(PerContext<StateMarginalMatching>),
    PerEgreedy(PerContext<EpsilonGreedy>),
    PerUniform(PerContext<UniformPolicy>),
    ClosedLoop(ClosedLoopE3d),
    QLearning(QLearning),
}

/// Applies `$f` to the concrete learner of `$held`.
macro_rules! with_held {
    ($held:expr, $l:ident => $f:expr) => {
        match $held {
            Held::E3d($l) => $f,
            Held::Relaxed($l) => $f,
            Held::Count($l) => $f,
            Held::Smm($l) => $f,
            Held::Egreedy($l) => $f,
            Held::Uniform($l) => $f,
            Held::Gaussian($l) => $f,
            Held::UniformValues($l) => $f,
            Held::GoalBabbling($l) => $f,
            Held::GoalBabblingValues($l) => $f,
            Held::Archive($l) => $f,
            Held::ArchiveValues($l) => $f,
            Held::PerE3d($l) => $f,
            Held::PerRelaxed($l) => $f,
            Held::PerCount($l) => $f,
            Held::PerSmm($l) => $f,
            Held::PerEgreedy($l) => $f,
            Held::PerUniform($l) => $f,
            Held::ClosedLoop($l) => $f,
            Held::QLearning($l) => $f,
        }
    };
}

pub(crate) fn bad(e: LearnerError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

impl Held {
    /// A fresh learner of `kind` for `scene`.
    pub(crate) fn new(
        scene: &PyScene,
        kind: LearnerKind,
        params: &Params,
        target: &e3d::Target,
    ) -> PyResult<Held> {
        let n = scene.inner.num_effects();
        if let Some(values) = &scene.values {
            return match kind {
                LearnerKind::E3d => GaussianE3d::new(values, n, params, target).map(Held::Gaussian),
                LearnerKind::Uniform => Ok(Held::UniformValues(UniformValues::new(values))),
                LearnerKind::GoalBabbling => Ok(Held::GoalBabblingValues(GoalBabblingValues::new(values, n, params))),
                LearnerKind::Archive => Ok(Held::ArchiveValues(ArchiveValues::new(values, n, params))),
                other => Err(LearnerError::State(format!(
                    "learner `{other}`: a saved state of continuous commands is kept for \"e3d\", \"uniform\", \"goal_babbling\" and \"archive\""
                ))),
            }
            .map_err(bad);
        }
        let s = &scene.space;
        Ok(match kind {
            LearnerKind::E3d => Held::E3d(E3d::new(s, n, params, target).map_err(bad)?),
            LearnerKind::E3dRelax => {
                Held::Relaxed(RelaxedE3d::new(s, n, params, target).map_err(bad)?)
            }
            LearnerKind::Count => Held::Count(CountBonus::new(s, n, params)),
            LearnerKind::Smm => {
                Held::Smm(StateMarginalMatching::new(s, n, params, target).map_err(bad)?)
            }
            LearnerKind::Egreedy => Held::Egreedy(EpsilonGreedy::new(s, params)),
            LearnerKind::Uniform => Held::Uniform(UniformPolicy::new(s)),
            LearnerKind::GoalBabbling => Held::GoalBabbling(GoalBabbling::new(s, n, params)),
            LearnerKind::Archive => Held::Archive(Archive::new(s, n, params)),
        })
    }

    /// The learner from the bytes of [`LearnerState::to_bytes`], whatever
    /// its kind.
    pub(crate) fn from_bytes(data: &[u8]) -> Result<Held, LearnerError> {
        let kind = state_kind(data)?;
        Ok(match kind.as_str() {
            "e3d" => Held::E3d(E3d::from_bytes(data)?),
            "e3d_relax" => Held::Relaxed(RelaxedE3d::from_bytes(data)?),
            "count" => Held::Count(CountBonus::from_bytes(data)?),
            "smm" => Held::Smm(StateMarginalMatching::from_bytes(data)?),
            "egreedy" => Held::Egreedy(EpsilonGreedy::from_bytes(data)?),
            "uniform" => Held::Uniform(UniformPolicy::from_bytes(data)?),
            "gaussian_e3d" => Held::Gaussian(GaussianE3d::from_bytes(data)?),
            "uniform_values" => Held::UniformValues(UniformValues::from_bytes(data)?),
            "goal_babbling" => Held::GoalBabbling(GoalBabbling::from_bytes(data)?),
            "goal_babbling_values" => {
                Held::GoalBabblingValues(GoalBabblingValues::from_bytes(data)?)
            }
            "archive" => Held::Archive(Archive::from_bytes(data)?),
            "archive_values" => Held::ArchiveValues(ArchiveValues::from_bytes(data)?),
            "e3d_closed_loop" => Held::ClosedLoop(ClosedLoopE3d::from_bytes(data)?),
            "qlearning" => Held::QLearning(QLearning::from_bytes(data)?),
            "per_context" => match per_context_kind(data)?.as_str() {
                "e3d" => Held::PerE3d(PerContext::from_bytes(data)?),
                "e3d_relax" => Held::PerRelaxed(PerContext::from_bytes(data)?),
                "count" => Held::PerCount(PerContext::from_bytes(data)?),
                "smm" => Held::PerSmm(PerContext::from_bytes(data)?),
                "egreedy" => Held::PerEgreedy(PerContext::from_bytes(data)?),
                "uniform" => Held::PerUniform(PerContext::from_bytes(data)?),
                inner => {
                    return Err(LearnerError::State(format!(
                    "the state of `{inner}` learners per context, which e3d.Learner does not hold"
                )))
                }
            },
            _ => {
                return Err(LearnerError::State(format!(
                    "the state of a `{kind}` learner, which e3d.Learner does not hold"
                )))
            }
        })
    }

    pub(crate) fn to_bytes(&self) -> Vec<u8> {
        with_held!(self, l => l.to_bytes())
    }

    /// What the learner was made for (slots, effects, contexts).
    pub(crate) fn shape(&self) -> StateShape {
        with_held!(self, l => l.shape())
    }

    /// The learner's tables by name ([`LearnerState::tables`]).
    pub(crate) fn tables(&self) -> Vec<StateTable> {
        with_held!(self, l => l.tables())
    }

    /// The E3D learner, if it is one.
    pub(crate) fn e3d(&mut self) -> Option<&mut E3d> {
        match self {
            Held::E3d(l) => Some(l),
            _ => None,
        }
    }

    /// The learner as a learner of symbols, if it is one.
    pub(crate) fn symbols(&mut self) -> Option<&mut (dyn Learner + Send)> {
        Some(match self {
            Held::E3d(l) => l,
            Held::Relaxed(l) => l,
            Held::Count(l) => l,
            Held::Smm(l) => l,
            Held::Egreedy(l) => l,
            Held::Uniform(l) => l,
            Held::GoalBabbling(l) => l,
            Held::Archive(l) => l,
            _ => return None,
        })
    }

    /// The learner as a contextual learner, if it is one.
    pub(crate) fn contextual(&mut self) -> Option<&mut (dyn ContextualLearner + Send)> {
        Some(match self {
            Held::PerE3d(l) => l,
            Held::PerRelaxed(l) => l,
            Held::PerCount(l) => l,
            Held::PerSmm(l) => l,
            Held::PerEgreedy(l) => l,
            Held::PerUniform(l) => l,
            Held::ClosedLoop(l) => l,
            Held::QLearning(l) => l,
            _ => return None,
        })
    }

    /// A learner per context from one learner per context (all of one
    /// kind, as [`Held::new`] makes them).
    pub(crate) fn per_context(learners: Vec<Held>) -> Held {
        macro_rules! per {
            ($($one:ident => $per:ident),*) => {
                match &learners[0] {
                    $(Held::$one(_) => Held::$per(PerContext::new(
                        learners
                            .into_iter()
                            .map(|h| match h {
                                Held::$one(l) => l,
                                _ => unreachable!("one kind"),
                            })
                            .collect(),
                    )),)*
                    _ => unreachable!("a learner of symbols per context"),
                }
            };
        }
        per!(E3d => PerE3d, Relaxed => PerRelaxed, Count => PerCount, Smm => PerSmm,
            Egreedy => PerEgreedy, Uniform => PerUniform)
    }

    /// The learner as a learner of values, if it is one.
    pub(crate) fn values(&mut self) -> Option<&mut (dyn ContinuousLearner + Send)> {
        match self {
            Held::Gaussian(l) => Some(l),
            Held::UniformValues(l) => Some(l),
            Held::GoalBabblingValues(l) => Some(l),
            Held::ArchiveValues(l) => Some(l),
            _ => None,
        }
    }

    /// The kind a session runs (`LearnerKind`'s name).
    pub(crate) fn kind(&self) -> LearnerKind {
        match self {
            Held::E3d(_) | Held::Gaussian(_) => LearnerKind::E3d,
            Held::Relaxed(_) => LearnerKind::E3dRelax,
            Held::Count(_) => LearnerKind::Count,
            Held::Smm(_) => LearnerKind::Smm,
            Held::Egreedy(_) => LearnerKind::Egreedy,
            Held::Uniform(_) | Held::UniformValues(_) => LearnerKind::Uniform,
            Held::PerE3d(_) | Held::ClosedLoop(_) => LearnerKind::E3d,
            Held::PerRelaxed(_) => LearnerKind::E3dRelax,
            Held::PerCount(_) => LearnerKind::Count,
            Held::PerSmm(_) => LearnerKind::Smm,
            Held::PerEgreedy(_) | Held::QLearning(_) => LearnerKind::Egreedy,
            Held::PerUniform(_) => LearnerKind::Uniform,
            Held::GoalBabbling(_) | Held::GoalBabblingValues(_) => LearnerKind::GoalBabbling,
            Held::Archive(_) | Held::ArchiveValues(_) => LearnerKind::Archive,
        }
    }
}

pub(crate) use with_held;
