//! The commands as functions that return values instead of printing, for programs that embed
//! glassscan (the Python package in `python/`). Their arguments go through the same parsing
//! and checks as the command line's, so a bad value gets the same message and exit code.

use std::path::Path;

use clap::Parser;
use serde_json::Value;

use super::{flags, locate, register, Cli, CliError, Command};
use crate::scene::World;

pub use super::scan::{apply_overrides, SceneOverrides};

/// The message the command line prints after `error: ` for `error`.
pub fn message(error: &CliError) -> String {
    super::error_chain(&error.error)
}

/// Checks `--photons` and `--max-depth` as `scan` does; returns the photon count and whether
/// it is adaptive (`photons` is `None`: `--photons auto`).
pub fn check_light(photons: Option<u64>, max_depth: u32) -> Result<(u64, bool), CliError> {
    let budget = flags::photons(photons.map_or(flags::PhotonsArg::Auto, flags::PhotonsArg::Count))?;
    flags::TransportArgs {
        max_depth,
        threads: None,
    }
    .check()?;
    Ok(budget)
}

/// `glassscan locate SCENE FLAGS… --json` on `world`, loaded by the caller from the file that
/// `scene` names (or from text, `scene` then names it in messages): the summary it prints.
/// `flags` are the command line's (`--poses`, `12`, …); usage errors are clap's messages
/// (exit code 2).
pub fn locate(world: World, scene: &Path, flags: &[String]) -> Result<Value, CliError> {
    let mut argv = vec![
        "glassscan".to_string(),
        "locate".into(),
        scene.display().to_string(),
        "--json".into(),
    ];
    argv.extend(flags.iter().cloned());
    let cli = Cli::try_parse_from(argv).map_err(|e| CliError::input(anyhow::anyhow!("{e}")))?;
    let Command::Locate(args) = cli.command else {
        unreachable!("the first argument is `locate`")
    };
    locate::summary_on(world, &args)
}

/// `glassscan register MODEL_SCENE POINTS --json` with the points given as rows (a row
/// number, the point in the base frame in mm); `source` names the points in messages.
pub fn register(
    world: &World,
    model_scene: &Path,
    source: &Path,
    rows: &[(usize, [f64; 3])],
) -> Result<Value, CliError> {
    register::summary(world, model_scene, source, rows).map(|(value, _)| value)
}
