//! e3d's own CSV files, read back: a sweep's `summary.csv` ([`Summary`]),
//! the failures its `results.csv` records ([`failures`]) and a run's
//! `trials.csv` ([`parse_trials`]). They may have been edited by hand or
//! cut short: every reader is linear in the text, sizes nothing by a value
//! it reads, and refuses a bad value with `FILE:LINE:COL`, its column and
//! what was expected.

use crate::command::MAX_SLOTS;
use crate::effect::MAX_EFFECTS;
use crate::learner::Params;
use crate::sweep::{CELL_COLUMNS, KEY_COLUMNS};
use crate::text::{csv_fields, echo, parse_finite};

/// A file that cannot be read as what it should be: where and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct CsvError(pub String);

fn err<T>(m: impl Into<String>) -> Result<T, CsvError> {
    Err(CsvError(m.into()))
}

/// The first column of `names` named before: (its first index, its index,
/// its 1-based column in characters on the header line).
fn repeated<S: AsRef<str>>(names: &[S]) -> Option<(usize, usize, usize)> {
    let mut seen = std::collections::HashMap::with_capacity(names.len());
    let mut col = 1;
    for (k, c) in names.iter().enumerate() {
        if let Some(first) = seen.insert(c.as_ref(), k) {
            return Some((first, k, col));
        }
        col += c.as_ref().chars().count() + 1;
    }
    None
}

/// The largest `summary.csv` `e3d plot` and `e3d report` read (64 MiB;
/// one row per cell, a few hundred bytes each).
pub const MAX_SUMMARY_CSV_BYTES: u64 = 64 << 20;

/// The most columns a `summary.csv` may have (1024: the cell's, then
/// four per metric, for some 250 metrics): a summary of 30,000 columns
/// took more than 30 s to draw.
pub const MAX_SUMMARY_COLUMNS: usize = 1024;

/// A sweep's `summary.csv`, parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The column names.
    pub columns: Vec<String>,
    /// The rows, one field per column.
    pub rows: Vec<Vec<String>>,
}

impl Summary {
    /// Parses the text of a `summary.csv` (a byte order mark is ignored).
    /// The parameters and the columns after the cell's must be empty or
    /// finite numbers (an infinite one would stretch a figure's axis
    /// without end), `sessions` and `failed` whole numbers >= 0; a column
    /// named twice or more than [`MAX_SUMMARY_COLUMNS`] are refused. Every
    /// message starts with `summary.csv` (the caller puts the folder first).
    pub fn parse(text: &str) -> Result<Summary, CsvError> {
        const FILE: &str = "summary.csv";
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text.lines();
        let columns: Vec<String> = match lines.next() {
            Some(h) => h.split(',').map(str::to_string).collect(),
            None => {
                return err(format!(
                    "{FILE}: the file is empty; expected a sweep summary"
                ))
            }
        };
        if columns.len() > MAX_SUMMARY_COLUMNS {
            return err(format!(
                "{FILE}:1:1: at most {MAX_SUMMARY_COLUMNS} columns (e3d::csv::MAX_SUMMARY_COLUMNS), found {}",
                columns.len()
            ));
        }
        if columns.len() < CELL_COLUMNS + 1
            || columns[..CELL_COLUMNS] != KEY_COLUMNS[..CELL_COLUMNS]
        {
            return err(format!("{FILE}:1:1: not a sweep summary: expected the columns scene, learner, use_reward, alpha, beta, lambda, eta, epsilon, sessions, ..., found `{}`", echo(text.lines().next().unwrap_or(""))));
        }
        if let Some((first, k, col)) = repeated(&columns) {
            let (name, first, k) = (echo(&columns[k]), first + 1, k + 1);
            return err(format!("{FILE}:1:{col}: column `{name}` appears twice (columns {first} and {k}); expected each column once"));
        }
        let counts: Vec<usize> = ["sessions", "failed"]
            .iter()
            .filter_map(|c| columns.iter().position(|n| n == c))
            .collect();
        let mut rows = Vec::new();
        for (i, l) in lines.enumerate() {
            let f: Vec<String> = l.split(',').map(str::to_string).collect();
            let (line, found, expected) = (i + 2, f.len(), columns.len());
            if found != expected {
                return err(format!(
                    "{FILE}:{line}:1: {found} fields, expected {expected}"
                ));
            }
            let mut col = 1;
            for (k, v) in f.iter().enumerate() {
                if k >= CELL_COLUMNS - Params::SWEPT.len() && !v.is_empty() {
                    let x = parse_finite(v, FILE, line, col, &columns[k]).map_err(CsvError)?;
                    if counts.contains(&k) && !(x >= 0.0 && x.fract() == 0.0) {
                        let (name, v) = (&columns[k], echo(v));
                        return err(format!("{FILE}:{line}:{col}: column `{name}`: expected a whole number >= 0 (a count of sessions), found `{v}`"));
                    }
                }
                col += v.chars().count() + 1;
            }
            rows.push(f);
        }
        Ok(Summary { columns, rows })
    }

    /// The metrics summarised (the names `m` with an `m_mean` column).
    pub fn metrics(&self) -> Vec<&str> {
        self.columns
            .iter()
            .filter_map(|c| c.strip_suffix("_mean"))
            .collect()
    }

    /// The number of cell columns (those before `sessions`): the scene,
    /// learner, reward and parameters, then each scene axis's path.
    pub fn cell_columns(&self) -> usize {
        self.col("sessions").unwrap_or(CELL_COLUMNS)
    }

    /// The index of the column `name`, if the summary has one.
    pub fn col(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }
}

/// One row of `trials.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct TrialRow {
    /// The command, one character per slot.
    pub command: String,
    /// The terminal effect.
    pub effect: usize,
    /// The reward received.
    pub reward: f64,
    /// The values of a continuous command, one per slot (empty for a
    /// command of symbols, whose `command` is then empty).
    pub values: Vec<f64>,
    /// The start context of the trial's episode, for a run of episodes
    /// (`e3d run` on a scene with start contexts, or `--commands K`):
    /// its `start` column; empty otherwise.
    pub start: String,
    /// The 1-based command of the trial in its episode (the `command`
    /// column of a run of episodes); 1 otherwise.
    pub step: usize,
}

/// The largest `trials.csv` [`parse_trials`] is given by `e3d report`
/// (256 MiB, some 8 million trials): the page keeps every trial in memory.
pub const MAX_TRIALS_CSV_BYTES: u64 = 256 << 20;

/// Reads `trials.csv` (with or without a leading `session` column; a run
/// of episodes' `symbols`, `command` and `start` columns give the command,
/// its place in the episode and the start context). An effect must be a
/// whole number below [`MAX_EFFECTS`], a reward and values finite numbers,
/// a command at most [`MAX_SLOTS`] symbols (or values).
pub fn parse_trials(csv: &str) -> Result<Vec<TrialRow>, CsvError> {
    let mut lines = csv.lines();
    let Some(header) = lines.next() else {
        return err("trials.csv is empty");
    };
    let columns = TrialColumns::new(header).map_err(CsvError)?;
    let mut rows: Vec<TrialRow> = Vec::new();
    let mut starts = std::collections::HashSet::new();
    for (k, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let row = columns.row(k + 2, line).map_err(CsvError)?;
        if !row.start.is_empty() && !starts.contains(row.start.as_str()) {
            use crate::scene::MAX_CONTEXTS as MAX;
            if starts.len() == MAX {
                let (line, next, start) = (k + 2, MAX + 1, echo(&row.start));
                return err(format!("trials.csv:{line}:1: column `start`: at most {MAX} distinct start contexts, as a scene declares at most (e3d::scene::MAX_CONTEXTS), found a {next}th, `{start}`"));
            }
            starts.insert(row.start.clone());
        }
        rows.push(row);
    }
    Ok(rows)
}

/// Where a `trials.csv`'s header puts what a [`TrialRow`] holds.
struct TrialColumns {
    header: Vec<String>,
    /// A run of continuous commands: a quoted `values` column.
    continuous: bool,
    /// The command's symbols (or values).
    c: usize,
    /// The effect.
    e: usize,
    /// The reward.
    r: usize,
    /// A run of episodes: the command's place in its episode.
    step_col: Option<usize>,
    /// A run of episodes: the start context.
    start_col: Option<usize>,
}

impl TrialColumns {
    fn new(first_line: &str) -> Result<TrialColumns, String> {
        let header: Vec<String> = csv_fields(first_line)
            .into_iter()
            .map(|(f, _)| f.trim().to_string())
            .collect();
        if let Some((_, k, at)) = repeated(&header) {
            return Err(format!(
                "trials.csv:1:{at}: column `{}` appears twice; expected each column once",
                echo(&header[k])
            ));
        }
        let col = |name: &str| {
            header
                .iter()
                .position(|h| h == name)
                .ok_or(format!("trials.csv has no `{name}` column"))
        };
        // a run of continuous commands writes a quoted `values` column
        let continuous = header.iter().any(|h| h == "values");
        // a run of episodes: `command` is the command's place in its episode
        let episodes = header.iter().any(|h| h == "episode");
        let (step_col, start_col) = if episodes {
            (Some(col("command")?), Some(col("start")?))
        } else {
            (None, None)
        };
        let (c, e, r) = (
            col(if continuous {
                "values"
            } else if episodes {
                "symbols"
            } else {
                "command"
            })?,
            col("effect")?,
            col("reward")?,
        );
        Ok(TrialColumns {
            header,
            continuous,
            c,
            e,
            r,
            step_col,
            start_col,
        })
    }

    /// Line `n` (1-based), `line`, as a row.
    fn row(&self, n: usize, line: &str) -> Result<TrialRow, String> {
        const FILE: &str = "trials.csv";
        let (header, c, e, r) = (&self.header, self.c, self.e, self.r);
        let f = csv_fields(line);
        if f.len() != header.len() {
            let (found, expected, names) = (f.len(), header.len(), header.join(","));
            let line = echo(line);
            return Err(format!(
                "{FILE}:{n}:1: {found} fields, expected {expected} ({names}): `{line}`"
            ));
        }
        let (command, at) = (&f[c].0, f[c].1);
        let (values, command) = command_field(command, n, at, self.continuous)?;
        // a whole number in `ok`, else refused with the column and what it holds
        let whole = |k: usize, ok: std::ops::RangeInclusive<usize>, name: &str, what: &str| {
            let v = &f[k].0;
            let x = v.trim().parse::<usize>().ok().filter(|x| ok.contains(x));
            x.ok_or_else(|| {
                let at = f[k].1;
                format!(
                    "{FILE}:{n}:{at}: column `{name}`: expected {what}, found `{}`",
                    echo(v)
                )
            })
        };
        let below = format!("a whole number below {MAX_EFFECTS}");
        let effect = whole(e, 0..=MAX_EFFECTS - 1, "effect", &below)?;
        let reward = parse_finite(&f[r].0, FILE, n, f[r].1, "reward")?;
        let step = match self.step_col {
            None => 1,
            Some(k) => {
                let max = crate::sweep::MAX_COMMANDS;
                let what = format!("the command's place in its episode, 1 to {max}");
                whole(k, 1..=max, "command", &what)?
            }
        };
        let start = self
            .start_col
            .map_or(String::new(), |k| f[k].0.trim().to_string());
        Ok(TrialRow {
            command,
            values,
            effect,
            reward,
            start,
            step,
        })
    }
}

/// The `command` (or `values`) field of line `n`, starting at column `at`:
/// a command's values (at most [`MAX_SLOTS`], finite) and no symbols, or
/// its symbols (at most [`MAX_SLOTS`]) and no values.
fn command_field(
    command: &str,
    n: usize,
    at: usize,
    continuous: bool,
) -> Result<(Vec<f64>, String), String> {
    const FILE: &str = "trials.csv";
    Ok(if continuous {
        let mut values = Vec::new();
        for v in command.split(',') {
            if values.len() == MAX_SLOTS {
                return Err(format!(
                    "{FILE}:{n}:{at}: column `values`: expected at most {MAX_SLOTS} values"
                ));
            }
            values.push(parse_finite(v, FILE, n, at, "values")?);
        }
        (values, String::new())
    } else {
        if command.chars().nth(MAX_SLOTS).is_some() {
            return Err(format!(
                "{FILE}:{n}:{at}: column `command`: expected at most {MAX_SLOTS} symbols, found `{}`",
                echo(command)
            ));
        }
        (Vec::new(), command.to_string())
    })
}

/// The failure messages of a sweep's `results.csv` (its text): the last
/// field of every row after the header that is not empty.
pub fn failures(results_csv: &str) -> Vec<String> {
    results_csv
        .lines()
        .skip(1)
        .filter_map(|l| l.rsplit(',').next())
        .filter(|f| !f.trim().is_empty())
        .map(str::to_string)
        .collect()
}
