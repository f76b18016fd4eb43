//! A sweep driven from Rust: E3D's sensitivity to beta on two_rooms with
//! the reward (the paper's task 2), results collected in memory.
//!
//! ```sh
//! cargo run --release --example sweep_from_code
//! ```

use e3d::sweep::Sweep;

const SWEEP: &str = r#"
Sweep(
    scenes: ["two_rooms"],
    learners: [e3d],
    use_reward: [true],
    params: (beta: [10, 50, 100, 200]),
    sessions: 6,
    trials: 3000,
    seed: 7,
    metrics: [cumulative_reward(3000), normalized_entropy],
)
"#;

/// Mean cumulative reward per beta, in the order of the file.
fn mean_reward_per_beta() -> Vec<(f64, f64)> {
    let sweep = Sweep::parse(SWEEP, "<example>", None).expect("a valid sweep");
    let results = sweep.run(2).expect("the grid cannot fail");
    sweep
        .cells()
        .iter()
        .map(|cell| {
            let rewards: Vec<f64> = results
                .iter()
                .filter(|r| r.session.cell == cell.index)
                .filter_map(|r| r.values[0])
                .collect();
            (
                cell.params.beta,
                rewards.iter().sum::<f64>() / rewards.len() as f64,
            )
        })
        .collect()
}

fn main() {
    println!("beta  mean cumulative reward over 3000 trials (6 sessions)");
    for (beta, reward) in mean_reward_per_beta() {
        println!("{beta:>4}  {reward:8.1}");
    }
}

#[test]
fn reward_needs_beta_above_the_threshold() {
    // E3D keeps the reward only if beta * lambda > log 18 (beta > 96)
    let r = mean_reward_per_beta();
    assert!(r[0].1 < 0.2 * r[3].1, "{r:?}");
    assert!(r[3].1 > 1000.0, "{r:?}");
}
