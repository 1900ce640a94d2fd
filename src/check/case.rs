//! Running one case of a suite: the localisation pipeline of `glassscan locate` on the case's
//! scene and settings, reduced to the metrics of `compare::METRICS`.

use super::compare::Metrics;
use super::suite::CaseDef;
use crate::scan::bip::BipRule;
use crate::scan::errors::ErrorModel;
use crate::scan::locate::{locate_world, LocateSettings};
use crate::scene;
use crate::transport::TraceSettings;

/// Runs `case` (scene paths relative to the current directory) and returns its metrics.
/// Errors are bad input (a scene that does not load or has no target).
pub fn run_case(case: &CaseDef) -> anyhow::Result<Metrics> {
    let mut world = scene::load(&case.scene).map_err(anyhow::Error::new)?;
    let mut scan = world.scan;
    if let Some(a) = case.scan_angle_deg {
        scan.scan_angle_rad = a.to_radians();
    }
    if let Some(n) = case.poses {
        scan.poses = n;
    }
    if let Some(ms) = case.exposure_ms {
        world.sensor.imager.exposure_s = ms * 1e-3;
    }
    let settings = LocateSettings {
        rule: case.bip.parse::<BipRule>().map_err(anyhow::Error::msg)?,
        errors: match case.errors.as_str() {
            "default" => ErrorModel::DEFAULT,
            _ => ErrorModel::OFF,
        },
    };
    let trace = TraceSettings {
        photons: case.photons,
        adaptive: false,
        max_depth: 64,
        seed: case.seed,
    };
    let report = locate_world(&world, &scan, &trace, &settings, &|| {})?;
    let (valid, all) = report.poses.iter().fold((0usize, 0usize), |(v, a), p| {
        let pts = &p.result.profile.points;
        (v + pts.iter().filter(|q| q.valid).count(), a + pts.len())
    });
    let reg = report.registration.as_ref().ok();
    let b = &report.bip_error_mm;
    let finite = |v: f64| v.is_finite().then_some(v);
    let m: Metrics = [
        ("bips", Some(b.n as f64)),
        (
            "converged",
            Some(reg.is_some_and(|r| r.converged) as u8 as f64),
        ),
        (
            "valid_point_fraction",
            Some(valid as f64 / all.max(1) as f64),
        ),
        ("bip_error_mean_mm", finite(b.mean)),
        ("bip_error_max_mm", finite(b.max)),
        ("pose_translation_mm", report.pose_error.map(|e| e.0)),
        ("pose_rotation_deg", report.pose_error.map(|e| e.1)),
        (
            "task_error_mean_mm",
            report.task_error_mm.as_ref().map(|s| s.mean),
        ),
        (
            "task_error_max_mm",
            report.task_error_mm.as_ref().map(|s| s.max),
        ),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    Ok(m)
}
