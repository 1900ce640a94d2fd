//! The command line (the only module that names clap). Raw arguments are validated into a
//! resolved configuration in one step, before any work starts (ripgrep's LowArgs → HiArgs).
//!
//! Exit codes: 0 success; 2 bad input (scene file, flags, output directory, an unknown shipped
//! name); 1 anything else (a regression, a damaged dataset, an I/O failure).

mod check;
mod dataset;
mod docs;
pub mod embed;
mod flags;
mod help;
mod locate;
mod locate_out;
mod manifest;
mod merge;
pub mod progress;
mod register;
mod report;
mod scan;
mod scenes;
mod score;
mod study;
mod sweep;
mod verify;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// A physically based simulator of a laser-line triangulation sensor looking at glass.
#[derive(Debug, Parser)]
#[command(name = "glassscan", version, about, long_about = None, after_long_help = help::top())]
pub struct Cli {
    /// Print no progress and no notes (results, warnings and errors still print).
    #[arg(
        short,
        long,
        global = true,
        conflicts_with = "verbose",
        help_heading = "Global options"
    )]
    pub quiet: bool,
    /// Say more: where each scene and suite was read from (a file on disk or the copy shipped
    /// in glassscan).
    #[arg(
        short,
        long,
        global = true,
        action = clap::ArgAction::Count,
        help_heading = "Global options"
    )]
    pub verbose: u8,
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
    #[command(allow_negative_numbers = true, after_long_help = help::SCAN)]
    Scan(scan::ScanArgs),
    /// Scan the target's border, pick a Border Identifier Point per profile, register them to
    /// the model by ICP and report the errors against ground truth (the paper's pipeline).
    #[command(allow_negative_numbers = true, after_long_help = help::LOCATE)]
    Locate(locate::LocateArgs),
    /// Register your own border points (CSV, base frame, mm) to a scene's target border by
    /// ICP from its nominal pose, and print the pose.
    #[command(allow_negative_numbers = true, after_long_help = help::REGISTER)]
    Register(register::RegisterArgs),
    /// Run a regression suite (`fast` when none is named; shipped: fast, full) and compare its
    /// metrics with the committed baseline; exit 1 if any regressed.
    #[command(allow_negative_numbers = true, after_long_help = help::CHECK)]
    Check(check::CheckArgs),
    /// Make N samples of synthetic sensor data with exact ground truth, optionally with domain
    /// randomisation, in shards, resumable.
    #[command(allow_negative_numbers = true, after_long_help = help::DATASET)]
    Dataset(dataset::DatasetArgs),
    /// Join the shard manifests of a dataset into one manifest.jsonl sorted by sample index.
    #[command(allow_negative_numbers = true, after_long_help = help::MERGE)]
    Merge(merge::MergeArgs),
    /// Score your own Border Identifier Points (CSV) against a dataset's ground truth.
    #[command(allow_negative_numbers = true, after_long_help = help::SCORE)]
    Score(score::ScoreArgs),
    /// Studies of the paper: `study scan-angle` runs the edge experiment (tape, cover, bare)
    /// over scan angles and reports the BIP error against ground truth.
    #[command(allow_negative_numbers = true, after_long_help = help::STUDY)]
    Study(study::StudyArgs),
    /// BIP error, valid fraction, saturation and wrong-surface fraction over a grid of scan
    /// angle × exposure × threshold × peak selection, with heat maps.
    #[command(allow_negative_numbers = true, after_long_help = help::SWEEP)]
    Sweep(sweep::SweepArgs),
    /// Check that a dataset is complete and that every sample's files have the size and
    /// SHA-256 its manifest line records; exit 1 if anything is damaged or missing.
    #[command(allow_negative_numbers = true, after_long_help = help::VERIFY)]
    Verify(verify::VerifyArgs),
    /// List the scenes, randomisation files and suites shipped in glassscan, or export one to
    /// edit (`scenes list`, `scenes export NAME DIR`).
    #[command(after_long_help = help::SCENES)]
    Scenes(scenes::ScenesArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell) on stdout.
    #[command(after_long_help = help::COMPLETIONS)]
    Completions(docs::CompletionsArgs),
    /// Write man pages: glassscan.1 and one per subcommand, into DIR.
    #[command(after_long_help = help::MAN)]
    Man(docs::ManArgs),
    /// Write one self-contained HTML page of a study, sweep, locate run or dataset directory:
    /// settings, tables, figures, and the paper's numbers beside ours.
    #[command(after_long_help = help::REPORT)]
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
            // A path the user named that does not exist, or a text file that is not UTF-8
            // (`InvalidData` from reading it as text), is bad input; any other refusal of the
            // file system is not the input's fault.
            E::Io { source, .. }
                if !matches!(
                    source.kind(),
                    std::io::ErrorKind::NotFound | std::io::ErrorKind::InvalidData
                ) =>
            {
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

/// The scene file a SCENE argument names: the path itself when it exists, else a shipped
/// scene by name or repository path (`crate::shipped::resolve_scene`); an unknown name is bad
/// input (exit code 2) whose message lists the shipped names.
fn scene_path(arg: &std::path::Path) -> Result<std::path::PathBuf, CliError> {
    let path = crate::shipped::resolve_scene(arg).map_err(CliError::input)?;
    if crate::shipped::fallback(&path).is_some() {
        progress::detail(format_args!(
            "{}: the scene shipped in glassscan {} (no such file here; `glassscan scenes \
             export {} DIR` writes it)",
            path.display(),
            env!("CARGO_PKG_VERSION"),
            path.file_stem().and_then(|s| s.to_str()).unwrap_or("NAME")
        ));
    } else {
        progress::detail(format_args!("{}: the scene file on disk", path.display()));
    }
    Ok(path)
}

/// Loads the scene SCENE names ([`scene_path`]; bad input: exit code 2) and prints the
/// loader's warnings on stderr.
fn load_scene(arg: &std::path::Path) -> Result<crate::scene::World, CliError> {
    let world = crate::scene::load(&scene_path(arg)?).map_err(CliError::input)?;
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
    progress::set_verbosity(cli.quiet, cli.verbose);
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
        Command::Scenes(args) => scenes::run(args),
        Command::Completions(args) => docs::completions(&args),
        Command::Man(args) => docs::man(&args),
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
