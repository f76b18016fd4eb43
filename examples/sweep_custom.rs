//! A sweep of your own world and your own learner: a closed-form two-link
//! arm and a count-bonus explorer, swept over its inverse temperature beta
//! beside the built-in uniform policy, with the seeds, threads, resume and
//! shards of `e3d sweep`.
//!
//! The arm: each of 6 slots nudges one joint (`a`/`A` joint 1 by -/+0.35
//! rad, `b`/`B` joint 2, `.` nothing); the effect is the hand's cell on an
//! 8 x 8 grid over [-2, 2]^2. The learner: intrinsic reward
//! `1 / sqrt(N(e))` for the effect reached, `Q[slot, symbol] += alpha
//! (bonus - Q)`, a softmax policy of inverse temperature beta per slot.
//!
//! ```sh
//! cargo run --release --example sweep_custom
//! ```

use e3d::command::CommandSpace;
use e3d::effect::EffectGrid;
use e3d::rand::RngExt;
use e3d::sweep::{
    Learners, MetricSpec, ParamValues, SessionResult, Sweep, SweepSpec, Values, Worlds,
};
use e3d::{Command, Learner, Outcome, Params, SessionRng, World, WorldError};

/// A two-link arm, links 1.0 and 0.8 long, starting stretched along +x.
struct TwoLinkArm {
    space: CommandSpace,
    grid: EffectGrid,
}

impl TwoLinkArm {
    fn new() -> Self {
        TwoLinkArm {
            space: CommandSpace::repeat(6, &['a', 'A', 'b', 'B', '.']).unwrap(),
            grid: EffectGrid::new(8, 8, [-2.0, -2.0], [2.0, 2.0]).unwrap(),
        }
    }
}

impl World for TwoLinkArm {
    fn command_space(&self) -> &CommandSpace {
        &self.space
    }

    fn num_effects(&self) -> usize {
        self.grid.num_cells()
    }

    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        let (mut t1, mut t2) = (0.0f64, 0.0f64);
        for &s in &command.symbols {
            match s {
                0 => t1 -= 0.35,
                1 => t1 += 0.35,
                2 => t2 -= 0.35,
                3 => t2 += 0.35,
                _ => {}
            }
        }
        let hand = [
            t1.cos() + 0.8 * (t1 + t2).cos(),
            t1.sin() + 0.8 * (t1 + t2).sin(),
        ];
        Ok(Outcome {
            effect: self.grid.effect_of(hand),
            reward: 0.0,
            point: hand,
        })
    }
}

/// Count-based exploration: `Q[a_i, i] += alpha (1/sqrt(N(e)) - Q[a_i, i])`,
/// softmax of `beta Q` per slot.
struct CountBonus {
    q: Vec<Vec<f64>>,
    counts: Vec<f64>,
    alpha: f64,
    beta: f64,
}

impl CountBonus {
    fn new(space: &CommandSpace, num_effects: usize, params: &Params) -> Self {
        CountBonus {
            q: space.sizes().map(|k| vec![1.0; k]).collect(),
            counts: vec![0.0; num_effects],
            alpha: params.alpha,
            beta: params.beta,
        }
    }
}

impl Learner for CountBonus {
    fn name(&self) -> &str {
        "count_bonus"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        command.symbols.resize(self.q.len(), 0);
        for slot in 0..self.q.len() {
            let policy = self.slot_policy(slot).unwrap();
            let mut u: f64 = rng.random();
            let mut pick = policy.len() - 1;
            for (k, p) in policy.iter().enumerate() {
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

/// The worlds: the arm under the name `arm2` (any other name is refused).
fn worlds() -> Worlds {
    Worlds::new().with_world("arm2", TwoLinkArm::new)
}

/// The learners: the built-in ones and `count_bonus`, which uses alpha
/// and beta (so its grid spans them, and the results show them).
fn learners() -> Learners {
    Learners::builtin().with(
        "count_bonus",
        &["alpha", "beta"],
        |params, space, n, _target| Ok(Box::new(CountBonus::new(space, n, params))),
    )
}

/// The sweep, built in code: count_bonus at 4 values of beta and the
/// uniform policy, 6 sessions of 2000 trials each, without reward.
fn spec() -> SweepSpec {
    SweepSpec::new(["arm2"], ["count_bonus", "uniform"], 6, 2000)
        .with_name("arm2-count-bonus")
        .with_use_reward([false])
        .with_params(ParamValues {
            beta: Some(Values::log(1.0, 1000.0, 4)),
            ..Default::default()
        })
        .with_seed(16)
        .with_metrics([MetricSpec::NormalizedEntropy, MetricSpec::DistinctEffects])
}

fn sweep() -> Sweep {
    Sweep::with_factories(spec(), &worlds(), learners()).expect("a valid sweep")
}

/// Per cell: (learner, beta or None, mean normalised entropy, mean
/// distinct cells).
fn means(sweep: &Sweep, results: &[SessionResult]) -> Vec<(String, Option<f64>, f64, f64)> {
    sweep
        .cells()
        .iter()
        .map(|cell| {
            let mine: Vec<&SessionResult> = results
                .iter()
                .filter(|r| r.session.cell == cell.index)
                .collect();
            let mean = |k: usize| {
                mine.iter().map(|r| r.values[k].unwrap()).sum::<f64>() / mine.len() as f64
            };
            (
                cell.learner.clone(),
                cell.used[1].then_some(cell.params.beta),
                mean(0),
                mean(1),
            )
        })
        .collect()
}

fn main() {
    let sweep = sweep();
    println!("{}", sweep.text);
    let results = sweep.run(2).expect("the arm cannot fail");
    println!("learner       beta  entropy  cells (of 64), mean of 6 sessions");
    for (learner, beta, h, n) in means(&sweep, &results) {
        let beta = beta.map_or("-".into(), |b| b.to_string());
        println!("{learner:<12}{beta:>6}  {h:.3}    {n:.1}");
    }
    println!("\nresults.csv:\n{}", sweep.results_header());
    for r in results.iter().step_by(6) {
        println!("{}", sweep.result_row(r));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use e3d::sweep::{DirOptions, Shard};

    #[test]
    fn the_sweep_is_the_same_whatever_the_threads_and_a_bonus_explores() {
        let sweep = sweep();
        let results = sweep.run(2).unwrap();
        assert_eq!(results, sweep.run(1).unwrap());
        let m = means(&sweep, &results);
        // count_bonus at beta 1, 10, 100, 1000, then the uniform policy
        assert_eq!(m.len(), 5);
        assert_eq!(m[4].0, "uniform");
        let uniform = m[4].2;
        // beta 1: a softmax of values below 1, next to the uniform policy;
        // beta 100: the bonus spreads the hand evenly over the cells
        assert!((m[0].2 - uniform).abs() < 0.03, "{m:?}");
        assert!(m[2].2 > uniform + 0.15, "{m:?}");
        // the numbers themselves are fixed by the sessions' identities
        let row = sweep.result_row(&results[0]);
        assert!(
            row.starts_with("arm2,count_bonus,false,0.3,1,,,,0,"),
            "{row}"
        );
        let id = sweep.identity(&sweep.cells()[0], 0);
        assert_eq!(
            id,
            "scene=arm2;learner=count_bonus;use_reward=false;alpha=0.3;beta=1;lambda=-;eta=-;epsilon=-;session=0"
        );
        assert_eq!(results[0].session.seed, e3d::sweep::session_seed(16, &id));
    }

    #[test]
    fn the_spec_round_trips_and_shards_merge_into_the_whole() {
        let sweep = sweep();
        // the copy written into output folders reads back to the same spec
        let back = Sweep::parse_with(&sweep.text, "copy.ron", &worlds(), learners()).unwrap();
        assert_eq!(back.spec, sweep.spec);
        assert_eq!(back.sessions(), sweep.sessions());
        // shards into folders, merged: the bytes of one whole run
        let tmp = std::env::temp_dir().join(format!("e3d-sweep-custom-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        let run = |dir: &str, shard: Shard| {
            let options = DirOptions {
                threads: 2,
                resume: false,
                shard,
            };
            sweep
                .run_to_dir(&tmp.join(dir), &options, |_, _| {})
                .unwrap();
        };
        run("whole", Shard::ALL);
        run("1", Shard { k: 1, n: 2 });
        run("2", Shard { k: 2, n: 2 });
        e3d::sweep::merge(&[tmp.join("1"), tmp.join("2")], &tmp.join("merged")).unwrap();
        for file in ["results.csv", "summary.csv"] {
            let whole = std::fs::read(tmp.join("whole").join(file)).unwrap();
            assert_eq!(whole, std::fs::read(tmp.join("merged").join(file)).unwrap());
        }
        let csv = std::fs::read_to_string(tmp.join("whole/results.csv")).unwrap();
        assert_eq!(csv.lines().count(), 1 + 5 * 6);
        assert!(csv.lines().nth(1).unwrap().starts_with("arm2,count_bonus,"));
        std::fs::remove_dir_all(&tmp).unwrap();
    }
}
