//! Where the commands' outputs go: folders that are not overwritten without
//! `--force`, and files written whole or not at all.

use super::{CliError, CliResult};
use std::path::Path;

/// Refuses to overwrite the given files in `dir` unless `force`; creates `dir`.
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
    std::fs::create_dir_all(dir).map_err(|e| {
        CliError::output(format!("{}: cannot create the folder: {e}", dir.display()))
    })?;
    // what a run killed while writing here left (a full disk, SIGKILL)
    e3d::io::remove_stale_temps(dir);
    Ok(())
}

/// Writes a file whole or not at all, as a CLI error.
pub fn write_file(path: &Path, bytes: &[u8]) -> CliResult {
    e3d::io::write_atomic(path, bytes)
        .map_err(|e| CliError::output(format!("{}: cannot write: {e}", path.display())))
}
