//! `glassscan scan SCENE --out DIR`: simulate every scan pose and write its files.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::Args;

use super::manifest::{FileEntry, Manifest, PoseEntry, Summary};
use super::{flags, progress, CliError};
use crate::io::{exr, json, output_dir, png16, profile_csv};
use crate::scan::adaptive::StopRules;
use crate::scan::poses::plan_border_scan;
use crate::scan::simulate::simulate_pose;
use crate::scan::warnings::pose_warnings;
use crate::scan::ScanConfig;
use crate::scene;
use crate::sensor::imager::SensorKind;
use crate::sensor::SensorHead;
use crate::transport::{TraceScene, TraceSettings};

/// Arguments of `glassscan scan`.
#[derive(Debug, Args)]
pub struct ScanArgs {
    /// Scene: a scene file's path (TOML, scenes/README.md) or a shipped scene's name
    /// (`glassscan scenes list`); a path that exists wins.
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// Output directory (created if missing; must be empty unless --force).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Scan angle above the surface's tangent plane, in degrees (0 < A ≤ 90); overrides
    /// [scan].scan_angle_deg. Default: the scene's (40 in edge_study, 45 in car_side_window
    /// and flat_opaque; 45 if the scene sets none).
    #[arg(long, value_name = "A")]
    pub scan_angle_deg: Option<f64>,
    /// Number of scan poses along the border (1 to 10^6); overrides [scan].poses. Default: the
    /// scene's (4 in edge_study and flat_opaque, 12 in car_side_window; 4 if the scene sets
    /// none).
    #[arg(long, value_name = "N")]
    pub poses: Option<usize>,
    /// Exposure time in milliseconds (> 0); overrides [sensor].exposure_ms. Default: the
    /// scene's (0.5 in edge_study, 2 in car_side_window, 0.015 in flat_opaque; the preset's
    /// 0.5 if the scene sets none).
    #[arg(long, value_name = "E")]
    pub exposure_ms: Option<f64>,
    /// Peak detection threshold in DN (0 … 2^adc_bits − 1), or `auto` for the automatic
    /// threshold; overrides [sensor].threshold_dn / auto_threshold. Default: the scene's (the
    /// preset's 128 DN in every shipped scene).
    #[arg(long, value_name = "DN|auto")]
    pub threshold: Option<String>,
    /// Peak selection mode: all, first, last, largest_area, max_intensity, single; overrides
    /// [sensor].peak_select. Default: the scene's (`first`, the preset's, unless it sets
    /// one).
    #[arg(long, value_name = "MODE")]
    pub peak_select: Option<String>,
    /// Image sensor kind: cmos (clips at the full well) or ccd (excess charge bleeds along the
    /// column); overrides [sensor.imager].sensor_kind. Default: the scene's (`cmos`, the
    /// preset's, in every shipped scene).
    #[arg(long, value_name = "KIND")]
    pub sensor_kind: Option<String>,
    /// Master seed of all random numbers.
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    /// Laser photons traced per pose (1000 to 2^40); more means less Monte Carlo noise. `auto`:
    /// each pose stops once its edge-line BIP has converged, after 2^17 or 2^18 photons (the default count).
    #[arg(long, value_name = "N|auto", default_value_t = flags::PhotonsArg::default())]
    pub photons: flags::PhotonsArg,
    #[command(flatten)]
    pub transport: flags::TransportArgs,
    /// Write into a non-empty output directory (files are replaced one by one, atomically).
    #[arg(long)]
    pub force: bool,
    /// Print a machine-readable summary on stdout instead of progress on stderr.
    #[arg(long)]
    pub json: bool,
}

/// The validated run: everything resolved before any work starts.
struct RunConfig {
    world: scene::World,
    scan: ScanConfig,
    settings: TraceSettings,
    out: PathBuf,
    threads: Option<usize>,
    json: bool,
    force: bool,
}

/// The overrides of a scene's `[scan]` and `[sensor]` settings that `scan` takes as flags
/// (and the Python package as keywords), as typed: [`apply_overrides`] checks them.
#[derive(Clone, Debug, Default)]
pub struct SceneOverrides {
    /// `--scan-angle-deg`.
    pub scan_angle_deg: Option<f64>,
    /// `--poses`.
    pub poses: Option<usize>,
    /// `--exposure-ms`.
    pub exposure_ms: Option<f64>,
    /// `--threshold`: a DN value or `auto`.
    pub threshold: Option<String>,
    /// `--peak-select`.
    pub peak_select: Option<String>,
    /// `--sensor-kind`: `cmos` or `ccd`.
    pub sensor_kind: Option<String>,
}

/// Applies `overrides` to `world` (its `scan` settings included), each checked with the
/// message its flag gives (exit code 2).
pub fn apply_overrides(
    world: &mut scene::World,
    overrides: &SceneOverrides,
) -> Result<(), CliError> {
    let bad = flags::bad_flag;
    if let Some(a) = overrides.scan_angle_deg {
        world.scan.scan_angle_rad = flags::scan_angle_rad(a)?;
    }
    if let Some(n) = overrides.poses {
        world.scan.poses = flags::poses("poses", n, 1, "")?;
    }
    if let Some(e) = overrides.exposure_ms {
        world.sensor.imager.exposure_s = flags::exposure_s(e)?;
    }
    let max_dn = world.sensor.imager.max_dn();
    if let Some(t) = &overrides.threshold {
        world.sensor.firmware.threshold = flags::threshold(t, max_dn)?;
    }
    if let Some(m) = &overrides.peak_select {
        world.sensor.firmware.peak_select = flags::peak_select(m)?;
    }
    if let Some(k) = &overrides.sensor_kind {
        world.sensor.imager.kind = match k.to_ascii_lowercase().as_str() {
            "cmos" => SensorKind::Cmos,
            "ccd" => SensorKind::Ccd,
            _ => {
                return Err(bad(
                    "sensor-kind",
                    format!("must be `cmos` or `ccd`, got {k:?}"),
                ))
            }
        };
    }
    Ok(())
}

fn resolve(mut args: ScanArgs) -> Result<RunConfig, CliError> {
    args.scene = super::scene_path(&args.scene)?;
    let mut world = super::load_scene(&args.scene)?;
    let overrides = SceneOverrides {
        scan_angle_deg: args.scan_angle_deg,
        poses: args.poses,
        exposure_ms: args.exposure_ms,
        threshold: args.threshold.clone(),
        peak_select: args.peak_select.clone(),
        sensor_kind: args.sensor_kind.clone(),
    };
    apply_overrides(&mut world, &overrides)?;
    let scan = world.scan;
    let (photons, adaptive) = flags::photons(args.photons)?;
    args.transport.check()?;
    if world.target.is_none() {
        return Err(CliError::input(anyhow::anyhow!(
            "{}: the scene has no [target]: `scan` needs a panel whose border it scans",
            args.scene.display()
        )));
    }
    Ok(RunConfig {
        world,
        scan,
        settings: TraceSettings {
            photons,
            adaptive,
            max_depth: args.transport.max_depth,
            seed: args.seed,
        },
        out: args.out,
        threads: args.transport.threads,
        json: args.json,
        force: args.force,
    })
}

/// Runs `glassscan scan`.
pub fn run(args: ScanArgs) -> Result<(), CliError> {
    let cfg = resolve(args)?;
    flags::with_threads(cfg.threads, || execute(&cfg))
}

fn execute(cfg: &RunConfig) -> Result<(), CliError> {
    let started = Instant::now();
    let world = &cfg.world;
    let head = SensorHead::new(&world.sensor)
        .with_context(|| format!("{}: [sensor]", world.source.display()))
        .map_err(CliError::input)?;
    let trace_scene = TraceScene::new(world).map_err(CliError::input)?;
    output_dir::prepare_output_dir(&cfg.out, cfg.force).map_err(CliError::input)?;

    let border_b = world
        .true_border_in_base()
        .expect("resolve() checked the target");
    let poses = plan_border_scan(&border_b, &cfg.scan, &world.mount);
    let adc_bits = world.sensor.imager.adc_bits;

    let mut entries = Vec::with_capacity(poses.len());
    let mut written = std::collections::BTreeSet::from(["manifest.json".to_string()]);
    let bar = progress::bar(poses.len() as u64, "poses", cfg.json);
    for pose in &poses {
        let result = simulate_pose(
            &trace_scene,
            &head,
            pose,
            &cfg.settings,
            StopRules::EDGE_LINE,
        );
        let stem = format!("pose_{:03}", pose.index);
        let png = format!("{stem}.png");
        let exr_name = format!("{stem}.exr");
        let csv = format!("{stem}_profile.csv");
        png16::write_sensor_png16(&cfg.out.join(&png), &result.image, adc_bits)
            .map_err(CliError::internal)?;
        let notes = exr::IrradianceNotes {
            wavelength_m: world.sensor.laser.wavelength_m,
            exposure_s: world.sensor.imager.exposure_s,
            sensor_to_base: pose.sensor,
        };
        exr::write_irradiance_exr(&cfg.out.join(&exr_name), &result.irradiance, &notes)
            .map_err(CliError::internal)?;
        profile_csv::write_profile_csv(&cfg.out.join(&csv), &result.profile)
            .map_err(CliError::internal)?;
        written.extend([png.clone(), exr_name.clone(), csv.clone()]);
        let warnings = pose_warnings(&result, &world.sensor.range);
        for w in &warnings {
            bar.suspend(|| eprintln!("warning: {w}"));
        }
        let entry = PoseEntry::new(
            &result,
            vec![
                FileEntry::new("image", &png, "16-bit PNG, DN << (16 − adc_bits)"),
                FileEntry::new(
                    "irradiance",
                    &exr_name,
                    "EXR, f32 channels in W/m²: `irradiance` (total) and `class.<path class>`",
                ),
                FileEntry::new("profile", &csv, "CSV profile in the sensor frame, mm"),
            ],
            warnings,
        );
        let detail = format!(
            "{} of {} profile points valid, p_e = ({:.2}, {:.2}, {:.2}) mm",
            entry.valid_points,
            result.profile.points.len(),
            entry.edge_point_mm[0],
            entry.edge_point_mm[1],
            entry.edge_point_mm[2],
        );
        bar.done(&stem, Some(&detail));
        entries.push(entry);
    }
    bar.finish_and_clear();

    let manifest = Manifest::new(world, &cfg.scan, &cfg.settings, entries, started.elapsed());
    let manifest_path = cfg.out.join("manifest.json");
    json::write_json_pretty(&manifest_path, &manifest).map_err(CliError::internal)?;
    // A --force run into an earlier run's directory leaves only its own files.
    let removed =
        output_dir::remove_stale(&cfg.out, is_scan_output, &written).map_err(CliError::internal)?;
    if !removed.is_empty() {
        eprintln!(
            "removed {} file(s) of the earlier run in {} that this run does not write ({}{})",
            removed.len(),
            display(&cfg.out),
            removed[..removed.len().min(3)].join(", "),
            if removed.len() > 3 { ", …" } else { "" }
        );
    }
    if cfg.json {
        let summary = Summary::new(&manifest, &cfg.out, &manifest_path);
        super::print_json(&summary)?;
    } else if !progress::is_quiet() {
        eprintln!(
            "wrote {} poses to {} in {:.2} s",
            manifest.poses.len(),
            display(&cfg.out),
            manifest.elapsed_s
        );
    }
    Ok(())
}

/// Whether `name` is a file `scan` writes: `pose_NNN.png`, `pose_NNN.exr`,
/// `pose_NNN_profile.csv` (NNN: three or more digits).
fn is_scan_output(name: &str) -> bool {
    let Some(rest) = name.strip_prefix("pose_") else {
        return false;
    };
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    digits >= 3 && matches!(&rest[digits..], ".png" | ".exr" | "_profile.csv")
}

fn display(p: &Path) -> String {
    p.display().to_string()
}
