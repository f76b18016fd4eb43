//! Why a sweep stops.

use crate::scene::SceneError;
use crate::world::WorldError;
use std::path::{Path, PathBuf};

/// Why a sweep could not be loaded, run, resumed or merged.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A mistake in the sweep file (or in a scene it names), with file, line
    /// and column.
    #[error("{0}")]
    Input(#[from] SceneError),
    /// A session failed in its world.
    #[error("{0}")]
    World(#[from] WorldError),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What failed.
        source: std::io::Error,
    },
    /// An output folder that cannot be used as asked (exists, holds another
    /// sweep, is incomplete, ...).
    #[error("{0}")]
    Output(String),
    /// Anything else that stops a sweep (a learner refusing its parameters,
    /// a thread pool that cannot start, ...).
    #[error("{0}")]
    Other(String),
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> SweepError + '_ {
    move |source| SweepError::Io {
        path: path.to_path_buf(),
        source,
    }
}
