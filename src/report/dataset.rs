//! The page of a dataset directory (`glassscan dataset --out DIR`): from `run.json` (how it
//! was made, with the scene and randomisation files' text) and `manifest.jsonl` (one line per
//! finished sample: drawn parameters, valid points per path label, saturation, warnings).

use std::collections::BTreeMap;
use std::path::Path;

use super::format::{num, percent, MISSING};
use super::html::{Cell, Page, Table};
use super::json_view::{read_json_file, Node};
use super::svg::{BarChart, BarSeries, XyChart, XySeries, PALETTE};
use super::{settings_table, ReportError};
use crate::dataset::manifest::{for_each_line, ManifestLine, MANIFEST};

/// Rows of the per-sample table at most (a large dataset's page stays light).
const MAX_SAMPLE_ROWS: usize = 1000;

/// The page.
pub fn page(dir: &Path) -> Result<String, ReportError> {
    let run_path = dir.join("run.json");
    let v = read_json_file(&run_path, "the run.json of `glassscan dataset`")?;
    let run = Node::root(&run_path, &v);
    let count = run.get("count")?.u64()?;
    let manifest = dir.join(MANIFEST);
    if !manifest.is_file() {
        let shards = std::fs::read_dir(dir)
            .map(|d| {
                d.filter_map(|e| e.ok()).any(|e| {
                    e.file_name()
                        .to_string_lossy()
                        .starts_with("manifest-shard-")
                })
            })
            .unwrap_or(false);
        let hint = if shards {
            format!(
                "the shards' manifests are there but not merged: run `glassscan merge {}` first",
                dir.display()
            )
        } else {
            "no sample has finished yet".into()
        };
        return Err(ReportError::input(
            &manifest,
            format!("expected the dataset's manifest (one JSON line per finished sample): {hint}"),
        ));
    }
    let mut lines: Vec<ManifestLine> = Vec::new();
    for_each_line(&manifest, |_, line| {
        lines.push(line);
        Ok(())
    })
    .map_err(ReportError::Dataset)?;

    let mut page = Page::new(
        "Synthetic dataset",
        &format!("glassscan dataset, directory {}", dir.display()),
    );
    page.h2("Settings");
    page.table(&settings_table(
        &run,
        &[
            ("version", "glassscan version"),
            ("scene", "scene"),
            ("randomize", "randomisation file"),
            ("seed", "master seed"),
            ("count", "samples in the dataset"),
            ("photons", "laser photons per sample"),
            ("max_depth", "longest photon path (surface interactions)"),
            ("ply_ascii", "points.ply as text"),
        ],
    ));
    page.details_pre(
        "The scene file as the run read it",
        run.get("scene_toml")?.str()?,
    );
    if let Some(r) = run.opt("randomize_toml") {
        page.details_pre("The randomisation file as the run read it", r.str()?);
    }
    page.para(
        "The paper has no synthetic dataset to compare with; its pipeline scans at about 45° \
         (Section IV-A), which the randomised scan angle, where drawn, spreads around.",
    );

    page.h2("Samples");
    let finished = lines.len() as u64;
    let with_pe = lines.iter().filter(|l| l.edge_point_mm.is_some()).count();
    let warned = lines.iter().filter(|l| !l.warnings.is_empty()).count();
    let valid: Vec<f64> = lines.iter().map(|l| l.valid_points as f64).collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let mut t = Table::new(["", "value"]);
    t.row(vec![
        Cell::text("finished samples (manifest lines)"),
        Cell::num(format!("{finished} of {count}")),
    ]);
    t.row(vec![
        Cell::text("samples whose laser plane meets the border (p_e exists)"),
        Cell::num(with_pe.to_string()),
    ]);
    t.row(vec![
        Cell::text("samples with a warning"),
        Cell::num(warned.to_string()),
    ]);
    t.row(vec![
        Cell::text("valid profile points per sample: mean (min–max)"),
        Cell::num(if lines.is_empty() {
            MISSING.into()
        } else {
            format!(
                "{} ({}–{})",
                num(mean(&valid)),
                valid.iter().cloned().fold(f64::INFINITY, f64::min),
                valid.iter().cloned().fold(0.0, f64::max)
            )
        }),
    ]);
    page.table(&t);

    // Drawn parameters: min, mean, max over the finished samples.
    let mut params: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
    for l in &lines {
        for (k, v) in &l.parameters {
            params.entry(k.as_str()).or_default().push(*v);
        }
    }
    if !params.is_empty() {
        page.h3("Drawn parameters");
        let mut t = Table::new(["parameter", "samples", "min", "mean", "max"]);
        for (k, v) in &params {
            t.row(vec![
                Cell::text(*k),
                Cell::num(v.len().to_string()),
                Cell::num(num(v.iter().cloned().fold(f64::INFINITY, f64::min))),
                Cell::num(num(mean(v))),
                Cell::num(num(v.iter().cloned().fold(f64::NEG_INFINITY, f64::max))),
            ]);
        }
        page.table(&t);
    }

    // Path labels of the valid points, over all samples.
    let mut labels: BTreeMap<&str, usize> = BTreeMap::new();
    for l in &lines {
        for (k, n) in &l.labels {
            *labels.entry(k.as_str()).or_default() += n;
        }
    }
    let total: usize = labels.values().sum();
    page.h3("Where the valid points came from");
    let mut t = Table::new(["path label", "points", "share"]);
    for (k, n) in &labels {
        t.row(vec![
            Cell::text(*k),
            Cell::num(n.to_string()),
            Cell::num(percent(*n as f64 / total.max(1) as f64)),
        ]);
    }
    page.table(&t);
    let chart = BarChart {
        title: "Valid profile points by path label, all samples".into(),
        x_label: "path label".into(),
        y_label: "points".into(),
        log_y: false,
        categories: labels.keys().map(|k| k.to_string()).collect(),
        series: vec![BarSeries {
            name: "points".into(),
            color: PALETTE[0],
            values: labels.values().map(|n| Some(*n as f64)).collect(),
            errors: Vec::new(),
        }],
    };
    page.figure(
        &chart.to_svg(),
        "The path class that dominates each valid point's peak (manifest.jsonl, labels).",
    );

    let (x_key, x_label) = if params.contains_key("scan_angle_deg") {
        ("scan_angle_deg", "scan angle (deg, drawn)")
    } else {
        ("border_fraction", "position along the border (fraction)")
    };
    let points: Vec<(f64, f64)> = lines
        .iter()
        .map(|l| {
            let x = match x_key {
                "border_fraction" => l.border_fraction,
                k => l.parameters.get(k).copied().unwrap_or(f64::NAN),
            };
            let edge = l.labels.get("glass_edge").copied().unwrap_or(0) as f64;
            (x, edge)
        })
        .collect();
    let chart = XyChart {
        title: format!(
            "Points on the glass edge against the {}",
            x_label.split(" (").next().unwrap_or(x_label)
        ),
        x_label: x_label.into(),
        y_label: "valid points labelled glass_edge".into(),
        log_y: false,
        series: vec![XySeries {
            name: "one sample".into(),
            color: PALETTE[1],
            points,
            line: false,
        }],
    };
    page.figure(
        &chart.to_svg(),
        "Per sample: how many valid points the glass edge returned.",
    );

    page.h3("Per sample");
    if lines.len() > MAX_SAMPLE_ROWS {
        page.para(&format!(
            "The first {MAX_SAMPLE_ROWS} of {} samples.",
            lines.len()
        ));
    }
    let mut t = Table::new([
        "sample",
        "directory",
        "border fraction",
        "valid points",
        "glass_edge points",
        "saturated pixels",
        "p_e (mm)",
        "warnings",
    ]);
    for l in lines.iter().take(MAX_SAMPLE_ROWS) {
        t.row(vec![
            Cell::num(l.index.to_string()),
            Cell::text(&l.directory),
            Cell::num(num(l.border_fraction)),
            Cell::num(l.valid_points.to_string()),
            Cell::num(l.labels.get("glass_edge").copied().unwrap_or(0).to_string()),
            Cell::num(l.saturated_pixels.to_string()),
            Cell::num(l.edge_point_mm.map_or(MISSING.into(), |p| {
                format!("{}, {}, {}", num(p[0]), num(p[1]), num(p[2]))
            })),
            Cell::note(l.warnings.join("; ")),
        ]);
    }
    page.table(&t);
    Ok(page.finish())
}
