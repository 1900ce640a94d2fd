//! The scan-angle study's tables: the points in the edge frame, the per-angle summary, the
//! BIP-error curve (CSV text) and the JSON summary.

use serde_json::{json, Value};

use super::csv_number;
use super::scan_angle::{AngleResult, ScanAngleStudy, SweepAngle};
use super::tally::{by_rule_json, RuleSummary};
use crate::plot::error_bars::{ErrorBars, Series};
use crate::plot::heat_map::HeatMap;

/// `variant,scan_angle_deg,position,out_mm,up_mm,intensity,label`: every valid point of every
/// variant at one angle; `label` is the path class (`sensor::path_class`), empty if none.
pub fn points_csv(angle: &AngleResult) -> String {
    let mut s = String::from("variant,scan_angle_deg,position,out_mm,up_mm,intensity,label\n");
    for p in &angle.points {
        s += &format!(
            "{},{},{},{},{},{},{}\n",
            p.variant.name(),
            p.scan_angle_deg,
            p.position,
            csv_number(Some(p.out_mm)),
            csv_number(Some(p.up_mm)),
            p.intensity,
            p.label.map_or("", |l| l.name())
        );
    }
    s
}

/// One row per (angle, variant): points, nearest-point distance to p_e, saturation and
/// wrong-surface fractions; the bare rows also carry the BIP errors by both rules.
pub fn summary_csv(study: &ScanAngleStudy) -> String {
    let mut s = String::from(
        "scan_angle_deg,variant,positions,valid_points,nearest_mm_mean,nearest_mm_std,\
         nearest_mm_max,saturated_pixel_fraction,saturated_point_fraction,\
         wrong_surface_fraction,bip_highest_mean_mm,bip_highest_std_mm,bip_highest_max_mm,\
         bip_highest_valid_fraction,bip_edge_line_mean_mm,bip_edge_line_std_mm,\
         bip_edge_line_max_mm,bip_edge_line_valid_fraction\n",
    );
    for a in &study.angles {
        let bip = a.bip();
        for v in &a.variants {
            let n = v.nearest_stats();
            let valid = v.valid_points();
            let mut row = vec![
                format!("{}", a.scan_angle_deg),
                v.variant.name().to_owned(),
                v.tallies.len().to_string(),
                valid.to_string(),
                csv_number(Some(n.mean)),
                csv_number(Some(n.std)),
                csv_number(Some(n.max)),
                csv_number(Some(v.saturated_pixel_fraction())),
                csv_number(Some(v.saturated_points as f64 / valid as f64)),
                csv_number(Some(v.wrong_surface_fraction())),
            ];
            for k in 0..2 {
                match (&bip, v.variant == super::scan_angle::Variant::Bare) {
                    (Some(r), true) => row.extend([
                        csv_number(Some(r[k].error_mm.mean)),
                        csv_number(Some(r[k].error_mm.std)),
                        csv_number(Some(r[k].error_mm.max)),
                        csv_number(Some(r[k].valid_fraction)),
                    ]),
                    _ => row.extend(std::iter::repeat_n(String::new(), 4)),
                }
            }
            s += &row.join(",");
            s.push('\n');
        }
    }
    s
}

/// `scan_angle_deg,rule,mean_mm,std_mm,max_mm,n,valid_fraction`: the BIP-error curve.
pub fn sweep_csv(study: &ScanAngleStudy) -> String {
    let mut s = String::from("scan_angle_deg,rule,mean_mm,std_mm,max_mm,n,valid_fraction\n");
    for a in &study.sweep {
        for r in &a.rules {
            s += &format!(
                "{},{},{},{},{},{},{}\n",
                a.scan_angle_deg,
                r.rule.name(),
                csv_number(Some(r.error_mm.mean)),
                csv_number(Some(r.error_mm.std)),
                csv_number(Some(r.error_mm.max)),
                r.error_mm.n,
                csv_number(Some(r.valid_fraction))
            );
        }
    }
    s
}

/// The BIP-error curve: mean ± std of |BIP − p_e| against the scan angle, one series per rule.
pub fn bip_curve_figure(sweep: &[SweepAngle]) -> ErrorBars {
    let series = (0..2)
        .map(|k| Series {
            name: format!("{} rule", super::tally::RULES[k].name()),
            points: sweep
                .iter()
                .map(|a| {
                    let s = &a.rules[k].error_mm;
                    (a.scan_angle_deg, s.mean, s.std)
                })
                .collect(),
        })
        .collect();
    ErrorBars {
        title: "BIP error |BIP − p_e| against scan angle (bare pane, mean ± std)".into(),
        x_desc: "scan angle (deg above the surface)".into(),
        y_desc: "BIP error (mm, log scale)".into(),
        series,
    }
}

/// The angles of the exposure axis with their rules per exposure: the sweep's when there is
/// one (it includes the edge-plot angles), otherwise the edge-plot angles' bare variant.
fn exposure_rows(study: &ScanAngleStudy) -> Vec<(f64, Vec<[RuleSummary; 2]>)> {
    if !study.sweep.is_empty() {
        return study
            .sweep
            .iter()
            .map(|a| (a.scan_angle_deg, a.by_exposure.clone()))
            .collect();
    }
    study
        .angles
        .iter()
        .filter_map(|a| {
            let b = a.bare()?;
            let rules = b.by_exposure.iter().map(|t| RuleSummary::both(t)).collect();
            Some((a.scan_angle_deg, rules))
        })
        .collect()
}

/// `exposure_ms,scan_angle_deg,rule,mean_mm,std_mm,max_mm,n,valid_fraction`: the bare pane's BIP
/// error over the exposure axis × scan angle.
pub fn exposure_csv(study: &ScanAngleStudy, exposures_ms: &[f64]) -> String {
    let mut s =
        String::from("exposure_ms,scan_angle_deg,rule,mean_mm,std_mm,max_mm,n,valid_fraction\n");
    for (e, &ms) in exposures_ms.iter().enumerate() {
        for (angle, rules) in exposure_rows(study) {
            for r in &rules[e] {
                s += &format!(
                    "{ms},{angle},{},{},{},{},{},{}\n",
                    r.rule.name(),
                    csv_number(Some(r.error_mm.mean)),
                    csv_number(Some(r.error_mm.std)),
                    csv_number(Some(r.error_mm.max)),
                    r.error_mm.n,
                    csv_number(Some(r.valid_fraction))
                );
            }
        }
    }
    s
}

/// Heat maps of the bare pane's mean BIP error over scan angle × exposure, one per rule (in
/// [`super::tally::RULES`] order).
pub fn exposure_heat_maps(study: &ScanAngleStudy, exposures_ms: &[f64]) -> Vec<HeatMap> {
    let rows = exposure_rows(study);
    (0..2)
        .map(|k| HeatMap {
            title: format!(
                "BIP error, {} rule: scan angle × exposure (bare pane, mean over positions)",
                super::tally::RULES[k].name()
            ),
            x_desc: "scan angle (deg)".into(),
            x_labels: rows.iter().map(|(a, _)| format!("{a}")).collect(),
            y_desc: "exposure (ms)".into(),
            y_labels: exposures_ms.iter().map(|e| format!("{e}")).collect(),
            values: (0..exposures_ms.len())
                .map(|e| rows.iter().map(|(_, r)| r[e][k].error_mm.mean).collect())
                .collect(),
            value_desc: "mm".into(),
            marked: Vec::new(),
        })
        .collect()
}

/// The JSON summary: `angles` (per angle: `scan_angle_deg`, `bip_error_mm` and
/// `valid_fraction` by the paper's rule, `bip_error_mm_by_rule`, per-variant distances of the
/// points from p_e, per-position BIPs) and `sweep` (the BIP-error curve). `run` holds the
/// settings and files, merged in at the top level.
pub fn summary_json(study: &ScanAngleStudy, run: Value) -> Value {
    let angles: Vec<Value> = study
        .angles
        .iter()
        .map(|a| {
            let bip = a.bip();
            let variants: serde_json::Map<String, Value> = a
                .variants
                .iter()
                .map(|v| {
                    let valid = v.valid_points();
                    (
                        v.variant.name().to_owned(),
                        json!({
                            "valid_points": valid,
                            "nearest_point_mm": v.nearest_stats(),
                            "nearest_point_mm_per_position": v.nearest_mm,
                            "saturated_pixel_fraction": v.saturated_pixel_fraction(),
                            "saturated_point_fraction": v.saturated_points as f64 / valid as f64,
                            "wrong_surface_fraction": v.wrong_surface_fraction(),
                        }),
                    )
                })
                .collect();
            let per_position: Vec<Value> = a.bare().map_or_else(Vec::new, |b| {
                b.tallies
                    .iter()
                    .enumerate()
                    .map(|(i, t)| {
                        let rules: serde_json::Map<String, Value> = t
                            .bips
                            .iter()
                            .map(|o| {
                                (
                                    o.rule.name().to_owned(),
                                    json!({
                                        "error_mm": o.error_mm,
                                        "out_mm": o.edge_mm.map(|e| e.0),
                                        "up_mm": o.edge_mm.map(|e| e.1),
                                        "label": o.label.map(|l| l.name()),
                                    }),
                                )
                            })
                            .collect();
                        json!({"position": i, "bip": rules})
                    })
                    .collect()
            });
            json!({
                "scan_angle_deg": a.scan_angle_deg,
                "bip_error_mm": bip.map(|r| r[0].error_mm),
                "valid_fraction": bip.map(|r| r[0].valid_fraction),
                "bip_error_mm_by_rule": bip.as_ref().map(by_rule_json),
                "variants": variants,
                "bare_positions": per_position,
            })
        })
        .collect();
    let sweep: Vec<Value> = study
        .sweep
        .iter()
        .map(|a| {
            json!({
                "scan_angle_deg": a.scan_angle_deg,
                "bip_error_mm": a.rules[0].error_mm,
                "valid_fraction": a.rules[0].valid_fraction,
                "bip_error_mm_by_rule": by_rule_json(&a.rules),
            })
        })
        .collect();
    let exposure_axis: Vec<Value> = exposure_rows(study)
        .into_iter()
        .map(|(angle, rules)| {
            json!({
                "scan_angle_deg": angle,
                "bip_error_mm_by_rule_per_exposure": rules.iter().map(by_rule_json).collect::<Vec<_>>(),
            })
        })
        .collect();
    super::with_run(
        json!({"angles": angles, "sweep": sweep, "exposure_axis": exposure_axis}),
        run,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::path_class::PathClass;
    use crate::study::scan_angle::{EdgePoint, SweepAngle, Variant, VariantAngle};
    use crate::study::tally::{BipOutcome, PoseTally, RULES};

    fn tally(error: Option<f64>) -> PoseTally {
        PoseTally {
            bips: [0, 1].map(|k| BipOutcome {
                rule: RULES[k],
                error_mm: error.map(|e| e * (k + 1) as f64),
                edge_mm: error.map(|e| (-e, 0.0)),
                label: Some(PathClass::GlassEdge),
            }),
            saturated_pixels: 1,
            pixels: 100,
            valid_points: 2,
            wrong_surface_points: 1,
        }
    }

    fn study() -> ScanAngleStudy {
        let bare = VariantAngle {
            variant: Variant::Bare,
            tallies: vec![tally(Some(0.5)), tally(None)],
            nearest_mm: vec![Some(0.25), None],
            saturated_points: 1,
            by_exposure: vec![vec![tally(Some(0.25)), tally(Some(0.75))]],
        };
        let tape = VariantAngle {
            variant: Variant::Tape,
            ..bare.clone()
        };
        let point = EdgePoint {
            variant: Variant::Bare,
            scan_angle_deg: 40.0,
            position: 1,
            out_mm: -1.5,
            up_mm: 0.25,
            intensity: 700,
            label: Some(PathClass::ThroughGlass),
        };
        let tallies = bare.tallies.clone();
        let exposure_tallies = bare.by_exposure[0].clone();
        ScanAngleStudy {
            angles: vec![AngleResult {
                scan_angle_deg: 40.0,
                variants: vec![tape, bare],
                points: vec![
                    point,
                    EdgePoint {
                        label: None,
                        ..point
                    },
                ],
            }],
            sweep: vec![SweepAngle {
                scan_angle_deg: 40.0,
                rules: RuleSummary::both(&tallies),
                by_exposure: vec![RuleSummary::both(&exposure_tallies)],
                tallies,
            }],
        }
    }

    #[test]
    fn points_csv_has_one_row_per_point() {
        let s = study();
        let csv = points_csv(&s.angles[0]);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines[0],
            "variant,scan_angle_deg,position,out_mm,up_mm,intensity,label"
        );
        assert_eq!(lines[1], "bare,40,1,-1.5,0.25,700,through_glass");
        assert_eq!(lines[2], "bare,40,1,-1.5,0.25,700,");
        assert_eq!(lines.len(), 3);
    }

    #[test]
    fn summary_tables_carry_bip_errors_on_the_bare_rows_only() {
        let s = study();
        let csv = summary_csv(&s);
        let lines: Vec<&str> = csv.lines().collect();
        let header: Vec<&str> = lines[0].split(',').collect();
        let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
        let tape: Vec<&str> = lines[1].split(',').collect();
        let bare: Vec<&str> = lines[2].split(',').collect();
        assert_eq!((tape.len(), bare.len()), (header.len(), header.len()));
        assert_eq!(tape[col("variant")], "tape");
        assert_eq!(tape[col("bip_highest_mean_mm")], "");
        assert_eq!(bare[col("bip_highest_mean_mm")], "0.5");
        assert_eq!(bare[col("bip_edge_line_mean_mm")], "1");
        assert_eq!(bare[col("bip_highest_valid_fraction")], "0.5");
        assert_eq!(bare[col("saturated_pixel_fraction")], "0.01");
        assert_eq!(bare[col("wrong_surface_fraction")], "0.5");
        assert_eq!(bare[col("nearest_mm_mean")], "0.25");

        let sweep = sweep_csv(&s);
        assert_eq!(sweep.lines().count(), 3);
        assert!(sweep.contains("40,highest,0.5,0,0.5,1,0.5\n"), "{sweep}");

        let j = summary_json(&s, json!({"seed": 3}));
        assert_eq!(j["seed"], 3);
        let a = &j["angles"][0];
        assert_eq!(a["scan_angle_deg"], 40.0);
        assert_eq!(a["bip_error_mm"]["mean"], 0.5);
        assert_eq!(a["valid_fraction"], 0.5);
        assert_eq!(a["bip_error_mm_by_rule"]["edge-line"]["mean"], 1.0);
        assert_eq!(a["variants"]["tape"]["nearest_point_mm"]["mean"], 0.25);
        assert!(a["bare_positions"][1]["bip"]["highest"]["error_mm"].is_null());
        assert_eq!(j["sweep"][0]["bip_error_mm_by_rule"]["highest"]["n"], 1);
        let e = &j["exposure_axis"][0]["bip_error_mm_by_rule_per_exposure"][0];
        assert_eq!(e["highest"]["mean"], 0.5);

        let csv = exposure_csv(&s, &[0.15]);
        assert!(csv.contains("0.15,40,highest,0.5,"), "{csv}");
        assert!(csv.contains("0.15,40,edge-line,1,"), "{csv}");
        let maps = exposure_heat_maps(&s, &[0.15]);
        assert_eq!(maps.len(), 2);
        assert_eq!(maps[1].values, vec![vec![1.0]]);
    }
}
