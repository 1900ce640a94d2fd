//! The finding map's tables and figures: one CSV row per (cell, exposure, rule), one heat map
//! of the 10°/40° error ratio per (exposure, rule), and the JSON summary with the region where
//! the paper's finding holds.

use serde_json::{json, Value};

use super::csv_number;
use super::finding_map::{FindingMapConfig, MapCell, HOLDS_MARGIN_MM, HOLDS_RATIO};
use super::tally::RULES;
use crate::plot::heat_map::HeatMap;

/// Degrees of the map's two angles, as typed.
fn angles_deg(cfg: &FindingMapConfig) -> [f64; 2] {
    cfg.angles_rad.map(|a| super::as_typed(a.to_degrees()))
}

/// `arris_width_mm,roughness,exposure_ms,rule,shallow_deg,shallow_mean_mm,shallow_std_mm,
/// shallow_valid_fraction,steep_deg,steep_mean_mm,steep_std_mm,steep_valid_fraction,ratio,
/// holds` (`holds` is 1, 0 or empty when a position had no BIP).
pub fn map_csv(cfg: &FindingMapConfig, cells: &[MapCell]) -> String {
    let [lo, hi] = angles_deg(cfg);
    let mut s = String::from(
        "arris_width_mm,roughness,exposure_ms,rule,shallow_deg,shallow_mean_mm,shallow_std_mm,\
         shallow_valid_fraction,steep_deg,steep_mean_mm,steep_std_mm,steep_valid_fraction,\
         ratio,holds\n",
    );
    for c in cells {
        for (e, exposure_s) in cfg.exposures_s.iter().enumerate() {
            for k in 0..2 {
                let [a, b] = &c.rules[e];
                let holds = c
                    .holds(e, k)
                    .map_or(String::new(), |h| (h as u8).to_string());
                s += &format!(
                    "{},{},{},{},{lo},{},{},{},{hi},{},{},{},{},{holds}\n",
                    c.arris_width_mm,
                    c.roughness,
                    super::as_typed(exposure_s * 1e3),
                    RULES[k].name(),
                    csv_number(Some(a[k].error_mm.mean)),
                    csv_number(Some(a[k].error_mm.std)),
                    csv_number(Some(a[k].valid_fraction)),
                    csv_number(Some(b[k].error_mm.mean)),
                    csv_number(Some(b[k].error_mm.std)),
                    csv_number(Some(b[k].valid_fraction)),
                    csv_number(Some(c.ratio(e, k))),
                );
            }
        }
    }
    s
}

/// One heat map per (exposure, rule): the ratio of the 10° to the 40° mean BIP error over
/// arris width (columns) × roughness (rows). Returns (file stem, figure).
pub fn map_heat_maps(cfg: &FindingMapConfig, cells: &[MapCell]) -> Vec<(String, HeatMap)> {
    let [lo, hi] = angles_deg(cfg);
    let mut maps = Vec::new();
    for (e, exposure_s) in cfg.exposures_s.iter().enumerate() {
        let ms = super::as_typed(exposure_s * 1e3);
        for (k, rule) in RULES.iter().enumerate() {
            let value = |w: f64, alpha: f64| {
                cells
                    .iter()
                    .find(|c| c.arris_width_mm == w && c.roughness == alpha)
                    .map_or(f64::NAN, |c| c.ratio(e, k))
            };
            let fig = HeatMap {
                title: format!(
                    "BIP error at {lo}° ÷ at {hi}°, {} rule, {ms} ms (* = the finding holds)",
                    rule.name()
                ),
                x_desc: "arris width (mm, both corners)".into(),
                x_labels: cfg.arris_widths_mm.iter().map(|w| format!("{w}")).collect(),
                y_desc: "edge roughness α (GGX)".into(),
                y_labels: cfg.roughness.iter().map(|a| format!("{a}")).collect(),
                values: cfg
                    .roughness
                    .iter()
                    .map(|&a| cfg.arris_widths_mm.iter().map(|&w| value(w, a)).collect())
                    .collect(),
                value_desc: format!("error at {lo}° ÷ at {hi}°"),
                marked: cfg
                    .roughness
                    .iter()
                    .map(|&a| {
                        cfg.arris_widths_mm
                            .iter()
                            .map(|&w| {
                                cells
                                    .iter()
                                    .find(|c| c.arris_width_mm == w && c.roughness == a)
                                    .and_then(|c| c.holds(e, k))
                                    .unwrap_or(false)
                            })
                            .collect()
                    })
                    .collect(),
            };
            maps.push((format!("finding_map_{}_{ms}ms", rule.name()), fig));
        }
    }
    maps
}

/// `{"angles_deg", "holds_ratio", "holds_margin_mm", "cells": [...], "holds": {rule:
/// {exposure_ms: [[arris, roughness], …]}}}`.
pub fn map_json(cfg: &FindingMapConfig, cells: &[MapCell]) -> Value {
    let cell_values: Vec<Value> = cells
        .iter()
        .map(|c| {
            let per_exposure: Vec<Value> = (0..cfg.exposures_s.len())
                .map(|e| {
                    let rules: serde_json::Map<String, Value> = (0..2)
                        .map(|k| {
                            let [a, b] = &c.rules[e];
                            (
                                RULES[k].name().to_owned(),
                                json!({
                                    "shallow": a[k].to_json(),
                                    "steep": b[k].to_json(),
                                    "ratio": c.ratio(e, k),
                                    "holds": c.holds(e, k),
                                }),
                            )
                        })
                        .collect();
                    json!({"exposure_ms": super::as_typed(cfg.exposures_s[e] * 1e3), "rules": rules})
                })
                .collect();
            json!({
                "arris_width_mm": c.arris_width_mm,
                "roughness": c.roughness,
                "exposures": per_exposure,
            })
        })
        .collect();
    let holds: serde_json::Map<String, Value> = (0..2)
        .map(|k| {
            let per_exposure: serde_json::Map<String, Value> = (0..cfg.exposures_s.len())
                .map(|e| {
                    let region: Vec<[f64; 2]> = cells
                        .iter()
                        .filter(|c| c.holds(e, k) == Some(true))
                        .map(|c| [c.arris_width_mm, c.roughness])
                        .collect();
                    (
                        format!("{}", super::as_typed(cfg.exposures_s[e] * 1e3)),
                        json!(region),
                    )
                })
                .collect();
            (RULES[k].name().to_owned(), Value::Object(per_exposure))
        })
        .collect();
    json!({
        "angles_deg": angles_deg(cfg),
        "holds_ratio": HOLDS_RATIO,
        "holds_margin_mm": HOLDS_MARGIN_MM,
        "positions": cfg.scan.poses,
        "cells": cell_values,
        "holds": holds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::localise::metrics::Stats;
    use crate::study::tally::RuleSummary;
    use crate::transport::TraceSettings;

    fn cfg() -> FindingMapConfig {
        FindingMapConfig {
            arris_widths_mm: vec![0.0, 0.8],
            roughness: vec![0.3],
            angles_rad: [10f64.to_radians(), 40f64.to_radians()],
            exposures_s: vec![0.15e-3],
            scan: crate::scan::ScanConfig {
                scan_angle_rad: 0.7,
                poses: 2,
                standoff_m: 0.2575,
                start_fraction: 0.1,
            },
            trace: TraceSettings {
                photons: 1,
                adaptive: false,
                max_depth: 1,
                seed: 1,
            },
        }
    }

    fn cell(w: f64, shallow: f64, steep: f64) -> MapCell {
        let s = |k: usize, m: f64| RuleSummary {
            rule: RULES[k],
            error_mm: Stats::from_values(&[m, m]),
            valid_fraction: 1.0,
        };
        MapCell {
            arris_width_mm: w,
            roughness: 0.3,
            rules: vec![[[s(0, shallow), s(1, shallow)], [s(0, steep), s(1, steep)]]],
        }
    }

    #[test]
    fn tables_maps_and_json_name_the_region_where_the_finding_holds() {
        let cells = [cell(0.0, 0.1, 0.4), cell(0.8, 1.0, 0.1)];
        let csv = map_csv(&cfg(), &cells);
        assert_eq!(csv.lines().count(), 1 + 2 * 2);
        assert!(
            csv.contains("0.8,0.3,0.15,edge-line,10,1,0,1,40,0.1,0,1,10,1\n"),
            "{csv}"
        );
        assert!(
            csv.contains("0,0.3,0.15,highest,10,0.1,0,1,40,0.4,0,1,0.25,0\n"),
            "{csv}"
        );
        let maps = map_heat_maps(&cfg(), &cells);
        assert_eq!(maps.len(), 2);
        assert_eq!(maps[1].0, "finding_map_edge-line_0.15ms");
        assert_eq!(maps[1].1.values, vec![vec![0.25, 10.0]]);
        let j = map_json(&cfg(), &cells);
        assert_eq!(j["holds"]["edge-line"]["0.15"], json!([[0.8, 0.3]]));
        assert_eq!(
            j["cells"][1]["exposures"][0]["rules"]["highest"]["holds"],
            true
        );
    }
}
