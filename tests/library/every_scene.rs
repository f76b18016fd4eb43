//! Every shipped scene runs with every learner, reproducibly.

use e3d::learner::LearnerSetup;
use e3d::scene::BUILTIN;
use e3d::{run_session, LearnerKind, Params, Scene, SessionConfig};

#[test]
fn every_scene_with_every_learner_gives_effects_in_range_and_repeats() {
    for (name, _) in BUILTIN {
        let scene = Scene::builtin(name).unwrap();
        if scene.spec().is_continuous() {
            // its own learners, on live physics (tests/physics/continuous.rs)
            continue;
        }
        let space = scene.command_space();
        // per-move Q-learning runs episodes, not single commands
        // (tests/library/contexts.rs)
        let open_loop = LearnerKind::ALL
            .into_iter()
            .filter(|&k| k != LearnerKind::QlearningMoves);
        for kind in open_loop {
            let run = || {
                let mut world = scene.build();
                let mut l = LearnerSetup::new(kind)
                    .params(Params::TASK2)
                    .symbols(&space, scene.num_effects())
                    .unwrap();
                let cfg = SessionConfig {
                    trials: 25,
                    seed: 5,
                    use_reward: true,
                };
                run_session(&mut world, &mut l, &cfg)
                    .unwrap_or_else(|e| panic!("{name} with {kind}: {e}"))
            };
            let rec = run();
            assert_eq!(rec.effects.len(), 25);
            assert!(rec.effects.iter().all(|&e| e < scene.num_effects()));
            assert_eq!(rec, run(), "{name} with {kind} does not repeat");
        }
    }
    assert!(BUILTIN.len() >= 5);
}
