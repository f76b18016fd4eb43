//! The exploitation threshold of E3D (docs/algorithms.md, "E3D"): a
//! command whose effect `e` the policy has settled on (`p(e) = 1`) gains
//! value only if `beta lambda r > log(1 / p*(e))`, `log 36 ≈ 3.58` on
//! four_rooms' 36 cells; in a closed loop, the command `j` commands
//! before an episode's last learns towards at most `gamma^j r`, so its
//! condition is `beta lambda gamma^j r > log 36`. Computed by e3d's own
//! learners.

use e3d::command::CommandSpace;
use e3d::learner::{ClosedLoopE3d, ContextTargets, ContextualLearner, E3d};
use e3d::{Command, Learner, Outcome, Params, Target};

/// four_rooms' cells, the support of its uniform target.
const CELLS: usize = 36;

fn outcome(effect: usize, reward: f64) -> Outcome {
    Outcome {
        effect,
        reward,
        point: [0.0, 0.0],
    }
}

/// The paper's task 2 with `beta` and `eta = 1`: the histogram is the
/// one-hot of the last effect, `log p(e) = 0`, as for a policy settled on
/// `e`.
fn settled(beta: f64, alpha: f64) -> Params {
    Params {
        beta,
        alpha,
        eta: 1.0,
        ..Params::TASK2
    }
}

#[test]
fn the_value_of_a_settled_rewarded_command_changes_sign_at_log_36() {
    let lambda = Params::TASK2.lambda;
    let threshold = (CELLS as f64).ln() / lambda; // beta = 119.45 at lambda 0.03
    assert!((CELLS as f64).ln() > 3.58 && (CELLS as f64).ln() < 3.59);
    let space = CommandSpace::repeat(5, &['E', 'S', 'W', 'N']).unwrap();
    let cmd = Command::new(vec![0; 5]);
    for (beta, positive) in [
        (threshold * 0.99, false),
        (threshold * 1.01, true),
        (100.0, false), // beta lambda = 3 < log 36: the paper's beta
        (300.0, true),
    ] {
        let p = settled(beta, Params::TASK2.alpha);
        let mut l = E3d::new(&space, CELLS, &p, &Target::Uniform).unwrap();
        l.learn(&cmd, &outcome(7, 1.0));
        let q = l.q(0)[0];
        // from Q = 0: alpha lambda r - (alpha/beta) log(1/p*) = (alpha/beta)(beta lambda r - log 36)
        let expected = p.alpha / beta * (beta * lambda - (CELLS as f64).ln());
        assert!(
            (q - expected).abs() < 1e-12,
            "beta {beta}: {q} against {expected}"
        );
        assert_eq!(q > 0.0, positive, "beta {beta}: {q}");
        // every slot of the command alike; the symbols not chosen stay at 0
        assert!((0..5).all(|s| l.q(s)[0] == q && l.q(s)[1..].iter().all(|&v| v == 0.0)));
    }
}

/// A closed loop of 3 commands repeated `episodes` times: from context 0
/// to 1, 1 to 2, 2 to cell 3 where the reward 1 is; `alpha = 1`, so
/// `Q_ref` is the Bellman target itself and reaches `gamma^j` within 3
/// episodes. Returns `Q(s)[a_0, 0]` of each context `s = 0, 1, 2`.
fn closed_loop_values(beta: f64, gamma: f64, episodes: usize) -> [f64; 3] {
    let space = CommandSpace::repeat(5, &['E', 'S', 'W', 'N']).unwrap();
    let params = settled(beta, 1.0);
    let targets = ContextTargets::Shared(Target::Uniform);
    let mut l = ClosedLoopE3d::new(&space, CELLS, CELLS, &params, &targets, gamma).unwrap();
    let cmd = Command::new(vec![0; 5]);
    for _ in 0..episodes {
        l.learn(0, &cmd, &outcome(1, 0.0), Some(1));
        l.learn(1, &cmd, &outcome(2, 0.0), Some(2));
        l.learn(2, &cmd, &outcome(3, 1.0), None);
    }
    [0, 1, 2].map(|s| l.context_learner(s).q(0)[0])
}

#[test]
fn in_a_closed_loop_the_command_j_before_the_last_needs_beta_lambda_gamma_j_above_log_36() {
    let (lambda, gamma) = (Params::TASK2.lambda, 0.9);
    let log36 = (CELLS as f64).ln();
    // the fixed point of Q <- (1 - lambda) Q + lambda y - (1/beta) log 36 (alpha = 1):
    // Q = y - log 36 / (beta lambda), y = gamma^j for the command j before the last
    for beta in [100.0, 150.0, 300.0] {
        let q = closed_loop_values(beta, gamma, 3000);
        for (s, j) in [(0, 2), (1, 1), (2, 0)] {
            let y = gamma.powi(j);
            let fixed = y - log36 / (beta * lambda);
            assert!(
                (q[s] - fixed).abs() < 1e-9,
                "beta {beta}, j {j}: {} against {fixed}",
                q[s]
            );
            assert_eq!(q[s] > 0.0, beta * lambda * y > log36, "beta {beta}, j {j}");
        }
    }
    // straddle each command's threshold log 36 / (lambda gamma^j)
    for j in 0..3 {
        let threshold = log36 / (lambda * gamma.powi(j));
        let below = closed_loop_values(threshold * 0.99, gamma, 3000);
        let above = closed_loop_values(threshold * 1.01, gamma, 3000);
        let s = 2 - j as usize;
        assert!(
            below[s] < 0.0 && above[s] > 0.0,
            "j {j}: {below:?} {above:?}"
        );
    }
    // beta 150: beta lambda gamma^j = 4.5, 4.05, 3.645, all above 3.58: every command gains
    let q = closed_loop_values(150.0, gamma, 3000);
    assert!(q.iter().all(|&v| v > 0.0), "{q:?}");
    // beta 140: 4.2 and 3.78 are above 3.58, 3.40 is not: the first command loses
    let q = closed_loop_values(140.0, gamma, 3000);
    assert!(q[0] < 0.0 && q[1] > 0.0 && q[2] > 0.0, "{q:?}");
}
