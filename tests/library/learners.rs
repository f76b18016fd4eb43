//! The learners against hand-computed updates, and their ranges.

use e3d::command::CommandSpace;
use e3d::learner::LearnerSetup;
use e3d::learner::{E3d, EpsilonGreedy, LearnerError};
use e3d::{Command, Learner, LearnerKind, Outcome, Params, SessionRng, Target};
use rand::SeedableRng;

fn outcome(effect: usize, reward: f64) -> Outcome {
    Outcome {
        effect,
        reward,
        point: [0.0, 0.0],
    }
}

#[test]
fn e3d_updates_p_first_then_q_with_the_fresh_p() {
    let space = CommandSpace::repeat(2, &['a', 'b', 'c']).unwrap();
    let params = Params {
        alpha: 0.3,
        beta: 2.0,
        lambda: 0.5,
        eta: 0.1,
        epsilon: 0.0,
        ..Params::TASK1
    };
    let mut l = E3d::new(&space, 4, &params, &Target::Uniform).unwrap();

    // trial 1: command (a, c), effect 1, reward 1
    l.learn(&Command::new(vec![0, 2]), &outcome(1, 1.0));
    // p = 0.9 * 0.25 + 0.1 = 0.325 for effect 1
    let p1 = 0.325f64;
    let q1 = 0.3 * 0.5 * 1.0 - (0.3 / 2.0) * (p1.ln() - 0.25f64.ln());
    assert!((l.effect_model().prob(1) - p1).abs() < 1e-12);
    assert!((l.q(0)[0] - q1).abs() < 1e-12, "{} vs {q1}", l.q(0)[0]);
    assert!((l.q(1)[2] - q1).abs() < 1e-12);
    assert_eq!(l.q(0)[1], 0.0);
    assert_eq!(l.q(1)[0], 0.0);

    // trial 2: command (a, b), effect 3, no reward
    l.learn(&Command::new(vec![0, 1]), &outcome(3, 0.0));
    let p3 = 0.9 * (0.9 * 0.25) + 0.1;
    let drive = -(0.3 / 2.0) * (f64::ln(p3) - 0.25f64.ln());
    let q_a = (1.0 - 0.3 * 0.5) * q1 + drive;
    assert!((l.q(0)[0] - q_a).abs() < 1e-12);
    assert!((l.q(1)[1] - drive).abs() < 1e-12);
    assert!(
        (l.q(1)[2] - q1).abs() < 1e-12,
        "untouched entries keep their value"
    );

    // the policy is the softmax of beta * Q
    let pol = l.slot_policy(0).unwrap();
    let z: f64 = l.q(0).iter().map(|q| (2.0 * q).exp()).sum();
    for (k, p) in pol.iter().enumerate() {
        assert!((p - (2.0 * l.q(0)[k]).exp() / z).abs() < 1e-12);
    }

    // p stays a distribution
    let sum: f64 = l.effect_model().probs().iter().sum();
    assert!((sum - 1.0).abs() < 1e-12);
    let expected = [0.9 * 0.225, 0.9 * p1, 0.9 * 0.225, p3];
    for (e, want) in expected.iter().enumerate() {
        assert!((l.effect_model().prob(e) - want).abs() < 1e-12);
    }
}

#[test]
fn e3d_with_a_target_prefers_effects_the_target_wants() {
    let space = CommandSpace::repeat(1, &['a', 'b']).unwrap();
    let target = Target::Weights(vec![0.9, 0.1]);
    let mut l = E3d::new(&space, 2, &Params::TASK1, &target).unwrap();
    // the same count of each effect: 0 is under its target, 1 over it
    for _ in 0..50 {
        l.learn(&Command::new(vec![0]), &outcome(0, 0.0));
        l.learn(&Command::new(vec![1]), &outcome(1, 0.0));
    }
    let pol = l.slot_policy(0).unwrap();
    assert!(pol[0] > 0.6, "{pol:?}");
}

#[test]
fn egreedy_moves_q_towards_the_reward_and_breaks_ties_at_random() {
    let space = CommandSpace::repeat(3, &['E', 'S', 'W', 'N']).unwrap();
    let params = Params {
        epsilon: 0.0,
        ..Params::TASK2
    };
    let mut l = EpsilonGreedy::new(&space, &params);
    // all Q equal: greedy choices are spread over all symbols
    let mut rng = SessionRng::seed_from_u64(1);
    let mut c = space.first();
    let mut seen = [0usize; 4];
    for _ in 0..400 {
        l.propose(&mut rng, &mut c);
        seen[c.symbols[0] as usize] += 1;
    }
    assert!(seen.iter().all(|&k| k > 60), "{seen:?}");
    // one reward: Q[a] = alpha * r, and the greedy choice follows it
    l.learn(&Command::new(vec![1, 2, 3]), &outcome(0, 1.0));
    assert!((l.q(0)[1] - 0.3).abs() < 1e-15);
    assert!((l.q(2)[3] - 0.3).abs() < 1e-15);
    for _ in 0..20 {
        l.propose(&mut rng, &mut c);
        assert_eq!(c.symbols, vec![1, 2, 3]);
    }
    l.learn(&Command::new(vec![1, 2, 3]), &outcome(0, 0.0));
    assert!((l.q(0)[1] - 0.7 * 0.3).abs() < 1e-15);
    let pol = EpsilonGreedy::new(&space, &Params::TASK2)
        .slot_policy(0)
        .unwrap();
    assert!(pol.iter().all(|p| (p - 0.25).abs() < 1e-15));
}

#[test]
fn parameters_out_of_range_are_refused_with_the_range() {
    let bad = [
        (
            Params {
                alpha: 0.0,
                ..Params::TASK1
            },
            "alpha = 0: expected a finite number > 0",
        ),
        (
            Params {
                beta: -1.0,
                ..Params::TASK1
            },
            "beta = -1: expected a finite number > 0",
        ),
        (
            Params {
                lambda: -0.1,
                ..Params::TASK1
            },
            "lambda = -0.1: expected a finite number >= 0",
        ),
        (
            Params {
                eta: 0.0,
                ..Params::TASK1
            },
            "eta = 0: expected a number in (0, 1]",
        ),
        (
            Params {
                eta: 1.5,
                ..Params::TASK1
            },
            "eta = 1.5: expected a number in (0, 1]",
        ),
        (
            Params {
                epsilon: 1.01,
                ..Params::TASK1
            },
            "epsilon = 1.01: expected a number in [0, 1]",
        ),
        (
            Params {
                alpha: f64::NAN,
                ..Params::TASK1
            },
            "alpha = NaN: expected a finite number > 0",
        ),
    ];
    let space = CommandSpace::repeat(1, &['a']).unwrap();
    for (p, msg) in bad {
        assert_eq!(p.validate().unwrap_err().to_string(), msg);
        let err = LearnerSetup::new(LearnerKind::E3d)
            .params(p)
            .symbols(&space, 2)
            .err()
            .unwrap();
        assert_eq!(err.to_string(), msg);
        // typed: the parameter's own error (a NaN is not equal to itself)
        let LearnerError::Params(e) = err else {
            panic!("{err:?}")
        };
        assert_eq!(e.name, p.validate().unwrap_err().name);
    }
    assert!(Params {
        eta: 1.0,
        lambda: 0.0,
        epsilon: 0.0,
        ..Params::TASK1
    }
    .validate()
    .is_ok());
}
