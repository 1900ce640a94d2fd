//! The sensor head in its own frame S (scanCONTROL convention): the laser plane is y = 0,
//! x runs along the laser line and z is the measuring direction away from the sensor.
//!
//! - `projector`: the laser sheet (fan from a virtual source at the origin, Gaussian-beam
//!   thickness, power, wavelength).
//! - `camera`: thin lens with a finite aperture and a Scheimpflug-tilted image plane on which
//!   the whole laser plane is in focus; the exact map pixel ↔ (x, z) in the laser plane.
//! - `imager`, `emva`, `bloom`: irradiance → photons → electrons → digital numbers, with the
//!   EMVA 1288 noise model and full-well overflow (CMOS clip, CCD bleed).
//! - `diffraction`: the lens's Airy PSF, coherent (sub-pixel amplitude) and incoherent
//!   (integrated over pixels: the blur of light that forms no speckle).
//! - `speckle`: coherent imaging of rough returns (speckle and diffraction), by FFT.
//! - `path_class`: what produced the light on the sensor.
//! - `profile`: the firmware: per-column peaks, filters, selection modes, triangulation.
//! - `preset`: named sensor presets (`scancontrol-2600-100`).
//!
//! Units: SI inside (m, s, W, rad). Images are row-major, row 0 at the top (near range).

pub mod bloom;
pub mod camera;
pub mod diffraction;
pub mod emva;
pub mod image;
pub mod imager;
pub mod path_class;
pub mod preset;
pub mod profile;
pub mod projector;
pub mod speckle;

use camera::CameraSpec;
use imager::ImagerSpec;
use projector::LaserSheet;

/// The measuring range of the head (for validation of scan standoffs and reports).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MeasuringRange {
    /// Start of the z range (m).
    pub z_min_m: f64,
    /// End of the z range (m).
    pub z_max_m: f64,
    /// Largest x width of the field, reached at `z_max_m` (m).
    pub x_width_m: f64,
}

impl MeasuringRange {
    /// Middle of the z range (m): the default scan standoff.
    pub fn z_mid_m(&self) -> f64 {
        0.5 * (self.z_min_m + self.z_max_m)
    }
}

/// A complete sensor head: projector, camera, image sensor and profile settings.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SensorConfig {
    /// Preset name it was built from (e.g. `scancontrol-2600-100`).
    pub preset: String,
    /// The laser sheet.
    pub laser: LaserSheet,
    /// The receiving camera.
    pub camera: CameraSpec,
    /// The image sensor behind the camera.
    pub imager: ImagerSpec,
    /// Nominal measuring range.
    pub range: MeasuringRange,
    /// The profile firmware: threshold, peak filters, selection mode, points per profile.
    pub firmware: profile::FirmwareSettings,
    /// Laser speckle on rough-surface returns; `None` = incoherent image (still blurred by
    /// the lens's diffraction, `diffraction::AiryPsf`).
    pub speckle: Option<speckle::SpeckleSettings>,
}

/// A sensor configuration with its camera built (the Scheimpflug plane solved once).
#[derive(Clone, Debug)]
pub struct SensorHead {
    /// The configuration.
    pub config: SensorConfig,
    /// The camera model.
    pub camera: camera::Camera,
    /// The image sensor's fixed pattern (PRNU and DSNU maps) of this simulated unit, made once
    /// and shared by every exposure and every clone of the head.
    pub fixed_pattern: std::sync::Arc<emva::FixedPattern>,
}

impl SensorHead {
    /// Builds the camera of `config`; fails if the measuring range does not image onto the
    /// pixel grid.
    pub fn new(config: &SensorConfig) -> Result<SensorHead, camera::CameraError> {
        SensorHead::new_like(config, None)
    }

    /// [`SensorHead::new`], sharing `unit`'s fixed pattern where it is the pattern `config`
    /// would make (the same PRNU, DSNU and pixel grid: the pattern depends on nothing else),
    /// as the samples of a randomised dataset do; making it costs two Gaussian draws per pixel.
    pub fn new_like(
        config: &SensorConfig,
        unit: Option<&SensorHead>,
    ) -> Result<SensorHead, camera::CameraError> {
        let camera = camera::Camera::new(&config.camera, &config.range)?;
        let (w, h) = (camera.spec().columns, camera.spec().rows);
        let fixed_pattern = match unit {
            Some(u) if u.fixed_pattern.fits(&config.imager, w, h) => u.fixed_pattern.clone(),
            _ => std::sync::Arc::new(emva::FixedPattern::new(&config.imager, w, h)),
        };
        Ok(SensorHead {
            config: config.clone(),
            camera,
            fixed_pattern,
        })
    }

    /// The lens's image-side working f-number, taken at mid-range for the whole image (the
    /// lens stage's one PSF, `scan::simulate::apply_lens_psf`).
    pub fn lens_f_number(&self) -> f64 {
        self.camera
            .working_f_number(0.0, self.config.range.z_mid_m())
    }

    /// The lens's Airy PSF at [`SensorHead::lens_f_number`] and the laser's wavelength, on a
    /// grid of `oversampling` sub-samples per pixel and axis.
    pub fn lens_psf(&self, oversampling: usize) -> diffraction::AiryPsf {
        diffraction::AiryPsf::new(
            self.config.laser.wavelength_m,
            self.lens_f_number(),
            self.camera.spec().pixel_pitch_m,
            oversampling,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn a_head_like_another_shares_its_fixed_pattern_only_where_it_is_the_same() {
        let config = preset::scancontrol_2600_100();
        let unit = SensorHead::new(&config).unwrap();
        let mut exposed_longer = config.clone();
        exposed_longer.imager.exposure_s *= 3.0;
        let same = SensorHead::new_like(&exposed_longer, Some(&unit)).unwrap();
        assert!(Arc::ptr_eq(&same.fixed_pattern, &unit.fixed_pattern));
        assert_eq!(
            *same.fixed_pattern,
            *SensorHead::new(&exposed_longer).unwrap().fixed_pattern
        );
        let mut other_unit = config.clone();
        other_unit.imager.prnu *= 2.0;
        let other = SensorHead::new_like(&other_unit, Some(&unit)).unwrap();
        assert!(!Arc::ptr_eq(&other.fixed_pattern, &unit.fixed_pattern));
        assert_eq!(
            *other.fixed_pattern,
            *SensorHead::new(&other_unit).unwrap().fixed_pattern
        );
    }
}
