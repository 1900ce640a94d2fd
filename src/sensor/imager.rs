//! The image sensor: irradiance (W/m²) → photons → electrons → digital numbers (DN).
//!
//! EMVA 1288 linear model (PARAMETERS.md §2a): μ_p = A·E·t_exp·λ/(h·c), μ_e = η·μ_p, clipped at
//! the full well, μ_y = K·μ_e, clipped to 2^bits − 1. This is the noise-free part of the model;
//! shot, dark and read noise, PRNU/DSNU and blooming belong to the sensor-realism issue (#4).

/// Parameters of the image sensor.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ImagerSpec {
    /// Quantum efficiency η at the laser wavelength, in (0, 1].
    pub quantum_efficiency: f64,
    /// Full-well capacity (e⁻), > 0.
    pub full_well_e: f64,
    /// Overall system gain K (DN per e⁻), > 0.
    pub gain_dn_per_e: f64,
    /// ADC resolution (bits), 8…16.
    pub adc_bits: u32,
    /// Exposure (shutter) time (s), > 0.
    pub exposure_s: f64,
}

use super::image::Image;

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
    /// `pixel_area_m2` (EMVA 1288, PARAMETERS.md §2a).
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
