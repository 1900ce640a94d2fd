//! Point clouds as PLY (Turk's format, as Open3D, CloudCompare, MeshLab and `plyfile` read
//! it), binary little-endian by default or ASCII: `x y z` as doubles and, each optional,
//! `red green blue` (uchar), `label` (uchar) and `intensity` (ushort). Binary doubles, and
//! ASCII's shortest round-trip decimals, read back bit for bit.
//!
//! The header carries `comment` lines (frame and units, e.g. "base frame B, millimetres", and
//! what a label number means).

use std::path::Path;

use super::atomic::write_atomic;
use super::FileError;

/// How the vertex data is stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PlyEncoding {
    /// `format binary_little_endian 1.0`: 8 bytes per coordinate, ~3× smaller and faster to
    /// load than text.
    #[default]
    BinaryLittleEndian,
    /// `format ascii 1.0`: one text line per vertex.
    Ascii,
}

impl PlyEncoding {
    fn header(self) -> &'static str {
        match self {
            PlyEncoding::BinaryLittleEndian => "format binary_little_endian 1.0",
            PlyEncoding::Ascii => "format ascii 1.0",
        }
    }
}

/// A point cloud: positions, optional per-point colours, labels and intensities, and header
/// comments. Each optional list is empty or holds one entry per point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointCloud {
    /// Positions.
    pub points: Vec<[f64; 3]>,
    /// One colour per point, or empty for none.
    pub colors: Vec<[u8; 3]>,
    /// One label number per point (its meaning in a comment), or empty for none.
    pub labels: Vec<u8>,
    /// One intensity (DN) per point, or empty for none.
    pub intensities: Vec<u16>,
    /// Header comment lines (no newlines).
    pub comments: Vec<String>,
}

impl PointCloud {
    /// Appends `points`, all in `color`.
    pub fn push_colored(&mut self, points: impl IntoIterator<Item = [f64; 3]>, color: [u8; 3]) {
        for p in points {
            self.points.push(p);
            self.colors.push(color);
        }
    }
}

/// The optional properties, in file order after x, y, z.
const RGB: [&str; 3] = ["uchar red", "uchar green", "uchar blue"];
const LABEL: &str = "uchar label";
const INTENSITY: &str = "ushort intensity";

/// Writes `cloud` at `path` (atomically) in `encoding`. Each optional list must be absent or
/// hold one entry per point.
pub fn write_ply(path: &Path, cloud: &PointCloud, encoding: PlyEncoding) -> Result<(), FileError> {
    let n = cloud.points.len();
    for (what, len) in [
        ("colours", cloud.colors.len()),
        ("labels", cloud.labels.len()),
        ("intensities", cloud.intensities.len()),
    ] {
        if len != 0 && len != n {
            return Err(FileError::PlyLayout {
                path: path.to_path_buf(),
                line: 0,
                expected: format!("{n} {what} (one per point) or none"),
                found: format!("{len}"),
            });
        }
    }
    let (colored, labelled, with_intensity) = (
        !cloud.colors.is_empty(),
        !cloud.labels.is_empty(),
        !cloud.intensities.is_empty(),
    );
    let mut properties = vec!["double x", "double y", "double z"];
    if colored {
        properties.extend(RGB);
    }
    if labelled {
        properties.push(LABEL);
    }
    if with_intensity {
        properties.push(INTENSITY);
    }
    write_atomic(path, |w| {
        writeln!(w, "ply\n{}", encoding.header())?;
        for c in &cloud.comments {
            writeln!(w, "comment {}", c.replace(['\n', '\r'], " "))?;
        }
        writeln!(w, "element vertex {n}")?;
        for p in &properties {
            writeln!(w, "property {p}")?;
        }
        writeln!(w, "end_header")?;
        for (i, p) in cloud.points.iter().enumerate() {
            match encoding {
                PlyEncoding::Ascii => {
                    write!(w, "{} {} {}", p[0], p[1], p[2])?;
                    if colored {
                        let c = cloud.colors[i];
                        write!(w, " {} {} {}", c[0], c[1], c[2])?;
                    }
                    if labelled {
                        write!(w, " {}", cloud.labels[i])?;
                    }
                    if with_intensity {
                        write!(w, " {}", cloud.intensities[i])?;
                    }
                    writeln!(w)?;
                }
                PlyEncoding::BinaryLittleEndian => {
                    for v in p {
                        w.write_all(&v.to_le_bytes())?;
                    }
                    if colored {
                        w.write_all(&cloud.colors[i])?;
                    }
                    if labelled {
                        w.write_all(&[cloud.labels[i]])?;
                    }
                    if with_intensity {
                        w.write_all(&cloud.intensities[i].to_le_bytes())?;
                    }
                }
            }
        }
        Ok(())
    })
}

/// Reads a PLY written by [`write_ply`], in either encoding: a vertex element with x, y, z as
/// doubles and then, each optional and in this order, red green blue, label and intensity;
/// nothing else.
pub fn read_ply(path: &Path) -> Result<PointCloud, FileError> {
    let bytes = std::fs::read(path).map_err(|e| FileError::io(path, "read", e))?;
    let bad = |line: usize, expected: &str, found: &str| FileError::PlyLayout {
        path: path.to_path_buf(),
        line,
        expected: expected.to_string(),
        found: found.to_string(),
    };
    // The header is ASCII lines up to and including "end_header\n".
    let mut rest: &[u8] = &bytes;
    let mut line_number = 0;
    let mut next_line = |rest: &mut &[u8]| -> Option<(usize, String)> {
        let end = rest.iter().position(|&b| b == b'\n')?;
        let line = String::from_utf8_lossy(&rest[..end])
            .trim_end_matches('\r')
            .to_string();
        *rest = &rest[end + 1..];
        line_number += 1;
        Some((line_number, line))
    };
    let mut next = |rest: &mut &[u8], expected: &str| {
        next_line(rest).ok_or_else(|| bad(0, expected, "end of file"))
    };
    let (n, l) = next(&mut rest, "\"ply\"")?;
    if l != "ply" {
        return Err(bad(n, "\"ply\"", &l));
    }
    let formats = "\"format binary_little_endian 1.0\" or \"format ascii 1.0\"";
    let (n, l) = next(&mut rest, formats)?;
    let encoding = [PlyEncoding::BinaryLittleEndian, PlyEncoding::Ascii]
        .into_iter()
        .find(|e| e.header() == l)
        .ok_or_else(|| bad(n, formats, &l))?;
    let mut cloud = PointCloud::default();
    let mut count = None;
    let mut properties = Vec::new();
    loop {
        let (n, l) = next(&mut rest, "a header line")?;
        if let Some(c) = l.strip_prefix("comment ") {
            cloud.comments.push(c.to_string());
        } else if let Some(c) = l.strip_prefix("element vertex ") {
            count = Some(
                c.trim()
                    .parse::<usize>()
                    .map_err(|_| bad(n, "a vertex count", c))?,
            );
        } else if let Some(p) = l.strip_prefix("property ") {
            properties.push(p.to_string());
        } else if l == "end_header" {
            break;
        } else {
            return Err(bad(
                n,
                "comment, element vertex, property or end_header",
                &l,
            ));
        }
    }
    let layout = || {
        bad(
            0,
            "properties double x, y, z [uchar red, green, blue] [uchar label] [ushort intensity]",
            &properties.join(", "),
        )
    };
    if properties.len() < 3 || properties[..3] != ["double x", "double y", "double z"] {
        return Err(layout());
    }
    let mut k = 3;
    let colored = properties.get(3..6).is_some_and(|p| p == RGB);
    if colored {
        k = 6;
    }
    let labelled = properties.get(k).is_some_and(|p| p == LABEL);
    k += usize::from(labelled);
    let with_intensity = properties.get(k).is_some_and(|p| p == INTENSITY);
    k += usize::from(with_intensity);
    if k != properties.len() {
        return Err(layout());
    }
    let count = count.ok_or_else(|| bad(0, "an \"element vertex N\" line", "none"))?;
    match encoding {
        PlyEncoding::BinaryLittleEndian => {
            let size = 24
                + 3 * usize::from(colored)
                + usize::from(labelled)
                + 2 * usize::from(with_intensity);
            if count.checked_mul(size) != Some(rest.len()) {
                return Err(bad(
                    0,
                    &format!("{count} vertices of {size} bytes after the header"),
                    &format!("{} bytes", rest.len()),
                ));
            }
            for v in rest.chunks_exact(size) {
                let f = |o: usize| f64::from_le_bytes(v[o..o + 8].try_into().expect("8 bytes"));
                cloud.points.push([f(0), f(8), f(16)]);
                let mut o = 24;
                if colored {
                    cloud.colors.push([v[o], v[o + 1], v[o + 2]]);
                    o += 3;
                }
                if labelled {
                    cloud.labels.push(v[o]);
                    o += 1;
                }
                if with_intensity {
                    cloud.intensities.push(u16::from_le_bytes([v[o], v[o + 1]]));
                }
            }
        }
        PlyEncoding::Ascii => {
            for _ in 0..count {
                let (n, l) = next(&mut rest, "a vertex line")?;
                let f: Vec<&str> = l.split_whitespace().collect();
                if f.len() != properties.len() {
                    return Err(bad(n, &format!("{} values", properties.len()), &l));
                }
                let num = |s: &str| s.parse::<f64>().map_err(|_| bad(n, "a number", s));
                cloud.points.push([num(f[0])?, num(f[1])?, num(f[2])?]);
                let byte = |s: &str| s.parse::<u8>().map_err(|_| bad(n, "a byte 0-255", s));
                let mut o = 3;
                if colored {
                    cloud.colors.push([byte(f[3])?, byte(f[4])?, byte(f[5])?]);
                    o = 6;
                }
                if labelled {
                    cloud.labels.push(byte(f[o])?);
                    o += 1;
                }
                if with_intensity {
                    let dn = f[o]
                        .parse::<u16>()
                        .map_err(|_| bad(n, "an integer 0-65535", f[o]))?;
                    cloud.intensities.push(dn);
                }
            }
        }
    }
    Ok(cloud)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_cloud() -> PointCloud {
        let mut cloud = PointCloud {
            comments: vec!["base frame B, millimetres".into()],
            ..Default::default()
        };
        cloud.push_colored(
            [[0.1, -2.5e-7, 1234.5678901234], [1.0 / 3.0, 2.0, 3.0]],
            [255, 0, 7],
        );
        cloud
    }

    #[test]
    fn round_trip_is_exact_in_both_encodings_with_every_optional_property() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.ply");
        let full = PointCloud {
            labels: vec![3, 11],
            intensities: vec![0, 1023],
            ..sample_cloud()
        };
        let plain = PointCloud {
            points: vec![[1.0, 2.0, 3.0]],
            ..Default::default()
        };
        let only_labels = PointCloud {
            labels: vec![7],
            ..plain.clone()
        };
        for encoding in [PlyEncoding::BinaryLittleEndian, PlyEncoding::Ascii] {
            for cloud in [&full, &sample_cloud(), &plain, &only_labels] {
                write_ply(&path, cloud, encoding).unwrap();
                assert_eq!(&read_ply(&path).unwrap(), cloud, "{encoding:?}");
            }
        }
    }

    #[test]
    fn binary_layout_is_the_header_then_packed_little_endian_vertices() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("b.ply");
        let cloud = PointCloud {
            points: vec![[1.0, -2.0, 0.5]],
            labels: vec![9],
            intensities: vec![0x0102],
            ..Default::default()
        };
        write_ply(&path, &cloud, PlyEncoding::BinaryLittleEndian).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let header = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n\
                      property double x\nproperty double y\nproperty double z\n\
                      property uchar label\nproperty ushort intensity\nend_header\n";
        assert_eq!(&bytes[..header.len()], header.as_bytes());
        let body = &bytes[header.len()..];
        assert_eq!(body.len(), 24 + 1 + 2);
        assert_eq!(&body[8..16], &(-2.0f64).to_le_bytes());
        assert_eq!(&body[24..], &[9, 0x02, 0x01]);
    }

    #[test]
    fn bad_files_name_the_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.ply");
        std::fs::write(&path, "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\nend_header\n1 2 3\n4 five 6\n").unwrap();
        let e = read_ply(&path).unwrap_err().to_string();
        assert!(e.contains("bad.ply:9") && e.contains("five"), "{e}");
        let truncated = PointCloud {
            points: vec![[0.0; 3]; 2],
            ..Default::default()
        };
        write_ply(&path, &truncated, PlyEncoding::BinaryLittleEndian).unwrap();
        let mut bytes = std::fs::read(&path).unwrap();
        bytes.truncate(bytes.len() - 5);
        std::fs::write(&path, &bytes).unwrap();
        let e = read_ply(&path).unwrap_err().to_string();
        assert!(
            e.contains("2 vertices of 24 bytes") && e.contains("43 bytes"),
            "{e}"
        );
        let mismatched = PointCloud {
            points: vec![[0.0; 3]; 2],
            colors: vec![[0; 3]],
            ..Default::default()
        };
        assert!(write_ply(&path, &mismatched, PlyEncoding::Ascii).is_err());
    }
}
