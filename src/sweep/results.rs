//! The results of a sweep: the columns and rows of `results.csv`, the
//! files of an output folder, and the merge of shards.

use super::journal::{self, JournalHeader};
use super::plan::{format_number, SessionSpec, Shard, Sweep};
use super::spec::MetricSpec;
use super::summary::{self, FAILURE_COLUMN, KEY_COLUMNS};
use super::{io_err, SweepError};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The result of one session: its identity and the kept metrics.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionResult {
    /// The session.
    pub session: SessionSpec,
    /// One value per [`Sweep::metric_columns`] (`None`: no first reward, or
    /// a failed session).
    pub values: Vec<Option<f64>>,
    /// Why the session failed (its world reported an error, for example a
    /// physics blow-up naming the command); `None` for a session that ran.
    /// A failed session is recorded, not fatal: the sweep goes on.
    pub failure: Option<String>,
}

impl Sweep {
    /// The metric column names.
    pub fn metric_columns(&self) -> Vec<String> {
        self.metrics.iter().map(MetricSpec::column).collect()
    }

    /// The header line of `results.csv` (without line break).
    pub fn results_header(&self) -> String {
        let mut cols = self.cell_columns();
        cols.extend(
            KEY_COLUMNS[super::CELL_COLUMNS..]
                .iter()
                .map(|s| s.to_string()),
        );
        cols.extend(self.metric_columns());
        cols.push(FAILURE_COLUMN.to_string());
        cols.join(",")
    }

    /// The CSV row of a result (without line break).
    pub fn result_row(&self, r: &SessionResult) -> String {
        let cell = &self.cells[r.session.cell];
        let mut f = self.cell_fields(cell);
        f.push(r.session.replicate.to_string());
        f.push(r.session.seed.to_string());
        f.extend(
            r.values
                .iter()
                .map(|v| v.map(format_number).unwrap_or_default()),
        );
        // one line, no comma: the reason stays one CSV field
        f.push(
            r.failure
                .as_deref()
                .unwrap_or_default()
                .replace([',', '\n', '\r'], ";"),
        );
        f.join(",")
    }
}

/// What [`Sweep::run_to_dir`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DirReport {
    /// The sessions of the shard.
    pub sessions: usize,
    /// How many were already in the journal.
    pub resumed: usize,
    /// How many ran now.
    pub ran: usize,
}

pub use crate::world::{PHYSICS_FINGERPRINT, VERSION};

/// The journal's file name in an output folder.
pub const JOURNAL: &str = "journal.txt";
/// The copy of the sweep file in an output folder.
pub const SWEEP_COPY: &str = "sweep.ron";
/// The version file in an output folder.
pub const VERSION_FILE: &str = "version.txt";
/// The per-session results in an output folder.
pub const RESULTS: &str = "results.csv";
/// The largest `results.csv` `e3d report` reads (1 GiB: a few hundred
/// bytes a session, and a sweep holds at most
/// [`MAX_SESSIONS`](super::MAX_SESSIONS)).
pub const MAX_RESULTS_BYTES: u64 = 1 << 30;
/// The per-cell summary in an output folder.
pub const SUMMARY: &str = "summary.csv";

pub(super) fn version_line() -> String {
    format!("e3d {VERSION}\n")
}

/// Writes `results.csv` (and `summary.csv` for a whole sweep) from the
/// journal's rows, when every session of the shard is there.
pub(super) fn write_final(
    dir: &Path,
    header: &JournalHeader,
    rows: &BTreeMap<usize, String>,
) -> Result<(), SweepError> {
    let expected = header.shard.count(header.total);
    if rows.len() != expected {
        let (dir, done) = (dir.display(), rows.len());
        return Err(SweepError::Output(format!(
            "{dir}: {done} of {expected} sessions done; run again with --resume"
        )));
    }
    let mut csv = String::with_capacity(64 * (rows.len() + 1));
    for row in std::iter::once(&header.columns).chain(rows.values()) {
        csv.push_str(row);
        csv.push('\n');
    }
    let p = dir.join(RESULTS);
    crate::io::write_atomic(&p, csv.as_bytes()).map_err(io_err(&p))?;
    if header.shard.n == 1 {
        let s = summary::summarize(&header.columns, rows.values().map(String::as_str))?;
        let p = dir.join(SUMMARY);
        crate::io::write_atomic(&p, s.as_bytes()).map_err(io_err(&p))?;
    }
    Ok(())
}

/// Joins the output folders of the shards of one sweep into `out`, which
/// then holds the same files, byte for byte, as a one-process run
/// (`results.csv`, `summary.csv`, `sweep.ron`, `version.txt`, and a
/// journal in canonical order). Every shard `1..=N` must be given once and
/// be complete. `out` must not exist or be empty.
pub fn merge(inputs: &[PathBuf], out: &Path) -> Result<DirReport, SweepError> {
    if inputs.is_empty() {
        return Err(SweepError::Output(
            "nothing to merge: name the shards' folders".into(),
        ));
    }
    let mut first: Option<(JournalHeader, Vec<u8>, Vec<u8>)> = None;
    let mut seen: BTreeMap<usize, PathBuf> = BTreeMap::new();
    let mut rows: BTreeMap<usize, String> = BTreeMap::new();
    for dir in inputs {
        let (read, sweep_copy, version) = read_shard(dir)?;
        let h = &read.header;
        match &first {
            None => first = Some((h.clone(), sweep_copy, version)),
            Some((h0, s0, v0)) => {
                check_same_sweep(dir, &inputs[0], (h, &sweep_copy, &version), (h0, s0, v0))?
            }
        }
        if let Some(other) = seen.insert(h.shard.k, dir.clone()) {
            let (shard, other, dir) = (h.shard, other.display(), dir.display());
            return Err(SweepError::Output(format!(
                "shard {shard} given twice: {other} and {dir}"
            )));
        }
        rows.extend(shard_rows(dir, read)?);
    }
    let (h0, sweep_copy, version) = first.expect("at least one input");
    let missing: Vec<String> = (1..=h0.shard.n)
        .filter(|k| !seen.contains_key(k))
        .map(|k| format!("{k}/{}", h0.shard.n))
        .collect();
    if !missing.is_empty() {
        return Err(SweepError::Output(format!(
            "missing shard(s) {}; give the folders of all {} shards",
            missing.join(", "),
            h0.shard.n
        )));
    }
    check_out_empty(out)?;
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let header = JournalHeader {
        shard: Shard::ALL,
        ..h0
    };
    for (name, bytes) in [(SWEEP_COPY, &sweep_copy), (VERSION_FILE, &version)] {
        let p = out.join(name);
        crate::io::write_atomic(&p, bytes).map_err(io_err(&p))?;
    }
    journal::write_whole(&out.join(JOURNAL), &header, &rows)?;
    write_final(out, &header, &rows)?;
    Ok(DirReport {
        sessions: rows.len(),
        resumed: rows.len(),
        ran: 0,
    })
}

/// A shard's folder: its journal, and the bytes of its copy of the sweep
/// file and of its version file.
fn read_shard(dir: &Path) -> Result<(journal::JournalRead, Vec<u8>, Vec<u8>), SweepError> {
    let jp = dir.join(JOURNAL);
    if !jp.exists() {
        return Err(SweepError::Output(format!(
            "{}: no {JOURNAL}; expected the --out folder of `e3d sweep --shard K/N`",
            dir.display()
        )));
    }
    let read = journal::read(&jp)?;
    let own = |name: &str| {
        crate::text::read_own_bytes(&dir.join(name), crate::scene::MAX_FILE_BYTES, name)
            .map_err(|e| SweepError::Output(e.to_string()))
    };
    Ok((read, own(SWEEP_COPY)?, own(VERSION_FILE)?))
}

/// The rows of a shard's own sessions, in its folder `dir`, all of them
/// (else the shard is incomplete: an error saying how to finish it).
fn shard_rows(dir: &Path, read: journal::JournalRead) -> Result<Vec<(usize, String)>, SweepError> {
    let h = &read.header;
    let expected = h.shard.count(h.total);
    let (shard, total) = (h.shard, h.total);
    let mine = read
        .rows
        .into_iter()
        .filter(|(i, _)| shard.contains(*i) && *i < total)
        .collect::<Vec<_>>();
    if mine.len() != expected {
        return Err(SweepError::Output(format!(
            "{}: shard {shard} is incomplete ({} of {expected} sessions); finish it with `e3d sweep ... --shard {shard} --resume`",
            dir.display(),
            mine.len(),
        )));
    }
    Ok(mine)
}

/// A shard's folder `dir` against the first one (`first_dir`): the same
/// sweep (scenes' content, sweep file, shard count, sessions, columns)
/// run by the same e3d version, else why they cannot be merged.
fn check_same_sweep(
    dir: &Path,
    first_dir: &Path,
    (h, sweep_copy, version): (&JournalHeader, &[u8], &[u8]),
    (h0, s0, v0): (&JournalHeader, &[u8], &[u8]),
) -> Result<(), SweepError> {
    let (dir, first) = (dir.display(), first_dir.display());
    if let Some((name, here, there)) = h.changed_scene(h0) {
        return Err(SweepError::Output(format!(
            "{dir}: ran scene `{name}` with other content ({here:016x}) than {first} ({there:016x}); the scene was edited between the shards, which cannot be merged: rerun them with one version"
        )));
    }
    if h.sweep_hash != h0.sweep_hash
        || h.shard.n != h0.shard.n
        || h.total != h0.total
        || h.columns != h0.columns
        || sweep_copy != s0
    {
        return Err(SweepError::Output(format!(
            "{dir}: holds {}, but {first} holds {}; shards of different sweeps cannot be merged",
            h.describe(),
            h0.describe()
        )));
    }
    if version != v0 || h.version != h0.version {
        let (here, there) = (&h.version, &h0.version);
        return Err(SweepError::Output(format!(
            "{dir}: made by e3d {here}, but {first} by e3d {there}; rerun the shards with one version"
        )));
    }
    Ok(())
}

/// `out` must not exist or be empty (what a killed merge left,
/// `.summary.csv.tmp-*`, does not count, and is removed).
fn check_out_empty(out: &Path) -> Result<(), SweepError> {
    crate::io::remove_stale_temps(out);
    // the lock of the command writing here (`e3d merge` takes it) does
    // not count either
    if out.exists()
        && (!out.is_dir()
            || std::fs::read_dir(out)
                .map_err(io_err(out))?
                .filter_map(Result::ok)
                .any(|e| e.file_name() != crate::io::LOCK_FILE))
    {
        Err(SweepError::Output(format!(
            "{} exists and is not empty; choose another --out",
            out.display()
        )))
    } else {
        Ok(())
    }
}
