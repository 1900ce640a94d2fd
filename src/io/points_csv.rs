//! Points as CSV with a header that names the columns: BIPs written by `glassscan locate --out`
//! and the user's own points read by `glassscan register`. The reader finds `x_mm`, `y_mm` and
//! `z_mm` by name (other columns, in any order, are ignored), so a spreadsheet's export works.
//! The file may be comma-, semicolon- or tab-separated, quoted, with a byte-order mark (see
//! `csv_read`). A row whose three coordinates are all missing (empty, `NA` or `NaN`: a pose
//! without a BIP) is skipped; anything else that is not a finite number is an error naming the
//! file, line and column.

use std::path::Path;

use super::atomic::write_atomic;
use super::csv_read::CsvText;
use super::FileError;
use crate::limits::MAX_LENGTH_MM;

/// A table of named columns, written as CSV with Rust's shortest round-trip floats.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CsvTable {
    /// Column names (the header).
    pub columns: Vec<String>,
    /// Rows of already formatted fields, one per column; a field with a comma, a quote or a
    /// line break is quoted as RFC 4180 says.
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
                delimiter: ',',
            });
        }
    }
    let line = |fields: &[String]| -> String {
        let quoted: Vec<std::borrow::Cow<str>> = fields.iter().map(|f| quote(f)).collect();
        quoted.join(",")
    };
    write_atomic(path, |w| {
        writeln!(w, "{}", line(&table.columns))?;
        for r in &table.rows {
            writeln!(w, "{}", line(r))?;
        }
        Ok(())
    })
}

/// `field` as a CSV field: as it is, or in double quotes with inner quotes doubled when it
/// holds a comma, a quote or a line break (RFC 4180 §2).
fn quote(field: &str) -> std::borrow::Cow<'_, str> {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\"")).into()
    } else {
        field.into()
    }
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
    let csv = CsvText::parse(path, text)?;
    let index = csv.column_indices(path, &COLUMNS)?;
    let mut points = Vec::new();
    for row in &csv.rows {
        let fields = index.map(|i| row.fields[i].as_str());
        if fields.iter().all(|f| is_missing(f)) {
            continue;
        }
        let mut p = [0.0; 3];
        for (k, column) in COLUMNS.into_iter().enumerate() {
            p[k] = csv
                .number(fields[k])
                .filter(|v| v.is_finite() && v.abs() <= MAX_LENGTH_MM)
                .ok_or_else(|| FileError::CsvValue {
                    path: path.to_path_buf(),
                    line: row.line,
                    column,
                    expected: "a finite number of mm within ±1e5 (100 m)",
                    found: fields[k].to_string(),
                })?;
        }
        points.push((row.line, p));
    }
    Ok(points)
}

/// Whether a field says "no value" as the programs that write these files spell it: empty
/// (glassscan, pandas), `NA` (R), `NaN` or `nan` (numpy, Rust).
pub fn is_missing(field: &str) -> bool {
    matches!(field, "" | "NA" | "NaN" | "nan")
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
    fn fields_with_commas_or_quotes_are_quoted_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        let table = CsvTable {
            columns: vec!["name".into(), "x_mm".into(), "y_mm".into(), "z_mm".into()],
            rows: vec![vec![
                "pane, \"left\"".into(),
                "1".into(),
                "2".into(),
                "3".into(),
            ]],
        };
        write_csv_table(&path, &table).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, "name,x_mm,y_mm,z_mm\n\"pane, \"\"left\"\"\",1,2,3\n");
        let csv = CsvText::parse(&path, &text).unwrap();
        assert_eq!(csv.rows[0].fields[0], "pane, \"left\"");
        assert_eq!(read_points_csv(&path).unwrap(), vec![(2, [1.0, 2.0, 3.0])]);
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
