//! Coherent imaging (criterion): the FFT speckle imager against the direct reference on the
//! default head (640 × 832 px, 9.4 µm, f/2.8 → N_w at mid-range, 8× sub-grid, contrast 1),
//! and the incoherent PSF blur (the speckle-off path), on
//!
//! - `line`: a synthetic laser line across all 640 columns (Gaussian, σ 0.8 px, its row
//!   wandering by ±40 px along the line), no stray light;
//! - `edge_study_bare_pose0`: the rough-surface irradiance of `scenes/edge_study_bare.toml`'s
//!   first pose, traced once with 2¹⁸ photons (seed 1) before timing.
//!
//! and the whole lens stage of a pose (`scan::simulate::apply_lens_psf`: speckle or blur,
//! glints, class shares, on every class layer) on the traced pose, speckle on and off.
//!
//! Fixed seeds; throughput in image pixels per second.

#[path = "support/traced_pose.rs"]
mod traced_pose;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use glassscan::sampler::PoseSampler;
use glassscan::scan::simulate::apply_lens_psf;
use glassscan::sensor::image::Image;
use glassscan::sensor::path_class::PathClass;
use glassscan::sensor::SensorHead;
use glassscan::transport::Irradiance;
use traced_pose::traced_pose;

/// The rough-surface light of `irradiance`: every class but glints.
fn rough_light(irradiance: &Irradiance) -> Image<f64> {
    let mut rough = irradiance.total.clone();
    let glint = &irradiance.by_class[PathClass::Glint.index()];
    for (r, g) in rough.data.iter_mut().zip(&glint.data) {
        *r = (*r - g).max(0.0);
    }
    rough
}

/// A laser line across every column of a `w` × `h` image.
fn synthetic_line(w: usize, h: usize) -> Image<f64> {
    let mut img = Image::new(w, h);
    for x in 0..w {
        let centre = 0.5 * h as f64 + 40.0 * (x as f64 / w as f64 * 6.0).sin();
        for y in 0..h {
            let d = (y as f64 + 0.5 - centre) / 0.8;
            let v = 0.05 * (-0.5 * d * d).exp();
            if v > 1e-12 {
                img.data[y * w + x] = v;
            }
        }
    }
    img
}

fn bench(c: &mut Criterion) {
    let (head, pose, irradiance) = traced_pose("edge_study_bare.toml", 1 << 18);
    let traced = rough_light(&irradiance);
    let cam = &head.camera;
    let speckle = head.config.speckle.expect("the preset has speckle on");
    let psf = head.lens_psf(speckle.oversampling);
    let spec = cam.spec();
    let line = synthetic_line(spec.columns, spec.rows);
    let sampler = PoseSampler::new(1, 0x5bec_1e00_0000_0000);
    let mut g = c.benchmark_group("speckle");
    g.sample_size(10);
    g.throughput(Throughput::Elements((spec.columns * spec.rows) as u64));
    for (label, image) in [("line", &line), ("edge_study_bare_pose0", &traced)] {
        g.bench_function(format!("{label}/fft"), |b| {
            b.iter(|| {
                glassscan::sensor::speckle::speckle_image(image, &psf, speckle.contrast, &sampler)
            })
        });
        g.bench_function(format!("{label}/direct"), |b| {
            b.iter(|| {
                glassscan::sensor::speckle::speckle_image_direct(
                    image,
                    &psf,
                    speckle.contrast,
                    &sampler,
                )
            })
        });
        g.bench_function(format!("{label}/incoherent_blur"), |b| {
            b.iter(|| psf.blur(image))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("lens_stage");
    g.sample_size(20);
    g.throughput(Throughput::Elements((spec.columns * spec.rows) as u64));
    let mut config = head.config.clone();
    config.speckle = None;
    let head_off = SensorHead::new(&config).expect("preset camera");
    for (label, h) in [("speckle_on", &head), ("speckle_off", &head_off)] {
        g.bench_function(format!("edge_study_bare_pose0/{label}"), |b| {
            b.iter_batched(
                || irradiance.clone(),
                |mut irr| {
                    apply_lens_psf(&mut irr, h, &pose, 1);
                    irr
                },
                BatchSize::LargeInput,
            )
        });
    }
    g.finish();
}

// Without plots: they need system fonts (benches/README.md).
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
