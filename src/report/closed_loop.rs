//! The table of the closed-loop comparison
//! ([`experiment::closed_loop`](crate::experiment::closed_loop), what
//! `e3d closed-loop` prints).

use crate::experiment::closed_loop::{ArmSession, ClosedLoopConfig, ARMS};

/// The table of a comparison, one row per arm: sessions rewarded, the
/// median first rewarded episode and its moves, the mean (sd) reward over
/// all episodes and over the last 1000.
pub fn markdown(
    sessions: &[ArmSession],
    cfg: &ClosedLoopConfig,
    moves_per_episode: usize,
) -> String {
    let mut out = format!(
        "| arm | sessions rewarded | median first reward: episode (moves) | reward, all {} episodes: mean (sd) | reward, last 1000: mean (sd) |\n|---|---|---|---|---|\n",
        cfg.episodes
    );
    for arm in ARMS {
        let rows: Vec<&ArmSession> = sessions.iter().filter(|s| s.arm == arm).collect();
        if rows.is_empty() {
            continue;
        }
        let mut firsts: Vec<usize> = rows.iter().filter_map(|s| s.first_reward_episode).collect();
        firsts.sort_unstable();
        // the median counts never-rewarded sessions as later than all
        let mid = (rows.len() - 1) / 2;
        let median = if mid < firsts.len() {
            let m = firsts[mid];
            format!("{m} ({})", m * moves_per_episode)
        } else {
            "never".into()
        };
        let total = super::describe(&rows.iter().map(|s| s.cumulative_reward).collect::<Vec<_>>());
        let late = super::describe(&rows.iter().map(|s| s.late_reward).collect::<Vec<_>>());
        out.push_str(&format!(
            "| {arm} | {}/{} | {median} | {:.1} ({:.1}) | {:.1} ({:.1}) |\n",
            firsts.len(),
            rows.len(),
            total.mean,
            total.sd,
            late.mean,
            late.sd
        ));
    }
    out
}
