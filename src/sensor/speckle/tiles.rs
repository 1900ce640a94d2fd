//! What the fast and the direct coherent imagers share, so that they compute the same image:
//! the tiling and its faint-tile rule, the keyed random phases of the object field, and the
//! assembly of coherent tiles with the incoherent mean elsewhere.
//!
//! Phase keying (changing it changes every speckle realisation): the object field at global
//! sub-sample (X, Y) of the image's sub-grid, X ∈ [0, width·q), Y ∈ [0, height·q), for
//! pattern m is √I·e^{iφ} with φ = 2π·u, u = `sampler.uniform(Y·width·q + X, m)`, and I the
//! incoherent irradiance of the pixel (X / q, Y / q). The key is global, so tiles, halos and
//! FFT blocks that overlap see the same field.

use super::super::diffraction::AiryPsf;
use super::super::image::Image;
use crate::sampler::PoseSampler;

/// Pixels per tile side.
pub(super) const TILE: usize = 16;

/// Tiles whose source region (tile and halo) is below this fraction of the image's brightest
/// pixel get the incoherent mean image instead of a coherent one: stray light that faint
/// (< 0.1 DN for a line near full scale) gains nothing from speckle and would cost most of
/// the time.
pub(super) const FAINT_FRACTION: f64 = 1e-4;

/// One tile of output pixels [x0, x1) × [y0, y1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Tile {
    pub x0: usize,
    pub y0: usize,
    pub x1: usize,
    pub y1: usize,
}

impl Tile {
    /// Pixels of the tile.
    pub fn len(&self) -> usize {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }
}

/// Halo (pixels) around a tile that holds every source sub-sample the kernel reaches.
pub(super) fn halo(psf: &AiryPsf) -> usize {
    psf.half_width().div_ceil(psf.oversampling())
}

/// The tiles that get a coherent image, in row-major tile order: those whose source region
/// (the tile plus `halo` pixels, clipped to the image) has a pixel above [`FAINT_FRACTION`] of
/// the brightest pixel.
pub(super) fn coherent_tiles(rough: &Image<f64>, halo: usize) -> Vec<Tile> {
    let (w, h) = (rough.width, rough.height);
    let faint = FAINT_FRACTION * rough.data.iter().copied().fold(0.0, f64::max);
    // Brightest pixel of each row segment of TILE columns widened by the halo, then over the
    // tile's rows widened by the halo: the source region's maximum.
    let tiles_x = w.div_ceil(TILE);
    let mut band_max = vec![0.0f64; tiles_x * h];
    for y in 0..h {
        let row = &rough.data[y * w..(y + 1) * w];
        for tx in 0..tiles_x {
            let (sx0, sx1) = (
                (tx * TILE).saturating_sub(halo),
                (tx * TILE + TILE + halo).min(w),
            );
            band_max[y * tiles_x + tx] = row[sx0..sx1].iter().copied().fold(0.0, f64::max);
        }
    }
    let mut tiles = Vec::new();
    for ty in 0..h.div_ceil(TILE) {
        let (y0, y1) = (ty * TILE, (ty * TILE + TILE).min(h));
        let (sy0, sy1) = (y0.saturating_sub(halo), (y1 + halo).min(h));
        for tx in 0..tiles_x {
            let m = (sy0..sy1)
                .map(|y| band_max[y * tiles_x + tx])
                .fold(0.0, f64::max);
            if m > faint {
                let x0 = tx * TILE;
                tiles.push(Tile {
                    x0,
                    y0,
                    x1: (x0 + TILE).min(w),
                    y1,
                });
            }
        }
    }
    tiles
}

/// Independent patterns averaged for speckle contrast C: M = round(1/C²) ≥ 1 (contrast
/// 1/√M, Goodman 2007, §5.3).
pub(super) fn patterns(contrast: f64) -> usize {
    (1.0 / (contrast * contrast)).round().max(1.0) as usize
}

/// Entries of the table of (cos, sin) at multiples of 2π/[`TURN_STEPS`] used by [`phase`].
const TURN_STEPS: usize = 1024;

/// (cos 2πk/N, sin 2πk/N) for k < N = [`TURN_STEPS`], computed once.
fn turn_table() -> &'static [(f64, f64)] {
    static TABLE: std::sync::OnceLock<Vec<(f64, f64)>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        (0..TURN_STEPS)
            .map(|k| {
                let (s, c) = (2.0 * std::f64::consts::PI * k as f64 / TURN_STEPS as f64).sin_cos();
                (c, s)
            })
            .collect()
    })
}

/// (cos 2πu, sin 2πu) for u ∈ [0, 1), to ~2 ulp: the nearest lower table angle rotated by
/// the rest δ < 2π/1024 with Taylor series (truncation < δ⁷/5040 ≈ 6e-20). About twice as fast
/// as the libm `sin_cos` that dominated the imager's time; the same phases to rounding.
#[inline]
fn cos_sin_turns(u: f64) -> (f64, f64) {
    let t = u * TURN_STEPS as f64;
    let k = (t as usize).min(TURN_STEPS - 1);
    let d = (t - k as f64) * (2.0 * std::f64::consts::PI / TURN_STEPS as f64);
    let d2 = d * d;
    // sin δ = δ(1 − δ²/6 + δ⁴/120), cos δ = 1 − δ²/2 + δ⁴/24 − δ⁶/720.
    let sd = d * (1.0 + d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0)));
    let cd = 1.0 + d2 * (-0.5 + d2 * (1.0 / 24.0 + d2 * (-1.0 / 720.0)));
    let (c, s) = turn_table()[k];
    (c * cd - s * sd, s * cd + c * sd)
}

/// The phase factor (cos φ, sin φ) of the object field at global sub-sample (`gx`, `gy`) of
/// a sub-grid `width_sub` wide, pattern `pattern` (module docs: the keying).
#[inline]
pub(super) fn phase(
    sampler: &PoseSampler,
    width_sub: usize,
    gx: usize,
    gy: usize,
    pattern: usize,
) -> (f64, f64) {
    let key = (gy * width_sub + gx) as u64;
    cos_sin_turns(sampler.uniform(key, pattern as u32))
}

/// Slots per tile in a buffer of tile pixels: [`TILE`]², of which a tile uses [`Tile::len`]
/// (row-major, `x1 − x0` wide).
pub(super) const SLOTS: usize = TILE * TILE;

/// The image: each coherent tile's pixels from `pixels` (tile after tile, [`SLOTS`] each),
/// and elsewhere the incoherent mean image of `rough` (the expectation of its coherent image).
pub(super) fn assemble(
    rough: &Image<f64>,
    psf: &AiryPsf,
    tiles: &[Tile],
    pixels: &[f64],
) -> Image<f64> {
    let mut out = psf.blur(rough);
    let w = rough.width;
    for (t, slots) in tiles.iter().zip(pixels.chunks(SLOTS)) {
        let tw = t.x1 - t.x0;
        for (k, row) in slots[..t.len()].chunks(tw).enumerate() {
            let y = t.y0 + k;
            out.data[y * w + t.x0..y * w + t.x1].copy_from_slice(row);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_sine_and_cosine_match_libm_to_rounding() {
        let mut worst: f64 = 0.0;
        for i in 0..100_000u32 {
            let u = (i as f64 + 0.37) / 100_000.0;
            let (c, s) = cos_sin_turns(u);
            let (s0, c0) = (2.0 * std::f64::consts::PI * u).sin_cos();
            worst = worst.max((c - c0).abs()).max((s - s0).abs());
        }
        assert!(worst < 1e-15, "{worst}");
        let (c, s) = cos_sin_turns(0.0);
        assert_eq!((c, s), (1.0, 0.0));
    }
}
