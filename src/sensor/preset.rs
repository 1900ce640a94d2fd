//! Named sensor presets. Every number cites docs/parameters.md, where its source and confidence are.

use super::camera::CameraSpec;
use super::imager::{ImagerSpec, SensorKind};
use super::profile::{FirmwareSettings, DRIVER_DEFAULT_THRESHOLD_DN};
use super::projector::{LaserSheet, LineProfile, Polarization};
use super::speckle::SpeckleSettings;
use super::{MeasuringRange, SensorConfig};

/// Names accepted by [`by_name`].
pub const PRESET_NAMES: &[&str] = &["scancontrol-2600-100"];

/// Looks a preset up by name; `None` for an unknown name.
pub fn by_name(name: &str) -> Option<SensorConfig> {
    match name {
        "scancontrol-2600-100" => Some(scancontrol_2600_100()),
        _ => None,
    }
}

/// A Micro-Epsilon scanCONTROL 2600-100 class head.
///
/// - z range 125–390 mm, x width 143.5 mm at the far end (docs/parameters.md §1c, Zebra/MIL
///   `PRANGE`, M–H); 640 points per profile (§1a SDK, H); 658 nm (paper, H).
/// - Laser power 8 mW (class 2M, §1c, L). Waist 1/e² full width 0.35 mm at 257.5 mm, the
///   Gaussian optimum over the range (§4, derived, M). Fan 24° (not published; chosen to cover
///   the camera field, L). Uniform (Powell) line (§4, H for the lens type). Linearly polarised
///   along the line (x): laser diodes emit linearly polarised light (L for the axis: not
///   published for the scanCONTROL; the scene file can set any axis or unpolarised).
/// - Camera: not published. Base 100 mm (triangulation angle 21° at mid-range, inside the
///   20–35° band of §1c, L); f = 16 mm, f/2.8; 640 × 832 pixels of 9.4 µm, sized so that the
///   columns cover ±71.75 mm at z = 390 mm and the rows cover 125–390 mm (derived).
/// - Imager: QE 0.5 at 658 nm (§2b, L); full well 15 000 e⁻ (§2b emva1288 default, M); 10-bit
///   ADC, K = 1023/15 000 DN/e⁻ so the full well maps to full scale (§1a/§2b); exposure
///   0.5 ms (§1a driver default, M); threshold 128 DN (§1a driver default, H).
/// - Imager noise (EMVA 1288, §2a): CMOS, clipping at the full well without spill (§2c
///   simulator default; the sensor type is not published, §1c, L). Read noise σ_d0 = 10 e⁻,
///   inside the 7–13 e⁻ of §2b (IMX174 6.83 H, ICX625 8.28–13 H, CMV2000 ~13 L; M as a
///   choice). Dark current 125 e⁻/s (CMV300 datasheet, §2b, H for that sensor, M by analogy):
///   0.06 e⁻ in 0.5 ms. Black level 0 DN (`EMVA1288/emva1288` `camera.py` default
///   `blackoffset = 0`, M; the head's own black level is not published). PRNU 1 % and DSNU
///   3 e⁻: typical magnitudes, no datasheet (L). Noise on.
pub fn scancontrol_2600_100() -> SensorConfig {
    SensorConfig {
        preset: "scancontrol-2600-100".to_owned(),
        laser: LaserSheet {
            wavelength_m: 658e-9,
            power_w: 8e-3,
            fan_angle_rad: 24f64.to_radians(),
            waist_radius_m: 0.175e-3,
            waist_distance_m: 0.2575,
            m_squared: 1.0,
            line_profile: LineProfile::Uniform,
            polarization: Polarization::Linear { angle_rad: 0.0 },
        },
        camera: CameraSpec {
            baseline_m: 0.100,
            lens_z_m: 0.0,
            aim_distance_m: 0.240,
            focal_length_m: 0.016,
            f_number: 2.8,
            pixel_pitch_m: 9.4e-6,
            columns: 640,
            rows: 832,
        },
        imager: ImagerSpec {
            quantum_efficiency: 0.5,
            full_well_e: 15_000.0,
            gain_dn_per_e: 1023.0 / 15_000.0,
            adc_bits: 10,
            exposure_s: 0.5e-3,
            kind: SensorKind::Cmos,
            dark_current_e_per_s: 125.0,
            read_noise_e: 10.0,
            dark_offset_dn: 0.0,
            prnu: 0.01,
            dsnu_e: 3.0,
            noise: true,
        },
        range: MeasuringRange {
            z_min_m: 0.125,
            z_max_m: 0.390,
            x_width_m: 0.1435,
        },
        firmware: FirmwareSettings::scancontrol_default(DRIVER_DEFAULT_THRESHOLD_DN),
        speckle: Some(SpeckleSettings {
            contrast: 1.0,
            oversampling: 8,
        }),
    }
}
