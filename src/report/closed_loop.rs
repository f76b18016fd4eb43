//! The table of the closed-loop comparison
//! ([`experiment::closed_loop`](crate::experiment::closed_loop), what
//! `e3d closed-loop` prints).

use super::{MeanCi, Stats};
use crate::experiment::closed_loop::{ArmSession, ClosedLoopConfig, ARMS};

/// The table of a comparison, one row per arm: sessions rewarded, the
/// median first rewarded episode and its moves, the mean (sd) reward over
/// all episodes and over the last 1000; then their intervals: the 95%
/// Wilson interval of the share of sessions rewarded
/// ([`wilson95`](super::wilson95)), the quartiles of the first rewarded
/// episode (order statistics, never-rewarded sessions later than all:
/// [`order_quartiles`](super::order_quartiles); a skewed count, so no
/// mean), and each mean reward with its 95% Student t interval
/// ([`mean_ci95`](super::mean_ci95)).
///
/// ```
/// use e3d::experiment::closed_loop::{ArmSession, ClosedLoopConfig};
/// use e3d::report::closed_loop::markdown;
/// let s = |seed, first, total| ArmSession {
///     arm: "uniform", seed, first_reward_episode: first,
///     cumulative_reward: total, late_reward: 0.0,
/// };
/// let sessions = [s(0, Some(10), 4.0), s(1, Some(30), 2.0), s(2, None, 0.0), s(3, None, 0.0)];
/// let md = markdown(&sessions, &ClosedLoopConfig::default(), 15);
/// // 2/4 rewarded (Wilson 15.0%..85.0%); first reward 10, 30, never, never:
/// // median 30, quartiles 10..never; reward 1.5 ± 3.182 * 1.915 / 2
/// assert!(md.contains("| uniform | 2/4 | 30 (450) | 1.5 (1.9) | 0.0 (0.0) |"), "{md}");
/// assert!(md.contains("| 15%..85% | 10..never | 1.5 ± 3.0 | 0.0 ± 0.0 |"), "{md}");
/// ```
pub fn markdown(
    sessions: &[ArmSession],
    cfg: &ClosedLoopConfig,
    moves_per_episode: usize,
) -> String {
    let mut out = format!(
        "| arm | sessions rewarded | median first reward: episode (moves) | reward, all {} episodes: mean (sd) | reward, last 1000: mean (sd) | rewarded: 95% interval (Wilson) | first reward: quartiles Q1..Q3 (episode) | reward, all: mean ± 95% (t) | reward, last 1000: mean ± 95% (t) |\n|---|---|---|---|---|---|---|---|---|\n",
        cfg.episodes
    );
    for r in arms(sessions) {
        let never = super::or_never;
        let median = r.first[1].map_or("never".into(), |m| {
            format!("{m} ({})", m * moves_per_episode)
        });
        let (q1, q3) = (never(r.first[0]), never(r.first[2]));
        // per reward: its mean (sd), and its mean ± its 95% t interval
        let reward = |(d, ci): &(Stats, Option<MeanCi>)| {
            let ci = ci.map(|c| format!("{c:.1}"));
            (
                format!("{:.1} ({:.1})", d.mean, d.sd),
                ci.unwrap_or("-".into()),
            )
        };
        let ((total, total_ci), (late, late_ci)) = (reward(&r.total), reward(&r.late));
        let share = r.share.map_or("-".to_string(), |(lo, hi)| {
            format!("{:.0}%..{:.0}%", 100.0 * lo, 100.0 * hi)
        });
        let (arm, rewarded, n) = (r.arm, r.rewarded, r.n);
        out.push_str(&format!(
            "| {arm} | {rewarded}/{n} | {median} | {total} | {late} | {share} | {q1}..{q3} | {total_ci} | {late_ci} |\n"
        ));
    }
    out
}

/// The figures of [`markdown`]'s table as CSV (`closed_loop.csv`), one row
/// per arm, every number unrounded: sessions and sessions rewarded, the
/// Wilson interval of that share, the first rewarded episode's quartiles
/// (empty for never), each reward's mean, sd and 95% t interval.
///
/// ```
/// use e3d::experiment::closed_loop::ArmSession;
/// use e3d::report::closed_loop::csv;
/// let s = |seed, first, total| ArmSession {
///     arm: "uniform", seed, first_reward_episode: first,
///     cumulative_reward: total, late_reward: 0.0,
/// };
/// let text = csv(&[s(0, Some(10), 4.0), s(1, Some(30), 2.0), s(2, None, 0.0), s(3, None, 0.0)]);
/// let mut lines = text.lines();
/// assert!(lines.next().unwrap().starts_with("arm,sessions,rewarded,rewarded_wilson95_lo,"));
/// let row: Vec<&str> = lines.next().unwrap().split(',').collect();
/// assert_eq!(row[..3], ["uniform", "4", "2"]);
/// assert_eq!(row[5..8], ["10", "30", ""]); // quartiles: 10, 30, never
/// assert_eq!(row[8], "1.5");
/// ```
pub fn csv(sessions: &[ArmSession]) -> String {
    let mut out = String::from("arm,sessions,rewarded,rewarded_wilson95_lo,rewarded_wilson95_hi,first_reward_episode_q1,first_reward_episode_median,first_reward_episode_q3");
    for m in ["cumulative_reward", "late_reward"] {
        for c in ["mean", "sd", "ci95_lo", "ci95_hi"] {
            out.push_str(&format!(",{m}_{c}"));
        }
    }
    out.push('\n');
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for r in arms(sessions) {
        let mut row = vec![r.arm.to_string(), r.n.to_string(), r.rewarded.to_string()];
        row.extend([opt(r.share.map(|s| s.0)), opt(r.share.map(|s| s.1))]);
        row.extend(r.first.map(|q| opt(q.map(|q| q as f64))));
        for (d, ci) in [&r.total, &r.late] {
            row.extend([d.mean.to_string(), d.sd.to_string()]);
            row.extend([opt(ci.map(|c| c.lo())), opt(ci.map(|c| c.hi()))]);
        }
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

/// One arm's figures, as both tables show them.
struct ArmRow {
    arm: &'static str,
    n: usize,
    rewarded: usize,
    /// The Wilson interval of `rewarded / n`.
    share: Option<(f64, f64)>,
    /// The first rewarded episode's quartiles (`None`: never).
    first: [Option<usize>; 3],
    /// The reward over all episodes, and over the last 1000.
    total: (Stats, Option<MeanCi>),
    late: (Stats, Option<MeanCi>),
}

/// The arms of `sessions`, in the order of [`ARMS`].
fn arms(sessions: &[ArmSession]) -> Vec<ArmRow> {
    let figures = |xs: Vec<f64>| (super::describe(&xs), super::mean_ci95(&xs));
    (ARMS.iter())
        .filter_map(|&arm| {
            let rows: Vec<&ArmSession> = sessions.iter().filter(|s| s.arm == arm).collect();
            if rows.is_empty() {
                return None;
            }
            let firsts: Vec<usize> = rows.iter().filter_map(|s| s.first_reward_episode).collect();
            // the quartiles count never-rewarded sessions as later than all
            Some(ArmRow {
                arm,
                n: rows.len(),
                rewarded: firsts.len(),
                share: super::wilson95(firsts.len(), rows.len()),
                first: super::order_quartiles(&firsts, rows.len()),
                total: figures(rows.iter().map(|s| s.cumulative_reward).collect()),
                late: figures(rows.iter().map(|s| s.late_reward).collect()),
            })
        })
        .collect()
}
