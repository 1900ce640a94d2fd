//! Running the `glassscan` binary the way a user does, for the command-line tests.

use std::path::Path;
use std::process::{Command, Output};

/// `glassscan ARGS` run from the repository root.
pub fn glassscan(args: &[&str]) -> Output {
    glassscan_in(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

/// `glassscan ARGS` run from `cwd`.
pub fn glassscan_in(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glassscan"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the glassscan binary runs")
}

/// Its standard output, as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Its standard error, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
