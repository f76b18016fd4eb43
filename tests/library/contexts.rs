//! Start contexts, contextual learners and closed loops (docs/algorithms.md,
//! "Contexts and closed loop"): every contextual learner against a plain
//! transcription of its equations, and a K-command episode against one
//! continued command.

use e3d::episode::{run_episodes, EpisodeConfig, Observe};
use e3d::learner::LearnerSetup;
use e3d::learner::{ClosedLoopE3d, ContextTargets, ContextualLearner, QLearning};
use e3d::scene::{CommandSpec, WorldSpec};
use e3d::world::{Episodic, WorldState};
use e3d::{
    run_session, Command, LearnerKind, Outcome, Params, Scene, SessionConfig, SessionRng, Target,
    World,
};
use rand::{RngExt, SeedableRng};

const TWO_ROOMS_CONTEXTS: &str = r#"Scene(
    name: "two_rooms_contexts",
    world: Grid(rows: 3, cols: 6, start: (0, 0),
        walls: [((0, 2), (0, 3)), ((2, 2), (2, 3))],
        contexts: [(name: "a", cell: (0, 0)), (name: "b", cell: (2, 5)), (name: "anywhere_b", cell: (0, 3), to: (2, 5))]),
    command: Repeat(slots: 3, alphabet: [
        (symbol: 'E', action: Move(drow: 0, dcol: 1)),
        (symbol: 'S', action: Move(drow: 1, dcol: 0)),
        (symbol: 'W', action: Move(drow: 0, dcol: -1)),
        (symbol: 'N', action: Move(drow: -1, dcol: 0)),
    ]),
    reward: (cells: [(2, 5)]),
)"#;

fn with_slots(scene: &Scene, n: usize) -> Scene {
    let mut s = scene.to_spec();
    if let CommandSpec::Repeat { slots, .. } = &mut s.command {
        *slots = n;
    }
    s.validate().unwrap()
}

#[test]
fn grid_start_contexts_load_draw_and_refuse_bad_cells() {
    let scene = Scene::parse(TWO_ROOMS_CONTEXTS, "t.ron").unwrap();
    let WorldSpec::Grid(g) = &scene.spec().world else {
        panic!()
    };
    assert_eq!(g.num_contexts(), 3);
    assert_eq!(
        Scene::parse(&scene.spec().to_ron(), "again.ron").unwrap(),
        scene
    );
    let world = scene.build();
    assert_eq!(world.num_contexts(), 3);
    let mut rng = SessionRng::seed_from_u64(1);
    assert_eq!(world.draw_start(1, &mut rng).unwrap(), WorldState::Cell(17));
    // the rectangle: every cell of room B, none of room A
    let mut seen = [0usize; 18];
    for _ in 0..900 {
        let WorldState::Cell(c) = world.draw_start(2, &mut rng).unwrap() else {
            panic!()
        };
        seen[c] += 1;
    }
    for (c, &n) in seen.iter().enumerate() {
        if c % 6 >= 3 {
            assert!((60..=140).contains(&n), "cell {c}: {n}");
        } else {
            assert_eq!(n, 0, "cell {c}");
        }
    }
    assert!(world.draw_start(3, &mut rng).is_err());
    // a scene without contexts has one: its start
    assert_eq!(
        Scene::builtin("two_rooms").unwrap().build().num_contexts(),
        1
    );

    let bad = TWO_ROOMS_CONTEXTS.replace("cell: (2, 5)),", "cell: (3, 5)),");
    let e = Scene::parse(&bad, "bad.ron").unwrap_err().to_string();
    assert!(
        e.contains("bad.ron") && e.contains("contexts") && e.contains("(3, 5)"),
        "{e}"
    );
    let twice = TWO_ROOMS_CONTEXTS.replace("name: \"b\"", "name: \"a\"");
    let e = Scene::parse(&twice, "twice.ron").unwrap_err().to_string();
    assert!(e.contains("distinct"), "{e}");
}

#[test]
fn a_k_command_episode_ends_where_one_continued_command_ends() {
    let scene = Scene::builtin("four_rooms").unwrap();
    let mut short = scene.build();
    let mut long = with_slots(&scene, 15).build();
    let space = scene.command_space();
    let mut rng = SessionRng::seed_from_u64(4);
    let mut far = 0;
    for _ in 0..3000 {
        let parts: Vec<Command> = (0..3)
            .map(|_| Command::new((0..5).map(|_| rng.random_range(0..4u8)).collect()))
            .collect();
        let mut state = short.draw_start(0, &mut rng).unwrap();
        let mut last = None;
        for c in &parts {
            let (o, s) = short.execute_from(&state, c).unwrap();
            state = s;
            last = Some(o);
        }
        let joined = Command::new(parts.iter().flat_map(|c| c.symbols.clone()).collect());
        let one = long.execute(&joined).unwrap();
        assert_eq!(last.unwrap(), one, "{}", space.format(&parts[0]));
        assert_eq!(state, WorldState::Cell(one.effect));
        far += usize::from(one.effect % 12 >= 6);
    }
    assert!(far > 0);
    // and the reward cell is out of reach of one command of 5 or 7 moves
    for n in [5, 7] {
        let table = e3d::OutcomeTable::build(&mut with_slots(&scene, n).build()).unwrap();
        assert!(table.outcomes().all(|o| o.effect != 35), "{n} moves");
    }
}

/// The plain, per-context transcription of the softmax drives
/// (docs/algorithms.md): `Q[s][slot][a]`, `p[s][e]`, counts per context.
struct Plain {
    kind: LearnerKind,
    q: Vec<Vec<Vec<f64>>>,
    p: Vec<Vec<f64>>,
    counts: Vec<Vec<f64>>,
    params: Params,
}

impl Plain {
    fn new(kind: LearnerKind, contexts: usize, slots: usize, k: usize, effects: usize) -> Self {
        let params = Params {
            epsilon: 0.2,
            ..Params::TASK2
        };
        Plain {
            kind,
            q: vec![vec![vec![0.0; k]; slots]; contexts],
            p: vec![vec![1.0 / effects as f64; effects]; contexts],
            counts: vec![vec![0.0; effects]; contexts],
            params,
        }
    }

    fn propose(&self, s: usize, rng: &mut SessionRng) -> Vec<u8> {
        self.q[s]
            .iter()
            .map(|q| match self.kind {
                LearnerKind::Uniform => rng.random_range(0..q.len()) as u8,
                LearnerKind::Egreedy => {
                    if rng.random::<f64>() < self.params.epsilon {
                        rng.random_range(0..q.len()) as u8
                    } else {
                        let best = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                        let ties: Vec<usize> = (0..q.len()).filter(|&a| q[a] == best).collect();
                        ties[rng.random_range(0..ties.len())] as u8
                    }
                }
                _ => {
                    let top = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    let w: Vec<f64> = q
                        .iter()
                        .map(|v| (self.params.beta * (v - top)).exp())
                        .collect();
                    let z: f64 = w.iter().sum();
                    let u: f64 = rng.random();
                    let mut acc = 0.0;
                    for (a, v) in w.iter().enumerate() {
                        acc += v / z;
                        if u < acc {
                            return a as u8;
                        }
                    }
                    (q.len() - 1) as u8
                }
            })
            .collect()
    }

    fn learn(&mut self, s: usize, c: &[u8], e: usize, r: f64) {
        let Params {
            alpha,
            beta,
            lambda,
            eta,
            ..
        } = self.params;
        let n = self.p[s].len() as f64;
        self.counts[s][e] += 1.0;
        for (i, v) in self.p[s].iter_mut().enumerate() {
            *v = (1.0 - eta) * *v + if i == e { eta } else { 0.0 };
        }
        let drive = match self.kind {
            LearnerKind::E3d | LearnerKind::E3dRelax => -(self.p[s][e].ln() - (1.0 / n).ln()),
            LearnerKind::Count => 1.0 / self.counts[s][e].sqrt(),
            _ => 0.0,
        };
        if self.kind == LearnerKind::E3dRelax {
            for q in self.q[s].iter_mut().flatten() {
                *q *= 1.0 - 0.02 * alpha * lambda;
            }
        }
        for (slot, &a) in c.iter().enumerate() {
            let q = &mut self.q[s][slot][a as usize];
            *q = match self.kind {
                LearnerKind::Egreedy => (1.0 - alpha) * *q + alpha * r,
                LearnerKind::Uniform => 0.0,
                _ => (1.0 - alpha * lambda) * *q + alpha * lambda * r + alpha / beta * drive,
            };
        }
    }
}

/// Runs `kind` per context on the start contexts of TWO_ROOMS_CONTEXTS
/// against its plain transcription: the same commands (nearly all: a draw
/// may round the other way), the same policies and Q to 1e-9.
fn follows_the_plain_transcription(kind: LearnerKind) {
    let scene = Scene::parse(TWO_ROOMS_CONTEXTS, "t.ron").unwrap();
    let mut world = scene.build();
    let space = scene.command_space();
    let mut plain = Plain::new(kind, 3, 3, 4, 18);
    let mut fast = LearnerSetup::new(kind)
        .params(plain.params)
        .contexts(&space, 18, 3)
        .unwrap();
    let (mut ra, mut rb) = (SessionRng::seed_from_u64(7), SessionRng::seed_from_u64(7));
    let mut c = space.first();
    let mut same = 0;
    let trials = 4000;
    for _ in 0..trials {
        let s = ra.random_range(0..3usize);
        assert_eq!(s, rb.random_range(0..3usize));
        let start = world.draw_start(s, &mut ra).unwrap();
        assert_eq!(start, world.draw_start(s, &mut rb).unwrap());
        fast.propose(s, &mut ra, &mut c);
        let cp = plain.propose(s, &mut rb);
        same += usize::from(c.symbols == cp);
        let cp = Command::new(cp);
        let (o, _) = world.execute_from(&start, &cp).unwrap();
        fast.learn(s, &cp, &o, None);
        plain.learn(s, &cp.symbols, o.effect, o.reward);
    }
    assert!(
        same >= trials - 10,
        "{kind}: {same} of {trials} commands equal"
    );
    for s in 0..3 {
        for slot in 0..3 {
            let want = &plain.q[s][slot];
            let got = fast.slot_policy(s, slot).unwrap();
            let probs = match kind {
                LearnerKind::Uniform => vec![0.25; 4],
                LearnerKind::Egreedy => {
                    let best = want.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    let ties = want.iter().filter(|&&v| v == best).count() as f64;
                    want.iter()
                        .map(|&v| 0.05 + if v == best { 0.8 / ties } else { 0.0 })
                        .collect()
                }
                _ => {
                    let top = want.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    let w: Vec<f64> = want.iter().map(|v| (100.0 * (v - top)).exp()).collect();
                    let z: f64 = w.iter().sum();
                    w.iter().map(|v| v / z).collect()
                }
            };
            for (a, b) in got.iter().zip(&probs) {
                assert!(
                    (a - b).abs() < 1e-9,
                    "{kind} context {s} slot {slot}: {a} vs {b}"
                );
            }
        }
    }
    // the contexts learned apart: context b (the reward cell) differs from a
    assert!(kind == LearnerKind::Uniform || plain.q[0] != plain.q[1]);
}

#[test]
fn every_contextual_learner_follows_its_plain_transcription() {
    for kind in [
        LearnerKind::E3d,
        LearnerKind::Uniform,
        LearnerKind::Egreedy,
        LearnerKind::E3dRelax,
        LearnerKind::Count,
    ] {
        follows_the_plain_transcription(kind);
    }
}

/// SMM per context: each context's learner is a fresh SMM fed only that
/// context's trials (SMM itself follows its plain transcription:
/// `drives::smm_follows_its_plain_transcription`).
#[test]
fn smm_per_context_is_one_smm_per_context() {
    let scene = Scene::parse(TWO_ROOMS_CONTEXTS, "t.ron").unwrap();
    let mut world = scene.build();
    let space = scene.command_space();
    let shared = ContextTargets::Shared(Target::Uniform);
    let mut ctx = LearnerSetup::new(LearnerKind::Smm)
        .params(Params::TASK2)
        .targets(shared)
        .contexts(&space, 18, 3)
        .unwrap();
    let mut apart: Vec<_> = (0..3)
        .map(|_| {
            LearnerSetup::new(LearnerKind::Smm)
                .params(Params::TASK2)
                .symbols(&space, 18)
                .unwrap()
        })
        .collect();
    let (mut ra, mut rb) = (SessionRng::seed_from_u64(3), SessionRng::seed_from_u64(3));
    let (mut c, mut d) = (space.first(), space.first());
    for _ in 0..3000 {
        let s = ra.random_range(0..3usize);
        rb.random_range(0..3usize);
        let start = world.draw_start(s, &mut ra).unwrap();
        world.draw_start(s, &mut rb).unwrap();
        ctx.propose(s, &mut ra, &mut c);
        apart[s].propose(&mut rb, &mut d);
        assert_eq!(c, d);
        let (o, _) = world.execute_from(&start, &c).unwrap();
        ctx.learn(s, &c, &o, None);
        apart[s].learn(&d, &o);
    }
}

#[test]
fn one_context_and_one_command_is_the_open_loop_session() {
    let scene = Scene::builtin("two_rooms").unwrap();
    let space = scene.command_space();
    for kind in [LearnerKind::E3d, LearnerKind::Egreedy, LearnerKind::Count] {
        let mut open = LearnerSetup::new(kind)
            .params(Params::TASK2)
            .symbols(&space, 18)
            .unwrap();
        let cfg = SessionConfig {
            trials: 3000,
            seed: 5,
            use_reward: true,
        };
        let a = run_session(&mut scene.build(), &mut open, &cfg).unwrap();
        let mut ctx = LearnerSetup::new(kind)
            .params(Params::TASK2)
            .contexts(&space, 18, 1)
            .unwrap();
        let ecfg = EpisodeConfig {
            episodes: 3000,
            commands: 1,
            seed: 5,
            use_reward: true,
            observe: Observe::StartContext,
        };
        let b = run_episodes(
            &mut scene.build(),
            &mut ctx,
            &ecfg,
            &e3d::session::Control::default(),
        )
        .unwrap();
        assert_eq!(a.effects, b.effects, "{kind}");
        assert_eq!(a.commands, b.commands, "{kind}");
        assert_eq!(a.rewards, b.rewards, "{kind}");
    }
}

/// Plain closed-loop E3D and Q-learning: `Q_ref` (or `Q`) a map over
/// (context, command index), the Bellman target, E3D's update with it.
#[test]
fn closed_loop_learners_follow_their_plain_transcription() {
    let scene = Scene::builtin("four_rooms").unwrap();
    let space = scene.command_space();
    let (contexts, commands, gamma) = (36, 1024, 0.9);
    let params = Params {
        epsilon: 0.2,
        ..Params::TASK2
    };
    let targets = ContextTargets::Shared(Target::Uniform);
    let mut e3d = ClosedLoopE3d::new(&space, 36, contexts, &params, &targets, gamma).unwrap();
    let mut ql = QLearning::new(&space, contexts, &params, gamma).unwrap();
    let mut qref = vec![vec![0.0; commands]; contexts];
    let mut qq = qref.clone();
    let mut policy = Plain::new(LearnerKind::E3d, contexts, 5, 4, 36);
    let best = |row: &[f64]| row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut world = scene.build();
    let mut rng = SessionRng::seed_from_u64(8);
    let mut rng_q = SessionRng::seed_from_u64(8);
    let mut rng_plain = SessionRng::seed_from_u64(8);
    let mut rng_q_plain = SessionRng::seed_from_u64(8);
    let mut c = space.first();
    let (mut rewarded, mut same) = (0, 0);
    for _ in 0..3000 {
        // from (1, 6) the reward cell (2, 11) is 6 moves away: two
        // commands, so the Bellman targets carry it back
        let mut state = WorldState::Cell(18);
        for k in 0..3 {
            let s = world.bin_state(&state).unwrap();
            e3d.propose(s, &mut rng, &mut c);
            let cp = policy.propose(s, &mut rng_plain);
            same += usize::from(c.symbols == cp);
            // both learn from the plain command (a draw rounded the other
            // way does not fork the runs)
            let c = Command::new(cp);
            // Q-learning's draws, transcribed: epsilon-greedy over the
            // commands, a uniform command or one of the best, drawn in
            // index order
            let mut cq = space.first();
            ql.propose(s, &mut rng_q, &mut cq);
            let plain_q = if rng_q_plain.random::<f64>() < params.epsilon {
                space
                    .sizes()
                    .map(|k| rng_q_plain.random_range(0..k) as u8)
                    .collect()
            } else {
                let top = best(&qq[s]);
                let ties: Vec<usize> = (0..commands).filter(|&i| qq[s][i] == top).collect();
                let mut d = space.first();
                space
                    .write_command_at(ties[rng_q_plain.random_range(0..ties.len())] as u64, &mut d);
                d.symbols
            };
            assert_eq!(cq.symbols, plain_q, "Q-learning's command");
            let (o, next_state) = world.execute_from(&state, &c).unwrap();
            let last = k == 2;
            let r = if last { o.reward } else { 0.0 };
            rewarded += usize::from(r > 0.0);
            let next = (!last).then_some(o.effect);
            let a = space.index_of(&c) as usize;
            let y = r + next.map_or(0.0, |n| gamma * best(&qref[n]));
            qref[s][a] += params.alpha * (y - qref[s][a]);
            policy.learn(s, &c.symbols, o.effect, y);
            e3d.learn(s, &c, &Outcome { reward: r, ..o }, next);
            let aq = space.index_of(&cq) as usize;
            let (oq, _) = world.execute_from(&state, &cq).unwrap();
            let rq = if last { oq.reward } else { 0.0 };
            let yq = rq + next.map_or(0.0, |n| gamma * best(&qq[n]));
            qq[s][aq] += params.alpha * (yq - qq[s][aq]);
            ql.learn(s, &cq, &Outcome { reward: rq, ..oq }, next);
            state = next_state;
        }
    }
    assert!(rewarded > 0);
    // the reward reached (18)'s values through the Bellman target
    assert!(best(&qref[18]) > 0.0);
    assert!(same >= 9000 - 10, "{same} of 9000 commands equal");
    for s in 0..contexts {
        assert_eq!(e3d.reference(s), &qref[s][..], "Q_ref, context {s}");
        assert_eq!(ql.values(s), &qq[s][..], "Q, context {s}");
        for slot in 0..5 {
            for (a, b) in e3d
                .context_learner(s)
                .q(slot)
                .iter()
                .zip(&policy.q[s][slot])
            {
                assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{a} vs {b}");
            }
        }
    }
}

#[test]
fn closed_loop_e3d_with_one_command_is_contextual_e3d() {
    let scene = Scene::parse(TWO_ROOMS_CONTEXTS, "t.ron").unwrap();
    let space = scene.command_space();
    let shared = ContextTargets::Shared(Target::Uniform);
    let cfg = EpisodeConfig {
        episodes: 3000,
        commands: 1,
        seed: 2,
        use_reward: true,
        observe: Observe::StartContext,
    };
    let mut a = ClosedLoopE3d::new(&space, 18, 3, &Params::TASK2, &shared, 0.9).unwrap();
    let mut b = LearnerSetup::new(LearnerKind::E3d)
        .params(Params::TASK2)
        .targets(shared)
        .contexts(&space, 18, 3)
        .unwrap();
    let ra = run_episodes(
        &mut scene.build(),
        &mut a,
        &cfg,
        &e3d::session::Control::default(),
    )
    .unwrap();
    let rb = run_episodes(
        &mut scene.build(),
        &mut b,
        &cfg,
        &e3d::session::Control::default(),
    )
    .unwrap();
    assert_eq!(ra, rb);
    assert!(ra.cumulative_reward() > 0.0);
    // per-context targets of the wrong length are refused
    let two = ContextTargets::PerContext(vec![Target::Uniform; 2]);
    assert!(ClosedLoopE3d::new(&space, 18, 3, &Params::TASK2, &two, 0.9).is_err());
}

/// The four_rooms comparison (docs/reproducing.md, "Closed loop on
/// four_rooms") on 6 of its 20 seeds: closed-loop E3D keeps collecting the
/// reward it found; without Q_ref's bootstrap (gamma 0) it does not.
#[test]
fn closed_loop_e3d_exploits_where_contextual_e3d_cannot() {
    use e3d::experiment::closed_loop::{run_arm, ClosedLoopConfig};
    let scene = Scene::builtin("four_rooms").unwrap();
    let cfg = ClosedLoopConfig {
        params: Params {
            beta: 300.0,
            ..Params::TASK2
        },
        ..ClosedLoopConfig::default()
    };
    let cfg = ClosedLoopConfig {
        episodes: 20_000,
        ..cfg
    };
    let (mut closed, mut contextual) = (0.0, 0.0);
    for seed in 0..6 {
        let a = run_arm(&scene, "e3d_closed_loop", seed, &cfg).unwrap();
        let b = run_arm(&scene, "e3d_contextual", seed, &cfg).unwrap();
        // the same exploration until the first reward: the same episode
        assert_eq!(a.first_reward_episode, b.first_reward_episode);
        eprintln!("seed {seed}: {a:?} {b:?}");
        closed += a.late_reward;
        contextual += b.late_reward;
    }
    // measured: 3000 (three sessions at 1000 of 1000) against 18
    assert!(closed > 2500.0, "{closed}");
    assert!(contextual < 100.0, "{contextual}");
}

/// docs/reproducing.md, "Start contexts on two_rooms", on 4 of its 20
/// seeds: contextual E3D spreads each context's terminal cells, the
/// context-blind E3D does not (measured: 0.95-0.99 against 0.79-0.82).
#[test]
fn contextual_e3d_spreads_every_context_where_blind_e3d_cannot() {
    let scene = Scene::load("scenes/two_rooms_contexts.ron").unwrap();
    let space = scene.command_space();
    for seed in 0..4 {
        let h = crate::common::seen_and_blind_entropy(&space, 18, 2, seed, || scene.build());
        for s in 0..2 {
            assert!(h[0][s] > 0.93, "seed {seed}: {h:?}");
            assert!(h[1][s] < 0.84, "seed {seed}: {h:?}");
        }
    }
}

#[test]
fn states_outside_the_world_and_worlds_without_states_are_errors() {
    let scene = Scene::builtin("four_rooms").unwrap();
    let mut world = scene.build();
    let c = scene.command_space().first();
    let e = world.execute_from(&WorldState::Cell(36), &c).unwrap_err();
    assert_eq!(e.to_string(), "cell 36 is outside this 36-cell grid");
    assert!(world.bin_state(&WorldState::Cell(99)).is_err());
    assert!(world
        .execute_from(&WorldState::Cell(0), &Command::new(vec![0; 4]))
        .is_err());
    // a table has no states: it is no Episodic world (a compile error, where
    // run_episodes used to fail at run time)
    let cfg = EpisodeConfig {
        episodes: 3,
        commands: 2,
        seed: 0,
        use_reward: true,
        observe: Observe::StartContext,
    };
    let mut l = LearnerSetup::new(LearnerKind::Uniform)
        .contexts(&scene.command_space(), 36, 1)
        .unwrap();
    let zero = EpisodeConfig { commands: 0, ..cfg };
    assert!(run_episodes(
        &mut scene.build(),
        &mut l,
        &zero,
        &e3d::session::Control::default()
    )
    .is_err());
}

/// The reward per start context (the sweeps' `cumulative_reward_context_I`
/// and `first_reward_trial_context_I`): on TWO_ROOMS_CONTEXTS, whose reward
/// cell (2, 5) is context b's start and 7 moves from a's, uniform episodes
/// of 2 commands (6 moves) are rewarded from b and anywhere_b, never from
/// a; the sums and first episodes are those of a plain count over the
/// record, and add up to the session's.
#[test]
fn rewards_are_counted_per_start_context() {
    let scene = Scene::parse(TWO_ROOMS_CONTEXTS, "t.ron").unwrap();
    let mut world = scene.build();
    let cfg = EpisodeConfig {
        episodes: 600,
        commands: 2,
        seed: 4,
        use_reward: true,
        observe: Observe::StartContext,
    };
    let mut learner = LearnerSetup::new(LearnerKind::Uniform)
        .params(Params::TASK2)
        .contexts(&scene.command_space(), 18, 3)
        .unwrap();
    let rec = run_episodes(
        &mut *world,
        &mut learner,
        &cfg,
        &e3d::session::Control::default(),
    )
    .unwrap();
    let (mut sums, mut firsts) = (vec![0.0; 3], vec![None; 3]);
    for (i, &s) in rec.starts.iter().enumerate() {
        let r = rec.rewards[2 * i] + rec.rewards[2 * i + 1];
        sums[s] += r;
        if r > 0.0 && firsts[s].is_none() {
            firsts[s] = Some(i + 1);
        }
    }
    assert_eq!(rec.reward_per_start(3), sums);
    assert_eq!(rec.first_reward_per_start(3), firsts);
    assert!(
        firsts[0].is_none() && firsts[1].is_some() && firsts[2].is_some(),
        "{firsts:?}"
    );
    // from b (on the reward cell) more often than from anywhere in b's room
    assert!(
        sums[0] == 0.0 && sums[1] > sums[2] && sums[2] > 0.0,
        "{sums:?}"
    );
    assert_eq!(sums.iter().sum::<f64>(), rec.cumulative_reward());
    assert_eq!(
        firsts.iter().flatten().min().copied(),
        rec.first_reward_episode()
    );
}

/// Issue 46, item 2: per-move Q-learning with optimistic values
/// (`qlearning_moves`: 15 commands of one move, the current cell before
/// each, values from 1, epsilon 0) reaches four_rooms' reward cell, 13
/// moves from the start, in every session within 2000 episodes, where 15
/// uniform moves almost never end there and whole-command Q-learning from
/// 0 is such a walk until its first reward.
#[test]
fn optimistic_per_move_qlearning_reaches_what_a_uniform_walk_does_not() {
    use e3d::experiment::closed_loop::{run_arm, ClosedLoopConfig};
    let scene = Scene::builtin("four_rooms").unwrap();
    let cfg = ClosedLoopConfig {
        episodes: 2000,
        ..ClosedLoopConfig::default()
    };
    let (mut moves, mut uniform, mut whole) = (Vec::new(), 0, 0);
    for seed in 0..20 {
        let a = run_arm(&scene, "qlearning_moves", seed, &cfg).unwrap();
        moves.push(a.first_reward_episode);
        if a.first_reward_episode.is_some() {
            // once found, the greedy policy keeps collecting it
            assert!(a.late_reward > 900.0, "seed {seed}: {a:?}");
        }
        let u = run_arm(&scene, "uniform", seed, &cfg).unwrap();
        uniform += usize::from(u.first_reward_episode.is_some());
        let q = run_arm(&scene, "qlearning", seed, &cfg).unwrap();
        whole += usize::from(q.first_reward_episode.is_some());
    }
    let reached = moves.iter().flatten().count();
    assert_eq!(reached, 20, "{moves:?}");
    let mut firsts: Vec<usize> = moves.iter().flatten().copied().collect();
    firsts.sort();
    // a median near the issue's 295 (measured over 20 sessions of 20 000)
    assert!((100..=1000).contains(&firsts[9]), "{firsts:?}");
    // 15 uniform moves end on the reward cell about once in 10^5 episodes
    assert!(uniform <= 2, "{uniform}");
    assert!(whole <= 2, "{whole}");
}

/// The same seed gives the same session of per-move Q-learning; the
/// seeds give different ones.
#[test]
fn per_move_qlearning_is_deterministic_for_a_seed() {
    use e3d::experiment::closed_loop::{run_arm, ClosedLoopConfig};
    let scene = Scene::builtin("four_rooms").unwrap();
    let cfg = ClosedLoopConfig {
        episodes: 1500,
        ..ClosedLoopConfig::default()
    };
    let runs: Vec<_> = (0..4)
        .map(|seed| run_arm(&scene, "qlearning_moves", seed, &cfg).unwrap())
        .collect();
    for (seed, a) in runs.iter().enumerate() {
        let again = run_arm(&scene, "qlearning_moves", seed as u64, &cfg).unwrap();
        assert_eq!(*a, again);
    }
    let firsts: std::collections::BTreeSet<_> =
        runs.iter().map(|a| a.first_reward_episode).collect();
    assert!(firsts.len() > 1, "{runs:?}");
    // the records too, move by move, through the engine
    let single = with_slots(&scene, 1);
    let space = single.command_space();
    let config = EpisodeConfig {
        episodes: 300,
        commands: 15,
        seed: 7,
        use_reward: true,
        observe: Observe::State,
    };
    let params = Params {
        epsilon: 0.0,
        ..Params::TASK2
    };
    let record = || {
        let mut l = QLearning::optimistic(&space, 36, &params, 0.9, QLearning::OPTIMISTIC).unwrap();
        let rec = run_episodes(
            &mut single.build(),
            &mut l,
            &config,
            &e3d::Control::default(),
        )
        .unwrap();
        (rec, l.values(0).to_vec())
    };
    let (a, qa) = record();
    let (b, qb) = record();
    assert_eq!(a, b);
    assert_eq!(qa, qb);
    assert_eq!(a.effects.len(), 300 * 15);
    // the start cell's values moved down from 1: every move was tried
    assert!(qa.iter().all(|&q| q < 1.0), "{qa:?}");
}

/// Per-move Q-learning's parameters are checked, each refusal naming it.
#[test]
fn per_move_qlearning_refuses_bad_parameters_by_name() {
    let space = with_slots(&Scene::builtin("four_rooms").unwrap(), 1).command_space();
    let params = Params {
        epsilon: 0.0,
        ..Params::TASK2
    };
    let make = |p: &Params, gamma, initial| {
        QLearning::optimistic(&space, 36, p, gamma, initial)
            .err()
            .map(|e| e.to_string())
    };
    assert_eq!(make(&params, 0.9, 1.0), None);
    assert_eq!(make(&params, 0.9, -3.0), None);
    assert_eq!(
        make(&params, 0.9, f64::NAN).as_deref(),
        Some("initial = NaN: expected a finite number")
    );
    assert_eq!(
        make(&params, 0.9, f64::INFINITY).as_deref(),
        Some("initial = inf: expected a finite number")
    );
    assert_eq!(
        make(&params, 1.5, 1.0).as_deref(),
        Some("gamma = 1.5: expected a number in [0, 1]")
    );
    let bad = Params {
        alpha: 0.0,
        ..params
    };
    assert_eq!(
        make(&bad, 0.9, 1.0).as_deref(),
        Some("alpha = 0: expected a finite number > 0")
    );
    let bad = Params {
        epsilon: 1.5,
        ..params
    };
    assert_eq!(
        make(&bad, 0.9, 1.0).as_deref(),
        Some("epsilon = 1.5: expected a number in [0, 1]")
    );
    // whole-command Q-learning starts at 0, as before
    let q = QLearning::new(&space, 36, &params, 0.9).unwrap();
    assert_eq!(q.values(0), [0.0; 4]);
    // the comparison refuses, before any work, more moves than a session
    // of episodes may hold (every move of the arm is a command)
    use e3d::experiment::closed_loop::{run_comparison, ClosedLoopConfig};
    let cfg = ClosedLoopConfig {
        episodes: 7_000_000,
        ..ClosedLoopConfig::default()
    };
    let e = run_comparison(&Scene::builtin("four_rooms").unwrap(), &cfg)
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "arm qlearning_moves (one move a command): at most 100000000 commands in all per session (episodes x commands), found 7000000 episodes of 15 commands"
    );
}

/// Per-move Q-learning in a sweep of single commands (`e3d compare
/// --learners`, `e3d sweep`): each of its sessions runs episodes of the
/// scene's 7 moves one by one, observing the cell before each, on
/// `Scene::with_moves(1)` with the session's seed: the same episodes as
/// `run_episodes` with `LearnerSetup::new(QlearningMoves)`, exactly. On
/// two_rooms' far corner its optimistic values find the reward in every
/// session and then collect it in most trials, where uniform moves
/// almost never reach it.
#[test]
fn per_move_q_learning_runs_in_a_sweep_of_single_commands() {
    let sweep = e3d::sweep::Sweep::parse(
        r#"Sweep(name: "moves", scenes: ["two_rooms"], learners: [qlearning_moves, uniform],
            use_reward: [true], params: (epsilon: 0, initial: 1.0), sessions: 4, trials: 1500, seed: 3)"#,
        "moves.ron",
        None,
    )
    .unwrap();
    let results = sweep.run(2).unwrap();
    let cols = sweep.metric_columns();
    let col = |name: &str| cols.iter().position(|c| c == name).unwrap();
    let (reward, first) = (col("cumulative_reward_at_1500"), col("first_reward_trial"));
    let scene = Scene::builtin("two_rooms").unwrap();
    let single = scene.with_moves(1).unwrap().unwrap();
    let mut uniform = 0.0;
    for r in &results {
        let r_reward = r.values[reward].unwrap();
        if sweep.cells()[r.session.cell].learner == "uniform" {
            uniform += r_reward;
            continue;
        }
        let mut world = single.build();
        let params = Params {
            epsilon: 0.0,
            ..Params::TASK1
        };
        let cfg = EpisodeConfig {
            episodes: 1500,
            commands: 7,
            seed: r.session.seed,
            use_reward: true,
            observe: Observe::State,
        };
        let mut learner = LearnerSetup::new(LearnerKind::QlearningMoves)
            .params(params)
            .contexts(&single.command_space(), 18, cfg.num_contexts(&*world))
            .unwrap();
        let control = e3d::session::Control::default();
        let rec = run_episodes(&mut *world, &mut *learner, &cfg, &control).unwrap();
        let total: f64 = rec.episode_rewards().sum();
        assert_eq!(r_reward, total);
        assert_eq!(
            r.values[first],
            rec.first_reward_episode().map(|e| e as f64)
        );
        assert!(total > 1100.0, "{total}");
    }
    assert!(uniform < 20.0, "{uniform}");
    // a scene whose moves are not one alphabet's has no single move
    assert!(Scene::builtin("arm7").unwrap().with_moves(1).is_none());
}

/// `e3d closed-loop` on a physics scene of repeated slots on a sequential
/// schedule (puck_rooms): every arm runs on the same budget of impulses,
/// the open-loop arms with one command of K n slots; a physics scene of
/// other slots (arm7) is refused, naming what it takes.
#[test]
fn the_closed_loop_comparison_runs_on_a_sequential_physics_scene() {
    use e3d::experiment::closed_loop::{check_scene, run_arm, ClosedLoopConfig, ARMS};
    let puck = Scene::builtin("puck_rooms").unwrap();
    let cfg = ClosedLoopConfig {
        episodes: 5,
        seeds: 1,
        commands: 2,
        ..ClosedLoopConfig::default()
    };
    check_scene(&puck, 2).unwrap();
    for arm in ARMS {
        let s = run_arm(&puck, arm, 0, &cfg).unwrap_or_else(|e| panic!("{arm}: {e}"));
        assert!(
            s.cumulative_reward >= 0.0 && s.cumulative_reward <= 5.0,
            "{arm}: {s:?}"
        );
    }
    let e = check_scene(&Scene::builtin("arm7").unwrap(), 2)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("a Physics scene on a `Sequential` schedule"),
        "{e}"
    );
}
