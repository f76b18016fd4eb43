//! The support of the uniform target `p*` (docs/algorithms.md, "E3D"):
//! every cell (`Target::Uniform`, the default) or the cells some command
//! reaches (`OutcomeTable::reachable_target`). On the reached effects the two differ by
//! `log(|E| / |R|)` in `log p*`, so E3D's values differ by
//! `(1 - (1 - alpha lambda)^n) log(|E| / |R|) / (beta lambda)` after `n`
//! updates, `log(|E| / |R|) / (beta lambda)` in the limit.

use e3d::learner::{E3d, LearnerSetup};
use e3d::{run_session, Learner, LearnerKind, OutcomeTable, Params, Scene, SessionConfig, Target};

#[test]
fn the_reachable_support_shifts_e3ds_values_by_log_e_over_r() {
    // four_rooms: 36 cells, 13 of them reached by its 1024 commands of 5 moves
    let scene = Scene::builtin("four_rooms").unwrap();
    let table = OutcomeTable::build(&mut *scene.build()).unwrap();
    let (all, reach) = (scene.num_effects(), table.reachable());
    assert_eq!((all, reach.len()), (36, 13));
    assert_eq!(reach.len(), table.reachable_effects());
    let space = scene.command_space();
    let p = Params::TASK2;
    let mut uniform = E3d::new(&space, all, &p, &Target::Uniform).unwrap();
    let mut on = E3d::new(&space, all, &p, &table.reachable_target()).unwrap();
    // the same commands and outcomes to both (the histograms p stay equal);
    // how often each slot chose each symbol
    let mut n = vec![[0i32; 4]; space.num_slots()];
    for t in 0..3000u64 {
        let cmd = space.command_at((t * 7919 + t * t) % 1024);
        let o = table.lookup(&cmd).unwrap();
        assert!(reach.contains(&o.effect));
        uniform.learn(&cmd, o);
        on.learn(&cmd, o);
        for (slot, &a) in cmd.symbols.iter().enumerate() {
            n[slot][a as usize] += 1;
        }
    }
    assert_eq!(uniform.effect_model(), on.effect_model());
    let shift = (all as f64 / reach.len() as f64).ln() / (p.beta * p.lambda);
    assert!((shift - 0.3395).abs() < 1e-4, "{shift}"); // log(36/13) / 3
    for (slot, counts) in n.iter().enumerate() {
        for (a, &k) in counts.iter().enumerate() {
            let expected = (1.0 - (1.0 - p.alpha * p.lambda).powi(k)) * shift;
            let d = on.q(slot)[a] - uniform.q(slot)[a];
            assert!(
                (d - expected).abs() < 1e-9,
                "slot {slot} symbol {a}: {d} against {expected}"
            );
        }
    }
    // the most chosen symbols are within 1% of the limit
    assert!(n.iter().flatten().any(|&k| k > 600));
    let most = n[0].iter().enumerate().max_by_key(|(_, &k)| k).unwrap().0;
    assert!((on.q(0)[most] - uniform.q(0)[most] - shift).abs() < 0.01 * shift);
}

#[test]
fn the_support_changes_a_session_and_uniform_stays_the_default() {
    let scene = Scene::builtin("four_rooms").unwrap();
    let table = OutcomeTable::build(&mut *scene.build()).unwrap();
    let space = scene.command_space();
    let cfg = SessionConfig {
        trials: 2000,
        seed: 3,
        use_reward: false,
    };
    let session = |setup: LearnerSetup| {
        let mut l = setup.symbols(&space, scene.num_effects()).unwrap();
        run_session(&mut table.clone(), &mut l, &cfg).unwrap()
    };
    let plain = LearnerSetup::new(LearnerKind::E3d).params(Params::TASK1);
    let default = session(plain.clone());
    let uniform = session(plain.clone().target(Target::Uniform));
    let reachable = session(plain.target(table.reachable_target()));
    // the default is Target::Uniform, trial for trial
    assert_eq!(default.effects, uniform.effects);
    // the support of p* changes what E3D explores
    assert_ne!(default.effects, reachable.effects);
}

#[test]
fn the_reachable_target_is_uniform_on_the_reached_cells_and_floored_elsewhere() {
    let scene = Scene::builtin("four_rooms").unwrap();
    let table = OutcomeTable::build(&mut *scene.build()).unwrap();
    let reach = table.reachable();
    let lp = table.reachable_target().log_probs(36).unwrap();
    for (e, &v) in lp.iter().enumerate() {
        if reach.contains(&e) {
            assert!((v + 13f64.ln()).abs() < 1e-12, "cell {e}: {v}");
        } else {
            assert_eq!(v, e3d::effect::P_FLOOR.ln(), "cell {e}");
        }
    }
    // every cell reached: the same logs as the default, to rounding
    let two = Scene::builtin("two_rooms").unwrap();
    let t2 = OutcomeTable::build(&mut *two.build()).unwrap();
    assert_eq!(t2.reachable_effects(), 18);
    let (a, b) = (
        t2.reachable_target().log_probs(18).unwrap(),
        Target::Uniform.log_probs(18).unwrap(),
    );
    assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12));
}
