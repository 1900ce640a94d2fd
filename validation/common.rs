//! Builders for small analytic worlds (boxes in front of a sensor at a known pose).

use std::path::PathBuf;

use glassscan::geometry::cuboid::cuboid;
use glassscan::geometry::pose::{pose_from_mm_deg, Pose};
use glassscan::scan::adaptive::StopRules;
use glassscan::scan::poses::ScanPose;
use glassscan::scan::simulate::{simulate_pose, PoseResult};
use glassscan::scan::ScanConfig;
use glassscan::scene::world::{Material, NamedMaterial, Object, ObjectLabel, World};
use glassscan::sensor::preset::scancontrol_2600_100;
use glassscan::sensor::SensorHead;
use glassscan::transport::{TraceScene, TraceSettings};
use nalgebra::Point3;

/// A box of `size_mm` whose pose is given in mm and degrees, with Lambertian `albedo`.
pub struct BoxSpec {
    pub size_mm: [f64; 3],
    pub translation_mm: [f64; 3],
    pub rotation_deg: [f64; 3],
    pub albedo: f64,
}

/// A plate facing the sensor (which sits at the base-frame origin looking along +z), whose
/// near face is the plane z = `z_mm`, rotated by `tilt_deg` about the y axis through (0, 0, z).
pub fn facing_plate(z_mm: f64, tilt_deg: f64) -> BoxSpec {
    // The box is 10 mm thick; its centre sits 5 mm behind the face along the tilted normal.
    let t = tilt_deg.to_radians();
    BoxSpec {
        size_mm: [400.0, 400.0, 10.0],
        translation_mm: [5.0 * t.sin(), 0.0, z_mm + 5.0 * t.cos()],
        rotation_deg: [0.0, tilt_deg, 0.0],
        albedo: 0.8,
    }
}

/// A world of boxes seen by the default scanCONTROL 2600-100 head, with the exposure set so
/// that a white target at mid-range stays below full scale, noise and speckle off.
pub fn world_of_boxes(boxes: &[BoxSpec]) -> World {
    let mut sensor = scancontrol_2600_100();
    sensor.imager.exposure_s = 0.02e-3;
    // Analytic checks compare with exact geometry: no sensor noise, no speckle (the tests of
    // those switch them on themselves).
    sensor.imager.noise = false;
    sensor.speckle = None;
    World {
        source: PathBuf::from("<analytic test world>"),
        objects: boxes
            .iter()
            .enumerate()
            .map(|(i, b)| Object {
                name: format!("box{i}"),
                mesh: cuboid(b.size_mm.map(|v| v * 1e-3)),
                pose: pose_from_mm_deg(b.translation_mm, b.rotation_deg),
                material: i,
                label: ObjectLabel::Other,
            })
            .collect(),
        materials: boxes
            .iter()
            .enumerate()
            .map(|(i, b)| NamedMaterial {
                name: format!("m{i}"),
                material: Material::Lambertian { albedo: b.albedo },
            })
            .collect(),
        target: None,
        sensor,
        mount: Pose::identity(),
        scan: ScanConfig {
            scan_angle_rad: std::f64::consts::FRAC_PI_2,
            poses: 1,
            standoff_m: 0.2575,
            start_fraction: 0.0,
        },
        material_sources: Vec::new(),
        warnings: Vec::new(),
    }
}

/// The sensor at the base-frame origin (S = B).
pub fn identity_pose() -> ScanPose {
    ScanPose {
        index: 0,
        sensor: Pose::identity(),
        flange: Pose::identity(),
        edge_point: Point3::origin(),
        border_fraction: 0.0,
    }
}

/// Simulates `world` from the identity pose with `photons` photons.
pub fn simulate(world: &World, photons: u64, seed: u64) -> PoseResult {
    let scene = TraceScene::new(world).expect("analytic worlds are opaque");
    let head = SensorHead::new(&world.sensor).expect("preset camera is valid");
    simulate_pose(
        &scene,
        &head,
        &identity_pose(),
        &TraceSettings {
            photons,
            adaptive: false,
            max_depth: 16,
            seed,
        },
        StopRules::EDGE_LINE,
    )
}

/// Least-squares line z = a + b·x through (x, z) points; returns (a, b, rms residual).
pub fn fit_line(points: &[(f64, f64)]) -> (f64, f64, f64) {
    let n = points.len() as f64;
    let (sx, sz) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
    let (mx, mz) = (sx / n, sz / n);
    let (mut sxx, mut sxz) = (0.0, 0.0);
    for &(x, z) in points {
        sxx += (x - mx) * (x - mx);
        sxz += (x - mx) * (z - mz);
    }
    let b = sxz / sxx;
    let a = mz - b * mx;
    let rms = (points
        .iter()
        .map(|&(x, z)| (z - a - b * x).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    (a, b, rms)
}

/// Valid (x_mm, z_mm) points of a profile.
pub fn valid_points(r: &PoseResult) -> Vec<(f64, f64)> {
    r.profile
        .points
        .iter()
        .filter(|p| p.valid)
        .map(|p| (p.x_mm, p.z_mm))
        .collect()
}

/// Adds a glass box (polished on every face, no imperfections unless given) to `world`.
pub fn add_glass_box(
    world: &mut World,
    size_mm: [f64; 3],
    translation_mm: [f64; 3],
    rotation_deg: [f64; 3],
    glass: glassscan::scene::world::GlassSpec,
) {
    world.materials.push(NamedMaterial {
        name: "glass".into(),
        material: Material::Glass(glass),
    });
    world.objects.push(Object {
        name: "pane".into(),
        mesh: cuboid(size_mm.map(|v| v * 1e-3)),
        pose: pose_from_mm_deg(translation_mm, rotation_deg),
        material: world.materials.len() - 1,
        label: ObjectLabel::Other,
    });
}

/// Clear soda-lime glass with the given index and absorption, no imperfections, smooth edges.
pub fn clear_glass(ior: f64, absorption_per_m: f64) -> glassscan::scene::world::GlassSpec {
    glassscan::scene::world::GlassSpec {
        ior: Some(ior),
        cauchy: None,
        sellmeier: None,
        absorption_per_m,
        face_imperfection: 0.0,
        edge_roughness: 0.0,
    }
}

/// `simulate` on a thread pool of `threads` threads.
pub fn simulate_with_threads(world: &World, photons: u64, seed: u64, threads: usize) -> PoseResult {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(|| simulate(world, photons, seed))
}

/// Irradiance summed over ±4 rows around `row` in `column`: the whole laser line, and little
/// of the stray light that lands all over the image.
pub fn line_band(img: &glassscan::sensor::image::Image<f64>, column: usize, row: usize) -> f64 {
    (row.saturating_sub(4)..(row + 5).min(img.height))
        .map(|k| img.get(column, k))
        .sum()
}

/// A shipped scene ready to trace at `poses` border poses at `scan_angle_deg` (the scene's own
/// scan otherwise), planned on the true border as `glassscan scan` plans them.
pub struct ShippedScan {
    pub head: SensorHead,
    pub trace: TraceScene,
    pub poses: Vec<ScanPose>,
}

/// Loads `scenes/NAME` and plans its scan ([`ShippedScan`]).
pub fn shipped_scan(name: &str, scan_angle_deg: f64, poses: usize) -> ShippedScan {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    scene_scan(&path, scan_angle_deg, poses)
}

/// Loads the scene file `path` and plans its scan ([`ShippedScan`]).
pub fn scene_scan(path: &std::path::Path, scan_angle_deg: f64, poses: usize) -> ShippedScan {
    let world = glassscan::scene::load(path).unwrap_or_else(|e| panic!("{e}"));
    let mut scan = world.scan;
    scan.scan_angle_rad = scan_angle_deg.to_radians();
    scan.poses = poses;
    let border = world.true_border_in_base().expect("the scene has a target");
    ShippedScan {
        head: SensorHead::new(&world.sensor).unwrap(),
        trace: TraceScene::new(&world).unwrap(),
        poses: glassscan::scan::poses::plan_border_scan(&border, &scan, &world.mount),
    }
}
