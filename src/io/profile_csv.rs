//! Line profiles as CSV, one point per line after the header
//! `column,reflection,row_px,x_mm,z_mm,intensity_dn,width_px,threshold_dn,m0_dn,m1_dn_px,label,valid,saturated`.
//!
//! The fields are the firmware's per-peak record (the scanCONTROL SDK's profile container:
//! width, maximum intensity, threshold, x, z, M0, M1 in each of 4 reflection slots;
//! `libmescan.c`, `convert_profile_2_values`), plus the sub-pixel row, the path class `label`
//! (`PathClass::name()`, empty when unknown) and the `saturated` flag (the peak reaches the
//! ADC's full scale). Points are in the profile's order: column order, then reflection index.
//!
//! One naming rule: every physical column ends in its unit (`_px`, `_mm`, `_dn`, `_dn_px` for
//! DN·px); `column` and `reflection` are indices. Booleans are `true`/`false`. Floats are
//! written with Rust's `Display`, which prints the shortest decimal that parses back to the same
//! f64, so a written profile reads back bit for bit. Invalid points carry `NaN` in `row_px`,
//! `x_mm` and `z_mm`, and `false` in `valid`. `pandas.read_csv` reads the file as it is (NaN,
//! booleans and the empty label included).

use std::path::Path;
use std::str::FromStr;

use super::atomic::write_atomic;
use super::csv_read::CsvText;
use super::FileError;
use crate::sensor::path_class::PathClass;
use crate::sensor::profile::{Profile, ProfilePoint, MAX_PEAKS};

/// The column names, in file order.
pub const COLUMNS: [&str; 13] = [
    "column",
    "reflection",
    "row_px",
    "x_mm",
    "z_mm",
    "intensity_dn",
    "width_px",
    "threshold_dn",
    "m0_dn",
    "m1_dn_px",
    "label",
    "valid",
    "saturated",
];

/// Writes `profile` to `path` as CSV, atomically.
pub fn write_profile_csv(path: &Path, profile: &Profile) -> Result<(), FileError> {
    write_atomic(path, |w| {
        writeln!(w, "{}", COLUMNS.join(","))?;
        for p in &profile.points {
            write!(w, "{},{},", p.column, p.reflection)?;
            if p.valid {
                write!(w, "{},{},{},", p.row, p.x_mm, p.z_mm)?;
            } else {
                // Whatever an invalid point's position fields hold, they mean "no measurement".
                w.write_all(b"NaN,NaN,NaN,")?;
            }
            writeln!(
                w,
                "{},{},{},{},{},{},{},{}",
                p.intensity,
                p.width,
                p.threshold,
                p.m0,
                p.m1,
                p.label.map_or("", PathClass::name),
                p.valid,
                p.saturated
            )?;
        }
        Ok(())
    })
}

/// Reads a profile written by [`write_profile_csv`]. The header must name [`COLUMNS`] in order;
/// a line with a missing field or a value that does not parse is reported with its file, line
/// number and column name. The file may have been re-saved by a spreadsheet (byte-order mark,
/// quotes, `\r\n`, `;` with decimal commas: see `csv_read`).
pub fn read_profile_csv(path: &Path) -> Result<Profile, FileError> {
    let text = std::fs::read_to_string(path).map_err(|e| FileError::io(path, "read", e))?;
    parse_profile_csv(path, &text)
}

/// [`read_profile_csv`] of a file's text already in memory (`path` names it in messages).
pub fn parse_profile_csv(path: &Path, text: &str) -> Result<Profile, FileError> {
    let csv = CsvText::parse(path, text)?;
    if csv.header != COLUMNS {
        return Err(FileError::CsvHeader {
            path: path.to_path_buf(),
            expected: COLUMNS.join(","),
            found: csv.header_line(),
        });
    }
    let points = csv
        .rows
        .iter()
        .map(|row| parse_row(path, &csv, row.line, &row.fields))
        .collect::<Result<_, _>>()?;
    Ok(Profile { points })
}

fn parse_row(
    path: &Path,
    csv: &CsvText,
    line: usize,
    fields: &[String],
) -> Result<ProfilePoint, FileError> {
    let error = |index: usize, expected: &'static str| FileError::CsvValue {
        path: path.to_path_buf(),
        line,
        column: COLUMNS[index],
        expected,
        found: fields[index].clone(),
    };
    let number = |index: usize| csv.number(&fields[index]).ok_or(error(index, "a number"));
    let boolean = |index: usize| match fields[index].as_str() {
        "true" => Ok(true),
        "false" => Ok(false),
        _ => Err(error(index, "true or false")),
    };
    // Fields are checked left to right, so the first bad field is the one reported.
    let column = parse_integer(fields, 0, "a non-negative integer", &error)?;
    let reflection: u8 = parse_integer(fields, 1, "an integer from 0 to 3", &error)?;
    if usize::from(reflection) >= MAX_PEAKS {
        return Err(error(1, "an integer from 0 to 3"));
    }
    let row = number(2)?;
    let x_mm = number(3)?;
    let z_mm = number(4)?;
    let intensity = parse_integer(fields, 5, "an integer from 0 to 65535", &error)?;
    let width = parse_integer(fields, 6, "an integer from 0 to 4294967295", &error)?;
    let threshold = parse_integer(fields, 7, "an integer from 0 to 65535", &error)?;
    let m0 = number(8)?;
    let m1 = number(9)?;
    let label = match fields[10].as_str() {
        "" => None,
        name => Some(
            PathClass::from_name(name)
                .ok_or_else(|| error(10, "a path class name (glass_face, table, …) or nothing"))?,
        ),
    };
    let valid = boolean(11)?;
    let saturated = boolean(12)?;
    Ok(ProfilePoint {
        column,
        reflection,
        row,
        x_mm,
        z_mm,
        intensity,
        width,
        threshold,
        m0,
        m1,
        label,
        valid,
        saturated,
    })
}

/// Parses `fields[index]` as an integer type, or reports what the column should have held.
fn parse_integer<T: FromStr>(
    fields: &[String],
    index: usize,
    expected: &'static str,
    error: &impl Fn(usize, &'static str) -> FileError,
) -> Result<T, FileError> {
    fields[index].parse().map_err(|_| error(index, expected))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(column: usize, row: f64, x_mm: f64, z_mm: f64) -> ProfilePoint {
        ProfilePoint {
            column,
            reflection: 0,
            row,
            x_mm,
            z_mm,
            intensity: 1023,
            width: 3,
            threshold: 128,
            m0: 2500.0,
            m1: 2500.0 * row,
            label: None,
            valid: true,
            saturated: row > 500.0,
        }
    }

    fn invalid(column: usize) -> ProfilePoint {
        ProfilePoint {
            column,
            reflection: 0,
            row: f64::NAN,
            x_mm: f64::NAN,
            z_mm: f64::NAN,
            intensity: 0,
            width: 0,
            threshold: 57,
            m0: 0.0,
            m1: 0.0,
            label: None,
            valid: false,
            saturated: false,
        }
    }

    fn write_text(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("profile.csv");
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn round_trip_is_bit_exact() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("profile.csv");
        let mut points = vec![
            point(0, 0.1, 1.0 / 3.0, -0.0),
            invalid(1),
            point(2, 511.5, 5e-324, f64::MAX),
            point(3, 123.456_789_012_345_68, -1e-300, 1e300),
            ProfilePoint {
                intensity: u16::MAX,
                width: u32::MAX,
                threshold: u16::MAX,
                m0: 1.0 / 7.0,
                m1: 1e-310,
                reflection: 3,
                label: Some(PathClass::InternalReflection),
                ..point(usize::MAX, 0.0, 2.0_f64.sqrt(), std::f64::consts::PI)
            },
        ];
        // Every class name, on the reflections of one column.
        for (i, &class) in PathClass::LABELS.iter().enumerate() {
            points.push(ProfilePoint {
                reflection: (i % MAX_PEAKS) as u8,
                label: Some(class),
                ..point(4, 10.0 + i as f64, -1.5, 200.25)
            });
        }
        let profile = Profile { points };
        write_profile_csv(&path, &profile).unwrap();
        let read = read_profile_csv(&path).unwrap();
        assert_eq!(read.points.len(), profile.points.len());
        let exact = |p: &ProfilePoint| {
            (
                p.column,
                p.reflection,
                p.intensity,
                p.width,
                p.threshold,
                p.m0.to_bits(),
                p.m1.to_bits(),
                p.label,
                p.valid,
                p.saturated,
            )
        };
        for (a, b) in read.points.iter().zip(&profile.points) {
            assert_eq!(exact(a), exact(b));
            if b.valid {
                let bits = |p: &ProfilePoint| [p.row, p.x_mm, p.z_mm].map(f64::to_bits);
                assert_eq!(bits(a), bits(b));
            } else {
                assert!(a.row.is_nan() && a.x_mm.is_nan() && a.z_mm.is_nan());
            }
        }
    }

    #[test]
    fn file_layout_is_header_then_one_line_per_point() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("profile.csv");
        let profile = Profile {
            points: vec![
                point(7, 10.5, -2.25, 100.0),
                ProfilePoint {
                    reflection: 1,
                    label: Some(PathClass::GlassEdge),
                    ..point(7, 20.0, -2.25, 120.0)
                },
                invalid(8),
            ],
        };
        write_profile_csv(&path, &profile).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "column,reflection,row_px,x_mm,z_mm,intensity_dn,width_px,threshold_dn,m0_dn,\
             m1_dn_px,label,valid,saturated\n\
             7,0,10.5,-2.25,100,1023,3,128,2500,26250,,true,false\n\
             7,1,20,-2.25,120,1023,3,128,2500,50000,glass_edge,true,false\n\
             8,0,NaN,NaN,NaN,0,0,57,0,0,,false,false\n"
        );
    }

    /// The header line as written.
    fn header() -> String {
        COLUMNS.join(",")
    }

    #[test]
    fn crlf_and_missing_final_newline_are_accepted() {
        let (_dir, path) = write_text(&format!(
            "{}\r\n1,2,2.5,3,4,5,6,7,8,9,table,true,true\r\n2,0,NaN,NaN,NaN,0,0,128,0,0,,false,false",
            header()
        ));
        let read = read_profile_csv(&path).unwrap();
        assert_eq!(read.points.len(), 2);
        let expected = ProfilePoint {
            column: 1,
            reflection: 2,
            row: 2.5,
            x_mm: 3.0,
            z_mm: 4.0,
            intensity: 5,
            width: 6,
            threshold: 7,
            m0: 8.0,
            m1: 9.0,
            label: Some(PathClass::Table),
            valid: true,
            saturated: true,
        };
        assert_eq!(read.points[0], expected);
        assert!(!read.points[1].valid && read.points[1].threshold == 128);
    }

    #[test]
    fn truncated_line_reports_file_and_line() {
        let (_dir, path) = write_text(&format!(
            "{}\n0,0,1.5,2,3,100,4,128,1,1.5,,true,false\n1,0,2.5,3",
            header()
        ));
        let err = read_profile_csv(&path).unwrap_err();
        assert!(
            matches!(
                err,
                FileError::CsvFieldCount {
                    line: 3,
                    expected: 13,
                    found: 4,
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("profile.csv:3:"), "{err}");
    }

    #[test]
    fn bad_number_reports_file_line_and_column() {
        let (_dir, path) = write_text(&format!(
            "{}\n0,0,1.5,2,3,100,4,128,1,1.5,,true,false\n1,0,2.5,3,abc,100,4,128,1,1.5,,true,false\n",
            header()
        ));
        let message = read_profile_csv(&path).unwrap_err().to_string();
        assert!(
            message.ends_with("profile.csv:3: column z_mm: expected a number, got \"abc\""),
            "{message}"
        );
    }

    #[test]
    fn out_of_range_and_bad_fields_are_refused() {
        for (line, column) in [
            ("0,0,1,2,3,70000,4,128,1,1,,true,false", "intensity_dn"),
            ("-1,0,1,2,3,7,4,128,1,1,,true,false", "column"),
            ("0,4,1,2,3,7,4,128,1,1,,true,false", "reflection"),
            ("0,-1,1,2,3,7,4,128,1,1,,true,false", "reflection"),
            ("0,0,1,2,3,7,4,1024000,1,1,,true,false", "threshold_dn"),
            ("0,0,1,2,3,7,4,128,x,1,,true,false", "m0_dn"),
            ("0,0,1,2,3,7,4,128,1,,,true,false", "m1_dn_px"),
            ("0,0,1,2,3,7,4,128,1,1,Table,true,false", "label"),
            ("0,0,1,2,3,7,4,128,1,1,glass,true,false", "label"),
            ("0,0,1,2,3,7,4,128,1,1,,2,false", "valid"),
            ("0,0,1,2,3,7,4,128,1,1,,1,false", "valid"),
            ("0,0,1,2,3,7,4,128,1,1,,true,TRUE", "saturated"),
            ("0,0,1,2,3,7,,128,1,1,,true,false", "width_px"),
        ] {
            let (_dir, path) = write_text(&format!("{}\n{line}\n", header()));
            let err = read_profile_csv(&path).unwrap_err();
            assert!(
                err.to_string()
                    .contains(&format!("profile.csv:2: column {column}: expected")),
                "{line}: {err}"
            );
        }
    }

    #[test]
    fn wrong_or_missing_header_is_refused() {
        for text in [
            "",
            "column,row,x_mm,z_mm,intensity,width,valid\n",
            // The header before units and booleans (glassscan 0.1 before issue 13).
            "column,reflection,row,x_mm,z_mm,intensity,width,threshold,m0,m1,label,valid\n",
            "0,0,1,2,3,7,4,128,1,1,,true,false\n",
        ] {
            let (_dir, path) = write_text(text);
            let err = read_profile_csv(&path).unwrap_err();
            assert!(matches!(err, FileError::CsvHeader { .. }), "{err}");
            assert!(
                err.to_string().contains("profile.csv:1: expected header"),
                "{err}"
            );
        }
    }
}
