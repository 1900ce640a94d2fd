//! `glassscan study scan-angle [SCENE]`: the paper's edge experiment (tape, cover, bare) at
//! several scan angles and positions, the BIP error by both rules, and the BIP-error curve over
//! a sweep of scan angles (`study::scan_angle`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Subcommand};
use serde_json::{json, Value};

use super::{flags, progress, CliError};
use crate::dataset::scene_edit::SceneTemplate;
use crate::io::{atomic::write_atomic, json as json_file, output_dir};
use crate::plot::edge_scatter::EdgeScatter;
use crate::plot::save;
use crate::scene;
use crate::sensor::SensorHead;
use crate::shipped;
use crate::study::as_typed;
use crate::study::finding_map::{run_finding_map, FindingMapConfig, MapCell};
use crate::study::finding_map_report::{map_csv, map_heat_maps, map_json};
use crate::study::scan_angle::{
    run_scan_angle_study, ScanAngleConfig, ScanAngleStudy, Variant, VariantSetup,
};
use crate::study::scan_angle_report::{
    bip_curve_figure, exposure_csv, exposure_heat_maps, points_csv, summary_csv, summary_json,
    sweep_csv,
};
use crate::transport::{TraceScene, TraceSettings};

/// Arguments of `glassscan study`.
#[derive(Debug, Args)]
pub struct StudyArgs {
    /// Which study.
    #[command(subcommand)]
    pub study: StudyCommand,
}

/// The studies.
#[derive(Debug, Subcommand)]
pub enum StudyCommand {
    /// The paper's edge experiment (Section III-C, Figs. 6–7): tape, cover and bare pane at
    /// several scan angles; points in the edge frame of p_e, BIP errors by both rules, and the
    /// BIP error over a sweep of scan angles.
    #[command(allow_negative_numbers = true, after_long_help = super::help::STUDY_SCAN_ANGLE)]
    ScanAngle(ScanAngleArgs),
}

/// Arguments of `glassscan study scan-angle`.
#[derive(Debug, Args)]
pub struct ScanAngleArgs {
    /// The bare-pane scene: a file's path or a shipped scene's name (a path that exists wins;
    /// the default is the shipped edge_study, from any directory). The tape and cover variants
    /// are its siblings `<stem>_tape.toml` and `<stem>_cover.toml` (a trailing `_bare` of the
    /// stem is dropped first); a missing sibling is skipped, with a note.
    #[arg(value_name = "SCENE", default_value = "scenes/edge_study.toml")]
    pub scene: PathBuf,
    /// Scan angles of the edge plots, comma-separated degrees, each in (0, 90].
    #[arg(long, value_name = "LIST", default_value = "10,40,45")]
    pub angles_deg: String,
    /// Positions along the border per angle (≥ 1), spread evenly from the scene's start.
    #[arg(long, value_name = "N", default_value_t = 12)]
    pub positions: usize,
    /// Scan angles of the BIP-error curve (bare pane), START:STOP:STEP in degrees.
    #[arg(long, value_name = "START:STOP:STEP", default_value = "5:85:5")]
    pub sweep_deg: String,
    /// Skip the BIP-error curve.
    #[arg(long)]
    pub no_sweep: bool,
    /// The exposure axis: exposures (ms, comma-separated) at which every bare-pane pose is
    /// also sensed (the light is traced once). Around the scanCONTROL driver's default 0.5 ms.
    #[arg(long, value_name = "LIST", default_value = "0.15,0.5,1.5")]
    pub exposures_ms: String,
    /// Arris face widths (mm, both corners; 0 = flat ground) of the finding map.
    #[arg(long, value_name = "LIST", default_value = "0,0.4,0.8,1.2,1.6")]
    pub map_arris_mm: String,
    /// Edge roughness values (GGX α) of the finding map.
    #[arg(long, value_name = "LIST", default_value = "0.1,0.3,0.6,1")]
    pub map_roughness: String,
    /// The shallow and the steep scan angle the map compares (deg): the paper's 10° and 40°.
    #[arg(long, value_name = "A,B", default_value = "10,40")]
    pub map_angles_deg: String,
    /// Positions along the border per map cell and angle (≥ 1).
    #[arg(long, value_name = "N", default_value_t = 4)]
    pub map_positions: usize,
    /// Skip the finding map.
    #[arg(long)]
    pub no_map: bool,
    #[command(flatten)]
    pub light: flags::LightArgs,
    #[command(flatten)]
    pub output: flags::OutArgs,
    /// Print the summary as JSON on stdout (and no progress).
    #[arg(long)]
    pub json: bool,
}

/// Runs `glassscan study …`.
pub fn run(args: StudyArgs) -> Result<(), CliError> {
    match args.study {
        StudyCommand::ScanAngle(a) => run_scan_angle(a),
    }
}

/// The sibling scene of `variant` next to the bare scene `bare`.
fn sibling(bare: &Path, variant: Variant) -> PathBuf {
    let stem = bare.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    let stem = stem.strip_suffix("_bare").unwrap_or(stem);
    bare.with_file_name(format!("{stem}_{}.toml", variant.name()))
}

/// Loads a variant's scene and prepares it for tracing.
fn setup(path: &Path, variant: Variant) -> Result<(VariantSetup, scene::World), CliError> {
    let world = super::load_scene(path)?;
    let Some(border_b) = world.true_border_in_base() else {
        return Err(CliError::input(anyhow::anyhow!(
            "{}: the scene has no [target]: `study scan-angle` needs a panel whose border it scans",
            path.display()
        )));
    };
    let head = SensorHead::new(&world.sensor)
        .with_context(|| format!("{}: [sensor]", path.display()))
        .map_err(CliError::input)?;
    let scene = TraceScene::new(&world).map_err(CliError::input)?;
    let s = VariantSetup {
        variant,
        scene,
        head,
        border_b,
        mount: world.mount,
    };
    Ok((s, world))
}

fn run_scan_angle(mut args: ScanAngleArgs) -> Result<(), CliError> {
    let started = Instant::now();
    // Every flag is checked before any scene is loaded or any work starts.
    let angles_rad = flags::list("angles-deg", &args.angles_deg, |s| {
        flags::angle_rad("angles-deg", flags::number("angles-deg", s)?)
    })?;
    let sweep_rad = if args.no_sweep {
        Vec::new()
    } else {
        flags::angle_range_rad("sweep-deg", &args.sweep_deg)?
    };
    flags::poses("positions", args.positions, 1, "")?;
    let exposures_s = flags::list("exposures-ms", &args.exposures_ms, |s| {
        let ms = flags::number("exposures-ms", s)?;
        if ms.is_finite() && ms > 0.0 {
            Ok(ms * 1e-3)
        } else {
            Err(flags::bad_flag(
                "exposures-ms",
                format!("must be > 0, got {ms}"),
            ))
        }
    })?;
    let map = if args.no_map {
        None
    } else {
        Some(map_settings(&args)?)
    };
    let (photons, adaptive) = flags::photons(args.light.photons)?;
    args.scene = super::scene_path(&args.scene)?;

    let (bare, bare_world) = setup(&args.scene, Variant::Bare)?;
    let mut setups = Vec::new();
    let mut notes = Vec::new();
    let mut scenes = serde_json::Map::new();
    for v in [Variant::Tape, Variant::Cover] {
        let path = sibling(&args.scene, v);
        if shipped::is_file(&path) {
            setups.push(setup(&path, v)?.0);
            scenes.insert(v.name().into(), json!(path.display().to_string()));
        } else {
            notes.push(format!(
                "no {} variant: {} does not exist; running without it",
                v.name(),
                path.display()
            ));
            scenes.insert(v.name().into(), Value::Null);
        }
    }
    setups.push(bare);
    scenes.insert("bare".into(), json!(args.scene.display().to_string()));
    if let Some(out) = &args.output.out {
        output_dir::prepare_output_dir(out, args.output.force).map_err(CliError::input)?;
    }
    if !args.json {
        for n in &notes {
            progress::note(n);
        }
    }

    let cfg = ScanAngleConfig {
        angles_rad,
        sweep_rad,
        exposures_s: exposures_s.clone(),
        scan: crate::scan::ScanConfig {
            poses: args.positions,
            ..bare_world.scan
        },
        trace: TraceSettings {
            photons,
            adaptive,
            max_depth: 64,
            seed: args.light.seed,
        },
    };
    let map_cfg = map.map(|m| FindingMapConfig {
        arris_widths_mm: m.arris_widths_mm,
        roughness: m.roughness,
        angles_rad: m.angles_rad,
        exposures_s: exposures_s.clone(),
        scan: crate::scan::ScanConfig {
            poses: args.map_positions,
            ..bare_world.scan
        },
        trace: cfg.trace,
    });
    let template = match &map_cfg {
        Some(_) => Some(SceneTemplate::load(&args.scene).map_err(CliError::input)?),
        None => None,
    };
    let total = cfg.simulations(setups.len()) + map_cfg.as_ref().map_or(0, |m| m.simulations());
    let bar = progress::bar(total as u64, "poses", args.json);
    let study = run_scan_angle_study(&setups, &cfg, &|| bar.inc(1));
    let map_cells = match (&map_cfg, &template) {
        (Some(m), Some(t)) => Some(
            run_finding_map(t, m, &|| bar.inc(1))
                .map_err(|e| CliError::input(anyhow::anyhow!("{}: {e}", args.scene.display())))?,
        ),
        _ => None,
    };
    bar.finish_and_clear();
    let simulated_s = started.elapsed().as_secs_f64();

    let exposures_ms: Vec<f64> = exposures_s.iter().map(|e| as_typed(e * 1e3)).collect();
    let mut files = Vec::new();
    if let Some(out) = &args.output.out {
        files = write_outputs(out, &study, &exposures_ms).map_err(CliError::internal)?;
        if let (Some(m), Some(cells)) = (&map_cfg, &map_cells) {
            files.extend(write_map(out, m, cells).map_err(CliError::internal)?);
        }
        files.push("summary.json".into());
    }
    let run = json!({
        "scene": args.scene.display().to_string(),
        "scenes": scenes,
        "notes": notes,
        "positions": cfg.scan.poses,
        "photons": cfg.trace.photons,
        "seed": cfg.trace.seed,
        "sweep_deg": cfg.sweep_rad.iter().map(|a| as_typed(a.to_degrees())).collect::<Vec<_>>(),
        "exposure_ms": as_typed(bare_world.sensor.imager.exposure_s * 1e3),
        "exposures_ms": exposures_ms,
        "finding_map": match (&map_cfg, &map_cells) {
            (Some(m), Some(c)) => map_json(m, c),
            _ => Value::Null,
        },
        "files": files,
        "elapsed_s": simulated_s,
    });
    let summary = summary_json(&study, run);
    if let Some(out) = &args.output.out {
        json_file::write_json_pretty(&out.join("summary.json"), &summary)
            .map_err(CliError::internal)?;
    }
    if args.json {
        super::print_json(&summary)?;
    } else {
        print_table(&study, &exposures_ms);
        if let (Some(m), Some(c)) = (&map_cfg, &map_cells) {
            print_map(m, c);
        }
        eprintln!("{total} poses simulated in {simulated_s:.1} s");
    }
    Ok(())
}

/// The finding map's axes as given by its flags.
struct MapAxes {
    arris_widths_mm: Vec<f64>,
    roughness: Vec<f64>,
    angles_rad: [f64; 2],
}

/// The finding map's flags: arris widths, roughness values, the two angles.
fn map_settings(args: &ScanAngleArgs) -> Result<MapAxes, CliError> {
    let widths = flags::list("map-arris-mm", &args.map_arris_mm, |s| {
        let w = flags::number("map-arris-mm", s)?;
        if w.is_finite() && w >= 0.0 {
            Ok(w)
        } else {
            Err(flags::bad_flag(
                "map-arris-mm",
                format!("must be ≥ 0, got {w}"),
            ))
        }
    })?;
    let roughness = flags::list("map-roughness", &args.map_roughness, |s| {
        let a = flags::number("map-roughness", s)?;
        if a.is_finite() && a > 0.0 {
            Ok(a)
        } else {
            Err(flags::bad_flag(
                "map-roughness",
                format!("must be > 0, got {a}"),
            ))
        }
    })?;
    let angles = flags::list("map-angles-deg", &args.map_angles_deg, |s| {
        flags::angle_rad("map-angles-deg", flags::number("map-angles-deg", s)?)
    })?;
    let [lo, hi] = angles[..] else {
        return Err(flags::bad_flag(
            "map-angles-deg",
            format!("expects two angles, got {:?}", args.map_angles_deg),
        ));
    };
    flags::poses("map-positions", args.map_positions, 1, "")?;
    Ok(MapAxes {
        arris_widths_mm: widths,
        roughness,
        angles_rad: [lo, hi],
    })
}

/// Writes the finding map's CSV and heat maps; returns the file names.
fn write_map(out: &Path, cfg: &FindingMapConfig, cells: &[MapCell]) -> anyhow::Result<Vec<String>> {
    write_atomic(&out.join("finding_map.csv"), |w| {
        w.write_all(map_csv(cfg, cells).as_bytes())
    })?;
    let mut files = vec!["finding_map.csv".to_owned()];
    for (stem, fig) in map_heat_maps(cfg, cells) {
        save(&fig, out, &stem)?;
        files.extend([format!("{stem}.png"), format!("{stem}.svg")]);
    }
    Ok(files)
}

/// The map on stderr: per exposure and rule, the 10°/40° ratio per cell and whether it holds.
fn print_map(cfg: &FindingMapConfig, cells: &[MapCell]) {
    let [lo, hi] = cfg.angles_rad.map(|a| as_typed(a.to_degrees()));
    for (e, exposure_s) in cfg.exposures_s.iter().enumerate() {
        for k in 0..2 {
            eprintln!(
                "finding map, {} rule, {} ms: BIP error at {lo}° / at {hi}° (* = holds)",
                crate::study::tally::RULES[k].name(),
                as_typed(exposure_s * 1e3)
            );
            for &alpha in &cfg.roughness {
                let row: Vec<String> = cfg
                    .arris_widths_mm
                    .iter()
                    .map(|&w| {
                        let c = cells
                            .iter()
                            .find(|c| c.arris_width_mm == w && c.roughness == alpha);
                        c.map_or("–".into(), |c| {
                            let mark = if c.holds(e, k) == Some(true) {
                                "*"
                            } else {
                                " "
                            };
                            format!("{:>7.2}{mark}", c.ratio(e, k))
                        })
                    })
                    .collect();
                eprintln!("  α {alpha:<5} {}", row.join(" "));
            }
            eprintln!(
                "  (columns: arris width {} mm)",
                cfg.arris_widths_mm
                    .iter()
                    .map(|w| w.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
}

/// Writes the CSVs and plots into `out`; returns the file names (summary.json is written
/// after, by the caller).
fn write_outputs(
    out: &Path,
    study: &ScanAngleStudy,
    exposures_ms: &[f64],
) -> anyhow::Result<Vec<String>> {
    let mut files = Vec::new();
    let mut text = |name: String, body: String| -> anyhow::Result<()> {
        write_atomic(&out.join(&name), |w| w.write_all(body.as_bytes()))?;
        files.push(name);
        Ok(())
    };
    for a in &study.angles {
        text(format!("points_{}deg.csv", a.scan_angle_deg), points_csv(a))?;
    }
    text("summary.csv".into(), summary_csv(study))?;
    if !study.sweep.is_empty() {
        text("sweep.csv".into(), sweep_csv(study))?;
    }
    if !exposures_ms.is_empty() {
        text(
            "exposure_axis.csv".into(),
            exposure_csv(study, exposures_ms),
        )?;
    }
    for a in &study.angles {
        let pts = |v: Variant| -> Vec<(f64, f64)> {
            a.points
                .iter()
                .filter(|p| p.variant == v)
                .map(|p| (p.out_mm, p.up_mm))
                .collect()
        };
        let bips = a.bare().map_or_else(Vec::new, |b| {
            b.tallies.iter().filter_map(|t| t.bips[0].edge_mm).collect()
        });
        let positions = a.variants.first().map_or(0, |v| v.tallies.len());
        let fig = EdgeScatter {
            title: format!(
                "Scan angle {}°: readings near the edge, {} position{}",
                a.scan_angle_deg,
                positions,
                if positions == 1 { "" } else { "s" }
            ),
            cover: pts(Variant::Cover),
            tape: pts(Variant::Tape),
            bare: pts(Variant::Bare),
            bips,
            window: EdgeScatter::EDGE_WINDOW,
        };
        let stem = format!("edge_{}deg", a.scan_angle_deg);
        save(&fig, out, &stem)?;
        files.extend([format!("{stem}.png"), format!("{stem}.svg")]);
    }
    if !study.sweep.is_empty() {
        let fig = bip_curve_figure(&study.sweep);
        save(&fig, out, "bip_error_vs_angle")?;
        files.extend([
            "bip_error_vs_angle.png".into(),
            "bip_error_vs_angle.svg".into(),
        ]);
    }
    if !exposures_ms.is_empty() {
        for (k, fig) in exposure_heat_maps(study, exposures_ms).iter().enumerate() {
            let stem = format!("exposure_axis_{}", crate::study::tally::RULES[k].name());
            save(fig, out, &stem)?;
            files.extend([format!("{stem}.png"), format!("{stem}.svg")]);
        }
    }
    Ok(files)
}

/// The human-readable table on stderr.
fn print_table(study: &ScanAngleStudy, exposures_ms: &[f64]) {
    eprintln!(
        "{:>7}  {:<9}  {:>28}  {:>8}",
        "angle", "rule", "BIP error mean ± std (max) mm", "valid"
    );
    for a in &study.angles {
        if let Some(rules) = a.bip() {
            for r in &rules {
                let s = &r.error_mm;
                eprintln!(
                    "{:>6}°  {:<9}  {:>10.3} ± {:>6.3} ({:>6.3})  {:>8.2}",
                    a.scan_angle_deg,
                    r.rule.name(),
                    s.mean,
                    s.std,
                    s.max,
                    r.valid_fraction
                );
            }
        }
        for v in &a.variants {
            let n = v.nearest_stats();
            eprintln!(
                "{:>7}  {:<9}  nearest point to p_e {:.3} ± {:.3} mm, saturated pixels {:.2e}",
                "",
                v.variant.name(),
                n.mean,
                n.std,
                v.saturated_pixel_fraction()
            );
        }
    }
    for a in &study.angles {
        let Some(bare) = a.bare() else { continue };
        for (t, ms) in bare.by_exposure.iter().zip(exposures_ms) {
            let [h, e] = crate::study::tally::RuleSummary::both(t);
            eprintln!(
                "{:>6}°  {:>5} ms   highest {:.3} ± {:.3} mm ({:.2} valid), edge-line {:.3} ± {:.3} mm ({:.2} valid)",
                a.scan_angle_deg, ms, h.error_mm.mean, h.error_mm.std, h.valid_fraction,
                e.error_mm.mean, e.error_mm.std, e.valid_fraction
            );
        }
    }
    for a in &study.sweep {
        let [h, e] = &a.rules;
        eprintln!(
            "sweep {:>4}°: highest {:.3} ± {:.3} mm ({:.2} valid), edge-line {:.3} ± {:.3} mm ({:.2} valid)",
            a.scan_angle_deg,
            h.error_mm.mean,
            h.error_mm.std,
            h.valid_fraction,
            e.error_mm.mean,
            e.error_mm.std,
            e.valid_fraction
        );
    }
}
