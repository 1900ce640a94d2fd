//! Coherent imaging of optically rough surfaces: diffraction blur and laser speckle.
//!
//! A rough surface (ground edge, table, tape) lit by the laser scatters a field whose phase is
//! random from point to point. The camera forms the coherent image of that field: the image
//! field is the object field convolved with the lens's amplitude point-spread function, the
//! Airy amplitude h(r) = 2·J₁(v)/v with v = π·r/(λ·N_w) for a circular pupil at image-side
//! working f-number N_w (Goodman, *Speckle Phenomena in Optics*, 2007, ch. 4–5). The pixel
//! integrates |field|². Grains are ~λ·N_w across, so a larger aperture gives finer speckle, and
//! the speckle noise of the line centre follows Dorsch, Häusler & Herrmann (Appl. Opt. 33(7),
//! 1994): δz = C·λ / (2π·sin u_obs·sin θ) (PARAMETERS.md §5).
//!
//! Method: the incoherent irradiance from the light tracer (which has no diffraction) is the
//! mean intensity. On a sub-pixel grid (`oversampling` points per pixel and axis) the object
//! field is √I·e^{iφ} with independent uniform phases φ (a surface rough on the scale of the
//! sub-grid, i.e. δ-correlated at the resolution that matters), convolved with h normalised to
//! Σ|h|² = 1 so that the mean intensity is I blurred by the incoherent PSF |h|². A speckle
//! contrast C < 1 (wavelength, angle or polarisation diversity) is modelled as the average of
//! M = round(1/C²) independent patterns (contrast 1/√M). The image is processed in tiles with
//! a halo of the kernel's radius; tiles whose light is below 1e-4 of the image's brightest pixel
//! keep their incoherent irradiance (faint stray light, < 0.1 DN at a line near full scale).

use rayon::prelude::*;

use super::image::Image;
use crate::sampler::PoseSampler;

/// Speckle settings.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SpeckleSettings {
    /// Speckle contrast C of the object-side field in (0, 1]; 1 = fully developed speckle.
    pub contrast: f64,
    /// Sub-samples per pixel and axis of the coherent grid (≥ 2): the grid must resolve the
    /// Airy core (radius 1.22·λ·N_w ≈ 2.2 µm at f/2.8, 6.4 µm at f/8; pixels are 9.4 µm).
    pub oversampling: usize,
}

/// Pixels per tile side.
const TILE: usize = 16;
/// Tiles fainter than this fraction of the brightest pixel are left incoherent.
const FAINT_FRACTION: f64 = 1e-4;
/// The Airy amplitude is kept out to this many dark rings.
const AIRY_RINGS: f64 = 4.0;

/// Bessel function J₁ (Numerical Recipes 2nd ed. §6.5 `bessj1`, rational and asymptotic fits,
/// |error| < 1e-7).
fn bessel_j1(x: f64) -> f64 {
    let ax = x.abs();
    if ax < 8.0 {
        let y = x * x;
        let a1 = x
            * (72_362_614_232.0
                + y * (-7_895_059_235.0
                    + y * (242_396_853.1
                        + y * (-2_972_611.439 + y * (15_704.482_60 + y * -30.160_366_06)))));
        let a2 = 144_725_228_442.0
            + y * (2_300_535_178.0
                + y * (18_583_304.74 + y * (99_447.433_94 + y * (376.999_139_7 + y))));
        a1 / a2
    } else {
        let z = 8.0 / ax;
        let y = z * z;
        let xx = ax - 3.0 * std::f64::consts::FRAC_PI_4;
        let a1 = 1.0
            + y * (0.183_105e-2
                + y * (-0.351_639_649_6e-4 + y * (0.245_752_017_3e-5 + y * -0.240_337_019e-6)));
        let a2 = 0.046_874_999_95
            + y * (-0.200_269_087_3e-3
                + y * (0.844_919_909_6e-5 + y * (-0.882_289_87e-6 + y * 0.105_787_412e-6)));
        let r = (std::f64::consts::FRAC_2_PI / ax).sqrt() * (xx.cos() * a1 - z * xx.sin() * a2);
        if x < 0.0 {
            -r
        } else {
            r
        }
    }
}

/// The Airy amplitude kernel on the sub-grid: (half-width in sub-samples, weights row-major),
/// normalised so that Σ h² = 1.
fn airy_kernel(wavelength_m: f64, f_number: f64, sub_pitch_m: f64) -> (usize, Vec<f64>) {
    // First zero of 2J₁(v)/v at v = 3.8317, i.e. r = 1.22·λ·N; rings every ~π in v.
    let v_max = 3.8317 + (AIRY_RINGS - 1.0) * std::f64::consts::PI;
    let r_max = v_max * wavelength_m * f_number / std::f64::consts::PI;
    let half = (r_max / sub_pitch_m).ceil() as usize;
    let n = 2 * half + 1;
    let mut k = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let (dy, dx) = (i as f64 - half as f64, j as f64 - half as f64);
            let r = (dx * dx + dy * dy).sqrt() * sub_pitch_m;
            let v = std::f64::consts::PI * r / (wavelength_m * f_number);
            k[i * n + j] = if r > r_max {
                0.0
            } else if v < 1e-9 {
                1.0
            } else {
                2.0 * bessel_j1(v) / v
            };
        }
    }
    let norm = k.iter().map(|h| h * h).sum::<f64>().sqrt();
    k.iter_mut().for_each(|h| *h /= norm);
    (half, k)
}

/// Replaces the incoherent irradiance `rough` (W/m²) of rough-surface returns by its coherent
/// image: speckle and diffraction blur. `wavelength_m`, `f_number` (image-side working
/// f-number N_w) and `pixel_pitch_m` describe the camera; random phases come from `sampler`,
/// keyed by sub-sample index and pattern number.
pub fn speckle_image(
    rough: &Image<f64>,
    wavelength_m: f64,
    f_number: f64,
    pixel_pitch_m: f64,
    settings: &SpeckleSettings,
    sampler: &PoseSampler,
) -> Image<f64> {
    let q = settings.oversampling.max(2);
    let (half, kernel) = airy_kernel(wavelength_m, f_number, pixel_pitch_m / q as f64);
    let kn = 2 * half + 1;
    let halo = half.div_ceil(q);
    let patterns = (1.0 / (settings.contrast * settings.contrast))
        .round()
        .max(1.0) as usize;
    let (w, h) = (rough.width, rough.height);
    let tiles: Vec<(usize, usize)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..w.div_ceil(TILE)).map(move |tx| (tx, ty)))
        .collect();
    // Tiles whose brightest pixel is below FAINT_FRACTION of the image's keep their incoherent
    // irradiance: stray light that faint (< 0.1 DN for a line near full scale) gains nothing
    // from a coherent image and would cost most of the time.
    let faint = FAINT_FRACTION * rough.data.iter().copied().fold(0.0, f64::max);
    // Each tile yields its own pixels; tiles are reassembled in order (deterministic).
    let results: Vec<Option<Vec<f64>>> = tiles
        .par_iter()
        .map(|&(tx, ty)| {
            let (x0, y0) = (tx * TILE, ty * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            // Source region: the tile plus a halo.
            let (sx0, sy0) = (x0.saturating_sub(halo), y0.saturating_sub(halo));
            let (sx1, sy1) = ((x1 + halo).min(w), (y1 + halo).min(h));
            let tile_max = (sy0..sy1)
                .flat_map(|y| (sx0..sx1).map(move |x| (x, y)))
                .map(|(x, y)| rough.get(x, y))
                .fold(0.0, f64::max);
            if tile_max <= faint {
                return None;
            }
            let (gw, gh) = ((sx1 - sx0) * q, (sy1 - sy0) * q);
            let mut intensity = vec![0.0; (x1 - x0) * (y1 - y0) * q * q];
            for pattern in 0..patterns {
                // Object field on the source sub-grid.
                let mut re = vec![0.0; gw * gh];
                let mut im = vec![0.0; gw * gh];
                for gy in 0..gh {
                    for gx in 0..gw {
                        let (px, py) = (sx0 + gx / q, sy0 + gy / q);
                        let i = rough.get(px, py);
                        if i <= 0.0 {
                            continue;
                        }
                        // Key: the global sub-sample index, so overlapping halos agree.
                        let global = ((py * q + gy % q) * w * q + px * q + gx % q) as u64;
                        let phase =
                            2.0 * std::f64::consts::PI * sampler.uniform(global, pattern as u32);
                        let a = i.sqrt();
                        re[gy * gw + gx] = a * phase.cos();
                        im[gy * gw + gx] = a * phase.sin();
                    }
                }
                // Sub-grid rows that have some field within the kernel's reach: the line
                // crosses a tile in a few pixels, so most output rows are dark.
                let lit_rows: Vec<bool> = (0..gh)
                    .map(|gy| {
                        re[gy * gw..(gy + 1) * gw].iter().any(|&v| v != 0.0)
                            || im[gy * gw..(gy + 1) * gw].iter().any(|&v| v != 0.0)
                    })
                    .collect();
                // Coherent image on the tile's own sub-grid.
                let (ox, oy) = ((x0 - sx0) * q, (y0 - sy0) * q);
                let tw = (x1 - x0) * q;
                for ty_ in 0..(y1 - y0) * q {
                    let cy = oy + ty_;
                    let (lo, hi) = (cy.saturating_sub(half), (cy + half).min(gh - 1));
                    if !lit_rows[lo..=hi].iter().any(|&l| l) {
                        continue;
                    }
                    for tx_ in 0..tw {
                        let cx = ox + tx_;
                        let (mut fr, mut fi) = (0.0, 0.0);
                        for ky in 0..kn {
                            let gy = cy as isize + ky as isize - half as isize;
                            if gy < 0 || gy >= gh as isize || !lit_rows[gy as usize] {
                                continue;
                            }
                            let row = gy as usize * gw;
                            let krow = ky * kn;
                            for kx in 0..kn {
                                let gx = cx as isize + kx as isize - half as isize;
                                if gx < 0 || gx >= gw as isize {
                                    continue;
                                }
                                let kv = kernel[krow + kx];
                                if kv == 0.0 {
                                    continue;
                                }
                                let idx = row + gx as usize;
                                fr += kv * re[idx];
                                fi += kv * im[idx];
                            }
                        }
                        intensity[ty_ * tw + tx_] += (fr * fr + fi * fi) / patterns as f64;
                    }
                }
            }
            // Pixel = mean of its q × q sub-samples.
            let tw = (x1 - x0) * q;
            let mut pixels = vec![0.0; (x1 - x0) * (y1 - y0)];
            for (k, v) in intensity.iter().enumerate() {
                let (sy, sx) = (k / tw, k % tw);
                pixels[(sy / q) * (x1 - x0) + sx / q] += v / (q * q) as f64;
            }
            Some(pixels)
        })
        .collect();
    let mut out = rough.clone();
    for ((tx, ty), pixels) in tiles.iter().zip(results) {
        let Some(pixels) = pixels else { continue };
        let (x0, y0) = (tx * TILE, ty * TILE);
        let tw = (x0 + TILE).min(w) - x0;
        for (k, v) in pixels.into_iter().enumerate() {
            out.data[(y0 + k / tw) * w + x0 + k % tw] = v;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bessel_j1_reference_values() {
        // Abramowitz & Stegun, Table 9.1.
        for (x, j1) in [
            (1.0, 0.440_050_586),
            (2.0, 0.576_724_808),
            (5.0, -0.327_579_138),
            (10.0, 0.043_472_746),
        ] {
            assert!(
                (bessel_j1(x) - j1).abs() < 1e-7,
                "J1({x}) = {}",
                bessel_j1(x)
            );
        }
    }

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

    #[test]
    fn fully_developed_speckle_keeps_the_mean_and_has_unit_contrast() {
        // 1 µm pixels at f/8 and 658 nm: grains ~5 µm, far larger than a pixel, so pixels do
        // not average grains and the statistics are those of the intensity itself: exponential,
        // contrast 1 (Goodman 2007, §3.2). ~160 grains per patch, 4 patches.
        let settings = SpeckleSettings {
            contrast: 1.0,
            oversampling: 2,
        };
        let mut values = Vec::new();
        for seed in 0..4 {
            let s = PoseSampler::new(3, seed);
            values.extend(interior(&speckle_image(
                &flat_patch(1.0),
                658e-9,
                8.0,
                1e-6,
                &settings,
                &s,
            )));
        }
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64;
        let contrast = var.sqrt() / mean;
        assert!((mean - 1.0).abs() < 0.1, "mean {mean}");
        assert!((contrast - 1.0).abs() < 0.15, "contrast {contrast}");
    }

    #[test]
    fn reduced_contrast_averages_independent_patterns() {
        let s = PoseSampler::new(4, 0);
        let run = |c: f64| {
            let out = speckle_image(
                &flat_patch(1.0),
                658e-9,
                8.0,
                1e-6,
                &SpeckleSettings {
                    contrast: c,
                    oversampling: 2,
                },
                &s,
            );
            let v = interior(&out);
            let m = v.iter().sum::<f64>() / v.len() as f64;
            (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt() / m
        };
        let (c1, c_half) = (run(1.0), run(0.5));
        assert!((c_half / c1 - 0.5).abs() < 0.15, "{c1} → {c_half}");
    }
}
