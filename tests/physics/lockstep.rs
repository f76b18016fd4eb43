//! Sessions in lockstep give the records of sessions run one by one.

use e3d::learner::LearnerSetup;
use e3d::session::run_group;
use e3d::{
    run_session, Control, LearnerKind, Params, Scene, SessionConfig, SessionRecord, World,
    WorldError,
};

/// `run_group` into a record per session: each session's record, or its error.
fn run_lockstep<W: World + ?Sized, L: e3d::Learner>(
    world: &mut W,
    learners: &mut [L],
    configs: &[SessionConfig],
) -> Vec<Result<SessionRecord, WorldError>> {
    let mut records: Vec<SessionRecord> = configs
        .iter()
        .map(|c| SessionRecord::new(world, c.trials))
        .collect();
    let status = run_group(world, learners, configs, &mut records, &Control::default());
    status
        .into_iter()
        .zip(records)
        .map(|(s, r)| s.map(|()| r))
        .collect()
}

#[test]
fn lockstep_sessions_equal_independent_sessions() {
    for name in ["two_rooms", "puck_rooms"] {
        let scene = Scene::builtin(name).unwrap();
        let space = scene.command_space();
        let kinds = [
            LearnerKind::E3d,
            LearnerKind::Uniform,
            LearnerKind::Egreedy,
            LearnerKind::E3d,
        ];
        let trials = if name == "two_rooms" { 2000 } else { 40 };
        let configs: Vec<SessionConfig> = (0..4)
            .map(|i| SessionConfig {
                // different lengths: the shorter sessions stop on time
                trials: trials - 5 * i,
                seed: 100 + i as u64,
                use_reward: i % 2 == 0,
            })
            .collect();
        let make = |k: LearnerKind| {
            LearnerSetup::new(k)
                .params(Params::TASK2)
                .symbols(&space, scene.num_effects())
                .unwrap()
        };
        let mut learners: Vec<_> = kinds.iter().map(|&k| make(k)).collect();
        let together = run_lockstep(&mut scene.build(), &mut learners, &configs);
        for ((k, cfg), rec) in kinds.iter().zip(&configs).zip(together) {
            let alone = run_session(&mut scene.build(), &mut make(*k), cfg).unwrap();
            assert_eq!(rec.unwrap(), alone, "{name}, {k}");
        }
    }
}

#[test]
fn lockstep_on_a_multi_copy_world_equals_independent_sessions() {
    let scene = Scene::builtin("puck_rooms").unwrap();
    let space = scene.command_space();
    let make = || {
        LearnerSetup::new(LearnerKind::E3d)
            .symbols(&space, 18)
            .unwrap()
    };
    let configs: Vec<SessionConfig> = (0..6)
        .map(|i| SessionConfig {
            trials: 30,
            seed: i,
            use_reward: false,
        })
        .collect();
    let mut learners: Vec<_> = configs.iter().map(|_| make()).collect();
    // 4 copies for 6 sessions: batches of 4 and 2 each trial
    let mut world = scene.as_physics().unwrap().world(4);
    let together = run_lockstep(&mut world, &mut learners, &configs);
    for (cfg, rec) in configs.iter().zip(together) {
        let alone = run_session(&mut scene.build(), &mut make(), cfg).unwrap();
        assert_eq!(rec.unwrap(), alone, "seed {}", cfg.seed);
    }
}
