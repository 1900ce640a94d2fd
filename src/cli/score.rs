//! `glassscan score DATASET BIPS.csv`: the user's Border Identifier Points against the
//! dataset's ground truth p_e (the work is `dataset::score`).

use std::path::PathBuf;

use clap::Args;

use super::CliError;
use crate::dataset::score::score;

/// Arguments of `glassscan score`.
#[derive(Debug, Args)]
pub struct ScoreArgs {
    /// Dataset directory with a (merged) manifest.jsonl.
    pub dataset: PathBuf,
    /// CSV with a header naming at least sample,x_mm,y_mm,z_mm (base frame, mm).
    pub bips: PathBuf,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `glassscan score`.
pub fn run(args: ScoreArgs) -> Result<(), CliError> {
    let report = score(&args.dataset, &args.bips).map_err(CliError::from_dataset)?;
    if args.json {
        super::print_json(&report)?;
        return Ok(());
    }
    let mm = |v: Option<f64>| v.map_or("–".to_owned(), |v| format!("{v:.3} mm"));
    println!("BIP error |BIP − p_e| over {} samples", report.scored);
    println!("  mean {}", mm(report.mean_mm));
    println!("  std  {}", mm(report.std_mm));
    match report.worst_sample {
        Some(s) => println!("  max  {} (sample {s})", mm(report.max_mm)),
        None => println!("  max  {}", mm(report.max_mm)),
    }
    let list = |v: &[u64]| {
        let mut s: Vec<String> = v.iter().take(20).map(u64::to_string).collect();
        if v.len() > 20 {
            s.push("…".into());
        }
        s.join(", ")
    };
    println!(
        "  samples missing a BIP: {}{}",
        report.missing.len(),
        if report.missing.is_empty() {
            String::new()
        } else {
            format!(" ({})", list(&report.missing))
        }
    );
    if !report.without_ground_truth.is_empty() {
        println!(
            "  samples without ground truth (laser plane misses the border): {} ({})",
            report.without_ground_truth.len(),
            list(&report.without_ground_truth)
        );
    }
    Ok(())
}
