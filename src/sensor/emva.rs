//! The image sensor's noise: an EMVA 1288 camera simulation, irradiance → noisy digital image.
//!
//! Model (EMVA 1288 linear model, docs/parameters.md §2a; the steps of the reference simulator
//! `EMVA1288/emva1288`, `emva1288/camera/camera.py` `Camera.grab`), for pixel i:
//!
//! 1. mean photons μ_p = A·E·t_exp·λ/(h·c) ([`ImagerSpec::photons`]);
//! 2. collected charge q = Poisson(η·μ_p·g_i) + Poisson(μ_I·t_exp), with g_i = 1 + PRNU·n_i the
//!    fixed per-pixel gain map (camera.py `_u_e`: `qe · prnu · photons`) and μ_I the dark current;
//! 3. charge above the full well μ_e,sat: a CMOS pixel clips, a CCD spills it along its column
//!    (`bloom`, docs/parameters.md §2c);
//! 4. readout: s = q + N(0, σ_d0²) + d_i, with d_i = DSNU·n′_i the fixed per-pixel dark offset
//!    map (e⁻);
//! 5. y = K·s + black level, rounded and clipped to [0, 2^bits − 1] (camera.py:
//!    `img = K·img_e; img += blackoffset; rint; clip`, without camera.py's uniform dither: a
//!    real ADC does not dither, and EMVA 1288's σ_q² = 1/12 DN² assumes it does not).
//!
//! Where this differs from camera.py, and why:
//! - Read noise and DSNU are added after the full well, not before: they belong to the readout
//!   electronics, not to the charge in the well, so blooming moves only collected charge and a
//!   saturated pixel still shows read noise. camera.py also clips electrons at 0; here the only
//!   low clip is the ADC's at 0 DN (the black level keeps the dark noise above it).
//! - camera.py's mean electronic offset `dark_signal_0` (e⁻) is folded into the black level
//!   `dark_offset_dn`; the dark current has no temperature law (μ_I is the value at the
//!   operating temperature).
//!
//! Temporal variance that follows (EMVA 1288, docs/parameters.md §2a):
//! σ_y² = K²·(σ_d0² + μ_I·t_exp) + σ_q² + K·(μ_y − μ_y,dark), σ_q² = 1/12 DN². (camera.py's
//! rectangular dither before rounding would make it 1/6: the ADC's 1/12 plus the dither's.)
//!
//! Randomness (no generator state, so any thread order gives the same image): every draw is `sampler.uniform(pixel_key(c, r), dimension)`
//! with a fixed dimension per noise term — see [`DIM_PHOTO`], [`DIM_DARK`], [`DIM_READ`]. The PRNU and DSNU maps belong to the sensor, not the frame: they are keyed
//! by the constant ([`FIXED_PATTERN_SEED`], [`FIXED_PATTERN_STREAM`]), the same for every
//! frame, pose and run seed. Pixels are independent, so the result does not depend on the
//! thread count.

use rayon::prelude::*;

use super::bloom;
use super::image::Image;
use super::imager::{ImagerSpec, SensorKind};
use crate::optics::warp::normal_quantile;
use crate::sampler::{mix64, IndexUniforms, PoseSampler};

/// What one exposure produced.
#[derive(Clone, Debug, PartialEq)]
pub struct Exposure {
    /// The digital image (DN, 0 … 2^bits − 1).
    pub dn: Image<u16>,
    /// Collected charge per pixel (e⁻) after the full well (CMOS clip or CCD bleed), before
    /// read noise, DSNU and gain.
    pub electrons: Image<f64>,
    /// Pixels at the full well or at the ADC's full scale.
    pub saturated: usize,
    /// Charge removed by the full well (e⁻): drained by CMOS pixels, or bled off the top and
    /// bottom rows of a CCD.
    pub lost_e: f64,
}

/// Poisson means below this are drawn by inversion (one uniform), from it up by PTRS.
pub const INVERSION_MAX_MEAN: f64 = 30.0;
/// Most PTRS trials per draw; each trial takes two uniforms. A trial is accepted with
/// probability α ≈ 1/(1.1239 + 1.1328/(b − 3.4)), b = 0.931 + 2.53·√μ (the inverse of the
/// hat's area, Hörmann 1993): measured 0.81 at μ = 30 and 0.89 at μ = 10⁵, so running out has
/// probability < 10⁻²³; the draw then returns the rounded mean.
pub const PTRS_MAX_TRIALS: u32 = 32;
/// Dimensions reserved for one Poisson draw.
pub const POISSON_DIMS: u32 = 2 * PTRS_MAX_TRIALS;

/// Photo-electrons: dimensions `DIM_PHOTO .. DIM_PHOTO + POISSON_DIMS` (0…63).
pub const DIM_PHOTO: u32 = 0;
/// Dark-current electrons: `DIM_DARK .. DIM_DARK + POISSON_DIMS` (64…127).
pub const DIM_DARK: u32 = DIM_PHOTO + POISSON_DIMS;
/// Read noise (inverse normal CDF): `DIM_READ` (128).
pub const DIM_READ: u32 = DIM_DARK + POISSON_DIMS;

/// Seed of the sensor's fixed pattern (PRNU and DSNU maps): one simulated sensor unit.
pub const FIXED_PATTERN_SEED: u64 = 1288;
/// Stream of the fixed pattern (no pose uses it).
pub const FIXED_PATTERN_STREAM: u64 = u64::MAX;
/// PRNU map (inverse normal CDF): fixed-pattern dimension 0.
pub const DIM_PRNU: u32 = 0;
/// DSNU map (inverse normal CDF): fixed-pattern dimension 2.
pub const DIM_DSNU: u32 = 2;

/// Mixed into the run seed by [`frame_sampler`], so that the sensor's noise never reuses the
/// light transport's uniforms (which are keyed by (seed, pose, photon, dimension)).
const NOISE_SEED_SALT: u64 = 0x454D_5641_1288_0001;

/// The sampler index of pixel (column, row): independent of the image width, so a pixel keeps
/// its fixed pattern when the image is cropped.
pub fn pixel_key(column: usize, row: usize) -> u64 {
    ((row as u64) << 32) | column as u64
}

/// The noise sampler of frame (or pose) `frame` under the run's `seed`: a stream separate from
/// the transport's `PoseSampler::new(seed, pose)`.
pub fn frame_sampler(seed: u64, frame: u64) -> PoseSampler {
    PoseSampler::new(mix64(seed ^ NOISE_SEED_SALT), frame)
}

/// A standard normal deviate from one uniform in [0, 1): the inverse normal CDF
/// (`optics::warp::normal_quantile`, relative error < 1.15e-9). It replaced Box–Muller's
/// cosine, logarithm and square root, a third of an exposure's time (issue 11).
pub fn standard_normal(u: f64) -> f64 {
    normal_quantile(u)
}

/// A Poisson deviate of mean `mean` (≥ 0, finite) from the uniforms in [0, 1) that `u` yields.
///
/// Means below [`INVERSION_MAX_MEAN`]: exact inversion by sequential search of the CDF (one
/// uniform). Larger means: Hörmann's PTRS transformed rejection with squeeze ("The transformed
/// rejection method for generating Poisson random variables", Insurance: Mathematics and
/// Economics 12, 1993; valid for μ ≥ 10), two uniforms per trial, at most
/// [`PTRS_MAX_TRIALS`] trials. Exact up to f64 rounding for means below 2⁵².
pub fn poisson(mean: f64, mut u: impl FnMut() -> f64) -> f64 {
    debug_assert!(mean >= 0.0 && mean.is_finite(), "Poisson mean {mean}");
    if mean.is_nan() || mean <= 0.0 {
        return 0.0;
    }
    if mean < INVERSION_MAX_MEAN {
        poisson_inversion(mean, u())
    } else {
        poisson_ptrs(mean, u)
    }
}

fn poisson_inversion(mean: f64, u: f64) -> f64 {
    poisson_inversion_from(mean, (-mean).exp(), u)
}

/// [`poisson_inversion`] with P(K = 0) = e^(−μ) given: a draw of one mean for every pixel
/// (the dark current) computes it once.
fn poisson_inversion_from(mean: f64, p0: f64, u: f64) -> f64 {
    let (mut k, mut p) = (0.0, p0);
    let mut cdf = p;
    // P(k > 1000) < 10⁻⁹⁰⁰ for μ < 30; the bound also ends the search when rounding leaves
    // the summed CDF just below a u close to 1.
    while u >= cdf && k < 1000.0 {
        k += 1.0;
        p *= mean / k;
        cdf += p;
    }
    k
}

fn poisson_ptrs(mean: f64, mut u: impl FnMut() -> f64) -> f64 {
    // Hörmann 1993, algorithm PTRS: constants of the transformed hat, its squeeze v_r.
    let b = 0.931 + 2.53 * mean.sqrt();
    let a = -0.059 + 0.02483 * b;
    let ln_inv_alpha = (1.1239 + 1.1328 / (b - 3.4)).ln();
    let v_r = 0.9277 - 3.6224 / (b - 2.0);
    for _ in 0..PTRS_MAX_TRIALS {
        let uu = u() - 0.5;
        let v = u();
        let us = 0.5 - uu.abs();
        let k = ((2.0 * a / us + b) * uu + mean + 0.43).floor();
        if us >= 0.07 && v <= v_r {
            return k;
        }
        // us = 0 gives k = −∞ and is rejected here.
        if k < 0.0 || (us < 0.013 && v > us) {
            continue;
        }
        if v.ln() + ln_inv_alpha - (a / (us * us) + b).ln() <= ln_poisson_pmf(k, mean) {
            return k;
        }
    }
    mean.round()
}

/// ln P(K = k) for K ~ Poisson(μ): −μ + k·ln μ − ln k!. For k ≥ 10, Stirling's series for
/// ln Γ(k + 1) (Abramowitz & Stegun 6.1.41, error < 10⁻¹²) in a form without cancellation at
/// large μ: with x = k + 1 and δ = (μ − x)/x, ln P = k·(ln(1 + δ) − δ) − δ − ½·ln(2πx) − S(x).
fn ln_poisson_pmf(k: f64, mean: f64) -> f64 {
    if k < 10.0 {
        let ln_factorial: f64 = (2..=k as u32).map(|j| f64::from(j).ln()).sum();
        return k * mean.ln() - mean - ln_factorial;
    }
    let x = k + 1.0;
    let delta = (mean - x) / x;
    let (inv, inv2) = (1.0 / x, 1.0 / (x * x));
    let series = inv * (1.0 / 12.0 - inv2 * (1.0 / 360.0 - inv2 * (1.0 / 1260.0 - inv2 / 1680.0)));
    k * (delta.ln_1p() - delta) - delta - 0.5 * (std::f64::consts::TAU * x).ln() - series
}

/// Consecutive uniforms of one pixel from dimension `base` on, for one Poisson draw.
fn draws(pixel: IndexUniforms, base: u32) -> impl FnMut() -> f64 {
    let mut dim = base;
    move || {
        debug_assert!(
            dim < base + POISSON_DIMS,
            "Poisson draw overran its dimensions"
        );
        let u = pixel.uniform(dim);
        dim += 1;
        u
    }
}

/// The digital number of a signal y (DN): rounded half away from zero, as `f64::round`, and
/// clipped to [0, `max_dn`]. Bit for bit `y.round().clamp(0.0, max_dn as f64) as u16`, without
/// `round`, which x86-64 without SSE4.1 calls in the maths library: below 0.5 (and NaN) the
/// result is 0, at or above `max_dn` it is `max_dn`, and in between y's integer and fractional
/// parts are exact (y < 2¹⁶).
fn digitise(y: f64, max_dn: u16) -> u16 {
    if y >= f64::from(max_dn) {
        return max_dn;
    }
    if y < 0.5 || y.is_nan() {
        return 0;
    }
    let whole = y as u16;
    whole + u16::from(y - f64::from(whole) >= 0.5)
}

/// The sensor's fixed pattern on a `width` × `height` grid: per-pixel gain (PRNU, mean 1) and
/// dark offset (DSNU, e⁻, mean 0), both Gaussian. It belongs to the simulated sensor unit, so
/// `SensorHead` makes it once and every exposure reuses it (making it costs two Gaussian
/// draws per pixel, a third of an exposure's time).
#[derive(Clone, Debug, PartialEq)]
pub struct FixedPattern {
    /// Gain map g = max(1 + PRNU·n, 0), multiplying η.
    pub gain: Image<f64>,
    /// Dark offset map d = DSNU·n′ (e⁻).
    pub offset_e: Image<f64>,
    /// The PRNU and DSNU (e⁻) it was made for.
    made_for: (f64, f64),
}

impl FixedPattern {
    /// The fixed pattern of `spec` (its `prnu` and `dsnu_e`) on a `width` × `height` grid.
    pub fn new(spec: &ImagerSpec, width: usize, height: usize) -> FixedPattern {
        let s = PoseSampler::new(FIXED_PATTERN_SEED, FIXED_PATTERN_STREAM);
        let map = |sigma: f64, dim: u32, mean: f64| {
            let mut data = vec![mean; width * height];
            if sigma != 0.0 && width > 0 {
                data.par_chunks_mut(width).enumerate().for_each(|(r, row)| {
                    for (c, v) in row.iter_mut().enumerate() {
                        *v = mean + sigma * standard_normal(s.uniform(pixel_key(c, r), dim));
                    }
                });
            }
            Image {
                width,
                height,
                data,
            }
        };
        let mut gain = map(spec.prnu, DIM_PRNU, 1.0);
        // A negative gain is unphysical; at PRNU ≤ 0.2 it would take a 5σ pixel.
        gain.data.iter_mut().for_each(|g| *g = g.max(0.0));
        FixedPattern {
            gain,
            offset_e: map(spec.dsnu_e, DIM_DSNU, 0.0),
            made_for: (spec.prnu, spec.dsnu_e),
        }
    }

    /// Whether this is the pattern of `spec` on a `width` × `height` grid.
    pub fn fits(&self, spec: &ImagerSpec, width: usize, height: usize) -> bool {
        self.made_for == (spec.prnu, spec.dsnu_e)
            && (self.gain.width, self.gain.height) == (width, height)
    }
}

/// Exposes `irradiance` (W/m², on pixels of `pixel_area_m2` at `wavelength_m`) with the
/// temporal noise of `sampler` and the sensor's fixed `pattern` (made anew if it is not the
/// pattern of `spec` on this grid). With `spec.noise` false the result is the noise-free mean
/// model: `dn` is exactly [`ImagerSpec::expose`], `electrons` = min(η·μ_p, full well), no
/// dark signal, fixed pattern or blooming.
pub fn expose(
    spec: &ImagerSpec,
    irradiance: &Image<f64>,
    pixel_area_m2: f64,
    wavelength_m: f64,
    sampler: &PoseSampler,
    pattern: &FixedPattern,
) -> Exposure {
    let light = Light {
        irradiance,
        pixel_area_m2,
        wavelength_m,
    };
    expose_with(spec, &light, sampler, &Keyed(*sampler), pattern)
}

/// [`expose`] with the frame's draws that no exposure setting changes made beforehand: bit for
/// bit `expose` with the sampler the draws were made from. Several exposures of one
/// frame (a study's exposure axis) share one [`FrameDraws`] and skip most of the hashing and
/// all of the read noise's inverse normal CDF.
///
/// # Panics
/// If `draws` were made for another grid than `irradiance`'s.
pub fn expose_drawn(
    spec: &ImagerSpec,
    irradiance: &Image<f64>,
    pixel_area_m2: f64,
    wavelength_m: f64,
    draws: &FrameDraws,
    pattern: &FixedPattern,
) -> Exposure {
    assert_eq!(
        (draws.width, draws.height),
        (irradiance.width, irradiance.height),
        "frame draws of another grid"
    );
    let light = Light {
        irradiance,
        pixel_area_m2,
        wavelength_m,
    };
    expose_with(spec, &light, &draws.sampler, draws, pattern)
}

/// The draws of one frame that do not depend on the exposure setting, per pixel (row-major):
/// the dark charge's first uniform (dimension [`DIM_DARK`], all an inversion draw takes) and
/// the read noise's standard normal deviate (dimension [`DIM_READ`]). They depend only on the
/// frame's sampler and the pixel, so every exposure of the frame draws the same ones.
#[derive(Clone, Debug)]
pub struct FrameDraws {
    sampler: PoseSampler,
    width: usize,
    height: usize,
    dark_u: Vec<f64>,
    read_z: Vec<f64>,
}

impl FrameDraws {
    /// The draws of the frame keyed by `sampler` on a `width` × `height` grid.
    pub fn new(sampler: &PoseSampler, width: usize, height: usize) -> FrameDraws {
        let (mut dark_u, mut read_z) = (vec![0.0; width * height], vec![0.0; width * height]);
        if width > 0 {
            let rows = dark_u
                .par_chunks_mut(width)
                .zip(read_z.par_chunks_mut(width));
            rows.enumerate().for_each(|(r, (dark, read))| {
                for (c, (d, z)) in dark.iter_mut().zip(read).enumerate() {
                    let pixel = sampler.at(pixel_key(c, r));
                    *d = pixel.uniform(DIM_DARK);
                    *z = standard_normal(pixel.uniform(DIM_READ));
                }
            });
        }
        FrameDraws {
            sampler: *sampler,
            width,
            height,
            dark_u,
            read_z,
        }
    }
}

/// Where an exposure takes a pixel's exposure-independent draws from.
trait PixelDraws: Sync {
    /// The dark charge's first uniform of pixel (`column`, `row`), row-major number `index`.
    fn dark_uniform(&self, column: usize, row: usize, index: usize) -> f64;
    /// The read noise's standard normal deviate of that pixel.
    fn read_deviate(&self, column: usize, row: usize, index: usize) -> f64;
}

/// Drawn pixel by pixel from the frame's sampler (one exposure of a frame).
struct Keyed(PoseSampler);

impl PixelDraws for Keyed {
    fn dark_uniform(&self, column: usize, row: usize, _: usize) -> f64 {
        self.0.at(pixel_key(column, row)).uniform(DIM_DARK)
    }

    fn read_deviate(&self, column: usize, row: usize, _: usize) -> f64 {
        standard_normal(self.0.at(pixel_key(column, row)).uniform(DIM_READ))
    }
}

impl PixelDraws for FrameDraws {
    fn dark_uniform(&self, _: usize, _: usize, index: usize) -> f64 {
        self.dark_u[index]
    }

    fn read_deviate(&self, _: usize, _: usize, index: usize) -> f64 {
        self.read_z[index]
    }
}

/// The light an exposure integrates: irradiance (W/m²) on pixels of an area at a wavelength.
struct Light<'a> {
    irradiance: &'a Image<f64>,
    pixel_area_m2: f64,
    wavelength_m: f64,
}

/// [`expose`] with the exposure-independent draws of `pixel_draws`, which come from `sampler`.
fn expose_with(
    spec: &ImagerSpec,
    light: &Light,
    sampler: &PoseSampler,
    pixel_draws: &impl PixelDraws,
    pattern: &FixedPattern,
) -> Exposure {
    let Light {
        irradiance,
        pixel_area_m2,
        wavelength_m,
    } = *light;
    if !spec.noise {
        return expose_mean(spec, irradiance, pixel_area_m2, wavelength_m);
    }
    let (w, h) = (irradiance.width, irradiance.height);
    let full_well = spec.full_well_e;
    let made;
    let pattern = if pattern.fits(spec, w, h) {
        pattern
    } else {
        made = FixedPattern::new(spec, w, h);
        &made
    };
    let dark_e = spec.dark_current_e_per_s * spec.exposure_s;
    // The dark charge has one mean for every pixel, so inversion's e^(−μ) is computed once
    // (the same draw as `poisson`, uniform for uniform).
    let dark_p0 = (-dark_e).exp();
    let dark = |c: usize, r: usize, i: usize| {
        if dark_e > 0.0 && dark_e < INVERSION_MAX_MEAN {
            poisson_inversion_from(dark_e, dark_p0, pixel_draws.dark_uniform(c, r, i))
        } else {
            poisson(dark_e, draws(sampler.at(pixel_key(c, r)), DIM_DARK))
        }
    };
    // Row by row: a pixel's key needs its column and row without a division per pixel.
    let mut electrons = Image {
        width: w,
        height: h,
        data: vec![0.0; w * h],
    };
    let span = |r: usize| r * w..(r + 1) * w;
    let charge = electrons.data.par_chunks_mut(w.max(1)).enumerate();
    charge.for_each(|(r, row)| {
        let (light, gain) = (&irradiance.data[span(r)], &pattern.gain.data[span(r)]);
        for (c, ((q, &e), &g)) in row.iter_mut().zip(light).zip(gain).enumerate() {
            let photons = spec.photons(e, pixel_area_m2, wavelength_m);
            let mean_e = (spec.quantum_efficiency * photons * g).max(0.0);
            // `poisson` of a mean of 0 is 0 without a draw: a dark pixel needs no hash here.
            let photo_e = if mean_e > 0.0 {
                poisson(mean_e, draws(sampler.at(pixel_key(c, r)), DIM_PHOTO))
            } else {
                0.0
            };
            *q = photo_e + dark(c, r, r * w + c);
        }
    });
    let lost_e = match spec.kind {
        SensorKind::Cmos => bloom::clip_to_full_well(&mut electrons, full_well),
        SensorKind::Ccd => bloom::bleed_columns(&mut electrons, full_well),
    };
    let max_dn = spec.max_dn();
    let mut dn = vec![0u16; w * h];
    dn.par_chunks_mut(w.max(1))
        .enumerate()
        .for_each(|(r, row)| {
            let (charge, offset) = (&electrons.data[span(r)], &pattern.offset_e.data[span(r)]);
            for (c, ((d, &q), &off)) in row.iter_mut().zip(charge).zip(offset).enumerate() {
                let read = spec.read_noise_e * pixel_draws.read_deviate(c, r, r * w + c);
                // A real ADC rounds without dither: quantisation noise σ_q² = 1/12 DN² (EMVA 1288).
                *d = digitise(
                    spec.gain_dn_per_e * (q + read + off) + spec.dark_offset_dn,
                    max_dn,
                );
            }
        });
    let saturated = count_saturated(&electrons.data, &dn, full_well, max_dn);
    Exposure {
        dn: Image {
            width: w,
            height: h,
            data: dn,
        },
        electrons,
        saturated,
        lost_e,
    }
}

/// The noise-free mean model (`spec.noise == false`).
fn expose_mean(
    spec: &ImagerSpec,
    irradiance: &Image<f64>,
    pixel_area_m2: f64,
    wavelength_m: f64,
) -> Exposure {
    let dn = spec.expose(irradiance, pixel_area_m2, wavelength_m);
    let mut lost_e = 0.0;
    let data: Vec<f64> = irradiance
        .data
        .iter()
        .map(|&e| {
            let q = spec.quantum_efficiency * spec.photons(e, pixel_area_m2, wavelength_m);
            lost_e += (q - spec.full_well_e).max(0.0);
            q.min(spec.full_well_e)
        })
        .collect();
    let saturated = count_saturated(&data, &dn.data, spec.full_well_e, spec.max_dn());
    Exposure {
        electrons: Image {
            width: irradiance.width,
            height: irradiance.height,
            data,
        },
        dn,
        saturated,
        lost_e,
    }
}

fn count_saturated(electrons: &[f64], dn: &[u16], full_well: f64, max_dn: u16) -> usize {
    electrons
        .iter()
        .zip(dn)
        .filter(|&(&q, &d)| q >= full_well || d == max_dn)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::preset::scancontrol_2600_100;

    #[test]
    fn digitise_is_rounding_half_away_from_zero_then_clipping() {
        let reference = |y: f64, max: u16| y.round().clamp(0.0, f64::from(max)) as u16;
        let halves = [0.5, 1.5, 2.5, 1022.5, 1023.5, 4094.5];
        let tricky = [
            -0.5,
            -0.0,
            0.0,
            0.499_999_999_999_999_94,
            1e300,
            -1e300,
            f64::NAN,
        ];
        for max in [255u16, 1023, 4095, 65535] {
            for &y in halves.iter().chain(&tricky) {
                for y in [
                    y,
                    f64::from_bits(y.to_bits().wrapping_sub(1)),
                    f64::from_bits(y.to_bits().wrapping_add(1)),
                ] {
                    assert_eq!(digitise(y, max), reference(y, max), "y = {y:e}, max {max}");
                }
            }
            for i in 0..100_000 {
                let y = f64::from(max) * 1.1 * (i as f64 / 100_000.0) - 2.0;
                assert_eq!(digitise(y, max), reference(y, max), "y = {y:e}, max {max}");
            }
        }
    }

    /// Mean and unbiased variance of `n` Poisson draws of mean `mu`, draw i keyed by i.
    fn sample_moments(mu: f64, n: u64, stream: u64) -> (f64, f64) {
        let s = PoseSampler::new(11, stream);
        let (mut m, mut m2) = (0.0, 0.0);
        for i in 0..n {
            let k = poisson(mu, draws(s.at(i), 0));
            assert!(k >= 0.0 && k.fract() == 0.0, "{k}");
            // Shifted sums keep the variance exact at μ = 10⁵.
            let d = k - mu;
            m += d;
            m2 += d * d;
        }
        let nf = n as f64;
        let mean = m / nf;
        (mu + mean, (m2 - nf * mean * mean) / (nf - 1.0))
    }

    #[test]
    fn poisson_mean_and_variance_pass_z_tests() {
        // Poisson(μ): mean μ, variance μ; σ(mean) = √(μ/n), σ(s²) = √((μ4 − σ⁴)/n) with the
        // fourth central moment μ4 = μ(1 + 3μ), so σ(s²) = √((μ + 2μ²)/n). |z| < 4 for each of
        // the 10 tests (family-wise false alarm 6·10⁻⁴).
        let n = 100_000;
        for (stream, mu) in [0.5, 5.0, 50.0, 5e3, 1e5].into_iter().enumerate() {
            let (mean, var) = sample_moments(mu, n, stream as u64);
            let z_mean = (mean - mu) / (mu / n as f64).sqrt();
            let z_var = (var - mu) / ((mu + 2.0 * mu * mu) / n as f64).sqrt();
            eprintln!(
                "Poisson μ = {mu}: mean {mean:.5} (z {z_mean:+.2}), var {var:.5} (z {z_var:+.2})"
            );
            assert!(
                z_mean.abs() < 4.0 && z_var.abs() < 4.0,
                "μ = {mu}: mean {mean} (z {z_mean:.2}), variance {var} (z {z_var:.2})"
            );
        }
    }

    #[test]
    fn poisson_pmf_logarithm_matches_direct_sums() {
        for mu in [30.0, 50.0, 1e3] {
            for k in (0..3000).step_by(7) {
                let k = k as f64;
                let ln_fact: f64 = (2..=k as u32).map(|j| f64::from(j).ln()).sum();
                let direct = -mu + k * f64::ln(mu) - ln_fact;
                let got = ln_poisson_pmf(k, mu);
                assert!(
                    (got - direct).abs() < 1e-9 * direct.abs().max(1.0),
                    "μ {mu}, k {k}: {got} vs {direct}"
                );
            }
        }
    }

    #[test]
    fn ptrs_takes_the_hat_area_in_trials_per_draw() {
        // The mean number of trials of a rejection sampler is the area under its hat; Hörmann
        // (1993) gives it as 1/α ≈ 1.1239 + 1.1328/(b − 3.4), a fitted approximation, so the
        // check allows 2 % (σ of the measured mean ≈ √(1 − α)/α/√n ≈ 0.004).
        let s = PoseSampler::new(5, 0);
        let n = 20_000u64;
        for mu in [30.0, 1e3, 1e5] {
            let mut used = 0u64;
            for i in 0..n {
                let mut dim = 0;
                poisson(mu, || {
                    used += 1;
                    dim += 1;
                    s.uniform(i, dim)
                });
            }
            let trials = used as f64 / 2.0 / n as f64;
            let b = 0.931 + 2.53 * f64::sqrt(mu);
            let hat = 1.1239 + 1.1328 / (b - 3.4);
            eprintln!("PTRS μ = {mu}: {trials:.4} trials per draw, hat area {hat:.4}");
            assert!(
                (trials / hat - 1.0).abs() < 0.02,
                "μ {mu}: {trials} trials per draw, hat area {hat}"
            );
        }
    }

    #[test]
    fn standard_normal_has_unit_variance() {
        let s = PoseSampler::new(2, 9);
        let n = 100_000;
        let (mut m, mut m2) = (0.0, 0.0);
        for i in 0..n {
            let x = standard_normal(s.uniform(i, 0));
            m += x;
            m2 += x * x;
        }
        let (mean, var) = (m / n as f64, m2 / n as f64);
        // σ(mean) = 1/√n = 0.0032; σ(var) = √(2/n) = 0.0045.
        assert!(
            mean.abs() < 0.013 && (var - 1.0).abs() < 0.018,
            "{mean} {var}"
        );
    }

    #[test]
    fn exposures_from_frame_draws_are_the_keyed_ones_bit_for_bit() {
        // A frame with dark pixels, faint ones (inversion), bright ones (PTRS) and saturated
        // ones, exposed as a study's exposure axis does, with both sensor kinds and a dark
        // current large enough for PTRS (μ_I·t = 50 e⁻ at 0.5 ms) as well as the preset's.
        let (w, h) = (23, 9);
        let mut e = Image::<f64>::new(w, h);
        for (i, v) in e.data.iter_mut().enumerate() {
            *v = if i % 3 == 0 {
                0.0
            } else {
                1e-3 * (i * i) as f64
            };
        }
        let (area, lambda) = (9.4e-6 * 9.4e-6, 658e-9);
        let sampler = frame_sampler(7, 3);
        let draws = FrameDraws::new(&sampler, w, h);
        let base = scancontrol_2600_100().imager;
        let mut compared = 0;
        for kind in [SensorKind::Cmos, SensorKind::Ccd] {
            for dark_current in [base.dark_current_e_per_s, 1e5] {
                for exposure_s in [0.15e-3, 0.5e-3, 1.5e-3] {
                    let spec = ImagerSpec {
                        kind,
                        dark_current_e_per_s: dark_current,
                        exposure_s,
                        ..base
                    };
                    let pattern = FixedPattern::new(&spec, w, h);
                    let keyed = expose(&spec, &e, area, lambda, &sampler, &pattern);
                    let drawn = expose_drawn(&spec, &e, area, lambda, &draws, &pattern);
                    assert_eq!(drawn, keyed, "{kind:?}, μ_I {dark_current}, t {exposure_s}");
                    assert!(keyed.saturated > 0 && keyed.dn.data.iter().any(|&d| d > 0));
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, 12);
        // Draws of another frame give another image: the comparison above can fail.
        let other = FrameDraws::new(&frame_sampler(7, 4), w, h);
        let pattern = FixedPattern::new(&base, w, h);
        assert_ne!(
            expose_drawn(&base, &e, area, lambda, &other, &pattern).dn,
            expose(&base, &e, area, lambda, &sampler, &pattern).dn
        );
    }

    #[test]
    fn noise_off_is_the_mean_model_and_noise_on_is_keyed() {
        let mut spec = scancontrol_2600_100().imager;
        let mut e = Image::<f64>::new(16, 8);
        for (i, v) in e.data.iter_mut().enumerate() {
            *v = 0.3 * i as f64;
        }
        let (area, lambda) = (9.4e-6 * 9.4e-6, 658e-9);
        let s = frame_sampler(1, 0);
        let pattern = FixedPattern::new(&spec, 16, 8);
        spec.noise = false;
        let off = expose(&spec, &e, area, lambda, &s, &pattern);
        assert_eq!(off.dn, spec.expose(&e, area, lambda));
        spec.noise = true;
        let a = expose(&spec, &e, area, lambda, &s, &pattern);
        let again = expose(&spec, &e, area, lambda, &frame_sampler(1, 0), &pattern);
        assert_eq!(a, again);
        assert_ne!(
            a.dn,
            expose(&spec, &e, area, lambda, &frame_sampler(1, 1), &pattern).dn
        );
        assert_ne!(a.dn, off.dn);
        // A pattern of another grid or another PRNU is not used: the right one is made.
        let mut other = spec;
        other.prnu *= 2.0;
        for wrong in [
            FixedPattern::new(&spec, 8, 8),
            FixedPattern::new(&other, 16, 8),
        ] {
            assert!(!wrong.fits(&spec, 16, 8));
            assert_eq!(a, expose(&spec, &e, area, lambda, &s, &wrong));
        }
    }
}
