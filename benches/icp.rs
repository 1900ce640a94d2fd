//! ICP of 12 Border Identifier Points against a 300 × 200 mm pane's border (criterion).
//!
//! The border is a rounded rectangle (20 mm corners) sampled every 2 mm (484 segments), the
//! BIPs are exact border points under a known pose and ICP starts 5 mm / 2° away, as in the
//! unit tests of `localise::icp`. For scale: the paper's whole pose estimation took 23 ms
//! (Adrian & Pham, Table 2).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glassscan::geometry::border::{BorderCurve, BorderVertex};
use glassscan::geometry::pose::pose_from_mm_deg;
use glassscan::localise::icp::{register, register_on_grid, IcpSettings};
use glassscan::localise::nearest::SegmentGrid;
use nalgebra::{Point3, Vector3};
use std::f64::consts::FRAC_PI_2;

/// A flat rounded rectangle at z = 4 mm, counter-clockwise seen from above.
fn pane(width: f64, height: f64, radius: f64, step: f64) -> BorderCurve {
    let (hx, hy) = (width / 2.0 - radius, height / 2.0 - radius);
    let corners = [(hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)];
    let arc_n = (FRAC_PI_2 * radius / step).ceil() as usize;
    let mut xy = Vec::new();
    for k in 0..4 {
        let (cx, cy) = corners[k];
        let (px, py) = corners[(k + 3) % 4];
        let a0 = -FRAC_PI_2 + k as f64 * FRAC_PI_2;
        let (sx, sy) = (px + radius * a0.cos(), py + radius * a0.sin());
        let (ex, ey) = (cx + radius * a0.cos(), cy + radius * a0.sin());
        let side_n = (((ex - sx).hypot(ey - sy)) / step).ceil() as usize;
        for i in 0..side_n {
            let t = i as f64 / side_n as f64;
            xy.push((sx + (ex - sx) * t, sy + (ey - sy) * t));
        }
        for i in 0..arc_n {
            let a = a0 + FRAC_PI_2 * i as f64 / arc_n as f64;
            xy.push((cx + radius * a.cos(), cy + radius * a.sin()));
        }
    }
    let n = xy.len();
    let vertices = (0..n)
        .map(|i| {
            let (x, y) = xy[i];
            let (xp, yp) = xy[(i + n - 1) % n];
            let (xn, yn) = xy[(i + 1) % n];
            let tangent = Vector3::new(xn - xp, yn - yp, 0.0).normalize();
            BorderVertex {
                position: Point3::new(x, y, 0.004),
                tangent,
                surface_normal: Vector3::z(),
                outward: tangent.cross(&Vector3::z()),
            }
        })
        .collect();
    BorderCurve { vertices }
}

fn bench_icp(c: &mut Criterion) {
    let model = pane(0.3, 0.2, 0.02, 0.002);
    let truth = pose_from_mm_deg([450.0, -120.0, 2.0], [0.5, -0.3, 30.0]);
    let nominal = truth * pose_from_mm_deg([3.0, -4.0, 0.0], [0.3, -0.2, 2.0]);
    let len = model.length();
    let bips: Vec<Point3<f64>> = (0..12)
        .map(|k| {
            truth
                * model
                    .at_arc_length(len * (0.013 + k as f64 / 12.0))
                    .position
        })
        .collect();
    let settings = IcpSettings::robust();
    let mut group = c.benchmark_group("icp");
    group.throughput(Throughput::Elements(bips.len() as u64));
    group.bench_function("register_12_bips_484_segments", |b| {
        b.iter(|| register(&model, &bips, &nominal, &settings).expect("valid input"))
    });
    // Many registrations against one model (a sweep, a Monte Carlo study) build its grid once.
    let grid = SegmentGrid::new(&model);
    group.bench_function("segment_grid_build_484_segments", |b| {
        b.iter(|| SegmentGrid::new(&model))
    });
    group.bench_function("register_12_bips_484_segments_grid_built", |b| {
        b.iter(|| register_on_grid(&model, &grid, &bips, &nominal, &settings).expect("valid input"))
    });
    group.finish();
}

// Without plots: they need system fonts (benches/README.md).
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench_icp
}
criterion_main!(benches);
