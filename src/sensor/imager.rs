//! The image sensor: irradiance (W/m²) → photons → electrons → digital numbers (DN).
//!
//! EMVA 1288 linear model (docs/parameters.md §2a): μ_p = A·E·t_exp·λ/(h·c), μ_e = η·μ_p, clipped at
//! the full well, μ_y = K·μ_e, clipped to 2^bits − 1. [`ImagerSpec::expose`] is that noise-free
//! mean model; [`ImagerSpec::expose_noisy`] adds shot, dark and read noise, PRNU/DSNU, the black
//! level, quantisation and blooming (`emva`, `bloom`), and falls back to `expose` when
//! `noise` is off.

use super::emva::{self, Exposure, FixedPattern};
use super::image::Image;
use crate::sampler::PoseSampler;

/// What the sensor does with charge above the full well (docs/parameters.md §2c).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SensorKind {
    /// CMOS: pixels are read independently; a pixel clips at the full well and the excess is
    /// drained, so the overflow never reaches a neighbour.
    Cmos,
    /// CCD without anti-blooming drain: the excess spills up and down its column (a vertical
    /// bleed trail, as LSST imSim's bleed trails), conserving charge.
    Ccd,
}

/// Parameters of the image sensor.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ImagerSpec {
    /// Quantum efficiency η at the laser wavelength, in (0, 1].
    pub quantum_efficiency: f64,
    /// Full-well capacity μ_e,sat (e⁻), > 0.
    pub full_well_e: f64,
    /// Overall system gain K (DN per e⁻), > 0.
    pub gain_dn_per_e: f64,
    /// ADC resolution (bits), 8…16.
    pub adc_bits: u32,
    /// Exposure (shutter) time (s), > 0.
    pub exposure_s: f64,
    /// CMOS (clip at the full well) or CCD (spill along the column).
    pub kind: SensorKind,
    /// Dark current μ_I (e⁻/s per pixel, at the operating temperature), ≥ 0.
    pub dark_current_e_per_s: f64,
    /// Temporal dark (read) noise σ_d0 (e⁻ rms), ≥ 0.
    pub read_noise_e: f64,
    /// Black level added before quantisation (DN), 0 … 2^bits − 1.
    pub dark_offset_dn: f64,
    /// Photo-response non-uniformity: relative standard deviation of the fixed per-pixel gain
    /// map, in [0, 1) (0.01 = 1 %).
    pub prnu: f64,
    /// Dark-signal non-uniformity: standard deviation of the fixed per-pixel dark offset map
    /// (e⁻), ≥ 0.
    pub dsnu_e: f64,
    /// Noise on: `expose_noisy` simulates the EMVA 1288 camera. Off: it returns the noise-free
    /// mean model of `expose` (used where a test needs exact, noiseless images).
    pub noise: bool,
}

/// Planck constant (J·s), CODATA 2018 exact value.
pub const PLANCK_J_S: f64 = 6.626_070_15e-34;
/// Speed of light in vacuum (m/s), exact.
pub const SPEED_OF_LIGHT_M_S: f64 = 299_792_458.0;

impl ImagerSpec {
    /// Largest digital number the ADC can output.
    pub fn max_dn(&self) -> u16 {
        ((1u32 << self.adc_bits) - 1) as u16
    }

    /// Mean photon count μ_p = A·E·t_exp·λ/(h·c) for irradiance `e_w_m2` on a pixel of area
    /// `pixel_area_m2` (EMVA 1288, docs/parameters.md §2a).
    pub fn photons(&self, e_w_m2: f64, pixel_area_m2: f64, wavelength_m: f64) -> f64 {
        e_w_m2 * pixel_area_m2 * self.exposure_s * wavelength_m / (PLANCK_J_S * SPEED_OF_LIGHT_M_S)
    }

    /// Noise-free digital number for a mean photon count: η·μ_p electrons, clipped at the full
    /// well, times K, rounded and clipped to the ADC range.
    pub fn digitize(&self, photons: f64) -> u16 {
        let electrons = (self.quantum_efficiency * photons).min(self.full_well_e);
        let dn = (self.gain_dn_per_e * electrons).round();
        dn.clamp(0.0, self.max_dn() as f64) as u16
    }

    /// Exposes an irradiance image (W/m²) and returns the digital image (DN).
    pub fn expose(
        &self,
        irradiance: &Image<f64>,
        pixel_area_m2: f64,
        wavelength_m: f64,
    ) -> Image<u16> {
        Image {
            width: irradiance.width,
            height: irradiance.height,
            data: irradiance
                .data
                .iter()
                .map(|&e| self.digitize(self.photons(e, pixel_area_m2, wavelength_m)))
                .collect(),
        }
    }

    /// Exposes an irradiance image (W/m², on pixels of `pixel_area_m2` at `wavelength_m`) with
    /// the EMVA 1288 noise model (`emva`): shot noise, dark current, read noise, PRNU/DSNU,
    /// black level, dithered quantisation, and CMOS clipping or CCD blooming. The temporal
    /// noise is keyed by `sampler` (use `emva::frame_sampler(seed, pose)`); the fixed pattern
    /// is the sensor unit's (`SensorHead::fixed_pattern`), the same for every frame. With
    /// `noise` off, `dn` equals [`ImagerSpec::expose`].
    pub fn expose_noisy(
        &self,
        irradiance: &Image<f64>,
        pixel_area_m2: f64,
        wavelength_m: f64,
        sampler: &PoseSampler,
        pattern: &FixedPattern,
    ) -> Exposure {
        emva::expose(
            self,
            irradiance,
            pixel_area_m2,
            wavelength_m,
            sampler,
            pattern,
        )
    }
}

#[cfg(test)]
mod tests {
    use crate::sensor::preset::scancontrol_2600_100;

    #[test]
    fn photon_count_matches_hand_calculation() {
        let imager = scancontrol_2600_100().imager;
        // 1 W/m² on a (10 µm)² pixel for 0.5 ms at 658 nm: 5e-14 J · λ/(h·c) = 165 622 photons.
        let p = imager.photons(1.0, 1e-10, 658e-9);
        assert!((p - 165_622.4).abs() < 0.5, "{p}");
    }

    #[test]
    fn digitize_is_linear_then_clips() {
        let imager = scancontrol_2600_100().imager;
        let half_well = imager.full_well_e / imager.quantum_efficiency / 2.0;
        assert_eq!(imager.digitize(half_well), 512);
        assert_eq!(imager.digitize(10.0 * half_well), 1023);
        assert_eq!(imager.digitize(0.0), 0);
    }

    #[test]
    fn signal_scales_linearly_with_exposure_until_full_well() {
        let mut imager = scancontrol_2600_100().imager;
        let e = 2.0; // W/m²
        let a = imager.photons(e, 9.4e-6 * 9.4e-6, 658e-9);
        imager.exposure_s *= 3.0;
        let b = imager.photons(e, 9.4e-6 * 9.4e-6, 658e-9);
        assert!((b / a - 3.0).abs() < 1e-12);
        let dn = |p: f64| imager.digitize(p) as f64;
        // 100 e⁻ → 6.82 DN: linear to the rounding.
        assert!((dn(600.0) - 3.0 * dn(200.0)).abs() <= 1.5);
    }
}
