//! `Held`: a built-in learner of either kind of command as its concrete
//! type, what an `e3d.Learner` holds.

use crate::scene::PyScene;
use e3d::learner::state::tables::StateTable;
use e3d::learner::state::{per_context_kind, state_kind, StateShape};
use e3d::learner::{
    Archive, ArchiveReached, ArchiveReachedValues, ArchiveValues, ClosedLoopE3d, ContextualLearner,
    CountBonus, GoalBabbling, GoalBabblingValues, MapElites, MapElitesValues, PerContext,
    QLearning, RelaxedE3d, StateMarginalMatching,
};
use e3d::learner::{
    E3d, Effort, EpsilonGreedy, GaussianE3d, LearnerError, LearnerState, UniformPolicy,
    UniformValues,
};
use e3d::{ContinuousLearner, Learner, LearnerKind, Params};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A learner's state behind a reference: what `Learner` asks of every
/// kind ([`LearnerState`] made object-safe).
pub(crate) trait State {
    /// [`LearnerState::KIND`].
    fn kind(&self) -> &'static str;
    fn to_bytes(&self) -> Vec<u8>;
    fn shape(&self) -> StateShape;
    fn tables(&self) -> Vec<StateTable>;
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError>;
}

impl<L: LearnerState> State for L {
    fn kind(&self) -> &'static str {
        L::KIND
    }
    fn to_bytes(&self) -> Vec<u8> {
        LearnerState::to_bytes(self)
    }
    fn shape(&self) -> StateShape {
        LearnerState::shape(self)
    }
    fn tables(&self) -> Vec<StateTable> {
        LearnerState::tables(self)
    }
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        LearnerState::set_table(self, name, values)
    }
}

/// `Held` and what reads it, from one list: each variant, its type and
/// the [`LearnerKind`] a session runs it as, by what it learns (symbols,
/// values, one learner of symbols per context, one over contexts).
macro_rules! held {
    (
        symbols: $($s:ident($st:ty) $sk:ident),*;
        values: $($v:ident($vt:ty) $vk:ident),*;
        per_context: $($p:ident($one:ident: $pt:ty) $pk:ident),*;
        over_contexts: $($c:ident($ct:ty) $ck:ident),*;
    ) => {
        /// A built-in learner of either kind of command, as its concrete type.
        #[derive(Clone)]
        pub(crate) enum Held {
            $($s($st),)*
            $($v($vt),)*
            $($p(PerContext<$pt>),)*
            $($c($ct),)*
        }

        impl Held {
            /// The learner's state.
            pub(crate) fn state(&self) -> &dyn State {
                match self {
                    $(Held::$s(l) => l,)*
                    $(Held::$v(l) => l,)*
                    $(Held::$p(l) => l,)*
                    $(Held::$c(l) => l,)*
                }
            }

            /// The learner's state, to write.
            pub(crate) fn state_mut(&mut self) -> &mut dyn State {
                match self {
                    $(Held::$s(l) => l,)*
                    $(Held::$v(l) => l,)*
                    $(Held::$p(l) => l,)*
                    $(Held::$c(l) => l,)*
                }
            }

            /// The learner as a learner of symbols, if it is one.
            pub(crate) fn symbols(&mut self) -> Option<&mut (dyn Learner + Send)> {
                match self {
                    $(Held::$s(l) => Some(l),)*
                    _ => None,
                }
            }

            /// The learner as a learner of values, if it is one.
            pub(crate) fn values(&mut self) -> Option<&mut (dyn ContinuousLearner + Send)> {
                match self {
                    $(Held::$v(l) => Some(l),)*
                    _ => None,
                }
            }

            /// The learner as a contextual learner, if it is one.
            pub(crate) fn contextual(&mut self) -> Option<&mut (dyn ContextualLearner + Send)> {
                match self {
                    $(Held::$p(l) => Some(l),)*
                    $(Held::$c(l) => Some(l),)*
                    _ => None,
                }
            }

            /// The kind a session runs (`LearnerKind`'s name).
            pub(crate) fn kind(&self) -> LearnerKind {
                match self {
                    $(Held::$s(_) => LearnerKind::$sk,)*
                    $(Held::$v(_) => LearnerKind::$vk,)*
                    $(Held::$p(_) => LearnerKind::$pk,)*
                    $(Held::$c(_) => LearnerKind::$ck,)*
                }
            }

            /// The learner from the bytes of [`LearnerState::to_bytes`],
            /// whatever its kind.
            pub(crate) fn from_bytes(data: &[u8]) -> Result<Held, LearnerError> {
                let kind = state_kind(data)?;
                $(if kind == <$st>::KIND { return Ok(Held::$s(<$st>::from_bytes(data)?)); })*
                $(if kind == <$vt>::KIND { return Ok(Held::$v(<$vt>::from_bytes(data)?)); })*
                $(if kind == <$ct>::KIND { return Ok(Held::$c(<$ct>::from_bytes(data)?)); })*
                if kind != "per_context" {
                    return Err(LearnerError::State(format!(
                        "the state of a `{kind}` learner, which e3d.Learner does not hold"
                    )));
                }
                let inner = per_context_kind(data)?;
                $(if inner == <$pt>::KIND { return Ok(Held::$p(PerContext::from_bytes(data)?)); })*
                Err(LearnerError::State(format!(
                    "the state of `{inner}` learners per context, which e3d.Learner does not hold"
                )))
            }

            /// A learner per context from one learner per context (all of
            /// one kind, as [`Held::new`] makes them).
            pub(crate) fn per_context(learners: Vec<Held>) -> Held {
                match &learners[0] {
                    $(Held::$one(_) => Held::$p(PerContext::new(
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
            }
        }
    };
}

held! {
    symbols: E3d(E3d) E3d, Relaxed(RelaxedE3d) E3dRelax, Count(CountBonus) Count,
        Smm(StateMarginalMatching) Smm, Egreedy(EpsilonGreedy) Egreedy,
        Uniform(UniformPolicy) Uniform, GoalBabbling(GoalBabbling) GoalBabbling,
        Archive(Archive) Archive, ArchiveReached(ArchiveReached) ArchiveReached,
        MapElites(MapElites) MapElites;
    values: Gaussian(GaussianE3d) E3d, UniformValues(UniformValues) Uniform,
        GoalBabblingValues(GoalBabblingValues) GoalBabbling,
        ArchiveValues(ArchiveValues) Archive,
        ArchiveReachedValues(ArchiveReachedValues) ArchiveReached,
        MapElitesValues(MapElitesValues) MapElites;
    per_context: PerE3d(E3d: E3d) E3d, PerRelaxed(Relaxed: RelaxedE3d) E3dRelax,
        PerCount(Count: CountBonus) Count, PerSmm(Smm: StateMarginalMatching) Smm,
        PerEgreedy(Egreedy: EpsilonGreedy) Egreedy, PerUniform(Uniform: UniformPolicy) Uniform;
    over_contexts: ClosedLoop(ClosedLoopE3d) E3d, QLearning(QLearning) Egreedy;
}

/// A learner's error as a `ValueError`.
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
                LearnerKind::ArchiveReached => Ok(Held::ArchiveReachedValues(ArchiveReachedValues::new(values, n, params))),
                LearnerKind::MapElites => Ok(Held::MapElitesValues(MapElitesValues::new(values, n, params).with_effort(Some(Effort::of_scene(&scene.inner))))),
                other => Err(LearnerError::State(format!(
                    "learner `{other}`: a saved state of continuous commands is kept for \"e3d\", \"uniform\", \"goal_babbling\", \"archive\", \"archive_reached\" and \"map_elites\""
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
            LearnerKind::ArchiveReached => Held::ArchiveReached(ArchiveReached::new(s, n, params)),
            LearnerKind::MapElites => Held::MapElites(
                MapElites::new(s, n, params).with_effort(Some(Effort::of_scene(&scene.inner))),
            ),
            LearnerKind::QlearningMoves => {
                // its learner is over contexts (Learner.contextual), made below
                return Err(PyValueError::new_err(
                    "learner `qlearning_moves` chooses each move from the cell it is in: it runs episodes (run_episodes, Learner.contextual), not single commands",
                ));
            }
        })
    }

    /// The E3D learner, if it is one.
    pub(crate) fn e3d(&mut self) -> Option<&mut E3d> {
        match self {
            Held::E3d(l) => Some(l),
            _ => None,
        }
    }
}
