//! `glassscan check [SUITE] [--json] [--update-baseline]`: runs a regression suite (`fast`
//! when none is named) and compares its metrics with the committed baseline (see
//! `crate::check`). Exit 0 when nothing regressed, 1 when something did, 2 for a bad suite or
//! scene. Shipped suites run from any directory (`crate::shipped`).

use std::time::Instant;

use clap::Args;
use serde_json::json;

use super::{flags, progress, CliError};
use crate::check::baseline::{read_baseline, write_baseline, Baseline};
use crate::check::case::run_case;
use crate::check::compare::{compare, table, Verdict};
use crate::check::suite::load_suite;
use crate::shipped::{self, resolve_suite};

/// Arguments of `glassscan check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// A shipped suite's name, `fast` (the subset CI runs, ~1 min) or `full` (~10 min), or a
    /// suite file's path. A name reads validation/check/NAME.toml from disk when it exists
    /// (the repository root) and the copy shipped in glassscan elsewhere.
    #[arg(value_name = "SUITE", default_value = "fast")]
    pub suite: String,
    /// Print the comparison as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write the current metrics as the new baseline, NAME.baseline.json next to the suite
    /// file (after a change that is meant; not for a shipped copy: run from the repository
    /// root).
    #[arg(long)]
    pub update_baseline: bool,
}

/// Runs `glassscan check`.
pub fn run(args: CheckArgs) -> Result<(), CliError> {
    let path = resolve_suite(&args.suite).map_err(CliError::input)?;
    let suite = load_suite(&path).map_err(CliError::input)?;
    let baseline_path = suite.baseline_path();
    match shipped::fallback(&path) {
        Some(_) if args.update_baseline => {
            return Err(flags::bad_flag(
                "update-baseline",
                format!(
                    "writes {} next to the suite, but {} is not on disk here (the suite is \
                     the copy shipped in glassscan): run from the repository root or give the \
                     suite file's path",
                    baseline_path.display(),
                    path.display()
                ),
            ));
        }
        Some(_) => progress::detail(format_args!(
            "{}: not on disk here; running the copy shipped in glassscan {}",
            path.display(),
            env!("CARGO_PKG_VERSION")
        )),
        None => progress::detail(format_args!("suite {}", path.display())),
    }
    let baseline = read_baseline(&baseline_path).map_err(CliError::input)?;
    let bar = progress::bar(suite.cases.len() as u64, "cases", args.json);
    let mut rows = Vec::new();
    let mut current = Baseline {
        glassscan_version: env!("CARGO_PKG_VERSION").to_string(),
        ..Default::default()
    };
    let started = Instant::now();
    for case in &suite.cases {
        bar.set_message(case.name.clone());
        let metrics = run_case(case).map_err(CliError::input)?;
        rows.extend(compare(
            &case.name,
            &metrics,
            baseline.cases.get(&case.name),
            &case.tolerance,
        ));
        current.cases.insert(case.name.clone(), metrics);
        bar.done(&case.name, None);
    }
    bar.finish_and_clear();
    let count = |v: Verdict| rows.iter().filter(|r| r.verdict == v).count();
    let (regressed, improved, new) = (
        count(Verdict::Regressed),
        count(Verdict::Improved),
        count(Verdict::New),
    );
    if args.update_baseline {
        write_baseline(&baseline_path, &current).map_err(CliError::internal)?;
    }
    if args.json {
        let v = json!({
            "suite": path.display().to_string(),
            "baseline": baseline_path.display().to_string(),
            "rows": rows,
            "regressed": regressed,
            "improved": improved,
            "new": new,
            "baseline_updated": args.update_baseline,
            "seconds": started.elapsed().as_secs_f64(),
        });
        super::print_json(&v)?;
    } else {
        print!("{}", table(&rows, false));
        eprintln!(
            "{} cases in {:.1} s: {regressed} regressed, {improved} improved, {new} new (baseline {})",
            suite.cases.len(),
            started.elapsed().as_secs_f64(),
            baseline_path.display()
        );
        if args.update_baseline {
            eprintln!("baseline written: {}", baseline_path.display());
        } else if improved + new > 0 {
            eprintln!("run with --update-baseline to record the improved and new values");
        }
    }
    if regressed > 0 && !args.update_baseline {
        return Err(CliError::internal(anyhow::anyhow!(
            "{regressed} metric(s) regressed against {}",
            baseline_path.display()
        )));
    }
    Ok(())
}
