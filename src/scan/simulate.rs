//! One scan pose end to end: light transport → exposure → profile.

use super::poses::ScanPose;
use crate::sensor::image::Image;
use crate::sensor::profile::{extract, ExtractSettings, Profile};
use crate::sensor::SensorHead;
use crate::transport::{render, Irradiance, TraceScene, TraceSettings, TraceStats};

/// Everything the sensor produced at one pose.
#[derive(Clone, Debug)]
pub struct PoseResult {
    /// The pose.
    pub pose: ScanPose,
    /// Irradiance on the image plane (W/m²), in total and per path class.
    pub irradiance: Irradiance,
    /// Digital image (DN, `imager.adc_bits` wide).
    pub image: Image<u16>,
    /// The extracted profile.
    pub profile: Profile,
    /// Transport counters.
    pub stats: TraceStats,
}

/// Simulates the sensor `head` at `pose`.
pub fn simulate_pose(
    scene: &TraceScene,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
) -> PoseResult {
    let (irradiance, stats) = render(scene, head, &pose.sensor, settings, pose.index as u64);
    let cfg = &head.config;
    let image = cfg.imager.expose(
        &irradiance.total,
        head.camera.pixel_area(),
        cfg.laser.wavelength_m,
    );
    let profile = extract(
        &image,
        &head.camera,
        &ExtractSettings {
            threshold_dn: cfg.threshold_dn,
            points_per_profile: cfg.points_per_profile,
        },
    );
    PoseResult {
        pose: pose.clone(),
        irradiance,
        image,
        profile,
        stats,
    }
}
