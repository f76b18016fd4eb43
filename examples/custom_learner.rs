//! Your own learner: a count-based explorer (intrinsic reward
//! `1 / sqrt(N(e))`, softmax policy per slot), compared with E3D on
//! two_rooms.
//!
//! ```sh
//! cargo run --release --example custom_learner
//! ```

use e3d::command::CommandSpace;
use e3d::learner::LearnerSetup;
use e3d::rand::RngExt;
use e3d::{
    run_session, Command, Learner, LearnerKind, Outcome, Scene, SessionConfig, SessionRng, Target,
}; // the rand e3d uses, re-exported: no version to pin

/// Count-based exploration: `Q[a_i, i] += alpha (1/sqrt(N(e)) - Q[a_i, i])`.
struct CountBonus {
    q: Vec<Vec<f64>>,
    counts: Vec<f64>,
    alpha: f64,
    beta: f64,
}

impl CountBonus {
    fn new(space: &CommandSpace, num_effects: usize) -> Self {
        CountBonus {
            q: space.sizes().map(|k| vec![1.0; k]).collect(),
            counts: vec![0.0; num_effects],
            alpha: 0.3,
            beta: 40.0,
        }
    }
}

impl Learner for CountBonus {
    fn name(&self) -> &str {
        "count-bonus"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        command.symbols.resize(self.q.len(), 0);
        for (slot, q) in self.q.iter().enumerate() {
            let pol = self.slot_policy(slot).unwrap();
            let mut u: f64 = rng.random();
            let mut pick = q.len() - 1;
            for (k, p) in pol.iter().enumerate() {
                if u < *p {
                    pick = k;
                    break;
                }
                u -= p;
            }
            command.symbols[slot] = pick as u8;
        }
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        self.counts[outcome.effect] += 1.0;
        let bonus = 1.0 / self.counts[outcome.effect].sqrt();
        for (slot, &a) in command.symbols.iter().enumerate() {
            let q = &mut self.q[slot][a as usize];
            *q += self.alpha * (bonus - *q);
        }
    }

    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        let q = &self.q[slot];
        let top = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let w: Vec<f64> = q.iter().map(|v| (self.beta * (v - top)).exp()).collect();
        let z: f64 = w.iter().sum();
        Some(w.into_iter().map(|v| v / z).collect())
    }
}

/// Mean normalised entropy over 5 sessions of 5000 trials: (count bonus, E3D, uniform).
fn compare() -> (f64, f64, f64) {
    let scene = Scene::builtin("two_rooms").unwrap();
    let mut world = scene.build();
    let space = scene.command_space();
    let mut mean = |make: &dyn Fn() -> Box<dyn Learner>| {
        (0..5)
            .map(|seed| {
                let mut l = make();
                let cfg = SessionConfig {
                    trials: 5000,
                    seed,
                    use_reward: false,
                };
                run_session(&mut world, &mut l, &cfg)
                    .unwrap()
                    .metrics(&Target::Uniform)
                    .normalized_entropy
            })
            .sum::<f64>()
            / 5.0
    };
    let kind = |k: LearnerKind| {
        let space = space.clone();
        move || -> Box<dyn Learner> { LearnerSetup::new(k).symbols(&space, 18).unwrap() }
    };
    let count = mean(&|| Box::new(CountBonus::new(&space, 18)));
    let e3d = mean(&kind(LearnerKind::E3d));
    let uniform = mean(&kind(LearnerKind::Uniform));
    (count, e3d, uniform)
}

fn main() {
    let (count, e3d, uniform) = compare();
    println!("normalised entropy over 5 sessions x 5000 trials on two_rooms:");
    println!("  count bonus {count:.3}\n  E3D         {e3d:.3}\n  uniform     {uniform:.3}");
}

#[test]
fn both_explorers_beat_the_uniform_policy() {
    let (count, e3d, uniform) = compare();
    assert!(
        count > uniform + 0.05 && e3d > uniform + 0.1,
        "{count} {e3d} {uniform}"
    );
}
