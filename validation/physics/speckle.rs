//! Speckle: line-centre jitter on a rough target against the Dorsch–Häusler–Herrmann limit, and
//! the contrast of speckle integrated over a pixel against Goodman's.

use glassscan::sampler::PoseSampler;
use glassscan::sensor::image::Image;
use glassscan::sensor::preset::scancontrol_2600_100;
use glassscan::sensor::speckle::{speckle_image, SpeckleSettings};
use glassscan::sensor::SensorHead;

use crate::common::{facing_plate, fit_line, simulate, valid_points, world_of_boxes};

/// Standard deviation (mm) of the profile's z residuals about a fitted line, |x| < 30 mm.
fn z_jitter_mm(f_number: f64, exposure_s: f64, seed: u64) -> (f64, f64) {
    let mut world = world_of_boxes(&[facing_plate(257.5, 0.0)]);
    world.sensor.camera.f_number = f_number;
    world.sensor.imager.exposure_s = exposure_s;
    world.sensor.speckle = Some(SpeckleSettings {
        contrast: 1.0,
        oversampling: 8,
    });
    let head = SensorHead::new(&world.sensor).unwrap();
    let r = simulate(&world, 1 << 21, seed);
    let pts: Vec<(f64, f64)> = valid_points(&r)
        .into_iter()
        .filter(|p| p.0.abs() < 30.0)
        .collect();
    let (_, _, rms) = fit_line(&pts);
    // Dorsch, Häusler & Herrmann, Appl. Opt. 33(7):1306 (1994): δz = C·λ/(2π·sin u_obs·sin θ)
    // with u_obs the observation aperture's half-angle and θ the triangulation angle at the
    // target point (docs/parameters.md §5).
    let c = head.camera.center() * 1e3; // mm
    let l = (c - nalgebra::Vector3::new(0.0, 0.0, 257.5)).norm();
    let sin_u = 0.5 * head.camera.spec().aperture_diameter_m() * 1e3 / l;
    let sin_theta = c.y / l;
    let dorsch =
        world.sensor.laser.wavelength_m * 1e3 / (2.0 * std::f64::consts::PI * sin_u * sin_theta);
    (rms, dorsch)
}

#[test]
fn speckle_jitter_follows_the_dorsch_limit_for_two_apertures() {
    // Exposures keep the mean line near 250 DN so that speckle peaks rarely clip at 1023.
    for (f_number, exposure_s) in [(2.8, 0.005e-3), (8.0, 0.041e-3)] {
        let (jitter, dorsch) = z_jitter_mm(f_number, exposure_s, 71);
        eprintln!(
            "f/{f_number}: speckle z jitter {:.1} µm, Dorsch limit {:.1} µm (ratio {:.2})",
            jitter * 1e3,
            dorsch * 1e3,
            jitter / dorsch
        );
        assert!(
            (jitter / dorsch - 1.0).abs() < 0.3,
            "f/{f_number}: {jitter} vs {dorsch}"
        );
    }
}

/// J₁(v) by Bessel's integral J₁(v) = (1/π)∫₀^π cos(τ − v·sin τ) dτ (Abramowitz & Stegun
/// 9.1.21), the midpoint rule on a smooth periodic integrand: spectrally accurate; 64 points
/// give the contrast below to 4 digits for the v < 20 a pixel spans. Written apart from
/// `sensor::diffraction`'s series on purpose.
fn bessel_j1(v: f64) -> f64 {
    let n = 64;
    (0..n)
        .map(|k| {
            let t = std::f64::consts::PI * (k as f64 + 0.5) / n as f64;
            (t - v * t.sin()).cos()
        })
        .sum::<f64>()
        / n as f64
}

/// The contrast of fully developed speckle integrated over an L × L pixel: C² = 1/M with
/// 1/M = (1/L⁴)∬(L − |x|)(L − |y|)·|μ(x, y)|² dx dy over [−L, L]², and for a circular pupil
/// |μ|² = (2·J₁(v)/v)², v = π·r/(λ·N_w) (Goodman, *Speckle Phenomena in Optics*, 2007, ch. 4:
/// speckle integrated over a finite area, and the intensity correlation of an image-plane
/// speckle pattern). Midpoint rule on [0, L]² by symmetry; 400² cells give 4 digits.
fn integrated_contrast(pixel_m: f64, lambda_n_m: f64) -> f64 {
    let m = 400;
    let d = pixel_m / m as f64;
    let mut sum = 0.0;
    for i in 0..m {
        let x = (i as f64 + 0.5) * d;
        for j in 0..m {
            let y = (j as f64 + 0.5) * d;
            let v = std::f64::consts::PI * x.hypot(y) / lambda_n_m;
            let mu = 2.0 * bessel_j1(v) / v;
            sum += (pixel_m - x) * (pixel_m - y) * mu * mu;
        }
    }
    (4.0 * sum * d * d / pixel_m.powi(4)).sqrt()
}

/// Contrast (σ/mean) of the pixels of fully developed speckle (C = 1) on a uniform patch, on a
/// sub-grid of `oversampling` per pixel and axis, over 16 phase draws.
fn pixel_contrast(head: &SensorHead, oversampling: usize) -> f64 {
    let psf = head.lens_psf(oversampling);
    let (w, h) = (96, 96);
    let mut patch = Image::new(w, h);
    for y in 8..88 {
        patch.data[y * w + 8..y * w + 88].fill(1.0);
    }
    let (mut s1, mut s2, mut n) = (0.0, 0.0, 0.0);
    for draw in 0..16 {
        let out = speckle_image(&patch, &psf, 1.0, &PoseSampler::new(77, draw));
        // Pixels clear of the patch's blurred border.
        for y in 16..80 {
            for x in 16..80 {
                let v = out.get(x, y);
                (s1, s2, n) = (s1 + v, s2 + v * v, n + 1.0);
            }
        }
    }
    let mean = s1 / n;
    (s2 / n - mean * mean).sqrt() / mean
}

#[test]
fn pixel_integrated_speckle_contrast_converges_to_goodmans_and_the_shipped_grid_is_within_12_percent(
) {
    // The shipped head at mid-range: N_w 2.97, λ·N_w 1.96 µm (the field's Nyquist spacing),
    // 9.4 µm pixels; Goodman's contrast for them is 0.2087.
    let head = SensorHead::new(&scancontrol_2600_100()).unwrap();
    let cfg = &head.config;
    let lambda_n = cfg.laser.wavelength_m * head.lens_f_number();
    let goodman = integrated_contrast(head.camera.spec().pixel_pitch_m, lambda_n);
    let shipped = cfg.speckle.expect("the preset has speckle on").oversampling;
    let (at_shipped, at_16) = (pixel_contrast(&head, shipped), pixel_contrast(&head, 16));
    eprintln!(
        "Goodman {goodman:.4}; model {at_shipped:.4} at {shipped}× ({:+.1} %), {at_16:.4} at 16× ({:+.1} %)",
        100.0 * (at_shipped / goodman - 1.0),
        100.0 * (at_16 / goodman - 1.0)
    );
    // Measured 2026-12-07: 0.1872 at 8× (−10.3 %), 0.2069 at 16× (−0.9 %); the statistical
    // error of a contrast from 16 × 4096 pixels is ~0.3 %. The model converges to the analytic
    // value as the grid is refined; the shipped grid's deficit is a stated bias
    // (ARCHITECTURE.md, image sensor: the lens stage).
    assert!(
        (at_16 / goodman - 1.0).abs() < 0.02,
        "16×: {at_16} against {goodman}"
    );
    assert!(
        at_shipped < at_16 && at_shipped / goodman > 0.88,
        "{shipped}×: {at_shipped} against {goodman}"
    );
}
