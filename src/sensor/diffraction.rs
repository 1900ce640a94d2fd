//! The lens's diffraction: the Airy point-spread function of a circular pupil, once as the
//! coherent amplitude kernel on a sub-pixel grid (for speckle, `sensor::speckle`) and once as
//! the incoherent intensity kernel integrated over pixels (for light that does not form
//! speckle: rough-surface light with speckle off, glints, faint stray light).
//!
//! Airy amplitude of an aberration-free circular pupil at image-side working f-number N_w
//! (Born & Wolf, *Principles of Optics*, 7th ed., §8.5.2, eq. 8.5(14); Goodman, *Speckle
//! Phenomena in Optics*, 2007, §4.4): h(r) = 2·J₁(v)/v with v = π·r/(λ·N_w). The first dark
//! ring is at r = 1.22·λ·N_w (≈ 2.4 µm at f/2.8, 19 µm at f/22 for this head's N_w ≈ 1.07·N
//! at 658 nm); the kernel is kept out to [`AIRY_RINGS`] dark rings (≈ 95 % of the pattern's
//! energy, Born & Wolf Fig. 8.12) and normalised on its sub-grid to Σ h² = 1, so no light is
//! created or lost by the truncation: the outer rings' share is spread over the inner ones.
//!
//! The incoherent pixel kernel is the mean of the coherent image of a δ-correlated field: a
//! source uniform over pixel p′ (the light tracer's resolution) seen by pixel p gives
//! P(p − p′) = (1/q²)·Σ_{o∈p} Σ_{s∈p′} h²(o − s) over the q × q sub-samples of each pixel,
//! which is Σ_u h²(u)·t(u_x − q·Δ_x)·t(u_y − q·Δ_y) / q² with the triangle t(d) = max(0, q − |d|)
//! (the autocorrelation of two pixel boxes). Σ_Δ P = 1 exactly (each triangle sums to q over
//! shifts by q), and it is exactly the expectation of `speckle::speckle_image`, so switching
//! speckle off keeps the mean image and the lens's blur.
//!
//! Image border: the tracer records only light that lands on the sensor, so near the border
//! the blur would lose what it spreads off the sensor and miss what the untraced light just
//! beyond it spreads in. The incoherent blur takes the second equal to the first: it mirrors
//! the image about the border's half-sample edges (the same as folding each source pixel's
//! spill back in, P being symmetric), so each source pixel's kernel sums to 1 over the image
//! and Σ out = Σ in to rounding. This touches the outer [`AiryPsf::pixel_radius`] pixels (1 at
//! f/2.8, 7 at f/22). The coherent image (`speckle`) has no field beyond the border instead.
//!
//! Units: metres for lengths; kernels are dimensionless weights.

use std::ops::Range;

use rayon::prelude::*;

use super::image::Image;

/// The Airy amplitude is kept out to this many dark rings.
pub const AIRY_RINGS: f64 = 4.0;

/// Sub-samples per pixel and axis on which the incoherent pixel kernel is integrated when no
/// speckle settings give one (speckle off): the same grid as the preset's speckle, so the two
/// modes blur alike. 8 × 8 midpoints resolve the Airy core at f/2.8 (radius 2.4 µm, sub-pitch
/// 1.2 µm) and integrate the pixel boxes exactly.
pub const DIFFRACTION_OVERSAMPLING: usize = 8;

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

/// The lens's point-spread function for one camera setting: the coherent amplitude kernel on
/// the sub-grid and the incoherent kernel on pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct AiryPsf {
    oversampling: usize,
    half: usize,
    amplitude: Vec<f64>,
    pixel_radius: usize,
    pixel: Vec<f64>,
}

impl AiryPsf {
    /// The PSF at `wavelength_m` and image-side working f-number `f_number` for square pixels
    /// of `pixel_pitch_m`, sampled on `oversampling` (≥ 2, smaller values are raised to 2)
    /// sub-samples per pixel and axis.
    pub fn new(wavelength_m: f64, f_number: f64, pixel_pitch_m: f64, oversampling: usize) -> Self {
        let q = oversampling.max(2);
        let sub_pitch_m = pixel_pitch_m / q as f64;
        // First zero of 2J₁(v)/v at v = 3.8317, i.e. r = 1.22·λ·N; rings every ~π in v.
        let v_max = 3.8317 + (AIRY_RINGS - 1.0) * std::f64::consts::PI;
        let r_max = v_max * wavelength_m * f_number / std::f64::consts::PI;
        let half = (r_max / sub_pitch_m).ceil() as usize;
        let n = 2 * half + 1;
        let mut amplitude = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let (dy, dx) = (i as f64 - half as f64, j as f64 - half as f64);
                let r = (dx * dx + dy * dy).sqrt() * sub_pitch_m;
                let v = std::f64::consts::PI * r / (wavelength_m * f_number);
                amplitude[i * n + j] = if r > r_max {
                    0.0
                } else if v < 1e-9 {
                    1.0
                } else {
                    2.0 * bessel_j1(v) / v
                };
            }
        }
        let norm = amplitude.iter().map(|h| h * h).sum::<f64>().sqrt();
        amplitude.iter_mut().for_each(|h| *h /= norm);
        // Pixel kernel: h² against the two-box autocorrelation t(d) = q − |d| (module docs).
        let pixel_radius = half.div_ceil(q);
        let pn = 2 * pixel_radius + 1;
        let tri = |d: isize| (q as isize - d.abs()).max(0) as f64;
        let mut pixel = vec![0.0; pn * pn];
        for (py, prow) in pixel.chunks_mut(pn).enumerate() {
            let sy = (py as isize - pixel_radius as isize) * q as isize;
            for (px, p) in prow.iter_mut().enumerate() {
                let sx = (px as isize - pixel_radius as isize) * q as isize;
                let mut acc = 0.0;
                for i in 0..n {
                    let ty = tri(i as isize - half as isize - sy);
                    if ty == 0.0 {
                        continue;
                    }
                    for j in 0..n {
                        let h = amplitude[i * n + j];
                        acc += h * h * ty * tri(j as isize - half as isize - sx);
                    }
                }
                *p = acc / (q * q) as f64;
            }
        }
        AiryPsf {
            oversampling: q,
            half,
            amplitude,
            pixel_radius,
            pixel,
        }
    }

    /// Sub-samples per pixel and axis.
    pub fn oversampling(&self) -> usize {
        self.oversampling
    }

    /// Half-width of the amplitude kernel in sub-samples: it is (2·half + 1)² wide.
    pub fn half_width(&self) -> usize {
        self.half
    }

    /// The amplitude kernel h on the sub-grid, row-major, centre at (half, half), Σ h² = 1.
    pub fn amplitude(&self) -> &[f64] {
        &self.amplitude
    }

    /// Half-width of the pixel kernel in pixels: it is (2·radius + 1)² wide.
    pub fn pixel_radius(&self) -> usize {
        self.pixel_radius
    }

    /// The incoherent pixel kernel P, row-major, centre at (radius, radius), Σ P = 1.
    pub fn pixel_kernel(&self) -> &[f64] {
        &self.pixel
    }

    /// The incoherent image of `image` (W/m²): `image` convolved with the pixel kernel, with
    /// the light that would spread off the sensor folded back in (module docs: the border),
    /// so Σ out = Σ in to rounding.
    pub fn blur(&self, image: &Image<f64>) -> Image<f64> {
        let mut out = Image::new(image.width, image.height);
        self.blur_into(image, &mut out);
        out
    }

    /// [`AiryPsf::blur`] of `image` into `out` (resized to fit, overwritten). Rows run in
    /// parallel; a source row with few lit pixels is scattered pixel by pixel, a dense one
    /// row-wise, and each output pixel sums its terms in an order fixed by the image alone, so
    /// the result does not depend on the thread count.
    pub fn blur_into(&self, image: &Image<f64>, out: &mut Image<f64>) {
        self.blur_rows_into(image, 0..image.height, out);
    }

    /// [`AiryPsf::blur_into`] of an `image` that is zero outside `rows`: only those rows are
    /// read and only the output rows within the kernel's reach of them are computed (the rest
    /// of `out` is zero), with the same result.
    pub fn blur_rows_into(&self, image: &Image<f64>, rows: Range<usize>, out: &mut Image<f64>) {
        out.width = image.width;
        out.height = image.height;
        out.data.clear();
        out.data.resize(image.width * image.height, 0.0);
        self.blur_rows_onto_zeros(image, rows, out);
    }

    /// [`AiryPsf::blur_rows_into`] where `out` is already an all-zero image of `image`'s size:
    /// the same result without clearing the whole frame (4 MB a call), for callers that keep a
    /// zeroed buffer by clearing only the rows they dirtied.
    pub fn blur_rows_onto_zeros(
        &self,
        image: &Image<f64>,
        rows: Range<usize>,
        out: &mut Image<f64>,
    ) {
        let (w, h) = (image.width, image.height);
        assert!(out.width == w && out.height == h && out.data.len() == w * h);
        debug_assert!(out.data.iter().all(|&v| v == 0.0), "`out` must be zero");
        let rows = rows.start.min(h)..rows.end.min(h);
        if w == 0 || h == 0 || rows.is_empty() {
            return;
        }
        let r = self.pixel_radius;
        let pn = 2 * r + 1;
        // The lit columns of each row, flat: row y's are cols[start[y]..start[y + 1]].
        let mut cols: Vec<u32> = Vec::new();
        let mut start = Vec::with_capacity(h + 1);
        start.push(0);
        for (y, row) in image.data.chunks(w).enumerate() {
            if rows.contains(&y) {
                cols.extend((0..w as u32).filter(|&x| row[x as usize] != 0.0));
            }
            start.push(cols.len());
        }
        // Output rows the kernel reaches from `rows` (the mirror at the border folds light back
        // into rows that are within the reach anyway).
        let (y0, y1) = (rows.start.saturating_sub(r), (rows.end + r).min(h));
        let reached = &mut out.data[y0 * w..y1 * w];
        reached.par_chunks_mut(w).enumerate().for_each(|(dy, row)| {
            let y = y0 + dy;
            for ky in 0..pn {
                // Source row y − (ky − r), mirrored at the border.
                let sy = mirror(y as isize + r as isize - ky as isize, h);
                let lit = &cols[start[sy]..start[sy + 1]];
                if lit.is_empty() {
                    continue;
                }
                let src = &image.data[sy * w..(sy + 1) * w];
                let krow = &self.pixel[ky * pn..(ky + 1) * pn];
                if lit.len() * 4 < w {
                    // Sparse: source pixel s lands on s + (kx − r), folded at the border.
                    for &s in lit {
                        let v = src[s as usize];
                        for (kx, &k) in krow.iter().enumerate() {
                            row[mirror(s as isize + kx as isize - r as isize, w)] += k * v;
                        }
                    }
                    continue;
                }
                for (kx, &k) in krow.iter().enumerate() {
                    if k == 0.0 {
                        continue;
                    }
                    // out[x] += k·src[x − d]: a slice where x − d stays inside, the border
                    // columns one by one.
                    let d = kx as isize - r as isize;
                    let (lo, hi) = (
                        d.clamp(0, w as isize) as usize,
                        (w as isize + d).clamp(0, w as isize) as usize,
                    );
                    if lo < hi {
                        let s0 = (lo as isize - d) as usize;
                        for (o, s) in row[lo..hi].iter_mut().zip(&src[s0..s0 + hi - lo]) {
                            *o += k * s;
                        }
                    }
                    for x in (0..lo).chain(hi.max(lo)..w) {
                        row[x] += k * src[mirror(x as isize - d, w)];
                    }
                }
            }
        });
    }
}

/// Index `i` reflected into [0, n) about the half-sample edges (−1 ↦ 0, n ↦ n − 1), clamped
/// if the kernel is wider than the image.
fn mirror(i: isize, n: usize) -> usize {
    let n = n as isize;
    let j = if i < 0 {
        -1 - i
    } else if i >= n {
        2 * n - 1 - i
    } else {
        i
    };
    j.clamp(0, n - 1) as usize
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

    #[test]
    fn kernels_are_normalised_and_symmetric() {
        for n_w in [3.0, 8.6, 23.5] {
            let psf = AiryPsf::new(658e-9, n_w, 9.4e-6, 8);
            let s2: f64 = psf.amplitude().iter().map(|h| h * h).sum();
            assert!((s2 - 1.0).abs() < 1e-12, "Σh² = {s2}");
            let p = psf.pixel_kernel();
            let sum: f64 = p.iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "ΣP = {sum}");
            let pn = 2 * psf.pixel_radius() + 1;
            for i in 0..pn {
                for j in 0..pn {
                    let v = p[i * pn + j];
                    for m in [
                        p[j * pn + i],
                        p[(pn - 1 - i) * pn + j],
                        p[i * pn + pn - 1 - j],
                    ] {
                        assert!((v - m).abs() <= 1e-15, "asymmetric kernel");
                    }
                }
            }
        }
        // f/2.8 (N_w ≈ 3): the Airy core is far below a 9.4 µm pixel, a 3 × 3 kernel that
        // keeps most of the light in its pixel; f/22 (N_w ≈ 23.5): 15 × 15.
        let fine = AiryPsf::new(658e-9, 3.0, 9.4e-6, 8);
        assert_eq!(fine.pixel_radius(), 1);
        assert!(fine.pixel_kernel()[4] > 0.6, "{}", fine.pixel_kernel()[4]);
        assert_eq!(AiryPsf::new(658e-9, 23.5, 9.4e-6, 8).pixel_radius(), 7);
    }

    /// The blur by its definition: a gather over the mirrored image.
    fn blur_reference(psf: &AiryPsf, img: &Image<f64>) -> Image<f64> {
        let (w, h, r) = (img.width, img.height, psf.pixel_radius() as isize);
        let pn = 2 * r as usize + 1;
        let mut out = Image::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let mut acc = 0.0;
                for ky in 0..pn {
                    for kx in 0..pn {
                        let sx = mirror(x as isize - (kx as isize - r), w);
                        let sy = mirror(y as isize - (ky as isize - r), h);
                        acc += psf.pixel_kernel()[ky * pn + kx] * img.get(sx, sy);
                    }
                }
                out.data[y * w + x] = acc;
            }
        }
        out
    }

    #[test]
    fn sparse_and_dense_rows_match_the_definition_up_to_the_border() {
        let psf = AiryPsf::new(658e-9, 23.5, 9.4e-6, 8);
        let (w, h) = (48, 36);
        let mut img = Image::new(w, h);
        for x in 0..w {
            img.data[17 * w + x] = 1.0 + (x % 7) as f64; // dense row
        }
        for (x, y) in [(0, 0), (47, 3), (5, 35), (30, 20), (2, 1)] {
            img.data[y * w + x] = 3.0; // sparse rows, some at the border
        }
        let (fast, slow) = (psf.blur(&img), blur_reference(&psf, &img));
        for (f, s) in fast.data.iter().zip(&slow.data) {
            assert!((f - s).abs() <= 1e-14 * s.abs().max(1.0), "{f} vs {s}");
        }
    }

    #[test]
    fn blurring_only_the_lit_rows_gives_the_whole_image_blur_bit_for_bit() {
        // Bands in the middle and touching either border (where the mirror folds light back).
        let psf = AiryPsf::new(658e-9, 23.5, 9.4e-6, 8);
        let (w, h) = (40, 30);
        for rows in [10..14, 0..2, 27..30, 0..30] {
            let mut img = Image::new(w, h);
            for y in rows.clone() {
                for x in (y % 3..w).step_by(3) {
                    img.data[y * w + x] = 1.0 + (x * y) as f64;
                }
            }
            let mut banded = Image::new(1, 1);
            psf.blur_rows_into(&img, rows.clone(), &mut banded);
            assert_eq!(banded, psf.blur(&img), "rows {rows:?}");
        }
    }

    #[test]
    fn blur_of_a_point_is_the_kernel_and_flux_is_conserved_up_to_the_border() {
        let psf = AiryPsf::new(658e-9, 23.5, 9.4e-6, 8);
        let r = psf.pixel_radius();
        let pn = 2 * r + 1;
        let mut img = Image::new(40, 30);
        img.data[15 * 40 + 20] = 2.0;
        let out = psf.blur(&img);
        for ky in 0..pn {
            for kx in 0..pn {
                let v = out.get(20 + kx - r, 15 + ky - r);
                assert!((v - 2.0 * psf.pixel_kernel()[ky * pn + kx]).abs() < 1e-15);
            }
        }
        let sum: f64 = out.data.iter().sum();
        assert!((sum - 2.0).abs() < 1e-13, "flux {sum}");
        // At the corner the spill is folded back: still all the light, and the corner pixel
        // gets its own share plus the mirrored ones (more than the kernel's centre).
        let mut corner = Image::new(40, 30);
        corner.data[0] = 1.0;
        corner.data[30 * 40 - 1] = 0.5;
        let out = psf.blur(&corner);
        let sum: f64 = out.data.iter().sum();
        assert!((sum - 1.5).abs() < 1e-14, "flux {sum}");
        assert!(out.data[0] > psf.pixel_kernel()[r * pn + r]);
        assert_eq!(mirror(-1, 5), 0);
        assert_eq!(mirror(5, 5), 4);
        assert_eq!(mirror(-3, 5), 2);
        assert_eq!(mirror(9, 3), 0);
    }
}
