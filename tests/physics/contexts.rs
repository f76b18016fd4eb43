//! Start contexts of physics scenes (docs/scenes.md, "Start contexts"):
//! named and drawn starts, a command continued exactly from the state the
//! last one left, commands from named contexts kept by (context, command),
//! and contextual E3D on scenes/puck_contexts.ron.

use e3d::episode::{run_episodes, EpisodeConfig, Observe};
use e3d::learner::ContextTargets;
use e3d::world::WorldState;
use e3d::world::{ContextMemoized, OutcomeMemo};
use e3d::{LearnerKind, Params, Scene, SessionRng, Target, World};
use rand::SeedableRng;

fn puck_contexts() -> Scene {
    Scene::load("scenes/puck_contexts.ron").unwrap()
}

fn physics(state: &WorldState) -> &e3d::world::PhysicsState {
    match state {
        WorldState::Physics(s) => s,
        other => panic!("a physics state, found {other:?}"),
    }
}

/// `scene`'s text with `from` replaced by `to` (exactly once), parsed.
fn edited(name: &str, edits: &[(&str, &str)]) -> Scene {
    let mut text = std::fs::read_to_string(format!("scenes/{name}.ron")).unwrap();
    for (from, to) in edits {
        assert_eq!(text.matches(from).count(), 1, "{from}");
        text = text.replace(from, to);
    }
    Scene::parse(&text, &format!("{name}.ron")).unwrap()
}

/// Executing `c1` from a start, then `c2` from the state `c1` left, ends in
/// the very bytes of one continued rollout of `c1` then `c2` (a scene of
/// twice the slots, no settling in between): on the puck, which bounces off
/// the north wall, and on arm_push (joints, contacts with the puck), whose
/// joint targets hold from `c1` into `c2`.
#[test]
fn a_command_continues_exactly_from_the_state_the_last_one_left() {
    /// A scene, the edits that double its slots, its settle, `c1`, `c2`.
    type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a str, &'a str, &'a str);
    let cases: [Case<'_>; 2] = [
        (
            "puck_contexts",
            &[("slots: 7", "slots: 14")],
            "settle: 2.0",
            "NNNNNNN",
            "EEEEESS",
        ),
        (
            "arm_push",
            &[
                ("    slots: 6,\n    world", "    slots: 12,\n    world"),
                ("        slots: 6,", "        slots: 12,"),
            ],
            "settle: 1.0",
            "+-0+0-",
            "-++0-0",
        ),
    ];
    for (name, twice, settle, c1, c2) in cases {
        let short = edited(name, &[(settle, "settle: 0.0")]);
        let mut edits = vec![(settle, "settle: 0.0")];
        edits.extend_from_slice(twice);
        let long = edited(name, &edits);
        let mut rng = SessionRng::seed_from_u64(0);
        let mut w = short.build();
        let s = w.draw_start(0, &mut rng).unwrap();
        let (c1, c2) = (
            short.command_space().parse(c1).unwrap(),
            short.command_space().parse(c2).unwrap(),
        );
        let (_, s1) = w.execute_from(&s, &c1).unwrap();
        let (o2, s2) = w.execute_from(&s1, &c2).unwrap();
        let mut both = c1.symbols.clone();
        both.extend(&c2.symbols);
        let mut wl = long.build();
        let (o, t) = wl.execute_from(&s, &e3d::Command::new(both)).unwrap();
        assert_eq!(physics(&s2).to_bytes(), physics(&t).to_bytes(), "{name}");
        assert_eq!(
            o2.point.map(f64::to_bits),
            o.point.map(f64::to_bits),
            "{name}"
        );
        // and the continuation moved: c2 did not start from the scene's start
        let (fresh, _) = w.execute_from(&s, &c2).unwrap();
        assert_ne!(fresh.point, o2.point, "{name}");
    }
}

/// From a start context, `execute_from` gives `execute`'s outcome on the
/// scene that starts there; the state it leaves is the world's terminal
/// state, binned as its effect; a state without its snapshot is refused.
#[test]
fn named_contexts_start_where_they_say() {
    let scene = puck_contexts();
    let mut w = scene.build();
    assert_eq!(w.num_contexts(), 2);
    let mut rng = SessionRng::seed_from_u64(3);
    let a = w.draw_start(0, &mut rng).unwrap();
    let b = w.draw_start(1, &mut rng).unwrap();
    assert_eq!((a.context(), b.context()), (Some(0), Some(1)));
    let puck = |s: &WorldState| physics(s).poses.last().unwrap()[..2].to_vec();
    assert_eq!(puck(&a), vec![0.5f32 as f64, 2.5]);
    assert_eq!(puck(&b), vec![5.5, 0.5]);
    // the effect bins: cell (0, 0) and cell (2, 5)
    assert_eq!(
        (w.bin_state(&a).unwrap(), w.bin_state(&b).unwrap()),
        (0, 17)
    );
    // room_a is puck_rooms' start: the same outcome as puck_rooms
    let rooms = Scene::builtin("puck_rooms").unwrap();
    let c = scene.command_space().parse("SEEEEES").unwrap();
    let (o, end) = w.execute_from(&a, &c).unwrap();
    let r = rooms.build().execute(&c).unwrap();
    assert_eq!((o.effect, o.point), (r.effect, r.point));
    assert_eq!(w.bin_state(&end).unwrap(), o.effect);
    assert_eq!(end.context(), None);
    // west from room_a stays in cell (0, 0); from room_b it stops at the
    // inner wall, in cell (2, 3)
    let west = scene.command_space().parse("WWWWWWW").unwrap();
    let (oa, _) = w.execute_from(&a, &west).unwrap();
    let (ob, _) = w.execute_from(&b, &west).unwrap();
    assert_eq!((oa.effect, ob.effect), (0, 15));
    // a state read back has no snapshot: compared equal, never executed
    let json = serde_json::to_string(&end).unwrap();
    let back: WorldState = serde_json::from_str(&json).unwrap();
    assert_eq!(physics(&back).poses.len(), physics(&end).poses.len());
    assert!(!physics(&back).is_executable() && physics(&end).is_executable());
    let e = w.execute_from(&back, &c).unwrap_err().to_string();
    assert!(e.contains("no snapshot"), "{e}");
    assert!(w.execute_from(&WorldState::Cell(0), &c).is_err());
    assert!(w.draw_start(2, &mut rng).is_err());
}

/// A context with a range draws the start with the session's generator:
/// inside the rectangle, the same seed the same start, and such starts are
/// never looked up by context.
/// The start drawn in `context` with seed `seed`: the same twice, and a
/// drawn state (no listed context).
fn seeded_draw(w: &dyn World, context: usize, seed: u64) -> WorldState {
    let s = w
        .draw_start(context, &mut SessionRng::seed_from_u64(seed))
        .unwrap();
    let again = w
        .draw_start(context, &mut SessionRng::seed_from_u64(seed))
        .unwrap();
    assert_eq!(s, again);
    assert_eq!(s.context(), None);
    s
}

#[test]
fn drawn_contexts_are_seeded_and_inside_their_range() {
    let scene = edited(
        "puck_contexts",
        &[(
            "position: (5.5, 0.5))",
            "position: (3.5, 0.5), to: (5.5, 2.5), velocity: (0.5, 0.0))",
        )],
    );
    let w = scene.build();
    let mut xs = Vec::new();
    for seed in 0..20 {
        let s = seeded_draw(&*w, 1, seed);
        let st = physics(&s);
        let p = st.poses.last().unwrap();
        assert!(
            (3.5..=5.5).contains(&p[0]) && (0.5..=2.5).contains(&p[1]),
            "{p:?}"
        );
        assert_eq!(st.velocities.last().unwrap()[0], 0.5);
        xs.push(p[0]);
    }
    xs.sort_by(f64::total_cmp);
    assert!(xs[19] - xs[0] > 1.0, "{xs:?}");
}

/// Sessions with their outcomes from named contexts kept by (context,
/// command) record the same bytes as sessions that simulate every
/// command, and simulate each (context, command) once.
#[test]
fn the_context_memo_changes_no_result() {
    let scene = puck_contexts();
    let space = scene.command_space();
    let shared = ContextTargets::Shared(Target::Uniform);
    let memos: Vec<OutcomeMemo> = (0..2)
        .map(|_| OutcomeMemo::new(&space, 18, 1 << 20).unwrap())
        .collect();
    let cfg = EpisodeConfig {
        episodes: 300,
        commands: 1,
        seed: 5,
        use_reward: false,
        observe: Observe::StartContext,
    };
    let make = || {
        LearnerKind::E3d
            .make_contextual(&Params::TASK1, &space, 18, 2, &shared)
            .unwrap()
    };
    let plain = run_episodes(
        &mut scene.build(),
        &mut make(),
        &cfg,
        &e3d::session::Control::default(),
    )
    .unwrap();
    let mut kept = ContextMemoized::new(scene.build(), &memos);
    let memoized = run_episodes(
        &mut kept,
        &mut make(),
        &cfg,
        &e3d::session::Control::default(),
    )
    .unwrap();
    assert_eq!(plain, memoized);
    let again = run_episodes(
        &mut kept,
        &mut make(),
        &cfg,
        &e3d::session::Control::default(),
    )
    .unwrap();
    assert_eq!(plain, again);
    let len = memos[0].len() + memos[1].len();
    let misses = memos[0].misses() + memos[1].misses();
    assert_eq!(len as u64, misses, "each (context, command) simulated once");
    assert_eq!(memos[0].hits() + memos[1].hits() + misses, 600);
    assert!(
        memos[0].hits() + memos[1].hits() >= 300,
        "the second run is all look-ups"
    );
}

/// docs/reproducing.md, "Start contexts on puck_contexts", on 3 of its 20
/// seeds: contextual E3D spreads each room's terminal cells evenly, the
/// context-blind E3D cannot (measured on the 20 seeds: 0.957..0.990
/// against 0.783..0.815).
#[test]
fn contextual_e3d_spreads_every_room_of_the_puck_where_blind_e3d_cannot() {
    let scene = puck_contexts();
    let space = scene.command_space();
    let memos: Vec<OutcomeMemo> = (0..2)
        .map(|_| OutcomeMemo::new(&space, 18, 1 << 20).unwrap())
        .collect();
    for seed in 0..3 {
        let h = crate::common::seen_and_blind_entropy(&space, 18, 2, seed, || {
            Box::new(ContextMemoized::new(scene.build(), &memos))
        });
        for s in 0..2 {
            assert!(h[0][s] > 0.94, "seed {seed}: {h:?}");
            assert!(h[1][s] < 0.84, "seed {seed}: {h:?}");
        }
    }
}

/// The world spec of a physics scene (its shorthands expanded).
fn spec_of(scene: &Scene) -> &e3d::scene::physics::PhysicsSpec {
    match &scene.spec().world {
        e3d::scene::WorldSpec::Physics(p) => p,
        _ => panic!("a physics scene"),
    }
}

/// Whether every hinge of `scene` holds in `state`: its anchors on the
/// parent (or ground) and on the child at the same world point.
fn hinges_hold(scene: &Scene, state: &WorldState) -> f64 {
    let spec = spec_of(scene);
    let st = physics(state);
    let world = |body: &str, p: (f64, f64)| -> (f64, f64) {
        match spec.bodies.iter().position(|b| b.name == body) {
            None => p, // ground
            Some(i) => {
                let [x, y, a] = st.poses[i];
                (
                    x + a.cos() * p.0 - a.sin() * p.1,
                    y + a.sin() * p.0 + a.cos() * p.1,
                )
            }
        }
    };
    spec.joints
        .iter()
        .map(|j| {
            let (p, c) = (
                world(&j.parent, j.parent_anchor),
                world(&j.child, j.child_anchor),
            );
            (p.0 - c.0).hypot(p.1 - c.1)
        })
        .fold(0.0, f64::max)
}

/// A context may turn joints and set them turning: on arm_push (a
/// multibody hung on ground) and on the swimmer (a free-floating tree of
/// impulse joints), the start has the joints' coordinates and rates the
/// context gives, the unlisted joints at 0, every hinge holding, and the
/// unlisted bodies where the scene puts them.
#[test]
fn joint_contexts_start_in_the_pose_they_give() {
    let contexts = "        schedule:";
    let arm = edited(
        "arm_push",
        &[(
            contexts,
            "        contexts: [(name: \"bent\", joints: [(joint: \"j1\", angle: -0.6), (joint: \"j2\", angle: -0.4, velocity: 0.5)])],\n        schedule:",
        )],
    );
    let swimmer = edited(
        "swimmer",
        &[(
            contexts,
            "        contexts: [(name: \"curled\", joints: [(joint: \"j2\", angle: 0.8, velocity: -0.3)])],\n        schedule:",
        )],
    );
    let cases = [
        (arm, "arm_push", vec![(-0.6, 0.0), (-0.4, 0.5), (0.0, 0.0)]),
        (
            swimmer,
            "swimmer",
            vec![(0.0, 0.0), (0.8, -0.3), (0.0, 0.0)],
        ),
    ];
    for (scene, name, want) in cases {
        let w = scene.build();
        let plain = Scene::builtin(name).unwrap();
        let pristine = plain
            .build()
            .draw_start(0, &mut SessionRng::seed_from_u64(0))
            .unwrap();
        let s = w.draw_start(0, &mut SessionRng::seed_from_u64(0)).unwrap();
        assert_eq!(s.context(), Some(0), "{name}");
        let st = physics(&s);
        for (k, (q, w)) in want.iter().enumerate() {
            let [a, r] = st.joints[k];
            assert!(
                (a - q).abs() < 1e-5 && (r - w).abs() < 1e-4,
                "{name} joint {k}: {a} {r}, want {q} {w}"
            );
        }
        assert!(
            hinges_hold(&scene, &s) < 1e-5,
            "{name}: {}",
            hinges_hold(&scene, &s)
        );
        assert!(hinges_hold(&plain, &pristine) < 1e-5, "{name}");
        // the last link turned by the sum of the joints' angles
        let last = spec_of(&scene)
            .bodies
            .iter()
            .rposition(|b| b.name.starts_with("link"))
            .unwrap();
        let turned = st.poses[last][2] - physics(&pristine).poses[last][2];
        let sum: f64 = want.iter().map(|(q, _)| q).sum();
        assert!((turned - sum).abs() < 1e-5, "{name}: {turned} {sum}");
    }
    // arm_push's puck, no joint's body, starts where the scene puts it
    let arm = edited("arm_push", &[(contexts, "        contexts: [(name: \"bent\", joints: [(joint: \"j3\", angle: 1.0)])],\n        schedule:")]);
    let s = arm
        .build()
        .draw_start(0, &mut SessionRng::seed_from_u64(0))
        .unwrap();
    assert_eq!(
        physics(&s).poses.last().unwrap()[..2],
        [0.7f32 as f64, 0.3f32 as f64]
    );
}

/// A drawn joint angle is seeded and inside its range, and an episode of
/// K = 3 commands from a joint context on arm_push ends in the very bytes
/// of one continued rollout of the three commands.
#[test]
fn joint_contexts_continue_exactly_over_three_commands() {
    let context = "        contexts: [(name: \"bent\", joints: [(joint: \"j1\", angle: -0.6, velocity: -0.5), (joint: \"j2\", angle: -0.4)])],\n        schedule:";
    let short = edited(
        "arm_push",
        &[
            ("        schedule:", context),
            ("settle: 1.0", "settle: 0.0"),
        ],
    );
    let long = edited(
        "arm_push",
        &[
            ("        schedule:", context),
            ("settle: 1.0", "settle: 0.0"),
            ("    slots: 6,\n    world", "    slots: 18,\n    world"),
            ("        slots: 6,", "        slots: 18,"),
        ],
    );
    let mut w = short.build();
    let s = w.draw_start(0, &mut SessionRng::seed_from_u64(0)).unwrap();
    let space = short.command_space();
    let cs = ["+-0+0-", "-++0-0", "0+-+-+"].map(|c| space.parse(c).unwrap());
    let mut at = s.clone();
    let mut last = None;
    for c in &cs {
        let (o, next) = w.execute_from(&at, c).unwrap();
        last = Some(o);
        at = next;
    }
    let all: Vec<u8> = cs.iter().flat_map(|c| c.symbols.clone()).collect();
    let (o, t) = long
        .build()
        .execute_from(&s, &e3d::Command::new(all))
        .unwrap();
    assert_eq!(physics(&at).to_bytes(), physics(&t).to_bytes());
    assert_eq!(
        last.unwrap().point.map(f64::to_bits),
        o.point.map(f64::to_bits)
    );
    // the joint context is not the scene's start: the first command ends elsewhere
    let plain = edited("arm_push", &[("settle: 1.0", "settle: 0.0")]);
    let p0 = plain
        .build()
        .draw_start(0, &mut SessionRng::seed_from_u64(0))
        .unwrap();
    let (from_bent, _) = w.execute_from(&s, &cs[0]).unwrap();
    let (from_plain, _) = plain.build().execute_from(&p0, &cs[0]).unwrap();
    assert_ne!(from_bent.point, from_plain.point);
    // a joint's rate alone moves the arm: the multibody's generalized
    // velocity is set, not only its bodies' velocities
    let spun = edited(
        "arm_push",
        &[
            ("settle: 1.0", "settle: 0.0"),
            ("        schedule:", "        contexts: [(name: \"spun\", joints: [(joint: \"j1\", velocity: -2.0)])],\n        schedule:"),
        ],
    );
    let mut ws = spun.build();
    let s0 = ws.draw_start(0, &mut SessionRng::seed_from_u64(0)).unwrap();
    let idle = space.parse("000000").unwrap();
    let (_, after) = ws.execute_from(&s0, &idle).unwrap();
    let (_, still) = plain.build().execute_from(&p0, &idle).unwrap();
    // (the motors pull j1 back to its set point 0 within the 3 s; at rest
    // the arm does not move at all)
    let (moved, rest) = (physics(&after).joints[0][0], physics(&still).joints[0][0]);
    assert!(moved.abs() > 1e-6 && rest.abs() < 1e-9, "{moved} {rest}");
    // a drawn angle: seeded, inside its range
    let drawn = edited(
        "arm_push",
        &[("        schedule:", "        contexts: [(name: \"any\", joints: [(joint: \"j2\", angle: -0.5, to: 0.3)])],\n        schedule:")],
    );
    let w = drawn.build();
    let mut qs = Vec::new();
    for seed in 0..10 {
        let a = seeded_draw(&*w, 0, seed);
        let q = physics(&a).joints[1][0];
        assert!((-0.5 - 1e-5..=0.3 + 1e-5).contains(&q), "{q}");
        assert!(hinges_hold(&drawn, &a) < 1e-5);
        qs.push(q);
    }
    qs.sort_by(f64::total_cmp);
    assert!(qs[9] - qs[0] > 0.4, "{qs:?}");
}

/// The start poses a scene file gives its contexts (forward kinematics of
/// the file, what the load-time overlap check tests) are the world's own
/// starts, to within Rapier's single precision: on arm7_poses (a
/// multibody hung on ground, three poses), on the swimmer (a free-floating
/// tree, its root moved and turned, a joint turned) and on arm_push (a
/// turned joint and the puck left where the scene puts it).
#[test]
fn a_scene_file_gives_each_context_the_world_s_start_poses() {
    let swimmer = edited(
        "swimmer",
        &[(
            "        schedule:",
            "        contexts: [(name: \"moved\", bodies: [(body: \"link1\", position: (0.3, 0.2), angle: 0.5)], joints: [(joint: \"j2\", angle: 0.8)])],\n        schedule:",
        )],
    );
    let arm_push = edited(
        "arm_push",
        &[(
            "        schedule:",
            "        contexts: [(name: \"bent\", joints: [(joint: \"j1\", angle: 0.6), (joint: \"j3\", angle: 0.9)])],\n        schedule:",
        )],
    );
    let arm7 = Scene::load("scenes/arm7_poses.ron").unwrap();
    let mut checked = 0;
    for scene in [&arm7, &swimmer, &arm_push] {
        let spec = spec_of(scene);
        let w = scene.build();
        for k in 0..spec.contexts.len() {
            let s = w.draw_start(k, &mut SessionRng::seed_from_u64(0)).unwrap();
            let from_file = spec.context_poses(k);
            for (b, (pose, file)) in physics(&s).poses.iter().zip(&from_file).enumerate() {
                let da = (pose[2] - file.2 + std::f64::consts::PI)
                    .rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI;
                assert!(
                    (pose[0] - file.0).abs() < 2e-5
                        && (pose[1] - file.1).abs() < 2e-5
                        && da.abs() < 2e-5,
                    "{} context {k} body {b}: world {pose:?}, file {file:?}",
                    scene.spec().name
                );
                checked += 1;
            }
        }
    }
    // 3 x 7 links, the swimmer's links, arm_push's links and puck
    assert!(checked >= 21 + 3 + 4, "{checked}");
    // the bent arm's tip is not where the straight arm's is
    let p = spec_of(&arm7);
    assert!((p.context_poses(0)[6].0 - p.context_poses(1)[6].0).abs() > 0.4);
}

/// A context that folds arm7 onto itself (non-neighbour links collide) is
/// refused at load with the context's place and the two links, as a wall
/// through a link is (tests/bad_inputs/context_*_in_wall.ron).
#[test]
fn a_context_folding_the_arm_onto_itself_is_refused() {
    let text = std::fs::read_to_string("scenes/arm7_poses.ron").unwrap();
    let folded = "(joint: \"j4\", angle: 1.5)";
    assert_eq!(text.matches(folded).count(), 1);
    let bad = text.replace(
        folded,
        "(joint: \"j3\", angle: 2.5), (joint: \"j4\", angle: 2.5)",
    );
    let e = Scene::parse(&bad, "arm7_folded.ron")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("arm7_folded.ron:33:")
            && e.contains("field `joints`: expected context `curled`: a start where no two bodies overlap, but `link"),
        "{e}"
    );
}
