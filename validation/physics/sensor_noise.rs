//! The image sensor's noise model (`sensor::emva`, `sensor::bloom`) against the EMVA 1288
//! linear model and charge conservation.
//!
//! Reference values: EMVA 1288 Release 3.1 (photon transfer, docs/parameters.md §2a) and the
//! formulas of the reference implementation `EMVA1288/emva1288` (`process/results.py`:
//! σ_y² = K²σ_d² + σ_q² + K·(μ_y − μ_y,dark), SNR = μ_e/√(σ_d² + σ_q²/K² + μ_e)); blooming
//! after docs/parameters.md §2c and LSST imSim `imsim/bleed_trails.py`. All frames are synthetic
//! irradiance images, so every expected value is known in closed form.

use glassscan::sampler::PoseSampler;
use glassscan::sensor::emva::{frame_sampler, poisson, Exposure, FixedPattern};
use glassscan::sensor::image::Image;
use glassscan::sensor::imager::{ImagerSpec, SensorKind};
use glassscan::sensor::preset::scancontrol_2600_100;

use crate::stats::{chi2_p_value, sidak, SIGNIFICANCE};

/// Pixel area of the preset (9.4 µm pitch) and the laser wavelength.
const AREA_M2: f64 = 9.4e-6 * 9.4e-6;
const LAMBDA_M: f64 = 658e-9;

fn flat(width: usize, height: usize, e_w_m2: f64) -> Image<f64> {
    Image {
        width,
        height,
        data: vec![e_w_m2; width * height],
    }
}

/// Irradiance (W/m²) that gives a mean of `electrons` photo-electrons with `spec`.
fn irradiance_for(spec: &ImagerSpec, electrons: f64) -> f64 {
    electrons / (spec.quantum_efficiency * spec.photons(1.0, AREA_M2, LAMBDA_M))
}

fn expose(spec: &ImagerSpec, e: &Image<f64>, sampler: &PoseSampler) -> Exposure {
    let pattern = FixedPattern::new(spec, e.width, e.height);
    spec.expose_noisy(e, AREA_M2, LAMBDA_M, sampler, &pattern)
}

/// Mean of two frames and the temporal variance from their difference, σ² = var(A − B)/2,
/// which cancels the fixed pattern (EMVA 1288 §6.3); also the spatial variance of the mean
/// image minus its temporal part (the fixed pattern, EMVA 1288 §8).
fn frame_pair_moments(a: &Image<u16>, b: &Image<u16>) -> (f64, f64, f64) {
    let n = a.data.len() as f64;
    let pairs = || {
        a.data
            .iter()
            .zip(&b.data)
            .map(|(&x, &y)| (x as f64, y as f64))
    };
    let mean = pairs().map(|(x, y)| 0.5 * (x + y)).sum::<f64>() / n;
    let diff_mean = pairs().map(|(x, y)| x - y).sum::<f64>() / n;
    let temporal = pairs()
        .map(|(x, y)| (x - y - diff_mean).powi(2))
        .sum::<f64>()
        / (2.0 * (n - 1.0));
    let spatial = pairs()
        .map(|(x, y)| (0.5 * (x + y) - mean).powi(2))
        .sum::<f64>()
        / (n - 1.0)
        - 0.5 * temporal;
    (mean, temporal, spatial)
}

/// Weighted least squares v = c + s·x with weights wᵢ; returns (s, c, σ_s, σ_c).
fn weighted_line(x: &[f64], v: &[f64], w: &[f64]) -> (f64, f64, f64, f64) {
    let (mut sw, mut sx, mut sxx, mut sv, mut sxv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for ((&x, &v), &w) in x.iter().zip(v).zip(w) {
        sw += w;
        sx += w * x;
        sxx += w * x * x;
        sv += w * v;
        sxv += w * x * v;
    }
    let det = sw * sxx - sx * sx;
    let slope = (sw * sxv - sx * sv) / det;
    let intercept = (sxx * sv - sx * sxv) / det;
    (slope, intercept, (sw / det).sqrt(), (sxx / det).sqrt())
}

#[test]
fn photon_transfer_gives_the_gain_and_the_dark_noise() {
    // EMVA 1288 photon transfer (docs/parameters.md §2a): a flat patch at 11 levels from dark to 85 %
    // of the ADC range, two frames per level. The temporal variance (difference image) against
    // the dark-subtracted mean is a line of slope K and intercept K²σ_d² + σ_q², with
    // σ_d² = σ_d0² + μ_I·t_exp (read noise plus dark-current shot noise) and σ_q² = 1/12 DN²
    // (an ADC that rounds without dither). A 20 DN black level keeps the dark noise off the ADC's zero, and the
    // driver's longest exposure, 40 ms (§1a), gives 5 dark electrons at the CMV300's 125 e⁻/s.
    let mut spec = scancontrol_2600_100().imager;
    spec.dark_offset_dn = 20.0;
    spec.exposure_s = 40e-3;
    let k = spec.gain_dn_per_e;
    let sigma_d2 = spec.read_noise_e.powi(2) + spec.dark_current_e_per_s * spec.exposure_s;
    let (w, h) = (256, 256);
    let n = (w * h) as f64;
    let top_e = 0.85 * (f64::from(spec.max_dn()) - spec.dark_offset_dn) / k;
    let levels: Vec<f64> = (0..=10).map(|j| top_e * j as f64 / 10.0).collect();
    let mut measured = Vec::new();
    for (j, &mu_e) in levels.iter().enumerate() {
        let e = flat(w, h, irradiance_for(&spec, mu_e));
        let a = expose(&spec, &e, &frame_sampler(7, 2 * j as u64));
        let b = expose(&spec, &e, &frame_sampler(7, 2 * j as u64 + 1));
        assert_eq!(a.saturated + b.saturated, 0, "level {j} saturates");
        measured.push(frame_pair_moments(&a.dn, &b.dn));
    }
    let (dark_mean, dark_var, _) = measured[0];
    let x: Vec<f64> = measured.iter().map(|m| m.0 - dark_mean).collect();
    let v: Vec<f64> = measured.iter().map(|m| m.1).collect();
    // Var(s²) = 2σ⁴/(n − 1) for a sample variance of n near-Gaussian values; the model's σ² is
    // used for the weights, so the weights do not correlate with the noise in v.
    let q2 = 1.0 / 12.0;
    let model = |x: f64| k * k * sigma_d2 + q2 + k * x;
    let weights: Vec<f64> = x
        .iter()
        .map(|&x| (n - 1.0) / (2.0 * model(x).powi(2)))
        .collect();
    let (slope, intercept, se_slope, se_intercept) = weighted_line(&x, &v, &weights);
    let expected_intercept = k * k * sigma_d2 + q2;
    eprintln!(
        "photon transfer: slope {slope:.6} ± {se_slope:.6} DN/e⁻ vs K = {k:.6} ({:+.3} %); \
         intercept {intercept:.4} ± {se_intercept:.4} DN² vs K²σ_d² + 1/12 = \
         {expected_intercept:.4} (EMVA's 1/12 would give {:.4})",
        100.0 * (slope / k - 1.0),
        k * k * sigma_d2 + 1.0 / 12.0
    );
    assert!(
        (slope / k - 1.0).abs() < 0.03 && (slope - k).abs() < 4.0 * se_slope,
        "slope {slope} ± {se_slope}, K {k}"
    );
    assert!(
        (intercept - expected_intercept).abs() < 4.0 * se_intercept,
        "intercept {intercept} ± {se_intercept}, expected {expected_intercept}"
    );

    // Dark frames: mean = black level + K·(μ_I·t_exp + the DSNU map's mean); the read noise
    // (0.7 DN) spreads each pixel over several codes, so rounding is unbiased on average. Variance = K²σ_d² + σ_q².
    let pattern = FixedPattern::new(&spec, w, h);
    let dsnu_mean = pattern.offset_e.data.iter().sum::<f64>() / n;
    let expected_dark =
        spec.dark_offset_dn + k * (spec.dark_current_e_per_s * spec.exposure_s + dsnu_mean);
    let se_dark = (dark_var / (2.0 * n)).sqrt();
    eprintln!(
        "dark: mean {dark_mean:.4} DN vs {expected_dark:.4} (± {se_dark:.4}); temporal variance \
         {dark_var:.4} DN² vs {expected_intercept:.4}"
    );
    assert!((dark_mean - expected_dark).abs() < 4.0 * se_dark);
    let se_dark_var = expected_intercept * (2.0 / (n - 1.0)).sqrt();
    assert!((dark_var - expected_intercept).abs() < 4.0 * se_dark_var);

    // SNR at the top level: μ_e/σ_e with the temporal noise, against √μ_e (the shot-noise
    // limit, SNR_max = √μ_e,sat in docs/parameters.md §2a) and the EMVA formula
    // SNR = μ_e/√(σ_d² + σ_q²/K² + μ_e).
    let (top_mean, top_var, top_spatial) = measured[10];
    let mu_e = (top_mean - dark_mean) / k;
    let snr = (top_mean - dark_mean) / top_var.sqrt();
    let snr_emva = mu_e / (sigma_d2 + q2 / (k * k) + mu_e).sqrt();
    eprintln!(
        "SNR at μ_e = {mu_e:.0} e⁻: {snr:.2}; √μ_e = {:.2}; EMVA formula {snr_emva:.2}",
        mu_e.sqrt()
    );
    // σ(SNR)/SNR ≈ 1/√(2(n − 1)) = 0.28 %.
    assert!((snr / mu_e.sqrt() - 1.0).abs() < 0.02);
    assert!((snr / snr_emva - 1.0).abs() < 4.0 / (2.0 * (n - 1.0)).sqrt());
    // The fixed pattern is what the difference image removed: the spatial variance of the
    // mean image is K²·(PRNU²·μ_e² + DSNU²) (EMVA 1288 §8).
    let expected_spatial = k * k * ((spec.prnu * mu_e).powi(2) + spec.dsnu_e.powi(2));
    eprintln!("spatial variance at the top level: {top_spatial:.2} DN² vs {expected_spatial:.2}");
    assert!((top_spatial / expected_spatial - 1.0).abs() < 0.15);
}

/// A 40 × 120 frame with a 3 × 3 spot (centre 20 full wells, ring 5) at column 20, row 60 on a
/// background of 200 e⁻, and no dark current (so only light makes charge).
fn spot_scene(kind: SensorKind) -> (ImagerSpec, Image<f64>) {
    let mut spec = scancontrol_2600_100().imager;
    spec.kind = kind;
    spec.dark_current_e_per_s = 0.0;
    let fw = spec.full_well_e;
    let mut e = flat(40, 120, irradiance_for(&spec, 200.0));
    for dr in -1i32..=1 {
        for dc in -1i32..=1 {
            let wells = if dr == 0 && dc == 0 { 20.0 } else { 5.0 };
            let (c, r) = ((20 + dc) as usize, (60 + dr) as usize);
            e.data[r * 40 + c] = irradiance_for(&spec, wells * fw);
        }
    }
    (spec, e)
}

#[test]
fn ccd_blooming_conserves_charge_and_bleeds_only_along_the_column() {
    // docs/parameters.md §2c: a CCD's excess charge spills along the vertical transfer column. The
    // reference is the same frame (same keyed draws) with a full well too deep to fill: its
    // charge is the charge before blooming.
    let (spec, e) = spot_scene(SensorKind::Ccd);
    let fw = spec.full_well_e;
    let s = frame_sampler(3, 0);
    let ccd = expose(&spec, &e, &s);
    let mut deep = spec;
    deep.full_well_e = 1e12;
    let before = expose(&deep, &e, &s);
    let total_before: f64 = before.electrons.data.iter().sum();
    let total_after: f64 = ccd.electrons.data.iter().sum();
    eprintln!(
        "CCD bloom: {total_before:.1} e⁻ before, {total_after:.1} after, {} lost",
        ccd.lost_e
    );
    assert_eq!(ccd.lost_e, 0.0);
    assert!((total_after - total_before).abs() <= 1e-12 * total_before);
    let (w, h) = (e.width, e.height);
    let changed = |c: usize, r: usize| ccd.electrons.get(c, r) != before.electrons.get(c, r);
    // Only the spot's three columns change; in each, the charge is conserved on its own.
    for c in 0..w {
        let col_before: f64 = (0..h).map(|r| before.electrons.get(c, r)).sum();
        let col_after: f64 = (0..h).map(|r| ccd.electrons.get(c, r)).sum();
        assert!(
            (col_after - col_before).abs() <= 1e-9 * col_before,
            "column {c}"
        );
        if !(19..=21).contains(&c) {
            assert!((0..h).all(|r| !changed(c, r)), "column {c} received charge");
        }
    }
    assert!(ccd.electrons.data.iter().all(|&q| q <= fw));
    // The trail: one unbroken vertical run of full pixels. The spot's run (rows 59–61) holds
    // X = Σq − 3·μ_e,sat excess electrons; half goes each way and fills pixels that already
    // hold the ~200 e⁻ background, so each side gets ⌊(X/2)/(μ_e,sat − 200)⌋ full pixels plus
    // one partly filled.
    let full_rows: Vec<usize> = (0..h).filter(|&r| ccd.electrons.get(20, r) >= fw).collect();
    let excess = (59..=61).map(|r| before.electrons.get(20, r)).sum::<f64>() - 3.0 * fw;
    let expected_rows = 3.0 + 2.0 * (0.5 * excess / (fw - 200.0)).floor();
    let full_in_row_60 = (0..w).filter(|&c| ccd.electrons.get(c, 60) >= fw).count();
    eprintln!(
        "trail: {} full pixels in column 20 (rows {}…{}), expected {expected_rows} from an \
         excess of {:.2} full wells; {full_in_row_60} full pixels in row 60",
        full_rows.len(),
        full_rows[0],
        full_rows[full_rows.len() - 1],
        excess / fw
    );
    assert_eq!(
        full_rows.len(),
        full_rows[full_rows.len() - 1] - full_rows[0] + 1
    );
    // ±1 per side for the background's shot noise and PRNU at the partly filled ends.
    assert!((full_rows.len() as f64 - expected_rows).abs() <= 2.0);
    assert_eq!(full_in_row_60, 3);
    assert!(ccd.saturated >= full_rows.len());
}

#[test]
fn cmos_clips_at_the_full_well_and_never_spreads() {
    // docs/parameters.md §2c: CMOS pixels are read independently; the overflow stays local. Every
    // pixel outside the spot reads exactly what it reads with the spot dark (same keyed noise).
    let (spec, e) = spot_scene(SensorKind::Cmos);
    let fw = spec.full_well_e;
    let s = frame_sampler(3, 0);
    let cmos = expose(&spec, &e, &s);
    let mut dark_spot = e.clone();
    let background = dark_spot.data[0];
    let spot = |c: usize, r: usize| (19..=21).contains(&c) && (59..=61).contains(&r);
    let w = e.width;
    for (i, v) in dark_spot.data.iter_mut().enumerate() {
        if spot(i % w, i / w) {
            *v = background;
        }
    }
    let without = expose(&spec, &dark_spot, &s);
    let mut deep = spec;
    deep.full_well_e = 1e12;
    let before = expose(&deep, &e, &s);
    let mut drained = 0.0;
    for (i, (&q, &d)) in cmos.electrons.data.iter().zip(&cmos.dn.data).enumerate() {
        let (c, r) = (i % w, i / w);
        if spot(c, r) {
            // Read noise and DSNU come after the full well: with K·μ_e,sat at full scale a
            // clipped pixel reads full scale or a few DN below (σ ≈ 0.7 DN).
            assert_eq!(q, fw);
            assert!(d + 5 >= spec.max_dn(), "{d}");
            drained += before.electrons.data[i] - fw;
        } else {
            assert_eq!(q, without.electrons.data[i], "pixel ({c}, {r})");
            assert_eq!(d, without.dn.data[i], "pixel ({c}, {r})");
        }
    }
    eprintln!(
        "CMOS: 9 pixels clipped, {:.0} e⁻ drained (expected {drained:.0}); {} saturated",
        cmos.lost_e, cmos.saturated
    );
    assert!((cmos.lost_e - drained).abs() <= 1e-9 * drained);
    assert_eq!(cmos.saturated, 9);
}

#[test]
fn saturation_exposure_scales_as_one_over_irradiance() {
    // μ_e = η·A·E·t·λ/(h·c) (docs/parameters.md §2a) saturates at a fixed charge, so the exposure at
    // which a pixel saturates is inversely proportional to the irradiance (the laser power).
    let mut spec = scancontrol_2600_100().imager;
    let k = spec.gain_dn_per_e;
    let irradiances = [0.5, 1.0, 2.0, 5.0, 20.0];
    // Noise-free: the DN reaches full scale where K·η·μ_p = max − ½.
    spec.noise = false;
    let per_joule = spec.photons(1.0, AREA_M2, LAMBDA_M) / spec.exposure_s;
    let mut products = Vec::new();
    for &e in &irradiances {
        let t = bisect_exposure(&mut spec, |sp| {
            let x = expose(sp, &flat(1, 1, e), &frame_sampler(0, 0));
            x.dn.data[0] == sp.max_dn()
        });
        products.push(t * e);
    }
    let analytic = (f64::from(spec.max_dn()) - 0.5) / (k * spec.quantum_efficiency * per_joule);
    eprintln!("noise-free t_sat·E: {products:?} J/m² (analytic {analytic:.6e})");
    for p in &products {
        assert!((p / analytic - 1.0).abs() < 1e-9);
    }
    // Noisy: the exposure at which half the pixels of a flat 64 × 64 patch saturate, each
    // irradiance with its own frame of noise. The median saturating charge is within a few e⁻
    // of the noise-free one (σ per pixel ≈ 200 e⁻ from shot noise and PRNU, over 4096 pixels).
    spec.noise = true;
    let mut noisy = Vec::new();
    for (j, &e) in irradiances.iter().enumerate() {
        let t = bisect_exposure(&mut spec, |sp| {
            let x = expose(sp, &flat(64, 64, e), &frame_sampler(5, j as u64));
            2 * x.saturated >= 64 * 64
        });
        noisy.push(t * e);
    }
    let mean = noisy.iter().sum::<f64>() / noisy.len() as f64;
    eprintln!(
        "noisy t_50%·E: {noisy:?} J/m²; spread {:.3} %, mean vs noise-free {:+.3} %",
        100.0
            * noisy
                .iter()
                .map(|p| (p / mean - 1.0).abs())
                .fold(0.0, f64::max),
        100.0 * (mean / analytic - 1.0)
    );
    for p in &noisy {
        assert!((p / mean - 1.0).abs() < 0.005, "{noisy:?}");
    }
    assert!((mean / analytic - 1.0).abs() < 0.01);
}

/// The shortest exposure (s) at which `saturated` holds, by bisection on log t over
/// 1 ns … 10 s (monotone in t for a fixed frame: more light never desaturates a pixel).
fn bisect_exposure(spec: &mut ImagerSpec, saturated: impl Fn(&ImagerSpec) -> bool) -> f64 {
    let (mut lo, mut hi) = (1e-9f64, 10.0f64);
    for _ in 0..80 {
        let mid = (lo * hi).sqrt();
        spec.exposure_s = mid;
        if saturated(spec) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

#[test]
fn noise_off_reproduces_expose_and_noise_is_keyed_by_seed_and_pose() {
    let mut spec = scancontrol_2600_100().imager;
    let (w, h) = (64, 48);
    // A ramp from dark to 3× the full well.
    let top = irradiance_for(&spec, 3.0 * spec.full_well_e);
    let e = Image {
        width: w,
        height: h,
        data: (0..w * h)
            .map(|i| top * i as f64 / (w * h) as f64)
            .collect(),
    };
    spec.noise = false;
    for kind in [SensorKind::Cmos, SensorKind::Ccd] {
        spec.kind = kind;
        let off = expose(&spec, &e, &frame_sampler(1, 0));
        assert_eq!(off.dn, spec.expose(&e, AREA_M2, LAMBDA_M), "{kind:?}");
    }
    spec.noise = true;
    spec.kind = SensorKind::Cmos;
    let a = expose(&spec, &e, &frame_sampler(1, 0));
    assert_eq!(a, expose(&spec, &e, &frame_sampler(1, 0)));
    let other_pose = expose(&spec, &e, &frame_sampler(1, 1));
    let other_seed = expose(&spec, &e, &frame_sampler(2, 0));
    // Among the pixels below saturation (the ramp's upper two thirds saturate).
    let unsaturated = a
        .electrons
        .data
        .iter()
        .filter(|&&q| q < 0.9 * spec.full_well_e)
        .count();
    let differing = |x: &Exposure| {
        (0..w * h)
            .filter(|&i| {
                a.electrons.data[i] < 0.9 * spec.full_well_e && a.dn.data[i] != x.dn.data[i]
            })
            .count()
    };
    eprintln!(
        "unsaturated pixels that differ: {} of {unsaturated} for another pose, {} for another \
         seed",
        differing(&other_pose),
        differing(&other_seed)
    );
    assert!(differing(&other_pose) > unsaturated / 2 && differing(&other_seed) > unsaturated / 2);
    // Thread count: pixels are independent and blooming runs in order.
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
            .install(|| expose(&spec, &e, &frame_sampler(1, 0)))
    };
    assert_eq!(on(1), on(2));
    // The fixed pattern is the sensor's, not the frame's.
    assert_eq!(
        FixedPattern::new(&spec, w, h),
        FixedPattern::new(&spec, w, h)
    );
}

#[test]
fn poisson_draws_follow_the_poisson_pmf() {
    // Pearson's χ² of 200 000 draws against the Poisson pmf, cells with expected count < 5
    // pooled (Cochran's rule, as in `stats`), at 1 % family-wise significance (Šidák). Means on
    // both sides of the inversion / PTRS switch at 30.
    let means: [f64; 6] = [0.5, 5.0, 29.9, 30.0, 50.0, 5e3];
    let alpha = sidak(SIGNIFICANCE, means.len());
    let n = 200_000u64;
    for (stream, &mu) in means.iter().enumerate() {
        let s = PoseSampler::new(17, stream as u64);
        let hi = (mu + 10.0 * mu.sqrt() + 20.0).ceil() as usize;
        let mut observed = vec![0u64; hi + 1];
        for i in 0..n {
            let mut dim = 0;
            let k = poisson(mu, || {
                dim += 1;
                s.uniform(i, dim)
            });
            observed[(k as usize).min(hi)] += 1;
        }
        // pmf by recurrence in logs; the last cell takes the upper tail.
        let mut ln_p = -mu;
        let mut expected = Vec::with_capacity(hi + 1);
        for kk in 0..=hi {
            if kk > 0 {
                ln_p += mu.ln() - (kk as f64).ln();
            }
            expected.push(n as f64 * ln_p.exp());
        }
        let head: f64 = expected[..hi].iter().sum();
        expected[hi] = (n as f64 - head).max(0.0);
        let (chi2, dof) = pooled_chi2(&expected, &observed);
        let p = chi2_p_value(chi2, dof);
        eprintln!("Poisson χ² μ = {mu}: χ² = {chi2:.1}, {dof} dof, p = {p:.3}");
        assert!(p >= alpha, "μ = {mu}: p = {p}");
    }
}

/// Pearson's χ² over cells in order, adjacent cells pooled until each expects ≥ 5; a short
/// remainder joins the last pooled cell. Returns (χ², cells − 1).
fn pooled_chi2(expected: &[f64], observed: &[u64]) -> (f64, usize) {
    let mut cells: Vec<(f64, f64)> = Vec::new();
    let (mut e, mut o) = (0.0, 0.0);
    for (&ei, &oi) in expected.iter().zip(observed) {
        e += ei;
        o += oi as f64;
        if e >= 5.0 {
            cells.push((e, o));
            (e, o) = (0.0, 0.0);
        }
    }
    if let Some(last) = cells.last_mut() {
        last.0 += e;
        last.1 += o;
    }
    let chi2 = cells.iter().map(|&(e, o)| (o - e).powi(2) / e).sum();
    (chi2, cells.len().saturating_sub(1))
}
