//! The page of `glassscan study scan-angle --out DIR`: from `summary.json` (settings, the BIP
//! error per angle and rule, per-variant counts, the sweep, the exposure axis, the finding map)
//! and the study's SVG figures, with the paper's findings at 10°, 40° and 45° beside ours.

use std::path::Path;

use super::format::{num, percent, stats, MISSING};
use super::html::{Cell, Page, Table};
use super::json_view::{read_json_file, Node, Stats};
use super::{listed_figures, paper, place_figures, settings_table, ReportError};
use crate::study::finding_map::{HOLDS_MARGIN_MM, HOLDS_RATIO};

/// The two BIP rules as the study's files name them, and as the page names them.
const RULES: [(&str, &str); 2] = [
    ("edge-line", "edge-line rule"),
    ("highest", "paper's rule (highest point)"),
];

/// The statistics of `rule` in a `bip_error_mm_by_rule` object (absent: nothing).
fn rule_stats(by_rule: Option<&Node>, rule: &str) -> Result<(Stats, Option<f64>), ReportError> {
    let Some(r) = by_rule.and_then(|b| b.opt(rule)) else {
        return Ok((Stats::default(), None));
    };
    let valid = r.opt("valid_fraction").map(|v| v.f64()).transpose()?;
    Ok((r.stats()?, valid))
}

/// The page.
pub fn page(dir: &Path) -> Result<String, ReportError> {
    let path = dir.join("summary.json");
    let v = read_json_file(&path, "the summary.json of `glassscan study scan-angle`")?;
    let root = Node::root(&path, &v);
    let mut figures = listed_figures(dir, &root.get("files")?, "summary.json")?;
    let mut page = Page::new(
        "Scan-angle study: the paper's edge experiment",
        &format!(
            "glassscan study scan-angle, run directory {}",
            dir.display()
        ),
    );

    page.h2("Settings");
    page.table(&settings_table(
        &root,
        &[
            ("scene", "bare-pane scene"),
            ("scenes", "scenes of the variants"),
            ("positions", "positions along the border per angle"),
            ("photons", "laser photons per pose"),
            ("seed", "seed"),
            ("exposure_ms", "exposure of the edge plots (ms)"),
            ("exposures_ms", "exposure axis (ms)"),
            ("sweep_deg", "scan angles of the BIP-error curve (deg)"),
            ("elapsed_s", "run time (s)"),
        ],
    ));
    let notes: Vec<String> = root
        .opt("notes")
        .map(|n| n.array())
        .transpose()?
        .unwrap_or_default()
        .iter()
        .map(|n| n.str().map(str::to_owned))
        .collect::<Result<_, _>>()?;
    if !notes.is_empty() {
        page.list(&notes);
    }

    // The angles of the edge plots, against the paper.
    let angles = root.get("angles")?.array()?;
    page.h2("BIP error at the study's angles, beside the paper");
    page.para(
        "|BIP − p_e| on the bare pane, mean ± std (max) over the positions, in mm: p_e is the \
         exact border point in the laser plane. The paper reports the edge experiment as \
         figures, not numbers: its finding at each angle is quoted in words.",
    );
    let mut t = Table::new([
        "scan angle",
        "edge-line rule (mm)",
        "paper's rule (mm)",
        "BIPs found",
        "the paper",
        "source",
    ]);
    let mut errors_at = Vec::new();
    for a in &angles {
        let deg = a.get("scan_angle_deg")?.f64()?;
        let by_rule = a.opt("bip_error_mm_by_rule");
        let (edge, valid) = rule_stats(by_rule.as_ref(), RULES[0].0)?;
        let (high, _) = rule_stats(by_rule.as_ref(), RULES[1].0)?;
        errors_at.push((deg, [edge.mean, high.mean]));
        let (finding, source) =
            paper::angle_finding(deg).map_or((MISSING, MISSING), |f| (f.finding, f.source));
        t.row(vec![
            Cell::num(format!("{}°", num(deg))),
            Cell::num(stats(&edge)),
            Cell::num(stats(&high)),
            Cell::num(valid.map_or(MISSING.into(), percent)),
            Cell::paper(finding),
            Cell::note(source),
        ]);
    }
    page.table(&t);
    finding_in_this_run(&mut page, &errors_at);

    page.h3("What each variant returned");
    page.para(
        "Tape = the true contour (the paper's step 1), cover = where the border starts (step 2), \
         bare = the glass alone (step 3). Nearest point: the valid profile point closest to p_e \
         per position. Wrong surface: points labelled through_glass, glint, internal_reflection, \
         glass_reflected or sensor_noise.",
    );
    let mut t = Table::new([
        "scan angle",
        "variant",
        "valid points",
        "nearest point to p_e (mm)",
        "saturated pixels",
        "wrong-surface points",
    ]);
    for a in &angles {
        let deg = a.get("scan_angle_deg")?.f64()?;
        for (name, var) in a.get("variants")?.members()? {
            t.row(vec![
                Cell::num(format!("{}°", num(deg))),
                Cell::text(name),
                Cell::num(var.get("valid_points")?.u64()?.to_string()),
                Cell::num(stats(&var.get("nearest_point_mm")?.stats()?)),
                Cell::num(percent(var.get("saturated_pixel_fraction")?.f64()?)),
                Cell::num(percent(var.get("wrong_surface_fraction")?.f64()?)),
            ]);
        }
    }
    page.table(&t);
    place_figures(
        &mut page,
        &mut figures,
        |n| n.starts_with("edge_") && n.ends_with("deg.svg"),
        |n| {
            format!(
                "{n}: the readings near the edge in the edge frame of p_e (out, up; mm), as the \
                 paper's Fig. 7: cover blue crosses, tape green squares, bare glass red dots; \
                 the bare pane's BIPs by the paper's rule circled, p_e at the origin."
            )
        },
    );

    if let Some(sweep) = root.opt("sweep") {
        let rows = sweep.array()?;
        if !rows.is_empty() {
            page.h2("BIP error against the scan angle");
            let mut t = Table::new([
                "scan angle",
                "edge-line rule (mm)",
                "BIPs found (edge-line)",
                "paper's rule (mm)",
                "BIPs found (paper's)",
            ]);
            for r in &rows {
                let by_rule = r.opt("bip_error_mm_by_rule");
                let (e, ev) = rule_stats(by_rule.as_ref(), RULES[0].0)?;
                let (h, hv) = rule_stats(by_rule.as_ref(), RULES[1].0)?;
                t.row(vec![
                    Cell::num(format!("{}°", num(r.get("scan_angle_deg")?.f64()?))),
                    Cell::num(stats(&e)),
                    Cell::num(ev.map_or(MISSING.into(), percent)),
                    Cell::num(stats(&h)),
                    Cell::num(hv.map_or(MISSING.into(), percent)),
                ]);
            }
            page.table(&t);
            place_figures(
                &mut page,
                &mut figures,
                |n| n == "bip_error_vs_angle.svg",
                |n| {
                    format!("{n}: mean ± std of |BIP − p_e| against the scan angle, both rules (log scale).")
                },
            );
        }
    }

    exposure_axis(&mut page, &root)?;
    place_figures(
        &mut page,
        &mut figures,
        |n| n.starts_with("exposure_axis_"),
        |n| format!("{n}: mean BIP error over scan angle × exposure."),
    );
    if let Some(map) = root.opt("finding_map") {
        finding_map(&mut page, &map)?;
        place_figures(
            &mut page,
            &mut figures,
            |n| n.starts_with("finding_map_"),
            |n| {
                format!(
                    "{n}: BIP error at the shallow angle divided by that at the steep one, per \
                     arris width × roughness; marked where the paper's finding holds."
                )
            },
        );
    }
    if !figures.is_empty() {
        page.h2("Other figures of the run");
        place_figures(&mut page, &mut figures, |_| true, |n| n.to_owned());
    }
    Ok(page.finish())
}

/// Whether this run shows the paper's finding (10° worse than 40°) by the finding map's
/// criterion, per rule.
fn finding_in_this_run(page: &mut Page, errors_at: &[(f64, [Option<f64>; 2])]) {
    let at = |deg: f64| {
        errors_at
            .iter()
            .find(|(d, _)| (d - deg).abs() < 1e-6)
            .map(|e| e.1)
    };
    let (Some(shallow), Some(steep)) = (at(10.0), at(40.0)) else {
        page.para("The run has no 10° and 40° pair, so the paper's finding is not tested here.");
        return;
    };
    page.h3("The paper's finding in this run");
    page.para(&format!(
        "The paper finds the readings at 10° further from p_e than at 40°. It holds here when \
         the BIP error at 10° is at least {HOLDS_RATIO}× and {HOLDS_MARGIN_MM} mm above that at \
         40° (the study's finding-map criterion)."
    ));
    let mut t = Table::new(["rule", "10° (mm)", "40° (mm)", "10° / 40°", "holds"]);
    for (k, (_, label)) in RULES.iter().enumerate() {
        let (a, b) = (shallow[k], steep[k]);
        let (ratio, holds) = match (a, b) {
            (Some(a), Some(b)) if b > 0.0 => (
                num(a / b),
                if a >= HOLDS_RATIO * b && a - b >= HOLDS_MARGIN_MM {
                    "yes"
                } else {
                    "no"
                },
            ),
            _ => (MISSING.into(), MISSING),
        };
        t.row(vec![
            Cell::text(*label),
            Cell::num(a.map_or(MISSING.into(), num)),
            Cell::num(b.map_or(MISSING.into(), num)),
            Cell::num(ratio),
            Cell::text(holds),
        ]);
    }
    page.table(&t);
}

/// The exposure axis: per angle and exposure, the BIP error by both rules.
fn exposure_axis(page: &mut Page, root: &Node) -> Result<(), ReportError> {
    let Some(axis) = root.opt("exposure_axis") else {
        return Ok(());
    };
    let rows = axis.array()?;
    let exposures = root.get("exposures_ms")?.array()?;
    if rows.is_empty() || exposures.is_empty() {
        return Ok(());
    }
    page.h2("Exposure axis");
    page.para("Every bare-pane pose sensed again at each exposure (the light traced once): mean ± std of |BIP − p_e| in mm, edge-line rule / paper's rule.");
    let mut header = vec!["scan angle".to_owned()];
    for e in &exposures {
        header.push(format!("{} ms", num(e.f64()?)));
    }
    let mut t = Table::new(header);
    for r in &rows {
        let mut cells = vec![Cell::num(format!(
            "{}°",
            num(r.get("scan_angle_deg")?.f64()?)
        ))];
        let per = r.get("bip_error_mm_by_rule_per_exposure")?.array()?;
        if per.len() != exposures.len() {
            return Err(per
                .first()
                .unwrap_or(r)
                .error(&format!("one entry per exposure ({})", exposures.len())));
        }
        for e in &per {
            let (a, _) = rule_stats(Some(e), RULES[0].0)?;
            let (b, _) = rule_stats(Some(e), RULES[1].0)?;
            let mean_std = |s: &Stats| match (s.mean, s.std) {
                (Some(m), Some(d)) => format!("{} ± {}", num(m), num(d)),
                (Some(m), None) => num(m),
                _ => MISSING.into(),
            };
            cells.push(Cell::num(format!("{} / {}", mean_std(&a), mean_std(&b))));
        }
        t.row(cells);
    }
    page.table(&t);
    Ok(())
}

/// The finding map's cells: per arris width, roughness, exposure and rule, the ratio and
/// whether the finding holds.
fn finding_map(page: &mut Page, map: &Node) -> Result<(), ReportError> {
    let angles_node = map.get("angles_deg")?;
    let angles: Vec<f64> = angles_node
        .array()?
        .iter()
        .map(|x| x.f64())
        .collect::<Result<_, _>>()?;
    let [lo, hi] = angles[..] else {
        return Err(angles_node.error("two angles"));
    };
    page.h2("Finding map");
    page.para(&format!(
        "BIP error at {}° divided by that at {}° over edge finishes ({} positions per cell and \
         angle); the paper's finding holds where the ratio is at least {} and the difference at \
         least {} mm.",
        num(lo),
        num(hi),
        map.get("positions")?.u64()?,
        num(map.get("holds_ratio")?.f64()?),
        num(map.get("holds_margin_mm")?.f64()?),
    ));
    let mut t = Table::new([
        "arris width (mm)",
        "roughness α",
        "exposure (ms)",
        "rule",
        &format!("{}° (mm)", num(lo)),
        &format!("{}° (mm)", num(hi)),
        "ratio",
        "holds",
    ]);
    for c in map.get("cells")?.array()? {
        let w = c.get("arris_width_mm")?.f64()?;
        let alpha = c.get("roughness")?.f64()?;
        for e in c.get("exposures")?.array()? {
            let ms = e.get("exposure_ms")?.f64()?;
            for (rule, r) in e.get("rules")?.members()? {
                t.row(vec![
                    Cell::num(num(w)),
                    Cell::num(num(alpha)),
                    Cell::num(num(ms)),
                    Cell::text(rule),
                    Cell::num(stats(&r.get("shallow")?.stats()?)),
                    Cell::num(stats(&r.get("steep")?.stats()?)),
                    Cell::num(r.get("ratio")?.opt_f64()?.map_or(MISSING.into(), num)),
                    Cell::text(match r.get("holds")?.value().as_bool() {
                        Some(true) => "yes",
                        Some(false) => "no",
                        None => MISSING,
                    }),
                ]);
            }
        }
    }
    page.table(&t);
    Ok(())
}
