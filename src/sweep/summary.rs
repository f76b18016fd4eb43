//! `summary.csv`: per cell, the mean, standard deviation and 95% interval
//! of each metric.
//!
//! For each metric column `m` of `results.csv`, the summary has `m_mean`,
//! `m_sd` (sample standard deviation, `n - 1` in the denominator),
//! `m_ci_low` and `m_ci_high`: the 95% confidence interval of the mean,
//! `mean -/+ t(0.975, n - 1) sd / sqrt(n)` (Student). With one session the
//! sd and the interval are empty. Empty values (a session that never got a
//! reward has no `first_reward_trial`, one that never reached 90% of the
//! cells no `trials_to_90_percent`) are left out; a metric with empty
//! values also gets `m_n`, the number of sessions that have one. Failed
//! sessions (a non-empty `failure` in `results.csv`) count in `failed` and
//! give no value.

use super::SweepError;

/// A number as written in results and identities: Rust's shortest
/// round-trip decimal form (`0.3`, `100`, `0.001`).
pub fn format_number(v: f64) -> String {
    format!("{v}")
}

/// The columns of `results.csv` before the metrics.
pub const KEY_COLUMNS: [&str; 10] = [
    "scene",
    "learner",
    "use_reward",
    "alpha",
    "beta",
    "lambda",
    "eta",
    "epsilon",
    "session",
    "seed",
];

/// The last column of `results.csv`: empty, or why the session failed.
pub const FAILURE_COLUMN: &str = "failure";

/// The number of leading [`KEY_COLUMNS`] that identify a cell (all but
/// `session` and `seed`).
pub const CELL_COLUMNS: usize = 8;

/// The number of cell columns of a `results.csv` header `cols`: the
/// first [`CELL_COLUMNS`] of [`KEY_COLUMNS`], then the scene axes' paths,
/// up to `session` and `seed`; `None` for another header.
pub fn cell_columns(cols: &[&str]) -> Option<usize> {
    let n = cols.iter().position(|&c| c == "session")?;
    let keys = &KEY_COLUMNS[..CELL_COLUMNS];
    (n >= CELL_COLUMNS && cols[..CELL_COLUMNS] == *keys && cols.get(n + 1) == Some(&"seed"))
        .then_some(n)
}

/// Mean, sd and 95% interval of `xs` (sd and interval `None` below 2 values).
pub fn stats(xs: &[f64]) -> (Option<f64>, Option<f64>, Option<(f64, f64)>) {
    let n = xs.len();
    if n == 0 {
        return (None, None, None);
    }
    let d = crate::report::describe(xs);
    let Some(ci) = crate::report::mean_ci95(xs) else {
        return (Some(d.mean), None, None);
    };
    let half = ci.half;
    (
        Some(d.mean),
        Some(d.sd),
        Some((d.mean - half, d.mean + half)),
    )
}

fn num(v: Option<f64>) -> String {
    v.map(format_number).unwrap_or_default()
}

/// A cell's key, each session's values, and how many of its sessions
/// failed.
type Group = (String, Vec<Vec<Option<f64>>>, usize);

/// The summary of `results.csv` rows (without header, in canonical order,
/// so that the sessions of a cell are consecutive) whose header line is
/// `columns`.
pub fn summarize<'a>(
    columns: &str,
    rows: impl Iterator<Item = &'a str>,
) -> Result<String, SweepError> {
    let cols: Vec<&str> = columns.split(',').collect();
    let Some(cell) = cell_columns(&cols) else {
        return Err(SweepError::Output(format!(
            "unexpected results columns `{columns}`"
        )));
    };
    let with_failure = cols.last() == Some(&FAILURE_COLUMN);
    let metrics = &cols[cell + 2..cols.len() - usize::from(with_failure)];
    let groups = group_cells(&cols, cell, metrics.len(), with_failure, rows)?;
    // which metrics may be empty (get an `_n` column)
    let has_n: Vec<bool> = metrics
        .iter()
        .map(|m| {
            matches!(
                *m,
                "first_reward_trial" | "trials_to_50_percent" | "trials_to_90_percent"
            ) || m.starts_with("normalized_entropy_context_")
                || m.starts_with("cumulative_reward_context_")
                || m.starts_with("first_reward_trial_context_")
        })
        .collect();
    let mut out = String::new();
    let header = summary_header(&cols[..cell], metrics, &has_n, with_failure);
    out.push_str(&header.join(","));
    out.push('\n');
    for (key, sessions, failed) in &groups {
        let mut f = vec![key.clone(), sessions.len().to_string()];
        if with_failure {
            f.push(failed.to_string());
        }
        for (j, &n) in has_n.iter().enumerate() {
            let xs: Vec<f64> = sessions.iter().filter_map(|s| s[j]).collect();
            let (mean, sd, ci) = stats(&xs);
            f.extend([mean, sd, ci.map(|c| c.0), ci.map(|c| c.1)].map(num));
            f.extend(n.then(|| xs.len().to_string()));
        }
        out.push_str(&f.join(","));
        out.push('\n');
    }
    Ok(out)
}

/// Per cell: its key, each session's values of the `metrics` metrics,
/// and how many of its sessions failed; the `rows` grouped by their
/// `cell` cell columns (consecutive), checked against the columns `cols`.
fn group_cells<'a>(
    cols: &[&str],
    cell: usize,
    metrics: usize,
    with_failure: bool,
    rows: impl Iterator<Item = &'a str>,
) -> Result<Vec<Group>, SweepError> {
    let mut groups: Vec<Group> = Vec::new();
    for row in rows {
        let f: Vec<&str> = row.split(',').collect();
        if f.len() != cols.len() {
            return Err(SweepError::Output(format!(
                "a results row has {} fields, expected {}: `{row}`",
                f.len(),
                cols.len()
            )));
        }
        let key = f[..cell].join(",");
        let values = f[cell + 2..cell + 2 + metrics]
            .iter()
            .map(|v| {
                let value = (!v.is_empty()).then(|| v.parse::<f64>()).transpose();
                value.map_err(|_| {
                    SweepError::Output(format!("a results value is not a number: `{v}`"))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let failed = usize::from(with_failure && !f[f.len() - 1].is_empty());
        match groups.last_mut() {
            Some((k, v, n)) if *k == key => {
                v.push(values);
                *n += failed;
            }
            _ => groups.push((key, vec![values], failed)),
        }
    }
    Ok(groups)
}

/// The summary's header: the cell columns `cells`, `sessions`, `failed`
/// (when the results have failures), and per metric its mean, sd,
/// interval and (for `has_n`) count.
fn summary_header(
    cells: &[&str],
    metrics: &[&str],
    has_n: &[bool],
    with_failure: bool,
) -> Vec<String> {
    let mut header: Vec<String> = cells.iter().map(|s| s.to_string()).collect();
    header.push("sessions".into());
    if with_failure {
        header.push("failed".into());
    }
    for (m, &n) in metrics.iter().zip(has_n) {
        header.extend(["mean", "sd", "ci_low", "ci_high"].map(|s| format!("{m}_{s}")));
        header.extend(n.then(|| format!("{m}_n")));
    }
    header
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interval_of_a_known_sample() {
        let (m, sd, ci) = stats(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(m, Some(2.5));
        let sd = sd.unwrap();
        assert!((sd - 1.2909944487358056).abs() < 1e-15);
        let (lo, hi) = ci.unwrap();
        let half = 3.182446305 * sd / 2.0;
        assert!((lo - (2.5 - half)).abs() < 1e-12 && (hi - (2.5 + half)).abs() < 1e-12);
        assert_eq!(stats(&[5.0]), (Some(5.0), None, None));
        // the expansion joins the table smoothly
        assert!((crate::report::t_quantile_975(31) - 2.039513446).abs() < 1e-7);
        assert!((crate::report::t_quantile_975(60) - 2.000297822).abs() < 1e-7);
    }

    #[test]
    fn groups_cells_and_counts_missing_first_rewards() {
        let cols = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,session,seed,x,first_reward_trial";
        let rows = [
            "s,e3d,true,0.3,1,0.03,0.01,,0,11,1,5",
            "s,e3d,true,0.3,1,0.03,0.01,,1,12,3,",
            "s,uniform,true,,,,,,0,13,2,",
        ];
        let s = summarize(cols, rows.iter().copied()).unwrap();
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].ends_with("first_reward_trial_ci_high,first_reward_trial_n"));
        assert!(lines[1].starts_with("s,e3d,true,0.3,1,0.03,0.01,,2,2,1.4142135623730951,"));
        assert!(lines[1].ends_with(",5,,,,1"));
        assert_eq!(lines[2], "s,uniform,true,,,,,,1,2,,,,,,,,0");
    }
}
