//! The support of the uniform target `p*` (docs/algorithms.md, "E3D"):
//! every cell (`Target::Uniform`, the default) or the cells some command
//! reaches (`Target::UniformOn`). On the reached effects the two differ by
//! `log(|E| / |R|)` in `log p*`, so E3D's values differ by
//! `(1 - (1 - alpha lambda)^n) log(|E| / |R|) / (beta lambda)` after `n`
//! updates, `log(|E| / |R|) / (beta lambda)` in the limit.

use e3d::effect::TargetError;
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
    let mut on = E3d::new(&space, all, &p, &Target::UniformOn(reach.clone())).unwrap();
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
    let reachable = session(plain.target(Target::UniformOn(table.reachable())));
    // the default is Target::Uniform, trial for trial
    assert_eq!(default.effects, uniform.effects);
    // the support of p* changes what E3D explores
    assert_ne!(default.effects, reachable.effects);
}

#[test]
fn a_support_must_list_effects_in_range() {
    assert_eq!(
        Target::UniformOn(vec![]).log_probs(3),
        Err(TargetError::EmptySupport)
    );
    assert_eq!(
        Target::UniformOn(vec![0, 3]).probs(3),
        Err(TargetError::Support {
            effect: 3,
            effects: 3
        })
    );
    // listed twice counts once; outside the support, the floor
    let lp = Target::UniformOn(vec![2, 0, 2]).log_probs(3).unwrap();
    assert_eq!(lp[0], -(2f64).ln());
    assert_eq!(lp[1], e3d::effect::P_FLOOR.ln());
    // the whole support is the uniform target
    let every = Target::UniformOn((0..5).collect()).log_probs(5).unwrap();
    assert_eq!(every, Target::Uniform.log_probs(5).unwrap());
}
