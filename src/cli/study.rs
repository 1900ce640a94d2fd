//! `glassscan study scan-angle [SCENE]`: the paper's edge experiment (tape, cover, bare) at
//! several scan angles and positions, the BIP error by both rules, and the BIP-error curve over
//! a sweep of scan angles (`study::scan_angle`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Subcommand};
use serde_json::{json, Value};

use super::{flags, progress, CliError};
use crate::dataset::{atomic::write_atomic, json as json_file, output_dir};
use crate::plot::edge_scatter::EdgeScatter;
use crate::plot::save;
use crate::scene;
use crate::sensor::SensorHead;
use crate::study::as_typed;
use crate::study::scan_angle::{
    run_scan_angle_study, ScanAngleConfig, ScanAngleStudy, Variant, VariantSetup,
};
use crate::study::scan_angle_report::{
    bip_curve_figure, points_csv, summary_csv, summary_json, sweep_csv,
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
    ScanAngle(ScanAngleArgs),
}

/// Arguments of `glassscan study scan-angle`.
#[derive(Debug, Args)]
pub struct ScanAngleArgs {
    /// The bare-pane scene. The tape and cover variants are its siblings `<stem>_tape.toml`
    /// and `<stem>_cover.toml` (a trailing `_bare` of the stem is dropped first); a missing
    /// sibling is skipped, with a note.
    #[arg(default_value = "scenes/edge_study.toml")]
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
    let world = scene::load(path).map_err(CliError::input)?;
    let Some(target) = world.target.as_ref() else {
        return Err(CliError::input(anyhow::anyhow!(
            "{}: the scene has no [target]: `study scan-angle` needs a panel whose border it scans",
            path.display()
        )));
    };
    let head = SensorHead::new(&world.sensor)
        .with_context(|| format!("{}: [sensor]", path.display()))
        .map_err(CliError::input)?;
    let scene = TraceScene::new(&world).map_err(CliError::input)?;
    let border_b = target
        .border
        .transformed(&world.objects[target.object].pose);
    let s = VariantSetup {
        variant,
        scene,
        head,
        border_b,
        mount: world.mount,
    };
    Ok((s, world))
}

fn run_scan_angle(args: ScanAngleArgs) -> Result<(), CliError> {
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
    if args.positions == 0 {
        return Err(flags::bad_flag("positions", "must be ≥ 1, got 0".into()));
    }
    flags::photons(args.light.photons)?;

    let (bare, bare_world) = setup(&args.scene, Variant::Bare)?;
    let mut setups = Vec::new();
    let mut notes = Vec::new();
    let mut scenes = serde_json::Map::new();
    for v in [Variant::Tape, Variant::Cover] {
        let path = sibling(&args.scene, v);
        if path.is_file() {
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
            eprintln!("note: {n}");
        }
    }

    let cfg = ScanAngleConfig {
        angles_rad,
        sweep_rad,
        scan: crate::scan::ScanConfig {
            poses: args.positions,
            ..bare_world.scan
        },
        trace: TraceSettings {
            photons: args.light.photons,
            max_depth: 64,
            seed: args.light.seed,
        },
    };
    let bar = progress::bar(cfg.simulations(setups.len()) as u64, "poses", args.json);
    let study = run_scan_angle_study(&setups, &cfg, &|| bar.inc(1));
    bar.finish_and_clear();
    let simulated_s = started.elapsed().as_secs_f64();

    let mut files = Vec::new();
    if let Some(out) = &args.output.out {
        files = write_outputs(out, &study).map_err(CliError::internal)?;
    }
    let run = json!({
        "scene": args.scene.display().to_string(),
        "scenes": scenes,
        "notes": notes,
        "positions": cfg.scan.poses,
        "photons": cfg.trace.photons,
        "seed": cfg.trace.seed,
        "sweep_deg": cfg.sweep_rad.iter().map(|a| as_typed(a.to_degrees())).collect::<Vec<_>>(),
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
        print_table(&study);
        eprintln!(
            "{} poses simulated in {:.1} s",
            cfg.simulations(setups.len()),
            simulated_s
        );
    }
    Ok(())
}

/// Writes the CSVs and plots into `out`; returns the file names (summary.json is written
/// after, by the caller).
fn write_outputs(out: &Path, study: &ScanAngleStudy) -> anyhow::Result<Vec<String>> {
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
    files.push("summary.json".into());
    Ok(files)
}

/// The human-readable table on stderr.
fn print_table(study: &ScanAngleStudy) {
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
