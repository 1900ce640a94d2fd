//! `glassscan verify DIR`: checks that a dataset is complete and that every finished sample's
//! files are what its manifest line records (the work is `dataset::verify`).
//!
//! Exit codes: 0 complete and intact, 1 damaged or incomplete (each damaged file is printed),
//! 2 not a dataset or an unreadable manifest.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::CliError;
use crate::dataset::verify::verify_dataset;

/// Arguments of `glassscan verify`.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// Dataset directory (holding run.json and manifest.jsonl or shard manifests).
    pub dir: PathBuf,
    /// Print a machine-readable report on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `glassscan verify`.
pub fn run(args: VerifyArgs) -> Result<(), CliError> {
    let started = Instant::now();
    let report = verify_dataset(&args.dir).map_err(CliError::from_dataset)?;
    let elapsed_s = started.elapsed().as_secs_f64();
    if args.json {
        super::print_json(&serde_json::json!({
            "dir": args.dir.display().to_string(),
            "ok": report.is_ok(),
            "report": report,
            "elapsed_s": elapsed_s,
        }))?;
    } else {
        for d in &report.damage {
            println!("damaged: {d}");
        }
        if report.missing > 0 {
            let listed: Vec<String> = report.missing_first.iter().map(u64::to_string).collect();
            let more = if report.missing > report.missing_first.len() as u64 {
                ", …"
            } else {
                ""
            };
            println!(
                "missing: {} of {} samples are in no manifest: {}{more}",
                report.missing,
                report.count,
                listed.join(", ")
            );
        }
        if !report.duplicated.is_empty() {
            let listed: Vec<String> = report.duplicated.iter().map(u64::to_string).collect();
            println!("listed more than once: {}", listed.join(", "));
        }
        eprintln!(
            "{}: {} samples ({} files, {:.1} MB) checked in {:.1} s: {} damaged, {} missing",
            args.dir.display(),
            report.samples,
            report.files,
            report.bytes as f64 / 1e6,
            elapsed_s,
            report.damaged_samples,
            report.missing
        );
    }
    if report.is_ok() {
        Ok(())
    } else {
        Err(CliError {
            code: 1,
            error: anyhow::anyhow!(
                "{}: {} damaged and {} missing of {} samples (remake them with `glassscan \
                 dataset … --resume`)",
                args.dir.display(),
                report.damaged_samples,
                report.missing,
                report.count
            ),
        })
    }
}
