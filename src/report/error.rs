//! The one error type of `report`: a run directory that is not what it should be (bad input,
//! exit code 2), or the page that could not be written.

use std::path::{Path, PathBuf};

use crate::io::FileError;

/// Why no report was written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file of the run directory is missing, unreadable as what it should be, or lacks a
    /// value the report needs. `path` names the file (or the directory), `message` says what
    /// was expected there.
    #[error("{}: {message}", path.display())]
    Input {
        /// The file or directory concerned.
        path: PathBuf,
        /// What was expected, and what was found.
        message: String,
    },
    /// A file of the run that its reader refused (the message names the file, and the line
    /// where there is one).
    #[error(transparent)]
    Read(FileError),
    /// A dataset's manifest that its reader refused (the message names the file and line).
    #[error(transparent)]
    Dataset(crate::dataset::DatasetError),
    /// Writing the page failed (nothing was written over an existing page).
    #[error(transparent)]
    Write(FileError),
}

impl ReportError {
    /// A bad-input error about `path`.
    pub fn input(path: &Path, message: impl Into<String>) -> ReportError {
        ReportError::Input {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// Whether the run directory is at fault (exit code 2) rather than the output.
    pub fn is_input(&self) -> bool {
        !matches!(self, ReportError::Write(_))
    }
}
