//! Your own simulator as a world: a two-link planar arm by closed-form
//! kinematics, learned by E3D.
//!
//! Each of 6 slots nudges one joint: `a`/`A` turn joint 1 by -/+0.35 rad,
//! `b`/`B` turn joint 2 by -/+0.35 rad, `.` does nothing. The effect is the
//! hand's cell on an 8 x 8 grid over [-2, 2]^2.
//!
//! ```sh
//! cargo run --release --example custom_world
//! ```

use e3d::command::CommandSpace;
use e3d::effect::EffectGrid;
use e3d::learner::LearnerSetup;
use e3d::{run_session, Command, LearnerKind, Outcome, SessionConfig, Target, World, WorldError};

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

/// Normalised entropy of the effects of a 3000-trial session, per learner.
fn compare() -> Vec<(LearnerKind, f64, usize)> {
    let mut world = TwoLinkArm::new();
    let space = world.command_space().clone();
    [LearnerKind::Uniform, LearnerKind::E3d]
        .into_iter()
        .map(|kind| {
            let mut learner = LearnerSetup::new(kind)
                .symbols(&space, world.num_effects())
                .unwrap();
            let cfg = SessionConfig {
                trials: 3000,
                seed: 1,
                use_reward: false,
            };
            let m = run_session(&mut world, &mut learner, &cfg)
                .unwrap()
                .metrics(&Target::Uniform);
            (kind, m.normalized_entropy, m.distinct_effects)
        })
        .collect()
}

fn main() {
    for (kind, h, n) in compare() {
        println!("{kind:>8}: normalised entropy {h:.3}, {n} of 64 cells reached");
    }
}

#[test]
fn e3d_spreads_the_hand_wider_than_the_uniform_policy() {
    let r = compare();
    assert!(r[1].1 > r[0].1 + 0.05, "{r:?}");
}
