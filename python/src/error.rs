//! The exceptions: one for bad input (the command line's exit code 2: a scene, flag or file
//! that is not what it should be) and their base for everything else (exit code 1). The
//! message is the one the command line prints after `error: `.

use glassscan::cli::{embed, CliError};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::PyErr;

create_exception!(
    glassscan,
    GlassscanError,
    PyException,
    "A glassscan failure (the command line's exit code 1); the base of every glassscan exception."
);
create_exception!(
    glassscan,
    InputError,
    GlassscanError,
    "Bad input (the command line's exit code 2): the message names the file, the field and what was expected."
);

/// The exception for a command-line error, by its exit code.
pub fn to_py(error: CliError) -> PyErr {
    let message = embed::message(&error);
    if error.code == 2 {
        InputError::new_err(message)
    } else {
        GlassscanError::new_err(message)
    }
}

/// A bad-input exception from anything that displays (the error chain joined as the command
/// line joins it).
pub fn input(error: impl Into<anyhow::Error>) -> PyErr {
    to_py(CliError::input(error))
}
