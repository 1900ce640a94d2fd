//! Scoring a user's Border Identifier Points against a dataset's ground truth: per sample
//! |BIP − p_e| in the base frame, summarised as mean, standard deviation and maximum (the
//! paper's BIP error, Adrian & Pham, Section VI).
//!
//! The BIPs come as a CSV whose header names at least the columns `sample,x_mm,y_mm,z_mm`
//! (base frame, millimetres), in any order, other columns ignored; one row per sample at most.
//! Samples of the dataset without a row are reported as missing; samples whose laser plane
//! misses the border (no p_e) are reported apart and not scored.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use super::manifest::{for_each_line, MANIFEST};
use super::DatasetError;
use crate::io::csv_read::CsvText;
use crate::localise::metrics::Stats;

/// The columns a BIPs CSV must have.
pub const REQUIRED: [&str; 4] = ["sample", "x_mm", "y_mm", "z_mm"];

/// One BIP row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BipRow {
    /// Sample index.
    pub sample: u64,
    /// The BIP in the base frame (mm).
    pub point_mm: [f64; 3],
    /// 1-based line in the CSV.
    pub line: usize,
}

/// Reads a BIPs CSV (see the module documentation). Errors name the file, line and column.
pub fn read_bips_csv(path: &Path) -> Result<Vec<BipRow>, DatasetError> {
    let text = std::fs::read_to_string(path).map_err(|e| DatasetError::io(path, "read", e))?;
    let csv = CsvText::parse(path, &text)?;
    let index = csv.column_indices(path, &REQUIRED)?;
    let mut rows = Vec::new();
    for row in &csv.rows {
        let bad = |k: usize, message: String| crate::io::FileError::CsvField {
            path: path.to_path_buf(),
            line: row.line,
            column: REQUIRED[k].to_owned(),
            message,
        };
        let fields = index.map(|i| row.fields[i].as_str());
        let field = fields[0];
        let sample = field.parse::<u64>().map_err(|_| {
            bad(
                0,
                format!("expected a sample index (a non-negative integer), got \"{field}\""),
            )
        })?;
        let mut point_mm = [0.0; 3];
        for (k, v) in point_mm.iter_mut().enumerate() {
            let field = fields[k + 1];
            *v = csv
                .number(field)
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(k + 1, format!("expected a finite number, got \"{field}\"")))?;
        }
        rows.push(BipRow {
            sample,
            point_mm,
            line: row.line,
        });
    }
    Ok(rows)
}

/// The score of a BIPs file against a dataset.
#[derive(Debug, Serialize)]
pub struct ScoreReport {
    /// Samples scored (with both a BIP and p_e).
    pub scored: usize,
    /// Mean |BIP − p_e| (mm), `None` when nothing was scored.
    pub mean_mm: Option<f64>,
    /// Sample standard deviation (mm).
    pub std_mm: Option<f64>,
    /// Largest error (mm).
    pub max_mm: Option<f64>,
    /// The sample with the largest error.
    pub worst_sample: Option<u64>,
    /// Samples of the dataset with ground truth but no BIP.
    pub missing: Vec<u64>,
    /// Samples without ground truth p_e (laser plane misses the border); their BIPs, if any,
    /// are not scored.
    pub without_ground_truth: Vec<u64>,
    /// Per scored sample: (index, error in mm), in index order.
    pub errors_mm: Vec<(u64, f64)>,
}

/// Scores `bips` against the dataset in `dataset` (its merged `manifest.jsonl`).
pub fn score(dataset: &Path, bips: &Path) -> Result<ScoreReport, DatasetError> {
    let manifest = dataset.join(MANIFEST);
    if !manifest.is_file() {
        return Err(DatasetError::NotADataset {
            path: manifest,
            message: "not found: score needs a whole dataset (run `glassscan merge` on a \
                      sharded one first)"
                .into(),
        });
    }
    let rows = read_bips_csv(bips)?;
    let mut truth: BTreeMap<u64, Option<[f64; 3]>> = BTreeMap::new();
    for_each_line(&manifest, |_, line| {
        truth.insert(line.index, line.edge_point_mm);
        Ok(())
    })?;
    let mut by_sample: BTreeMap<u64, BipRow> = BTreeMap::new();
    for row in rows {
        let bad = |message: String| -> DatasetError {
            crate::io::FileError::CsvField {
                path: bips.to_path_buf(),
                line: row.line,
                column: "sample".into(),
                message,
            }
            .into()
        };
        if !truth.contains_key(&row.sample) {
            return Err(bad(format!(
                "sample {} is not in the dataset {} ({} samples)",
                row.sample,
                dataset.display(),
                truth.len()
            )));
        }
        if let Some(first) = by_sample.insert(row.sample, row) {
            return Err(bad(format!(
                "sample {} already has a BIP on line {}",
                row.sample, first.line
            )));
        }
    }
    let mut report = ScoreReport {
        scored: 0,
        mean_mm: None,
        std_mm: None,
        max_mm: None,
        worst_sample: None,
        missing: Vec::new(),
        without_ground_truth: Vec::new(),
        errors_mm: Vec::new(),
    };
    for (&index, p_e) in &truth {
        match (p_e, by_sample.get(&index)) {
            (None, _) => report.without_ground_truth.push(index),
            (Some(_), None) => report.missing.push(index),
            (Some(p), Some(b)) => {
                let d = (0..3)
                    .map(|k| (b.point_mm[k] - p[k]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                report.errors_mm.push((index, d));
            }
        }
    }
    let values: Vec<f64> = report.errors_mm.iter().map(|e| e.1).collect();
    let stats = Stats::from_values(&values);
    report.scored = stats.n;
    if stats.n > 0 {
        report.mean_mm = Some(stats.mean);
        report.std_mm = Some(stats.std);
        report.max_mm = Some(stats.max);
        report.worst_sample = report
            .errors_mm
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|e| e.0);
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bips.csv");
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn columns_are_found_by_name_in_any_order() {
        let (_d, p) = csv("note,z_mm,sample,y_mm,x_mm\nok,3.5,2,-1,10\n\n a , 4 , 0 , 0 , 0 \n");
        let rows = read_bips_csv(&p).unwrap();
        assert_eq!(
            rows,
            [
                BipRow {
                    sample: 2,
                    point_mm: [10.0, -1.0, 3.5],
                    line: 2
                },
                BipRow {
                    sample: 0,
                    point_mm: [0.0, 0.0, 4.0],
                    line: 4
                }
            ]
        );
    }

    #[test]
    fn malformed_csvs_name_file_line_and_column() {
        for (text, expected) in [
            (
                "sample,x_mm,y_mm\n1,2,3\n",
                "bips.csv:1: expected a header with the column `z_mm`",
            ),
            ("", "bips.csv:1: expected a header with the column `sample`"),
            (
                "sample,x_mm,y_mm,z_mm\n1,2,3\n",
                "bips.csv:2: expected 4 fields separated by ',', got 3",
            ),
            (
                "sample,x_mm,y_mm,z_mm\n1,2,3,4\n-1,2,3,4\n",
                "bips.csv:3: column sample: expected a sample index",
            ),
            (
                "sample,x_mm,y_mm,z_mm\n1,2,abc,4\n",
                "bips.csv:2: column y_mm: expected a finite number, got \"abc\"",
            ),
            (
                "sample,x_mm,y_mm,z_mm\n1,2,3,NaN\n",
                "bips.csv:2: column z_mm: expected a finite number",
            ),
        ] {
            let (_d, p) = csv(text);
            let message = read_bips_csv(&p).unwrap_err().to_string();
            assert!(message.contains(expected), "{text:?}: {message}");
        }
    }
}
