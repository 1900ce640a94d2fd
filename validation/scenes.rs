//! The shipped scenes: they load, and the first runnable one triangulates to its geometry.

use std::path::Path;

use glassscan::scan::adaptive::StopRules;
use glassscan::scan::poses::plan_border_scan;
use glassscan::scan::simulate::simulate_pose;
use glassscan::scene;
use glassscan::sensor::path_class::PathClass;
use glassscan::sensor::SensorHead;
use glassscan::transport::{TraceScene, TraceSettings, DEFAULT_PHOTONS};
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
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        // `randomize_X.toml` holds the domain-randomisation ranges for `X.toml`: every range
        // must parse and be accepted by that scene at both of its ends.
        if let Some(scene_name) = name.strip_prefix("randomize_") {
            let r = glassscan::dataset::randomize::Randomization::load(&path)
                .unwrap_or_else(|e| panic!("{e}"));
            let template =
                glassscan::dataset::scene_edit::SceneTemplate::load(&scene_path(scene_name))
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
            template
                .check_randomization(&r)
                .unwrap_or_else(|e| panic!("{e}"));
            continue;
        }
        let world = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(!world.objects.is_empty(), "{}", path.display());
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
        adaptive: false,
        max_depth: 16,
        seed: 5,
    };
    let (mut top, mut table) = (Vec::new(), Vec::new());
    for pose in &poses {
        let r = simulate_pose(&trace, &head, pose, &settings, StopRules::EDGE_LINE);
        for p in r.profile.points.iter().filter(|p| p.valid) {
            let b = pose.sensor * Point3::new(p.x_mm * 1e-3, 0.0, p.z_mm * 1e-3);
            // Classify by height, away from the edge (1 mm either side) where the line bends.
            let z_mm = b.z * 1e3;
            if border_distance_mm(&border, &b) < 1.0 {
                continue;
            }
            // Issue 10, part 5: the plate is the scene's target and carries no label, so its
            // returns are `target` (they used to be reported as `background`), the table's
            // `table`; every valid point has a class.
            if (z_mm - 4.0).abs() < 1.0 {
                assert_eq!(p.label, Some(PathClass::Target), "plate point {p:?}");
                top.push(z_mm - 4.0);
            } else if z_mm.abs() < 1.0 {
                assert_eq!(p.label, Some(PathClass::Table), "table point {p:?}");
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

#[test]
fn mixed_pixels_the_selection_mode_decides_between_pane_and_background() {
    // scenes/mixed_pixels.toml: the paper's Table I settings (2° from the normal, 5 ms) with the
    // background board 60 mm behind the pane, inside the measuring range. Columns hold both the
    // pane's faint face return and the board seen through the pane (paper §III-B).
    use glassscan::sensor::profile::PeakSelect;
    let mut world = scene::load(&scene_path("mixed_pixels.toml")).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let border = world.true_border_in_base().expect("the scene has a target");
    let pose = plan_border_scan(&border, &world.scan, &world.mount).remove(0);
    let settings = TraceSettings {
        photons: 1 << 19,
        adaptive: false,
        max_depth: 64,
        seed: 9,
    };
    let mut count = |mode: PeakSelect| {
        world.sensor.firmware.peak_select = mode;
        let head = SensorHead::new(&world.sensor).unwrap();
        let r = simulate_pose(&trace, &head, &pose, &settings, StopRules::EDGE_LINE);
        let n = |c: PathClass| {
            r.profile
                .points
                .iter()
                .filter(|p| p.valid && p.label == Some(c))
                .count()
        };
        let columns_with_both = {
            let mut cols = std::collections::BTreeMap::<usize, (bool, bool)>::new();
            for p in r.profile.points.iter().filter(|p| p.valid) {
                let e = cols.entry(p.column).or_default();
                e.0 |= p.label == Some(PathClass::GlassFace);
                e.1 |= p.label == Some(PathClass::ThroughGlass);
            }
            cols.values().filter(|(a, b)| *a && *b).count()
        };
        (
            n(PathClass::GlassFace),
            n(PathClass::ThroughGlass),
            columns_with_both,
        )
    };
    let (all_face, all_through, both) = count(PeakSelect::All);
    let (max_face, max_through, _) = count(PeakSelect::MaxIntensity);
    let (first_face, first_through, _) = count(PeakSelect::First);
    eprintln!(
        "mixed pixels: ALL {all_face} face + {all_through} through-glass points, {both} columns with both; \
         MAX_INTENSITY {max_face} face / {max_through} through glass; FIRST {first_face} / {first_through}"
    );
    assert!(both > 50, "only {both} columns see both returns");
    assert!(
        max_through > 2 * max_face,
        "MAX_INTENSITY should report the board through the pane"
    );
    // FIRST reports the nearer peak, the pane, wherever its faint return clears the threshold.
    assert!(
        first_face > 2 * max_face,
        "FIRST should report the pane's own return more often"
    );
}

/// The car window's convex faces return light above the threshold at the scene's 2 ms
/// exposure, so the paper's "highest point above the ground" lands on the top face or on light
/// seen through it (21–124 mm from p_e at the 3 poses), while the
/// edge-line rule climbs the chain of edge returns to the top of the seam: p_e (sensor only,
/// true pose known, 2^16 photons: 0.18, 0.11, 0.10 mm from p_e at the 3 poses; stopping at the
/// top of the vertical wall, as the rule did before it climbed, gave 0.67–0.84 mm).
#[test]
fn car_window_edge_line_bips_find_p_e_where_the_highest_point_does_not() {
    // Well inside the seam, whose top (p_e) is 1.13 mm from the top of the wall.
    const LIMIT_MM: f64 = 0.5;
    use glassscan::scan::bip::{find_bip, BipRule};
    let world = scene::load(&scene_path("car_side_window.toml")).unwrap();
    let head = SensorHead::new(&world.sensor).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let border_b = world.true_border_in_base().expect("the scene has a target");
    let mut scan = world.scan;
    scan.poses = 3;
    let settings = TraceSettings {
        photons: 1 << 16,
        adaptive: false,
        max_depth: 64,
        seed: 1,
    };
    let mut off_edge = 0;
    for pose in plan_border_scan(&border_b, &scan, &world.mount) {
        let r = simulate_pose(&trace, &head, &pose, &settings, StopRules::EDGE_LINE);
        let edge = find_bip(&r.profile, &pose.sensor, BipRule::EdgeLine).expect("an edge BIP");
        let d = (edge.point_b - pose.edge_point).norm() * 1e3;
        eprintln!(
            "car window pose {}: edge-line BIP {d:.3} mm from p_e",
            pose.index
        );
        assert!(
            d < LIMIT_MM,
            "pose {}: edge-line BIP {d:.3} mm from p_e",
            pose.index
        );
        assert_eq!(edge.label, Some(PathClass::GlassEdge));
        let paper = find_bip(&r.profile, &pose.sensor, BipRule::Highest).unwrap();
        let paper_mm = (paper.point_b - pose.edge_point).norm() * 1e3;
        eprintln!(
            "pose {}: paper's rule {paper_mm:.2} mm from p_e ({:?})",
            pose.index, paper.label
        );
        if paper_mm > 5.0 && paper.label != Some(PathClass::GlassEdge) {
            off_edge += 1;
        }
    }
    assert!(
        off_edge >= 2,
        "the paper's rule picked a point off the edge at only {off_edge} of 3 poses"
    );
}

#[test]
fn skipping_connections_that_cannot_land_changes_no_image() {
    // Issue 11, step 1: connections through glass whose chains provably cannot reach the pixel
    // grid (`transport::deviation` bounds how far the panes can turn them) are not solved. The
    // images must be bit-identical to solving every connection, on every shipped glass scene.
    for (name, scan_angle_deg) in [
        ("flat_panel.toml", None),
        ("edge_study_bare.toml", Some(10.0)),
        ("edge_study_bare.toml", Some(45.0)),
        ("car_side_window.toml", None),
        ("mixed_pixels.toml", None),
    ] {
        let mut world = scene::load(&scene_path(name)).unwrap();
        if let Some(a) = scan_angle_deg {
            world.scan.scan_angle_rad = f64::to_radians(a);
        }
        let head = SensorHead::new(&world.sensor).unwrap();
        let bounded = TraceScene::new(&world).unwrap();
        let bound = bounded
            .deviation
            .expect("shipped panes have rough edges: a bound");
        let mut exhaustive = TraceScene::new(&world).unwrap();
        exhaustive.deviation = None;
        let border = world.true_border_in_base().expect("the scene has a target");
        let poses = plan_border_scan(&border, &world.scan, &world.mount);
        let settings = TraceSettings {
            photons: 1 << 15,
            adaptive: false,
            max_depth: 64,
            seed: 3,
        };
        let pose = &poses[0];
        let (a, sa) = glassscan::transport::render(&bounded, &head, &pose.sensor, &settings, 0);
        let (b, sb) = glassscan::transport::render(&exhaustive, &head, &pose.sensor, &settings, 0);
        eprintln!(
            "{name} {scan_angle_deg:?}: bound {bound:?}; {} of {} connections culled, {} / {} \
             solved through glass",
            sa.connections_culled,
            sa.connections,
            sa.connections_through_glass,
            sb.connections_through_glass
        );
        assert_eq!(
            a.total.data, b.total.data,
            "{name}: total irradiance differs"
        );
        for (x, y) in a.by_class.iter().zip(&b.by_class) {
            assert_eq!(x.data, y.data, "{name}: a class layer differs");
        }
        assert_eq!(sa.flux_on_sensor_w, sb.flux_on_sensor_w);
        assert_eq!(sb.connections_culled, 0);
    }
}

/// The edge experiment's step 1 (paper §III-C): the tape, built from the pane's seamed section,
/// is what the sensor reads near the border at both of the paper's scan angles. Every profile
/// point within 3 mm of p_e (taken to the base frame with the true pose) must lie within
/// 0.1 mm of the tape's outer surface: the tape reads the true contour, 0.11 mm proud of the
/// glass. Noise and speckle off, one pose per angle, 2^16 photons; the exposure is lowered to
/// 0.02 ms so that the white tape (albedo 0.7) stays below full scale, as on `flat_opaque`.
#[test]
fn edge_study_tape_is_read_on_its_surface_at_10_and_40_degrees() {
    use glassscan::geometry::closest::nearest_on_mesh;
    let mut world = scene::load(&scene_path("edge_study_tape.toml")).unwrap();
    world.sensor.imager.noise = false;
    world.sensor.speckle = None;
    world.sensor.imager.exposure_s = 0.02e-3;
    let head = SensorHead::new(&world.sensor).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let tape = world.objects.iter().find(|o| o.name == "tape").unwrap();
    let tape_b = tape.mesh.transformed(&tape.pose);
    let border = world.true_border_in_base().expect("the scene has a target");
    let settings = TraceSettings {
        photons: 1 << 16,
        adaptive: false,
        max_depth: 16,
        seed: 3,
    };
    for angle_deg in [10.0f64, 40.0] {
        let mut scan = world.scan;
        scan.scan_angle_rad = angle_deg.to_radians();
        scan.poses = 1;
        let pose = plan_border_scan(&border, &scan, &world.mount).remove(0);
        let r = simulate_pose(&trace, &head, &pose, &settings, StopRules::EDGE_LINE);
        let mut distances = Vec::new();
        for p in r.profile.points.iter().filter(|p| p.valid) {
            let b = pose.sensor * Point3::new(p.x_mm * 1e-3, 0.0, p.z_mm * 1e-3);
            if (b - pose.edge_point).norm() > 3e-3 {
                continue;
            }
            assert_eq!(p.label, Some(PathClass::TapeCover), "{angle_deg}°: {b}");
            distances.push(nearest_on_mesh(&tape_b, &b).unwrap().distance * 1e3);
        }
        let max = distances.iter().fold(0.0f64, |a, &d| a.max(d));
        let mean = distances.iter().sum::<f64>() / distances.len() as f64;
        eprintln!(
            "edge_study_tape at {angle_deg}°: {} points within 3 mm of p_e, distance to the tape \
             surface mean {mean:.4} mm, max {max:.4} mm",
            distances.len()
        );
        assert!(
            distances.len() >= 10,
            "{angle_deg}°: {} points",
            distances.len()
        );
        assert!(max < 0.1, "{angle_deg}°: a point {max:.3} mm off the tape");
    }
}

/// The edge-line rule on simulated profiles of the edge finishes a glass shop makes (issue 10,
/// part 3; the synthetic-profile tests are in `src/localise/edge_line.rs`): the edge-study pane
/// with a flat-ground wall, seamed edges of three arris widths and a half-round pencil edge, at
/// the paper's two scan angles and the driver's 0.5 ms. Where the rule is reliable it must land
/// within 0.3 mm (1.5 profile points at the edge study's ~0.2 mm spacing) of the best any rule
/// could do: p_e, or the edge return nearest to it when the physics leaves the top of the
/// finish dark, and on the pencil edge no nearer than its documented climb limit
/// r·sin 20° = 0.68 mm (r = 2 mm: the climb stops where the arc turns flatter than 20°).
///
/// Two cases are marginal and only have to stay on the edge (the BIP is a glass-edge return):
/// the flat-ground wall and the 0.4 mm seam at 40°. There the chain of edge returns up the wall
/// often has a gap (returns near the threshold, speckle), and the rule takes the top of the
/// longer run below it, ~1.6–2.7 mm under p_e. Measured over 8 seeds × 4 poses at 2^16 photons
/// and 4 × 4 at 2^20: flat ground at 40° misses p_e by more than 0.5 mm in 19 of 32 profiles at
/// 2^16 and 7–8 of 16 at 2^20 (before and after issue 11's beam sampling alike: physics and
/// rule, not Monte Carlo noise); the 0.4 mm seam in 2–4 of 32 at 2^16; the default 0.8 mm seam
/// in none of 32. Sensor only, true pose known, the default photon count (2^18), seed 5, 2 poses. (At
/// 2^16, since the fan's focus on p_e narrowed to ±2 mm, two pencil-edge poses fail: a lone
/// noisy edge return nearer p_e than the chain, 0.4 of the photons off the window, sets the
/// bar; at 2^18 the nearest edge return and the BIP are the same point at 10° and 0.74/0.86
/// mm at 40°.)
#[test]
fn edge_line_bips_land_on_p_e_on_simulated_flat_seamed_and_pencil_edges() {
    use glassscan::scan::bip::{find_bip, BipRule};
    const SLACK_MM: f64 = 0.3;
    let text = std::fs::read_to_string(scene_path("edge_study.toml")).unwrap();
    let seamed = |w: f64| {
        format!(
            "edge = {{ seamed = {{ top = {{ width_mm = {w} }}, bottom = {{ width_mm = {w} }} }} }}"
        )
    };
    // (edge, the rule's own limit in mm, the scan angle at which the case is marginal)
    let cases = [
        ("edge = \"flat_ground\"".to_owned(), 0.0, Some(40.0)),
        (seamed(0.4), 0.0, Some(40.0)),
        (seamed(0.8), 0.0, None),
        (seamed(1.2), 0.0, None),
        (
            "edge = \"pencil\"".to_owned(),
            2.0 * 20f64.to_radians().sin(),
            None,
        ),
    ];
    let settings = TraceSettings {
        photons: DEFAULT_PHOTONS,
        adaptive: false,
        max_depth: 16,
        seed: 5,
    };
    let mut failures = Vec::new();
    for (edge, rule_limit_mm, marginal_at) in &cases {
        let scene_text = text.replace("\nedge = \"seamed\"\n", &format!("\n{edge}\n"));
        assert_ne!(scene_text, text);
        let world = scene::load_str(&scene_path("edge_study.toml"), &scene_text).unwrap();
        let head = SensorHead::new(&world.sensor).unwrap();
        let trace = TraceScene::new(&world).unwrap();
        let border_b = world.true_border_in_base().expect("the scene has a target");
        for angle_deg in [10.0f64, 40.0] {
            let mut scan = world.scan;
            scan.scan_angle_rad = angle_deg.to_radians();
            scan.poses = 2;
            for pose in plan_border_scan(&border_b, &scan, &world.mount) {
                let r = simulate_pose(&trace, &head, &pose, &settings, StopRules::EDGE_LINE);
                let nearest_edge_mm = r
                    .profile
                    .points
                    .iter()
                    .filter(|p| p.valid && p.label == Some(PathClass::GlassEdge))
                    .map(|p| {
                        let b = pose.sensor * Point3::new(p.x_mm * 1e-3, 0.0, p.z_mm * 1e-3);
                        (b - pose.edge_point).norm() * 1e3
                    })
                    .fold(f64::INFINITY, f64::min);
                let bip = find_bip(&r.profile, &pose.sensor, BipRule::EdgeLine);
                let d = bip.map(|b| (b.point_b - pose.edge_point).norm() * 1e3);
                let limit = nearest_edge_mm.max(*rule_limit_mm) + SLACK_MM;
                eprintln!(
                    "{edge} at {angle_deg}°, pose {}: BIP {d:?} mm from p_e, nearest edge \
                     return {nearest_edge_mm:.3} mm",
                    pose.index
                );
                if *marginal_at == Some(angle_deg) {
                    if bip.is_none_or(|b| b.label != Some(PathClass::GlassEdge)) {
                        failures.push(format!(
                            "{edge} at {angle_deg}° pose {}: the BIP is not an edge return",
                            pose.index
                        ));
                    }
                } else if d.is_none_or(|d| d > limit) {
                    failures.push(format!(
                        "{edge} at {angle_deg}° pose {}: {d:?} > {limit:.3}",
                        pose.index
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The paper's scan-angle finding (Section III-C, Fig. 7: at 40° the edge readings lie close to
/// p_e, at 10° further away) on the shipped seamed edge, where the simulation reproduces it
/// and where not (issue 10; the scan-angle study's exposure axis and finding map):
/// - at 0.15 ms the 0.8 mm arris stays under the threshold when seen at 10° (its facet faces up
///   and out, 55° off the view), so the BIP is the top of the wall, the arris's lower corner
///   ~1.1 mm from p_e, while at 40° the arris returns and the BIP is p_e: the finding holds by
///   the finding map's criterion (10° error ≥ 2× the 40° one and ≥ 0.2 mm more);
/// - at the driver's 0.5 ms the arris clears the threshold at both angles and both BIPs lie
///   within 0.3 mm of p_e: the finding does not hold.
///
/// Edge-line rule, 2 poses, 2^18 photons (at 2^16 the 10° arris at 0.5 ms, near the threshold,
/// dropped out at one pose: 1.0 mm), noise and speckle on (study, 12 positions, 2^20:
/// 1.17 vs 0.09 mm at 0.15 ms, 0.10 vs 0.09 mm at 0.5 ms).
#[test]
fn the_paper_scan_angle_finding_holds_at_a_short_exposure_and_not_at_the_default() {
    use glassscan::scan::bip::{find_bip, BipRule};
    use glassscan::study::finding_map::{HOLDS_MARGIN_MM, HOLDS_RATIO};
    let mut world = scene::load(&scene_path("edge_study.toml")).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let border_b = world.true_border_in_base().expect("the scene has a target");
    let settings = TraceSettings {
        photons: 1 << 18,
        adaptive: false,
        max_depth: 16,
        seed: 2,
    };
    let mut mean_error = |exposure_ms: f64, angle_deg: f64| {
        world.sensor.imager.exposure_s = exposure_ms * 1e-3;
        let head = SensorHead::new(&world.sensor).unwrap();
        let mut scan = world.scan;
        scan.scan_angle_rad = angle_deg.to_radians();
        scan.poses = 2;
        let poses = plan_border_scan(&border_b, &scan, &world.mount);
        let errors: Vec<f64> = poses
            .iter()
            .map(|pose| {
                let r = simulate_pose(&trace, &head, pose, &settings, StopRules::EDGE_LINE);
                let bip = find_bip(&r.profile, &pose.sensor, BipRule::EdgeLine)
                    .unwrap_or_else(|| panic!("{exposure_ms} ms, {angle_deg}°: no BIP"));
                (bip.point_b - pose.edge_point).norm() * 1e3
            })
            .collect();
        let mean = errors.iter().sum::<f64>() / errors.len() as f64;
        eprintln!("{exposure_ms} ms, {angle_deg}°: BIP errors {errors:.3?} mm");
        mean
    };
    let (short_10, short_40) = (mean_error(0.15, 10.0), mean_error(0.15, 40.0));
    assert!(
        short_10 >= HOLDS_RATIO * short_40 && short_10 - short_40 >= HOLDS_MARGIN_MM,
        "0.15 ms: 10° {short_10:.3} mm against 40° {short_40:.3} mm"
    );
    assert!(
        (0.9..1.4).contains(&short_10),
        "0.15 ms, 10°: {short_10:.3} mm, not the arris's lower corner"
    );
    let (default_10, default_40) = (mean_error(0.5, 10.0), mean_error(0.5, 40.0));
    assert!(
        default_10 < 0.3 && default_40 < 0.3,
        "0.5 ms: 10° {default_10:.3} mm, 40° {default_40:.3} mm"
    );
}
