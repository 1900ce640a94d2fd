//! The convergence test (issue 11; `glassscan::study::convergence` states it): the default
//! photon count of every command (`transport::DEFAULT_PHOTONS`) must give profiles that cannot
//! be told from a 2^22-photon reference on the shipped glass scenes, and a photon count known
//! to be too low (2^14) must fail, so the test has the power to see a difference; and the
//! adaptive count (`--photons auto`) must pass where its results say it does. Slow tier
//! (`cargo test --release -- --ignored`, ~3 min on 2 cores for the four tests): the committed references were made
//! by `examples/convergence.rs` (which documents the seeds and poses), and must be regenerated
//! with it when the physics or the sensor's noise streams change.

use std::path::Path;

use glassscan::study::convergence::{judge, sample_profiles, ProfileSample, Verdict};
use glassscan::transport::DEFAULT_PHOTONS;

use crate::common::{shipped_scan, ShippedScan};

/// The example's settings (examples/convergence.rs).
const POSES: usize = 16;
const MAX_DEPTH: u32 = 64;
const SEEDS_A: [u64; 2] = [11, 12];
const SEEDS_C: [u64; 2] = [31, 32];

fn verdict(scene_name: &str, angle_deg: f64, results: &str, budget: (u64, bool)) -> Verdict {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(
        root.join("validation/results/convergence")
            .join(results)
            .join("reference.json"),
    )
    .expect("the committed reference (examples/convergence.rs makes it)");
    let (reference, reference_other): (Vec<ProfileSample>, Vec<ProfileSample>) =
        serde_json::from_str(&text).unwrap();
    let ShippedScan { head, trace, poses } = shipped_scan(scene_name, angle_deg, POSES);
    let same = sample_profiles(&trace, &head, &poses, &SEEDS_A, budget, MAX_DEPTH);
    let independent = sample_profiles(&trace, &head, &poses, &SEEDS_C, budget, MAX_DEPTH);
    let v = judge(&reference, &reference_other, &same, &independent);
    eprintln!(
        "{scene_name} at {angle_deg}°, 2^{} (adaptive: {}): {v:?}",
        budget.0.trailing_zeros(),
        budget.1
    );
    v
}

#[test]
#[ignore = "slow tier: ~2.5 min on 2 cores"]
fn the_default_photon_count_is_converged_on_edge_study_bare_at_40_degrees() {
    let (scene, results) = ("edge_study_bare.toml", "edge_study_bare");
    assert!(verdict(scene, 40.0, results, (DEFAULT_PHOTONS, false)).converged);
    assert!(!verdict(scene, 40.0, results, (1 << 14, false)).converged);
}

#[test]
#[ignore = "slow tier: ~2.5 min on 2 cores"]
fn the_default_photon_count_is_converged_on_the_car_side_window_at_45_degrees() {
    let (scene, results) = ("car_side_window.toml", "car_side_window_45");
    assert!(verdict(scene, 45.0, results, (DEFAULT_PHOTONS, false)).converged);
    assert!(!verdict(scene, 45.0, results, (1 << 14, false)).converged);
}

#[test]
#[ignore = "slow tier: ~1 min on 2 cores"]
fn the_default_photon_count_is_converged_on_edge_study_bare_at_45_degrees() {
    // The tightest case: with the line profile alone only 2^20 passed here; with the photons
    // focused on p_e 2^18 does (31 of 32 same-seed BIPs, the one apart by 0.202 mm).
    let (scene, results) = ("edge_study_bare.toml", "edge_study_bare_45");
    assert!(verdict(scene, 45.0, results, (DEFAULT_PHOTONS, false)).converged);
}

#[test]
#[ignore = "slow tier: ~1 min on 2 cores"]
fn the_adaptive_photon_count_is_converged_on_edge_study_bare_at_40_degrees() {
    // The edge-line stop as `scan` runs it, up to the default 2^18 (mean 2^17.29 photons, 32 of
    // 32 same-seed BIPs). It passes on the pane at 10° too, and fails at 45° on the pane and on
    // the car window by one pair each (30/32), which is why it is not the default:
    // validation/results/convergence/README.md.
    let v = verdict(
        "edge_study_bare.toml",
        40.0,
        "edge_study_bare",
        (DEFAULT_PHOTONS, true),
    );
    assert!(v.converged);
}
