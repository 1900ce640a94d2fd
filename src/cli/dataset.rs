//! `glassscan dataset SCENE --count N --out DIR`: synthetic sensor data with exact ground truth
//! (the work is `dataset::generate`; this file resolves the flags and the shard).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::{flags, progress, CliError};
use crate::dataset::generate::DatasetRun;
use crate::dataset::randomize::Randomization;
use crate::dataset::scene_edit::SceneTemplate;
use crate::dataset::shard::Shard;
use crate::limits::MAX_SAMPLES;

/// Arguments of `glassscan dataset`.
#[derive(Debug, Args)]
pub struct DatasetArgs {
    /// Scene with a [target] panel: a scene file's path (TOML, scenes/README.md) or a shipped scene's name
    /// (`glassscan scenes list`); a path that exists wins.
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// Number of samples of the whole dataset (all shards), ≥ 1.
    #[arg(long, value_name = "N")]
    pub count: u64,
    /// Output directory (created if missing; see --resume).
    #[arg(long)]
    pub out: PathBuf,
    /// Master seed: sample i's draws depend only on (S, i).
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    /// Domain-randomisation ranges (TOML, `name = [min, max]` lines; see
    /// scenes/randomize_edge_study.toml, `glassscan scenes export randomize_edge_study.toml
    /// DIR`). Default: none, every sample of the scene as written.
    #[arg(long, value_name = "FILE")]
    pub randomize: Option<PathBuf>,
    /// Make only the samples i with i % N == K (0 ≤ K < N). Default: from SLURM_ARRAY_TASK_ID
    /// (with SLURM_ARRAY_TASK_COUNT or _MIN/_MAX) or JOB_COMPLETION_INDEX (with
    /// GLASSSCAN_SHARD_COUNT), else the whole dataset.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Continue a killed run in DIR: keep its finished samples, redo the others.
    #[arg(long)]
    pub resume: bool,
    /// Write `points.ply` as ASCII text instead of binary little-endian (3× larger; for
    /// readers without binary PLY).
    #[arg(long)]
    pub ply_ascii: bool,
    /// Laser photons traced per sample (1000 to 2^40). `auto`: each sample stops once its
    /// edge-line BIP has converged, after 2^17 or 2^18 photons (the default count).
    #[arg(long, value_name = "N|auto", default_value_t = flags::PhotonsArg::default())]
    pub photons: flags::PhotonsArg,
    #[command(flatten)]
    pub transport: flags::TransportArgs,
    /// Print a machine-readable summary on stdout instead of progress on stderr.
    #[arg(long)]
    pub json: bool,
}

/// Runs `glassscan dataset`.
pub fn run(args: DatasetArgs) -> Result<(), CliError> {
    let bad = flags::bad_flag;
    if !(1..=MAX_SAMPLES).contains(&args.count) {
        return Err(bad(
            "count",
            format!("must be in 1..={MAX_SAMPLES}, got {}", args.count),
        ));
    }
    let (photons, adaptive) = flags::photons(args.photons)?;
    args.transport.check()?;
    let shard = match &args.shard {
        Some(s) => Shard::parse_flag(s).map_err(CliError::input)?,
        None => Shard::from_env(|name| std::env::var(name).ok())
            .map_err(CliError::input)?
            .unwrap_or(Shard::ALL),
    };
    let scene = super::scene_path(&args.scene)?;
    let template = SceneTemplate::load(&scene).map_err(CliError::input)?;
    super::print_scene_warnings(&template.world);
    if template.world.target.is_none() {
        return Err(CliError::input(anyhow::anyhow!(
            "{}: the scene has no [target]: `dataset` needs a panel whose border it scans",
            scene.display()
        )));
    }
    let randomization = match &args.randomize {
        Some(path) => {
            let r = Randomization::load(path).map_err(CliError::input)?;
            template.check_randomization(&r).map_err(CliError::input)?;
            Some(r)
        }
        None => None,
    };
    let job = DatasetRun {
        template: &template,
        randomization: randomization.as_ref(),
        seed: args.seed,
        count: args.count,
        photons,
        adaptive,
        max_depth: args.transport.max_depth,
        ply_ascii: args.ply_ascii,
        shard,
        out: &args.out,
        resume: args.resume,
    };
    let execute = || {
        let started = Instant::now();
        let bar = progress::bar(
            shard.indices(args.count).count() as u64,
            "samples",
            args.json,
        );
        let outcome = job
            .execute(|k| bar.inc(k))
            .map_err(CliError::from_dataset)?;
        bar.finish_and_clear();
        let elapsed_s = started.elapsed().as_secs_f64();
        for d in &outcome.damage {
            eprintln!("warning: damaged sample file, made again: {d}");
        }
        for w in &outcome.warnings {
            eprintln!("warning: {w}");
        }
        if args.json {
            let summary = serde_json::json!({
                "out": args.out.display().to_string(),
                "manifest": outcome.manifest.display().to_string(),
                "shard": shard.to_string(),
                "count": args.count,
                "in_shard": outcome.in_shard,
                "kept": outcome.kept,
                "made": outcome.made,
                "damaged_samples": outcome.damaged_samples,
                "damage": outcome.damage,
                "warnings": outcome.warnings,
                "elapsed_s": elapsed_s,
            });
            super::print_json(&summary)?;
        } else {
            let remade = if outcome.damaged_samples > 0 {
                format!(" ({} of them again: damaged)", outcome.damaged_samples)
            } else {
                String::new()
            };
            eprintln!(
                "shard {shard}: made {}{remade} and kept {} of {} samples in {} ({:.1} s); \
                 manifest {}",
                outcome.made,
                outcome.kept,
                outcome.in_shard,
                args.out.display(),
                elapsed_s,
                outcome.manifest.display()
            );
        }
        Ok(())
    };
    flags::with_threads(args.transport.threads, execute)
}
