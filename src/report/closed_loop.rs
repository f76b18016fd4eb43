//! The table of the closed-loop comparison
//! ([`experiment::closed_loop`](crate::experiment::closed_loop), what
//! `e3d closed-loop` prints).

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
    for arm in ARMS {
        let rows: Vec<&ArmSession> = sessions.iter().filter(|s| s.arm == arm).collect();
        if rows.is_empty() {
            continue;
        }
        let firsts: Vec<usize> = rows.iter().filter_map(|s| s.first_reward_episode).collect();
        // the median counts never-rewarded sessions as later than all
        let [q1, mid, q3] = super::order_quartiles(&firsts, rows.len());
        let median = mid.map_or("never".into(), |m| {
            format!("{m} ({})", m * moves_per_episode)
        });
        let never = |q: Option<usize>| q.map_or("never".to_string(), |q| q.to_string());
        let (q1, q3) = (never(q1), never(q3));
        // per reward: its mean (sd), and its mean ± its 95% t interval
        let reward = |xs: Vec<f64>| {
            let d = super::describe(&xs);
            let ci = super::mean_ci95(&xs).map(|c| format!("{:.1} ± {:.1}", c.mean, c.half));
            let mean_sd = format!("{:.1} ({:.1})", d.mean, d.sd);
            (mean_sd, ci.unwrap_or("-".into()))
        };
        let (total, total_ci) = reward(rows.iter().map(|s| s.cumulative_reward).collect());
        let (late, late_ci) = reward(rows.iter().map(|s| s.late_reward).collect());
        let (rewarded, n) = (firsts.len(), rows.len());
        let share = super::wilson95(rewarded, n).map_or("-".to_string(), |(lo, hi)| {
            format!("{:.0}%..{:.0}%", 100.0 * lo, 100.0 * hi)
        });
        out.push_str(&format!(
            "| {arm} | {rewarded}/{n} | {median} | {total} | {late} | {share} | {q1}..{q3} | {total_ci} | {late_ci} |\n"
        ));
    }
    out
}
