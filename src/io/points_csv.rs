//! Points as CSV with a header that names the columns: BIPs written by `glassscan locate --out`
//! and the user's own points read by `glassscan register`. The reader finds `x_mm`, `y_mm` and
//! `z_mm` by name (other columns, in any order, are ignored), so a spreadsheet's export works.
//! A row whose three coordinates are all empty (a pose without a BIP) is skipped; anything
//! else that is not a finite number is an error naming the file, line and column.

use std::path::Path;

use super::atomic::write_atomic;
use super::FileError;
use crate::limits::MAX_LENGTH_MM;

/// A table of named columns, written as CSV with Rust's shortest round-trip floats.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CsvTable {
    /// Column names (the header).
    pub columns: Vec<String>,
    /// Rows of already formatted fields, one per column (no commas or newlines inside).
    pub rows: Vec<Vec<String>>,
}

/// Writes `table` at `path`, atomically. Every row must have one field per column.
pub fn write_csv_table(path: &Path, table: &CsvTable) -> Result<(), FileError> {
    for (i, r) in table.rows.iter().enumerate() {
        if r.len() != table.columns.len() {
            return Err(FileError::CsvFieldCount {
                path: path.to_path_buf(),
                line: i + 2,
                expected: table.columns.len(),
                found: r.len(),
            });
        }
    }
    write_atomic(path, |w| {
        writeln!(w, "{}", table.columns.join(","))?;
        for r in &table.rows {
            writeln!(w, "{}", r.join(","))?;
        }
        Ok(())
    })
}

/// One data row of a CSV read by column names: its 1-based line number and the trimmed fields
/// of the requested columns, in the order they were requested.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedRow<'a> {
    /// 1-based line number (the header is line 1).
    pub line: usize,
    /// The requested columns' fields.
    pub fields: Vec<&'a str>,
}

/// The rows of a CSV text whose header names `columns` (in any order, among others), blank
/// lines skipped. A missing column or a row with another number of fields than the header is
/// an error naming `path` and the line.
pub fn named_rows<'a>(
    path: &Path,
    text: &'a str,
    columns: &[&'static str],
) -> Result<Vec<NamedRow<'a>>, FileError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let header = lines.next().map_or("", |(_, l)| l);
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let index = columns
        .iter()
        .map(|&column| {
            names
                .iter()
                .position(|n| *n == column)
                .ok_or_else(|| FileError::CsvMissingColumn {
                    path: path.to_path_buf(),
                    column,
                    required: columns.join(","),
                    found: header.to_string(),
                })
        })
        .collect::<Result<Vec<usize>, _>>()?;
    let mut rows = Vec::new();
    for (line, text) in lines {
        if text.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = text.split(',').map(str::trim).collect();
        if f.len() != names.len() {
            return Err(FileError::CsvFieldCount {
                path: path.to_path_buf(),
                line,
                expected: names.len(),
                found: f.len(),
            });
        }
        rows.push(NamedRow {
            line,
            fields: index.iter().map(|&i| f[i]).collect(),
        });
    }
    Ok(rows)
}

/// Reads the `x_mm,y_mm,z_mm` columns of a CSV file (mm, each within
/// [`crate::limits::MAX_LENGTH_MM`]); rows with all three empty are skipped. Returns the points with their 1-based line numbers.
pub fn read_points_csv(path: &Path) -> Result<Vec<(usize, [f64; 3])>, FileError> {
    let text = std::fs::read_to_string(path).map_err(|e| FileError::io(path, "read", e))?;
    parse_points_csv(path, &text)
}

/// [`read_points_csv`] of a file's text already in memory (`path` names it in messages).
pub fn parse_points_csv(path: &Path, text: &str) -> Result<Vec<(usize, [f64; 3])>, FileError> {
    const COLUMNS: [&str; 3] = ["x_mm", "y_mm", "z_mm"];
    let mut points = Vec::new();
    for row in named_rows(path, text, &COLUMNS)? {
        if row.fields.iter().all(|f| f.is_empty()) {
            continue;
        }
        let mut p = [0.0; 3];
        for (k, column) in COLUMNS.into_iter().enumerate() {
            p[k] = row.fields[k]
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && v.abs() <= MAX_LENGTH_MM)
                .ok_or_else(|| FileError::CsvValue {
                    path: path.to_path_buf(),
                    line: row.line,
                    column,
                    expected: "a finite number of mm within ±1e5 (100 m)",
                    found: row.fields[k].to_string(),
                })?;
        }
        points.push((row.line, p));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_points_read_back_exactly_and_empty_rows_are_skipped() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bips.csv");
        let f = |v: f64| v.to_string();
        let table = CsvTable {
            columns: ["pose", "x_mm", "y_mm", "z_mm", "label"]
                .map(String::from)
                .to_vec(),
            rows: vec![
                vec![
                    "0".into(),
                    f(1.0 / 3.0),
                    f(-2.5),
                    f(44.000001),
                    "glass_edge".into(),
                ],
                vec![
                    "1".into(),
                    String::new(),
                    String::new(),
                    String::new(),
                    String::new(),
                ],
                vec!["2".into(), f(7.0), f(8.0), f(9.0), String::new()],
            ],
        };
        write_csv_table(&path, &table).unwrap();
        let pts = read_points_csv(&path).unwrap();
        assert_eq!(
            pts,
            vec![(2, [1.0 / 3.0, -2.5, 44.000001]), (4, [7.0, 8.0, 9.0])]
        );
    }

    #[test]
    fn errors_name_the_line_and_column() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.csv");
        std::fs::write(&path, "z_mm,x_mm,y_mm\n1,2,3\n4,nan,6\n").unwrap();
        let e = read_points_csv(&path).unwrap_err().to_string();
        assert!(
            e.contains("p.csv:3") && e.contains("x_mm") && e.contains("nan"),
            "{e}"
        );
        std::fs::write(&path, "a,b\n1,2\n").unwrap();
        let e = read_points_csv(&path).unwrap_err().to_string();
        assert!(e.contains("p.csv:1") && e.contains("x_mm"), "{e}");
        std::fs::write(&path, "x_mm,y_mm,z_mm\n1,2\n").unwrap();
        let e = read_points_csv(&path).unwrap_err().to_string();
        assert!(e.contains("p.csv:2") && e.contains("3"), "{e}");
    }
}
