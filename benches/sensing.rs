//! The image sensor and the firmware (criterion) on the default head (640 × 832 px): one
//! pose's light after the lens stage (`scenes/edge_study_bare.toml`'s first pose, traced once
//! with 2¹⁸ photons, seed 1, before timing) exposed with EMVA 1288 noise (`expose`), and
//! exposed then reduced to a profile by the firmware (`sense`, what a study repeats per
//! exposure); and the sensor unit's fixed pattern, made once per sensor head
//! (`sensor_head_new`, what a randomised dataset repeats per sample).
//!
//! Fixed seeds; throughput in image pixels per second.

#[path = "support/traced_pose.rs"]
mod traced_pose;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glassscan::scan::simulate::{apply_lens_psf, sense};
use glassscan::sensor::emva::frame_sampler;
use glassscan::sensor::SensorHead;
use glassscan::transport::TraceSettings;
use traced_pose::traced_pose;

fn bench(c: &mut Criterion) {
    let (head, pose, mut irradiance) = traced_pose("edge_study_bare.toml", 1 << 18);
    apply_lens_psf(&mut irradiance, &head, &pose, 1);
    let settings = TraceSettings {
        photons: 1 << 18,
        adaptive: false,
        max_depth: 64,
        seed: 1,
    };
    let cfg = &head.config;
    let spec = head.camera.spec();
    let mut g = c.benchmark_group("sensing");
    g.sample_size(20);
    g.throughput(Throughput::Elements((spec.columns * spec.rows) as u64));
    g.bench_function("edge_study_bare_pose0/expose", |b| {
        let sampler = frame_sampler(settings.seed, pose.index as u64);
        b.iter(|| {
            cfg.imager.expose_noisy(
                &irradiance.total,
                head.camera.pixel_area(),
                cfg.laser.wavelength_m,
                &sampler,
                &head.fixed_pattern,
            )
        })
    });
    g.bench_function("edge_study_bare_pose0/sense", |b| {
        b.iter(|| sense(&irradiance, &head, &pose, &settings))
    });
    g.bench_function("sensor_head_new", |b| {
        b.iter(|| SensorHead::new(cfg).expect("preset camera"))
    });
    g.finish();
}

// Without plots: they need system fonts (benches/README.md).
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
