//! The convergence test (issue 11; `glassscan::study::convergence` states it): the default
//! photon count of every command (`transport::DEFAULT_PHOTONS`) must give profiles that cannot
//! be told from a 2^22-photon reference on the pane at 40° and 45° (all four criteria), and a
//! photon count known to be too low (2^14) must fail, so the test has the power to see a
//! difference; the adaptive count (`--photons auto`) must converge the BIP it waits for; on
//! the car window at 45°, where the default is not converged by every criterion, the
//! criteria it meets must keep holding. Slow tier
//! (`cargo test --release -- --ignored`, ~2 min on 2 cores for the four tests): the committed references were made
//! by `examples/convergence.rs` (which documents the seeds and poses), and must be regenerated
//! with it when the physics or the sensor's noise streams change.

use std::path::Path;

use glassscan::study::convergence::{
    judge, pooled_median_difference, sample_profiles, sample_twin_profiles, ProfileSample, Verdict,
};
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
fn the_twin_shares_the_speckle_and_the_sensor_noise_but_not_the_photons() {
    // The pane at 40°, 2^18 photons, two poses: the twin's profile differs from the run at the
    // same seed (other photons) by far less than a run at another seed does (other speckle).
    let ShippedScan { head, trace, poses } = shipped_scan("edge_study_bare.toml", 40.0, 2);
    let photons = 1 << 18;
    let same = sample_profiles(&trace, &head, &poses, &[5], (photons, false), MAX_DEPTH);
    let other = sample_profiles(&trace, &head, &poses, &[6], (photons, false), MAX_DEPTH);
    let twin = sample_twin_profiles(&trace, &head, &poses, &[5], photons, MAX_DEPTH);
    assert_ne!(twin, same);
    let monte_carlo = pooled_median_difference(same.iter().zip(&twin)).unwrap();
    let seed_to_seed = pooled_median_difference(same.iter().zip(&other)).unwrap();
    eprintln!("twin: {monte_carlo} mm, other seed: {seed_to_seed} mm");
    assert!(monte_carlo < 0.5 * seed_to_seed);
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
fn the_default_photon_count_meets_criteria_1_and_3_on_the_car_side_window_at_45_degrees() {
    // Not converged by all four criteria: the paper's highest-point BIP, which on the curved
    // window lands on faint face returns tens of millimetres up the glass, is still moving with
    // the photon count (median error 50 mm at 2^18, 30 mm at 2^22; KS p 0.003), and criterion
    // 2 holds on this draw (31 of 32) but not on every other (29-30 of 32):
    // validation/results/convergence/README.md. What holds, and what this test keeps: the
    // edge-line BIPs' distribution and the profile within the sensor's noise.
    let (scene, results) = ("car_side_window.toml", "car_side_window_45");
    let v = verdict(scene, 45.0, results, (DEFAULT_PHOTONS, false));
    assert!(v.edge_line_distribution_holds() && v.profile_z_holds());
    assert!(!verdict(scene, 45.0, results, (1 << 14, false)).profile_z_holds());
}

#[test]
#[ignore = "slow tier: ~1.5 min on 2 cores"]
fn the_default_photon_count_is_converged_on_edge_study_bare_at_45_degrees() {
    // The tightest pane case. With the fan's photons focused on p_e ±8 mm (until 2026-12-06)
    // the BIPs at 2^18 sat ~10 µm closer to p_e than the reference's (KS p 0.007 and 0.003)
    // and 2^21 still missed criterion 2; focused on ±2 mm with 0.6 of the photons it passes all
    // four on this draw and on three other photon draws (validation/results/convergence/
    // README.md, 2026-12-06). 2^14 must fail.
    let (scene, results) = ("edge_study_bare.toml", "edge_study_bare_45");
    assert!(verdict(scene, 45.0, results, (DEFAULT_PHOTONS, false)).converged);
    assert!(!verdict(scene, 45.0, results, (1 << 14, false)).converged);
}

#[test]
#[ignore = "slow tier: ~1 min on 2 cores"]
fn the_adaptive_photon_count_converges_the_edge_line_bip_on_edge_study_bare_at_40_degrees() {
    // The edge-line stop as `scan` runs it, up to the default 2^18 (mean 2^17.17 photons): the
    // BIP it waits for is converged (criteria 1 and 2: KS p 0.233, 32 of 32 same-seed BIPs).
    // The rest of the profile is not: since the fan's focus on p_e narrowed to ±2 mm with 0.6
    // of the photons, a pose stopped at 2^17 has the column noise of 0.4 × 2^17 photons off the
    // window (criterion 3: 10.3 against 9.4 µm, and the paper's BIP, criterion 4, p 0.009), as
    // on every case tested (validation/results/convergence/README.md).
    let v = verdict(
        "edge_study_bare.toml",
        40.0,
        "edge_study_bare",
        (DEFAULT_PHOTONS, true),
    );
    assert!(v.edge_line_distribution_holds() && v.paired_bips_hold());
}
