//! The BVH's ray queries against brute force on three scenes: a random triangle cloud, a
//! 20,000-triangle wavy height field (the benchmark field's smaller sibling) and the glass panel
//! scene `edge_study_bare.toml` as the light tracer builds it.

use std::path::Path;

use glassscan::geometry::accel::{SceneAccel, SceneTriangle};
use glassscan::geometry::mesh::SurfacePart;
use glassscan::sampler::PoseSampler;
use glassscan::scene;
use glassscan::transport::TraceScene;
use nalgebra::{Point3, Vector3};

fn triangle(vertices: [Point3<f64>; 3]) -> SceneTriangle {
    SceneTriangle {
        vertices,
        normals: None,
        object: 0,
        material: 0,
        part: SurfacePart::Solid,
    }
}

/// `n` random triangles of up to 60 mm in a 1 m cube.
fn cloud(n: u64) -> Vec<SceneTriangle> {
    let s = PoseSampler::new(7, 1);
    (0..n)
        .map(|i| {
            let c = [0, 1, 2].map(|k| s.uniform(i, k) - 0.5);
            let v = |j: u32| {
                Point3::new(
                    c[0] + 0.06 * (s.uniform(i, 3 + 3 * j) - 0.5),
                    c[1] + 0.06 * (s.uniform(i, 4 + 3 * j) - 0.5),
                    c[2] + 0.06 * (s.uniform(i, 5 + 3 * j) - 0.5),
                )
            };
            triangle([v(0), v(1), v(2)])
        })
        .collect()
}

/// The benchmark's wavy height field over [−0.5, 0.5]² m with 2·n² triangles.
fn height_field(n: usize) -> Vec<SceneTriangle> {
    let h = |i: usize, j: usize| {
        let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
        Point3::new(x, y, 0.002 * (40.0 * x).sin() * (30.0 * y).cos())
    };
    let mut tris = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (h(i, j), h(i + 1, j), h(i + 1, j + 1), h(i, j + 1));
            tris.push(triangle([a, b, c]));
            tris.push(triangle([a, c, d]));
        }
    }
    tris
}

/// Bounding box (m) of a scene's triangles.
fn bounds(accel: &SceneAccel) -> (Point3<f64>, Point3<f64>) {
    let mut lo = Point3::from([f64::INFINITY; 3]);
    let mut hi = Point3::from([f64::NEG_INFINITY; 3]);
    for i in 0..accel.triangle_count() as u32 {
        for v in &accel.triangle(i).vertices {
            lo = lo.inf(v);
            hi = hi.sup(v);
        }
    }
    (lo, hi)
}

/// Rays from random points of the scene's box (grown by 10 %) towards random points of it, and
/// rays from random points *on* random triangles (the light tracer's secondary rays start there)
/// in random directions; for each, the BVH's closest hit equals brute force (the same triangle,
/// or one at the same f32 distance; the same distance to f32 rounding) and occlusion agrees.
/// Returns the number of hits compared.
fn check_against_brute_force(accel: &SceneAccel, rays: u64, seed: u64) -> usize {
    let (lo, hi) = bounds(accel);
    let size = hi - lo;
    let s = PoseSampler::new(seed, 0);
    let in_box = |i: u64, k: u32| {
        Point3::new(
            lo.x + size.x * (1.2 * s.uniform(i, k) - 0.1),
            lo.y + size.y * (1.2 * s.uniform(i, k + 1) - 0.1),
            lo.z + size.z * (1.2 * s.uniform(i, k + 2) - 0.1),
        )
    };
    let mut hits = 0;
    for i in 0..rays {
        let (origin, dir) = if i % 2 == 0 {
            let o = in_box(i, 0);
            let Some(d) = (in_box(i, 3) - o).try_normalize(1e-12) else {
                continue;
            };
            (o, d)
        } else {
            let tri = (s.uniform(i, 0) * accel.triangle_count() as f64) as u32;
            let [a, b, c] = accel.triangle(tri).vertices;
            let (u, v) = (s.uniform(i, 1), s.uniform(i, 2));
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let o = a + (b - a) * u + (c - a) * v;
            let z = 2.0 * s.uniform(i, 3) - 1.0;
            let phi = std::f64::consts::TAU * s.uniform(i, 4);
            let r = (1.0 - z * z).sqrt();
            (o, Vector3::new(r * phi.cos(), r * phi.sin(), z))
        };
        let t_max = 2.0 * size.norm();
        let fast = accel.closest_hit(&origin, &dir, 0.0, t_max);
        let slow = accel.closest_hit_brute_force(&origin, &dir, 0.0, t_max);
        match (&fast, &slow) {
            (Some(f), Some(s)) => {
                hits += 1;
                if f.triangle != s.triangle {
                    // Only a tie at the same f32 distance may choose another triangle.
                    let f32_t = |t: f64| (t * 1e3) as f32;
                    assert_eq!(
                        f32_t(f.t),
                        f32_t(s.t),
                        "ray {i}: triangle {} at {} m vs brute force {} at {} m",
                        f.triangle,
                        f.t,
                        s.triangle,
                        s.t
                    );
                }
                let tol = 4.0 * f32::EPSILON as f64 * f.t.max(1e-3);
                assert!(
                    (f.t - s.t).abs() <= tol,
                    "ray {i}: t {} vs brute force {}",
                    f.t,
                    s.t
                );
            }
            (None, None) => {}
            _ => panic!("ray {i}: BVH {fast:?} vs brute force {slow:?}"),
        }
        assert_eq!(
            accel.occluded(&origin, &dir, 0.0, t_max),
            slow.is_some(),
            "ray {i}: occlusion"
        );
    }
    hits
}

#[test]
fn bvh_closest_hit_and_occlusion_equal_brute_force_on_a_random_cloud() {
    let accel = SceneAccel::build(cloud(3000));
    let hits = check_against_brute_force(&accel, 4000, 11);
    assert!(hits > 1500, "only {hits} hits");
}

#[test]
fn bvh_closest_hit_and_occlusion_equal_brute_force_on_a_height_field() {
    let accel = SceneAccel::build(height_field(100));
    let hits = check_against_brute_force(&accel, 3000, 12);
    assert!(hits > 1000, "only {hits} hits");
}

#[test]
fn bvh_closest_hit_and_occlusion_equal_brute_force_on_the_edge_study_panel() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/edge_study_bare.toml");
    let world = scene::load(&path).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let hits = check_against_brute_force(&trace.accel, 2000, 13);
    assert!(hits > 800, "only {hits} hits");
}
