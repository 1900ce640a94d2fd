//! `glassscan register MODEL_SCENE BIPS.csv`: registers the user's own border points (CSV in
//! the base frame, mm) to the model border of a scene's target, starting from its nominal pose:
//! the localisation step alone, on points from anywhere (a real sensor, another simulator).

use std::path::{Path, PathBuf};

use clap::Args;
use nalgebra::Point3;
use serde_json::{json, Value};

use super::manifest::PoseMmDeg;
use super::CliError;
use crate::io::points_csv::read_points_csv;
use crate::localise::icp::{register, IcpSettings, Registration};
use crate::localise::metrics::pose_error;
use crate::scene;

/// Arguments of `glassscan register`.
#[derive(Debug, Args)]
pub struct RegisterArgs {
    /// Scene whose [target] gives the model border and the nominal (initial) pose: a scene
    /// file's path or a shipped scene's name (a path that exists wins).
    #[arg(value_name = "MODEL_SCENE")]
    pub model_scene: PathBuf,
    /// CSV of border points in the base frame: a header naming x_mm, y_mm, z_mm (other
    /// columns ignored), one point per row; `locate --out` writes such a `bips.csv`.
    pub bips: PathBuf,
    /// Print a machine-readable result on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `glassscan register`.
pub fn run(mut args: RegisterArgs) -> Result<(), CliError> {
    args.model_scene = super::scene_path(&args.model_scene)?;
    let world = super::load_scene(&args.model_scene)?;
    let rows = read_points_csv(&args.bips).map_err(CliError::input)?;
    let (result, reg) = summary(&world, &args.model_scene, &args.bips, &rows)?;
    if args.json {
        super::print_json(&result)?;
    } else {
        let e = PoseMmDeg::from(&reg.pose);
        eprintln!(
            "{} points; {} iterations, converged {}, rms {:.3} mm, condition {:.3e}",
            rows.len(),
            reg.iterations,
            reg.converged,
            reg.rms_mm,
            reg.condition
        );
        if reg.degenerate {
            eprintln!(
                "warning: the points leave {} direction(s) unconstrained; the pose is not determined along them: {:?}",
                reg.weak_directions.len(),
                reg.weak_directions
            );
        }
        let outliers = &result["outlier_lines"];
        if outliers.as_array().is_some_and(|o| !o.is_empty()) {
            eprintln!("rejected as outliers: CSV lines {outliers}");
        }
        eprintln!(
            "estimate T_BM: translation {:?} mm, rotation {:?} deg (R = Rz·Ry·Rx)",
            e.translation_mm, e.rotation_deg
        );
        let difference = &result["difference_from_scene_pose"];
        eprintln!(
            "differs from the scene's object pose by {:.3} mm, {:.4}°",
            difference["translation_mm"].as_f64().unwrap_or(f64::NAN),
            difference["rotation_deg"].as_f64().unwrap_or(f64::NAN)
        );
    }
    Ok(())
}

/// Registers `rows` (each point's line or row number, and the point in the base frame, mm)
/// to the border of `world`'s target from its nominal pose: the `--json` result, and the
/// registration. `model_scene` and `source` name the scene and the points in messages.
pub fn summary(
    world: &scene::World,
    model_scene: &Path,
    source: &Path,
    rows: &[(usize, [f64; 3])],
) -> Result<(Value, Registration), CliError> {
    let Some(target) = world.target.as_ref() else {
        return Err(CliError::input(anyhow::anyhow!(
            "{}: the scene has no [target]: `register` needs the panel whose border is the model",
            model_scene.display()
        )));
    };
    let points: Vec<Point3<f64>> = rows
        .iter()
        .map(|(_, p)| Point3::new(p[0], p[1], p[2]) * 1e-3)
        .collect();
    let reg = register(
        &target.border,
        &points,
        &target.nominal_pose,
        &IcpSettings::robust(),
    )
    .map_err(|e| CliError::input(anyhow::anyhow!("{}: {e}", source.display())))?;
    let scene_pose = world.objects[target.object].pose;
    let (dt, dr) = pose_error(&reg.pose, &scene_pose);
    let outliers: Vec<usize> = rows
        .iter()
        .zip(&reg.inliers)
        .filter(|(_, &inlier)| !inlier)
        .map(|((line, _), _)| *line)
        .collect();
    let result = json!({
        "model_scene": model_scene.display().to_string(),
        "points": points.len(),
        "estimate": PoseMmDeg::from(&reg.pose),
        "initial": PoseMmDeg::from(&target.nominal_pose),
        "converged": reg.converged,
        "degenerate": reg.degenerate,
        "weak_directions": reg.weak_directions,
        "condition": reg.condition,
        "iterations": reg.iterations,
        "rms_mm": reg.rms_mm,
        "outlier_lines": outliers,
        "difference_from_scene_pose": {"translation_mm": dt, "rotation_deg": dr},
    });
    Ok((result, reg))
}
