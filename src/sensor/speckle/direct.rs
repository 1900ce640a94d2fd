//! The reference coherent imager: the direct convolution of the object field with the Airy
//! amplitude kernel, sub-sample by sub-sample, as glassscan first computed speckle. It is
//! O(sub-samples × kernel²) (0.4–2.3 s per traced pose at f/2.8 on two cores) and is kept as
//! the oracle that the fast imager (`fft`) is tested against, to FFT rounding, and as the
//! "old" side of `benches/speckle.rs`.

use rayon::prelude::*;

use super::super::diffraction::AiryPsf;
use super::super::image::Image;
use super::tiles::{halo, patterns, phase, Tile, SLOTS};
use crate::sampler::PoseSampler;

/// The coherent pixels of `tiles` ([`SLOTS`] per tile), computed directly: each tile's
/// field is laid out on its sub-grid with a halo of the kernel's reach and every output
/// sub-sample sums the kernel over it.
pub(super) fn tile_pixels(
    rough: &Image<f64>,
    psf: &AiryPsf,
    contrast: f64,
    sampler: &PoseSampler,
    tiles: &[Tile],
) -> Vec<f64> {
    let pixels: Vec<Vec<f64>> = tiles
        .par_iter()
        .map(|t| {
            let mut p = tile_direct(rough, psf, contrast, sampler, t);
            p.resize(SLOTS, 0.0);
            p
        })
        .collect();
    pixels.concat()
}

/// One tile's pixels, row-major.
fn tile_direct(
    rough: &Image<f64>,
    psf: &AiryPsf,
    contrast: f64,
    sampler: &PoseSampler,
    t: &Tile,
) -> Vec<f64> {
    let q = psf.oversampling();
    let half = psf.half_width();
    let kernel = psf.amplitude();
    let kn = 2 * half + 1;
    let halo = halo(psf);
    let patterns = patterns(contrast);
    let (w, h) = (rough.width, rough.height);
    let (x0, y0, x1, y1) = (t.x0, t.y0, t.x1, t.y1);
    // Source region: the tile plus a halo.
    let (sx0, sy0) = (x0.saturating_sub(halo), y0.saturating_sub(halo));
    let (sx1, sy1) = ((x1 + halo).min(w), (y1 + halo).min(h));
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
                let (c, s) = phase(sampler, w * q, sx0 * q + gx, sy0 * q + gy, pattern);
                let a = i.sqrt();
                re[gy * gw + gx] = a * c;
                im[gy * gw + gx] = a * s;
            }
        }
        // Sub-grid rows that have some field within the kernel's reach.
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
    pixels
}
