//! Seeded noise (a scene's `noise` section): the draws are keyed by the
//! session's seed and the trial, so records are the same bytes on 1 and 2
//! threads and in lockstep; a noisy world refuses tables and memos; the
//! loader checks the bounds, with the file, line and column.

use e3d::learner::LearnerSetup;
use e3d::scene::physics::DrawKey;
use e3d::session::run_group;
use e3d::world::{ExecOptions, Executor, Strategy, Workload};
use e3d::{
    run_session, Control, LearnerKind, OutcomeTable, Scene, Session, SessionConfig, SessionRecord,
    World,
};

/// The keys of execution `key` of the session keyed 0.
fn k(key: u64) -> DrawKey {
    DrawKey {
        session: 0,
        execution: key,
    }
}

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

/// Runs `configs` in lockstep on one world of 3 copies of `scene` and
/// asserts that each session's record equals the session run alone.
fn assert_lockstep_equals_alone(scene: &Scene, configs: &[SessionConfig]) {
    let space = scene.command_space();
    let make = || {
        LearnerSetup::new(LearnerKind::Uniform)
            .symbols(&space, scene.num_effects())
            .unwrap()
    };
    let mut learners: Vec<_> = configs.iter().map(|_| make()).collect();
    let mut world = scene.as_physics().unwrap().world(3);
    let mut records: Vec<SessionRecord> = configs
        .iter()
        .map(|c| SessionRecord::new(&world, c.trials))
        .collect();
    let status = run_group(
        &mut world,
        &mut learners,
        configs,
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
fn lockstep_under_noise_equals_sessions_alone() {
    let configs: Vec<SessionConfig> = (0..3)
        .map(|i| SessionConfig {
            trials: 30 - 5 * i,
            seed: 40 + i as u64,
            use_reward: true,
        })
        .collect();
    assert_lockstep_equals_alone(&noisy(), &configs);
}

#[test]
fn the_same_key_draws_the_same_outcome_and_another_key_another() {
    let scene = noisy();
    let mut world = scene.build();
    let c = world.command_space().parse("SEEEEES").unwrap();
    let at = |world: &mut Box<dyn e3d::world::Episodic + Send>, key: u64| {
        world.set_draw_keys(&[k(key)]);
        world.execute(&c).unwrap().point
    };
    let a = at(&mut world, 5);
    assert_eq!(at(&mut world, 9), at(&mut world, 9));
    assert_eq!(at(&mut world, 5), a);
    assert_ne!(at(&mut world, 6), a);
    assert!(!world.is_deterministic());
    // a batch of copies gives each command its key's outcome
    let mut copies = scene.as_physics().unwrap().world(4);
    copies.set_draw_keys(&[k(9), k(5), k(6), k(5)]);
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
        world.set_draw_keys(&[k(key)]);
        world.execute(&c).unwrap().point
    };
    let a = at(1);
    assert_eq!(at(1), a);
    assert_ne!(at(2), a);
    // the puck's own numbers come back at the next execution
    let plain = Scene::builtin("puck_rooms").unwrap();
    let mut copies = scene.as_physics().unwrap().world(3);
    copies.set_draw_keys(&[k(2), k(1), k(3)]);
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
        world.set_draw_keys(&[k(key)]);
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

/// puck_rooms whose puck's damping is drawn once per session (and its
/// mass per execution when `mass`).
fn per_session(mass: bool) -> Scene {
    let mass = match mass {
        true => r#"(body: "puck", mass: Gaussian(sd: 0.1)), "#,
        false => "",
    };
    let noise = format!(
        r#"(body_numbers: [{mass}(body: "puck", per: Session, linear_damping: Uniform(half_width: 0.5))])"#
    );
    puck_with(&noise).unwrap()
}

#[test]
fn a_per_session_draw_is_the_same_for_every_execution_of_a_session() {
    use e3d::scene::physics::session_key;
    let scene = per_session(false);
    let c = scene.command_space().parse("SEEEEES").unwrap();
    let mut world = scene.build();
    assert!(!world.is_deterministic());
    let mut at = |session: u64, execution: u64| {
        world.set_draw_keys(&[DrawKey { session, execution }]);
        world.execute(&c).unwrap().point
    };
    // one session: every execution draws the same damping
    let a = at(session_key(1), 0);
    for e in [1, 2, 77, u64::MAX] {
        assert_eq!(at(session_key(1), e), a);
    }
    // other sessions draw others
    let b = at(session_key(2), 0);
    assert_ne!(b, a);
    assert_ne!(at(session_key(3), 0), a);
    assert_ne!(at(session_key(3), 0), b);
    // the scene's own damping is neither
    let plain = Scene::builtin("puck_rooms").unwrap().build().execute(&c);
    assert_ne!(plain.unwrap().point, a);
    // in a batch, each copy its own session's draw
    let mut copies = scene.as_physics().unwrap().world(3);
    let keys: Vec<DrawKey> = [2, 1, 1]
        .iter()
        .map(|&s| DrawKey {
            session: session_key(s),
            execution: s * 5,
        })
        .collect();
    copies.set_draw_keys(&keys);
    let mut out = Vec::new();
    copies.execute_batch(&[c.clone(), c.clone(), c.clone()], &mut out);
    let points: Vec<_> = out.into_iter().map(|o| o.unwrap().point).collect();
    assert_eq!(points, [b, a, a]);
}

#[test]
fn sessions_with_per_session_draws_give_the_same_bytes_on_1_and_2_threads() {
    let scene = per_session(true);
    let one = records_on(&scene, 1, 4);
    assert_eq!(records_on(&scene, 2, 4), one);
    // lockstep: 3 sessions on one world of 3 copies, as each alone
    let configs: Vec<SessionConfig> = (0..3)
        .map(|i| SessionConfig {
            trials: 40,
            seed: 10 + i,
            use_reward: true,
        })
        .collect();
    assert_lockstep_equals_alone(&scene, &configs);
    // the per-session draw is there: the mass alone gives other records
    let mass = puck_with(r#"(body_numbers: [(body: "puck", mass: Gaussian(sd: 0.1))])"#).unwrap();
    assert_ne!(records_on(&mass, 1, 4), one);
}

#[test]
fn per_session_draws_follow_the_session_not_the_trial() {
    // a session whose only noise is drawn per session: each command's
    // outcome is the one it has under that session's key, whatever the trial
    use e3d::scene::physics::session_key;
    let scene = per_session(false);
    let config = SessionConfig {
        trials: 30,
        seed: 5,
        use_reward: true,
    };
    let mut learner = LearnerSetup::new(LearnerKind::Uniform)
        .symbols(&scene.command_space(), scene.num_effects())
        .unwrap();
    let record = run_session(&mut scene.build(), &mut learner, &config).unwrap();
    let mut world = scene.build();
    let space = scene.command_space();
    let (mut same_seed, mut other_seed) = (0, 0);
    for (t, symbols) in record.commands.chunks(space.num_slots()).enumerate() {
        let c = e3d::Command::new(symbols.to_vec());
        let mut effect = |seed: u64| {
            world.set_draw_keys(&[DrawKey {
                session: session_key(seed),
                execution: 12345,
            }]);
            world.execute(&c).unwrap().point
        };
        same_seed += usize::from(effect(5) == record.points[t]);
        other_seed += usize::from(effect(6) == record.points[t]);
    }
    assert_eq!(same_seed, 30);
    assert!(other_seed < 10, "{other_seed}");
}

#[test]
fn the_loader_checks_per_session_entries_at_their_place() {
    let e = puck_with(r#"(body_numbers: [(body: "puck", mass: Gaussian(sd: 0.1)), (body: "puck", per: Session, mass: Gaussian(sd: 0.1))])"#)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("p.ron:44:"), "{e}");
    assert!(
        e.contains("field `mass`: expected noise on the numbers of body `puck`: the `mass` of a body drawn in one entry only (per execution or per session, not both)"),
        "{e}"
    );
    let e = puck_with(r#"(body_numbers: [(body: "puck", per: Session, mass: Gaussian(sd: 0.1)), (body: "puck", per: Session, friction: Gaussian(sd: 0.1))])"#)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("each body listed once per `per` (Execution, Session)"),
        "{e}"
    );
    let e = puck_with(r#"(body_numbers: [(body: "puck", per: Trial, mass: Gaussian(sd: 0.1))])"#)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("p.ron:44:"), "{e}");
    assert!(e.contains("Execution") && e.contains("Session"), "{e}");
    // `per: Execution` is the default: the same bits
    let given =
        puck_with(r#"(body_numbers: [(body: "puck", per: Execution, mass: Gaussian(sd: 0.1))])"#)
            .unwrap();
    let left = puck_with(r#"(body_numbers: [(body: "puck", mass: Gaussian(sd: 0.1))])"#).unwrap();
    let c = given.command_space().parse("SEEEEES").unwrap();
    let (mut a, mut b) = (given.build(), left.build());
    for e in 0..5 {
        a.set_draw_keys(&[k(e)]);
        b.set_draw_keys(&[k(e)]);
        assert_eq!(a.execute(&c).unwrap(), b.execute(&c).unwrap());
    }
}

/// puck_contexts (two start contexts) with `noise` as its noise section.
fn contexts_with(noise: &str) -> Scene {
    let text = std::fs::read_to_string("scenes/puck_contexts.ron")
        .unwrap()
        .replace(
            "effect: (body: \"puck\"",
            &format!("noise: {noise},\n        effect: (body: \"puck\""),
        );
    Scene::parse(&text, "c.ron").unwrap()
}

const EPISODE_NOISE: &str = r#"(actions: Gaussian(sd: 0.05), starts: [(body: "puck", position: Gaussian(sd: 0.02))], body_numbers: [(body: "puck", per: Session, linear_damping: Uniform(half_width: 0.3))])"#;

/// Three sessions of 30 episodes of 2 commands on `threads` threads.
fn episodes_on(scene: &Scene, threads: usize) -> Vec<e3d::episode::EpisodeRecord> {
    use e3d::episode::{EpisodeConfig, EpisodeRecord, Observe};
    use e3d::session::run_episode_sessions;
    let configs: Vec<EpisodeConfig> = (0..3)
        .map(|seed| EpisodeConfig {
            episodes: 30,
            commands: 2,
            seed,
            use_reward: true,
            observe: Observe::State,
        })
        .collect();
    let n = scene.num_effects();
    let make = |_| -> Result<_, e3d::WorldError> {
        let learner = LearnerSetup::new(LearnerKind::E3d)
            .closed_loop(true)
            .contexts(&scene.command_space(), n, n)
            .unwrap();
        Ok((scene.build(), learner))
    };
    let mut records = vec![EpisodeRecord::default(); 3];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let status =
        pool.install(|| run_episode_sessions(&configs, make, &mut records, &Control::default()));
    assert!(status.iter().all(Result::is_ok));
    // each as alone
    let (mut world, mut learner) = make(0).unwrap();
    let alone =
        e3d::episode::run_episodes(&mut *world, &mut *learner, &configs[2], &Control::default());
    assert_eq!(alone.unwrap(), records[2]);
    records
}

#[test]
fn noisy_episodes_give_the_same_records_on_1_and_2_threads() {
    let scene = contexts_with(EPISODE_NOISE);
    let one = episodes_on(&scene, 1);
    assert_eq!(episodes_on(&scene, 2), one);
    // the noise is there
    let plain = episodes_on(&Scene::load("scenes/puck_contexts.ron").unwrap(), 1);
    assert_ne!(plain, one);
}

#[test]
fn start_offsets_apply_to_an_episodes_start_only() {
    use e3d::world::Episodic;
    use rand::SeedableRng;
    let scene = puck_with(
        r#"(starts: [(body: "puck", position: Gaussian(sd: 0.05), angle: Gaussian(sd: 0.1))])"#,
    )
    .unwrap();
    let mut world = scene.physics_world().unwrap();
    let c = scene.command_space().parse("SEEEEES").unwrap();
    let mut rng = e3d::SessionRng::seed_from_u64(0);
    let start = world.draw_start(0, &mut rng).unwrap();
    let from = |world: &mut e3d::world::PhysicsWorld, state, key| {
        world.set_draw_keys(&[k(key)]);
        world.execute_from(state, &c).unwrap()
    };
    // from a start: offset, each key its own
    let (a, next) = from(&mut world, &start, 1);
    let (b, _) = from(&mut world, &start, 2);
    assert_ne!(a.point, b.point);
    assert_eq!(from(&mut world, &start, 1).0, a);
    // from where a command left the world: no offset, whatever the key
    let (x, _) = from(&mut world, &next, 3);
    let (y, _) = from(&mut world, &next, 4);
    assert_eq!(x.point, y.point);
}

#[test]
fn a_context_memo_keeps_nothing_of_a_noisy_world() {
    use e3d::world::{ContextMemoized, Episodic, OutcomeMemo};
    use rand::SeedableRng;
    let scene = contexts_with(EPISODE_NOISE);
    let memos: Vec<OutcomeMemo> = (0..2)
        .map(|_| OutcomeMemo::new(&scene.command_space(), scene.num_effects(), 100).unwrap())
        .collect();
    let mut world = ContextMemoized::new(scene.build(), &memos);
    let c = world.command_space().parse("WWWWWWW").unwrap();
    let mut rng = e3d::SessionRng::seed_from_u64(0);
    let b = world.draw_start(1, &mut rng).unwrap();
    world.set_draw_keys(&[k(1)]);
    let first = world.execute_outcome_from(&b, &c).unwrap();
    world.set_draw_keys(&[k(2)]);
    let second = world.execute_outcome_from(&b, &c).unwrap();
    assert_ne!(first.point, second.point);
    assert_eq!(memos[1].len(), 0);
}

/// tests/scenes/puck_headings.ron (continuous headings) with `noise`.
fn headings_with(noise: &str) -> Scene {
    let text = std::fs::read_to_string("tests/scenes/puck_headings.ron")
        .unwrap()
        .replace(
            "effect: (body: \"puck\"",
            &format!("noise: {noise},\n        effect: (body: \"puck\""),
        );
    Scene::parse(&text, "h.ron").unwrap()
}

/// The reproducibility of the uniform policy of values on `scene`, on a
/// world of `copies` copies: 16 likely commands, 10 runs each, seed 4.
fn values_reproducibility(scene: &Scene, copies: usize) -> e3d::session::Reproducibility {
    use e3d::session::{reproducibility, RepeatOptions};
    let continuous = scene.as_continuous().unwrap();
    let learner = LearnerSetup::new(LearnerKind::Uniform)
        .values(continuous.values(), scene.num_effects())
        .unwrap();
    let options = RepeatOptions {
        commands: 16,
        runs: 10,
    };
    let mut world = continuous.world(copies);
    reproducibility(&mut world, &learner, options, 4)
        .unwrap()
        .expect("a policy of values is drawn from")
}

#[test]
fn the_reproducibility_of_values_is_1_without_noise_and_falls_with_it() {
    let plain = values_reproducibility(&Scene::load("tests/scenes/puck_headings.ron").unwrap(), 1);
    assert_eq!(plain.share, 1.0);
    assert_eq!(plain.each.len(), 16);
    assert!(plain.each.iter().all(|r| r.runs == 1));
    let noisy = headings_with(
        r#"(actions: Gaussian(sd: 0.15), starts: [(body: "puck", position: Gaussian(sd: 0.1))])"#,
    );
    let r = values_reproducibility(&noisy, 1);
    assert!(r.each.iter().all(|r| r.runs == 10));
    assert!(r.share < 1.0 && r.share > 0.0, "{}", r.share);
    // the same figure on a world of several copies, and again
    assert_eq!(values_reproducibility(&noisy, 4), r);
    assert_eq!(values_reproducibility(&noisy, 1), r);
}

#[test]
fn likely_values_come_from_the_policy_gaussians_within_the_ranges() {
    use e3d::session::Learns;
    use rand::SeedableRng;
    let scene = Scene::load("tests/scenes/puck_headings.ron").unwrap();
    let continuous = scene.as_continuous().unwrap();
    let space = continuous.values();
    let learner = LearnerSetup::new(LearnerKind::E3d)
        .values(space, scene.num_effects())
        .unwrap();
    let mut rng = e3d::SessionRng::seed_from_u64(1);
    let likely = learner.likely(&Vec::new(), 2000, &mut rng).unwrap();
    assert_eq!(likely.len(), 2000);
    for slot in 0..space.num_slots() {
        let (lo, hi) = space.range(slot);
        let xs: Vec<f64> = likely.iter().map(|v| v[slot]).collect();
        assert!(xs.iter().all(|&x| (lo..=hi).contains(&x)));
        // the mean of the draws is near the policy's (clamping is symmetric
        // about a centred mean)
        let (mean, sd) = learner.slot_gaussian(slot);
        let m = xs.iter().sum::<f64>() / xs.len() as f64;
        assert!(
            (m - mean).abs() < 4.0 * sd / (xs.len() as f64).sqrt() + 1e-9,
            "{m} {mean} {sd}"
        );
    }
}

/// The reproducibility of 40 episodes of 2 commands of closed-loop E3D
/// (seed 3) on `scene`: 12 likely episodes, 10 runs each.
fn episodes_reproducibility(scene: &Scene) -> e3d::session::Reproducibility {
    use e3d::episode::{run_episodes, EpisodeConfig, Observe};
    use e3d::session::{episode_reproducibility, RepeatOptions};
    let config = EpisodeConfig {
        episodes: 40,
        commands: 2,
        seed: 3,
        use_reward: true,
        observe: Observe::State,
    };
    let n = scene.num_effects();
    let mut learner = LearnerSetup::new(LearnerKind::E3d)
        .closed_loop(true)
        .contexts(&scene.command_space(), n, n)
        .unwrap();
    let mut world = scene.build();
    run_episodes(&mut *world, &mut *learner, &config, &Control::default()).unwrap();
    let options = RepeatOptions {
        commands: 12,
        runs: 10,
    };
    let r = episode_reproducibility(&mut *scene.build(), &*learner, &config, options);
    r.unwrap().expect("closed-loop E3D's policy is drawn from")
}

#[test]
fn the_reproducibility_of_episodes_is_1_without_noise_and_falls_with_it() {
    let plain = episodes_reproducibility(&Scene::load("scenes/puck_contexts.ron").unwrap());
    assert_eq!((plain.share, plain.each.len()), (1.0, 12));
    assert!(plain.each.iter().all(|r| (r.runs, r.kept) == (1, 1)));
    let noisy = contexts_with(
        r#"(actions: Gaussian(sd: 0.2), starts: [(body: "puck", position: Gaussian(sd: 0.1))])"#,
    );
    let r = episodes_reproducibility(&noisy);
    assert!(r.each.iter().all(|r| r.runs == 10));
    assert!(r.share < 1.0, "{}", r.share);
    assert!(r.each.iter().any(|r| r.kept < 10));
    // a fixed seed, fixed figures
    assert_eq!(episodes_reproducibility(&noisy), r);
}
