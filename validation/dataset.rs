//! `glassscan dataset`, `merge`, `verify` and `score` through the binary: a killed run resumes
//! to the same bytes, damaged samples are found by `verify`, refused by `merge` and made again
//! by `--resume`, shards merge to the one-shard dataset, the thread count changes nothing, the
//! randomised draws stay in their ranges, bad input exits with code 2, and scoring the ground
//! truth itself gives 0.
//!
//! Every run is small (6 samples of 2^14 photons on edge_study with the shipped randomisation
//! file); one reference run is shared by the tests that compare against it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use glassscan::dataset::manifest::ManifestLine;
use glassscan::dataset::randomize::Randomization;

const SCENE: &str = "scenes/edge_study.toml";
const RANDOMIZE: &str = "scenes/randomize_edge_study.toml";
const COUNT: usize = 6;

/// The scheduler variables a shard may come from: removed so that a CI job running inside a
/// Slurm array or a Kubernetes indexed job does not shard the tests' runs.
const SHARD_VARIABLES: [&str; 7] = [
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_MAX",
    "SLURM_ARRAY_TASK_STEP",
    "JOB_COMPLETION_INDEX",
    "GLASSSCAN_SHARD_COUNT",
];

fn command(args: &[&str], threads: Option<usize>) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_glassscan"));
    c.args(args).current_dir(env!("CARGO_MANIFEST_DIR"));
    for v in SHARD_VARIABLES {
        c.env_remove(v);
    }
    if let Some(n) = threads {
        c.env("RAYON_NUM_THREADS", n.to_string());
    }
    c
}

fn glassscan(args: &[&str], threads: Option<usize>) -> Output {
    command(args, threads)
        .output()
        .expect("the glassscan binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The arguments of the shared test run, writing into `out`.
fn run_args<'a>(out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "dataset",
        SCENE,
        "--count",
        "6",
        "--out",
        s(out),
        "--seed",
        "3",
        "--photons",
        "16384",
        "--randomize",
        RANDOMIZE,
    ];
    args.extend_from_slice(extra);
    args
}

fn run_ok(out: &Path, extra: &[&str], threads: Option<usize>) {
    let o = glassscan(&run_args(out, extra), threads);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Every file under `dir` (relative path → bytes).
fn tree(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                let rel = path.strip_prefix(root).unwrap().display().to_string();
                out.insert(rel, std::fs::read(&path).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Asserts that two dataset trees hold the same files with the same bytes.
fn assert_same_files(actual: &BTreeMap<String, Vec<u8>>, expected: &BTreeMap<String, Vec<u8>>) {
    let names = |t: &BTreeMap<String, Vec<u8>>| t.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(actual), names(expected));
    for (name, bytes) in expected {
        assert!(actual[name] == *bytes, "{name} differs");
    }
}

/// The reference run (2 threads, uninterrupted, unsharded), made once.
fn reference() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let tmp = tempfile::tempdir().unwrap();
        run_ok(&tmp.path().join("ds"), &[], Some(2));
        tmp
    })
    .path()
}

fn reference_tree() -> BTreeMap<String, Vec<u8>> {
    tree(&reference().join("ds"))
}

fn manifest_lines(path: &Path) -> Vec<ManifestLine> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn dataset_layout_and_ground_truth() {
    let ds = reference().join("ds");
    let files = reference_tree();
    assert!(files.contains_key("run.json") && files.contains_key("manifest.jsonl"));
    let lines = manifest_lines(&ds.join("manifest.jsonl"));
    assert_eq!(
        lines.iter().map(|l| l.index).collect::<Vec<_>>(),
        (0..COUNT as u64).collect::<Vec<_>>()
    );
    for line in &lines {
        for f in [
            "image.png",
            "irradiance.exr",
            "profile.csv",
            "points.ply",
            "ground_truth.json",
            "ideal_profile.csv",
        ] {
            assert!(
                files.contains_key(&format!("{}/{f}", line.directory)),
                "{}/{f}",
                line.directory
            );
        }
        let truth_bytes = &files[&format!("{}/ground_truth.json", line.directory)];
        // One line of compact JSON: one record for `pandas.read_json(..., lines=True)`.
        assert_eq!(
            truth_bytes.iter().filter(|&&b| b == b'\n').count(),
            1,
            "ground_truth.json is one line"
        );
        assert!(truth_bytes.len() < 8_000, "{} bytes", truth_bytes.len());
        let truth: serde_json::Value = serde_json::from_slice(truth_bytes).unwrap();
        assert_eq!(truth["index"], line.index);
        assert_eq!(truth["noise_seed"], line.seed);
        // Every pose also as a matrix and a quaternion that agree with each other.
        let pose = &truth["sensor_pose"];
        let floats = |key: &str| -> Vec<f64> {
            let values = pose[key].as_array().unwrap().iter();
            values.map(|v| v.as_f64().unwrap()).collect()
        };
        let (m, q) = (floats("matrix_mm"), floats("quaternion_wxyz"));
        let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
        assert!(w >= 0.0 && (w * w + x * x + y * y + z * z - 1.0).abs() < 1e-12);
        // R[0][0] and R[1][2] from the quaternion (Shoemake).
        assert!((m[0] - (1.0 - 2.0 * (y * y + z * z))).abs() < 1e-12);
        assert!((m[6] - 2.0 * (y * z - w * x)).abs() < 1e-12);
        for k in 0..3 {
            assert_eq!(m[4 * k + 3], pose["translation_mm"][k].as_f64().unwrap());
        }
        // p_e lies on the laser plane, near the aim point at the standoff (257.5 mm) but moved
        // along the line by the pose jitter (≤ 3 mm and 1°).
        let pe = truth["edge_point_sensor_mm"]
            .as_array()
            .expect("p_e exists");
        let (x, z) = (pe[0].as_f64().unwrap(), pe[1].as_f64().unwrap());
        assert!(
            x.abs() < 10.0 && (z - 257.5).abs() < 10.0,
            "p_e at ({x}, {z})"
        );
        // The ideal profile crosses the pane and the table, and labels them (at a low scan
        // angle the far end of the fan passes beyond the table and misses).
        let ideal_path = ds.join(&line.directory).join("ideal_profile.csv");
        let text = std::fs::read_to_string(&ideal_path).unwrap();
        let ideal = glassscan::io::csv_read::CsvText::parse(&ideal_path, &text).unwrap();
        assert_eq!(
            ideal.header,
            [
                "ray",
                "fan_angle_deg",
                "x_mm",
                "z_mm",
                "object",
                "label",
                "part",
                "glass"
            ]
        );
        assert_eq!(
            ideal.rows.len() as u64,
            truth["ideal_points"].as_u64().unwrap()
        );
        assert!(ideal.rows.len() > 320, "{} ideal points", ideal.rows.len());
        for object in ["pane", "table"] {
            assert!(ideal.rows.iter().any(|r| r.fields[4] == object), "{object}");
        }
        assert!(ideal
            .rows
            .iter()
            .any(|r| r.fields[7] == "true" && r.fields[6] == "top_face"));
        let ply =
            glassscan::io::ply::read_ply(&ds.join(&line.directory).join("points.ply")).unwrap();
        assert_eq!(ply.points.len(), line.valid_points);
    }
}

#[test]
fn randomized_draws_stay_in_their_ranges_and_vary() {
    let ranges = Randomization::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join(RANDOMIZE))
        .unwrap()
        .ranges;
    assert!(ranges.len() >= 10);
    let lines = manifest_lines(&reference().join("ds/manifest.jsonl"));
    for (param, range) in &ranges {
        let values: Vec<f64> = lines.iter().map(|l| l.parameters[param.key()]).collect();
        for v in &values {
            assert!(
                (range.min..range.max).contains(v),
                "{} = {v} outside [{}, {})",
                param.key(),
                range.min,
                range.max
            );
        }
        assert!(
            values.iter().any(|v| *v != values[0]),
            "{} does not vary: {values:?}",
            param.key()
        );
    }
    let seeds: std::collections::BTreeSet<u64> = lines.iter().map(|l| l.seed).collect();
    assert_eq!(seeds.len(), COUNT, "every sample has its own noise seed");
}

#[test]
fn thread_count_does_not_change_a_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    run_ok(&out, &[], Some(1));
    assert_same_files(&tree(&out), &reference_tree());
}

#[test]
fn ply_ascii_writes_the_same_cloud_as_text_and_a_resume_must_repeat_it() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    let args = [
        "dataset",
        SCENE,
        "--count",
        "1",
        "--out",
        s(&out),
        "--seed",
        "3",
        "--photons",
        "16384",
        "--ply-ascii",
    ];
    let o = glassscan(&args, None);
    assert!(o.status.success(), "{}", stderr(&o));
    let ply = out.join("sample_000000/points.ply");
    let text = std::fs::read_to_string(&ply).expect("an ASCII PLY is text");
    assert!(
        text.starts_with("ply\nformat ascii 1.0\n"),
        "{}",
        &text[..40]
    );
    let cloud = glassscan::io::ply::read_ply(&ply).unwrap();
    assert!(!cloud.points.is_empty());
    assert_eq!(cloud.labels.len(), cloud.points.len());
    assert_eq!(cloud.intensities.len(), cloud.points.len());
    // The same run without the flag is another run: refused, nothing touched.
    let before = tree(&out);
    let o = glassscan(
        &args[..args.len() - 1]
            .iter()
            .copied()
            .chain(["--resume"])
            .collect::<Vec<_>>(),
        None,
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("ply_ascii true there, false here"),
        "{}",
        stderr(&o)
    );
    assert_same_files(&tree(&out), &before);
}

/// Waits until `manifest` holds at least one line, then kills `child` with SIGKILL; returns
/// the number of lines it held.
fn kill_after_first_sample(child: &mut Child, manifest: &Path) -> usize {
    let started = Instant::now();
    loop {
        let lines = std::fs::read_to_string(manifest)
            .map(|t| t.lines().count())
            .unwrap_or(0);
        if lines >= 1 {
            child.kill().unwrap();
            child.wait().unwrap();
            return lines;
        }
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before its first sample was recorded");
        }
        assert!(started.elapsed() < Duration::from_secs(120), "no sample");
        std::thread::sleep(Duration::from_millis(2));
    }
}

#[test]
fn killed_run_resumes_to_the_same_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    let args = run_args(&out, &[]);
    let mut child = command(&args, Some(1))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let recorded = kill_after_first_sample(&mut child, &out.join("manifest.jsonl"));
    assert!(
        recorded < COUNT,
        "the run finished before it could be killed"
    );
    // Without --resume the directory is refused, and nothing in it changes.
    let before = tree(&out);
    let o = glassscan(&args, None);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--resume"), "{}", stderr(&o));
    assert_same_files(&tree(&out), &before);

    run_ok(&out, &["--resume"], Some(2));
    let resumed = tree(&out);
    assert!(
        resumed.keys().all(|k| !k.contains(".tmp-")),
        "temporaries left"
    );
    assert_same_files(&resumed, &reference_tree());
    // Resuming a finished run makes nothing and changes nothing.
    let o = glassscan(&run_args(&out, &["--resume", "--json"]), None);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["made"], 0);
    assert_eq!(summary["kept"], COUNT);
    assert_same_files(&tree(&out), &reference_tree());
}

/// Copies the directory tree `from` to `to`.
fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            copy_tree(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

/// Damages a finished dataset in every way the manifest's records must catch; returns the
/// damaged paths (relative to `ds`).
fn damage_dataset(ds: &Path) -> Vec<&'static str> {
    let png = ds.join("sample_000001/image.png");
    let len = std::fs::metadata(&png).unwrap().len();
    std::fs::OpenOptions::new()
        .write(true)
        .open(&png)
        .unwrap()
        .set_len(len / 2)
        .unwrap();
    std::fs::remove_file(ds.join("sample_000002/ground_truth.json")).unwrap();
    std::fs::write(ds.join("sample_000003/profile.csv"), "junk\n").unwrap();
    std::fs::remove_dir_all(ds.join("sample_000004")).unwrap();
    // Sample 5's line now points at another sample's files (same names, other content), as
    // after a copy from another run.
    std::fs::remove_dir_all(ds.join("sample_000005")).unwrap();
    copy_tree(&ds.join("sample_000000"), &ds.join("sample_000005"));
    vec![
        "sample_000001/image.png",
        "sample_000002/ground_truth.json",
        "sample_000003/profile.csv",
        "sample_000004",
        "sample_000005/image.png",
    ]
}

#[test]
fn damaged_samples_are_found_by_verify_and_made_again_by_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    copy_tree(&reference().join("ds"), &out);
    let o = glassscan(&["verify", s(&out)], None);
    assert!(o.status.success(), "{}", stderr(&o));

    let damaged = damage_dataset(&out);
    let o = glassscan(&["verify", s(&out)], None);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let report = String::from_utf8_lossy(&o.stdout).into_owned();
    for d in &damaged {
        assert!(report.contains(d), "verify does not name {d}:\n{report}");
    }
    assert!(stderr(&o).contains("5 damaged"), "{}", stderr(&o));

    // --resume makes exactly the damaged samples again, byte for byte as the first run did.
    let o = glassscan(&run_args(&out, &["--resume", "--json"]), None);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["damaged_samples"], 5, "{summary}");
    assert_eq!(
        (summary["kept"].clone(), summary["made"].clone()),
        (1.into(), 5.into())
    );
    assert_same_files(&tree(&out), &reference_tree());
    let o = glassscan(&["verify", s(&out)], None);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn two_shards_merged_equal_one_shard() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    run_ok(&out, &["--shard", "0/2"], None);
    // With a shard missing, merge names the missing samples.
    let o = glassscan(&["merge", s(&out)], None);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("missing 1, 3, 5"), "{}", stderr(&o));
    // The second shard comes from a Slurm job array's environment.
    let mut c = command(&run_args(&out, &[]), None);
    c.env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "2");
    let o = c.output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = glassscan(&["merge", s(&out)], None);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut merged = tree(&out);
    for k in 0..2 {
        let name = format!("manifest-shard-{k}-of-2.jsonl");
        assert_eq!(manifest_lines(&out.join(&name)).len(), COUNT / 2);
        merged.remove(&name);
    }
    assert_same_files(&merged, &reference_tree());

    // A damaged shard copy is refused, every damaged file named, the merged manifest kept.
    let before = std::fs::read(out.join("manifest.jsonl")).unwrap();
    let damaged = damage_dataset(&out);
    let o = glassscan(&["merge", s(&out)], None);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    for d in &damaged {
        assert!(
            stderr(&o).contains(d),
            "merge does not name {d}:\n{}",
            stderr(&o)
        );
    }
    assert_eq!(std::fs::read(out.join("manifest.jsonl")).unwrap(), before);
}

#[test]
fn merge_writes_over_no_file_a_dataset_did_not_write() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    run_ok(&out, &["--shard", "0/2"], None);
    run_ok(&out, &["--shard", "1/2"], None);
    // A directory of someone else's manifest.jsonl (no run.json beside it), and a file.
    let other = tmp.path().join("other");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("manifest.jsonl"), "someone's lines\n").unwrap();
    let file = tmp.path().join("notes.txt");
    std::fs::write(&file, "notes\n").unwrap();
    for (target, says) in [
        (
            other.join("manifest.jsonl"),
            "not a glassscan dataset's manifest",
        ),
        (file.clone(), "expected a directory"),
    ] {
        let dir = if target == file { &file } else { &other };
        let o = glassscan(&["merge", s(&out), "--out", s(dir)], None);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).contains(s(&target)) && stderr(&o).contains(says),
            "{}",
            stderr(&o)
        );
    }
    assert_eq!(
        std::fs::read(other.join("manifest.jsonl")).unwrap(),
        b"someone's lines\n"
    );
    assert!(!other.join("run.json").exists());
    assert_eq!(std::fs::read(&file).unwrap(), b"notes\n");
    // Merged once, merged again: the dataset's own manifest is replaced.
    for _ in 0..2 {
        let o = glassscan(&["merge", s(&out)], None);
        assert!(o.status.success(), "{}", stderr(&o));
    }
}

#[test]
fn bad_input_exits_with_code_2_and_names_the_culprit() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("x");
    let bad_keys = tmp.path().join("bad_keys.toml");
    std::fs::write(
        &bad_keys,
        "scan_angle_deg = [10, 40]\nthicknes_mm = [3, 5]\n",
    )
    .unwrap();
    let bad_order = tmp.path().join("bad_order.toml");
    std::fs::write(&bad_order, "exposure_ms = [2, 0.5]\n").unwrap();
    let base = |extra: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = [
            "dataset",
            SCENE,
            "--count",
            "2",
            "--out",
            s(&out),
            "--photons",
            "4096",
        ]
        .iter()
        .map(|a| a.to_string())
        .collect();
        v.extend(extra.iter().map(|a| a.to_string()));
        v
    };
    let cases: Vec<(Vec<String>, Vec<&str>)> = vec![
        (
            base(&["--randomize", s(&bad_keys)]),
            vec!["bad_keys.toml:2:1", "thicknes_mm", "unknown key"],
        ),
        (
            base(&["--randomize", s(&bad_order)]),
            vec!["bad_order.toml:1:1", "exposure_ms", "min ≤ max"],
        ),
        (base(&["--shard", "2/2"]), vec!["--shard", "K < N"]),
        (base(&["--count", "0"]), vec!["--count"]),
    ];
    for (args, expected) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = glassscan(&args, None);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        for e in expected {
            assert!(stderr(&o).contains(e), "{args:?}: {}", stderr(&o));
        }
        assert!(!out.exists(), "{args:?} created the output directory");
    }
    // A bad scheduler environment names its variable.
    let args = base(&[]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let mut c = command(&args, None);
    c.env("SLURM_ARRAY_TASK_ID", "3");
    let o = c.output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("SLURM_ARRAY_TASK_COUNT"),
        "{}",
        stderr(&o)
    );
    // A non-empty output directory is refused without --resume, and left as it was.
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("precious.txt"), "keep me").unwrap();
    for extra in [&[][..], &["--resume"][..]] {
        let args = base(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = glassscan(&args, None);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("not a glassscan dataset"),
            "{}",
            stderr(&o)
        );
        assert_eq!(tree(&out).into_keys().collect::<Vec<_>>(), ["precious.txt"]);
    }
}

/// Writes a BIPs CSV with one row per sample of `lines` that has p_e, shifted by `dx_mm`,
/// leaving out the samples in `skip`.
fn bips_csv(path: &Path, lines: &[ManifestLine], dx_mm: f64, skip: &[u64]) {
    let mut text = String::from("sample,x_mm,y_mm,z_mm,rule\n");
    for l in lines.iter().filter(|l| !skip.contains(&l.index)) {
        let p = l.edge_point_mm.unwrap();
        text.push_str(&format!(
            "{},{},{},{},highest\n",
            l.index,
            p[0] + dx_mm,
            p[1],
            p[2]
        ));
    }
    std::fs::write(path, text).unwrap();
}

fn score(dataset: &Path, bips: &Path) -> serde_json::Value {
    let o = glassscan(&["score", s(dataset), s(bips), "--json"], None);
    assert!(o.status.success(), "{}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn score_measures_bips_against_the_ground_truth() {
    let ds: PathBuf = reference().join("ds");
    let lines = manifest_lines(&ds.join("manifest.jsonl"));
    let tmp = tempfile::tempdir().unwrap();
    let bips = tmp.path().join("bips.csv");

    bips_csv(&bips, &lines, 0.0, &[]);
    let r = score(&ds, &bips);
    assert_eq!(r["scored"], COUNT);
    assert_eq!(r["mean_mm"], 0.0);
    assert_eq!(r["max_mm"], 0.0);
    assert_eq!(r["missing"].as_array().unwrap().len(), 0);

    bips_csv(&bips, &lines, 1.0, &[2]);
    let r = score(&ds, &bips);
    assert_eq!(r["scored"], COUNT - 1);
    for key in ["mean_mm", "max_mm"] {
        assert!((r[key].as_f64().unwrap() - 1.0).abs() < 1e-9, "{key}: {r}");
    }
    assert!(r["std_mm"].as_f64().unwrap() < 1e-9);
    assert_eq!(r["missing"], serde_json::json!([2]));

    std::fs::write(&bips, "sample,x_mm,y_mm,z_mm\n0,1,2,3\n1,1,oops,3\n").unwrap();
    let o = glassscan(&["score", s(&ds), s(&bips)], None);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("bips.csv:3: column y_mm: expected a finite number"),
        "{}",
        stderr(&o)
    );
}
