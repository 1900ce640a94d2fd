//! The command line (the only module that names clap). Raw arguments are validated into a
//! resolved configuration in one step, before any work starts (ripgrep's LowArgs → HiArgs).
//!
//! Exit codes: 0 success; 2 bad input (scene file, flags, output directory); 1 anything else.

mod check;
mod dataset;
pub mod embed;
mod flags;
mod locate;
mod locate_out;
mod manifest;
mod merge;
pub mod progress;
mod register;
mod report;
mod scan;
mod score;
mod study;
mod sweep;
mod verify;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// A physically based simulator of a laser-line triangulation sensor looking at glass.
#[derive(Debug, Parser)]
#[command(name = "glassscan", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands. Each accepts negative numbers as flag values (`--scan-angle-deg -5` reaches
/// the range check and its clear message, instead of clap's "unexpected argument").
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate the sensor at scan poses along the target's border and write images,
    /// profiles and a manifest.
    #[command(allow_negative_numbers = true)]
    Scan(scan::ScanArgs),
    /// Scan the target's border, pick a Border Identifier Point per profile, register them to
    /// the model by ICP and report the errors against ground truth (the paper's pipeline).
    #[command(allow_negative_numbers = true)]
    Locate(locate::LocateArgs),
    /// Register your own border points (CSV, base frame, mm) to a scene's target border by
    /// ICP from its nominal pose, and print the pose.
    #[command(allow_negative_numbers = true)]
    Register(register::RegisterArgs),
    /// Run a regression suite (validation/check/) and compare its metrics with the committed
    /// baseline; exit 1 if any regressed.
    #[command(allow_negative_numbers = true)]
    Check(check::CheckArgs),
    /// Make N samples of synthetic sensor data with exact ground truth, optionally with domain
    /// randomisation, in shards, resumable.
    #[command(allow_negative_numbers = true)]
    Dataset(dataset::DatasetArgs),
    /// Join the shard manifests of a dataset into one manifest.jsonl sorted by sample index.
    #[command(allow_negative_numbers = true)]
    Merge(merge::MergeArgs),
    /// Score your own Border Identifier Points (CSV) against a dataset's ground truth.
    #[command(allow_negative_numbers = true)]
    Score(score::ScoreArgs),
    /// Studies of the paper: `study scan-angle` runs the edge experiment (tape, cover, bare)
    /// over scan angles and reports the BIP error against ground truth.
    #[command(allow_negative_numbers = true)]
    Study(study::StudyArgs),
    /// BIP error, valid fraction, saturation and wrong-surface fraction over a grid of scan
    /// angle × exposure × threshold × peak selection, with heat maps.
    #[command(allow_negative_numbers = true)]
    Sweep(sweep::SweepArgs),
    /// Check that a dataset is complete and that every sample's files have the size and
    /// SHA-256 its manifest line records; exit 1 if anything is damaged or missing.
    #[command(allow_negative_numbers = true)]
    Verify(verify::VerifyArgs),
    /// Write one self-contained HTML page of a study, sweep, locate run or dataset directory:
    /// settings, tables, figures, and the paper's numbers beside ours.
    Report(report::ReportArgs),
}

/// A failure, with the exit code it maps to.
#[derive(Debug)]
pub struct CliError {
    /// 2 for bad input, 1 otherwise.
    pub code: u8,
    /// What went wrong (with its causes).
    pub error: anyhow::Error,
}

impl CliError {
    /// A bad-input error (exit code 2).
    pub fn input(error: impl Into<anyhow::Error>) -> Self {
        CliError {
            code: 2,
            error: error.into(),
        }
    }

    /// A file error: the file system refusing or a value that does not serialise (exit 1),
    /// or an input that is missing or not what it should be (exit 2).
    pub fn from_file(error: crate::io::FileError) -> Self {
        use crate::io::FileError as E;
        match &error {
            // A path the user named that does not exist is bad input; any other refusal of
            // the file system is not the input's fault.
            E::Io { source, .. } if source.kind() != std::io::ErrorKind::NotFound => {
                CliError::internal(error)
            }
            E::JsonWrite { .. } => CliError::internal(error),
            _ => CliError::input(error),
        }
    }

    /// A dataset error: a file error as [`CliError::from_file`] classes it; anything else is
    /// an input that is missing or not what it should be (exit 2).
    pub fn from_dataset(error: crate::dataset::DatasetError) -> Self {
        match error {
            crate::dataset::DatasetError::File(e) => CliError::from_file(e),
            other => CliError::input(other),
        }
    }

    /// An internal or I/O error (exit code 1).
    pub fn internal(error: impl Into<anyhow::Error>) -> Self {
        CliError {
            code: 1,
            error: error.into(),
        }
    }
}

/// Loads the scene file at `path` (bad input: exit code 2) and prints the loader's warnings
/// on stderr.
fn load_scene(path: &std::path::Path) -> Result<crate::scene::World, CliError> {
    let world = crate::scene::load(path).map_err(CliError::input)?;
    print_scene_warnings(&world);
    Ok(world)
}

/// The scene loader's warnings, one `warning:` line each on stderr.
fn print_scene_warnings(world: &crate::scene::World) {
    for w in &world.warnings {
        eprintln!("warning: {}: {w}", world.source.display());
    }
}

/// Prints `value` on stdout as pretty JSON (the `--json` output of every command).
fn print_json(value: &impl serde::Serialize) -> Result<(), CliError> {
    println!(
        "{}",
        serde_json::to_string_pretty(value).map_err(CliError::internal)?
    );
    Ok(())
}

/// Parses the process arguments, runs the command and maps the outcome to an exit code.
pub fn run() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help/version to stdout (exit 0) and usage errors to stderr (exit 2).
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    let outcome = match cli.command {
        Command::Scan(args) => scan::run(args),
        Command::Locate(args) => locate::run(args),
        Command::Register(args) => register::run(args),
        Command::Check(args) => check::run(args),
        Command::Dataset(args) => dataset::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Verify(args) => verify::run(args),
        Command::Score(args) => score::run(args),
        Command::Study(args) => study::run(args),
        Command::Sweep(args) => sweep::run(args),
        Command::Report(args) => report::run(args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_chain(&e.error));
            ExitCode::from(e.code)
        }
    }
}

/// The error and its causes, joined by ": ", leaving out a cause whose text the message already
/// holds (error types that print their source, like `thiserror`'s `{source}`, would otherwise
/// say it twice).
fn error_chain(error: &anyhow::Error) -> String {
    let mut message = String::new();
    for cause in error.chain() {
        let text = cause.to_string();
        if message.is_empty() {
            message = text;
        } else if !message.contains(&text) {
            message = format!("{message}: {text}");
        }
    }
    message
}

#[cfg(test)]
mod tests {
    #[test]
    fn error_chain_says_each_cause_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "No such file");
        let e = anyhow::Error::new(crate::io::FileError::Io {
            path: "x.csv".into(),
            action: "read",
            source: io,
        })
        .context("loading the BIPs");
        assert_eq!(
            super::error_chain(&e),
            "loading the BIPs: could not read x.csv: No such file"
        );
    }
}
