//! Where the commands' outputs go: folders that are not overwritten without
//! `--force`, and files written whole or not at all.

use super::{locked, CliError, CliResult};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The folders [`prepare_out`] created, deepest first.
static CREATED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The locks of the output folders this process writes into, held until
/// [`release_locks`] (the end of the command).
static LOCKS: Mutex<Vec<e3d::io::DirLock>> = Mutex::new(Vec::new());

/// Takes the lock of the output folder `dir` (creating it) to the end of
/// the command ([`release_locks`]), or refuses naming who holds it (two
/// commands would mix their files); a killed run's lock is taken over, with
/// a warning. A folder that cannot be created is left to the command.
pub fn lock_out(dir: &Path) -> CliResult {
    if (dir.exists() && !dir.is_dir()) || std::fs::create_dir_all(dir).is_err() {
        return Ok(());
    }
    let lock = e3d::io::DirLock::acquire(dir).map_err(|e| {
        let d = dir.display();
        CliError::output(match e.kind() {
            std::io::ErrorKind::WouldBlock => format!(
                "{d}: in use by {e}, which is writing into it; wait for it to end or choose another --out"
            ),
            // the error names the lock file
            _ => format!("{d}: cannot take the lock: {e}"),
        })
    })?;
    if let Some(old) = &lock.previous {
        crate::cli::console::errln!(
            "warning: {}: took over the lock of a run that ended without releasing it ({old})",
            dir.display()
        );
    }
    locked(&LOCKS).push(lock);
    Ok(())
}

/// Releases the locks [`lock_out`] took (their files removed).
pub fn release_locks() {
    std::mem::take(&mut *locked(&LOCKS));
}

/// Removes the folders [`prepare_out`] created that are still empty: a
/// command refused after it prepared its `--out` leaves no empty folder.
pub fn remove_created_if_empty() {
    let created = std::mem::take(&mut *locked(&CREATED));
    for dir in created {
        // fails, as it should, on a folder that holds anything
        let _ = std::fs::remove_dir(dir);
    }
}

/// Refuses to overwrite the given files in `dir` unless `force`; creates
/// `dir` and takes its lock ([`lock_out`]): a second command writing into
/// it meanwhile is refused, naming the process that holds it.
pub fn prepare_out(dir: &Path, files: &[&str], force: bool) -> CliResult {
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::output(format!(
            "{}: exists and is not a directory",
            dir.display()
        )));
    }
    if !force {
        if let Some(f) = files.iter().map(|f| dir.join(f)).find(|p| p.exists()) {
            return Err(CliError::output(format!(
                "{} exists; pass --force to overwrite it, or choose another --out",
                f.display()
            )));
        }
    }
    let missing: Vec<PathBuf> = dir
        .ancestors()
        .take_while(|d| !d.as_os_str().is_empty() && std::fs::symlink_metadata(d).is_err())
        .map(Path::to_path_buf)
        .collect();
    std::fs::create_dir_all(dir).map_err(|e| {
        CliError::output(format!("{}: cannot create the folder: {e}", dir.display()))
    })?;
    locked(&CREATED).extend(missing);
    lock_out(dir)?;
    // what a run killed while writing here left (a full disk, SIGKILL)
    e3d::io::remove_stale_temps(dir);
    Ok(())
}

/// Refuses an output file (of the option `flag`) whose name does not end in
/// one of the `formats` written, any case (`x.png` would be SVG under a PNG
/// name); `hint` says how to get another format, if there is a way.
pub fn check_format(path: &Path, flag: &str, formats: &[&str], hint: &str) -> CliResult {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    // a stream (`/dev/stdout`, a named pipe) takes whatever it is given
    if formats.iter().any(|f| ext.eq_ignore_ascii_case(f)) || e3d::io::is_stream(path) {
        return Ok(());
    }
    let expected: Vec<String> = formats.iter().map(|f| format!(".{f}")).collect();
    let (path, expected) = (path.display(), expected.join(" or "));
    let found = match ext {
        "" => "no extension".to_string(),
        e => format!("a .{e} file"),
    };
    Err(CliError::input(format!(
        "{flag} {path}: expected a file ending in {expected} (the format written), found {found}{hint}"
    )))
}

/// Refuses, before any work, a cache folder (`--table-cache DIR`,
/// `scene table --cache DIR`) that exists and is not a folder: the outcomes
/// would be computed and then not kept, the run otherwise silent about it.
pub fn check_cache_folder(dir: &Path, flag: &str) -> CliResult {
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::output(format!(
            "{flag} {}: exists and is not a folder; expected the folder of the outcome cache (created if missing)",
            dir.display()
        )));
    }
    Ok(())
}

/// Writes a file whole or not at all, as a CLI error.
pub fn write_file(path: &Path, bytes: &[u8]) -> CliResult {
    e3d::io::write_atomic(path, bytes).map_err(|e| super::cannot_write(path, e))
}
