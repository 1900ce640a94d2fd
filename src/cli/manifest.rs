//! The run manifest (`manifest.json`) and the `--json` summary.

use std::path::Path;
use std::time::Duration;

use serde::Serialize;

pub use crate::geometry::pose::PoseMmDeg;
use crate::io::json::tidy_decimal;
use crate::scan::simulate::PoseResult;
use crate::scan::ScanConfig;
use crate::scene::World;
use crate::sensor::path_class::PathClass;
use crate::sensor::SensorConfig;
use crate::transport::{TraceSettings, TraceStats};

/// One written file.
#[derive(Debug, Serialize)]
pub struct FileEntry {
    /// What it holds.
    pub role: String,
    /// Path relative to the output directory.
    pub path: String,
    /// Format and units.
    pub format: String,
}

impl FileEntry {
    /// A file entry.
    pub fn new(role: &str, path: &str, format: &str) -> Self {
        FileEntry {
            role: role.into(),
            path: path.into(),
            format: format.into(),
        }
    }
}

/// One pose of the manifest.
#[derive(Debug, Serialize)]
pub struct PoseEntry {
    /// Pose index.
    pub index: usize,
    /// Sensor pose T_BS.
    pub sensor_pose: PoseMmDeg,
    /// Flange pose T_BF.
    pub flange_pose: PoseMmDeg,
    /// Ground-truth border point p_e in the base frame (mm).
    pub edge_point_mm: [f64; 3],
    /// Position of p_e along the border (fraction of its length).
    pub border_fraction: f64,
    /// Valid points in the profile (all reflections in `all` mode).
    pub valid_points: usize,
    /// Valid points per path class of their peak.
    pub labels: std::collections::BTreeMap<String, usize>,
    /// Pixels at the ADC's full scale.
    pub saturated_pixels: usize,
    /// Transport counters.
    pub stats: TraceStats,
    /// Files written for this pose.
    pub files: Vec<FileEntry>,
    /// Why the pose's result may be physically empty or meaningless (`scan::warnings`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

impl PoseEntry {
    /// Summarises a simulated pose.
    pub fn new(r: &PoseResult, files: Vec<FileEntry>, warnings: Vec<String>) -> Self {
        let e = r.pose.edge_point * 1e3;
        PoseEntry {
            index: r.pose.index,
            sensor_pose: (&r.pose.sensor).into(),
            flange_pose: (&r.pose.flange).into(),
            edge_point_mm: [e.x, e.y, e.z],
            border_fraction: r.pose.border_fraction,
            valid_points: r.profile.points.iter().filter(|p| p.valid).count(),
            labels: PathClass::LABELS
                .iter()
                .map(|&c| {
                    let n = r
                        .profile
                        .points
                        .iter()
                        .filter(|p| p.valid && p.label == Some(c))
                        .count();
                    (c.name().to_owned(), n)
                })
                .filter(|(_, n)| *n > 0)
                .collect(),
            saturated_pixels: r.saturated_pixels,
            stats: r.stats,
            files,
            warnings,
        }
    }
}

/// The manifest of a `scan` run.
#[derive(Debug, Serialize)]
pub struct Manifest {
    /// glassscan version.
    pub version: String,
    /// Scene file as given.
    pub scene: String,
    /// Master seed.
    pub seed: u64,
    /// Transport settings.
    pub trace: TraceSettings,
    /// Scan settings in named units.
    pub scan: ScanSummary,
    /// The sensor configuration (SI units).
    pub sensor: SensorConfig,
    /// Hand-eye mount T_FS.
    pub mount: PoseMmDeg,
    /// True pose of the target T_BM.
    pub target_pose: Option<PoseMmDeg>,
    /// Nominal (coarse) pose of the target T_BM0.
    pub target_nominal_pose: Option<PoseMmDeg>,
    /// The poses.
    pub poses: Vec<PoseEntry>,
    /// Where the values of each material taken from a glTF file came from (absent when none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub material_sources: Vec<crate::scene::world::MaterialSource>,
    /// The scene loader's warnings (absent when there are none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub scene_warnings: Vec<String>,
    /// Wall-clock time of the run (s).
    pub elapsed_s: f64,
}

/// Scan settings in named units.
#[derive(Debug, Serialize)]
pub struct ScanSummary {
    /// Scan angle (deg).
    pub scan_angle_deg: f64,
    /// Number of poses.
    pub poses: usize,
    /// Standoff (mm).
    pub standoff_mm: f64,
    /// Exposure (ms).
    pub exposure_ms: f64,
}

impl Manifest {
    /// Assembles the manifest.
    pub fn new(
        world: &World,
        scan: &ScanConfig,
        trace: &TraceSettings,
        poses: Vec<PoseEntry>,
        elapsed: Duration,
    ) -> Self {
        let target = world.target.as_ref();
        Manifest {
            version: env!("CARGO_PKG_VERSION").into(),
            scene: world.source.display().to_string(),
            seed: trace.seed,
            trace: *trace,
            scan: ScanSummary {
                scan_angle_deg: tidy_decimal(scan.scan_angle_rad.to_degrees()),
                poses: scan.poses,
                standoff_mm: tidy_decimal(scan.standoff_m * 1e3),
                exposure_ms: tidy_decimal(world.sensor.imager.exposure_s * 1e3),
            },
            sensor: world.sensor.clone(),
            mount: (&world.mount).into(),
            target_pose: target.map(|t| (&world.objects[t.object].pose).into()),
            target_nominal_pose: target.map(|t| (&t.nominal_pose).into()),
            poses,
            material_sources: world.material_sources.clone(),
            scene_warnings: world.warnings.clone(),
            elapsed_s: elapsed.as_secs_f64(),
        }
    }
}

/// The `--json` summary printed on stdout.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Scene file.
    pub scene: String,
    /// Output directory.
    pub out: String,
    /// The manifest file.
    pub manifest: String,
    /// Master seed.
    pub seed: u64,
    /// Per pose: index, valid points, p_e and files.
    pub poses: Vec<SummaryPose>,
    /// Wall-clock time (s).
    pub elapsed_s: f64,
}

/// One pose of the summary.
#[derive(Debug, Serialize)]
pub struct SummaryPose {
    /// Pose index.
    pub index: usize,
    /// Valid profile points.
    pub valid_points: usize,
    /// Saturated pixels.
    pub saturated_pixels: usize,
    /// Ground-truth p_e (mm, base frame).
    pub edge_point_mm: [f64; 3],
    /// Files, relative to the output directory.
    pub files: Vec<String>,
    /// The pose's warnings (empty: none).
    pub warnings: Vec<String>,
}

impl Summary {
    /// Summarises a manifest.
    pub fn new(m: &Manifest, out: &Path, manifest_path: &Path) -> Self {
        Summary {
            scene: m.scene.clone(),
            out: out.display().to_string(),
            manifest: manifest_path.display().to_string(),
            seed: m.seed,
            poses: m
                .poses
                .iter()
                .map(|p| SummaryPose {
                    index: p.index,
                    valid_points: p.valid_points,
                    saturated_pixels: p.saturated_pixels,
                    edge_point_mm: p.edge_point_mm,
                    files: p.files.iter().map(|f| f.path.clone()).collect(),
                    warnings: p.warnings.clone(),
                })
                .collect(),
            elapsed_s: m.elapsed_s,
        }
    }
}
