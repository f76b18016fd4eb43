//! The optimised E3D (cached softmax weights, O(1) histogram, branch-free
//! sampling) against a straightforward transcription of the paper's
//! Algorithm 1.

use e3d::learner::E3d;
use e3d::{Command, Learner, OutcomeTable, Params, Scene, SessionRng, Target};
use rand::{RngExt, SeedableRng};

/// Algorithm 1 as written: full softmax each trial, plain histogram update.
struct Plain {
    q: Vec<Vec<f64>>,
    p: Vec<f64>,
    params: Params,
}

impl Plain {
    fn policy(&self, slot: usize) -> Vec<f64> {
        let q = &self.q[slot];
        let top = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let w: Vec<f64> = q
            .iter()
            .map(|v| (self.params.beta * (v - top)).exp())
            .collect();
        let z: f64 = w.iter().sum();
        w.iter().map(|v| v / z).collect()
    }

    fn propose(&self, rng: &mut SessionRng) -> Command {
        let symbols = (0..self.q.len())
            .map(|slot| {
                let pol = self.policy(slot);
                let u: f64 = rng.random();
                let mut acc = 0.0;
                for (k, p) in pol.iter().enumerate() {
                    acc += p;
                    if u < acc {
                        return k as u8;
                    }
                }
                (pol.len() - 1) as u8
            })
            .collect();
        Command::new(symbols)
    }

    fn learn(&mut self, c: &Command, e: usize, r: f64) {
        let Params {
            alpha,
            beta,
            lambda,
            eta,
            ..
        } = self.params;
        for (i, v) in self.p.iter_mut().enumerate() {
            *v = (1.0 - eta) * *v + if i == e { eta } else { 0.0 };
        }
        let n = self.p.len() as f64;
        for (slot, &a) in c.symbols.iter().enumerate() {
            let q = &mut self.q[slot][a as usize];
            *q = (1.0 - alpha * lambda) * *q + alpha * lambda * r
                - alpha / beta * (self.p[e].ln() - (1.0 / n).ln());
        }
    }
}

#[test]
fn optimised_e3d_follows_the_plain_algorithm() {
    let scene = Scene::builtin("two_rooms").unwrap();
    let table = OutcomeTable::build(&mut scene.build()).unwrap();
    let space = scene.command_space();
    for params in [Params::TASK1, Params::TASK2] {
        let mut fast = E3d::new(&space, 18, &params, &Target::Uniform).unwrap();
        let mut plain = Plain {
            q: vec![vec![0.0; 4]; 7],
            p: vec![1.0 / 18.0; 18],
            params,
        };
        let (mut rng_a, mut rng_b) = (SessionRng::seed_from_u64(9), SessionRng::seed_from_u64(9));
        let mut c = space.first();
        let mut same = 0;
        for _ in 0..5000 {
            fast.propose(&mut rng_a, &mut c);
            let c_plain = plain.propose(&mut rng_b);
            same += usize::from(c == c_plain);
            // both learn from the plain learner's command, so that one
            // rounding-level difference in a draw does not fork the runs
            let o = *table.lookup(&c_plain).unwrap();
            fast.learn(&c_plain, &o);
            plain.learn(&c_plain, o.effect, o.reward);
        }
        assert!(same >= 4990, "{same} of 5000 commands equal");
        for slot in 0..7 {
            for (a, b) in fast.q(slot).iter().zip(&plain.q[slot]) {
                assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "Q {a} vs {b}");
            }
            for (a, b) in fast
                .slot_policy(slot)
                .unwrap()
                .iter()
                .zip(plain.policy(slot))
            {
                assert!((a - b).abs() < 1e-9, "policy {a} vs {b}");
            }
        }
        for (e, want) in plain.p.iter().enumerate() {
            assert!((fast.effect_model().prob(e) - want).abs() < 1e-12);
        }
    }
}
