//! `run_sweep`: sweeps, their `results.csv` rows, and `--out` folders.

use crate::errors::{Fail, STOPPED};
use crate::progress::{watched, Watch};
use e3d::sweep::SweepError;
use e3d::sweep::{DirOptions, Shard};
use e3d::Sweep;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

/// The marker a cancelled `run_to_dir` unwinds with (its progress callback
/// cannot return an error). The journal is written to survive a kill at
/// any moment, so an unwind leaves a folder that `resume=True` completes.
pub(crate) struct Interrupted;

/// Takes the lock of the output folder as `e3d sweep` does (creating the
/// folder), or refuses with the CLI's text.
pub(crate) fn lock_out(dir: &Path) -> PyResult<Option<e3d::io::DirLock>> {
    if (dir.exists() && !dir.is_dir()) || std::fs::create_dir_all(dir).is_err() {
        return Ok(None);
    }
    match e3d::io::DirLock::acquire(dir) {
        Ok(lock) => Ok(Some(lock)),
        Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => Err(pyo3::exceptions::PyOSError::new_err(format!(
            "{}: in use by {e}, which is running a sweep into it; wait for it to end or choose another --out",
            dir.display()
        ))),
        Err(e) => Err(pyo3::exceptions::PyOSError::new_err(format!(
            "{}: cannot take the lock {}: {e}",
            dir.display(),
            dir.join(e3d::io::LOCK_FILE).display()
        ))),
    }
}

/// The native part of `e3d.run_sweep` (python/e3d/__init__.py, which
/// documents it, takes a dict and makes columns of the rows): the header
/// and rows of the sweep's `results.csv`, in memory or in the folder `out`.
#[pyfunction]
#[pyo3(signature = (sweep, threads = None, table_cache = None, out = None, resume = false,
    progress = None, shard = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_sweep<'py>(
    py: Python<'py>,
    sweep: &Bound<'py, PyAny>,
    threads: Option<usize>,
    table_cache: Option<PathBuf>,
    out: Option<PathBuf>,
    resume: bool,
    progress: Option<&Bound<'py, PyAny>>,
    shard: Option<(usize, usize)>,
) -> PyResult<(String, Vec<String>)> {
    let sw = sweep_of(sweep, table_cache)?;
    let threads = threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let watch = Watch::default();
    let sw = sw.with_trial_counter(watch.done.clone());
    let total = sw.num_sessions() as u64 * sw.spec.trials as u64;
    let header = sw.results_header();
    let Some(dir) = out else {
        let rows = rows_in_memory(py, &sw, threads, progress, total, &watch)?;
        return Ok((header, rows));
    };
    let _lock = lock_out(&dir)?;
    let shard = shard.map_or(Shard::ALL, |(k, n)| Shard { k, n });
    let total = shard.count(sw.num_sessions()) as u64 * sw.spec.trials as u64;
    let options = DirOptions {
        threads,
        resume,
        shard,
    };
    run_in_dir(py, &sw, &dir, &options, progress, total, &watch)?;
    results_of(&dir)
}

/// `e3d merge DIR... --out OUT`: joins the folders of every shard of one
/// sweep into `out` (the bytes of a one-process run) and returns its
/// `results.csv` as `run_sweep` does.
#[pyfunction]
pub(crate) fn merge_sweeps(
    py: Python<'_>,
    dirs: Vec<PathBuf>,
    out: PathBuf,
) -> PyResult<(String, Vec<String>)> {
    let _lock = lock_out(&out)?;
    py.detach(|| e3d::sweep::merge(&dirs, &out))
        .map_err(|e| PyErr::from(Fail::from(e)))?;
    results_of(&out)
}

/// The header and rows of the `results.csv` in `dir`.
fn results_of(dir: &Path) -> PyResult<(String, Vec<String>)> {
    let path = dir.join(e3d::sweep::RESULTS);
    // as the command line reads it: a regular file of bounded size
    let text = e3d::text::read_own_file(&path, e3d::sweep::MAX_RESULTS_BYTES, e3d::sweep::RESULTS)
        .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))?;
    let mut lines = text.lines().map(str::to_string);
    let header = lines.next().unwrap_or_default();
    Ok((header, lines.collect()))
}

/// The sweep `sweep` gives: the text of one (when it names no file and
/// holds a `(`), else the file it names; with its table cache.
fn sweep_of(sweep: &Bound<'_, PyAny>, table_cache: Option<PathBuf>) -> PyResult<Sweep> {
    let text_or_path: PathBuf = sweep.extract()?;
    let s = text_or_path.to_string_lossy().to_string();
    let is_text = !Path::new(&s).exists() && s.contains('(');
    let mut sw = if is_text {
        Sweep::parse(&s, "<string>", None)
    } else {
        Sweep::load(&text_or_path)
    }
    .map_err(|e| PyErr::from(Fail::from(e)))?;
    if let Some(dir) = table_cache {
        sw = sw.with_table_cache(dir);
    }
    Ok(sw)
}

/// Runs the sweep's sessions without the GIL, watched, and returns their
/// results rows in session order.
fn rows_in_memory(
    py: Python<'_>,
    sw: &Sweep,
    threads: usize,
    progress: Option<&Bound<'_, PyAny>>,
    total: u64,
    watch: &Watch,
) -> PyResult<Vec<String>> {
    Ok(watched(py, progress, total, watch, |watch| {
        let sessions = sw.sessions();
        let mut rows: Vec<Option<String>> = vec![None; sessions.len()];
        sw.run_with(&sessions, threads, |r| {
            if watch.cancelled() {
                return Err(SweepError::Other(STOPPED.into()));
            }
            rows[r.session.index] = Some(sw.result_row(&r));
            Ok(())
        })?;
        Ok::<_, Fail>(rows.into_iter().flatten().collect())
    })??)
}

/// Runs the sweep into the folder `dir` as `e3d sweep --out DIR` does,
/// without the GIL, watched: the sessions of an earlier run count as
/// done, and Ctrl-C stops it between sessions.
fn run_in_dir(
    py: Python<'_>,
    sw: &Sweep,
    dir: &Path,
    options: &DirOptions,
    progress: Option<&Bound<'_, PyAny>>,
    total: u64,
    watch: &Watch,
) -> PyResult<()> {
    let per_session = sw.spec.trials as u64;
    watched(py, progress, total, watch, |watch| {
        let mut first = true;
        let run = std::panic::AssertUnwindSafe(|| {
            sw.run_to_dir(dir, options, |done, _| {
                if first {
                    // the sessions of an earlier run count as done
                    watch
                        .base
                        .store(done as u64 * per_session, Ordering::Relaxed);
                    first = false;
                }
                if watch.cancelled() {
                    std::panic::resume_unwind(Box::new(Interrupted));
                }
            })
        });
        match std::panic::catch_unwind(run) {
            Ok(r) => r.map(|_| ()).map_err(Fail::from),
            Err(p) if p.is::<Interrupted>() => Err(Fail::Runtime(STOPPED.into())),
            Err(p) => std::panic::resume_unwind(p),
        }
    })??;
    Ok(())
}
