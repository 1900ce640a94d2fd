//! Coherent imaging of optically rough surfaces: laser speckle and diffraction blur.
//!
//! A rough surface (ground edge, table, tape) lit by the laser scatters a field whose phase is
//! random from point to point. The camera forms the coherent image of that field: the image
//! field is the object field convolved with the lens's amplitude point-spread function, the
//! Airy amplitude h(r) = 2·J₁(v)/v with v = π·r/(λ·N_w) for a circular pupil at image-side
//! working f-number N_w (Goodman, *Speckle Phenomena in Optics*, 2007, ch. 4–5; the kernel is
//! `sensor::diffraction::AiryPsf`). The pixel integrates |field|². Grains are ~λ·N_w across,
//! so a larger aperture gives finer speckle, and the speckle noise of the line centre follows
//! Dorsch, Häusler & Herrmann (Appl. Opt. 33(7), 1994): δz = C·λ / (2π·sin u_obs·sin θ).
//!
//! Method: the incoherent irradiance from the light tracer (which has no diffraction) is the
//! mean intensity. On a sub-pixel grid (`oversampling` points per pixel and axis) the object
//! field is √I·e^{iφ} with independent uniform phases φ (a surface rough on the scale of the
//! sub-grid, i.e. δ-correlated at the resolution that matters; keyed as `tiles` documents),
//! convolved with h normalised to Σ|h|² = 1 so that the mean intensity is I blurred by the
//! incoherent PSF |h|² (`AiryPsf::blur`, exactly). A speckle contrast C < 1 (wavelength,
//! angle or polarisation diversity) is modelled as the average of M = round(1/C²) independent
//! patterns (contrast 1/√M). The image is processed in 16 × 16-pixel tiles with a halo of the
//! kernel's reach; tiles whose light is below 1e-4 of the image's brightest pixel get the
//! incoherent mean image instead (faint stray light, < 0.1 DN at a line near full scale).
//!
//! Two implementations of the same convolution: [`speckle_image`] by FFT per tile (`fft`,
//! milliseconds per pose; f32 arithmetic) and [`speckle_image_direct`] term by term (`direct`,
//! f64, the reference it is tested against: within 2·10⁻⁶ of the brightest pixel, measured
//! 3·10⁻⁷). Both are bit-identical for any thread count.

mod direct;
mod fft;
mod tiles;

use super::diffraction::AiryPsf;
use super::image::Image;
use crate::sampler::PoseSampler;

/// Speckle settings.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SpeckleSettings {
    /// Speckle contrast C of the object-side field in (0, 1]; 1 = fully developed speckle.
    pub contrast: f64,
    /// Sub-samples per pixel and axis of the coherent grid (≥ 2): the grid must resolve the
    /// Airy core (radius 1.22·λ·N_w ≈ 2.4 µm at f/2.8, 6.9 µm at f/8; pixels are 9.4 µm).
    /// The pixels' speckle contrast converges to the analytic one as the grid is refined: for
    /// the shipped head it is 10 % low at 8×, 1 % at 16× (validation
    /// `physics::speckle::pixel_integrated_speckle_contrast_…`), while the lens stage's cost
    /// grows as the square of this number.
    pub oversampling: usize,
}

/// Replaces the incoherent irradiance `rough` (W/m²) of rough-surface returns by its coherent
/// image (speckle and diffraction blur) through the lens of `psf` (whose oversampling is the
/// coherent grid's), with speckle `contrast` C; random phases come from `sampler`, keyed by
/// sub-sample and pattern. Computed by FFT in f32; equal to [`speckle_image_direct`] to f32
/// rounding (~3·10⁻⁷ of the brightest pixel).
pub fn speckle_image(
    rough: &Image<f64>,
    psf: &AiryPsf,
    contrast: f64,
    sampler: &PoseSampler,
) -> Image<f64> {
    let tiles = tiles::coherent_tiles(rough, tiles::halo(psf));
    let pixels = fft::tile_pixels(rough, psf, contrast, sampler, &tiles);
    tiles::assemble(rough, psf, &tiles, &pixels)
}

/// The reference for [`speckle_image`]: the same image, convolved directly (O(kernel²) per
/// sub-sample, ~100× slower). For tests and the benchmark.
pub fn speckle_image_direct(
    rough: &Image<f64>,
    psf: &AiryPsf,
    contrast: f64,
    sampler: &PoseSampler,
) -> Image<f64> {
    let tiles = tiles::coherent_tiles(rough, tiles::halo(psf));
    let pixels = direct::tile_pixels(rough, psf, contrast, sampler, &tiles);
    tiles::assemble(rough, psf, &tiles, &pixels)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat_patch(level: f64) -> Image<f64> {
        let mut img = Image::new(128, 128);
        for y in 16..112 {
            for x in 16..112 {
                img.data[y * 128 + x] = level;
            }
        }
        img
    }

    /// Pixels of the patch's interior (clear of the blurred border).
    fn interior(img: &Image<f64>) -> Vec<f64> {
        (32..96)
            .flat_map(|y| (32..96).map(move |x| (x, y)))
            .map(|(x, y)| img.get(x, y))
            .collect()
    }

    /// Mean and contrast (σ/mean) of `values`.
    fn mean_contrast(values: &[f64]) -> (f64, f64) {
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64;
        (mean, var.sqrt() / mean)
    }

    /// 1 µm pixels at f/8 and 658 nm on a 2× grid: grains ~5 µm, far larger than a pixel.
    fn test_psf() -> AiryPsf {
        AiryPsf::new(658e-9, 8.0, 1e-6, 2)
    }

    #[test]
    fn fully_developed_speckle_keeps_the_mean_and_has_unit_contrast() {
        // Pixels do not average grains, so the statistics are those of the intensity itself:
        // exponential, contrast 1 (Goodman 2007, §3.2). ~160 grains per patch, 4 patches.
        // The direct reference gives the same figures (same phases).
        let psf = test_psf();
        for (name, image) in [
            ("fft", speckle_image as fn(&_, &_, f64, &_) -> Image<f64>),
            ("direct", speckle_image_direct),
        ] {
            let mut values = Vec::new();
            for seed in 0..4 {
                let s = PoseSampler::new(3, seed);
                values.extend(interior(&image(&flat_patch(1.0), &psf, 1.0, &s)));
            }
            let (mean, contrast) = mean_contrast(&values);
            eprintln!("{name}: mean {mean:.4}, contrast {contrast:.4}");
            assert!((mean - 1.0).abs() < 0.1, "mean {mean}");
            assert!((contrast - 1.0).abs() < 0.15, "contrast {contrast}");
        }
    }

    #[test]
    fn reduced_contrast_averages_independent_patterns() {
        let (psf, s) = (test_psf(), PoseSampler::new(4, 0));
        let run =
            |c: f64| mean_contrast(&interior(&speckle_image(&flat_patch(1.0), &psf, c, &s))).1;
        let (c1, c_half) = (run(1.0), run(0.5));
        eprintln!("contrast 1 → {c1:.4}, contrast 0.5 → {c_half:.4}");
        assert!((c_half / c1 - 0.5).abs() < 0.15, "{c1} → {c_half}");
    }

    #[test]
    fn faint_light_gets_the_incoherent_mean_image() {
        // A bright pixel and, 100 px away, light at 1e-5 of it: that tile keeps no speckle but
        // the lens's incoherent blur, the coherent image's expectation.
        let psf = AiryPsf::new(658e-9, 23.5, 9.4e-6, 8);
        let mut img = Image::new(160, 40);
        img.data[20 * 160 + 10] = 1.0;
        img.data[20 * 160 + 120] = 1e-5;
        let out = speckle_image(&img, &psf, 1.0, &PoseSampler::new(1, 2));
        let mean = psf.blur(&img);
        for y in 0..40 {
            for x in 100..160 {
                assert_eq!(out.get(x, y), mean.get(x, y));
            }
        }
    }
}
