//! The fast coherent imager: the same convolution of the object field with the Airy amplitude
//! kernel as `direct`, computed per tile by FFT (circular convolution with a block large
//! enough that nothing wraps: overlap-save), only over the part of the tile that carries
//! light.
//!
//! Per coherent tile (sub-sample coordinates, kernel half-width h):
//! - the source box S is the bounding box of the lit pixels of the tile's source region,
//!   clipped to the kernel's reach of the tile; the output box O is the tile clipped to the
//!   reach of S (outputs beyond it are exactly zero, as in `direct`);
//! - per axis the block is M ≥ max(o_max − s_min, s_max − o_min) + h + 1 (and ≥ 2h + 1), the
//!   smallest 2ᵃ3ᵇ5ᶜ: every offset o − s then lies within ±(M − h − 1), so no kernel tap
//!   aliases onto another and the circular convolution equals the linear one exactly;
//! - field rows without light skip their forward FFT along x, output rows out of reach of
//!   any lit row skip their inverse FFT; the kernel's spectrum (real: h is even in x and y)
//!   is computed once per block size and call.
//!
//! Arithmetic: the blocks and their FFTs are complex f32, the pixels' sums of |field|² f64.
//! f32 halves the blocks' memory and doubles the FFT's SIMD width (rustfft's AVX kernels: eight
//! lanes of f32 against four of f64); its rounding is relative to a block's largest values,
//! ~3·10⁻⁷ of the brightest pixel against the f64 direct reference (test below), which is
//! far below a DN: on the shipped scenes every DN image and profile is byte for byte what the
//! f64 blocks gave, only the irradiance EXRs differ (benches/README.md, 2026-12-08).
//!
//! Work is per tile, in parallel; each tile runs in its thread's scratch (reset before use)
//! with the FFT plans fixed before the parallel part, so the image is bit-identical for any
//! thread count. Cost per tile ~ (lit rows + output rows)·M_x·log M_x + M_x·M_y·log M_y, against
//! the direct method's (output sub-samples)·(2h + 1)².

use std::collections::BTreeMap;
use std::sync::Arc;

use rayon::prelude::*;
use rustfft::num_complex::Complex32;
use rustfft::{Fft, FftPlanner};

use super::super::diffraction::AiryPsf;
use super::super::image::Image;
use super::tiles::{halo, patterns, phase, Tile, SLOTS};
use crate::sampler::PoseSampler;

/// One tile's blocks, in global sub-sample coordinates: source [s0, s1) and output [o0, o1)
/// per axis (x, y), block sizes M.
#[derive(Clone, Copy, Debug)]
struct Job {
    tile: Tile,
    s: [(usize, usize); 2],
    o: [(usize, usize); 2],
    m: [usize; 2],
}

/// The smallest n′ ≥ n whose only prime factors are 2, 3 and 5 (fast FFT sizes).
fn smooth_size(n: usize) -> usize {
    (n.max(1)..)
        .find(|&k| {
            let mut k = k;
            for p in [2, 3, 5] {
                while k % p == 0 {
                    k /= p;
                }
            }
            k == 1
        })
        .expect("2-3-5 numbers are unbounded")
}

/// The blocks of tile `t`, or `None` if the kernel reaches none of its sub-samples from a lit
/// one (its pixels are then exactly zero).
fn job(rough: &Image<f64>, psf: &AiryPsf, t: &Tile) -> Option<Job> {
    let (q, h, halo) = (psf.oversampling(), psf.half_width(), halo(psf));
    let (w, ht) = (rough.width, rough.height);
    // Lit pixels of the source region (the tile plus its halo).
    let (px0, py0) = (t.x0.saturating_sub(halo), t.y0.saturating_sub(halo));
    let (px1, py1) = ((t.x1 + halo).min(w), (t.y1 + halo).min(ht));
    let (mut bx0, mut bx1, mut by0, mut by1) = (usize::MAX, 0, usize::MAX, 0);
    for y in py0..py1 {
        for x in px0..px1 {
            if rough.get(x, y) > 0.0 {
                (bx0, bx1, by0, by1) = (bx0.min(x), bx1.max(x + 1), by0.min(y), by1.max(y + 1));
            }
        }
    }
    if bx0 >= bx1 {
        return None;
    }
    let axis = |b0: usize, b1: usize, t0: usize, t1: usize| {
        let (o0, o1) = (t0 * q, t1 * q);
        let s = ((b0 * q).max(o0.saturating_sub(h)), (b1 * q).min(o1 + h));
        let o = (o0.max(s.0.saturating_sub(h)), o1.min(s.1 + h));
        if s.0 >= s.1 || o.0 >= o.1 {
            return None;
        }
        let reach = (o.1 as isize - 1 - s.0 as isize).max(s.1 as isize - 1 - o.0 as isize);
        let m = smooth_size((reach.max(0) as usize + h + 1).max(2 * h + 1));
        Some((s, o, m))
    };
    let (sx, ox, mx) = axis(bx0, bx1, t.x0, t.x1)?;
    let (sy, oy, my) = axis(by0, by1, t.y0, t.y1)?;
    Some(Job {
        tile: *t,
        s: [sx, sy],
        o: [ox, oy],
        m: [mx, my],
    })
}

/// Forward and inverse plans of one length.
struct Plans {
    forward: Arc<dyn Fft<f32>>,
    inverse: Arc<dyn Fft<f32>>,
}

/// What every tile shares: plans per length and the kernel's spectrum per block size.
struct Engine {
    plans: BTreeMap<usize, Plans>,
    /// Real spectrum of the kernel on an M_y × M_x block divided by M_x·M_y, stored
    /// transposed (x-frequency major, M_y per x-frequency) like the y pass's buffer.
    spectra: BTreeMap<(usize, usize), Vec<f32>>,
    scratch_len: usize,
    max_area: usize,
    max_m: usize,
}

impl Engine {
    fn new(psf: &AiryPsf, jobs: &[Job]) -> Engine {
        let mut planner = FftPlanner::<f32>::new();
        let mut plans = BTreeMap::new();
        for j in jobs {
            for &m in &j.m {
                plans.entry(m).or_insert_with(|| Plans {
                    forward: planner.plan_fft_forward(m),
                    inverse: planner.plan_fft_inverse(m),
                });
            }
        }
        let scratch_len = plans
            .values()
            .flat_map(|p| {
                [
                    p.forward.get_inplace_scratch_len(),
                    p.inverse.get_inplace_scratch_len(),
                ]
            })
            .max()
            .unwrap_or(0);
        let mut engine = Engine {
            plans,
            spectra: BTreeMap::new(),
            scratch_len,
            max_area: jobs.iter().map(|j| j.m[0] * j.m[1]).max().unwrap_or(0),
            max_m: jobs.iter().flat_map(|j| j.m).max().unwrap_or(0),
        };
        let mut sizes: Vec<(usize, usize)> = jobs.iter().map(|j| (j.m[0], j.m[1])).collect();
        sizes.sort_unstable();
        sizes.dedup();
        let spectra: Vec<Vec<f32>> = sizes
            .par_iter()
            .map(|&(mx, my)| engine.kernel_spectrum(psf, mx, my))
            .collect();
        engine.spectra = sizes.into_iter().zip(spectra).collect();
        engine
    }

    /// The kernel wrapped onto an `my` × `mx` block (tap (dy, dx) at (dy mod M_y, dx mod M_x)),
    /// transformed along x then y; real part over M_x·M_y, x-frequency major.
    fn kernel_spectrum(&self, psf: &AiryPsf, mx: usize, my: usize) -> Vec<f32> {
        let (h, k) = (psf.half_width(), psf.amplitude());
        let kn = 2 * h + 1;
        let mut a = vec![Complex32::new(0.0, 0.0); mx * my];
        let mut scratch = vec![Complex32::new(0.0, 0.0); self.scratch_len];
        let wrap = |d: usize, m: usize| (d + m - h) % m;
        for ky in 0..kn {
            let row = &mut a[wrap(ky, my) * mx..][..mx];
            for kx in 0..kn {
                row[wrap(kx, mx)] = Complex32::new(k[ky * kn + kx] as f32, 0.0);
            }
            self.plans[&mx]
                .forward
                .process_with_scratch(row, &mut scratch);
        }
        let mut b = vec![Complex32::new(0.0, 0.0); mx * my];
        transpose(&a, &mut b, my, mx, None);
        self.plans[&my]
            .forward
            .process_with_scratch(&mut b, &mut scratch);
        let norm = 1.0 / (mx * my) as f32;
        b.iter().map(|c| c.re * norm).collect()
    }
}

/// `dst` (cols × rows) = `src` (rows × cols) transposed, both row-major, in cache blocks.
/// With `lit`, source rows r with `lit[r]` false (or r ≥ `lit.len()`) are taken as zero and
/// not read.
fn transpose(
    src: &[Complex32],
    dst: &mut [Complex32],
    rows: usize,
    cols: usize,
    lit: Option<&[bool]>,
) {
    const B: usize = 16;
    let zero = Complex32::new(0.0, 0.0);
    for r0 in (0..rows).step_by(B) {
        for c0 in (0..cols).step_by(B) {
            for r in r0..(r0 + B).min(rows) {
                let live = lit.is_none_or(|l| l.get(r).copied().unwrap_or(false));
                for c in c0..(c0 + B).min(cols) {
                    dst[c * rows + r] = if live { src[r * cols + c] } else { zero };
                }
            }
        }
    }
}

/// One thread's buffers. They grow to the largest block seen and are kept by the thread for
/// the next tile and the next call, so the imager allocates nothing per tile or per pose
/// once warm. Every buffer is overwritten (or reset) before it is read.
#[derive(Default)]
struct Scratch {
    a: Vec<Complex32>,
    b: Vec<Complex32>,
    fft: Vec<Complex32>,
    acc: Vec<f64>,
    lit: Vec<bool>,
    reached: Vec<bool>,
}

impl Scratch {
    /// Grows the buffers to what `e`'s blocks need.
    fn fit(&mut self, e: &Engine) {
        let zero = Complex32::new(0.0, 0.0);
        for (v, n) in [
            (&mut self.a, e.max_area),
            (&mut self.b, e.max_area),
            (&mut self.fft, e.scratch_len),
        ] {
            if v.len() < n {
                v.resize(n, zero);
            }
        }
        if self.acc.len() < SLOTS {
            self.acc.resize(SLOTS, 0.0);
        }
        self.lit.reserve(e.max_m);
        self.reached.reserve(e.max_m);
    }
}

thread_local! {
    /// This thread's [`Scratch`].
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// The coherent pixels of `tiles` ([`SLOTS`] per tile), by FFT.
pub(super) fn tile_pixels(
    rough: &Image<f64>,
    psf: &AiryPsf,
    contrast: f64,
    sampler: &PoseSampler,
    tiles: &[Tile],
) -> Vec<f64> {
    let jobs: Vec<Option<Job>> = tiles.par_iter().map(|t| job(rough, psf, t)).collect();
    let live: Vec<Job> = jobs.iter().flatten().copied().collect();
    let engine = Engine::new(psf, &live);
    let mut pixels = vec![0.0; tiles.len() * SLOTS];
    pixels
        .par_chunks_mut(SLOTS)
        .zip(&jobs)
        .for_each(|(out, job)| {
            if let Some(job) = job {
                SCRATCH.with_borrow_mut(|scratch| {
                    scratch.fit(&engine);
                    tile_fft(rough, psf, contrast, sampler, &engine, job, scratch, out);
                });
            }
        });
    pixels
}

/// One tile's pixels into `out` (row-major, the tile's width).
#[allow(clippy::too_many_arguments)]
fn tile_fft(
    rough: &Image<f64>,
    psf: &AiryPsf,
    contrast: f64,
    sampler: &PoseSampler,
    engine: &Engine,
    job: &Job,
    scratch: &mut Scratch,
    out: &mut [f64],
) {
    let (q, h) = (psf.oversampling(), psf.half_width());
    let w_sub = rough.width * q;
    let [(sx0, sx1), (sy0, sy1)] = job.s;
    let [(ox0, ox1), (oy0, oy1)] = job.o;
    let [mx, my] = job.m;
    let t = job.tile;
    let tw = t.x1 - t.x0;
    let (fx, fy) = (&engine.plans[&mx], &engine.plans[&my]);
    let spectrum = &engine.spectra[&(mx, my)];
    let patterns = patterns(contrast);
    let Scratch {
        a,
        b,
        fft,
        acc,
        lit,
        reached,
    } = scratch;
    let (a, b) = (&mut a[..mx * my], &mut b[..mx * my]);
    acc[..t.len()].fill(0.0);
    // Source sub-rows with light (their pixel row has a lit pixel in S's columns), and output
    // sub-rows within the kernel's reach of one.
    lit.clear();
    lit.extend((sy0..sy1).map(|y| {
        let py = y / q;
        (sx0 / q..(sx1 - 1) / q + 1).any(|px| rough.get(px, py) > 0.0)
    }));
    reached.clear();
    reached.extend((oy0..oy1).map(|y| {
        let lo = y.saturating_sub(h).max(sy0);
        let hi = (y + h + 1).min(sy1);
        lo < hi && lit[lo - sy0..hi - sy0].iter().any(|&l| l)
    }));
    for pattern in 0..patterns {
        for (j, y) in (sy0..sy1).enumerate() {
            if !lit[j] {
                continue;
            }
            let r = &mut a[j * mx..(j + 1) * mx];
            r.fill(Complex32::new(0.0, 0.0));
            // Pixel by pixel along S's columns: px covers sub-samples [px·q, px·q + q) ∩ S.
            for px in sx0 / q..(sx1 - 1) / q + 1 {
                let amp = rough.get(px, y / q).max(0.0).sqrt();
                if amp == 0.0 {
                    continue;
                }
                for x in (px * q).max(sx0)..(px * q + q).min(sx1) {
                    let (c, s) = phase(sampler, w_sub, x, y, pattern);
                    r[x - sx0] = Complex32::new((amp * c) as f32, (amp * s) as f32);
                }
            }
            fx.forward.process_with_scratch(r, fft);
        }
        transpose(a, b, my, mx, Some(lit));
        fy.forward.process_with_scratch(b, fft);
        for (v, k) in b.iter_mut().zip(spectrum) {
            *v *= *k;
        }
        fy.inverse.process_with_scratch(b, fft);
        transpose(b, a, mx, my, None);
        for (k, y) in (oy0..oy1).enumerate() {
            if !reached[k] {
                continue;
            }
            let j = (y + my - sy0) % my;
            let row = &mut a[j * mx..(j + 1) * mx];
            fx.inverse.process_with_scratch(row, fft);
            // Output columns pixel by pixel; block index of sub-sample x is (x − s0) mod M.
            let base = (y / q - t.y0) * tw;
            for px in ox0 / q..(ox1 - 1) / q + 1 {
                let (xa, xb) = ((px * q).max(ox0), (px * q + q).min(ox1));
                let mut sum = 0.0;
                for x in xa..xb {
                    let i = if x >= sx0 { x - sx0 } else { x + mx - sx0 };
                    sum += row[i].norm_sqr() as f64;
                }
                acc[base + px - t.x0] += sum;
            }
        }
    }
    let scale = 1.0 / (patterns * q * q) as f64;
    for (o, v) in out[..t.len()].iter_mut().zip(acc.iter()) {
        *o = v * scale;
    }
}

#[cfg(test)]
mod tests {
    use super::super::{speckle_image, speckle_image_direct};
    use super::*;

    /// A synthetic laser line: Gaussian across (σ 0.8 px), wandering in row along the columns,
    /// one end touching the top border, a steep segment, a few stray pixels and a faint patch.
    fn line_image(w: usize, h: usize) -> Image<f64> {
        let mut img = Image::new(w, h);
        for x in 0..w {
            let c = if x < w / 3 {
                0.6 + x as f64 * 0.15
            } else if x < w / 3 + 4 {
                0.6 + (w / 3) as f64 * 0.15 + (x - w / 3) as f64 * 6.0
            } else {
                0.5 * h as f64 + 3.0 * (x as f64 * 0.1).sin()
            };
            for y in 0..h {
                let d = (y as f64 + 0.5 - c) / 0.8;
                let v = 1e3 * (-0.5 * d * d).exp();
                if v > 1e-3 {
                    img.data[y * w + x] = v * (1.0 + 0.3 * ((x * 7 + y * 3) % 5) as f64 / 5.0);
                }
            }
        }
        for (x, y, v) in [(5, h - 1, 40.0), (w - 1, h - 2, 2.0), (w / 2, 2, 0.5)] {
            img.data[y * w + x] = v;
        }
        for y in h - 6..h - 2 {
            for x in w - 30..w - 20 {
                img.data[y * w + x] = 1e-3; // below the faint fraction: incoherent
            }
        }
        img
    }

    /// (max |fast − direct| / max direct, max relative difference over pixels above 1e-6 of
    /// the maximum).
    fn difference(fast: &Image<f64>, direct: &Image<f64>) -> (f64, f64) {
        let max = direct.data.iter().copied().fold(0.0, f64::max);
        let mut abs: f64 = 0.0;
        let mut rel: f64 = 0.0;
        for (f, d) in fast.data.iter().zip(&direct.data) {
            abs = abs.max((f - d).abs());
            if *d > 1e-6 * max {
                rel = rel.max((f - d).abs() / d);
            }
        }
        (abs / max, rel)
    }

    #[test]
    fn smooth_sizes_have_factors_two_three_five() {
        assert_eq!(smooth_size(1), 1);
        assert_eq!(smooth_size(7), 8);
        assert_eq!(smooth_size(143), 144);
        assert_eq!(smooth_size(145), 150);
        assert_eq!(smooth_size(241), 243);
    }

    #[test]
    fn fft_equals_the_direct_convolution_for_the_same_phases() {
        // f/2.8 and f/8 working f-numbers of the preset head on its 8× grid (the f/8 case on
        // a 4× grid to keep the direct reference quick), one and four patterns.
        for (n_w, q, contrast, w, h) in [
            (2.97, 8, 1.0, 120, 72),
            (8.5, 4, 1.0, 96, 64),
            (2.97, 4, 0.5, 80, 48),
        ] {
            let psf = AiryPsf::new(658e-9, n_w, 9.4e-6, q);
            let img = line_image(w, h);
            let s = PoseSampler::new(5, 9);
            let fast = speckle_image(&img, &psf, contrast, &s);
            let direct = speckle_image_direct(&img, &psf, contrast, &s);
            let (abs, rel) = difference(&fast, &direct);
            eprintln!("N_w {n_w}, q {q}, C {contrast}: max |Δ|/max {abs:.2e}, max rel {rel:.2e}");
            // The FFT runs in f32 (the direct reference in f64): its rounding is relative to
            // the block's largest values, ~3e-7 of the brightest pixel; a pixel at 1e-6 of it
            // is then ~2e-5 off relative (measured 2.7e-7 and 2.3e-5 at f/2.8).
            assert!(abs < 2e-6 && rel < 2e-4, "{abs} {rel}");
            // The image has speckle at all (not the mean image).
            assert!(difference(&fast, &psf.blur(&img)).0 > 1e-2);
        }
    }

    #[test]
    fn fft_image_is_bit_identical_for_one_and_two_threads() {
        let psf = AiryPsf::new(658e-9, 2.97, 9.4e-6, 8);
        let img = line_image(200, 64);
        let s = PoseSampler::new(2, 3);
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a thread pool")
                .install(|| speckle_image(&img, &psf, 1.0, &s))
        };
        let (one, two) = (run(1), run(2));
        assert!(one
            .data
            .iter()
            .zip(&two.data)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}
