//! Seeded noise (a scene's `noise` section): the draws are keyed by the
//! session's seed and the trial, so records are the same bytes on 1 and 2
//! threads and in lockstep; a noisy world refuses tables and memos; the
//! loader checks the bounds, with the file, line and column.

use e3d::learner::LearnerSetup;
use e3d::session::run_group;
use e3d::world::{ExecOptions, Executor, Strategy, Workload};
use e3d::{
    run_session, Control, LearnerKind, OutcomeTable, Scene, Session, SessionConfig, SessionRecord,
    World,
};

fn noisy() -> Scene {
    Scene::load("tests/scenes/puck_noisy.ron").unwrap()
}

/// `sessions` E3D sessions of 60 trials on `threads` threads.
fn records_on(scene: &Scene, threads: usize, sessions: usize) -> Vec<SessionRecord> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        Session::new(scene, LearnerKind::E3d)
            .trials(60)
            .seed(7)
            .run_many(sessions)
            .unwrap()
    })
}

#[test]
fn a_noisy_scene_gives_the_same_records_on_1_and_2_threads() {
    let scene = noisy();
    let one = records_on(&scene, 1, 4);
    let two = records_on(&scene, 2, 4);
    assert_eq!(one, two);
    // and the same again: a fixed seed, fixed bytes
    assert_eq!(records_on(&scene, 2, 4), one);
    // the noise is there: the noise-free scene's records differ
    let plain = records_on(&Scene::builtin("puck_rooms").unwrap(), 1, 4);
    assert_ne!(plain, one);
}

#[test]
fn lockstep_under_noise_equals_sessions_alone() {
    let scene = noisy();
    let space = scene.command_space();
    let make = || {
        LearnerSetup::new(LearnerKind::Uniform)
            .symbols(&space, scene.num_effects())
            .unwrap()
    };
    let configs: Vec<SessionConfig> = (0..3)
        .map(|i| SessionConfig {
            trials: 30 - 5 * i,
            seed: 40 + i as u64,
            use_reward: true,
        })
        .collect();
    let mut learners: Vec<_> = configs.iter().map(|_| make()).collect();
    let mut world = scene.as_physics().unwrap().world(3);
    let mut records: Vec<SessionRecord> = configs
        .iter()
        .map(|c| SessionRecord::new(&world, c.trials))
        .collect();
    let status = run_group(
        &mut world,
        &mut learners,
        &configs,
        &mut records,
        &Control::default(),
    );
    assert!(status.iter().all(Result::is_ok));
    for (c, r) in configs.iter().zip(&records) {
        let alone = run_session(&mut scene.build(), &mut make(), c).unwrap();
        assert_eq!(*r, alone, "seed {}", c.seed);
    }
}

#[test]
fn the_same_key_draws_the_same_outcome_and_another_key_another() {
    let scene = noisy();
    let mut world = scene.build();
    let c = world.command_space().parse("SEEEEES").unwrap();
    let at = |world: &mut Box<dyn e3d::world::Episodic + Send>, key: u64| {
        world.set_draw_keys(&[key]);
        world.execute(&c).unwrap().point
    };
    let a = at(&mut world, 5);
    assert_eq!(at(&mut world, 9), at(&mut world, 9));
    assert_eq!(at(&mut world, 5), a);
    assert_ne!(at(&mut world, 6), a);
    assert!(!world.is_deterministic());
    // a batch of copies gives each command its key's outcome
    let mut copies = scene.as_physics().unwrap().world(4);
    copies.set_draw_keys(&[9, 5, 6, 5]);
    let mut out = Vec::new();
    copies.execute_batch(&[c.clone(), c.clone(), c.clone(), c.clone()], &mut out);
    let points: Vec<_> = out.into_iter().map(|o| o.unwrap().point).collect();
    assert_eq!(points[1], a);
    assert_eq!(points[3], a);
    assert_eq!(points[0], at(&mut world, 9));
}

#[test]
fn a_noise_section_that_draws_nothing_changes_no_bit() {
    let plain = Scene::builtin("puck_rooms").unwrap();
    let text = std::fs::read_to_string("scenes/puck_rooms.ron")
        .unwrap()
        .replace(
            "effect: (body: \"puck\"",
            "noise: (actions: Gaussian(sd: 0.0)),\n        effect: (body: \"puck\"",
        );
    let quiet = Scene::parse(&text, "quiet.ron").unwrap();
    let (mut a, mut b) = (plain.build(), quiet.build());
    assert!(b.is_deterministic());
    let space = plain.command_space();
    for k in 0..20u64 {
        let c = space.command_at(k * 7919 % 16384);
        assert_eq!(a.execute(&c).unwrap(), b.execute(&c).unwrap());
    }
}

#[test]
fn a_noisy_scene_refuses_tables_and_memos_naming_its_noise() {
    let scene = noisy();
    let work = Workload {
        trials: 100_000,
        sessions: 1,
        threads: 1,
    };
    // left to choose, the executor runs live
    let exec = Executor::new(&scene, &work, &ExecOptions::default()).unwrap();
    assert_eq!(exec.plan().strategy, Strategy::Live);
    for force in [Strategy::Table, Strategy::Memo] {
        let options = ExecOptions {
            force: Some(force),
            ..ExecOptions::default()
        };
        let e = Executor::new(&scene, &work, &options)
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("scene `puck_noisy` has a `noise` section"),
            "{e}"
        );
        assert!(e.contains(&format!("--outcomes {force}")), "{e}");
    }
    let dir = std::env::temp_dir();
    let options = ExecOptions {
        cache: Some(dir),
        ..ExecOptions::default()
    };
    let e = Executor::new(&scene, &work, &options)
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("a table cache") && e.contains("`noise` section"),
        "{e}"
    );
    let e = OutcomeTable::build_scene(&scene).unwrap_err().to_string();
    assert!(e.contains("`noise` section"), "{e}");
    let e = OutcomeTable::build(&mut scene.build())
        .unwrap_err()
        .to_string();
    assert!(e.contains("not deterministic"), "{e}");
}

/// The noisy scene with `from` replaced by `to`: the error's text.
fn error(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string("tests/scenes/puck_noisy.ron").unwrap();
    assert_eq!(text.matches(from).count(), 1, "`{from}`");
    match Scene::parse(&text.replacen(from, to, 1), "n.ron") {
        Ok(_) => panic!("accepted: {to}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_loader_checks_the_noise_bounds_at_their_place() {
    // line 28 is `actions: ...`, line 29 the starts (see the fixture)
    let e = error("Gaussian(sd: 0.05)", "Gaussian(sd: -0.05)");
    assert!(e.starts_with("n.ron:28:13:"), "{e}");
    assert!(
        e.contains("sd in [0, 0.3333333333333333) (draws are cut at 3 sd), found -0.05"),
        "{e}"
    );
    // a factor 1 + x that could reach 0
    let e = error("Gaussian(sd: 0.05)", "Uniform(half_width: 1.0)");
    assert!(
        e.starts_with("n.ron:28:13:") && e.contains("half_width in [0, 1)"),
        "{e}"
    );
    let e = error(
        "position: Gaussian(sd: 0.02)",
        "position: Gaussian(sd: NaN)",
    );
    assert!(e.starts_with("n.ron:29:37:"), "{e}");
    assert!(
        e.contains("noise on the start of body `puck`: sd in [0, 33.33"),
        "{e}"
    );
    let e = error(
        "(body: \"puck\", position: G",
        "(body: \"wall_south\", position: G",
    );
    assert!(e.starts_with("n.ron:29:23:"), "{e}");
    assert!(e.contains("a free dynamic body of the scene"), "{e}");
    let e = error(
        "position: Gaussian(sd: 0.02)",
        "angle: Uniform(half_width: 4.0)",
    );
    assert!(
        e.starts_with("n.ron:29:37:") && e.contains("half_width in [0, 3.14"),
        "{e}"
    );
}

/// puck_rooms with `noise` as its noise section.
fn puck_with(noise: &str) -> Result<Scene, e3d::scene::SceneError> {
    let text = std::fs::read_to_string("scenes/puck_rooms.ron")
        .unwrap()
        .replace(
            "effect: (body: \"puck\"",
            &format!("noise: {noise},\n        effect: (body: \"puck\""),
        );
    Scene::parse(&text, "p.ron")
}

#[test]
fn body_numbers_are_drawn_per_execution_and_keyed() {
    let noise = r#"(body_numbers: [(body: "puck", mass: Gaussian(sd: 0.1), linear_damping: Uniform(half_width: 0.2))])"#;
    let scene = puck_with(noise).unwrap();
    let c = scene.command_space().parse("SEEEEES").unwrap();
    let mut world = scene.build();
    assert!(!world.is_deterministic());
    let mut at = |key: u64| {
        world.set_draw_keys(&[key]);
        world.execute(&c).unwrap().point
    };
    let a = at(1);
    assert_eq!(at(1), a);
    assert_ne!(at(2), a);
    // the puck's own numbers come back at the next execution
    let plain = Scene::builtin("puck_rooms").unwrap();
    let mut copies = scene.as_physics().unwrap().world(3);
    copies.set_draw_keys(&[2, 1, 3]);
    let mut out = Vec::new();
    copies.execute_batch(&[c.clone(), c.clone(), c.clone()], &mut out);
    assert_eq!(out[1].as_ref().unwrap().point, a);
    assert_ne!(plain.build().execute(&c).unwrap().point, a);
}

#[test]
fn body_numbers_keep_masses_positive_and_name_their_place() {
    let e = puck_with(r#"(body_numbers: [(body: "puck", mass: Uniform(half_width: 1.0))])"#)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "field `mass`: expected noise on the numbers of body `puck`: half_width in [0, 1)"
        ),
        "{e}"
    );
    // the line of the noise section, at the field
    assert!(e.starts_with("p.ron:44:47:"), "{e}");
    let e = puck_with(r#"(body_numbers: [(body: "puck", friction: Gaussian(sd: -0.1))])"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("sd in [0, 0.3333333333333333] (draws are cut at 3 sd), found -0.1: the `friction` is multiplied by 1 + x"), "{e}");
    let e = puck_with(r#"(body_numbers: [(body: "inner_low", mass: Gaussian(sd: 0.1))])"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("a free dynamic body of the scene"), "{e}");
}

/// arm7 with `noise` as its noise section.
fn arm_with(noise: &str) -> Result<Scene, e3d::scene::SceneError> {
    let text = std::fs::read_to_string("scenes/arm7.ron").unwrap().replace(
        "effect: (body: \"link7\"",
        &format!("noise: {noise},\n        effect: (body: \"link7\""),
    );
    Scene::parse(&text, "a.ron")
}

#[test]
fn joint_start_noise_turns_the_joint_and_its_tree_follows() {
    let scene = arm_with(r#"(starts: [(joint: "j2", angle: Gaussian(sd: 0.05))])"#).unwrap();
    let c = scene.command_space().parse("0000000").unwrap();
    let mut world = scene.build();
    let mut at = |key: u64| {
        world.set_draw_keys(&[key]);
        world.execute(&c).unwrap().point
    };
    let a = at(1);
    assert_eq!(at(1), a);
    assert_ne!(at(2), a);
    // at rest, the tip is where the start put it: off the plain arm's tip
    let plain = Scene::builtin("arm7")
        .unwrap()
        .build()
        .execute(&c)
        .unwrap()
        .point;
    assert_ne!(plain, a);
    let moved = ((a[0] - plain[0]).powi(2) + (a[1] - plain[1]).powi(2)).sqrt();
    assert!(moved < 0.5, "the tip moved {moved} m");
}

#[test]
fn joint_start_noise_stays_within_the_joint_limits() {
    let e = arm_with(r#"(starts: [(joint: "j2", angle: Uniform(half_width: 3.0))])"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("noise on the start of joint `j2`: half_width in [0, 2.5] rad, found 3 (its limits [-2.5, 2.5] rad hold every draw from 0)"), "{e}");
    let e = arm_with(r#"(starts: [(joint: "j9", angle: Uniform(half_width: 0.1))])"#)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "field `joint`: expected noise on the start of joint `j9`: a joint of the scene"
        ),
        "{e}"
    );
    let e = arm_with(r#"(starts: [(joint: "j2", position: Uniform(half_width: 0.1))])"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("field `position`"), "{e}");
}

/// The reproducibility of a uniform policy's repertoire on `scene`, of 16
/// commands run 10 times each, on a world of `copies` copies.
fn uniform_reproducibility(scene: &Scene, copies: usize) -> e3d::session::Reproducibility {
    use e3d::session::{reproducibility, RepeatOptions};
    let learner = LearnerSetup::new(LearnerKind::Uniform)
        .symbols(&scene.command_space(), scene.num_effects())
        .unwrap();
    let mut world = scene.as_physics().unwrap().world(copies);
    let options = RepeatOptions {
        commands: 16,
        runs: 10,
    };
    reproducibility(&mut world, &learner, options, 3)
        .unwrap()
        .unwrap()
}

#[test]
fn reproducibility_is_1_without_noise_and_falls_with_it() {
    let plain = uniform_reproducibility(&Scene::builtin("puck_rooms").unwrap(), 1);
    assert_eq!(plain.share, 1.0);
    assert_eq!(plain.each.len(), 16);
    // a deterministic world runs each command once
    assert!(plain.each.iter().all(|r| (r.kept, r.runs) == (1, 1)));
    // the same commands (drawn from the same seed) under mild and heavy noise
    let mild = uniform_reproducibility(&noisy(), 1);
    let heavy = uniform_reproducibility(
        &puck_with("(actions: Uniform(half_width: 0.9))").unwrap(),
        1,
    );
    assert!(mild.each.iter().all(|r| r.runs == 10));
    // a uniform policy's commands mostly end against a wall: 5% noise
    // moves few of them (docs/analysis.md: 0.985 over 100 sessions)
    assert!(mild.share >= 0.75, "{}", mild.share);
    assert!(heavy.share < 0.3, "{}", heavy.share);
    // the share counts the commands whose modal effect holds in >= 9 of 10
    let holding = heavy.each.iter().filter(|r| r.kept >= 9).count();
    assert_eq!(heavy.share, holding as f64 / 16.0);
    assert!(heavy.each.iter().any(|r| r.kept < 9 && r.runs == 10));
}

#[test]
fn reproducibility_is_the_same_in_lockstep_and_alone() {
    let scene = noisy();
    let alone = uniform_reproducibility(&scene, 1);
    let lockstep = uniform_reproducibility(&scene, 32);
    assert_eq!(alone, lockstep);
}

#[test]
fn reevaluate_keys_run_r_of_command_i_by_run_key() {
    use e3d::session::{reevaluate, run_key};
    let scene = noisy();
    let space = scene.command_space();
    let cmds: Vec<e3d::Command> = ["SEEEEES", "SSEENNE"]
        .iter()
        .map(|t| space.parse(t).unwrap())
        .collect();
    let mut world = scene.build();
    let r = reevaluate(&mut *world, &cmds, 6, 9).unwrap();
    for (i, c) in cmds.iter().enumerate() {
        // each run by hand, keyed run_key(seed, r, i)
        let effects: Vec<usize> = (0..6)
            .map(|run| {
                world.set_draw_keys(&[run_key(9, run, i as u64)]);
                world.execute(c).unwrap().effect
            })
            .collect();
        let mode = (0..18)
            .max_by_key(|e| {
                (
                    effects.iter().filter(|x| *x == e).count(),
                    std::cmp::Reverse(*e),
                )
            })
            .unwrap();
        let kept = effects.iter().filter(|&&e| e == mode).count();
        assert_eq!(
            (r[i].effect, r[i].kept, r[i].runs),
            (mode, kept, 6),
            "{effects:?}"
        );
    }
}
