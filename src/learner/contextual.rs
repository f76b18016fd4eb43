//! Learners conditioned on a context: the state a command starts from.
//!
//! The paper writes every quantity with a context `s`: the policy
//! `pi(a|s)`, the effect model `p(e|s)`, the target `p*(e|s)`. A
//! [`ContextualLearner`] proposes a command for a given context and learns
//! from its outcome in that context; in a closed loop (an episode of
//! several commands, [`run_episodes`](crate::episode::run_episodes)) it is
//! also told the context the next command starts from.
//!
//! - [`PerContext`]: one learner of any kind per context, each seeing only
//!   the trials of its context: exactly the paper's equations with an `s`
//!   index ([`LearnerSetup::contexts`](super::LearnerSetup::contexts));
//! - [`ClosedLoopE3d`]: contextual E3D whose reward is the Bellman target
//!   of a reference action-value `Q_ref(s, a)` (the paper's conclusion);
//! - [`QLearning`]: epsilon-greedy tabular Q-learning over (context,
//!   command), the closed-loop baseline: over whole commands with values
//!   from 0, or over single moves with optimistic values.
//!
//! Equations: docs/algorithms.md, "Contexts and closed loop".

use super::egreedy::random_argmax;
use super::mutation::random_symbols;
use super::{E3d, Learner, LearnerError, Params};
use crate::command::{Command, CommandSpace};
use crate::effect::Target;
use crate::rng::SessionRng;
use crate::world::Outcome;
use rand::RngExt;
use serde::{Deserialize, Serialize};

mod state;

/// A learner whose policy and models depend on a context, an index in
/// `0..num_contexts()`.
pub trait ContextualLearner {
    /// A short name (`"e3d"`, `"e3d_closed_loop"`, `"qlearning"`).
    fn name(&self) -> &str;

    /// The number of contexts it keeps a policy for.
    fn num_contexts(&self) -> usize;

    /// Draws the next command for `context` into `command` (see
    /// [`Learner::propose`]).
    ///
    /// # Panics
    /// If `context >= num_contexts()`.
    fn propose(&mut self, context: usize, rng: &mut SessionRng, command: &mut Command);

    /// Learns from the outcome of `command` executed in `context`. `next`
    /// is the context the next command of the same episode starts from,
    /// `None` after an episode's last command (or in an open loop).
    ///
    /// # Panics
    /// If `context` or `next` is `>= num_contexts()`.
    fn learn(&mut self, context: usize, command: &Command, outcome: &Outcome, next: Option<usize>);

    /// The probability of each symbol of `slot` under the policy of
    /// `context`, if that policy draws slots independently.
    fn slot_policy(&self, _context: usize, _slot: usize) -> Option<Vec<f64>> {
        None
    }
}

boxed!(ContextualLearner {
    fn name(&self) -> &str;
    fn num_contexts(&self) -> usize;
    fn slot_policy(&self, context: usize, slot: usize) -> Option<Vec<f64>>;
} {
    fn propose(&mut self, context: usize, rng: &mut SessionRng, command: &mut Command);
    fn learn(&mut self, context: usize, command: &Command, outcome: &Outcome, next: Option<usize>);
});

/// The target `p*` of a contextual learner: one for every context, or one
/// per context.
#[derive(Debug, Clone, PartialEq)]
pub enum ContextTargets {
    /// The same `p*(e)` in every context.
    Shared(Target),
    /// `p*(e|s)`: one target per context, in context order.
    PerContext(Vec<Target>),
}

impl ContextTargets {
    /// The target of `context`.
    pub(crate) fn of(&self, context: usize, num_contexts: usize) -> Result<&Target, LearnerError> {
        match self {
            ContextTargets::Shared(t) => Ok(t),
            ContextTargets::PerContext(v) if v.len() == num_contexts => Ok(&v[context]),
            ContextTargets::PerContext(v) => Err(LearnerError::contexts(format!(
                "{} targets for {num_contexts} contexts: give one per context",
                v.len()
            ))),
        }
    }
}

/// One learner per context, each learning only from the trials of its
/// context: `pi(a|s)`, `p(e|s)` and every other table of the learner are
/// indexed by `s`, and each context's learner follows its own (context-free)
/// equations exactly. The learners draw from the session's generator in
/// turn, as the contexts come. `next` is ignored (an open-loop learner per
/// context).
#[derive(Debug, Clone)]
pub struct PerContext<L> {
    learners: Vec<L>,
    name: String,
}

impl<L: Learner> PerContext<L> {
    /// Wraps `learners`, one per context (context `i` is `learners[i]`).
    ///
    /// # Panics
    /// On an empty list.
    pub fn new(learners: Vec<L>) -> Self {
        assert!(!learners.is_empty(), "at least one context");
        let name = learners[0].name().to_string();
        PerContext { learners, name }
    }

    /// The learner of `context`.
    pub fn learner(&self, context: usize) -> &L {
        &self.learners[context]
    }
}

impl<L: Learner> ContextualLearner for PerContext<L> {
    fn name(&self) -> &str {
        &self.name
    }
    fn num_contexts(&self) -> usize {
        self.learners.len()
    }
    fn propose(&mut self, context: usize, rng: &mut SessionRng, command: &mut Command) {
        self.learners[context].propose(rng, command)
    }
    fn learn(
        &mut self,
        context: usize,
        command: &Command,
        outcome: &Outcome,
        _next: Option<usize>,
    ) {
        self.learners[context].learn(command, outcome)
    }
    fn slot_policy(&self, context: usize, slot: usize) -> Option<Vec<f64>> {
        self.learners[context].slot_policy(slot)
    }
}

/// The most entries ([`QLearning`], [`ClosedLoopE3d`]) a table of
/// action-values over (context, command) may hold: 2^22 (32 MiB).
pub const MAX_ACTION_VALUES: u64 = 1 << 22;

/// The most entries a table over (context, effect) may hold (each
/// context's effect model and target: [`PerContext`], [`ClosedLoopE3d`]):
/// 2^22. A grid's cells observed as contexts make contexts x effects grow
/// as the square of the cells: 16384 cells would need 4 GB per table.
pub const MAX_CONTEXT_EFFECTS: u64 = 1 << 22;

/// Refuses tables over more than [`MAX_CONTEXT_EFFECTS`] (context,
/// effect) pairs (a learner per context makes them).
pub fn check_context_effects(num_contexts: usize, num_effects: usize) -> Result<(), LearnerError> {
    match (num_contexts as u64).checked_mul(num_effects as u64) {
        Some(n) if n <= MAX_CONTEXT_EFFECTS => Ok(()),
        _ => Err(LearnerError::contexts(format!(
            "tables over {num_contexts} contexts x {num_effects} effects: at most {MAX_CONTEXT_EFFECTS} entries (observe fewer contexts, or use a coarser grid)"
        ))),
    }
}

/// A dense table of action-values `Q(s, a)` over every (context, whole
/// command), all equal at the start (0, or an optimistic value).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct ActionValues {
    q: Vec<f64>,
    commands: usize,
}

impl ActionValues {
    fn new(space: &CommandSpace, num_contexts: usize, initial: f64) -> Result<Self, LearnerError> {
        let too_many = || {
            LearnerError::contexts(format!(
                "a table of action-values over {num_contexts} contexts x {} commands: at most {MAX_ACTION_VALUES} entries",
                space.num_commands_text()
            ))
        };
        let commands = space.num_commands().ok_or_else(too_many)?;
        if num_contexts == 0 {
            return Err(LearnerError::contexts("at least one context"));
        }
        let entries = commands
            .checked_mul(num_contexts as u64)
            .filter(|&n| n <= MAX_ACTION_VALUES)
            .ok_or_else(too_many)?;
        Ok(ActionValues {
            q: vec![initial; entries as usize],
            commands: commands as usize,
        })
    }

    fn row(&self, context: usize) -> &[f64] {
        &self.q[context * self.commands..(context + 1) * self.commands]
    }

    /// The Bellman target `r + gamma max_a' Q(s', a')` (`r` after an
    /// episode's last command), then `Q(s, a) <- Q(s, a) + alpha (y - Q(s, a))`;
    /// returns `y`.
    fn update(
        &mut self,
        context: usize,
        index: usize,
        reward: f64,
        next: Option<usize>,
        alpha: f64,
        gamma: f64,
    ) -> f64 {
        let best = |s| {
            self.row(s)
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let y = reward + next.map_or(0.0, |s| gamma * best(s));
        let q = &mut self.q[context * self.commands + index];
        *q += alpha * (y - *q);
        y
    }
}

/// Closed-loop E3D: contextual E3D (a policy `Q(s, .)` and an effect model
/// `p(e|s)` per context, each context's [`E3d`]) beside a reference
/// action-value `Q_ref(s, a)` over whole commands, learned by the Bellman
/// recurrence on the extrinsic reward. The policy's update takes the
/// Bellman target `y = r + gamma max_a' Q_ref(s', a')` where E3D takes `r`:
///
/// ```text
/// y <- r + gamma max_a' Q_ref(s', a')          (y = r after the episode's last command)
/// Q_ref(s, a) <- Q_ref(s, a) + alpha (y - Q_ref(s, a))
/// p(.|s) <- (1 - eta) p(.|s) + eta onehot(e)
/// Q(s)[a_i, i] <- (1 - alpha lambda) Q(s)[a_i, i] + alpha lambda y
///                  - (alpha/beta) (log p(e|s) - log p*(e|s))
/// ```
///
/// With one command per episode it is contextual E3D, bit for bit.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ClosedLoopE3d {
    policy: PerContext<E3d>,
    reference: ActionValues,
    space: CommandSpace,
    alpha: f64,
    gamma: f64,
}

impl ClosedLoopE3d {
    /// The default discount `gamma`.
    pub const GAMMA: f64 = 0.9;

    /// A fresh learner: `Q = 0`, `p(.|s)` uniform and `Q_ref = 0` for each
    /// of `num_contexts` contexts; the E3D parameters of `params`, the
    /// discount `gamma` in `[0, 1]`.
    pub fn new(
        space: &CommandSpace,
        num_effects: usize,
        num_contexts: usize,
        params: &Params,
        targets: &ContextTargets,
        gamma: f64,
    ) -> Result<Self, LearnerError> {
        check_gamma(gamma)?;
        check_context_effects(num_contexts, num_effects)?;
        let reference = ActionValues::new(space, num_contexts, 0.0)?;
        let learners = (0..num_contexts)
            .map(|s| E3d::new(space, num_effects, params, targets.of(s, num_contexts)?))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(ClosedLoopE3d {
            policy: PerContext::new(learners),
            reference,
            space: space.clone(),
            alpha: params.alpha,
            gamma,
        })
    }

    /// `Q_ref(s, .)`, in the order of [`CommandSpace::index_of`].
    pub fn reference(&self, context: usize) -> &[f64] {
        self.reference.row(context)
    }

    /// The E3D learner of `context` (its policy `Q(s, .)` and `p(.|s)`).
    pub fn context_learner(&self, context: usize) -> &E3d {
        self.policy.learner(context)
    }
}

/// Checks a discount `gamma` of the closed loop: a number in `[0, 1]`.
///
/// ```
/// use e3d::learner::contextual::check_gamma;
/// assert!(check_gamma(0.9).is_ok());
/// assert_eq!(check_gamma(7.0).unwrap_err().to_string(), "gamma = 7: expected a number in [0, 1]");
/// ```
pub fn check_gamma(gamma: f64) -> Result<(), LearnerError> {
    if (0.0..=1.0).contains(&gamma) {
        Ok(())
    } else {
        Err(super::ParamError {
            name: "gamma",
            value: gamma,
            expected: "a number in [0, 1]",
        }
        .into())
    }
}

impl ContextualLearner for ClosedLoopE3d {
    fn name(&self) -> &str {
        "e3d_closed_loop"
    }
    fn num_contexts(&self) -> usize {
        self.policy.num_contexts()
    }
    fn propose(&mut self, context: usize, rng: &mut SessionRng, command: &mut Command) {
        self.policy.propose(context, rng, command)
    }
    fn learn(&mut self, context: usize, command: &Command, outcome: &Outcome, next: Option<usize>) {
        let index = self.space.index_of(command) as usize;
        let y = self
            .reference
            .update(context, index, outcome.reward, next, self.alpha, self.gamma);
        let driven = Outcome {
            reward: y,
            ..*outcome
        };
        self.policy.learn(context, command, &driven, next)
    }
    fn slot_policy(&self, context: usize, slot: usize) -> Option<Vec<f64>> {
        self.policy.slot_policy(context, slot)
    }
}

/// Epsilon-greedy tabular Q-learning over (context, command): with
/// probability `epsilon` a uniform command (each slot uniform), otherwise
/// a command of largest `Q(s, .)`, ties broken uniformly at random; after
/// each command `Q(s, a) <- Q(s, a) + alpha (r + gamma max_a' Q(s', a') - Q(s, a))`
/// (`r` alone after the episode's last command).
///
/// Every value starts at `initial`: 0 for [`new`](Self::new), the
/// closed-loop baseline over whole commands (1024 a cell on four_rooms:
/// until its first reward every value is 0 and its greedy choice is
/// uniform); an optimistic value for [`optimistic`](Self::optimistic).
/// Over commands of **one move**, an episode of `K n` such commands
/// observing the current cell is ordinary per-move Q-learning (what
/// `e3d closed-loop`'s arm `qlearning_moves` runs): optimistic values make
/// the greedy policy try every move of a cell before it repeats one, a
/// systematic exploration that reaches far cells without epsilon.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct QLearning {
    values: ActionValues,
    space: CommandSpace,
    alpha: f64,
    epsilon: f64,
    gamma: f64,
}

impl QLearning {
    /// The default optimistic initial value of
    /// [`optimistic`](Self::optimistic): 1, the largest reward of the
    /// shipped grid scenes.
    pub const OPTIMISTIC: f64 = 1.0;

    /// A fresh learner (`Q = 0`) for `num_contexts` contexts, with
    /// `params.alpha`, `params.epsilon` and the discount `gamma` in `[0, 1]`.
    pub fn new(
        space: &CommandSpace,
        num_contexts: usize,
        params: &Params,
        gamma: f64,
    ) -> Result<Self, LearnerError> {
        Self::optimistic(space, num_contexts, params, gamma, 0.0)
    }

    /// A fresh learner whose values all start at `initial` (a finite
    /// number; [`OPTIMISTIC`](Self::OPTIMISTIC) by default), otherwise as
    /// [`new`](Self::new).
    ///
    /// ```
    /// use e3d::command::CommandSpace;
    /// use e3d::learner::QLearning;
    /// use e3d::Params;
    /// let space = CommandSpace::repeat(1, &['E', 'S', 'W', 'N']).unwrap();
    /// let q = QLearning::optimistic(&space, 9, &Params::TASK2, 0.9, 1.0).unwrap();
    /// assert_eq!(q.values(8), [1.0; 4]);
    /// let e = QLearning::optimistic(&space, 9, &Params::TASK2, 0.9, f64::NAN).unwrap_err();
    /// assert_eq!(e.to_string(), "initial = NaN: expected a finite number");
    /// ```
    pub fn optimistic(
        space: &CommandSpace,
        num_contexts: usize,
        params: &Params,
        gamma: f64,
        initial: f64,
    ) -> Result<Self, LearnerError> {
        params.validate()?;
        check_gamma(gamma)?;
        check_initial(initial)?;
        Ok(QLearning {
            values: ActionValues::new(space, num_contexts, initial)?,
            space: space.clone(),
            alpha: params.alpha,
            epsilon: params.epsilon,
            gamma,
        })
    }

    /// `Q(s, .)`, in the order of [`CommandSpace::index_of`].
    pub fn values(&self, context: usize) -> &[f64] {
        self.values.row(context)
    }
}

/// Checks the initial action-value of Q-learning: a finite number.
///
/// ```
/// use e3d::learner::contextual::check_initial;
/// assert!(check_initial(1.0).is_ok());
/// assert_eq!(check_initial(f64::INFINITY).unwrap_err().to_string(), "initial = inf: expected a finite number");
/// ```
pub fn check_initial(initial: f64) -> Result<(), LearnerError> {
    if initial.is_finite() {
        Ok(())
    } else {
        Err(super::ParamError {
            name: "initial",
            value: initial,
            expected: "a finite number",
        }
        .into())
    }
}
impl ContextualLearner for QLearning {
    fn name(&self) -> &str {
        "qlearning"
    }
    fn num_contexts(&self) -> usize {
        self.values.q.len() / self.values.commands
    }
    /// One `f64` (explore or not), then either one integer per slot (a
    /// uniform command) or one integer (which of the best commands).
    fn propose(&mut self, context: usize, rng: &mut SessionRng, command: &mut Command) {
        let explore: f64 = rng.random();
        if explore < self.epsilon {
            random_symbols(self.space.sizes(), rng, &mut command.symbols);
            return;
        }
        let index = random_argmax(self.values.row(context), rng);
        self.space.write_command_at(index as u64, command);
    }
    fn learn(&mut self, context: usize, command: &Command, outcome: &Outcome, next: Option<usize>) {
        let index = self.space.index_of(command) as usize;
        self.values
            .update(context, index, outcome.reward, next, self.alpha, self.gamma);
    }
}
