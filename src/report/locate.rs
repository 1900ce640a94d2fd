//! The page of `glassscan locate --out DIR`: from `summary.json` (settings, BIP, pose, task and
//! contour errors, registration, timings; the opaque copy's too), `bips.csv` and
//! `bips_paper_rule.csv` (per pose) and `poses.json` (valid points, saturation), with the
//! paper's point-localisation, full-pipeline and timing tables beside ours.

use std::path::Path;

use super::format::{num, opt, stats, MISSING};
use super::html::{Cell, Page, Table};
use super::json_view::{read_json_file, Node, Stats};
use super::paper::{self, Quoted};
use super::svg::{BarChart, BarSeries, PALETTE, PAPER_COLOR};
use super::{settings_table, ReportError};
use crate::io::csv_read::CsvText;

/// One pose of a BIP table: the path label of the BIP and its error (mm), if it has one.
#[derive(Clone, Debug, Default, PartialEq)]
struct PoseBip {
    label: String,
    error_mm: Option<f64>,
}

/// `pose,…,label,…,error_mm` rows of `bips.csv` or `bips_paper_rule.csv`, by pose index.
fn read_bips(path: &Path) -> Result<Vec<PoseBip>, ReportError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        ReportError::input(
            path,
            format!("could not read the BIP table of `glassscan locate --out`: {e}"),
        )
    })?;
    let csv = CsvText::parse(path, &text).map_err(ReportError::Read)?;
    let [pose, label, error] = csv
        .column_indices(path, &["pose", "label", "error_mm"])
        .map_err(ReportError::Read)?;
    let mut out = Vec::new();
    for (k, row) in csv.rows.iter().enumerate() {
        let bad = |column: &str, expected: &str, found: &str| {
            ReportError::input(
                path,
                format!(
                    "line {}: column {column}: expected {expected}, got \"{found}\"",
                    row.line
                ),
            )
        };
        let p = &row.fields[pose];
        if p.parse::<usize>().ok() != Some(k) {
            return Err(bad(
                "pose",
                &format!("pose {k} (one row per pose, in order)"),
                p,
            ));
        }
        let e = &row.fields[error];
        let error_mm = if e.is_empty() {
            None
        } else {
            Some(
                csv.number(e)
                    .ok_or_else(|| bad("error_mm", "a number or nothing", e))?,
            )
        };
        out.push(PoseBip {
            label: row.fields[label].clone(),
            error_mm,
        });
    }
    Ok(out)
}

/// `mean ± std (max)` of a run's error, or a dash.
fn error_stats(node: &Node, key: &str) -> Result<Stats, ReportError> {
    Ok(match node.opt(key) {
        Some(s) => s.stats()?,
        None => Stats::default(),
    })
}

/// A row of ours against the paper's.
fn versus(t: &mut Table, what: &str, ours: String, quoted: Option<&Quoted>) {
    t.row(vec![
        Cell::text(what),
        Cell::num(ours),
        match quoted {
            Some(q) => Cell::paper(q.text()),
            None => Cell::text(MISSING),
        },
        Cell::note(quoted.map_or("the paper reports none", |q| q.source)),
    ]);
}

/// The page.
pub fn page(dir: &Path) -> Result<String, ReportError> {
    let path = dir.join("summary.json");
    let v = read_json_file(&path, "the summary.json of `glassscan locate --out`")?;
    let root = Node::root(&path, &v);
    let rule = root.get("bip_rule")?.str()?;
    let bips = read_bips(&dir.join("bips.csv"))?;
    let paper_bips = read_bips(&dir.join("bips_paper_rule.csv"))?;
    let poses_path = dir.join("poses.json");
    let poses_v = read_json_file(&poses_path, "the poses.json of `glassscan locate --out`")?;
    let poses = Node::root(&poses_path, &poses_v).get("poses")?.array()?;
    let n = root.get("poses")?.u64()? as usize;
    for (file, len) in [
        ("bips.csv", bips.len()),
        ("bips_paper_rule.csv", paper_bips.len()),
        ("poses.json", poses.len()),
    ] {
        if len != n {
            return Err(ReportError::input(
                &dir.join(file),
                format!("expected one entry per pose ({n}, as summary.json says), found {len}"),
            ));
        }
    }
    let opaque = root.opt("opaque_copy");

    let mut page = Page::new(
        "Locate run: the paper's pipeline (BIP → ICP)",
        &format!("glassscan locate, run directory {}", dir.display()),
    );
    page.h2("Settings");
    let mut t = settings_table(
        &root,
        &[
            ("scene", "scene"),
            ("poses", "scan poses"),
            ("scan_angle_deg", "scan angle (deg)"),
            ("exposure_ms", "exposure (ms)"),
            ("photons", "laser photons per pose"),
            ("seed", "seed"),
            ("bip_rule", "BIP rule registered"),
            ("errors", "error models"),
            ("error_sources_on", "error sources on"),
        ],
    );
    if let Some(o) = &opaque {
        t.row(vec![
            Cell::text("opaque copy: exposure (ms)"),
            Cell::text(super::format::setting(o.get("exposure_ms")?.value())),
        ]);
    }
    page.table(&t);

    page.h2("Errors beside the paper");
    page.para(
        "Ours are measured against exact ground truth: |BIP − p_e| with p_e the true border \
         point in the true laser plane, and the task error at the border after registration. \
         The paper measured by touching the marked points with the robot's tooltip, so its \
         numbers include the robot's and the calibration's errors.",
    );
    let mut t = Table::new(["quantity", "this run", "the paper", "source"]);
    let glass = error_stats(&root, "bip_error_mm")?;
    versus(
        &mut t,
        &format!("BIP error, glass, {rule} rule (mm)"),
        stats(&glass),
        Some(&paper::POINT_GLASS),
    );
    if rule != "highest" {
        let s = error_stats(&root, "paper_rule_bip_error_mm")?;
        versus(
            &mut t,
            "BIP error, glass, paper's rule (mm)",
            stats(&s),
            Some(&paper::POINT_GLASS),
        );
    }
    let mut opaque_stats = None;
    if let Some(o) = &opaque {
        let s = error_stats(o, "bip_error_mm")?;
        opaque_stats = Some(s);
        versus(
            &mut t,
            &format!("BIP error, opaque copy, {rule} rule (mm)"),
            stats(&s),
            Some(&paper::POINT_OPAQUE),
        );
        if rule != "highest" {
            let s = error_stats(o, "paper_rule_bip_error_mm")?;
            versus(
                &mut t,
                "BIP error, opaque copy, paper's rule (mm)",
                stats(&s),
                Some(&paper::POINT_OPAQUE),
            );
        }
    }
    let task = error_stats(&root, "task_error_mm")?;
    versus(
        &mut t,
        "task error after ICP (mm)",
        stats(&task),
        Some(&paper::FULL_PIPELINE),
    );
    let pose_error = match root.opt("pose_error") {
        Some(p) => format!(
            "{} mm, {}°",
            num(p.get("translation_mm")?.f64()?),
            num(p.get("rotation_deg")?.f64()?)
        ),
        None => MISSING.into(),
    };
    versus(
        &mut t,
        "pose error (translation, rotation)",
        pose_error,
        None,
    );
    let contour = match root.opt("contour_error_mm") {
        Some(c) => format!(
            "{} (max {})",
            num(c.get("mean")?.f64()?),
            num(c.get("max")?.f64()?)
        ),
        None => MISSING.into(),
    };
    versus(&mut t, "contour (glue path) error (mm)", contour, None);
    let timings = root.get("timings_s")?;
    versus(
        &mut t,
        "scanning time (s; here the simulation, not robot motion)",
        num(timings.get("scanning")?.f64()?),
        Some(&paper::TIME_SCANNING),
    );
    versus(
        &mut t,
        "pose estimation time (s)",
        num(timings.get("pose_estimation")?.f64()?),
        Some(&paper::TIME_POSE_ESTIMATION),
    );
    page.table(&t);

    let mut categories = vec!["point localisation, glass".to_owned()];
    let mut ours = vec![(glass.mean, glass.std)];
    let mut quoted = vec![paper::POINT_GLASS];
    if let Some(s) = opaque_stats {
        categories.push("point localisation, opaque".into());
        ours.push((s.mean, s.std));
        quoted.push(paper::POINT_OPAQUE);
    }
    categories.push("full pipeline (task error)".into());
    ours.push((task.mean, task.std));
    quoted.push(paper::FULL_PIPELINE);
    let chart = BarChart {
        title: "This run beside the paper: mean ± std (mm)".into(),
        x_label: "quantity".into(),
        y_label: "error (mm)".into(),
        log_y: false,
        categories,
        series: vec![
            BarSeries {
                name: format!("this run ({rule} rule)"),
                color: PALETTE[0],
                values: ours.iter().map(|o| o.0).collect(),
                errors: ours.iter().map(|o| o.1).collect(),
            },
            BarSeries {
                name: "the paper".into(),
                color: PAPER_COLOR,
                values: quoted.iter().map(|q| Some(q.mean)).collect(),
                errors: quoted.iter().map(|q| q.std).collect(),
            },
        ],
    };
    page.figure(
        &chart.to_svg(),
        "Our errors against exact ground truth beside the paper's (Sections V-B and VI-B, tables \"Point localisation error\" and \"Full pipeline localisation error\"); whiskers ± std.",
    );

    page.h2("Registration");
    let mut t = Table::new(["", "value"]);
    for (key, label) in [
        ("bips", "BIPs registered"),
        ("converged", "converged"),
        ("degenerate", "degenerate"),
        ("weak_directions", "weak directions"),
        ("iterations", "iterations"),
        ("registration_error", "registration error"),
    ] {
        if let Some(v) = root.value().get(key) {
            t.row(vec![
                Cell::text(label),
                Cell::text(super::format::setting(v)),
            ]);
        }
    }
    if let Some(e) = root.opt("estimate") {
        let triple = |key: &str| -> Result<String, ReportError> {
            let v: Vec<String> = e
                .get(key)?
                .array()?
                .iter()
                .map(|x| x.f64().map(num))
                .collect::<Result<_, _>>()?;
            Ok(v.join(", "))
        };
        t.row(vec![
            Cell::text("estimated pose T_BM (ICP): translation (mm)"),
            Cell::text(triple("translation_mm")?),
        ]);
        t.row(vec![
            Cell::text("estimated pose T_BM (ICP): rotation (deg, R = Rz·Ry·Rx)"),
            Cell::text(triple("rotation_deg")?),
        ]);
    }
    page.table(&t);

    page.h2("Per pose");
    let mut t = Table::new([
        "pose",
        &format!("BIP label ({rule})"),
        &format!("|BIP − p_e|, {rule} (mm)"),
        "BIP label (paper's rule)",
        "|BIP − p_e|, paper's rule (mm)",
        "valid points",
        "saturated pixels",
    ]);
    for (k, ((b, p), pose)) in bips.iter().zip(&paper_bips).zip(&poses).enumerate() {
        t.row(vec![
            Cell::num(k.to_string()),
            Cell::text(if b.label.is_empty() {
                MISSING
            } else {
                &b.label
            }),
            Cell::num(opt(b.error_mm)),
            Cell::text(if p.label.is_empty() {
                MISSING
            } else {
                &p.label
            }),
            Cell::num(opt(p.error_mm)),
            Cell::num(pose.get("valid_points")?.u64()?.to_string()),
            Cell::num(pose.get("saturated_pixels")?.u64()?.to_string()),
        ]);
    }
    page.table(&t);
    let chart = BarChart {
        title: "BIP error per pose, both rules (log scale)".into(),
        x_label: "pose".into(),
        y_label: "|BIP − p_e| (mm)".into(),
        log_y: true,
        categories: (0..n).map(|k| k.to_string()).collect(),
        series: vec![
            BarSeries {
                name: format!("{rule} rule"),
                color: PALETTE[0],
                values: bips.iter().map(|b| b.error_mm).collect(),
                errors: Vec::new(),
            },
            BarSeries {
                name: "paper's rule (highest point)".into(),
                color: PALETTE[1],
                values: paper_bips.iter().map(|b| b.error_mm).collect(),
                errors: Vec::new(),
            },
        ],
    };
    page.figure(
        &chart.to_svg(),
        "|BIP − p_e| per scan pose (bips.csv and bips_paper_rule.csv); a pose without a bar has no BIP.",
    );
    Ok(page.finish())
}
