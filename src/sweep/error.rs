//! Why a sweep stops.

use crate::scene::SceneError;
use crate::world::WorldError;
use std::path::{Path, PathBuf};

/// An error a factory returns: any error type, sent across threads.
pub type BoxError = Box<dyn std::error::Error + Send + Sync>;

/// Why a sweep could not be loaded, run, resumed or merged.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
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
    /// A learner could not be made for a cell (its factory refused the
    /// parameters, the space or the target); the factory's error is the
    /// source.
    #[error("{source}")]
    Learner {
        /// The learner's name in the sweep.
        learner: String,
        /// The factory's error ([`LearnerError`](crate::learner::LearnerError) for
        /// the built-in learners).
        source: BoxError,
    },
    /// Anything else that stops a sweep (a world of another command space
    /// than its scene's, a thread pool that cannot start, ...).
    #[error("{0}")]
    Other(String),
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> SweepError + '_ {
    move |source| SweepError::Io {
        path: path.to_path_buf(),
        source,
    }
}
