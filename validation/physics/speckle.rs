//! Speckle: line-centre jitter on a rough target against the Dorsch–Häusler–Herrmann limit.

use glassscan::sensor::speckle::SpeckleSettings;
use glassscan::sensor::SensorHead;

use crate::common::{facing_plate, fit_line, simulate, valid_points, world_of_boxes};

/// Standard deviation (mm) of the profile's z residuals about a fitted line, |x| < 30 mm.
fn z_jitter_mm(f_number: f64, exposure_s: f64, seed: u64) -> (f64, f64) {
    let mut world = world_of_boxes(&[facing_plate(257.5, 0.0)]);
    world.sensor.camera.f_number = f_number;
    world.sensor.imager.exposure_s = exposure_s;
    world.sensor.speckle = Some(SpeckleSettings {
        contrast: 1.0,
        oversampling: 8,
    });
    let head = SensorHead::new(&world.sensor).unwrap();
    let r = simulate(&world, 1 << 21, seed);
    let pts: Vec<(f64, f64)> = valid_points(&r)
        .into_iter()
        .filter(|p| p.0.abs() < 30.0)
        .collect();
    let (_, _, rms) = fit_line(&pts);
    // Dorsch, Häusler & Herrmann, Appl. Opt. 33(7):1306 (1994): δz = C·λ/(2π·sin u_obs·sin θ)
    // with u_obs the observation aperture's half-angle and θ the triangulation angle at the
    // target point (docs/parameters.md §5).
    let c = head.camera.center() * 1e3; // mm
    let l = (c - nalgebra::Vector3::new(0.0, 0.0, 257.5)).norm();
    let sin_u = 0.5 * head.camera.spec().aperture_diameter_m() * 1e3 / l;
    let sin_theta = c.y / l;
    let dorsch =
        world.sensor.laser.wavelength_m * 1e3 / (2.0 * std::f64::consts::PI * sin_u * sin_theta);
    (rms, dorsch)
}

#[test]
fn speckle_jitter_follows_the_dorsch_limit_for_two_apertures() {
    // Exposures keep the mean line near 250 DN so that speckle peaks rarely clip at 1023.
    for (f_number, exposure_s) in [(2.8, 0.005e-3), (8.0, 0.041e-3)] {
        let (jitter, dorsch) = z_jitter_mm(f_number, exposure_s, 71);
        eprintln!(
            "f/{f_number}: speckle z jitter {:.1} µm, Dorsch limit {:.1} µm (ratio {:.2})",
            jitter * 1e3,
            dorsch * 1e3,
            jitter / dorsch
        );
        assert!(
            (jitter / dorsch - 1.0).abs() < 0.3,
            "f/{f_number}: {jitter} vs {dorsch}"
        );
    }
}
