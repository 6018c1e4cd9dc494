//! Errors of loading and validating scenes.

use std::path::{Path, PathBuf};

/// Why a scene could not be loaded or used. Every variant names where the problem is.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A problem with a whole file: missing, unreadable, unsupported or malformed.
    #[error("{path}: {message}")]
    File {
        /// The file concerned.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// A problem at a line of a text file.
    #[error("{path}:{line}: {message}")]
    Line {
        /// The file concerned.
        path: PathBuf,
        /// One-based line number.
        line: usize,
        /// What is wrong there.
        message: String,
    },
    /// A problem at a line and column of a text file.
    #[error("{path}:{line}:{column}: {message}")]
    Position {
        /// The file concerned.
        path: PathBuf,
        /// One-based line number.
        line: usize,
        /// One-based column.
        column: usize,
        /// What is wrong there.
        message: String,
    },
    /// Scene data that is not usable, whatever file it came from.
    #[error("{object}: {message}")]
    Invalid {
        /// The object (mesh, material, camera) concerned.
        object: String,
        /// What is wrong with it.
        message: String,
    },
}

impl SceneError {
    /// A file-level error.
    pub fn file(path: &Path, message: impl Into<String>) -> SceneError {
        SceneError::File { path: path.to_path_buf(), message: message.into() }
    }

    /// A data error about one object.
    pub fn invalid(object: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError::Invalid { object: object.into(), message: message.into() }
    }

    /// The same error, attributed to `path` when it does not name a file yet.
    pub fn in_file(self, path: &Path) -> SceneError {
        match self {
            SceneError::Invalid { object, message } => SceneError::file(path, format!("{object}: {message}")),
            other => other,
        }
    }
}
