//! `glassscan sweep SCENE --scan-angle-deg LIST --exposure-ms LIST …`: the BIP error, valid
//! fraction, saturation and wrong-surface fraction over a grid of settings (`study::sweep`),
//! with heat maps of the BIP error over scan angle × exposure.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::Args;
use serde_json::json;

use super::{flags, progress, CliError};
use crate::io::{atomic::write_atomic, json as json_file, output_dir};
use crate::plot::heat_map::HeatMap;
use crate::plot::save;
use crate::sensor::SensorHead;
use crate::study::as_typed;
use crate::study::grid::{threshold_name, SweepGrid};
use crate::study::sweep::{run_sweep, CellResult};
use crate::study::sweep_report::{cells_csv, cells_json};
use crate::study::tally::RULES;
use crate::transport::{TraceScene, TraceSettings};

/// Arguments of `glassscan sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Scene with a [target] panel: a scene file's path (TOML, scenes/README.md) or a shipped scene's name
    /// (`glassscan scenes list`); a path that exists wins.
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// Scan angles, comma-separated degrees, each in (0, 90].
    #[arg(long, value_name = "LIST", required = true)]
    pub scan_angle_deg: String,
    /// Exposure times, comma-separated milliseconds, each > 0.
    #[arg(long, value_name = "LIST", required = true)]
    pub exposure_ms: String,
    /// Peak detection thresholds, comma-separated: DN values in [0, 2^adc_bits − 1] or `auto`.
    /// Default: the scene's.
    #[arg(long, value_name = "LIST")]
    pub threshold: Option<String>,
    /// Peak selection modes, comma-separated: all, first, last, largest_area, max_intensity,
    /// single. Default: the scene's.
    #[arg(long, value_name = "LIST")]
    pub peak_select: Option<String>,
    /// Scan poses along the border per angle (1 to 10^6); overrides [scan].poses. Default: the
    /// scene's (4 in edge_study, 12 in car_side_window; 4 if the scene sets none).
    #[arg(long, value_name = "N")]
    pub poses: Option<usize>,
    #[command(flatten)]
    pub light: flags::LightArgs,
    #[command(flatten)]
    pub output: flags::OutArgs,
    /// Print the table as JSON on stdout (and no progress).
    #[arg(long)]
    pub json: bool,
}

/// Runs `glassscan sweep`.
pub fn run(mut args: SweepArgs) -> Result<(), CliError> {
    let started = Instant::now();
    args.scene = super::scene_path(&args.scene)?;
    let angles_rad = flags::list("scan-angle-deg", &args.scan_angle_deg, |s| {
        flags::scan_angle_rad(flags::number("scan-angle-deg", s)?)
    })?;
    let exposures_s = flags::list("exposure-ms", &args.exposure_ms, |s| {
        flags::exposure_s(flags::number("exposure-ms", s)?)
    })?;
    let peak_selects = match &args.peak_select {
        Some(l) => Some(flags::list("peak-select", l, flags::peak_select)?),
        None => None,
    };
    if let Some(n) = args.poses {
        flags::poses("poses", n, 1, "")?;
    }
    let (photons, adaptive) = flags::photons(args.light.photons)?;

    let world = super::load_scene(&args.scene)?;
    let max_dn = world.sensor.imager.max_dn();
    let thresholds = match &args.threshold {
        Some(l) => flags::list("threshold", l, |t| flags::threshold(t, max_dn))?,
        None => vec![world.sensor.firmware.threshold],
    };
    let grid = SweepGrid {
        angles_rad,
        exposures_s,
        thresholds,
        peak_selects: peak_selects.unwrap_or_else(|| vec![world.sensor.firmware.peak_select]),
    };
    let Some(border_b) = world.true_border_in_base() else {
        return Err(CliError::input(anyhow::anyhow!(
            "{}: the scene has no [target]: `sweep` needs a panel whose border it scans",
            args.scene.display()
        )));
    };
    let head = SensorHead::new(&world.sensor)
        .with_context(|| format!("{}: [sensor]", world.source.display()))
        .map_err(CliError::input)?;
    let trace_scene = TraceScene::new(&world).map_err(CliError::input)?;
    if let Some(out) = &args.output.out {
        output_dir::prepare_output_dir(out, args.output.force).map_err(CliError::input)?;
    }
    let mut scan = world.scan;
    if let Some(n) = args.poses {
        scan.poses = n;
    }
    let trace = TraceSettings {
        photons,
        adaptive,
        max_depth: 64,
        seed: args.light.seed,
    };

    let bar = progress::bar(
        (grid.angles_rad.len() * scan.poses) as u64,
        "poses",
        args.json,
    );
    let cells = run_sweep(
        &trace_scene,
        &head,
        &border_b,
        &world.mount,
        &scan,
        &grid,
        &trace,
        &|| bar.inc(1),
    );
    bar.finish_and_clear();
    let elapsed_s = started.elapsed().as_secs_f64();

    let mut files = Vec::new();
    if let Some(out) = &args.output.out {
        files = write_outputs(out, &grid, &cells).map_err(CliError::internal)?;
    }
    let run = json!({
        "scene": args.scene.display().to_string(),
        "poses": scan.poses,
        "photons": trace.photons,
        "seed": trace.seed,
        "wrong_surface_rule": "valid points labelled through_glass, glint or internal_reflection / valid points",
        "files": files,
        "elapsed_s": elapsed_s,
    });
    let table = cells_json(&grid, &cells, run);
    if let Some(out) = &args.output.out {
        json_file::write_json_pretty(&out.join("cells.json"), &table)
            .map_err(CliError::internal)?;
    }
    if args.json {
        super::print_json(&table)?;
    } else {
        eprint!("{}", cells_csv(&grid, &cells));
        eprintln!(
            "{} cells, {} traced poses in {:.1} s",
            cells.len(),
            grid.angles_rad.len() * scan.poses,
            elapsed_s
        );
    }
    Ok(())
}

/// Writes cells.csv and one heat map per threshold × peak selection × BIP rule; returns the
/// file names (cells.json is written after, by the caller).
fn write_outputs(
    out: &Path,
    grid: &SweepGrid,
    cells: &[CellResult],
) -> anyhow::Result<Vec<String>> {
    let mut files = vec!["cells.csv".to_owned()];
    let csv = cells_csv(grid, cells);
    write_atomic(&out.join("cells.csv"), |w| w.write_all(csv.as_bytes()))?;
    for (ti, t) in grid.thresholds.iter().enumerate() {
        for (pi, p) in grid.peak_selects.iter().enumerate() {
            for (k, rule) in RULES.iter().enumerate() {
                let value = |ai: usize, ei: usize| -> f64 {
                    cells
                        .iter()
                        .find(|c| {
                            let c = &c.cell;
                            (c.angle, c.exposure, c.threshold, c.peak_select) == (ai, ei, ti, pi)
                        })
                        .map_or(f64::NAN, |c| c.rules[k].error_mm.mean)
                };
                let fig = HeatMap {
                    title: format!(
                        "Mean BIP error ({} rule), threshold {}, peak select {}",
                        rule.name(),
                        threshold_name(t),
                        p.name()
                    ),
                    x_desc: "scan angle (deg)".into(),
                    x_labels: grid
                        .angles_rad
                        .iter()
                        .map(|a| format!("{}", as_typed(a.to_degrees())))
                        .collect(),
                    y_desc: "exposure (ms)".into(),
                    y_labels: grid
                        .exposures_s
                        .iter()
                        .map(|e| format!("{}", as_typed(e * 1e3)))
                        .collect(),
                    values: (0..grid.exposures_s.len())
                        .map(|ei| (0..grid.angles_rad.len()).map(|ai| value(ai, ei)).collect())
                        .collect(),
                    value_desc: "mean |BIP − p_e| (mm)".into(),
                    marked: Vec::new(),
                };
                let stem = format!(
                    "heat_{}_threshold-{}_{}",
                    rule.name(),
                    threshold_name(t),
                    p.name()
                );
                save(&fig, out, &stem)?;
                files.extend([format!("{stem}.png"), format!("{stem}.svg")]);
            }
        }
    }
    files.push("cells.json".into());
    Ok(files)
}
