//! Numeric edge cases of the learners: defined, finite, tested.

use e3d::command::CommandSpace;
use e3d::effect::{EffectModel, TargetError};
use e3d::learner::{E3d, LearnerError};
use e3d::{run_session, Command, Learner, Outcome, Params, Scene, SessionConfig, Target};

fn outcome(effect: usize, reward: f64) -> Outcome {
    Outcome {
        effect,
        reward,
        point: [0.0, 0.0],
    }
}

fn all_finite(l: &E3d, slots: usize) -> bool {
    (0..slots).all(|s| l.q(s).iter().all(|q| q.is_finite()))
        && (0..slots).all(|s| l.slot_policy(s).unwrap().iter().all(|p| p.is_finite()))
}

#[test]
fn eta_one_makes_p_the_last_effect_and_stays_finite() {
    let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
    let p = Params {
        eta: 1.0,
        ..Params::TASK1
    };
    let mut l = E3d::new(&space, 3, &p, &Target::Uniform).unwrap();
    l.learn(&Command::new(vec![0, 0]), &outcome(2, 0.0));
    assert_eq!(l.effect_model().probs(), vec![0.0, 0.0, 1.0]);
    // log p(e) = 0 > log(1/3): the symbols lose alpha/beta * log 3
    assert!((l.q(0)[0] + 0.3 * 3f64.ln()).abs() < 1e-12);
    assert!(all_finite(&l, 2));
}

#[test]
fn vanishing_probabilities_are_floored_not_infinite() {
    let mut m = EffectModel::new(3, 0.5).unwrap();
    for _ in 0..5000 {
        m.observe(0);
    }
    // 0.5^5000 underflows to 0; the log is taken at the floor
    assert_eq!(m.prob(1), 0.0);
    assert_eq!(m.log_prob(1), e3d::effect::P_FLOOR.ln());
    m.observe(1);
    assert!((m.prob(1) - 0.5).abs() < 1e-12 && (m.prob(0) - 0.5).abs() < 1e-12);
    let sum: f64 = m.probs().iter().sum();
    assert!((sum - 1.0).abs() < 1e-12);
}

#[test]
fn huge_beta_does_not_overflow_the_softmax() {
    let space = CommandSpace::repeat(2, &['a', 'b', 'c']).unwrap();
    let p = Params {
        beta: 1e300,
        ..Params::TASK1
    };
    let mut l = E3d::new(&space, 4, &p, &Target::Uniform).unwrap();
    for t in 0..100 {
        l.learn(&Command::new(vec![(t % 3) as u8, 1]), &outcome(t % 4, 1.0));
    }
    assert!(all_finite(&l, 2));
    let pol = l.slot_policy(1).unwrap();
    assert!((pol.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{pol:?}");
    // the greedy limit: one symbol takes everything
    assert!(pol.iter().any(|&p| p > 0.999));
}

#[test]
fn lambda_zero_ignores_the_reward() {
    let space = CommandSpace::repeat(1, &['a', 'b']).unwrap();
    let p = Params {
        lambda: 0.0,
        ..Params::TASK2
    };
    let mut with = E3d::new(&space, 2, &p, &Target::Uniform).unwrap();
    let mut without = E3d::new(&space, 2, &p, &Target::Uniform).unwrap();
    for t in 0..50 {
        let c = Command::new(vec![(t % 2) as u8]);
        with.learn(&c, &outcome(t % 2, 1.0));
        without.learn(&c, &outcome(t % 2, 0.0));
    }
    assert_eq!(with.q(0), without.q(0));
}

#[test]
fn effects_never_reached_keep_their_prior_and_the_session_runs() {
    // a learner told of 24 effects on two_rooms: effects 18..24 never happen
    let scene = Scene::builtin("two_rooms").unwrap();
    let mut world = scene.build();
    let mut l = E3d::new(&scene.command_space(), 24, &Params::TASK1, &Target::Uniform).unwrap();
    let cfg = SessionConfig {
        trials: 2000,
        seed: 3,
        use_reward: false,
    };
    let rec = run_session(&mut world, &mut l, &cfg).unwrap();
    assert_eq!(rec.metrics(&Target::Uniform).distinct_effects, 18);
    assert!(all_finite(&l, 7));
    // their p decays towards 0 but stays a probability
    let p = l.effect_model().probs();
    assert!(
        p[18..].iter().all(|&v| (0.0..1e-6).contains(&v)),
        "{:?}",
        &p[18..]
    );
    assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-9);
}

#[test]
fn a_target_with_zeros_steers_away_from_those_effects() {
    let scene = Scene::builtin("two_rooms").unwrap();
    let mut world = scene.build();
    // room B (columns 3..6) gets weight 0: explore room A only
    let w: Vec<f64> = (0..18).map(|e| if e % 6 < 3 { 1.0 } else { 0.0 }).collect();
    let target = Target::Weights(w);
    let mut l = E3d::new(&scene.command_space(), 18, &Params::TASK1, &target).unwrap();
    let cfg = SessionConfig {
        trials: 5000,
        seed: 2,
        use_reward: false,
    };
    let rec = run_session(&mut world, &mut l, &cfg).unwrap();
    assert!(all_finite(&l, 7));
    let in_b = rec.effects[1000..].iter().filter(|&&e| e % 6 >= 3).count();
    // the uniform policy ends in room B 4.3% of the time; this learner less
    assert!((in_b as f64) < 0.02 * 4000.0, "{in_b}");
    let m = rec.metrics(&target);
    assert!(m.kl_to_target.is_finite());
}

#[test]
fn bad_targets_are_refused() {
    let space = CommandSpace::repeat(1, &['a']).unwrap();
    for (w, msg) in [
        (
            vec![1.0],
            "the target has 1 weights, expected one per effect (2)",
        ),
        (
            vec![0.0, 0.0],
            "target weights must have a positive, finite sum",
        ),
        (
            vec![-1.0, 2.0],
            "target weights must be finite and >= 0, found -1",
        ),
        (
            vec![f64::NAN, 2.0],
            "target weights must be finite and >= 0, found NaN",
        ),
    ] {
        let e = E3d::new(&space, 2, &Params::TASK1, &Target::Weights(w.clone())).unwrap_err();
        assert_eq!(e.to_string(), msg);
        // typed: the target's own error, also from Target::probs
        let LearnerError::Target(t) = e else {
            panic!("{e:?}")
        };
        // (compared as text: a NaN weight is not equal to itself)
        assert_eq!(
            Target::Weights(w).probs(2).unwrap_err().to_string(),
            t.to_string()
        );
    }
    assert_eq!(Target::Uniform.probs(0), Err(TargetError::NoEffects));
    assert_eq!(
        Target::Weights(vec![1.0]).probs(2),
        Err(TargetError::Length {
            weights: 1,
            effects: 2
        })
    );
}
