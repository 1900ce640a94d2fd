//! Cost of the rough edge's BSDF per photon vertex (criterion): sampling the continuation and
//! evaluating the camera connection, single scattering (`microfacet::RoughDielectric`, the
//! model the tracer used before) against the multiple-scattering random walk
//! (`microfacet_walk::MultipleScatteringDielectric`, what it uses now).
//!
//! 4096 incident directions spread over the sphere (both sides of the edge), α = 0.3 and 1.0,
//! η = 1.5208; the evaluation is towards a fixed camera-like direction 30° from the normal in
//! air. One thread. Throughput is per direction.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use glassscan::optics::microfacet::RoughDielectric;
use glassscan::optics::microfacet_walk::MultipleScatteringDielectric;
use glassscan::optics::polarization::Stokes;
use glassscan::optics::uniform_stream::{KeyedStream, UniformSource};
use nalgebra::Vector3;

const ETA: f64 = 1.5208;
const DIRECTIONS: usize = 4096;

/// Directions with cos θ stratified over [−1, 1] (away from the horizon) and golden-angle φ.
fn directions() -> Vec<Vector3<f64>> {
    (0..DIRECTIONS)
        .map(|k| {
            let z = -0.98 + 1.96 * (k as f64 + 0.5) / DIRECTIONS as f64;
            let phi = k as f64 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            Vector3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

fn bench_rough_edge(c: &mut Criterion) {
    let wos = directions();
    let camera = Vector3::new(0.5, 0.0, 0.75f64.sqrt());
    let mut group = c.benchmark_group("rough_edge");
    group.throughput(Throughput::Elements(DIRECTIONS as u64));
    for alpha in [0.3, 1.0] {
        let single = RoughDielectric::new(alpha, ETA);
        let multiple = MultipleScatteringDielectric::new(alpha, ETA);
        group.bench_function(format!("sample_single_alpha_{alpha}"), |b| {
            let mut s = KeyedStream::new(&[1]);
            b.iter(|| {
                for wo in &wos {
                    let u = [s.next_uniform(), s.next_uniform(), s.next_uniform()];
                    black_box(single.sample(wo, u[0], [u[1], u[2]]));
                }
            })
        });
        group.bench_function(format!("sample_walk_polarised_alpha_{alpha}"), |b| {
            let mut s = KeyedStream::new(&[2]);
            b.iter(|| {
                for wo in &wos {
                    let mut stokes = Stokes::linear(&-wo, &Vector3::new(0.0, 1.0, 0.3));
                    black_box(multiple.sample(wo, &mut s, Some(&mut stokes)));
                }
            })
        });
        group.bench_function(format!("eval_single_alpha_{alpha}"), |b| {
            b.iter(|| {
                for wo in &wos {
                    black_box(single.f_adjoint(wo, &camera) * camera.z);
                }
            })
        });
        group.bench_function(format!("eval_walk_alpha_{alpha}"), |b| {
            let mut s = KeyedStream::new(&[3]);
            b.iter(|| {
                for wo in &wos {
                    black_box(multiple.f_adjoint_cos(wo, &camera, &mut s));
                }
            })
        });
    }
    group.finish();
}

// Without plots: they need system fonts (benches/README.md).
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench_rough_edge
}
criterion_main!(benches);
