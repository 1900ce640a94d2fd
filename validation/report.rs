//! `glassscan report RUN_DIR` end to end (issue 15): a real study, sweep, locate run and
//! dataset made here with few poses and photons, each turned into its page; the page holds the
//! run's numbers, one inline SVG per figure, the paper's numbers with their sources, and is
//! well-formed; damaged or unknown directories are refused with exit code 2, naming the file,
//! and an earlier page is left as it was. (The page in a real browser: validation/python.)

use std::path::Path;

use glassscan::report::format::num;
use glassscan::report::xml_check::check_well_formed;
use serde_json::Value;

use crate::binary::{glassscan, stderr};

fn run_ok(args: &[&str]) {
    let o = glassscan(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
}

/// `report DIR` fails with exit code 2; its message.
fn refused(dir: &Path) -> String {
    let o = glassscan(&["report", dir.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    stderr(&o)
}

/// `report DIR` succeeds; the page, checked to be self-contained and well-formed.
fn report_of(dir: &Path) -> String {
    run_ok(&["report", dir.to_str().unwrap()]);
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let body = html
        .strip_prefix("<!DOCTYPE html>\n")
        .expect("the page starts with its doctype");
    check_well_formed(body).unwrap_or_else(|e| panic!("the page is not well-formed: {e}"));
    assert!(!html.contains("<script") && !html.contains("https://"));
    // The only URL is the SVG namespace: nothing is fetched.
    for (i, _) in html.match_indices("http://") {
        assert!(
            html[i..].starts_with("http://www.w3.org/2000/svg"),
            "{}",
            &html[i..i + 60]
        );
    }
    html
}

fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// The SVG files a run lists in `files`.
fn listed_svgs(v: &Value) -> Vec<String> {
    v["files"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|f| f.as_str().filter(|n| n.ends_with(".svg")).map(String::from))
        .collect()
}

#[test]
fn study_report_shows_the_runs_numbers_figures_and_the_papers_findings() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("study");
    let o = out.to_str().unwrap();
    run_ok(&[
        "study",
        "scan-angle",
        "scenes/edge_study.toml",
        "--positions",
        "1",
        "--sweep-deg",
        "10:40:30",
        "--exposures-ms",
        "0.5",
        "--map-arris-mm",
        "0.8",
        "--map-roughness",
        "0.3",
        "--map-positions",
        "1",
        "--photons",
        "16384",
        "--out",
        o,
    ]);
    let html = report_of(&out);
    let summary = read_json(&out.join("summary.json"));
    for a in summary["angles"].as_array().unwrap() {
        let deg = a["scan_angle_deg"].as_f64().unwrap();
        for rule in ["edge-line", "highest"] {
            let mean = a["bip_error_mm_by_rule"][rule]["mean"].as_f64().unwrap();
            assert!(html.contains(&format!("{} ± ", num(mean))), "{deg}° {rule}");
        }
    }
    for s in summary["sweep"].as_array().unwrap() {
        let mean = s["bip_error_mm_by_rule"]["edge-line"]["mean"]
            .as_f64()
            .unwrap();
        assert!(html.contains(&num(mean)));
    }
    // Every figure of the run, inline, once.
    let svgs = listed_svgs(&summary);
    assert!(svgs.len() >= 6, "{svgs:?}");
    assert_eq!(html.matches("<svg").count(), svgs.len());
    for name in &svgs {
        assert_eq!(
            html.matches(&format!("<figcaption>{name}")).count(),
            1,
            "{name}"
        );
    }
    // The paper's findings at the three angles, with their sources, and the finding map.
    for quote in [
        "Section III-C, Fig. 7(a)",
        "Section III-C, Fig. 7(b)",
        "Section IV-A",
        "The paper&#39;s finding in this run",
        "Finding map",
    ] {
        assert!(html.contains(quote), "{quote}");
    }
    assert!(html.contains("scenes/edge_study_tape.toml"), "the settings");

    // A truncated figure: refused by name, and the earlier page stays as it was.
    let before = std::fs::read(out.join("report.html")).unwrap();
    let fig = out.join("edge_40deg.svg");
    let text = std::fs::read_to_string(&fig).unwrap();
    std::fs::write(&fig, &text[..text.len() / 2]).unwrap();
    let e = refused(&out);
    assert!(
        e.contains("edge_40deg.svg: expected a complete SVG document"),
        "{e}"
    );
    std::fs::remove_file(&fig).unwrap();
    let e = refused(&out);
    assert!(
        e.contains("edge_40deg.svg: could not read the figure summary.json lists"),
        "{e}"
    );
    std::fs::write(&fig, text).unwrap();
    // A summary without a value the page needs names the place in the file.
    let mut broken = summary.clone();
    broken["angles"][1]["variants"]["bare"]
        .as_object_mut()
        .unwrap()
        .remove("valid_points");
    std::fs::write(out.join("summary.json"), broken.to_string()).unwrap();
    let e = refused(&out);
    assert!(
        e.contains("summary.json: angles[1].variants.bare: expected a member \"valid_points\""),
        "{e}"
    );
    std::fs::write(out.join("summary.json"), "{\"angles\": [").unwrap();
    let e = refused(&out);
    assert!(e.contains("summary.json: line 1 column"), "{e}");
    assert_eq!(std::fs::read(out.join("report.html")).unwrap(), before);
}

#[test]
fn sweep_report_has_a_row_per_cell_and_every_heat_map() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("sweep");
    let o = out.to_str().unwrap();
    run_ok(&[
        "sweep",
        "scenes/edge_study.toml",
        "--scan-angle-deg",
        "10,40",
        "--exposure-ms",
        "0.15,0.5",
        "--poses",
        "1",
        "--photons",
        "16384",
        "--out",
        o,
    ]);
    let html = report_of(&out);
    let cells = read_json(&out.join("cells.json"));
    let svgs = listed_svgs(&cells);
    assert_eq!(svgs.len(), 2);
    assert_eq!(html.matches("<svg").count(), svgs.len());
    for c in cells["cells"].as_array().unwrap() {
        let s = &c["bip_error_mm_by_rule"]["edge-line"];
        let text = format!(
            "{} ± {}",
            num(s["mean"].as_f64().unwrap()),
            num(s["std"].as_f64().unwrap())
        );
        assert!(html.contains(&text), "{text}");
    }
    assert!(html.contains("5 ms, highest intensity") && html.contains("LRF properties"));
    // --out elsewhere: the page goes there, the run directory is left alone.
    let elsewhere = tmp.path().join("page.html");
    std::fs::remove_file(out.join("report.html")).unwrap();
    run_ok(&["report", o, "--out", elsewhere.to_str().unwrap()]);
    assert!(elsewhere.is_file() && !out.join("report.html").exists());
    // An --out in a directory that does not exist: an error, nothing written.
    let o2 = glassscan(&[
        "report",
        o,
        "--out",
        tmp.path().join("no/such/page.html").to_str().unwrap(),
    ]);
    assert_eq!(o2.status.code(), Some(2), "{}", stderr(&o2));
    // An --out that names a file the page did not write (the run's own table, by mistake) or
    // a directory: refused, naming it, and left as it was; an earlier page is replaced.
    let table = out.join("cells.json");
    let before = std::fs::read(&table).unwrap();
    for target in [&table, &out] {
        let o3 = glassscan(&["report", o, "--out", target.to_str().unwrap()]);
        assert_eq!(o3.status.code(), Some(2), "{}", stderr(&o3));
        let e = stderr(&o3);
        assert!(
            e.contains(target.to_str().unwrap()) && e.contains("not a page of `glassscan report`"),
            "{e}"
        );
    }
    assert_eq!(std::fs::read(&table).unwrap(), before);
    run_ok(&["report", o, "--out", elsewhere.to_str().unwrap()]);
}

#[test]
fn locate_report_sets_the_papers_tables_beside_the_runs_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("locate");
    let o = out.to_str().unwrap();
    run_ok(&[
        "locate",
        "scenes/edge_study_bare.toml",
        "--poses",
        "3",
        "--photons",
        "16384",
        "--opaque-copy",
        "--out",
        o,
    ]);
    let html = report_of(&out);
    let summary = read_json(&out.join("summary.json"));
    for (key, s) in [
        ("bip_error_mm", &summary["bip_error_mm"]),
        ("task_error_mm", &summary["task_error_mm"]),
    ] {
        let text = format!(
            "{} ± {}",
            num(s["mean"].as_f64().unwrap()),
            num(s["std"].as_f64().unwrap())
        );
        assert!(html.contains(&text), "{key}: {text}");
    }
    let bips = std::fs::read_to_string(out.join("bips.csv")).unwrap();
    for line in bips.lines().skip(1) {
        let error: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
        assert!(html.contains(&format!(">{}<", num(error))), "{line}");
    }
    for quote in [
        "0.94 ± 0.28 (max 1.35) mm",
        "1.01 ± 0.14 (max 1.27) mm",
        "0.88 ± 0.39 (max 1.65) mm",
        "14.845 s",
        "table &quot;Point localisation error&quot;",
        "table &quot;Full pipeline localisation error&quot;",
    ] {
        assert!(html.contains(quote), "{quote}");
    }
    assert_eq!(
        html.matches("<svg").count(),
        2,
        "our chart beside the paper, per-pose errors"
    );

    // A BIP table without its error column: refused, naming the file and the column.
    let before = std::fs::read(out.join("report.html")).unwrap();
    let cut: String = bips
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_owned() + "\n")
        .collect();
    std::fs::write(out.join("bips.csv"), cut).unwrap();
    let e = refused(&out);
    assert!(e.contains("bips.csv") && e.contains("error_mm"), "{e}");
    assert_eq!(std::fs::read(out.join("report.html")).unwrap(), before);
}

#[test]
fn dataset_report_summarises_the_manifest_and_refuses_unmerged_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    let o = out.to_str().unwrap();
    run_ok(&[
        "dataset",
        "scenes/edge_study.toml",
        "--count",
        "2",
        "--photons",
        "16384",
        "--seed",
        "3",
        "--randomize",
        "scenes/randomize_edge_study.toml",
        "--out",
        o,
    ]);
    let html = report_of(&out);
    assert!(html.contains("2 of 2"));
    assert!(html.contains("sample_000000") && html.contains("sample_000001"));
    assert!(html.contains("scan_angle_deg"), "the drawn parameters");
    assert_eq!(html.matches("<svg").count(), 2);
    let line: Value = serde_json::from_str(
        std::fs::read_to_string(out.join("manifest.jsonl"))
            .unwrap()
            .lines()
            .next()
            .unwrap(),
    )
    .unwrap();
    let valid = line["valid_points"].as_u64().unwrap();
    assert!(html.contains(&format!(">{valid}<")));

    std::fs::rename(
        out.join("manifest.jsonl"),
        out.join("manifest-shard-0-of-2.jsonl"),
    )
    .unwrap();
    let e = refused(&out);
    assert!(
        e.contains("manifest.jsonl") && e.contains("glassscan merge"),
        "{e}"
    );
}

#[test]
fn unknown_directories_are_refused_with_what_was_expected() {
    let tmp = tempfile::tempdir().unwrap();
    let e = refused(tmp.path());
    assert!(
        e.contains("no run files found: expected the output directory of"),
        "{e}"
    );
    std::fs::write(tmp.path().join("manifest.json"), "{}").unwrap();
    let e = refused(tmp.path());
    assert!(e.contains("`glassscan scan` run (manifest.json)"), "{e}");
    let e = refused(&tmp.path().join("missing"));
    assert!(e.contains("missing"), "{e}");
    assert!(!tmp.path().join("report.html").exists());
}
