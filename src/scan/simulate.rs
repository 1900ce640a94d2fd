//! One scan pose end to end: light transport → coherent imaging (speckle) → image sensor
//! (EMVA 1288 noise, full well) → profile firmware.

use super::poses::ScanPose;
use crate::sampler::PoseSampler;
use crate::sensor::emva::frame_sampler;
use crate::sensor::image::Image;
use crate::sensor::path_class::PathClass;
use crate::sensor::profile::{extract, Profile};
use crate::sensor::speckle::speckle_image;
use crate::sensor::SensorHead;
use crate::transport::{render, Irradiance, TraceScene, TraceSettings, TraceStats};

/// Everything the sensor produced at one pose.
#[derive(Clone, Debug)]
pub struct PoseResult {
    /// The pose.
    pub pose: ScanPose,
    /// Irradiance on the image plane (W/m²), in total and per path class, after speckle.
    pub irradiance: Irradiance,
    /// Digital image (DN, `imager.adc_bits` wide).
    pub image: Image<u16>,
    /// Pixels at the full well or at the ADC's full scale.
    pub saturated_pixels: usize,
    /// The extracted profile.
    pub profile: Profile,
    /// Transport counters.
    pub stats: TraceStats,
}

/// Stream of the speckle phases: apart from the transport's (the pose index) and the sensor
/// noise's (`frame_sampler`) streams.
const SPECKLE_STREAM: u64 = 0x5bec_1e00_0000_0000;

/// Replaces the light of every class but glints by its coherent image (speckle and
/// diffraction). All rough-surface light interferes together, so one coherent image is made of
/// their sum and shared among the classes in proportion to their incoherent irradiance at each
/// pixel. Glints come from polished faces (no speckle) and their diffraction spot
/// (1.22·λ·N ≈ 2 µm) is far below a pixel, so they stay as traced.
fn apply_speckle(irradiance: &mut Irradiance, head: &SensorHead, pose: &ScanPose, seed: u64) {
    let Some(settings) = head.config.speckle else {
        return;
    };
    let cam = &head.camera;
    let glint = PathClass::Glint.index();
    let mut rough = irradiance.total.clone();
    for (r, g) in rough.data.iter_mut().zip(&irradiance.by_class[glint].data) {
        *r = (*r - g).max(0.0);
    }
    if rough.data.iter().all(|&v| v == 0.0) {
        return;
    }
    let speckled = speckle_image(
        &rough,
        head.config.laser.wavelength_m,
        cam.working_f_number(0.0, head.config.range.z_mid_m()),
        cam.spec().pixel_pitch_m,
        &settings,
        &PoseSampler::new(seed, SPECKLE_STREAM ^ pose.index as u64),
    );
    for (k, layer) in irradiance.by_class.iter_mut().enumerate() {
        if k == glint {
            continue;
        }
        for ((v, s), r) in layer.data.iter_mut().zip(&speckled.data).zip(&rough.data) {
            if *r > 0.0 {
                *v *= s / r;
            }
        }
    }
    for ((t, s), g) in irradiance
        .total
        .data
        .iter_mut()
        .zip(&speckled.data)
        .zip(&irradiance.by_class[glint].data)
    {
        *t = s + g;
    }
}

/// The light that reaches the image plane at `pose`: the traced irradiance per path class
/// after speckle. It does not depend on the exposure, the threshold or the peak selection, so a
/// study that sweeps those traces each pose once and senses it many times ([`sense_pose`]).
pub fn trace_pose(
    scene: &TraceScene,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
) -> (Irradiance, TraceStats) {
    let (mut irradiance, stats) = render(scene, head, &pose.sensor, settings, pose.index as u64);
    apply_speckle(&mut irradiance, head, pose, settings.seed);
    (irradiance, stats)
}

/// The image sensor and the firmware at `pose`, given the light of [`trace_pose`]: EMVA 1288
/// exposure with the keyed noise of (seed, pose index), then the profile.
pub fn sense_pose(
    irradiance: Irradiance,
    stats: TraceStats,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
) -> PoseResult {
    let cfg = &head.config;
    let exposure = cfg.imager.expose_noisy(
        &irradiance.total,
        head.camera.pixel_area(),
        cfg.laser.wavelength_m,
        &frame_sampler(settings.seed, pose.index as u64),
    );
    let profile = extract(
        &exposure.dn,
        Some(&irradiance.by_class),
        &head.camera,
        &cfg.firmware,
    );
    PoseResult {
        pose: pose.clone(),
        irradiance,
        image: exposure.dn,
        saturated_pixels: exposure.saturated,
        profile,
        stats,
    }
}

/// Simulates the sensor `head` at `pose`: [`trace_pose`] then [`sense_pose`].
pub fn simulate_pose(
    scene: &TraceScene,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
) -> PoseResult {
    let (irradiance, stats) = trace_pose(scene, head, pose, settings);
    sense_pose(irradiance, stats, head, pose, settings)
}
