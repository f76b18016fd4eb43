//! The paper's experiment on `two_rooms` (Daucé 2020, Figures 2 and 3).
//!
//! - Task 1 (exploration, no reward): E3D (alpha 0.3, beta 1, lambda 0.03,
//!   eta 0.01) against the uniform policy; Figure 2 shows where the terminal
//!   states fall over 5000 trials.
//! - Task 2 (sparse reward in the lower-right corner of room B): E3D with
//!   beta 100 against epsilon-greedy (epsilon 0.1); Figure 3 shows the
//!   cumulative reward over 5000 trials and 10 sessions.
//!
//! Session `i` of every learner uses seed `seed + i` (the same seeds for
//! every learner). Sessions run in parallel; the results do not depend on
//! the number of threads.

use crate::effect::{EffectGrid, Target};
use crate::learner::LearnerSetup;
use crate::learner::{LearnerKind, Params};
use crate::scene::Scene;
use crate::scene::WorldSpec;
use crate::session::{
    policy_effect_distribution, run_sessions, Control, Metrics, SessionConfig, SessionRecord,
};
use crate::world::{GridSpec, OutcomeTable};
use LearnerKind::{E3d, Egreedy, Uniform};

/// The settings of a reproduction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperConfig {
    /// Sessions per learner (the paper: 10).
    pub sessions: usize,
    /// Trials per session (the paper: 5000).
    pub trials: usize,
    /// Session `i` uses seed `seed + i`.
    pub seed: u64,
}

impl Default for PaperConfig {
    fn default() -> Self {
        PaperConfig {
            sessions: 10,
            trials: 5000,
            seed: 0,
        }
    }
}

/// One learner in one task.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arm {
    /// A label for tables and figures.
    pub label: &'static str,
    /// The task (1: no reward, 2: sparse reward).
    pub task: u8,
    /// The learner.
    pub learner: LearnerKind,
    /// Its hyper-parameters.
    pub params: Params,
}

/// The four arms of the paper: task 1 uniform and E3D, task 2 E3D and
/// epsilon-greedy.
pub const ARMS: [Arm; 4] = [
    arm("uniform policy", 1, Uniform, Params::TASK1),
    arm("E3D", 1, E3d, Params::TASK1),
    arm("E3D (beta 100)", 2, E3d, Params::TASK2),
    arm("epsilon-greedy (0.1)", 2, Egreedy, Params::TASK2),
];

const fn arm(label: &'static str, task: u8, learner: LearnerKind, params: Params) -> Arm {
    Arm {
        label,
        task,
        learner,
        params,
    }
}

/// The sessions of one arm.
#[derive(Debug, Clone)]
pub struct ArmResult {
    /// The arm.
    pub arm: Arm,
    /// One record per session.
    pub records: Vec<SessionRecord>,
    /// One metrics row per session.
    pub metrics: Vec<Metrics>,
    /// The exact effect distribution of each session's final policy.
    pub final_policy: Vec<Vec<f64>>,
}

/// Everything the reproduction computed.
#[derive(Debug, Clone)]
pub struct PaperResults {
    /// The settings.
    pub config: PaperConfig,
    /// The cells of the grid.
    pub grid: EffectGrid,
    /// The grid world (walls, start).
    pub spec: GridSpec,
    /// The rewarded cells.
    pub reward_cells: Vec<(usize, usize)>,
    /// The four arms, in the order of [`ARMS`].
    pub arms: Vec<ArmResult>,
    /// The exact effect distribution of the uniform policy.
    pub uniform_exact: Vec<f64>,
}

/// Runs the paper's experiment. `progress` is called (from worker threads)
/// with the number of trials just run, every 64 trials of a session and
/// at its end: the counts add up to `4 x sessions x trials`.
pub fn run_paper(config: PaperConfig, progress: &(dyn Fn(u64) + Sync)) -> PaperResults {
    let scene = Scene::builtin("two_rooms").expect("two_rooms is built in");
    let table = OutcomeTable::build(&mut scene.build()).expect("the grid cannot fail");
    let space = scene.command_space();
    let n_eff = scene.num_effects();
    let jobs: Vec<(usize, usize)> = (0..ARMS.len())
        .flat_map(|a| (0..config.sessions).map(move |s| (a, s)))
        .collect();
    let mut learners: Vec<_> = jobs
        .iter()
        .map(|&(a, _)| {
            let arm = &ARMS[a];
            LearnerSetup::new(arm.learner)
                .params(arm.params)
                .symbols(&space, n_eff)
                .expect("the paper's parameters are valid")
        })
        .collect();
    let configs: Vec<SessionConfig> = jobs
        .iter()
        .map(|&(a, s)| SessionConfig {
            trials: config.trials,
            seed: config.seed.wrapping_add(s as u64),
            use_reward: ARMS[a].task == 2,
        })
        .collect();
    let mut records: Vec<SessionRecord> = configs
        .iter()
        .map(|c| SessionRecord::new(&table, c.trials))
        .collect();
    let control = Control::default().with_progress(progress);
    for status in run_sessions(&table, &mut learners, &configs, &mut records, &control) {
        status.expect("the grid cannot fail");
    }
    let done: Vec<(SessionRecord, Vec<f64>)> = records
        .into_iter()
        .zip(&learners)
        .map(|(rec, learner)| {
            let exact = policy_effect_distribution(&table, &**learner)
                .expect("shipped learners have per-slot policies");
            (rec, exact)
        })
        .collect();
    let mut it = done.into_iter();
    let arms = ARMS
        .iter()
        .map(|arm| {
            let (records, final_policy): (Vec<_>, Vec<_>) =
                it.by_ref().take(config.sessions).unzip();
            let metrics = records
                .iter()
                .map(|r| r.metrics(&Target::Uniform))
                .collect();
            ArmResult {
                arm: *arm,
                records,
                metrics,
                final_policy,
            }
        })
        .collect();
    let uniform = LearnerSetup::new(LearnerKind::Uniform)
        .symbols(&space, n_eff)
        .expect("valid");
    PaperResults {
        config,
        grid: scene.effect_grid(),
        spec: match &scene.spec().world {
            WorldSpec::Grid(g) => g.clone(),
            #[allow(unreachable_patterns)]
            _ => unreachable!("two_rooms is a grid"),
        },
        reward_cells: scene.spec().reward.cells.clone(),
        uniform_exact: policy_effect_distribution(&table, &*uniform).expect("uniform"),
        arms,
    }
}
