//! Full profiles (criterion): transport + exposure + extraction of the first scan pose with
//! the CLI's default photon count, on `scenes/flat_opaque.toml` (opaque) and on
//! `scenes/flat_panel.toml` scanned at 45° (glass: Fresnel splits, refraction, connections
//! through the pane). `converged_profile`: the issue-11 targets, the first pose of
//! `scenes/edge_study_bare.toml` and of `scenes/car_side_window.toml` at 45°, at the converged
//! default count (`transport::DEFAULT_PHOTONS`, 2¹⁸ with the photons focused on the edge), at
//! 2²⁰ (the default before the focus) and with the adaptive count (`scan::adaptive`, as
//! `scan --photons auto`).

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glassscan::scan::adaptive::StopRules;
use glassscan::scan::poses::plan_border_scan;
use glassscan::scan::simulate::simulate_pose;
use glassscan::scene;
use glassscan::sensor::SensorHead;
use glassscan::transport::{TraceScene, TraceSettings, DEFAULT_PHOTONS};

/// The first scan pose of a shipped scene, optionally at another scan angle.
fn first_pose(
    name: &str,
    scan_angle_deg: Option<f64>,
) -> (TraceScene, SensorHead, glassscan::scan::poses::ScanPose) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let world = scene::load(&path).expect("shipped scenes load");
    let head = SensorHead::new(&world.sensor).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let target = world.target.as_ref().unwrap();
    let border = target
        .border
        .transformed(&world.objects[target.object].pose);
    let mut scan = world.scan;
    if let Some(a) = scan_angle_deg {
        scan.scan_angle_rad = a.to_radians();
    }
    let pose = plan_border_scan(&border, &scan, &world.mount).remove(0);
    (trace, head, pose)
}

fn bench(c: &mut Criterion) {
    let settings = TraceSettings {
        photons: 1 << 20,
        adaptive: false,
        max_depth: 64,
        seed: 1,
    };
    let mut g = c.benchmark_group("profile");
    g.sample_size(10);
    g.throughput(Throughput::Elements(settings.photons));
    for (label, scene_file, angle) in [
        ("flat_opaque_pose0_1M_photons", "flat_opaque.toml", None),
        (
            "flat_panel_45deg_pose0_1M_photons",
            "flat_panel.toml",
            Some(45.0),
        ),
    ] {
        let (trace, head, pose) = first_pose(scene_file, angle);
        g.bench_function(label, |b| {
            b.iter(|| {
                simulate_pose(&trace, &head, &pose, &settings, StopRules::EDGE_LINE)
                    .profile
                    .points
                    .len()
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("converged_profile");
    g.sample_size(10);
    for scene_name in ["edge_study_bare", "car_side_window"] {
        let (trace, head, pose) = first_pose(&format!("{scene_name}.toml"), Some(45.0));
        for (label, photons, adaptive) in [
            ("default_photons", DEFAULT_PHOTONS, false),
            ("fixed_1M_photons", 1 << 20, false),
            ("auto", DEFAULT_PHOTONS, true),
        ] {
            let settings = TraceSettings {
                photons,
                adaptive,
                ..settings
            };
            g.bench_function(format!("{scene_name}_45deg_pose0/{label}"), |b| {
                b.iter(|| {
                    simulate_pose(&trace, &head, &pose, &settings, StopRules::EDGE_LINE)
                        .stats
                        .photons
                })
            });
        }
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
