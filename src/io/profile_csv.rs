//! Line profiles as CSV, one point per line after the header
//! `column,reflection,row,x_mm,z_mm,intensity,width,threshold,m0,m1,label,valid`.
//!
//! The fields are the firmware's per-peak record (PARAMETERS.md §1b: width, maximum intensity,
//! threshold, x, z, M0, M1, and the reflection slot 0…3), plus the sub-pixel row and the path
//! class `label` (`PathClass::name()`, empty when unknown). Points are in the profile's order:
//! column order, then reflection index.
//!
//! Floats are written with Rust's `Display`, which prints the shortest decimal that parses back
//! to the same f64, so a written profile reads back bit for bit. Invalid points carry `NaN` in
//! `row`, `x_mm` and `z_mm`, and `0` in `valid` (`1` for valid points).

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use super::atomic::write_atomic;
use super::FileError;
use crate::sensor::path_class::PathClass;
use crate::sensor::profile::{Profile, ProfilePoint, MAX_PEAKS};

/// The header line, which is also the column order.
pub const HEADER: &str =
    "column,reflection,row,x_mm,z_mm,intensity,width,threshold,m0,m1,label,valid";

/// The column names of [`HEADER`], for error messages.
const COLUMNS: [&str; 12] = [
    "column",
    "reflection",
    "row",
    "x_mm",
    "z_mm",
    "intensity",
    "width",
    "threshold",
    "m0",
    "m1",
    "label",
    "valid",
];

/// Writes `profile` to `path` as CSV, atomically.
pub fn write_profile_csv(path: &Path, profile: &Profile) -> Result<(), FileError> {
    write_atomic(path, |w| {
        writeln!(w, "{HEADER}")?;
        for p in &profile.points {
            writeln!(w, "{}", CsvLine(p))?;
        }
        Ok(())
    })
}

/// One point formatted as a CSV line (without the newline).
struct CsvLine<'a>(&'a ProfilePoint);

impl fmt::Display for CsvLine<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = self.0;
        write!(f, "{},{},", p.column, p.reflection)?;
        if p.valid {
            write!(f, "{},{},{},", p.row, p.x_mm, p.z_mm)?;
        } else {
            // Whatever an invalid point's position fields hold, they mean "no measurement".
            f.write_str("NaN,NaN,NaN,")?;
        }
        let label = p.label.map_or("", PathClass::name);
        write!(
            f,
            "{},{},{},{},{},{label},{}",
            p.intensity,
            p.width,
            p.threshold,
            p.m0,
            p.m1,
            u8::from(p.valid)
        )
    }
}

/// Reads a profile written by [`write_profile_csv`]. The header must match [`HEADER`] exactly;
/// a line with a missing field or a value that does not parse is reported with its file, line
/// number and column name. `\r\n` line endings are accepted.
pub fn read_profile_csv(path: &Path) -> Result<Profile, FileError> {
    let text = std::fs::read_to_string(path).map_err(|e| FileError::io(path, "read", e))?;
    parse_profile_csv(path, &text)
}

/// [`read_profile_csv`] of a file's text already in memory (`path` names it in messages).
pub fn parse_profile_csv(path: &Path, text: &str) -> Result<Profile, FileError> {
    let mut lines = text.lines();
    let header = lines.next().unwrap_or("");
    if header != HEADER {
        return Err(FileError::CsvHeader {
            path: path.to_path_buf(),
            expected: HEADER,
            found: header.to_string(),
        });
    }
    let mut points = Vec::new();
    for (i, line) in lines.enumerate() {
        // The header is line 1.
        points.push(parse_line(path, i + 2, line)?);
    }
    Ok(Profile { points })
}

fn parse_line(path: &Path, line_number: usize, line: &str) -> Result<ProfilePoint, FileError> {
    let fields: Vec<&str> = line.split(',').collect();
    let Ok(fields) = <[&str; COLUMNS.len()]>::try_from(fields.as_slice()) else {
        return Err(FileError::CsvFieldCount {
            path: path.to_path_buf(),
            line: line_number,
            expected: COLUMNS.len(),
            found: fields.len(),
        });
    };
    let error = |index: usize, expected: &'static str| FileError::CsvValue {
        path: path.to_path_buf(),
        line: line_number,
        column: COLUMNS[index],
        expected,
        found: fields[index].to_string(),
    };
    // Fields are checked left to right, so the first bad field is the one reported.
    let column = parse_field(&fields, 0, "a non-negative integer", &error)?;
    let reflection: u8 = parse_field(&fields, 1, "an integer from 0 to 3", &error)?;
    if usize::from(reflection) >= MAX_PEAKS {
        return Err(error(1, "an integer from 0 to 3"));
    }
    let row = parse_field(&fields, 2, "a number", &error)?;
    let x_mm = parse_field(&fields, 3, "a number", &error)?;
    let z_mm = parse_field(&fields, 4, "a number", &error)?;
    let intensity = parse_field(&fields, 5, "an integer from 0 to 65535", &error)?;
    let width = parse_field(&fields, 6, "an integer from 0 to 4294967295", &error)?;
    let threshold = parse_field(&fields, 7, "an integer from 0 to 65535", &error)?;
    let m0 = parse_field(&fields, 8, "a number", &error)?;
    let m1 = parse_field(&fields, 9, "a number", &error)?;
    let label = match fields[10] {
        "" => None,
        name => Some(
            PathClass::from_name(name)
                .ok_or_else(|| error(10, "a path class name (glass_face, table, …) or nothing"))?,
        ),
    };
    let valid = match fields[11] {
        "0" => false,
        "1" => true,
        _ => return Err(error(11, "0 or 1")),
    };
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
    })
}

/// Parses `fields[index]`, or reports what the column should have held.
fn parse_field<T: FromStr>(
    fields: &[&str],
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
            "column,reflection,row,x_mm,z_mm,intensity,width,threshold,m0,m1,label,valid\n\
             7,0,10.5,-2.25,100,1023,3,128,2500,26250,,1\n\
             7,1,20,-2.25,120,1023,3,128,2500,50000,glass_edge,1\n\
             8,0,NaN,NaN,NaN,0,0,57,0,0,,0\n"
        );
    }

    #[test]
    fn crlf_and_missing_final_newline_are_accepted() {
        let (_dir, path) = write_text(&format!(
            "{HEADER}\r\n1,2,2.5,3,4,5,6,7,8,9,table,1\r\n2,0,NaN,NaN,NaN,0,0,128,0,0,,0"
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
        };
        assert_eq!(read.points[0], expected);
        assert!(!read.points[1].valid && read.points[1].threshold == 128);
    }

    #[test]
    fn truncated_line_reports_file_and_line() {
        let (_dir, path) = write_text(&format!(
            "{HEADER}\n0,0,1.5,2,3,100,4,128,1,1.5,,1\n1,0,2.5,3"
        ));
        let err = read_profile_csv(&path).unwrap_err();
        assert!(
            matches!(
                err,
                FileError::CsvFieldCount {
                    line: 3,
                    expected: 12,
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
            "{HEADER}\n0,0,1.5,2,3,100,4,128,1,1.5,,1\n1,0,2.5,3,abc,100,4,128,1,1.5,,1\n"
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
            ("0,0,1,2,3,70000,4,128,1,1,,1", "intensity"),
            ("-1,0,1,2,3,7,4,128,1,1,,1", "column"),
            ("0,4,1,2,3,7,4,128,1,1,,1", "reflection"),
            ("0,-1,1,2,3,7,4,128,1,1,,1", "reflection"),
            ("0,0,1,2,3,7,4,1024000,1,1,,1", "threshold"),
            ("0,0,1,2,3,7,4,128,x,1,,1", "m0"),
            ("0,0,1,2,3,7,4,128,1,,,1", "m1"),
            ("0,0,1,2,3,7,4,128,1,1,Table,1", "label"),
            ("0,0,1,2,3,7,4,128,1,1,glass,1", "label"),
            ("0,0,1,2,3,7,4,128,1,1,,2", "valid"),
            ("0,0,1,2,3,7,4,128,1,1,,true", "valid"),
            ("0,0,1,2,3,7,,128,1,1,,1", "width"),
        ] {
            let (_dir, path) = write_text(&format!("{HEADER}\n{line}\n"));
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
            "0,0,1,2,3,7,4,128,1,1,,1\n",
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
