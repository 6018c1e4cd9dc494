//! Errors and warnings of the scene language, each located at a file, line and column.

use crate::SceneError;
use std::fmt;
use std::path::{Path, PathBuf};

/// A line of a scene-language input: the file it comes from (as the user named it, or a
/// placeholder such as `<stdin>`) and its one-based line number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Location<'a> {
    /// The file (relative `source` paths resolve against its folder).
    pub file: &'a Path,
    /// One-based line number.
    pub line: usize,
}

impl<'a> Location<'a> {
    /// Line `line` (one-based) of `file`.
    pub fn new(file: &'a Path, line: usize) -> Location<'a> {
        Location { file, line }
    }
}

/// Why a scene-language input was rejected. `Display` gives `file:line:column: message`,
/// followed by `(sourced from file:line)` for each `source` that led there, innermost first.
/// `line` and `column` are zero when the whole file is concerned (it cannot be read).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LangError {
    /// The file the offending line is in.
    pub file: PathBuf,
    /// One-based line number (0 = the file as a whole).
    pub line: usize,
    /// One-based column in characters of the offending token (0 = the file as a whole).
    pub column: usize,
    /// What is wrong and what was expected, starting with the command's name.
    pub message: String,
    /// The `source` lines through which the file was reached, innermost first.
    pub sourced_from: Vec<(PathBuf, usize)>,
}

impl LangError {
    pub(crate) fn at(at: Location<'_>, column: usize, message: impl Into<String>) -> LangError {
        LangError { file: at.file.to_path_buf(), line: at.line, column, message: message.into(), sourced_from: Vec::new() }
    }

    pub(crate) fn whole_file(file: &Path, message: impl Into<String>) -> LangError {
        LangError { file: file.to_path_buf(), line: 0, column: 0, message: message.into(), sourced_from: Vec::new() }
    }

    /// ` (sourced from file:line)` for the three innermost `source` lines, then a count.
    fn trace(&self) -> String {
        let mut text: String = self.sourced_from.iter().take(3).map(|(file, line)| format!(" (sourced from {}:{line})", file.display())).collect();
        if self.sourced_from.len() > 3 {
            text.push_str(&format!(" (and {} more source levels)", self.sourced_from.len() - 3));
        }
        text
    }
}

impl fmt::Display for LangError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}{}", self.file.display(), self.message, self.trace())
        } else {
            write!(f, "{}:{}:{}: {}{}", self.file.display(), self.line, self.column, self.message, self.trace())
        }
    }
}

impl std::error::Error for LangError {}

impl From<LangError> for SceneError {
    /// A [`SceneError::Position`] (`file:line:column: message`) or, for a whole-file
    /// problem, a [`SceneError::File`].
    fn from(error: LangError) -> SceneError {
        let trace = error.trace();
        if error.line == 0 {
            SceneError::File { path: error.file, message: format!("{}{trace}", error.message) }
        } else {
            SceneError::Position { path: error.file, line: error.line, column: error.column, message: format!("{}{trace}", error.message) }
        }
    }
}

/// Something accepted but worth telling the author: an unbalanced `pushTransform` at the end
/// of the input, more vertices than `maxverts` announced, and the like.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LangWarning {
    /// The file concerned.
    pub file: PathBuf,
    /// One-based line number.
    pub line: usize,
    /// One-based column.
    pub column: usize,
    /// What was noticed.
    pub message: String,
}

impl fmt::Display for LangWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}: warning: {}", self.file.display(), self.line, self.column, self.message)
    }
}
