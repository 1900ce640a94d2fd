//! `glassscan merge DIR [DIR...] [--out DIR]`: joins the shard manifests of a dataset into one
//! `manifest.jsonl` sorted by sample index (the work is `dataset::merge`).

use std::path::PathBuf;

use clap::Args;

use super::CliError;
use crate::dataset::merge::merge;

/// Arguments of `glassscan merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Dataset directories holding shard manifests (manifest-shard-K-of-N.jsonl).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Where to write manifest.jsonl (default: the first DIR): a directory, new or of this
    /// dataset (its run.json); a manifest.jsonl with no run.json beside it is refused and left
    /// as it is. Sample directories stay where they are; lines of samples in other
    /// directories get their absolute path.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print a machine-readable summary on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `glassscan merge`.
pub fn run(args: MergeArgs) -> Result<(), CliError> {
    let out = args.out.clone().unwrap_or_else(|| args.dirs[0].clone());
    let outcome = merge(&args.dirs, &out).map_err(CliError::from_dataset)?;
    if args.json {
        super::print_json(&outcome)?;
    } else {
        eprintln!(
            "merged {} shard manifests into {} ({} samples)",
            outcome.shards.len(),
            outcome.manifest.display(),
            outcome.samples
        );
    }
    Ok(())
}
