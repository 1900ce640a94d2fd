//! The sweep's table, one row per cell, as CSV text and as JSON.

use serde_json::{json, Value};

use super::grid::{threshold_name, SweepGrid};
use super::sweep::CellResult;
use super::tally::by_rule_json;
use super::{as_typed, csv_number};

/// One row per cell: the settings, BIP error by both rules, valid fractions, saturated-pixel
/// and wrong-surface fractions.
pub fn cells_csv(grid: &SweepGrid, cells: &[CellResult]) -> String {
    let mut s = String::from(
        "cell,scan_angle_deg,exposure_ms,threshold,peak_select,\
         bip_highest_mean_mm,bip_highest_std_mm,bip_highest_max_mm,bip_highest_valid_fraction,\
         bip_edge_line_mean_mm,bip_edge_line_std_mm,bip_edge_line_max_mm,\
         bip_edge_line_valid_fraction,saturated_pixel_fraction,wrong_surface_fraction,\
         valid_points\n",
    );
    for r in cells {
        let c = &r.cell;
        let mut row = vec![
            c.index.to_string(),
            format!("{}", as_typed(grid.angles_rad[c.angle].to_degrees())),
            format!("{}", as_typed(grid.exposures_s[c.exposure] * 1e3)),
            threshold_name(&grid.thresholds[c.threshold]),
            grid.peak_selects[c.peak_select].name().to_ascii_lowercase(),
        ];
        for k in &r.rules {
            row.extend([
                csv_number(Some(k.error_mm.mean)),
                csv_number(Some(k.error_mm.std)),
                csv_number(Some(k.error_mm.max)),
                csv_number(Some(k.valid_fraction)),
            ]);
        }
        row.extend([
            csv_number(Some(r.saturated_pixel_fraction())),
            csv_number(Some(r.wrong_surface_fraction())),
            r.valid_points().to_string(),
        ]);
        s += &row.join(",");
        s.push('\n');
    }
    s
}

/// The JSON table: `cells`, each with its settings, `bip_error_mm` (the paper's rule),
/// `bip_error_mm_by_rule`, `valid_fraction`, `saturated_pixel_fraction`,
/// `wrong_surface_fraction` and `valid_points`. `run` (settings, files) is merged in at the top.
pub fn cells_json(grid: &SweepGrid, cells: &[CellResult], run: Value) -> Value {
    let rows: Vec<Value> = cells
        .iter()
        .map(|r| {
            let c = &r.cell;
            json!({
                "cell": c.index,
                "scan_angle_deg": as_typed(grid.angles_rad[c.angle].to_degrees()),
                "exposure_ms": as_typed(grid.exposures_s[c.exposure] * 1e3),
                "threshold": threshold_name(&grid.thresholds[c.threshold]),
                "peak_select": grid.peak_selects[c.peak_select].name().to_ascii_lowercase(),
                "bip_error_mm": r.rules[0].error_mm,
                "valid_fraction": r.rules[0].valid_fraction,
                "bip_error_mm_by_rule": by_rule_json(&r.rules),
                "saturated_pixel_fraction": r.saturated_pixel_fraction(),
                "wrong_surface_fraction": r.wrong_surface_fraction(),
                "valid_points": r.valid_points(),
            })
        })
        .collect();
    super::with_run(json!({"cells": rows}), run)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scan::bip::BipRule;
    use crate::sensor::profile::{PeakSelect, Threshold};
    use crate::study::tally::{BipOutcome, PoseTally, RULES};

    fn result(grid: &SweepGrid, index: usize, error: Option<f64>) -> CellResult {
        let cell = grid.cells()[index];
        let tallies = vec![PoseTally {
            bips: [0, 1].map(|k| BipOutcome {
                rule: RULES[k],
                error_mm: error,
                edge_mm: None,
                label: None,
            }),
            saturated_pixels: 3,
            pixels: 12,
            valid_points: 4,
            wrong_surface_points: 1,
        }];
        CellResult {
            cell,
            rules: crate::study::tally::RuleSummary::both(&tallies),
            tallies,
        }
    }

    #[test]
    fn one_row_per_cell_with_its_settings_and_fractions() {
        let grid = SweepGrid {
            angles_rad: vec![40f64.to_radians()],
            exposures_s: vec![0.5e-3],
            thresholds: vec![Threshold::Fixed(128), Threshold::Automatic],
            peak_selects: vec![PeakSelect::First],
        };
        let cells = vec![result(&grid, 0, Some(0.25)), result(&grid, 1, None)];
        let csv = cells_csv(&grid, &cells);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 3);
        let header: Vec<&str> = lines[0].split(',').collect();
        let row: Vec<&str> = lines[1].split(',').collect();
        assert_eq!(header.len(), row.len());
        let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
        assert_eq!(row[col("threshold")], "128");
        assert_eq!(row[col("peak_select")], "first");
        assert_eq!(row[col("bip_highest_mean_mm")], "0.25");
        assert_eq!(row[col("saturated_pixel_fraction")], "0.25");
        assert_eq!(row[col("wrong_surface_fraction")], "0.25");
        let row2: Vec<&str> = lines[2].split(',').collect();
        assert_eq!(row2[col("threshold")], "auto");
        // No BIP: the error is missing (empty), the valid fraction is 0.
        assert_eq!(row2[col("bip_highest_mean_mm")], "");
        assert_eq!(row2[col("bip_highest_valid_fraction")], "0");

        let j = cells_json(&grid, &cells, json!({"seed": 7}));
        assert_eq!(j["seed"], 7);
        assert_eq!(j["cells"].as_array().unwrap().len(), 2);
        assert_eq!(j["cells"][0]["bip_error_mm"]["mean"], 0.25);
        assert_eq!(
            j["cells"][0]["bip_error_mm_by_rule"][BipRule::EdgeLine.name()]["mean"],
            0.25
        );
        assert!(j["cells"][1]["bip_error_mm"]["mean"].is_null());
        assert!((j["cells"][0]["scan_angle_deg"].as_f64().unwrap() - 40.0).abs() < 1e-12);
    }
}
