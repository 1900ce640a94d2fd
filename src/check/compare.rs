//! Metrics against the baseline: a verdict per metric and the table `check` prints.

use std::collections::BTreeMap;

/// A case's metrics by name; `None` where the run produced none (e.g. no registration).
pub type Metrics = BTreeMap<String, Option<f64>>;

/// Which way is better.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Better {
    /// Smaller values are better (errors).
    Lower,
    /// Larger values are better (counts, convergence).
    Higher,
}

/// A metric's definition.
#[derive(Clone, Copy, Debug)]
pub struct MetricDef {
    /// Name in suites, baselines and tables.
    pub name: &'static str,
    /// Which way is better.
    pub better: Better,
    /// Tolerance when the suite sets none (absolute, in the metric's unit). Runs are
    /// deterministic, so these only absorb float reordering (compiler, CPU) and separate it
    /// from real change: a fiftieth of a millimetre is a tenth of the profile's point spacing
    /// at mid range (docs/parameters.md §1c).
    pub default_tolerance: f64,
}

/// Every metric a case reports.
pub const METRICS: [MetricDef; 9] = [
    MetricDef {
        name: "bips",
        better: Better::Higher,
        default_tolerance: 0.0,
    },
    MetricDef {
        name: "converged",
        better: Better::Higher,
        default_tolerance: 0.0,
    },
    MetricDef {
        name: "valid_point_fraction",
        better: Better::Higher,
        default_tolerance: 0.02,
    },
    MetricDef {
        name: "bip_error_mean_mm",
        better: Better::Lower,
        default_tolerance: 0.02,
    },
    MetricDef {
        name: "bip_error_max_mm",
        better: Better::Lower,
        default_tolerance: 0.05,
    },
    MetricDef {
        name: "pose_translation_mm",
        better: Better::Lower,
        default_tolerance: 0.02,
    },
    MetricDef {
        name: "pose_rotation_deg",
        better: Better::Lower,
        default_tolerance: 0.005,
    },
    MetricDef {
        name: "task_error_mean_mm",
        better: Better::Lower,
        default_tolerance: 0.02,
    },
    MetricDef {
        name: "task_error_max_mm",
        better: Better::Lower,
        default_tolerance: 0.05,
    },
];

/// What became of one metric.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Within tolerance of the baseline.
    Ok,
    /// Worse than the baseline by more than the tolerance, or lost (a value became none).
    Regressed,
    /// Better by more than the tolerance: update the baseline.
    Improved,
    /// No baseline value to compare with.
    New,
}

/// One row of the comparison.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Row {
    /// Case name.
    pub case: String,
    /// Metric name.
    pub metric: &'static str,
    /// Baseline value (none if absent).
    pub baseline: Option<f64>,
    /// Current value.
    pub current: Option<f64>,
    /// Tolerance applied.
    pub tolerance: f64,
    /// The verdict.
    pub verdict: Verdict,
}

/// Compares `current` with `baseline` (none: a new case) under `tolerance` (per metric,
/// falling back to each metric's default).
pub fn compare(
    case: &str,
    current: &Metrics,
    baseline: Option<&Metrics>,
    tolerance: &BTreeMap<String, f64>,
) -> Vec<Row> {
    METRICS
        .iter()
        .map(|m| {
            let cur = current.get(m.name).copied().flatten();
            let base = baseline.and_then(|b| b.get(m.name).copied().flatten());
            let tol = tolerance
                .get(m.name)
                .copied()
                .unwrap_or(m.default_tolerance);
            let verdict = match (base, cur) {
                (None, _) if baseline.is_none_or(|b| !b.contains_key(m.name)) => Verdict::New,
                (None, None) => Verdict::Ok,
                (None, Some(_)) => Verdict::Improved,
                (Some(_), None) => Verdict::Regressed,
                (Some(b), Some(c)) => {
                    let worse_by = match m.better {
                        Better::Lower => c - b,
                        Better::Higher => b - c,
                    };
                    if worse_by > tol {
                        Verdict::Regressed
                    } else if -worse_by > tol {
                        Verdict::Improved
                    } else {
                        Verdict::Ok
                    }
                }
            };
            Row {
                case: case.to_string(),
                metric: m.name,
                baseline: base,
                current: cur,
                tolerance: tol,
                verdict,
            }
        })
        .collect()
}

/// The rows as a fixed-width table (all rows, or only those not `Ok`).
pub fn table(rows: &[Row], only_changes: bool) -> String {
    let fmt = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.4}"));
    let mut out = format!(
        "{:<24} {:<22} {:>10} {:>10} {:>8}  {}\n",
        "case", "metric", "baseline", "current", "tol", "verdict"
    );
    for r in rows
        .iter()
        .filter(|r| !only_changes || r.verdict != Verdict::Ok)
    {
        out += &format!(
            "{:<24} {:<22} {:>10} {:>10} {:>8}  {:?}\n",
            r.case,
            r.metric,
            fmt(r.baseline),
            fmt(r.current),
            format!("{:.4}", r.tolerance),
            r.verdict
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn metrics(pairs: &[(&str, Option<f64>)]) -> Metrics {
        pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
    }

    fn verdict(rows: &[Row], name: &str) -> Verdict {
        rows.iter().find(|r| r.metric == name).unwrap().verdict
    }

    #[test]
    fn verdicts_follow_direction_and_tolerance() {
        let base = metrics(&[
            ("bips", Some(12.0)),
            ("bip_error_mean_mm", Some(0.10)),
            ("task_error_max_mm", Some(0.20)),
            ("pose_rotation_deg", Some(0.01)),
            ("converged", Some(1.0)),
        ]);
        let cur = metrics(&[
            ("bips", Some(11.0)),               // fewer BIPs: worse
            ("bip_error_mean_mm", Some(0.115)), // +0.015 < 0.02: ok
            ("task_error_max_mm", Some(0.10)),  // −0.10: improved
            ("pose_rotation_deg", None),        // lost: regressed
            ("converged", Some(1.0)),
        ]);
        let rows = compare("c", &cur, Some(&base), &BTreeMap::new());
        assert_eq!(verdict(&rows, "bips"), Verdict::Regressed);
        assert_eq!(verdict(&rows, "bip_error_mean_mm"), Verdict::Ok);
        assert_eq!(verdict(&rows, "task_error_max_mm"), Verdict::Improved);
        assert_eq!(verdict(&rows, "pose_rotation_deg"), Verdict::Regressed);
        assert_eq!(verdict(&rows, "converged"), Verdict::Ok);
        assert_eq!(verdict(&rows, "valid_point_fraction"), Verdict::New);
        // A tighter tolerance turns the small drift into a regression.
        let tight: BTreeMap<String, f64> = [("bip_error_mean_mm".to_string(), 0.01)].into();
        let rows = compare("c", &cur, Some(&base), &tight);
        assert_eq!(verdict(&rows, "bip_error_mean_mm"), Verdict::Regressed);
        // No baseline at all: everything is new.
        assert!(compare("c", &cur, None, &BTreeMap::new())
            .iter()
            .all(|r| r.verdict == Verdict::New));
        let t = table(&rows, true);
        assert!(t.contains("bip_error_mean_mm") && t.contains("Regressed"));
        assert!(!t.contains("converged"));
    }
}
