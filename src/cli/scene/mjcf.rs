//! `e3d scene export --mjcf` and `e3d scene import`: a physics scene as
//! MuJoCo's MJCF, and the planar subset of MJCF as a scene.

use super::super::output::write_file;
use super::super::{CliError, CliResult};
use e3d::scene::mjcf;
use std::path::Path;

/// Writes the MJCF model of `scene` to `out`, or stdout.
pub(super) fn export(scene: &e3d::Scene, out: Option<&Path>) -> CliResult {
    let Some(xml) = mjcf::to_mjcf(scene) else {
        return Err(CliError::input(format!(
            "scene `{}` is a grid: only physics scenes export to MJCF",
            scene.spec().name
        )));
    };
    match out {
        Some(path) => write_file(path, xml.as_bytes()),
        None => crate::cli::console::write_stdout(xml.as_bytes()),
    }
}

/// Reads the MJCF file `model` and writes it as a RON scene to `out`, or
/// stdout.
pub(super) fn import(model: &Path, out: Option<&Path>) -> CliResult {
    let text = std::fs::read_to_string(model)
        .map_err(|e| CliError::input(format!("{}: cannot read: {e}", model.display())))?;
    let file = model.display().to_string();
    let imported = mjcf::import::from_mjcf(&text, &file).map_err(CliError::input)?;
    let name = model
        .file_name()
        .map_or(file.clone(), |f| f.to_string_lossy().into_owned());
    let ron = imported.to_ron(&name);
    match out {
        Some(path) => write_file(path, ron.as_bytes()),
        None => crate::cli::console::write_stdout(ron.as_bytes()),
    }
}
