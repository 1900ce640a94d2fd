//! The page of `glassscan sweep --out DIR`: from `cells.json` (the settings and one row per
//! cell of scan angle × exposure × threshold × peak selection) and the sweep's heat maps, with
//! the paper's settings beside the sweep's axes.

use std::path::Path;

use super::format::{percent, stats, typed, MISSING};
use super::html::{Cell, Page, Table};
use super::json_view::{read_json_file, Node};
use super::{listed_figures, paper, place_figures, settings_table, ReportError};

/// The distinct values of `key` over the cells, as text, in first-seen order.
fn axis(cells: &[Node], key: &str) -> Result<Vec<String>, ReportError> {
    let mut out: Vec<String> = Vec::new();
    for c in cells {
        let v = c.get(key)?;
        let t = match v.value() {
            serde_json::Value::String(s) => s.clone(),
            _ => typed(v.f64()?),
        };
        if !out.contains(&t) {
            out.push(t);
        }
    }
    Ok(out)
}

/// The page.
pub fn page(dir: &Path) -> Result<String, ReportError> {
    let path = dir.join("cells.json");
    let v = read_json_file(&path, "the cells.json of `glassscan sweep`")?;
    let root = Node::root(&path, &v);
    let cells = root.get("cells")?.array()?;
    let mut figures = listed_figures(dir, &root.get("files")?, "cells.json")?;
    let mut page = Page::new(
        "Settings sweep: BIP error over sensor settings",
        &format!("glassscan sweep, run directory {}", dir.display()),
    );

    page.h2("Settings");
    let mut t = settings_table(
        &root,
        &[
            ("scene", "scene"),
            ("poses", "poses along the border per angle"),
            ("photons", "laser photons per pose"),
            ("seed", "seed"),
            ("wrong_surface_rule", "wrong-surface fraction"),
            ("elapsed_s", "run time (s)"),
        ],
    );
    for (key, label) in [
        ("scan_angle_deg", "scan angles (deg)"),
        ("exposure_ms", "exposures (ms)"),
        ("threshold", "thresholds (DN)"),
        ("peak_select", "peak selection"),
    ] {
        t.row(vec![
            Cell::text(label),
            Cell::text(axis(&cells, key)?.join(", ")),
        ]);
    }
    page.table(&t);

    page.h3("The paper's settings");
    let mut t = Table::new(["setting", "the paper", "source"]);
    let pipeline = &paper::ANGLE_FINDINGS[2];
    t.row(vec![
        Cell::text("scan angle of the pipeline"),
        Cell::paper("approximately 45°"),
        Cell::note(pipeline.source),
    ]);
    for f in &paper::ANGLE_FINDINGS[..2] {
        t.row(vec![
            Cell::text(format!("edge experiment at {}°", typed(f.angle_deg))),
            Cell::paper(f.finding),
            Cell::note(f.source),
        ]);
    }
    t.row(vec![
        Cell::text("exposure, peak selection (glass-surface scans)"),
        Cell::paper("5 ms, highest intensity"),
        Cell::note("Section III-B, table \"LRF properties\""),
    ]);
    page.table(&t);

    page.h2("Cells");
    page.para("|BIP − p_e| in mm, mean ± std (max) over the poses; BIPs found = share of poses with a BIP.");
    let mut t = Table::new([
        "cell",
        "scan angle",
        "exposure (ms)",
        "threshold",
        "peak select",
        "edge-line rule (mm)",
        "BIPs found (edge-line)",
        "paper's rule (mm)",
        "BIPs found (paper's)",
        "saturated pixels",
        "wrong surface",
        "valid points",
    ]);
    for c in &cells {
        let by_rule = c.get("bip_error_mm_by_rule")?;
        let rule = |name: &str| -> Result<(String, String), ReportError> {
            let r = by_rule.get(name)?;
            let valid = r.opt("valid_fraction").map(|v| v.f64()).transpose()?;
            Ok((stats(&r.stats()?), valid.map_or(MISSING.into(), percent)))
        };
        let (e, ev) = rule("edge-line")?;
        let (h, hv) = rule("highest")?;
        t.row(vec![
            Cell::num(c.get("cell")?.u64()?.to_string()),
            Cell::num(format!("{}°", typed(c.get("scan_angle_deg")?.f64()?))),
            Cell::num(typed(c.get("exposure_ms")?.f64()?)),
            Cell::text(c.get("threshold")?.str()?),
            Cell::text(c.get("peak_select")?.str()?),
            Cell::num(e),
            Cell::num(ev),
            Cell::num(h),
            Cell::num(hv),
            Cell::num(percent(c.get("saturated_pixel_fraction")?.f64()?)),
            Cell::num(percent(c.get("wrong_surface_fraction")?.f64()?)),
            Cell::num(c.get("valid_points")?.u64()?.to_string()),
        ]);
    }
    page.table(&t);
    if !figures.is_empty() {
        page.h2("Heat maps");
        place_figures(
            &mut page,
            &mut figures,
            |_| true,
            |n| format!("{n}: mean BIP error over scan angle × exposure."),
        );
    }
    Ok(page.finish())
}
