//! How many photons make a converged profile? Runs the convergence test of
//! `glassscan::study::convergence` on a shipped scene at several photon counts against a
//! 2^22-photon reference, prints the table and writes it (and the reference, which the slow
//! validation test `convergence::the_default_photon_count_is_converged` reads) to `OUT`.
//!
//! ```sh
//! cargo run --release --example convergence -- scenes/edge_study_bare.toml 40 \
//!     validation/results/convergence/edge_study_bare
//! ```
//!
//! Seeds: reference A = {11, 12} and B = {21, 22}; N at A (same seed, criteria 2 and 3) and at
//! C = {31, 32} (independent, criteria 1 and 4). Poses: the scene's scan with `POSES` poses (16).
//!
//! With `twin` in place of the photon counts it runs the reference's twin instead
//! (`study::convergence::sample_twin_profiles`: another 2^22 photons at seeds A, the same
//! speckle and sensor noise) and records in `summary.json` how well the two agree: the null
//! of the paired criteria, and whether the reference is converged for each BIP rule.

use std::path::PathBuf;
use std::time::Instant;

use glassscan::scan::poses::plan_border_scan;
use glassscan::scene;
use glassscan::sensor::SensorHead;
use glassscan::study::convergence::{
    bip_errors, highest_bip_errors, judge, ks_two_sample, sample_profiles, sample_twin_profiles,
    ProfileSample,
};
use glassscan::transport::{TraceScene, DEFAULT_PHOTONS};
use serde_json::json;

const POSES: usize = 16;
const MAX_DEPTH: u32 = 64;
const REFERENCE_PHOTONS: u64 = 1 << 22;
const SEEDS_A: [u64; 2] = [11, 12];
const SEEDS_B: [u64; 2] = [21, 22];
const SEEDS_C: [u64; 2] = [31, 32];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene_path, angle_deg, out, ..] = &args[..] else {
        eprintln!("usage: convergence SCENE SCAN_ANGLE_DEG OUT_DIR [PHOTONS,…|twin]");
        std::process::exit(2);
    };
    // A count, or `auto` for the adaptive count up to the default (0 in the table).
    let photon_counts: Vec<u64> = match args.get(3).filter(|a| *a != "twin") {
        Some(list) => list
            .split(',')
            .map(|s| if s == "auto" { 0 } else { s.parse().unwrap() })
            .collect(),
        None => vec![1 << 14, 1 << 16, 1 << 18, 1 << 20],
    };
    let out = PathBuf::from(out);
    std::fs::create_dir_all(&out).unwrap();
    let world = scene::load(std::path::Path::new(scene_path)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let head = SensorHead::new(&world.sensor).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let border_b = world.true_border_in_base().expect("the scene has a target");
    let mut scan = world.scan;
    scan.scan_angle_rad = angle_deg.parse::<f64>().unwrap().to_radians();
    scan.poses = POSES;
    let poses = plan_border_scan(&border_b, &scan, &world.mount);

    let run = |seeds: &[u64], photons: u64| {
        let t = Instant::now();
        let budget = match photons {
            0 => (DEFAULT_PHOTONS, true),
            n => (n, false),
        };
        let s = sample_profiles(&trace, &head, &poses, seeds, budget, MAX_DEPTH);
        let per_profile = t.elapsed().as_secs_f64() / s.len() as f64;
        (s, per_profile)
    };
    let reference_file = out.join("reference.json");
    let (reference, reference_other): (Vec<ProfileSample>, Vec<ProfileSample>) =
        match std::fs::read_to_string(&reference_file) {
            Ok(text) => serde_json::from_str::<(Vec<_>, Vec<_>)>(&text).unwrap(),
            Err(_) => {
                let (a, ta) = run(&SEEDS_A, REFERENCE_PHOTONS);
                let (b, _) = run(&SEEDS_B, REFERENCE_PHOTONS);
                eprintln!("reference 2^22: {ta:.2} s per profile");
                std::fs::write(&reference_file, serde_json::to_string(&(&a, &b)).unwrap()).unwrap();
                (a, b)
            }
        };
    let mut rows = Vec::new();
    println!(
        "photons   KS D   KS p   BIPs agreeing  MC z (µm)  noise z (µm)  highest KS p  converged  s/profile"
    );
    // The reference's twin (photons from other seeds, the same speckle and sensor noise):
    // how well two reference runs agree with each other, the null of the paired criteria.
    let summary_file = out.join("summary.json");
    if args.iter().any(|a| a == "twin") {
        let t = Instant::now();
        let twin = sample_twin_profiles(
            &trace,
            &head,
            &poses,
            &SEEDS_A,
            REFERENCE_PHOTONS,
            MAX_DEPTH,
        );
        let per_profile = t.elapsed().as_secs_f64() / twin.len() as f64;
        // The paired criteria (2, 3) of the twin against the reference; the distributions of
        // both rules against reference B's (independent of the twin's speckle).
        let v = judge(&reference, &reference_other, &twin, &reference_other);
        let edge_line_ks = ks_two_sample(&bip_errors(&twin), &bip_errors(&reference_other));
        let highest_ks = ks_two_sample(
            &highest_bip_errors(&twin),
            &highest_bip_errors(&reference_other),
        );
        println!(
            "twin 2^22 ({per_profile:.2} s/profile): BIPs agreeing {:.3}, MC z {:.2} µm (noise {:.2}), against B: edge-line KS p {:.3}, highest KS p {:.3}",
            v.bip_match_fraction,
            v.monte_carlo_z_mm * 1e3,
            v.sensor_noise_z_mm * 1e3,
            edge_line_ks.p_value,
            highest_ks.p_value
        );
        let mut summary: serde_json::Value = std::fs::read_to_string(&summary_file)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .unwrap_or_else(|| json!({}));
        summary["twin"] = json!({
            "photons": REFERENCE_PHOTONS,
            "seeds": SEEDS_A,
            "bip_match_fraction": v.bip_match_fraction,
            "monte_carlo_z_mm": v.monte_carlo_z_mm,
            "sensor_noise_z_mm": v.sensor_noise_z_mm,
            "edge_line_ks_p_against_reference_b": edge_line_ks.p_value,
            "highest_ks_p_against_reference_b": highest_ks.p_value,
            "wall_s_per_profile": per_profile,
            "same_seed_bip_shift_mm": reference.iter().zip(&twin).map(|(a, b)| bip_shift_mm(a, b)).collect::<Vec<_>>(),
            "same_seed_highest_shift_mm": reference.iter().zip(&twin).map(|(a, b)| highest_shift_mm(a, b)).collect::<Vec<_>>(),
            "highest_bip_error_mm": twin.iter().map(|s| s.highest.error_mm).collect::<Vec<_>>(),
        });
        std::fs::write(
            &summary_file,
            serde_json::to_string_pretty(&summary).unwrap(),
        )
        .unwrap();
        return;
    }
    for &n in &photon_counts {
        let (same, t_same) = run(&SEEDS_A, n);
        let (independent, t_ind) = run(&SEEDS_C, n);
        let v = judge(&reference, &reference_other, &same, &independent);
        let s_per_profile = 0.5 * (t_same + t_ind);
        let traced: Vec<u64> = same.iter().chain(&independent).map(|s| s.photons).collect();
        let mean_photons = traced.iter().sum::<u64>() as f64 / traced.len() as f64;
        let label = match n {
            0 => format!("auto ({:.2})", mean_photons.log2()),
            n => format!("2^{}", n.trailing_zeros()),
        };
        println!(
            "{:<7} {:6.3} {:6.3} {:13.3} {:10.2} {:13.2} {:13.3} {:>10} {:10.3}",
            label,
            v.ks_statistic,
            v.ks_p_value,
            v.bip_match_fraction,
            v.monte_carlo_z_mm * 1e3,
            v.sensor_noise_z_mm * 1e3,
            v.highest_ks_p_value,
            v.converged,
            s_per_profile
        );
        rows.push(json!({
            "photons": n,
            "verdict": v,
            "wall_s_per_profile": s_per_profile,
            "mean_photons": mean_photons,
            "photons_traced": traced,
            "bip_error_mm": independent.iter().map(|s| s.bip_error_mm).collect::<Vec<_>>(),
            "highest_bip_error_mm": independent.iter().map(|s| s.highest.error_mm).collect::<Vec<_>>(),
            "same_seed_bip_shift_mm": reference.iter().zip(&same).map(|(a, b)| bip_shift_mm(a, b)).collect::<Vec<_>>(),
        }));
    }
    let twin = std::fs::read_to_string(&summary_file)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .map(|v| v["twin"].clone())
        .unwrap_or(serde_json::Value::Null);
    let summary = json!({
        "scene": scene_path,
        "scan_angle_deg": angle_deg.parse::<f64>().unwrap(),
        "poses": POSES,
        "reference_photons": REFERENCE_PHOTONS,
        "seeds": {"reference": SEEDS_A, "reference_other": SEEDS_B, "independent": SEEDS_C},
        "reference_bip_error_mm": reference.iter().map(|s| s.bip_error_mm).collect::<Vec<_>>(),
        "reference_highest_bip_error_mm": reference.iter().chain(&reference_other).map(|s| s.highest.error_mm).collect::<Vec<_>>(),
        "threads": rayon::current_num_threads(),
        "rows": merged_rows(&summary_file, rows),
        "twin": twin,
    });
    std::fs::write(
        &summary_file,
        serde_json::to_string_pretty(&summary).unwrap(),
    )
    .unwrap();
}

/// The rows of an earlier summary in `path` (if any) with this run's rows in place of those of
/// the same photon count (0: adaptive), in photon-count order, the adaptive row last: a run
/// of a few counts adds to the table instead of replacing it.
fn merged_rows(path: &std::path::Path, new: Vec<serde_json::Value>) -> Vec<serde_json::Value> {
    let key = |r: &serde_json::Value| match r["photons"].as_u64() {
        Some(0) | None => u64::MAX,
        Some(n) => n,
    };
    let earlier: Vec<serde_json::Value> = std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["rows"].as_array().cloned())
        .unwrap_or_default();
    let replaced: Vec<u64> = new.iter().map(key).collect();
    let mut rows: Vec<serde_json::Value> = earlier
        .into_iter()
        .filter(|r| !replaced.contains(&key(r)))
        .chain(new)
        .collect();
    rows.sort_by_key(key);
    rows
}

/// How far the edge-line BIP of one (pose, seed) moved from the reference's (mm); `None` when
/// either profile has no BIP.
fn bip_shift_mm(reference: &ProfileSample, at_n: &ProfileSample) -> Option<f64> {
    distance_mm(reference.bip_mm?, at_n.bip_mm?)
}

/// The same for the highest-point BIP.
fn highest_shift_mm(reference: &ProfileSample, at_n: &ProfileSample) -> Option<f64> {
    distance_mm(reference.highest.point_mm?, at_n.highest.point_mm?)
}

fn distance_mm(a: [f64; 3], b: [f64; 3]) -> Option<f64> {
    Some(((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt())
}
