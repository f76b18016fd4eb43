//! How to make a learner: one [`LearnerSetup`] for every kind of command.

use super::contextual::{check_context_effects, check_gamma};
use super::{
    Archive, ArchiveReached, ArchiveReachedValues, ArchiveValues, ClosedLoopE3d, ContextTargets,
    ContextualLearner, ContinuousLearner, CountBonus, E3d, Effort, EpsilonGreedy, GaussianE3d,
    GoalBabbling, GoalBabblingValues, Learner, LearnerError, LearnerKind, MapElites,
    MapElitesValues, Params, PerContext, QLearning, RelaxedE3d, StateMarginalMatching,
    UniformPolicy, UniformValues,
};
use crate::command::{CommandSpace, ValueSpace};

/// Why per-move Q-learning has no open-loop learner.
const MOVES_RUN_EPISODES: &str = "learner qlearning_moves chooses each move from the cell it is in: it runs episodes (`e3d run --commands K`, a sweep of episodes, `e3d closed-loop`), not single open-loop commands";
use crate::effect::Target;

/// How to make a learner: its kind, its hyper-parameters, its target
/// effect distribution `p*` (per start context, for episodes) and, for
/// episodes, whether it closes the loop. One setup makes the learner of
/// each kind of command: [`symbols`](Self::symbols) for a command of
/// symbols, [`values`](Self::values) for continuous commands,
/// [`contexts`](Self::contexts) for episodes (start contexts, or the
/// current cell of a closed loop). The hyper-parameters are checked
/// ([`Params::validate`]) whenever a learner is made.
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::{LearnerKind, Params, Scene};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let (space, effects) = (scene.command_space(), scene.num_effects());
/// let e3d = LearnerSetup::new(LearnerKind::E3d).params(Params::TASK2);
/// assert_eq!(e3d.symbols(&space, effects).unwrap().name(), "e3d");
/// // one policy per start context, or closed-loop E3D over the current cell
/// assert_eq!(e3d.contexts(&space, effects, 3).unwrap().num_contexts(), 3);
/// let closed = e3d.clone().closed_loop(true).gamma(0.9);
/// assert_eq!(closed.contexts(&space, effects, effects).unwrap().name(), "e3d_closed_loop");
/// // a parameter out of range is refused, naming it
/// let bad = e3d.params(Params { beta: -1.0, ..Params::TASK2 });
/// assert!(bad.symbols(&space, effects).err().unwrap().to_string().contains("beta"));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct LearnerSetup {
    /// The learner.
    pub kind: LearnerKind,
    /// Its hyper-parameters (those it does not read are ignored:
    /// [`LearnerKind::params`]).
    pub params: Params,
    /// The target `p*` (E3D and SMM only): shared by every context, or
    /// one per context for [`contexts`](Self::contexts).
    pub targets: ContextTargets,
    /// For [`contexts`](Self::contexts): a closed loop (closed-loop E3D
    /// for `e3d`, Q-learning for `egreedy`), or one policy per context.
    pub closed_loop: bool,
    /// The discount of a closed loop, in `[0, 1]` (checked open loop too:
    /// a discount out of range is a mistake either way).
    pub gamma: f64,
    /// The effort of the scene's commands, by which MAP-Elites keeps its
    /// elites ([`Effort::of_scene`]; none: by nothing, each cell keeps its
    /// first command).
    pub effort: Option<Effort>,
}

impl LearnerSetup {
    /// A learner of kind `kind` with the paper's task 1 parameters
    /// ([`Params::TASK1`]), the uniform target, open loop, `gamma` =
    /// [`ClosedLoopE3d::GAMMA`].
    pub fn new(kind: LearnerKind) -> LearnerSetup {
        LearnerSetup {
            kind,
            params: Params::TASK1,
            targets: ContextTargets::Shared(Target::Uniform),
            closed_loop: false,
            gamma: ClosedLoopE3d::GAMMA,
            effort: None,
        }
    }

    /// The same setup with the hyper-parameters `params`.
    pub fn params(self, params: Params) -> LearnerSetup {
        LearnerSetup { params, ..self }
    }

    /// The same setup with the target `p*` `target`, shared by every
    /// context.
    pub fn target(self, target: Target) -> LearnerSetup {
        self.targets(ContextTargets::Shared(target))
    }

    /// The same setup with the targets `targets` (one per context, or
    /// shared).
    pub fn targets(self, targets: ContextTargets) -> LearnerSetup {
        LearnerSetup { targets, ..self }
    }

    /// The same setup, closing the loop of episodes or not (see
    /// [`closed_loop`](Self::closed_loop)).
    pub fn closed_loop(self, closed_loop: bool) -> LearnerSetup {
        LearnerSetup {
            closed_loop,
            ..self
        }
    }

    /// The same setup with MAP-Elites' elites kept by the effort of
    /// `scene`'s commands ([`Effort::of_scene`]).
    pub fn effort_of(self, scene: &crate::Scene) -> LearnerSetup {
        LearnerSetup {
            effort: Some(Effort::of_scene(scene)),
            ..self
        }
    }

    /// The same setup with the discount `gamma` of a closed loop.
    pub fn gamma(self, gamma: f64) -> LearnerSetup {
        LearnerSetup { gamma, ..self }
    }

    /// A fresh learner of commands of symbols of `space`, with
    /// `num_effects` effects.
    pub fn symbols(
        &self,
        space: &CommandSpace,
        num_effects: usize,
    ) -> Result<Box<dyn Learner + Send>, LearnerError> {
        self.symbols_for(space, num_effects, self.targets.of(0, 1)?)
    }

    fn symbols_for(
        &self,
        space: &CommandSpace,
        num_effects: usize,
        target: &Target,
    ) -> Result<Box<dyn Learner + Send>, LearnerError> {
        let (params, n) = (&self.params, num_effects);
        params.validate()?;
        Ok(match self.kind {
            LearnerKind::E3d => Box::new(E3d::new(space, n, params, target)?),
            LearnerKind::Uniform => Box::new(UniformPolicy::new(space)),
            LearnerKind::Egreedy => Box::new(EpsilonGreedy::new(space, params)),
            LearnerKind::E3dRelax => Box::new(RelaxedE3d::new(space, n, params, target)?),
            LearnerKind::Count => Box::new(CountBonus::new(space, n, params)),
            LearnerKind::Smm => Box::new(StateMarginalMatching::new(space, n, params, target)?),
            LearnerKind::GoalBabbling => Box::new(GoalBabbling::new(space, n, params)),
            LearnerKind::Archive => Box::new(Archive::new(space, n, params)),
            LearnerKind::ArchiveReached => Box::new(ArchiveReached::new(space, n, params)),
            LearnerKind::MapElites => {
                Box::new(MapElites::new(space, n, params).with_effort(self.effort.clone()))
            }
            LearnerKind::QlearningMoves => return Err(LearnerError::contexts(MOVES_RUN_EPISODES)),
        })
    }

    /// A fresh learner of continuous commands of `space`, with
    /// `num_effects` effects: [`GaussianE3d`] for `e3d`, [`UniformValues`]
    /// for `uniform`, [`GoalBabblingValues`], [`ArchiveValues`],
    /// [`ArchiveReachedValues`] and [`MapElitesValues`]; the
    /// other kinds ([`LearnerKind::CONTINUOUS`]) are
    /// [`LearnerError::NotContinuous`].
    ///
    /// ```
    /// use e3d::learner::{LearnerError, LearnerSetup};
    /// use e3d::command::ValueSpace;
    /// use e3d::LearnerKind;
    /// let space = ValueSpace::new(vec![(-1.0, 1.0); 3]).unwrap();
    /// let l = LearnerSetup::new(LearnerKind::E3d).values(&space, 9).unwrap();
    /// assert_eq!(l.name(), "e3d");
    /// let e = LearnerSetup::new(LearnerKind::Egreedy).values(&space, 9);
    /// assert!(matches!(e.err().unwrap(), LearnerError::NotContinuous { learner: "egreedy" }));
    /// ```
    pub fn values(
        &self,
        space: &ValueSpace,
        num_effects: usize,
    ) -> Result<Box<dyn ContinuousLearner + Send>, LearnerError> {
        let (params, n) = (&self.params, num_effects);
        params.validate()?;
        let target = self.targets.of(0, 1)?;
        Ok(match self.kind {
            LearnerKind::E3d => Box::new(GaussianE3d::new(space, n, params, target)?),
            LearnerKind::Uniform => Box::new(UniformValues::new(space)),
            LearnerKind::GoalBabbling => Box::new(GoalBabblingValues::new(space, n, params)),
            LearnerKind::Archive => Box::new(ArchiveValues::new(space, n, params)),
            LearnerKind::ArchiveReached => Box::new(ArchiveReachedValues::new(space, n, params)),
            LearnerKind::MapElites => {
                Box::new(MapElitesValues::new(space, n, params).with_effort(self.effort.clone()))
            }
            other => {
                return Err(LearnerError::NotContinuous {
                    learner: other.as_str(),
                })
            }
        })
    }

    /// A fresh learner of episodes, over `num_contexts` contexts: closing
    /// the loop ([`closed_loop`](Self::closed_loop)), closed-loop E3D for
    /// [`LearnerKind::E3d`] ([`ClosedLoopE3d`]) and Q-learning for
    /// [`LearnerKind::Egreedy`] ([`QLearning`]), other kinds refused;
    /// without it, one fresh learner of this kind per context
    /// ([`PerContext`]), each with its context's target.
    /// [`LearnerKind::QlearningMoves`] is [`QLearning::optimistic`] (values
    /// from `params.initial`, `params.epsilon`, the discount `gamma`) either
    /// way: given commands of one move ([`Scene::with_moves`](crate::Scene::with_moves)),
    /// it is per-move Q-learning. What `e3d run --commands K
    /// [--closed-loop]`, sweeps of episodes and Python's `run_episodes` run.
    ///
    /// ```
    /// use e3d::learner::LearnerSetup;
    /// use e3d::command::CommandSpace;
    /// use e3d::LearnerKind;
    /// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
    /// let q = LearnerSetup::new(LearnerKind::Egreedy).closed_loop(true);
    /// assert_eq!(q.contexts(&space, 4, 4).unwrap().name(), "qlearning");
    /// let count = LearnerSetup::new(LearnerKind::Count).closed_loop(true);
    /// assert!(count.contexts(&space, 4, 4).is_err());
    /// // per-move Q-learning learns per context only
    /// let moves = LearnerSetup::new(LearnerKind::QlearningMoves);
    /// assert_eq!(moves.contexts(&space, 4, 4).unwrap().name(), "qlearning");
    /// assert!(moves.symbols(&space, 4).is_err());
    /// // gamma is checked open loop too
    /// let far = LearnerSetup::new(LearnerKind::E3d).gamma(7.0);
    /// assert!(far.contexts(&space, 4, 4).is_err());
    /// ```
    pub fn contexts(
        &self,
        space: &CommandSpace,
        num_effects: usize,
        num_contexts: usize,
    ) -> Result<Box<dyn ContextualLearner + Send>, LearnerError> {
        let (params, gamma) = (&self.params, self.gamma);
        check_gamma(gamma)?;
        match (self.closed_loop, self.kind) {
            (_, LearnerKind::QlearningMoves) => {
                QLearning::optimistic(space, num_contexts, params, gamma, params.initial)
                    .map(|l| Box::new(l) as _)
            }
            (false, _) => {
                if num_contexts == 0 {
                    return Err(LearnerError::contexts("at least one context"));
                }
                check_context_effects(num_contexts, num_effects)?;
                let learners = (0..num_contexts)
                    .map(|s| {
                        let target = self.targets.of(s, num_contexts)?;
                        self.symbols_for(space, num_effects, target)
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Box::new(PerContext::new(learners)))
            }
            (true, LearnerKind::E3d) => {
                let (n, targets) = (num_effects, &self.targets);
                ClosedLoopE3d::new(space, n, num_contexts, params, targets, gamma)
                    .map(|l| Box::new(l) as _)
            }
            (true, LearnerKind::Egreedy) => {
                QLearning::new(space, num_contexts, params, gamma).map(|l| Box::new(l) as _)
            }
            (true, other) => Err(LearnerError::contexts(format!(
                "the closed loop takes learner e3d (closed-loop E3D) or egreedy (Q-learning), not {other}"
            ))),
        }
    }
}
