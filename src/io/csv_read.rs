//! Reading CSV files that people and other programs write, with the `csv` crate (RFC 4180
//! quoting, `\r\n` or `\n`, a UTF-8 byte-order mark skipped): the profiles glassscan wrote
//! itself and the points a user hands to `register` or `score`, as Excel, R, pandas or a
//! text editor write them.
//!
//! The field separator is sniffed from the header line: the most frequent of `,`, `;` and tab
//! outside quotes, `,` when there is none (a one-column file) or on a tie. Excel writes `;` in
//! locales whose decimal separator is the comma (German, French, …), and its numbers then read
//! `1,5`: in a `;`-separated file a number with one comma and no point is read with the comma
//! as the decimal separator, which is the only reading such a file allows.

use std::path::Path;

use super::FileError;

/// One data row: its 1-based line number (the header is line 1) and its fields, trimmed.
#[derive(Clone, Debug, PartialEq)]
pub struct CsvRow {
    /// Line of the file where the row starts.
    pub line: usize,
    /// The fields, one per header column.
    pub fields: Vec<String>,
}

/// A CSV file's header and rows. Blank lines are skipped; every row has one field per header
/// column (else an error naming the line).
#[derive(Clone, Debug, PartialEq)]
pub struct CsvText {
    /// The field separator found in the header.
    pub delimiter: u8,
    /// The header's column names, trimmed and unquoted.
    pub header: Vec<String>,
    /// The data rows.
    pub rows: Vec<CsvRow>,
}

impl CsvText {
    /// Reads `text` (the contents of `path`, which names it in messages).
    pub fn parse(path: &Path, text: &str) -> Result<CsvText, FileError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let delimiter = sniff_delimiter(text.lines().next().unwrap_or(""));
        let mut reader = csv::ReaderBuilder::new()
            .delimiter(delimiter)
            .has_headers(true)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        // From valid UTF-8 text with flexible rows the reader has no error left to report but
        // its own invariants; kept as an error with the line rather than a panic.
        let syntax = |e: csv::Error| FileError::CsvSyntax {
            path: path.to_path_buf(),
            line: e.position().map_or(0, |p| p.line() as usize),
            message: e.to_string(),
        };
        let header: Vec<String> = reader
            .headers()
            .map_err(syntax)?
            .iter()
            .map(str::to_owned)
            .collect();
        // Line numbers from the records' byte offsets. A record's position is where the reader
        // began it: at the terminator of the line before (the reader's own line count is one
        // short there), so the line breaks at the position are skipped first.
        let mut lines = LineCounter::new(text);
        let mut rows = Vec::new();
        for record in reader.records() {
            let record = record.map_err(syntax)?;
            let line = record
                .position()
                .map_or(0, |p| lines.line_at(p.byte() as usize));
            // The reader yields a blank line as a record of one empty field.
            if record.iter().all(str::is_empty) {
                continue;
            }
            if record.len() != header.len() {
                return Err(FileError::CsvFieldCount {
                    path: path.to_path_buf(),
                    line,
                    expected: header.len(),
                    found: record.len(),
                    delimiter: delimiter as char,
                });
            }
            rows.push(CsvRow {
                line,
                fields: record.iter().map(str::to_owned).collect(),
            });
        }
        Ok(CsvText {
            delimiter,
            header,
            rows,
        })
    }

    /// The header line as one string, for messages.
    pub fn header_line(&self) -> String {
        self.header.join(&(self.delimiter as char).to_string())
    }

    /// The positions of `columns` in the header (each must be there, in any order among
    /// others), or an error naming the first missing one.
    pub fn column_indices<const N: usize>(
        &self,
        path: &Path,
        columns: &[&'static str; N],
    ) -> Result<[usize; N], FileError> {
        let mut index = [0; N];
        for (slot, &column) in index.iter_mut().zip(columns) {
            *slot = self
                .header
                .iter()
                .position(|n| n == column)
                .ok_or_else(|| FileError::CsvMissingColumn {
                    path: path.to_path_buf(),
                    column,
                    required: columns.join(","),
                    found: self.header_line(),
                })?;
        }
        Ok(index)
    }

    /// `field` as a number: Rust's float syntax, or with a decimal comma in a `;`-separated
    /// file (see the module documentation). `None` if it is neither.
    pub fn number(&self, field: &str) -> Option<f64> {
        if let Ok(v) = field.parse::<f64>() {
            return Some(v);
        }
        let decimal_comma = self.delimiter == b';'
            && field.bytes().filter(|&b| b == b',').count() == 1
            && !field.contains('.');
        if decimal_comma {
            field.replacen(',', ".", 1).parse().ok()
        } else {
            None
        }
    }
}

/// The 1-based line of byte offsets that only grow.
struct LineCounter<'a> {
    text: &'a [u8],
    byte: usize,
    line: usize,
}

impl<'a> LineCounter<'a> {
    fn new(text: &'a str) -> Self {
        LineCounter {
            text: text.as_bytes(),
            byte: 0,
            line: 1,
        }
    }

    fn line_at(&mut self, byte: usize) -> usize {
        let mut start = byte.min(self.text.len());
        while matches!(self.text.get(start), Some(b'\r' | b'\n')) {
            start += 1;
        }
        let end = start.max(self.byte);
        self.line += self.text[self.byte..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.byte = end;
        self.line
    }
}

/// The most frequent of `,`, `;` and tab outside double quotes in `header`; `,` if none or on
/// a tie with it.
fn sniff_delimiter(header: &str) -> u8 {
    let mut counts = [0usize; 3];
    let mut quoted = false;
    for b in header.bytes() {
        match b {
            b'"' => quoted = !quoted,
            b',' if !quoted => counts[0] += 1,
            b';' if !quoted => counts[1] += 1,
            b'\t' if !quoted => counts[2] += 1,
            _ => {}
        }
    }
    let candidates = [b',', b';', b'\t'];
    let best = (0..3)
        .max_by_key(|&i| (counts[i], std::cmp::Reverse(i)))
        .unwrap_or(0);
    if counts[best] == 0 {
        b','
    } else {
        candidates[best]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> CsvText {
        CsvText::parse(Path::new("t.csv"), text).unwrap()
    }

    #[test]
    fn files_as_excel_r_and_pandas_write_them_read_alike() {
        // The same two points as written by: glassscan/pandas (`to_csv(index=False)`), pandas
        // with its index, Excel "CSV UTF-8" (BOM, CRLF), Excel in a decimal-comma locale
        // (`;`, `1,5`), R's `write.csv` (quoted header, quoted row names) and a tab-separated
        // export.
        let files = [
            "x_mm,y_mm,z_mm\n1.5,-2,300\n0.25,0,301\n",
            ",x_mm,y_mm,z_mm\n0,1.5,-2,300\n1,0.25,0,301\n",
            "\u{feff}x_mm,y_mm,z_mm\r\n1.5,-2,300\r\n0.25,0,301\r\n",
            "x_mm;y_mm;z_mm\r\n1,5;-2;300\r\n0,25;0;301\r\n",
            "\"\",\"x_mm\",\"y_mm\",\"z_mm\"\n\"1\",1.5,-2,300\n\"2\",0.25,0,301\n",
            "x_mm\ty_mm\tz_mm\n1.5\t-2\t300\n0.25\t0\t301\n",
        ];
        for text in files {
            let csv = parse(text);
            let ix = csv
                .column_indices(Path::new("t.csv"), &["x_mm", "y_mm", "z_mm"])
                .unwrap_or_else(|e| panic!("{e}: {text:?}"));
            let got: Vec<Vec<f64>> = csv
                .rows
                .iter()
                .map(|r| {
                    ix.iter()
                        .map(|&i| csv.number(&r.fields[i]).unwrap())
                        .collect()
                })
                .collect();
            assert_eq!(
                got,
                vec![vec![1.5, -2.0, 300.0], vec![0.25, 0.0, 301.0]],
                "{text:?}"
            );
            assert_eq!(csv.rows[0].line, 2);
            assert_eq!(csv.rows[1].line, 3);
        }
    }

    #[test]
    fn blank_lines_are_skipped_and_line_numbers_kept() {
        let csv = parse("a,b\n\n1,2\n\n3,4\n");
        let lines: Vec<usize> = csv.rows.iter().map(|r| r.line).collect();
        assert_eq!(lines, vec![3, 5]);
    }

    #[test]
    fn a_short_row_is_an_error_naming_its_line_and_separator() {
        let e = CsvText::parse(Path::new("t.csv"), "a;b;c\n1;2;3\n4;5\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.csv:3: expected 3 fields separated by ';', got 2"
        );
    }

    #[test]
    fn a_decimal_comma_is_read_only_where_the_separator_allows_it() {
        let semi = parse("a;b\n1,5;2\n");
        assert_eq!(semi.number("1,5"), Some(1.5));
        assert_eq!(semi.number("1,5,6"), None);
        assert_eq!(semi.number("1.000,5"), None);
        let comma = parse("a,b\n1,2\n");
        assert_eq!(comma.number("1,5"), None);
    }

    #[test]
    fn sniffing_ignores_separators_inside_quotes() {
        assert_eq!(sniff_delimiter("\"a;b;c\",d,e"), b',');
        assert_eq!(sniff_delimiter("\"a,b,c\";d;e"), b';');
        assert_eq!(sniff_delimiter("single"), b',');
        assert_eq!(sniff_delimiter("a,b;c"), b',');
    }
}
