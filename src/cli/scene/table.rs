//! `e3d scene table`: a scene's whole outcome table, computed or read
//! from its cache.

use super::simulate::{build_table, simulate_all, table_seconds, world_error};
use crate::cli::console::{errln, outln};
use crate::cli::{CliError, CliResult};
use e3d::scene::{Scene, WorldSpec};
use e3d::OutcomeTable;
use std::path::Path;

pub(super) fn table(scene: &Scene, cache: Option<&Path>) -> CliResult {
    if !e3d::world::start_contexts(scene).is_empty() {
        return context_table(scene, cache);
    }
    let n = super::simulate::all_commands(scene, "for an outcome table")?;
    if let Some(dir) = cache {
        refuse_non_regular(&OutcomeTable::cache_path(scene, dir))?;
    }
    let start = std::time::Instant::now();
    let (table, existed) = match cache {
        Some(dir) => cached_table(scene, dir)?,
        None => (build_table(scene)?, false),
    };
    let secs = start.elapsed().as_secs_f64();
    let how = match &scene.spec().world {
        WorldSpec::Grid(_) => "grid".to_string(),
        WorldSpec::Physics(p) => {
            let copies = match p.copies_are_exact() {
                true => format!("{} copies per Rapier world", e3d::world::TABLE_COPIES),
                false => "one command per Rapier world".to_string(),
            };
            let simulated = OutcomeTable::simulated_commands(scene).unwrap_or(n);
            match p.symmetry {
                Some(sym) => format!(
                    "{copies}; {sym:?} symmetry: {simulated} simulated, the others reflected"
                ),
                None => copies,
            }
        }
    };
    let (name, k) = (&scene.spec().name, table.len());
    let (rate, threads) = (k as f64 / secs, rayon::current_num_threads());
    outln!("scene {name}: {k} commands in {secs:.3} s ({rate:.0} commands/s, {threads} thread(s), {how})");
    match cache.map(|dir| OutcomeTable::cache_path(scene, dir)) {
        Some(path) if !existed && !path.is_file() => {
            outln!(
                "could not write {} (the table was computed)",
                path.display()
            )
        }
        Some(path) => outln!("{} {}", cache_state(existed, &path), path.display()),
        None => outln!("not written (give --cache DIR to keep it)"),
    }
    Ok(())
}

/// What became of a table file at `path`: `read from` (it `existed`),
/// `written to` or `could not write`.
fn cache_state(existed: bool, path: &Path) -> &'static str {
    match (existed, path.is_file()) {
        (true, _) => "read from",
        (false, true) => "written to",
        (false, false) => "could not write",
    }
}

/// Refuses, before any work, a table file's path that exists and is not a
/// regular file (a FIFO blocked the write for ever; a device would take
/// the bytes): exit code 3, naming the file.
fn refuse_non_regular(path: &Path) -> CliResult {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(CliError::output(format!(
            "--cache: {}: this is not a regular file (a folder, a pipe, a device or a socket); the table file must be one (remove it, or choose another --cache folder)",
            path.display()
        ))),
        _ => Ok(()),
    }
}

/// The table of `scene` as [`OutcomeTable::cached`] gives it, with the
/// progress of its building shown ([`build_table`]), and whether it was
/// read from `dir`.
pub(super) fn cached_table(scene: &Scene, dir: &Path) -> Result<(OutcomeTable, bool), CliError> {
    use e3d::world::CachedOutcomes;
    let path = OutcomeTable::cache_path(scene, dir);
    let table = match OutcomeTable::read_file(&path, scene) {
        Ok(CachedOutcomes::Full(t)) => return Ok((t, true)),
        // what the partial file holds is not simulated again
        Ok(CachedOutcomes::Partial(known)) => {
            let (name, k, from) = (&scene.spec().name, known.len(), path.display());
            errln!("scene {name}: {k} outcomes read from {from}; simulating the others");
            let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
            let whole = OutcomeTable::simulated_commands(scene).unwrap_or(n);
            let simulated = whole.saturating_sub(known.len() as u64);
            let whole = whole.max(1);
            let secs = table_seconds(scene) * simulated as f64 / whole as f64;
            simulate_all(scene, simulated, secs, |progress| {
                OutcomeTable::complete_with(scene, &known, progress)
            })
            .map_err(world_error)?
        }
        Err(_) => build_table(scene)?,
    };
    // a cache that cannot be written is not an error: it costs time only
    let _ = table.write_file(&path, scene);
    Ok((table, false))
}

/// `e3d scene table` on a scene with start contexts: one table per named
/// context (every command from its start), the table keyed by
/// `(context, command)`; a drawn context is refused, named.
fn context_table(scene: &Scene, cache: Option<&Path>) -> CliResult {
    use e3d::world::{ContextTables, TabledContexts};
    let contexts = TabledContexts::of(scene).map_err(|e| CliError::input(e.to_string()))?;
    if let Some(dir) = cache {
        for k in 0..contexts.len() {
            refuse_non_regular(&ContextTables::cache_path(scene, dir, k))?;
        }
    }
    let simulated = contexts.simulated_commands();
    let secs = super::simulate::live_seconds(scene, simulated);
    let start = std::time::Instant::now();
    let (tables, existed) = simulate_all(scene, simulated, secs, |progress| match cache {
        Some(dir) => ContextTables::cached(contexts, dir, progress),
        None => ContextTables::build_with(contexts, progress).map(|t| (t, false)),
    })
    .map_err(world_error)?;
    let secs = start.elapsed().as_secs_f64();
    let total: usize = tables.tables().iter().map(|t| t.len()).sum();
    let (scene_name, m, n) = (&scene.spec().name, tables.len(), tables.table(0).len());
    let (rate, threads) = (total as f64 / secs, rayon::current_num_threads());
    outln!("scene {scene_name}: {m} start contexts x {n} commands = {total} outcomes in {secs:.3} s ({rate:.0} commands/s, {threads} thread(s), one command per world, from each context's start)");
    for (k, (name, t)) in tables.names().iter().zip(tables.tables()).enumerate() {
        let rewarded = t.outcomes().filter(|o| o.reward > 0.0).count();
        let (reached, all) = (t.reachable_effects(), scene.num_effects());
        let mut line = format!(
            "context {name}: reached effects {reached} of {all}, rewarded commands {rewarded}"
        );
        if let Some(dir) = cache {
            let path = ContextTables::cache_path(scene, dir, k);
            line = format!("{line}; {} {}", cache_state(existed, &path), path.display());
        }
        outln!("{line}");
    }
    if cache.is_none() {
        outln!("not written (give --cache DIR to keep it)");
    }
    Ok(())
}
