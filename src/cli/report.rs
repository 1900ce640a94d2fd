//! `glassscan report RUN_DIR [--out FILE]`: one self-contained HTML page of a study, sweep,
//! locate run or dataset directory (`report`).

use std::path::PathBuf;

use clap::Args;

use super::{progress, CliError};
use crate::report::{write_report, ReportError};

/// Arguments of `glassscan report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// The run directory: the `--out` of `study scan-angle`, `sweep` or `locate`, or a dataset.
    pub run_dir: PathBuf,
    /// Where to write the page: a new file, or an earlier page of this command (any other
    /// file is refused and left as it is). Default: RUN_DIR/report.html.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Runs `glassscan report`: a damaged or unknown directory is bad input (exit code 2), and no
/// page is written then.
pub fn run(args: ReportArgs) -> Result<(), CliError> {
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.run_dir.join("report.html"));
    match write_report(&args.run_dir, &out) {
        Ok(kind) => {
            progress::note(format_args!(
                "wrote the report of a {} to {}",
                kind.name(),
                out.display()
            ));
            Ok(())
        }
        Err(ReportError::Write(e)) => Err(CliError::from_file(e)),
        Err(e) => Err(CliError::input(e)),
    }
}
