//! One behaviour everywhere: every kind of world refuses a command that
//! does not fit its space with the same `WorldError::BadCommand`, sessions
//! keep what an outcome holds (effect as `usize`, reward, terminal point),
//! and the metrics know the entropy over the reachable cells when a table
//! gives them.

use e3d::learner::LearnerSetup;
use e3d::session::{run_session_into, RunningMetrics};
use e3d::world::{check_command, ExecOptions, Executor, Strategy, Workload};
use e3d::world::{Memoized, OutcomeMemo};
use e3d::{
    run_session, Command, LearnerKind, OutcomeTable, Scene, SessionConfig, Target, World,
    WorldError,
};

/// A command with a symbol outside slot 1's alphabet, one slot too many,
/// and one too few, for a space of `n` slots.
fn bad_commands(n: usize) -> Vec<Command> {
    let mut out_of_alphabet = vec![0u8; n];
    out_of_alphabet[1] = 200;
    vec![
        Command::new(out_of_alphabet),
        Command::new(vec![0; n + 1]),
        Command::new(vec![0; n - 1]),
    ]
}

/// The error texts `world` gives for the bad commands (each must be a
/// `BadCommand`).
fn refusals(world: &mut dyn World) -> Vec<String> {
    let n = world.command_space().num_slots();
    bad_commands(n)
        .iter()
        .map(|c| match world.execute(c) {
            Err(e @ WorldError::BadCommand { .. }) => e.to_string(),
            other => panic!("{c}: expected BadCommand, got {other:?}"),
        })
        .collect()
}

#[test]
fn every_world_refuses_a_bad_command_with_the_same_error() {
    for name in ["two_rooms", "puck_rooms"] {
        let scene = Scene::builtin(name).unwrap();
        let space = scene.command_space();
        let expected: Vec<String> = bad_commands(space.num_slots())
            .iter()
            .map(|c| check_command(&space, c).unwrap_err().to_string())
            .collect();
        assert_eq!(
            expected[0],
            format!(
                "command {} does not fit this world: slot 1 has no symbol 200",
                bad_commands(space.num_slots())[0]
            )
        );
        assert!(expected[1].ends_with(&format!("expected {} slots", space.num_slots())));

        // the scene's own world (grid or Rapier)
        assert_eq!(
            refusals(&mut *scene.build()),
            expected,
            "{name}: built world"
        );
        // a table, owned and shared, and its look-up
        let table = OutcomeTable::build(&mut *scene.build()).unwrap();
        for c in bad_commands(space.num_slots()) {
            assert!(matches!(
                table.lookup(&c),
                Err(WorldError::BadCommand { .. })
            ));
        }
        assert_eq!(refusals(&mut &table), expected, "{name}: &OutcomeTable");
        let mut owned = table.clone();
        assert_eq!(refusals(&mut owned), expected, "{name}: OutcomeTable");
        // a memoised world
        let memo = OutcomeMemo::new(&space, scene.num_effects(), 1000).unwrap();
        assert_eq!(
            refusals(&mut Memoized::new(scene.build(), &memo)),
            expected,
            "{name}: Memoized"
        );
        assert_eq!(memo.len(), 0, "nothing bad is memoised");
        // every strategy of an executor
        for force in [Strategy::Table, Strategy::Memo, Strategy::Live] {
            let work = Workload {
                trials: 100,
                sessions: 1,
                threads: 1,
            };
            let options = ExecOptions {
                force: Some(force),
                ..ExecOptions::default()
            };
            let exec = Executor::new(&scene, &work, &options).unwrap();
            assert_eq!(refusals(&mut *exec.world(1)), expected, "{name}: {force}");
        }
    }
}

#[test]
fn a_session_record_keeps_every_outcome_as_the_world_gave_it() {
    let scene = Scene::builtin("two_rooms").unwrap();
    let space = scene.command_space();
    let mut learner = LearnerSetup::new(LearnerKind::E3d)
        .symbols(&space, scene.num_effects())
        .unwrap();
    let cfg = SessionConfig {
        trials: 5000,
        seed: 5,
        use_reward: true,
    };
    let rec = run_session(&mut *scene.build(), &mut *learner, &cfg).unwrap();
    assert_eq!(rec.points.len(), 5000);
    let mut world = scene.build();
    let mut rewarded = 0;
    for t in 0..rec.trials() {
        let o = world.execute(&rec.command(t)).unwrap();
        assert_eq!(rec.effects[t], o.effect, "trial {t}");
        assert_eq!(rec.points[t], o.point, "trial {t}");
        assert_eq!(rec.rewards[t], o.reward, "trial {t}");
        rewarded += (o.reward > 0.0) as usize;
    }
    // two_rooms' reward cell is reached in 5000 trials of seed 5
    assert!(rewarded > 0);
}

#[test]
fn metrics_hold_the_entropy_over_the_reachable_cells_when_a_table_knows_them() {
    // arm7: 225 cells, 68 of them reachable (the README's figure)
    let scene = Scene::builtin("arm7").unwrap();
    let exec = Executor::new(
        &scene,
        &Workload {
            trials: 5000,
            sessions: 1,
            threads: 2,
        },
        &ExecOptions {
            force: Some(Strategy::Table),
            ..ExecOptions::default()
        },
    )
    .unwrap();
    let table = exec.table().unwrap();
    assert_eq!(table.reachable_effects(), 68);
    let make = || {
        LearnerSetup::new(LearnerKind::E3d)
            .symbols(&scene.command_space(), scene.num_effects())
            .unwrap()
    };
    let cfg = SessionConfig {
        trials: 5000,
        seed: 0,
        use_reward: false,
    };
    let rec = run_session(&mut &*table, &mut *make(), &cfg).unwrap();
    let m = rec.metrics_over_reachable(&Target::Uniform, 68);
    assert_eq!(m.reachable_effects, Some(68));
    let over = m.normalized_entropy_reachable.unwrap();
    // the same counts, normalised by log 68 instead of log 225
    let ratio = (225f64).ln() / (68f64).ln();
    assert!((over - m.normalized_entropy * ratio).abs() < 1e-12);
    // `e3d run arm7` prints 0.9306 over 68 beside 0.7250 over 225
    assert!((over - 0.9306).abs() < 5e-5, "{over}");
    assert!(
        (m.normalized_entropy - 0.7250).abs() < 5e-5,
        "{}",
        m.normalized_entropy
    );
    // everything else as without the reachable cells
    let plain = rec.metrics(&Target::Uniform);
    assert_eq!(plain.reachable_effects, None);
    assert_eq!(plain.normalized_entropy_reachable, None);
    assert_eq!(plain.normalized_entropy, m.normalized_entropy);
    // in constant memory, bit for bit
    let mut running = RunningMetrics::new(scene.num_effects());
    run_session_into(
        &mut &*table,
        &mut *make(),
        &cfg,
        &mut running,
        &e3d::Control::default(),
    )
    .unwrap();
    assert_eq!(running.metrics_over_reachable(&Target::Uniform, 68), m);
}
