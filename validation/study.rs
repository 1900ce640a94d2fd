//! The study commands end to end (issue 6): `glassscan study scan-angle` and `glassscan sweep`
//! on the edge-study scenes with few photons and poses: the JSON they print, the files and
//! plots they write, bit-identical results for any thread count, and bad flags.

use std::path::Path;
use std::process::{Command, Output};

use serde_json::Value;

fn glassscan(args: &[&str], threads: Option<&str>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_glassscan"));
    c.args(args).current_dir(env!("CARGO_MANIFEST_DIR"));
    if let Some(t) = threads {
        c.env("RAYON_NUM_THREADS", t);
    }
    c.output().expect("the glassscan binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json_of(o: &Output) -> Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_slice(&o.stdout).expect("--json prints JSON")
}

fn is_stats(v: &Value) -> bool {
    ["mean", "std", "max"]
        .iter()
        .all(|k| v[k].is_number() || v[k].is_null())
        && v["mean"].is_number()
}

fn assert_plot(dir: &Path, stem: &str) {
    let png = image::open(dir.join(format!("{stem}.png")))
        .unwrap_or_else(|e| panic!("{stem}.png does not decode: {e}"));
    assert!(png.width() > 100 && png.height() > 100);
    let svg = std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap();
    assert!(svg.starts_with("<svg") && svg.len() > 1000, "{stem}.svg");
}

#[test]
fn study_scan_angle_prints_the_summary_and_writes_tables_and_plots() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("study");
    let out_s = out.to_str().unwrap();
    let args = [
        "study",
        "scan-angle",
        "scenes/edge_study.toml",
        "--angles-deg",
        "10,40",
        "--positions",
        "1",
        "--sweep-deg",
        "20:40:20",
        "--exposures-ms",
        "0.15,0.5",
        "--map-arris-mm",
        "0,0.8",
        "--map-roughness",
        "0.3",
        "--map-positions",
        "1",
        "--photons",
        "16384",
        "--out",
        out_s,
        "--json",
    ];
    let j = json_of(&glassscan(&args, None));
    let angles = j["angles"].as_array().unwrap();
    assert_eq!(angles.len(), 2);
    for (a, deg) in angles.iter().zip([10.0, 40.0]) {
        assert_eq!(a["scan_angle_deg"].as_f64(), Some(deg));
        assert!(is_stats(&a["bip_error_mm"]), "{a}");
        let vf = a["valid_fraction"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&vf));
        for rule in ["highest", "edge-line"] {
            assert!(a["bip_error_mm_by_rule"][rule].is_object(), "{rule}");
        }
        // The paper's rule is the top-level one.
        assert_eq!(
            a["bip_error_mm"]["mean"],
            a["bip_error_mm_by_rule"]["highest"]["mean"]
        );
        for v in ["tape", "cover", "bare"] {
            assert!(
                a["variants"][v]["valid_points"].as_u64().unwrap() > 0,
                "{v}"
            );
        }
    }
    // The sweep reuses 40° and simulates 20°.
    let sweep: Vec<f64> = j["sweep"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["scan_angle_deg"].as_f64().unwrap())
        .collect();
    assert_eq!(sweep, [20.0, 40.0]);
    assert_eq!(j["sweep"][1]["bip_error_mm"], angles[1]["bip_error_mm"]);

    let points = std::fs::read_to_string(out.join("points_40deg.csv")).unwrap();
    assert!(points.starts_with("variant,scan_angle_deg,position,out_mm,up_mm,intensity,label\n"));
    for v in ["tape,", "cover,", "bare,"] {
        assert!(points.lines().any(|l| l.starts_with(v)), "{v}");
    }
    for f in [
        "summary.csv",
        "sweep.csv",
        "summary.json",
        "points_10deg.csv",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    for stem in [
        "edge_10deg",
        "edge_40deg",
        "bip_error_vs_angle",
        "exposure_axis_edge-line",
        "finding_map_highest_0.15ms",
        "finding_map_edge-line_0.5ms",
    ] {
        assert_plot(&out, stem);
    }
    // The exposure axis: one row per angle, exposure and rule; the map: one row per cell,
    // exposure and rule, and the region where the paper's finding holds per rule and exposure.
    assert_eq!(j["exposures_ms"], serde_json::json!([0.15, 0.5]));
    let axis = std::fs::read_to_string(out.join("exposure_axis.csv")).unwrap();
    assert_eq!(axis.lines().count(), 1 + 2 * 2 * 2, "{axis}");
    let map = std::fs::read_to_string(out.join("finding_map.csv")).unwrap();
    assert_eq!(map.lines().count(), 1 + 2 * 2 * 2, "{map}");
    let cells = j["finding_map"]["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 2);
    for rule in ["highest", "edge-line"] {
        for ms in ["0.15", "0.5"] {
            assert!(
                j["finding_map"]["holds"][rule][ms].is_array(),
                "{rule} {ms}"
            );
        }
    }
    let written: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(written["angles"], j["angles"]);

    // The directory now holds a run: refused without --force, and nothing is touched.
    let before = std::fs::read(out.join("summary.csv")).unwrap();
    let o = glassscan(&args, None);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    assert_eq!(std::fs::read(out.join("summary.csv")).unwrap(), before);
}

#[test]
fn study_scan_angle_runs_without_missing_variants_and_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("lonely_pane.toml");
    std::fs::copy("scenes/edge_study.toml", &scene).unwrap();
    let o = glassscan(
        &[
            "study",
            "scan-angle",
            scene.to_str().unwrap(),
            "--angles-deg",
            "45",
            "--positions",
            "1",
            "--no-sweep",
            "--no-map",
            "--photons",
            "8192",
            "--json",
        ],
        None,
    );
    let j = json_of(&o);
    assert!(j["scenes"]["tape"].is_null() && j["scenes"]["cover"].is_null());
    let notes = j["notes"].to_string();
    assert!(notes.contains("lonely_pane_tape.toml") && notes.contains("lonely_pane_cover.toml"));
    let a = &j["angles"][0];
    assert!(a["variants"]["bare"].is_object() && a["variants"]["tape"].is_null());
    assert!(j["sweep"].as_array().unwrap().is_empty());
}

/// A small study's JSON and CSV tables, run on `threads` threads: two positions, so its poses
/// run side by side (`study::side_by_side`), in the edge plot, the sweep and the finding map.
fn small_study(threads: &str) -> (Value, Vec<(String, String)>) {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("study");
    let args = [
        "study",
        "scan-angle",
        "scenes/edge_study.toml",
        "--angles-deg",
        "40",
        "--positions",
        "2",
        "--sweep-deg",
        "20:40:20",
        "--exposures-ms",
        "0.15,0.5",
        "--map-arris-mm",
        "0.8",
        "--map-roughness",
        "0.3",
        "--map-positions",
        "2",
        "--photons",
        "16384",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ];
    let mut j = json_of(&glassscan(&args, Some(threads)));
    let o = j.as_object_mut().unwrap();
    o.remove("elapsed_s");
    o.remove("files");
    let mut tables: Vec<(String, String)> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    tables.sort();
    (j, tables)
}

#[test]
fn study_scan_angle_is_bit_identical_for_any_thread_count() {
    let (json_1, tables_1) = small_study("1");
    let (json_3, tables_3) = small_study("3");
    assert!(tables_1.len() >= 4, "{:?}", tables_1.iter().map(|t| &t.0));
    assert_eq!(json_1, json_3, "1 and 3 threads differ");
    assert_eq!(tables_1, tables_3, "1 and 3 threads wrote other tables");
}

/// The sweep's JSON without its wall-clock time.
fn sweep_json(threads: &str, out: Option<&Path>) -> Value {
    let mut args = vec![
        "sweep",
        "scenes/edge_study.toml",
        "--scan-angle-deg",
        "10,40",
        "--exposure-ms",
        "0.1,0.5",
        "--poses",
        "2",
        "--photons",
        "16384",
        "--json",
    ];
    if let Some(out) = out {
        args.extend(["--out", out.to_str().unwrap()]);
    }
    let mut j = json_of(&glassscan(&args, Some(threads)));
    j.as_object_mut().unwrap().remove("elapsed_s");
    j.as_object_mut().unwrap().remove("files");
    j
}

#[test]
fn sweep_prints_one_row_per_cell_and_is_bit_identical_for_any_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("sweep");
    let one = sweep_json("1", None);
    let three = sweep_json("3", Some(&out));
    assert_eq!(one, three, "1 and 3 threads differ");
    let cells = one["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 4);
    let settings: Vec<(f64, f64)> = cells
        .iter()
        .map(|c| {
            (
                c["scan_angle_deg"].as_f64().unwrap().round(),
                c["exposure_ms"].as_f64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        settings,
        [(10.0, 0.1), (10.0, 0.5), (40.0, 0.1), (40.0, 0.5)]
    );
    for c in cells {
        for k in [
            "valid_fraction",
            "saturated_pixel_fraction",
            "wrong_surface_fraction",
        ] {
            let v = c[k].as_f64().unwrap_or_else(|| panic!("{k}: {c}"));
            assert!((0.0..=1.0).contains(&v), "{k} = {v}");
        }
        assert!(c["bip_error_mm_by_rule"]["edge-line"].is_object());
        assert_eq!(c["threshold"], cells[0]["threshold"]);
    }
    // A longer exposure saturates at least as many pixels (same light, same noise draws).
    assert!(
        cells[1]["saturated_pixel_fraction"].as_f64()
            >= cells[0]["saturated_pixel_fraction"].as_f64()
    );
    assert!(out.join("cells.csv").is_file() && out.join("cells.json").is_file());
    for rule in ["highest", "edge-line"] {
        let threshold = cells[0]["threshold"].as_str().unwrap();
        let peak = cells[0]["peak_select"].as_str().unwrap();
        assert_plot(&out, &format!("heat_{rule}_threshold-{threshold}_{peak}"));
    }
}

#[test]
fn bad_study_and_sweep_flags_exit_2_naming_the_flag() {
    let sweep = |extra: &[&str]| {
        let mut a = vec!["sweep", "scenes/edge_study.toml"];
        a.extend(extra);
        a.iter().map(|s| s.to_string()).collect::<Vec<_>>()
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            sweep(&["--scan-angle-deg", "", "--exposure-ms", "0.5"]),
            "--scan-angle-deg",
        ),
        (
            sweep(&["--scan-angle-deg", "0", "--exposure-ms", "0.5"]),
            "--scan-angle-deg",
        ),
        (
            sweep(&["--scan-angle-deg", "10,95", "--exposure-ms", "0.5"]),
            "--scan-angle-deg",
        ),
        (
            sweep(&["--scan-angle-deg", "40", "--exposure-ms", ""]),
            "--exposure-ms",
        ),
        (
            sweep(&["--scan-angle-deg", "40", "--exposure-ms", "0,1"]),
            "--exposure-ms",
        ),
        (
            sweep(&[
                "--scan-angle-deg",
                "40",
                "--exposure-ms",
                "0.5",
                "--peak-select",
                "best",
            ]),
            "--peak-select",
        ),
        (
            sweep(&[
                "--scan-angle-deg",
                "40",
                "--exposure-ms",
                "0.5",
                "--threshold",
                "5000",
            ]),
            "--threshold",
        ),
        (
            ["study", "scan-angle", "--angles-deg", "40,95"]
                .map(String::from)
                .to_vec(),
            "--angles-deg",
        ),
        (
            ["study", "scan-angle", "--angles-deg", ""]
                .map(String::from)
                .to_vec(),
            "--angles-deg",
        ),
        (
            ["study", "scan-angle", "--sweep-deg", "5:95:5"]
                .map(String::from)
                .to_vec(),
            "--sweep-deg",
        ),
        (
            ["study", "scan-angle", "--positions", "0"]
                .map(String::from)
                .to_vec(),
            "--positions",
        ),
    ];
    for (args, flag) in cases {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = glassscan(&a, None);
        assert_eq!(o.status.code(), Some(2), "{a:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(flag), "{a:?}: {}", stderr(&o));
    }
}
