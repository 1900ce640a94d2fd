//! `glassscan locate SCENE`: the paper's pipeline (scan the border, BIP per profile, ICP) with
//! the errors against ground truth, printed like the paper's Tables 2–4.

use std::path::PathBuf;

use clap::Args;
use serde_json::{json, Value};

use super::{flags, locate_out, progress, CliError};
use crate::geometry::pose::{pose_from_mm_deg, PoseMmDeg};
use crate::localise::metrics::Stats;
use crate::scan::bip::BipRule;
use crate::scan::errors::ErrorModel;
use crate::scan::locate::{locate_world, LocateReport, LocateSettings};
use crate::scan::ScanConfig;
use crate::scene::world::{World, OPAQUE_COPY_ALBEDO};
use crate::transport::TraceSettings;

/// Arguments of `glassscan locate`.
#[derive(Debug, Args)]
pub struct LocateArgs {
    /// Scene with a [target] panel: a scene file's path (TOML, scenes/README.md) or a shipped scene's name
    /// (`glassscan scenes list`); a path that exists wins.
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// Number of scan poses along the border (3 to 10^6); overrides [scan].poses. Default: the
    /// scene's (12 in car_side_window, 4 in edge_study; 4 if the scene sets none).
    #[arg(long, value_name = "N")]
    pub poses: Option<usize>,
    /// Scan angle in degrees (0 < A ≤ 90); overrides [scan].scan_angle_deg. Default: the
    /// scene's (45 in car_side_window, 40 in edge_study; 45 if the scene sets none).
    #[arg(long, value_name = "A")]
    pub scan_angle_deg: Option<f64>,
    /// The true pose relative to the nominal one, `dx_mm,dy_mm,dz_mm,rx_deg,ry_deg,rz_deg`
    /// (the coarse-localisation error). Default: the scene's true and nominal poses.
    #[arg(long, value_name = "DX,DY,DZ,RX,RY,RZ", allow_hyphen_values = true)]
    pub perturb: Option<String>,
    /// Exposure time in milliseconds (> 0); overrides [sensor].exposure_ms. Default: the
    /// scene's (2 in car_side_window, 0.5 in edge_study; the preset's 0.5 if the scene sets
    /// none).
    #[arg(long, value_name = "MS")]
    pub exposure_ms: Option<f64>,
    #[command(flatten)]
    pub light: flags::LightArgs,
    /// Robot repeatability, hand-eye and sensor linearity errors: `off` (the sensor alone) or
    /// `default` (docs/parameters.md §6).
    #[arg(long, value_name = "off|default", default_value = "off")]
    pub errors: String,
    /// BIP rule whose points are registered: `edge-line` (top of the steep run of edge
    /// returns) or `highest` (the paper's: highest point above the ground). Both are reported.
    #[arg(long, value_name = "RULE", default_value = "edge-line")]
    pub bip: String,
    /// Also run the opaque copy of the target (same shape, matte) for the paper's Table 3.
    #[arg(long)]
    pub opaque_copy: bool,
    /// Exposure of the opaque copy's scan in milliseconds (> 0); default: the glass scan's.
    /// A matte copy that the glass's exposure saturates is better scanned shorter, as an
    /// operator would.
    #[arg(long, value_name = "MS", requires = "opaque_copy")]
    pub opaque_exposure_ms: Option<f64>,
    #[command(flatten)]
    pub output: flags::OutArgs,
    /// Print a machine-readable summary on stdout.
    #[arg(long)]
    pub json: bool,
}

fn parse_perturb(s: &str) -> Result<[f64; 6], CliError> {
    let bad = |what: String| {
        flags::bad_flag(
            "perturb",
            format!("expected six finite numbers dx_mm,dy_mm,dz_mm,rx_deg,ry_deg,rz_deg, {what}"),
        )
    };
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| bad(format!("got {s:?} ({e})")))?;
    match <[f64; 6]>::try_from(v) {
        Ok(a) if a.iter().all(|x| x.is_finite()) => Ok(a),
        _ => Err(bad(format!("got {s:?}"))),
    }
}

/// `--errors`.
pub(super) fn parse_errors(s: &str) -> Result<ErrorModel, CliError> {
    match s {
        "off" => Ok(ErrorModel::OFF),
        "default" => Ok(ErrorModel::DEFAULT),
        _ => Err(flags::bad_flag(
            "errors",
            format!("expected off or default, got {s:?}"),
        )),
    }
}

/// The validated inputs of a run.
struct Resolved {
    world: World,
    /// The opaque copy of `world`'s target, if asked for.
    opaque: Option<World>,
    scan: ScanConfig,
    settings: LocateSettings,
    trace: TraceSettings,
}

fn resolve(args: &LocateArgs) -> Result<Resolved, CliError> {
    let world = super::load_scene(&args.scene)?;
    resolve_on(world, args)
}

/// [`resolve`] on a scene already loaded (`args.scene` names it in messages).
fn resolve_on(mut world: World, args: &LocateArgs) -> Result<Resolved, CliError> {
    let mut scan = world.scan;
    if let Some(n) = args.poses {
        scan.poses = flags::poses("poses", n, 3, " (ICP needs three points)")?;
    }
    if let Some(a) = args.scan_angle_deg {
        scan.scan_angle_rad = flags::scan_angle_rad(a)?;
    }
    let (photons, adaptive) = flags::photons(args.light.photons)?;
    if let Some(ms) = args.exposure_ms {
        world.sensor.imager.exposure_s = flags::exposure_s(ms)?;
    }
    let errors = parse_errors(&args.errors)?;
    let rule: BipRule = args
        .bip
        .parse()
        .map_err(|e: String| flags::bad_flag("bip", e))?;
    let Some(target) = world.target.clone() else {
        return Err(CliError::input(anyhow::anyhow!(
            "{}: the scene has no [target]: `locate` needs a panel whose border it scans",
            args.scene.display()
        )));
    };
    if let Some(p) = &args.perturb {
        let [dx, dy, dz, rx, ry, rz] = parse_perturb(p)?;
        world.objects[target.object].pose =
            target.nominal_pose * pose_from_mm_deg([dx, dy, dz], [rx, ry, rz]);
    }
    let opaque = match args.opaque_copy {
        false => None,
        true => {
            let mut w = world
                .with_opaque_target(OPAQUE_COPY_ALBEDO)
                .expect("the target exists");
            if let Some(ms) = args.opaque_exposure_ms {
                w.sensor.imager.exposure_s = flags::exposure_s(ms)?;
            }
            Some(w)
        }
    };
    if let Some(dir) = &args.output.out {
        crate::io::output_dir::prepare_output_dir(dir, args.output.force)
            .map_err(CliError::input)?;
    }
    Ok(Resolved {
        world,
        opaque,
        scan,
        settings: LocateSettings { rule, errors },
        trace: TraceSettings {
            photons,
            adaptive,
            max_depth: 64,
            seed: args.light.seed,
        },
    })
}

/// Runs the pipeline on `world` (whose target exists).
fn run_on(world: &World, r: &Resolved, quiet: bool, what: &str) -> Result<LocateReport, CliError> {
    let bar = progress::bar(r.scan.poses as u64, what, quiet);
    let report = locate_world(world, &r.scan, &r.trace, &r.settings, &|| bar.inc(1))
        .map_err(CliError::input)?;
    bar.finish_and_clear();
    Ok(report)
}

/// The `--json` summary of one run on `world` (and the `summary.json` of `--out`).
fn summary_json(report: &LocateReport, world: &World) -> Value {
    let (converged, degenerate, iterations, estimate, weak) = match &report.registration {
        Ok(r) => (
            r.converged,
            r.degenerate,
            r.iterations,
            Some(PoseMmDeg::from(&r.pose)),
            r.weak_directions.len(),
        ),
        Err(_) => (false, false, 0, None, 0),
    };
    let errors = report.settings.errors;
    json!({
        "exposure_ms": world.sensor.imager.exposure_s * 1e3,
        "bip_rule": report.settings.rule.name(),
        "errors": if errors.is_on() { "default" } else { "off" },
        "error_sources_on": errors.sources_on(),
        "error_model": errors,
        "bips": report.poses.iter().filter(|p| p.bip.is_some()).count(),
        "bip_error_mm": report.bip_error_mm,
        "paper_rule_bip_error_mm": report.paper_bip_error_mm,
        "pose_error": report.pose_error.map(|(t, r)| json!({"translation_mm": t, "rotation_deg": r})),
        "task_error_mm": report.task_error_mm,
        "contour_error_mm": report.contour_error_mm.as_ref().map(|s| json!({"mean": s.mean, "max": s.max})),
        "converged": converged,
        "degenerate": degenerate,
        "weak_directions": weak,
        "iterations": iterations,
        "registration_error": report.registration.as_ref().err().map(|e| e.to_string()),
        "estimate": estimate,
        "timings_s": {"scanning": report.timings_s.0, "pose_estimation": report.timings_s.1},
    })
}

/// Runs `glassscan locate`.
pub fn run(mut args: LocateArgs) -> Result<(), CliError> {
    args.scene = super::scene_path(&args.scene)?;
    let r = resolve(&args)?;
    let (summary, glass, opaque) = execute(&args, &r)?;
    if args.json {
        super::print_json(&summary)?;
    } else {
        print_tables(&glass, opaque.as_ref());
    }
    Ok(())
}

/// `glassscan locate` on the scene `world` (loaded by the caller; `args.scene` names it),
/// without printing: the `--json` summary, and the files of `--out` if it is given.
pub fn summary_on(world: World, args: &LocateArgs) -> Result<Value, CliError> {
    let r = resolve_on(world, args)?;
    Ok(execute(args, &r)?.0)
}

/// The pipeline, the summary and the files of `--out`.
fn execute(
    args: &LocateArgs,
    r: &Resolved,
) -> Result<(Value, LocateReport, Option<LocateReport>), CliError> {
    let glass = run_on(&r.world, r, args.json, "poses")?;
    let opaque = match &r.opaque {
        Some(world) => Some(run_on(world, r, args.json, "poses (opaque copy)")?),
        None => None,
    };
    let opaque_summary = opaque
        .as_ref()
        .zip(r.opaque.as_ref())
        .map(|(o, w)| summary_json(o, w));
    let summary = crate::study::with_run(
        summary_json(&glass, &r.world),
        json!({
            "scene": args.scene.display().to_string(),
            "poses": r.scan.poses,
            "scan_angle_deg": r.scan.scan_angle_rad.to_degrees(),
            "seed": args.light.seed,
            "photons": args.light.photons,
            "opaque_copy": opaque_summary,
        }),
    );
    if let Some(dir) = &args.output.out {
        locate_out::write_run(dir, &r.world, &glass, &summary).map_err(CliError::internal)?;
        if let Some(o) = &opaque {
            let sub = dir.join("opaque_copy");
            crate::io::output_dir::prepare_output_dir(&sub, true).map_err(CliError::internal)?;
            let world = r.opaque.as_ref().expect("ran");
            locate_out::write_run(&sub, world, o, &summary["opaque_copy"])
                .map_err(CliError::internal)?;
        }
    }
    Ok((summary, glass, opaque))
}

/// Per-pose lines and the paper's Tables 2–4, on stderr.
fn print_tables(glass: &LocateReport, opaque: Option<&LocateReport>) {
    let errors = glass.settings.errors.sources_on();
    eprintln!(
        "BIP rule {}; error sources: {}",
        glass.settings.rule.name(),
        if errors.is_empty() {
            "off (sensor only)".to_string()
        } else {
            errors.join(", ")
        }
    );
    for (k, p) in glass.poses.iter().enumerate() {
        match (p.bip, p.edge_point) {
            (Some(b), Some(pe)) => {
                let d = (b.point_b - pe) * 1e3;
                eprintln!(
                    "pose {k:2}: BIP − p_e = ({:7.2}, {:7.2}, {:7.2}) mm, |·| {:6.2} mm, from {}",
                    d.x,
                    d.y,
                    d.z,
                    d.norm(),
                    b.label.map_or("?", |l| l.name())
                );
            }
            (None, _) => eprintln!("pose {k:2}: no BIP"),
            (Some(_), None) => eprintln!("pose {k:2}: the laser plane misses the true border"),
        }
    }
    let row = |name: &str, s: &Stats| {
        format!(
            "{name:<34} {:>6.3} (± {:.3}) {:>8.3} {:>4}",
            s.mean, s.std, s.max, s.n
        )
    };
    eprintln!("\nPoint localisation error |BIP − p_e| (mm)   mean (± std)      max    n   [paper Table 3]");
    eprintln!(
        "{}",
        row(
            &format!("glass, {} rule", glass.settings.rule.name()),
            &glass.bip_error_mm
        )
    );
    if glass.settings.rule != BipRule::Highest {
        eprintln!(
            "{}",
            row("glass, paper's rule (highest)", &glass.paper_bip_error_mm)
        );
    }
    if let Some(o) = opaque {
        eprintln!(
            "{}",
            row(
                &format!("opaque copy, {} rule", o.settings.rule.name()),
                &o.bip_error_mm
            )
        );
        if o.settings.rule != BipRule::Highest {
            eprintln!(
                "{}",
                row("opaque copy, paper's rule", &o.paper_bip_error_mm)
            );
        }
    }
    eprintln!(
        "{:<34} {:>6.2} (± {:.2}) {:>8.2}        (opaque 1.01 ± 0.14, max 1.27)",
        "paper, glass", 0.94, 0.28, 1.35
    );
    match (&glass.registration, glass.pose_error, &glass.task_error_mm) {
        (Ok(r), Some((t, rot)), Some(task)) => {
            eprintln!(
                "\nICP: {} iterations, converged {}, degenerate {}, rms {:.3} mm, {} inliers of {}",
                r.iterations,
                r.converged,
                r.degenerate,
                r.rms_mm,
                r.inliers.iter().filter(|&&i| i).count(),
                glass.poses.iter().filter(|p| p.bip.is_some()).count()
            );
            eprintln!("pose error: {t:.3} mm, {rot:.4}°");
            eprintln!("Full pipeline localisation error (mm)     mean (± std)      max    n   [paper Table 4]");
            eprintln!("{}", row("task error", task));
            eprintln!(
                "{:<34} {:>6.2} (± {:.2}) {:>8.2}",
                "paper", 0.88, 0.39, 1.65
            );
            if let Some(c) = &glass.contour_error_mm {
                eprintln!(
                    "contour (glue path) error: mean {:.3} mm, max {:.3} mm",
                    c.mean, c.max
                );
            }
        }
        (Err(e), _, _) => eprintln!("\nregistration failed: {e}"),
        _ => {}
    }
    eprintln!("\nStage             time (s)   [paper Table 2]");
    eprintln!(
        "scanning          {:>9.3}   (14.845; here: simulation, not robot motion)",
        glass.timings_s.0
    );
    eprintln!("pose estimation   {:>9.6}   (0.023)", glass.timings_s.1);
}
