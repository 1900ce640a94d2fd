//! Triangulation of analytic targets: the simulated profile against the exact geometry.
//!
//! References are the targets' own analytic surfaces (pbrt-v4 `integrators_test.cpp` style:
//! a scene whose answer is known in closed form). Sensor noise does not exist yet (issue #4);
//! what remains is Monte Carlo noise of the transport and the pixel sampling of the line.

use crate::common::{facing_plate, fit_line, simulate, valid_points, world_of_boxes};

const PHOTONS: u64 = 1 << 21;

#[test]
fn flat_target_triangulates_flat_and_at_its_range() {
    for z_mm in [150.0, 257.5, 370.0] {
        let world = world_of_boxes(&[facing_plate(z_mm, 0.0)]);
        let r = simulate(&world, PHOTONS, 11);
        let pts = valid_points(&r);
        assert!(
            pts.len() > 600,
            "z = {z_mm}: only {} valid points",
            pts.len()
        );
        // The analytic plane is z = z_mm: RMS of the residual against it, not against a fit.
        let rms = (pts.iter().map(|p| (p.1 - z_mm).powi(2)).sum::<f64>() / pts.len() as f64).sqrt();
        let (_, slope, fit_rms) = fit_line(&pts);
        eprintln!(
            "flat z = {z_mm} mm: rms {:.1} µm, fit rms {:.1} µm, slope {slope:.2e}",
            rms * 1e3,
            fit_rms * 1e3
        );
        assert!(
            rms < 0.020,
            "z = {z_mm} mm: RMS residual {:.1} µm ≥ 20 µm",
            rms * 1e3
        );
    }
}

#[test]
fn step_target_gives_its_height() {
    // Two plates side by side (split at x = 0), the right one 12 mm nearer.
    let mut left = facing_plate(270.0, 0.0);
    left.size_mm = [200.0, 400.0, 10.0];
    left.translation_mm[0] = -100.0;
    let mut right = facing_plate(258.0, 0.0);
    right.size_mm = [200.0, 400.0, 10.0];
    right.translation_mm[0] = 100.0;
    let world = world_of_boxes(&[left, right]);
    let r = simulate(&world, PHOTONS, 12);
    let pts = valid_points(&r);
    // Stay 3 mm clear of the step, where the near plate shadows the far one.
    let far: Vec<f64> = pts.iter().filter(|p| p.0 < -3.0).map(|p| p.1).collect();
    let near: Vec<f64> = pts.iter().filter(|p| p.0 > 3.0).map(|p| p.1).collect();
    assert!(
        far.len() > 100 && near.len() > 100,
        "{} / {} points",
        far.len(),
        near.len()
    );
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let step = mean(&far) - mean(&near);
    eprintln!("step: {step:.4} mm (true 12)");
    assert!(
        (step - 12.0).abs() < 0.050,
        "step {step} mm, expected 12 ± 0.05"
    );
}

#[test]
fn tilted_plane_gives_its_tilt() {
    for tilt in [-20.0, 15.0] {
        let world = world_of_boxes(&[facing_plate(260.0, tilt)]);
        let r = simulate(&world, PHOTONS, 13);
        let pts = valid_points(&r);
        let (_, slope, rms) = fit_line(&pts);
        // A plane tilted by θ about y: z = z0 − x·tan θ (the box's +x side rotates towards −z
        // for a positive rotation about y).
        let measured = (-slope).atan().to_degrees();
        eprintln!(
            "tilt {tilt}°: measured {measured:.4}°, rms {:.1} µm",
            rms * 1e3
        );
        assert!(
            (measured - tilt).abs() < 0.02,
            "tilt {tilt}: measured {measured}"
        );
    }
}

#[test]
fn profile_moves_by_the_commanded_offset() {
    let base = simulate(&world_of_boxes(&[facing_plate(250.0, 0.0)]), PHOTONS, 14);
    let moved = simulate(&world_of_boxes(&[facing_plate(255.0, 0.0)]), PHOTONS, 14);
    let mean_z = |r: &glassscan::scan::simulate::PoseResult| {
        let p = valid_points(r);
        p.iter().map(|p| p.1).sum::<f64>() / p.len() as f64
    };
    let dz = mean_z(&moved) - mean_z(&base);
    eprintln!("commanded 5 mm, profile moved {dz:.4} mm");
    assert!((dz - 5.0).abs() < 0.010, "moved {dz} mm instead of 5");

    // A lateral move of a step edge moves the edge by the same amount in x.
    let edge_x = |offset: f64| {
        let mut near = facing_plate(240.0, 0.0);
        near.size_mm = [200.0, 400.0, 10.0];
        near.translation_mm[0] = 100.0 + offset;
        let r = simulate(&world_of_boxes(&[near]), PHOTONS, 15);
        // The leftmost valid point is the plate's left edge at x = offset.
        valid_points(&r)
            .iter()
            .map(|p| p.0)
            .fold(f64::INFINITY, f64::min)
    };
    let shift = edge_x(7.0) - edge_x(0.0);
    // One profile point per column: the edge is found to within a column's width (~0.23 mm here).
    eprintln!("commanded 7 mm lateral, edge moved {shift:.3} mm");
    assert!(
        (shift - 7.0).abs() < 0.3,
        "edge moved {shift} mm instead of 7"
    );
}
