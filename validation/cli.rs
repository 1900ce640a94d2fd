//! The command line on good and bad input: exit codes, messages, output-directory safety.

use std::path::{Path, PathBuf};

use crate::binary::{glassscan, stderr};

fn out_dir(tmp: &tempfile::TempDir, name: &str) -> PathBuf {
    tmp.path().join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn scan_writes_images_profiles_and_manifest_and_prints_json() {
    let tmp = tempfile::tempdir().unwrap();
    let out = out_dir(&tmp, "run");
    let o = glassscan(&[
        "scan",
        "scenes/flat_opaque.toml",
        "--out",
        s(&out),
        "--poses",
        "2",
        "--photons",
        "20000",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).expect("--json prints JSON");
    assert_eq!(summary["poses"].as_array().unwrap().len(), 2);
    for f in [
        "pose_000.png",
        "pose_000.exr",
        "pose_000_profile.csv",
        "pose_001.png",
        "manifest.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["seed"], 1);
    assert_eq!(manifest["poses"][1]["index"], 1);
    assert!(manifest["version"].is_string() && manifest["scene"].is_string());
}

#[test]
fn refuses_a_non_empty_output_directory_without_force_and_keeps_its_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = out_dir(&tmp, "busy");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("precious.txt"), "keep me").unwrap();
    let o = glassscan(&[
        "scan",
        "scenes/flat_opaque.toml",
        "--out",
        s(&out),
        "--photons",
        "5000",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(out.join("precious.txt")).unwrap(),
        "keep me"
    );
    // Files of an earlier 4-pose run.
    for name in ["pose_003.png", "pose_003.exr", "pose_003_profile.csv"] {
        std::fs::write(out.join(name), "old").unwrap();
    }
    let o = glassscan(&[
        "scan",
        "scenes/flat_opaque.toml",
        "--out",
        s(&out),
        "--photons",
        "5000",
        "--poses",
        "1",
        "--force",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(out.join("precious.txt")).unwrap(),
        "keep me"
    );
    // A --force run of fewer poses leaves only its own pose files beside the user's file.
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "manifest.json",
            "pose_000.exr",
            "pose_000.png",
            "pose_000_profile.csv",
            "precious.txt"
        ]
    );
}

/// Numbers beyond what the simulator can hold (f32 geometry, the sampler's lattice, memory):
/// each once crashed or aborted (exit 101 or 134); now each is bad input, caught before work.
fn limits_cases(out: &Path) -> Vec<(Vec<&'static str>, &'static str)> {
    let out: &'static str = Box::leak(out.display().to_string().into_boxed_str());
    let scan = |extra: &[&'static str]| {
        let mut a = vec!["scan", "scenes/flat_opaque.toml", "--out", out];
        a.extend_from_slice(extra);
        a
    };
    vec![
        (
            scan(&["--poses", "4000000000"]),
            "--poses must be in 1..=1000000",
        ),
        // The scene file caps scan.poses at 10⁶; the flag has the same cap.
        (
            scan(&["--poses", "2000000"]),
            "--poses must be in 1..=1000000",
        ),
        (
            scan(&["--photons", "18446744073709551615"]),
            "--photons must be in 1000..=",
        ),
        (
            scan(&["--max-depth", "100000"]),
            "--max-depth must be in 1..=4096",
        ),
        // A negative value reaches the range check instead of clap's "use '-- -5'" tip.
        (
            scan(&["--scan-angle-deg", "-5"]),
            "must be in (0, 90], got -5",
        ),
        (
            vec!["locate", "scenes/flat_panel.toml", "--poses", "4000000000"],
            "--poses must be in 3..=1000000",
        ),
        (
            vec![
                "sweep",
                "scenes/flat_panel.toml",
                "--scan-angle-deg",
                "45",
                "--exposure-ms",
                "0.5",
                "--poses",
                "4000000000",
            ],
            "--poses must be in 1..=1000000",
        ),
        (
            vec![
                "dataset",
                "scenes/edge_study.toml",
                "--out",
                out,
                "--count",
                "1000000000000",
            ],
            "--count must be in 1..=100000000",
        ),
    ]
}

#[test]
fn a_length_beyond_f32_geometry_is_bad_input_not_a_panic() {
    // thickness_mm = 1e300 once panicked inside the BVH build (exit 101).
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/flat_panel.toml"),
    )
    .unwrap();
    let (before, after) = text.split_once("thickness_mm = ").expect("a thickness");
    let rest = after.split_once('\n').map_or("", |(_, r)| r);
    let scene = tmp.path().join("huge.toml");
    std::fs::write(&scene, format!("{before}thickness_mm = 1e300\n{rest}")).unwrap();
    let out = out_dir(&tmp, "x");
    let o = glassscan(&["scan", s(&scene), "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("thickness_mm must be at most 1e5 in magnitude (100 m), got 1e300"),
        "{}",
        stderr(&o)
    );
    let points = tmp.path().join("far.csv");
    std::fs::write(&points, "x_mm,y_mm,z_mm\n1e300,0,0\n1,2,3\n4,5,6\n").unwrap();
    let o = glassscan(&["register", "scenes/flat_panel.toml", s(&points)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("far.csv:2: column x_mm"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn an_unwritable_output_directory_is_refused_before_any_work() {
    // Root may write anywhere an ordinary directory allows, but never into /proc/1.
    let proc_dir = std::path::Path::new("/proc/1");
    if !proc_dir.is_dir() {
        return;
    }
    let started = std::time::Instant::now();
    let o = glassscan(&[
        "scan",
        "scenes/flat_panel.toml",
        "--out",
        "/proc/1",
        "--force",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("is not writable"), "{}", stderr(&o));
    // Refused before the (multi-second) simulation of the scene's poses.
    assert!(started.elapsed().as_secs_f64() < 30.0);
}

#[test]
fn bad_input_exits_with_code_2_and_a_clear_message() {
    let tmp = tempfile::tempdir().unwrap();
    let out = out_dir(&tmp, "x");
    let cases: &[(&[&str], &str)] = &[
        (
            &["scan", "scenes/does_not_exist.toml", "--out", s(&out)],
            "does_not_exist.toml",
        ),
        (
            &[
                "scan",
                "scenes/flat_opaque.toml",
                "--out",
                s(&out),
                "--poses",
                "0",
            ],
            "--poses",
        ),
        (
            &[
                "scan",
                "scenes/flat_opaque.toml",
                "--out",
                s(&out),
                "--scan-angle-deg",
                "120",
            ],
            "--scan-angle-deg",
        ),
        (
            &[
                "scan",
                "scenes/flat_opaque.toml",
                "--out",
                s(&out),
                "--exposure-ms=-1",
            ],
            "--exposure-ms",
        ),
        (
            &[
                "scan",
                "scenes/flat_opaque.toml",
                "--out",
                s(&out),
                "--seed",
                "abc",
            ],
            "--seed",
        ),
        (
            &[
                "scan",
                "scenes/flat_opaque.toml",
                "--out",
                s(&out),
                "--max-depth",
                "0",
            ],
            "--max-depth",
        ),
        (
            &[
                "scan",
                "scenes/flat_opaque.toml",
                "--out",
                s(&out),
                "--peak-select",
                "brightest",
            ],
            "largest_area",
        ),
        (
            &[
                "scan",
                "scenes/flat_opaque.toml",
                "--out",
                s(&out),
                "--threshold",
                "5000",
            ],
            "--threshold",
        ),
        (
            &[
                "scan",
                "scenes/flat_opaque.toml",
                "--out",
                s(&out),
                "--sensor-kind",
                "cmosx",
            ],
            "--sensor-kind",
        ),
    ];
    let limits = limits_cases(&out);
    let all = (cases.iter().map(|(a, n)| (a.to_vec(), *n))).chain(limits.iter().cloned());
    for (args, needle) in all {
        let o = glassscan(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(needle),
            "{args:?}: message lacks {needle:?}: {}",
            stderr(&o)
        );
    }
    assert!(!out.exists(), "a failed run created its output directory");
}

#[test]
fn a_bad_scene_file_names_file_line_and_field() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("bad.toml");
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/flat_opaque.toml"),
    )
    .unwrap()
    .replace("thickness_mm = 4", "thickness_mm = -4");
    assert!(
        text.contains("thickness_mm = -4"),
        "flat_opaque.toml has no `thickness_mm = 4` line"
    );
    std::fs::write(&scene, text).unwrap();
    let o = glassscan(&["scan", s(&scene), "--out", s(&out_dir(&tmp, "y"))]);
    assert_eq!(o.status.code(), Some(2));
    let msg = stderr(&o);
    assert!(
        msg.contains("bad.toml:") && msg.contains("thickness_mm") && msg.contains("-4"),
        "{msg}"
    );
}

#[test]
fn locate_runs_the_pipeline_and_prints_the_paper_s_metrics_as_json() {
    let o = glassscan(&[
        "locate",
        "scenes/flat_opaque.toml",
        "--poses",
        "4",
        "--photons",
        "20000",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("--json prints JSON");
    for key in [
        "bip_error_mm",
        "pose_error",
        "task_error_mm",
        "contour_error_mm",
        "converged",
        "timings_s",
    ] {
        assert!(v.get(key).is_some(), "missing {key}: {v}");
    }
    assert_eq!(v["bips"], 4);
    let o = glassscan(&["locate", "scenes/flat_opaque.toml", "--perturb", "1,2,3"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--perturb"), "{}", stderr(&o));
}

#[test]
fn locate_out_files_feed_register_which_gives_the_same_pose() {
    let tmp = tempfile::tempdir().unwrap();
    let out = out_dir(&tmp, "loc");
    let o = glassscan(&[
        "locate",
        "scenes/flat_opaque.toml",
        "--poses",
        "5",
        "--photons",
        "20000",
        "--errors",
        "default",
        "--out",
        s(&out),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["errors"], "default");
    assert_eq!(v["error_sources_on"].as_array().unwrap().len(), 3);
    for f in [
        "bips.csv",
        "bips_paper_rule.csv",
        "poses.json",
        "summary.json",
        "registration_before.ply",
        "registration_after.ply",
        "profiles/pose_004_profile.csv",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    let cloud = glassscan::io::ply::read_ply(&out.join("registration_after.ply")).unwrap();
    assert_eq!(cloud.points.len(), cloud.colors.len());
    // The same BIPs from the same nominal pose: `register` reproduces locate's estimate.
    let r = glassscan(&[
        "register",
        "scenes/flat_opaque.toml",
        s(&out.join("bips.csv")),
        "--json",
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    let reg: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(reg["points"], v["bips"]);
    for (a, b) in [
        (
            &reg["estimate"]["translation_mm"],
            &v["estimate"]["translation_mm"],
        ),
        (
            &reg["estimate"]["rotation_deg"],
            &v["estimate"]["rotation_deg"],
        ),
    ] {
        let (a, b) = (a.as_array().unwrap(), b.as_array().unwrap());
        for k in 0..3 {
            assert!((a[k].as_f64().unwrap() - b[k].as_f64().unwrap()).abs() < 1e-9);
        }
    }
    // The same BIPs as Excel saves them in a decimal-comma locale (byte-order mark, `;`,
    // decimal commas, CRLF) give the same estimate bit for bit.
    let text = std::fs::read_to_string(out.join("bips.csv")).unwrap();
    let excel: String = text
        .lines()
        .map(|l| l.replace(',', ";").replace('.', ",") + "\r\n")
        .collect();
    let excel_path = tmp.path().join("bips_excel.csv");
    std::fs::write(&excel_path, format!("\u{feff}{excel}")).unwrap();
    let r2 = glassscan(&[
        "register",
        "scenes/flat_opaque.toml",
        s(&excel_path),
        "--json",
    ]);
    assert!(r2.status.success(), "{}", stderr(&r2));
    let reg2: serde_json::Value = serde_json::from_slice(&r2.stdout).unwrap();
    assert_eq!(reg2["estimate"], reg["estimate"]);
    // A non-empty --out is refused without --force, and nothing is lost.
    let before = std::fs::read(out.join("bips.csv")).unwrap();
    let o = glassscan(&["locate", "scenes/flat_opaque.toml", "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read(out.join("bips.csv")).unwrap(), before);
}

#[test]
fn locate_and_register_refuse_bad_input_with_exit_2() {
    for (args, needle) in [
        (
            vec!["locate", "scenes/flat_opaque.toml", "--errors", "some"],
            "--errors",
        ),
        (
            vec!["locate", "scenes/flat_opaque.toml", "--bip", "lowest"],
            "--bip",
        ),
        (
            vec!["locate", "scenes/flat_opaque.toml", "--exposure-ms", "0"],
            "--exposure-ms",
        ),
        (
            vec!["locate", "scenes/flat_opaque.toml", "--poses", "2"],
            "--poses",
        ),
    ] {
        let o = glassscan(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("two.csv");
    std::fs::write(&csv, "x_mm,y_mm,z_mm\n1,2,3\n4,5,6\n").unwrap();
    let o = glassscan(&["register", "scenes/flat_opaque.toml", s(&csv)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("two.csv") && stderr(&o).contains("at least 3"),
        "{}",
        stderr(&o)
    );
    std::fs::write(&csv, "x_mm,y_mm,z_mm\n1,2,3\n4,x,6\n").unwrap();
    let o = glassscan(&["register", "scenes/flat_opaque.toml", s(&csv)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("two.csv:3") && stderr(&o).contains("y_mm"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn check_passes_against_its_own_baseline_and_fails_on_a_regression() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("tiny.toml");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/flat_opaque.toml");
    std::fs::write(
        &suite,
        format!(
            "[[case]]\nname = \"plate\"\nscene = {:?}\nposes = 3\nseed = 1\nphotons = 16384\n",
            scene.to_str().unwrap()
        ),
    )
    .unwrap();
    let o = glassscan(&["check", s(&suite), "--update-baseline", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let baseline = tmp.path().join("tiny.baseline.json");
    let o = glassscan(&["check", s(&suite)]);
    assert!(
        o.status.success(),
        "same seed, same metrics: {}",
        stderr(&o)
    );
    // Pretend the BIPs used to be better than they are now.
    let mut b: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&baseline).unwrap()).unwrap();
    let cur = b["cases"]["plate"]["bip_error_mean_mm"].as_f64().unwrap();
    b["cases"]["plate"]["bip_error_mean_mm"] = serde_json::json!(cur - 0.05);
    std::fs::write(&baseline, serde_json::to_vec(&b).unwrap()).unwrap();
    let o = glassscan(&["check", s(&suite)]);
    assert_eq!(o.status.code(), Some(1));
    let table = String::from_utf8_lossy(&o.stdout);
    let line = table
        .lines()
        .find(|l| l.contains("bip_error_mean_mm"))
        .unwrap();
    assert!(line.contains("Regressed"), "{table}");
    assert!(
        stderr(&o).contains("1 metric(s) regressed"),
        "{}",
        stderr(&o)
    );
    // A bad suite is bad input.
    std::fs::write(
        &suite,
        "[[case]]\nname = \"x\"\nscene = \"s.toml\"\nseed = 1\nphotons = 5\n",
    )
    .unwrap();
    let o = glassscan(&["check", s(&suite)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("photons"), "{}", stderr(&o));
}

#[test]
fn physically_empty_or_flooded_frames_are_warned_about_on_stderr_and_in_json() {
    let tmp = tempfile::tempdir().unwrap();
    for (exposure, needle) in [
        ("1e-6", "pose 0: no valid profile point"),
        (
            "1e6",
            "pose 0: 532480 of 532480 pixels (100 %) are saturated",
        ),
    ] {
        let out = out_dir(&tmp, exposure);
        let o = glassscan(&[
            "scan",
            "scenes/flat_opaque.toml",
            "--out",
            s(&out),
            "--poses",
            "1",
            "--photons",
            "5000",
            "--exposure-ms",
            exposure,
            "--json",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            stderr(&o).contains(&format!("warning: {needle}")),
            "{}",
            stderr(&o)
        );
        let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let warnings = summary["poses"][0]["warnings"].as_array().unwrap();
        assert!(
            warnings
                .iter()
                .any(|w| w.as_str().unwrap().contains(needle)),
            "{summary}"
        );
    }
    // The shipped scene at its own settings warns about nothing.
    let out = out_dir(&tmp, "plain");
    let o = glassscan(&[
        "scan",
        "scenes/flat_opaque.toml",
        "--out",
        s(&out),
        "--poses",
        "1",
        "--photons",
        "5000",
    ]);
    assert!(
        o.status.success() && !stderr(&o).contains("warning"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn locate_force_with_fewer_poses_leaves_only_its_own_profiles() {
    let tmp = tempfile::tempdir().unwrap();
    let out = out_dir(&tmp, "loc");
    for (poses, force) in [("4", false), ("3", true)] {
        let mut args = vec![
            "locate",
            "scenes/flat_panel.toml",
            "--poses",
            poses,
            "--photons",
            "4096",
            "--out",
            s(&out),
        ];
        if force {
            args.push("--force");
        }
        let o = glassscan(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let mut names: Vec<String> = std::fs::read_dir(out.join("profiles"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "pose_000_profile.csv",
            "pose_001_profile.csv",
            "pose_002_profile.csv"
        ]
    );
}

#[test]
fn a_mesh_of_implausible_size_is_warned_about_on_stderr_and_in_the_manifest() {
    // flat_panel with a unit-cube glTF read at 20 m (as a file in other units would be), far
    // below the table where no light reaches it.
    let tmp = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/flat_panel.toml")).unwrap();
    let object = format!(
        "[[objects]]\nname = \"part\"\nmaterial = \"soda_lime\"\n\
         mesh = {{ file = \"{}\", scale = 20 }}\npose = {{ translation_mm = [0, 0, -60000] }}\n\n",
        root.join("scenes/meshes/cube.gltf").display()
    );
    let at = text.find("[[objects]]").unwrap();
    let scene = tmp.path().join("big_mesh.toml");
    std::fs::write(&scene, format!("{}{object}{}", &text[..at], &text[at..])).unwrap();
    let out = out_dir(&tmp, "scan");
    let o = glassscan(&[
        "scan",
        s(&scene),
        "--out",
        s(&out),
        "--poses",
        "1",
        "--photons",
        "1000",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    let line = err
        .lines()
        .find(|l| l.starts_with("warning: ") && l.contains("cube.gltf"))
        .unwrap_or_else(|| panic!("no mesh warning in:\n{err}"));
    assert!(line.contains("big_mesh.toml: objects[0].mesh"), "{line}");
    assert!(line.contains("set `scale = 0.001`"), "{line}");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let recorded = manifest["scene_warnings"]
        .as_array()
        .expect("scene_warnings");
    assert_eq!(recorded.len(), 1);
    assert!(line.ends_with(recorded[0].as_str().unwrap()), "{line}");
    // The shipped scenes load without any.
    let o = glassscan(&[
        "scan",
        "scenes/flat_panel.toml",
        "--out",
        s(&out_dir(&tmp, "plain")),
        "--poses",
        "1",
        "--photons",
        "1000",
    ]);
    assert!(
        !stderr(&o).contains("warning: scenes/flat_panel.toml"),
        "{}",
        stderr(&o)
    );
}
