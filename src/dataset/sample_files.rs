//! The files of one sample directory `sample_NNNNNN/`, and its manifest line:
//!
//! | File | Content |
//! |---|---|
//! | `image.png` | sensor image, 16-bit PNG, DN << (16 − adc_bits) (the SDK's container alignment) |
//! | `irradiance.exr` | irradiance (W/m², f32): `irradiance` (total) and `class.<path class>` layers |
//! | `profile.csv` | the measured profile (sensor frame, mm), with the path label of each peak |
//! | `points.ply` | the valid profile points in the base frame (mm), binary PLY: colour, `label` (path class number), `intensity` (DN) |
//! | `ground_truth.json` | drawn parameters, poses (mm/deg, 4 × 4 matrix, quaternion), p_e: one line of compact JSON |
//! | `ideal_profile.csv` | the exact cross-section: first hit of each fan ray (sensor frame, mm), what it hit |
//!
//! The label of each measured point is the `label` column of `profile.csv`.
//!
//! Every file is written atomically, then read back for its size and SHA-256, which the
//! manifest line records; the caller appends the line only after this returns, which is what
//! makes the sample finished.

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::Point3;
use serde::Serialize;

use super::ideal_profile::IdealPoint;
use super::integrity::record_files;
use super::manifest::ManifestLine;
use super::sample::Sample;
use super::DatasetError;
use crate::geometry::pose::PoseMmDeg;
use crate::io::json::tidy_decimal;
use crate::io::ply::{write_ply, PlyEncoding, PointCloud};
use crate::io::points_csv::{write_csv_table, CsvTable};
use crate::io::{exr, json, png16, profile_csv};
use crate::scan::bip::profile_in_base;
use crate::scan::warnings::pose_warnings;
use crate::sensor::path_class::PathClass;

/// The file names inside a sample directory.
pub const FILES: [&str; 6] = [
    "image.png",
    "irradiance.exr",
    "profile.csv",
    "points.ply",
    "ground_truth.json",
    "ideal_profile.csv",
];

/// The directory name of sample `index`.
pub fn sample_dir_name(index: u64) -> String {
    format!("sample_{index:06}")
}

/// The sample index of a directory name made by [`sample_dir_name`].
pub fn parse_sample_dir_name(name: &str) -> Option<u64> {
    let digits = name.strip_prefix("sample_")?;
    if digits.len() < 6 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// `ground_truth.json`.
#[derive(Debug, Serialize)]
pub struct GroundTruth<'a> {
    /// Sample index.
    pub index: u64,
    /// Seed of the transport, speckle and sensor noise.
    pub noise_seed: u64,
    /// Position of the scan pose along the border (fraction of its length).
    pub border_fraction: f64,
    /// The randomised parameters drawn for this sample, by key.
    pub parameters: BTreeMap<String, f64>,
    /// Scan angle used (deg).
    pub scan_angle_deg: f64,
    /// Exposure used (ms).
    pub exposure_ms: f64,
    /// Laser wavelength (nm).
    pub wavelength_nm: f64,
    /// Name of the target object.
    pub target: &'a str,
    /// True pose of the target T_BM in this sample.
    pub target_pose: PoseMmDeg,
    /// Nominal (coarse) pose of the target T_BM0, as the scene gives it.
    pub target_nominal_pose: PoseMmDeg,
    /// Sensor pose T_BS.
    pub sensor_pose: PoseMmDeg,
    /// Flange pose T_BF = T_BS · T_FS⁻¹.
    pub flange_pose: PoseMmDeg,
    /// Hand-eye mount T_FS.
    pub mount: PoseMmDeg,
    /// p_e in the base frame (mm); `None` if the laser plane misses the true border.
    pub edge_point_mm: Option<[f64; 3]>,
    /// p_e in the sensor frame, (x, z) in mm (y = 0 up to rounding).
    pub edge_point_sensor_mm: Option<[f64; 2]>,
    /// Fan rays of the ideal profile that hit something (the rows of `ideal_profile.csv`).
    pub ideal_points: usize,
    /// Files of the sample, relative to its directory.
    pub files: [&'static str; 6],
}

/// `ideal_profile.csv`: one row per fan ray that hits something.
fn ideal_table(ideal: &[IdealPoint]) -> CsvTable {
    CsvTable {
        columns: [
            "ray",
            "fan_angle_deg",
            "x_mm",
            "z_mm",
            "object",
            "label",
            "part",
            "glass",
        ]
        .map(String::from)
        .to_vec(),
        rows: ideal
            .iter()
            .map(|p| {
                vec![
                    p.ray.to_string(),
                    p.fan_angle_deg.to_string(),
                    p.x_mm.to_string(),
                    p.z_mm.to_string(),
                    p.object.clone(),
                    serde_name(&p.label),
                    serde_name(&p.part),
                    p.glass.to_string(),
                ]
            })
            .collect(),
    }
}

/// The name a unit enum variant serialises to (the snake_case name the JSON files use).
fn serde_name<T: Serialize>(value: &T) -> String {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::String(s)) => s,
        other => unreachable!("a unit enum variant serialises to a string, got {other:?}"),
    }
}

/// The `label` number of a point in `points.ply`: its path class's position in
/// `PathClass::LABELS`, 255 for none.
fn label_number(label: Option<PathClass>) -> u8 {
    label
        .and_then(|c| PathClass::LABELS.iter().position(|&l| l == c))
        .map_or(255, |k| k as u8)
}

/// Colour of a point labelled `label` in `points.ply`.
fn label_color(label: Option<PathClass>) -> [u8; 3] {
    match label {
        Some(PathClass::GlassFace) => [0, 170, 255],
        Some(PathClass::GlassEdge) => [255, 0, 255],
        Some(PathClass::ThroughGlass) => [0, 200, 120],
        Some(PathClass::Glint) => [255, 255, 0],
        Some(PathClass::InternalReflection) => [255, 128, 0],
        Some(PathClass::Table) => [128, 128, 128],
        Some(PathClass::TapeCover) => [160, 82, 45],
        Some(PathClass::Background) => [90, 90, 200],
        Some(PathClass::Target) => [255, 60, 60],
        Some(PathClass::Other) => [200, 200, 160],
        Some(PathClass::GlassReflected) => [0, 120, 255],
        Some(PathClass::SensorNoise) => [40, 40, 40],
        None => [255, 255, 255],
    }
}

fn mm(p: &Point3<f64>) -> [f64; 3] {
    [p.x * 1e3, p.y * 1e3, p.z * 1e3]
}

/// Writes the files of `sample` into `dir` (which must exist), `points.ply` in `ply`, and
/// returns its manifest line.
pub fn write_sample(
    dir: &Path,
    sample: &Sample,
    ply: PlyEncoding,
) -> Result<ManifestLine, DatasetError> {
    let world = &sample.prepared.world;
    let r = &sample.result;
    let adc_bits = world.sensor.imager.adc_bits;

    png16::write_sensor_png16(&dir.join(FILES[0]), &r.image, adc_bits)?;
    let notes = exr::IrradianceNotes {
        wavelength_m: world.sensor.laser.wavelength_m,
        exposure_s: world.sensor.imager.exposure_s,
        sensor_to_base: sample.pose.sensor,
    };
    exr::write_irradiance_exr(&dir.join(FILES[1]), &r.irradiance, &notes)?;

    profile_csv::write_profile_csv(&dir.join(FILES[2]), &r.profile)?;

    let in_base = profile_in_base(&r.profile, &sample.pose.sensor);
    let mut cloud = PointCloud {
        comments: vec![
            "glassscan dataset sample: valid profile points".into(),
            "base frame B (z up, table top z = 0), millimetres".into(),
            format!(
                "colour = path class of the peak: {}",
                PathClass::LABELS
                    .iter()
                    .map(|&c| {
                        let [r, g, b] = label_color(Some(c));
                        format!("{} {r} {g} {b}", c.name())
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            format!(
                "label = path class number: {}; intensity = peak maximum (DN)",
                PathClass::LABELS
                    .iter()
                    .map(|&c| format!("{} {}", label_number(Some(c)), c.name()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ],
        ..PointCloud::default()
    };
    for (i, p) in &in_base {
        let q = &r.profile.points[*i];
        cloud.push_colored([mm(p)], label_color(q.label));
        cloud.labels.push(label_number(q.label));
        cloud.intensities.push(q.intensity);
    }
    write_ply(&dir.join(FILES[3]), &cloud, ply)?;

    let parameters: BTreeMap<String, f64> = sample
        .draw
        .values
        .iter()
        .map(|(p, v)| (p.key().to_owned(), *v))
        .collect();
    let edge_point_mm = sample.edge_point.as_ref().map(mm);
    let target = world
        .target
        .as_ref()
        .expect("make_sample checked the target");
    let edge_point_sensor_mm = sample.edge_point.map(|p| {
        let s = sample.pose.sensor.inverse() * p;
        [s.x * 1e3, s.z * 1e3]
    });
    let truth = GroundTruth {
        index: sample.index,
        noise_seed: sample.draw.noise_seed,
        border_fraction: sample.draw.border_fraction,
        parameters: parameters.clone(),
        scan_angle_deg: tidy_decimal(world.scan.scan_angle_rad.to_degrees()),
        exposure_ms: tidy_decimal(world.sensor.imager.exposure_s * 1e3),
        wavelength_nm: tidy_decimal(world.sensor.laser.wavelength_m * 1e9),
        target: &world.objects[target.object].name,
        target_pose: (&sample.target_pose).into(),
        target_nominal_pose: (&target.nominal_pose).into(),
        sensor_pose: (&sample.pose.sensor).into(),
        flange_pose: (&sample.pose.flange).into(),
        mount: (&world.mount).into(),
        edge_point_mm,
        edge_point_sensor_mm,
        ideal_points: sample.ideal.len(),
        files: FILES,
    };
    json::write_json_line(&dir.join(FILES[4]), &truth)?;
    write_csv_table(&dir.join(FILES[5]), &ideal_table(&sample.ideal))?;

    let mut labels = BTreeMap::new();
    for (i, _) in &in_base {
        if let Some(c) = r.profile.points[*i].label {
            *labels.entry(c.name().to_owned()).or_insert(0) += 1;
        }
    }
    Ok(ManifestLine {
        index: sample.index,
        directory: sample_dir_name(sample.index),
        seed: sample.draw.noise_seed,
        border_fraction: sample.draw.border_fraction,
        parameters,
        edge_point_mm,
        valid_points: in_base.len(),
        labels,
        saturated_pixels: r.saturated_pixels,
        files: record_files(dir, &FILES)?,
        warnings: pose_warnings(r, &world.sensor.range),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directory_names_round_trip() {
        assert_eq!(sample_dir_name(123), "sample_000123");
        assert_eq!(sample_dir_name(1_234_567), "sample_1234567");
        for i in [0, 5, 999_999, 1_000_000] {
            assert_eq!(parse_sample_dir_name(&sample_dir_name(i)), Some(i));
        }
        for other in ["sample_12", "sample_00001x", "run.json", "sample_"] {
            assert_eq!(parse_sample_dir_name(other), None, "{other}");
        }
    }
}
