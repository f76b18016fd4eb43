//! The intervals of the comparisons (`e3d compare`, `e3d closed-loop`):
//! Student's t, Wilson and quartiles on known samples, and the
//! closed-loop table on a known set of sessions.

use e3d::experiment::closed_loop::{ArmSession, ClosedLoopConfig};
use e3d::report::{mean_ci95, order_quartiles, quartiles, t_quantile_975, wilson95};

#[test]
fn t_quantiles_match_the_tables() {
    // R: qt(0.975, df)
    for (df, t) in [
        (1, 12.7062),
        (4, 2.7764),
        (19, 2.0930),
        (30, 2.0423),
        (31, 2.0395),
        (60, 2.0003),
        (99, 1.9842),
        (1000, 1.9623),
    ] {
        assert!((t_quantile_975(df) - t).abs() < 1e-3, "df {df}");
    }
    // decreasing towards the normal's 1.96
    for df in 1..500 {
        assert!(t_quantile_975(df + 1) < t_quantile_975(df), "df {df}");
    }
    assert!(t_quantile_975(100_000) > 1.95996);
}

#[test]
fn the_mean_interval_of_a_known_sample() {
    // 10 sessions: mean 5.5, sd 3.02765, t(9) = 2.262157 -> 5.5 ± 2.1658
    let xs: Vec<f64> = (1..=10).map(f64::from).collect();
    let ci = mean_ci95(&xs).unwrap();
    assert_eq!(ci.n, 10);
    assert!((ci.mean - 5.5).abs() < 1e-12);
    assert!((ci.half - 2.262_157_163 * 3.027_650_354_097_491_7 / 10f64.sqrt()).abs() < 1e-9);
    assert!((ci.lo() - 3.3343).abs() < 1e-3 && (ci.hi() - 7.6657).abs() < 1e-3);
    // a constant sample: no spread, no width
    assert_eq!(mean_ci95(&[2.0; 5]).unwrap().half, 0.0);
}

#[test]
fn wilson_intervals_of_the_four_rooms_shares() {
    // 76/100 and 84/100 sessions rewarded: the intervals overlap
    let (a_lo, a_hi) = wilson95(76, 100).unwrap();
    let (b_lo, b_hi) = wilson95(84, 100).unwrap();
    assert!((a_lo - 0.6677).abs() < 1e-4 && (a_hi - 0.8331).abs() < 1e-4);
    assert!((b_lo - 0.7558).abs() < 1e-4 && (b_hi - 0.8990).abs() < 1e-4);
    assert!(b_lo < a_hi);
    let (lo, hi) = wilson95(20, 20).unwrap();
    assert!((lo - 0.8389).abs() < 1e-4 && hi == 1.0);
    assert_eq!(wilson95(0, 0), None);
}

#[test]
fn quartiles_interpolate_and_order_quartiles_count_never_as_last() {
    assert_eq!(quartiles(&[1.0, 2.0, 3.0, 4.0, 5.0]), Some([2.0, 3.0, 4.0]));
    assert_eq!(quartiles(&[7.0]), Some([7.0; 3]));
    // 8 sessions, 6 rewarded: positions 1, 3 and 5 of the sorted episodes
    assert_eq!(
        order_quartiles(&[60, 10, 50, 20, 40, 30], 8),
        [Some(20), Some(40), Some(60)]
    );
    // 8 sessions, 5 rewarded: the third quartile is never
    assert_eq!(
        order_quartiles(&[10, 20, 30, 40, 50], 8),
        [Some(20), Some(40), None]
    );
    assert_eq!(order_quartiles(&[], 3), [None, None, None]);
}

#[test]
fn the_closed_loop_table_prints_the_intervals_of_its_sessions() {
    let mut sessions = Vec::new();
    // arm uniform: 10 sessions, the first 8 rewarded at 100, 200, ..., 800;
    // cumulative reward 1..10, late reward 0 or 2
    for seed in 0..10u64 {
        sessions.push(ArmSession {
            arm: "uniform",
            seed,
            first_reward_episode: (seed < 8).then_some(100 * (seed as usize + 1)),
            cumulative_reward: seed as f64 + 1.0,
            late_reward: if seed % 2 == 0 { 2.0 } else { 0.0 },
        });
    }
    let cfg = ClosedLoopConfig {
        episodes: 2000,
        ..ClosedLoopConfig::default()
    };
    let md = e3d::report::closed_loop::markdown(&sessions, &cfg, 15);
    let row = md.lines().find(|l| l.starts_with("| uniform |")).unwrap();
    let cells: Vec<&str> = row.split(" | ").collect();
    assert_eq!(cells[1], "8/10");
    // median at position 4 of 9: 500, 7500 moves
    assert_eq!(cells[2], "500 (7500)");
    assert_eq!(cells[3], "5.5 (3.0)");
    assert_eq!(cells[4], "1.0 (1.1)");
    // Wilson 8/10: 49.0%..94.3%
    assert_eq!(cells[5], "49%..94%");
    // positions 2 and 6: 300 and 700
    assert_eq!(cells[6], "300..700");
    // 5.5 ± 2.262 * 3.028 / sqrt 10; 1 ± 2.262 * 1.054 / sqrt 10
    assert_eq!(cells[7], "5.5 ± 2.2");
    assert_eq!(cells[8].trim_end_matches(" |"), "1.0 ± 0.8");
    assert!(md.contains("reward, all 2000 episodes: mean (sd)"));
    assert!(md.contains("rewarded: 95% interval (Wilson)"));
}
