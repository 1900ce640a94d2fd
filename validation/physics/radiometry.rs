//! Radiometry and determinism of the light tracer on analytic scenes.

use glassscan::sensor::SensorHead;

use crate::common::{
    facing_plate, simulate, simulate_with_threads, valid_points, world_of_boxes, BoxSpec,
};

#[test]
fn flux_into_the_camera_matches_the_analytic_integral() {
    // A Lambertian plate z = z0 lit by the fan. Flux through the lens from a laser point x:
    // dΦ = Φ·(ρ/π)·cos θ_x·cos θ_L·A/r² (radiance of a Lambertian reflector, Lambert's cosine
    // law; e.g. Pharr, Jakob & Humphreys, PBR 4th ed., §4.1–4.3). Integrated over the uniform
    // (Powell) fan, counting only points whose image lands on the pixel grid.
    let z0 = 0.2575;
    let world = world_of_boxes(&[facing_plate(z0 * 1e3, 0.0)]);
    let head = SensorHead::new(&world.sensor).unwrap();
    let cam = &head.camera;
    let laser = &world.sensor.laser;
    let rho = 0.8;
    let n = 20_000;
    let mut expected = 0.0;
    for k in 0..n {
        let phi = laser.fan_angle((k as f64 + 0.5) / n as f64);
        let x = nalgebra::Vector3::new(z0 * phi.tan(), 0.0, z0);
        let [c, r] = cam.laser_plane_to_pixel(x.x, x.z).unwrap();
        let spec = cam.spec();
        if c < 0.0 || r < 0.0 || c >= spec.columns as f64 || r >= spec.rows as f64 {
            continue;
        }
        let to_lens = cam.center() - x;
        let d = to_lens.norm();
        let cos_x = -to_lens.z / d; // the plate faces the sensor: its normal is −z
        let cos_l = to_lens.dot(&cam.axis()).abs() / d;
        expected += laser.power_w / n as f64 * rho / std::f64::consts::PI
            * cos_x
            * cos_l
            * cam.aperture_area()
            / (d * d);
    }
    let r = simulate(&world, 1 << 20, 21);
    let got = r.stats.flux_on_sensor_w;
    let image_sum: f64 = r.irradiance.total.data.iter().sum::<f64>() * cam.pixel_area();
    eprintln!("flux on sensor: simulated {got:.6e} W, analytic {expected:.6e} W");
    assert!(
        (got / expected - 1.0).abs() < 0.005,
        "simulated {got}, analytic {expected}"
    );
    assert!(
        (image_sum / got - 1.0).abs() < 1e-9,
        "image holds {image_sum}, splatted {got}"
    );
}

#[test]
fn irradiance_is_linear_in_laser_power() {
    let mut world = world_of_boxes(&[facing_plate(240.0, 10.0)]);
    let a = simulate(&world, 1 << 16, 22);
    world.sensor.laser.power_w *= 2.0;
    let b = simulate(&world, 1 << 16, 22);
    for (x, y) in a.irradiance.total.data.iter().zip(&b.irradiance.total.data) {
        assert_eq!(2.0 * x, *y);
    }
}

#[test]
fn same_seed_gives_bit_identical_images_for_one_and_two_threads() {
    let world = world_of_boxes(&[facing_plate(230.0, 25.0), {
        let mut table = facing_plate(300.0, -10.0);
        table.albedo = 0.3;
        table
    }]);
    let one = simulate_with_threads(&world, 100_000, 23, 1);
    let two = simulate_with_threads(&world, 100_000, 23, 2);
    assert!(one.irradiance.total.data.iter().any(|&v| v > 0.0));
    let bits = |r: &glassscan::scan::simulate::PoseResult| {
        r.irradiance
            .total
            .data
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(one.image, two.image);
    assert_eq!(one.stats, two.stats);
    let other_seed = simulate(&world, 100_000, 24);
    assert_ne!(bits(&one), bits(&other_seed), "the seed does nothing");
}

#[test]
fn laser_side_shadow_removes_the_shadowed_part_of_the_target() {
    // A bar at z = 150 mm covering x ∈ [10, 30] mm casts a laser shadow on the plate at 300 mm
    // over x ∈ [20, 60] mm (central projection from the fan's source at the origin); the
    // profile shows the bar there instead of the plate.
    let bar = BoxSpec {
        size_mm: [20.0, 400.0, 5.0],
        translation_mm: [20.0, 0.0, 152.5],
        rotation_deg: [0.0; 3],
        albedo: 0.8,
    };
    let world = world_of_boxes(&[facing_plate(300.0, 0.0), bar]);
    let r = simulate(&world, 1 << 20, 25);
    let pts = valid_points(&r);
    let on_plate_in_shadow = pts
        .iter()
        .filter(|p| p.0 > 21.0 && p.0 < 59.0 && (p.1 - 300.0).abs() < 1.0)
        .count();
    let on_bar = pts.iter().filter(|p| (p.1 - 150.0).abs() < 1.0).count();
    let on_plate_outside = pts
        .iter()
        .filter(|p| p.0 < 0.0 && (p.1 - 300.0).abs() < 1.0)
        .count();
    assert_eq!(on_plate_in_shadow, 0, "points in the laser shadow");
    assert!(
        on_bar > 10 && on_plate_outside > 100,
        "bar {on_bar}, plate {on_plate_outside}"
    );
}

#[test]
fn camera_side_occluder_hides_the_line_but_not_the_laser() {
    // A block between the plate and the lens (y ∈ [20, 45] mm, off the laser plane) hides the
    // middle of the line from the camera; the laser itself passes untouched.
    let block = BoxSpec {
        size_mm: [40.0, 25.0, 10.0],
        translation_mm: [0.0, 32.5, 155.0],
        rotation_deg: [0.0; 3],
        albedo: 0.8,
    };
    let open = simulate(&world_of_boxes(&[facing_plate(257.5, 0.0)]), 1 << 19, 26);
    let r = simulate(
        &world_of_boxes(&[facing_plate(257.5, 0.0), block]),
        1 << 19,
        26,
    );
    let centre = |r: &glassscan::scan::simulate::PoseResult| {
        valid_points(r).iter().filter(|p| p.0.abs() < 10.0).count()
    };
    assert!(
        centre(&open) > 20,
        "no points at the centre without the block"
    );
    assert_eq!(centre(&r), 0, "the block does not hide the centre");
    assert!(r.stats.occluded > 0);
    assert_eq!(
        r.stats.laser_hits, open.stats.laser_hits,
        "the block touched the laser"
    );
}

#[test]
fn photons_focused_on_the_edge_keep_every_columns_mean_light() {
    // The fan's photons drawn densely around p_e (`transport::fan_focus`) are importance
    // sampling: the traced irradiance must have the line profile's mean in every band of
    // columns, inside the focus window and away from it, and less Monte Carlo error inside it.
    // edge_study_bare at 45°, one pose, 8 seeds per estimator; bands of 40 columns, each band's
    // light compared by a z-test on the two means (Šidák over the bands, family-wise 1 %).
    use glassscan::scan::simulate::pose_rendering;
    use glassscan::transport::fan_focus::FOCUS_HALF_WIDTH_M;
    use glassscan::transport::{Rendering, TraceSettings};

    use crate::common::{shipped_scan, ShippedScan};

    use crate::stats::{mean_and_error, sidak, z_test};

    let ShippedScan {
        head,
        trace: scene,
        mut poses,
    } = shipped_scan("edge_study_bare.toml", 45.0, 4);
    let pose = poses.swap_remove(1);
    // The focus window's columns: p_e ± the window's half-width along the line.
    let p = pose.sensor.inverse() * pose.edge_point;
    let column = |x: f64| head.camera.laser_plane_to_pixel(x, p.z).unwrap()[0] as usize;
    let (a, b) = (
        column(p.x - FOCUS_HALF_WIDTH_M),
        column(p.x + FOCUS_HALF_WIDTH_M),
    );
    let window = a.min(b)..a.max(b);
    const BAND: usize = 40;
    let columns = head.camera.spec().columns;
    let bands = columns / BAND;
    // Light per band of columns (W/m² summed over the band's pixels) of one rendering, and
    // last the window's.
    let band_light = |focused: bool, seed: u64| -> Vec<f64> {
        let settings = TraceSettings {
            photons: 1 << 15,
            adaptive: false,
            max_depth: 64,
            seed,
        };
        let mut rendering = if focused {
            pose_rendering(&scene, &head, &pose, &settings)
        } else {
            Rendering::new(&scene, &head, &pose.sensor, &settings, pose.index as u64)
        };
        rendering.trace_to(settings.photons);
        let image = rendering.develop().0.total;
        let mut light = vec![0.0; bands + 1];
        for row in image.data.chunks(image.width) {
            for (c, v) in row.iter().enumerate().take(bands * BAND) {
                light[c / BAND] += v;
            }
            light[bands] += row[window.clone()].iter().sum::<f64>();
        }
        light
    };
    let runs =
        |focused: bool| -> Vec<Vec<f64>> { (0..8).map(|s| band_light(focused, 100 + s)).collect() };
    let (focused, uniform) = (runs(true), runs(false));
    let alpha = sidak(0.01, bands);
    let mut errors = (0.0, 0.0);
    for b in 0..=bands {
        let (mf, ef) = mean_and_error(focused.iter().map(|r| r[b]));
        let (mu, eu) = mean_and_error(uniform.iter().map(|r| r[b]));
        if mu == 0.0 && mf == 0.0 {
            continue;
        }
        let p = z_test(mf - mu, (ef * ef + eu * eu).sqrt(), 0.0);
        eprintln!("band {b}: focused {mf:.4e} ± {ef:.1e}, uniform {mu:.4e} ± {eu:.1e}, p {p:.3}");
        if b < bands {
            assert!(
                p > alpha,
                "band {b}: focused {mf} ± {ef}, uniform {mu} ± {eu}"
            );
        } else {
            errors = (ef, eu);
        }
    }
    // Inside the window (±2 mm, 0.6 of the photons) they are ~15–20× denser, which predicts
    // ~0.25 of the Monte Carlo error. Measured (2026-12-06): 0.03 over these 8 seeds, 0.16
    // over 64: the line profile's few photons in the window make its error heavy-tailed, so 8
    // seeds estimate it poorly, hence the loose bound (0.42 with the earlier ±8 mm window and
    // half the photons, ~0.47 predicted).
    let ratio = errors.0 / errors.1;
    eprintln!("window {window:?}: error ratio focused/uniform {ratio:.2}");
    assert!(ratio < 0.75, "{ratio}");
}
