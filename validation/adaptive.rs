//! The adaptive photon count (`glassscan::scan::adaptive`): a pose that stops after n photons
//! is the rendering of its n photons traced at once, bit for bit, for any thread count.

use glassscan::scan::adaptive::StopRules;
use glassscan::scan::simulate::{
    apply_lens_psf, pose_rendering, sense_pose, simulate_pose, PoseResult,
};
use glassscan::transport::{TraceSettings, DEFAULT_PHOTONS, FIRST_PHOTON_SET};

use crate::common::{shipped_scan, ShippedScan};

fn on_threads(threads: usize, run: impl FnOnce() -> PoseResult + Send) -> PoseResult {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(run)
}

/// The same simulation bit for bit: counters, light, image and profile (compared through their
/// Debug text, where NaN, the range of an invalid point, equals itself).
fn assert_same(a: &PoseResult, b: &PoseResult, what: &str) {
    assert_eq!(a.stats, b.stats, "{what}: counters");
    assert!(a.irradiance == b.irradiance, "{what}: irradiance");
    assert!(a.image == b.image, "{what}: image");
    let text = |r: &PoseResult| format!("{:?}", r.profile);
    assert!(text(a) == text(b), "{what}: profile");
}

#[test]
fn an_adaptive_pose_is_its_photons_traced_at_once() {
    // edge_study_bare at 45°, the convergence test's 16 poses (examples/convergence.rs), seed
    // 12, waiting for the edge-line rule as `scan` does: pose 1 stops at the first check
    // (2^17), pose 4 takes another set (to the default 2^18; measured on 2026-12-07, since light
    // totally reflected in a flat pane ends there: 12 of the 16 poses stop at 2^17, and at
    // seed 11 all 16).
    let ShippedScan { head, trace, poses } = shipped_scan("edge_study_bare.toml", 45.0, 16);
    let settings = |photons, adaptive| TraceSettings {
        photons,
        adaptive,
        max_depth: 64,
        seed: 12,
    };
    let mut counts = Vec::new();
    for pose in [&poses[1], &poses[4]] {
        let adaptive = settings(DEFAULT_PHOTONS, true);
        let one = on_threads(1, || {
            simulate_pose(&trace, &head, pose, &adaptive, StopRules::EDGE_LINE)
        });
        let two = on_threads(2, || {
            simulate_pose(&trace, &head, pose, &adaptive, StopRules::EDGE_LINE)
        });
        let n = one.stats.photons;
        // It stops after a whole set: 2^17, 2^18, … up to the most allowed.
        assert!(n.is_power_of_two() && (2 * FIRST_PHOTON_SET..=DEFAULT_PHOTONS).contains(&n));
        assert_same(&one, &two, &format!("pose {}, 1 and 2 threads", pose.index));
        let at_once = settings(n, true);
        let mut rendering = pose_rendering(&trace, &head, pose, &at_once);
        rendering.trace_to(n);
        let (mut light, stats) = rendering.develop();
        apply_lens_psf(&mut light, &head, pose, at_once.seed);
        let fixed = sense_pose(light, stats, &head, pose, &at_once);
        assert_same(
            &one,
            &fixed,
            &format!("pose {}, grown and at once", pose.index),
        );
        // Waiting for more rules never takes fewer photons (a check both rules pass, the
        // edge-line rule passes too), and at the same count it is the same simulation (here
        // both rules stop at the same count, the same simulation bit for bit).
        let both = simulate_pose(&trace, &head, pose, &adaptive, StopRules::BOTH);
        assert!(both.stats.photons >= n, "pose {}", pose.index);
        if both.stats.photons == n {
            assert_same(
                &both,
                &one,
                &format!("pose {}, edge-line and both", pose.index),
            );
        }
        counts.push(n);
    }
    eprintln!("photons traced: {counts:?}");
    assert_eq!(counts[0], 2 * FIRST_PHOTON_SET);
    assert!(counts[1] > 2 * FIRST_PHOTON_SET, "{counts:?}");
}
