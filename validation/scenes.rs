//! The shipped scenes: they load, and the first runnable one triangulates to its geometry.

use std::path::Path;

use glassscan::scan::poses::plan_border_scan;
use glassscan::scan::simulate::simulate_pose;
use glassscan::scene;
use glassscan::sensor::SensorHead;
use glassscan::transport::{TraceScene, TraceSettings};
use nalgebra::Point3;

fn scene_path(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

#[test]
fn every_shipped_scene_loads() {
    for entry in std::fs::read_dir(scene_path("")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let world = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
            assert!(!world.objects.is_empty(), "{}", path.display());
        }
    }
}

#[test]
fn flat_opaque_profile_matches_the_analytic_plate_and_table() {
    // The plate's top face is the plane z = 4 mm of the base frame and the table top z = 0
    // (scenes/flat_opaque.toml). Every profile point, taken back to the base frame, must lie on
    // one of them — or on the plate's vertical edge — and the RMS distance of the points on
    // the two planes must be below 20 µm (sensor noise and speckle off).
    let mut world = scene::load(&scene_path("flat_opaque.toml")).unwrap();
    world.sensor.imager.noise = false;
    world.sensor.speckle = None;
    let head = SensorHead::new(&world.sensor).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let target = world.target.as_ref().unwrap();
    let plate_pose = world.objects[target.object].pose;
    let border = target.border.transformed(&plate_pose);
    let poses = plan_border_scan(&border, &world.scan, &world.mount);
    let settings = TraceSettings {
        photons: 1 << 21,
        max_depth: 16,
        seed: 5,
    };
    let (mut top, mut table) = (Vec::new(), Vec::new());
    for pose in &poses {
        let r = simulate_pose(&trace, &head, pose, &settings);
        for p in r.profile.points.iter().filter(|p| p.valid) {
            let b = pose.sensor * Point3::new(p.x_mm * 1e-3, 0.0, p.z_mm * 1e-3);
            // Classify by height, away from the edge (1 mm either side) where the line bends.
            let z_mm = b.z * 1e3;
            if border_distance_mm(&border, &b) < 1.0 {
                continue;
            }
            if (z_mm - 4.0).abs() < 1.0 {
                top.push(z_mm - 4.0);
            } else if z_mm.abs() < 1.0 {
                table.push(z_mm);
            } else {
                panic!(
                    "pose {}: point at z = {z_mm:.3} mm is on neither plane",
                    pose.index
                );
            }
        }
    }
    let rms = |v: &[f64]| (v.iter().map(|d| d * d).sum::<f64>() / v.len() as f64).sqrt();
    eprintln!(
        "flat_opaque: {} plate points rms {:.1} µm, {} table points rms {:.1} µm",
        top.len(),
        rms(&top) * 1e3,
        table.len(),
        rms(&table) * 1e3
    );
    assert!(
        top.len() > 200 && table.len() > 200,
        "{} / {}",
        top.len(),
        table.len()
    );
    assert!(rms(&top) < 0.020 && rms(&table) < 0.020);
}

/// Horizontal distance (mm) from `p` to the border polyline (its segments, in x–y).
fn border_distance_mm(border: &glassscan::geometry::border::BorderCurve, p: &Point3<f64>) -> f64 {
    let v = &border.vertices;
    (0..v.len())
        .map(|i| {
            let a = v[i].position.xy();
            let b = v[(i + 1) % v.len()].position.xy();
            let ab = b - a;
            let t = ((p.xy() - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
            (p.xy() - (a + ab * t)).norm()
        })
        .fold(f64::INFINITY, f64::min)
        * 1e3
}
