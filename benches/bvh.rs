//! BVH build and ray throughput (criterion). Scenes are procedural and seeds fixed.
//!
//! - build: a 1M-triangle wavy height field (1 m², 708 × 708 quads);
//! - closest hit, laser fan: the scanCONTROL 2600-100 fan from 300 mm above the field;
//! - closest hit, random rays: origins and directions from a hash, aimed at the field;
//! - occlusion: the same random rays as any-hit queries.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use glassscan::geometry::accel::{SceneAccel, SceneTriangle};
use glassscan::geometry::mesh::SurfacePart;
use glassscan::sampler::PoseSampler;
use glassscan::sensor::preset::scancontrol_2600_100;
use nalgebra::{Point3, Vector3};

/// A wavy height field of 2·n² triangles over [−0.5, 0.5]² m.
fn height_field(n: usize) -> Vec<SceneTriangle> {
    let h = |i: usize, j: usize| {
        let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
        Point3::new(x, y, 0.002 * (40.0 * x).sin() * (30.0 * y).cos())
    };
    let mut tris = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (h(i, j), h(i + 1, j), h(i + 1, j + 1), h(i, j + 1));
            for vertices in [[a, b, c], [a, c, d]] {
                tris.push(SceneTriangle {
                    vertices,
                    normals: None,
                    object: 0,
                    material: 0,
                    part: SurfacePart::Solid,
                });
            }
        }
    }
    tris
}

fn random_rays(count: u64) -> Vec<(Point3<f64>, Vector3<f64>)> {
    let s = PoseSampler::new(42, 0);
    (0..count)
        .map(|i| {
            let o = Point3::new(s.uniform(i, 0) - 0.5, s.uniform(i, 1) - 0.5, 0.3);
            let target = Point3::new(s.uniform(i, 2) - 0.5, s.uniform(i, 3) - 0.5, 0.0);
            (o, (target - o).normalize())
        })
        .collect()
}

fn fan_rays(count: u64) -> Vec<(Point3<f64>, Vector3<f64>)> {
    let laser = scancontrol_2600_100().laser;
    let s = PoseSampler::new(43, 0);
    (0..count)
        .map(|i| {
            let r = laser.sample_ray([
                (i as f64 + 0.5) / count as f64,
                s.uniform(i, 1),
                s.uniform(i, 2),
                0.0,
            ]);
            // The sensor 300 mm above the field, looking down (z_S = −z_B).
            let o = Point3::new(r.origin.x, -r.origin.y, 0.3 - r.origin.z);
            let d = Vector3::new(r.direction.x, -r.direction.y, -r.direction.z);
            (o, d)
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let tris = height_field(708);
    let mut g = c.benchmark_group("bvh");
    g.sample_size(10);
    g.throughput(Throughput::Elements(tris.len() as u64));
    g.bench_function("build_1M_triangles", |b| {
        b.iter_batched(|| tris.clone(), SceneAccel::build, BatchSize::LargeInput)
    });
    g.finish();

    let accel = SceneAccel::build(tris);
    let n = 1 << 16;
    let mut g = c.benchmark_group("rays_1M_triangles");
    g.throughput(Throughput::Elements(n));
    for (name, rays) in [
        ("closest_hit_laser_fan", fan_rays(n)),
        ("closest_hit_random", random_rays(n)),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|(o, d)| accel.closest_hit(o, d, 0.0, 10.0).is_some())
                    .count()
            })
        });
    }
    // The same rays through `SceneAccel::closest_hits` (the tracer's primary rays): the fan's in
    // bundles of 64, the random rays one at a time after the coherence check finds them apart.
    let mut hits = Vec::with_capacity(n as usize);
    for (name, rays) in [
        ("closest_hits_laser_fan_bundles", fan_rays(n)),
        ("closest_hits_random", random_rays(n)),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                accel.closest_hits(&rays, 0.0, 10.0, &mut hits);
                hits.iter().filter(|h| h.is_some()).count()
            })
        });
    }
    let rays = random_rays(n);
    g.bench_function("occlusion_random", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|(o, d)| accel.occluded(o, d, 0.0, 10.0))
                .count()
        })
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
