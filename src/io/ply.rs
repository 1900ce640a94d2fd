//! Point clouds as ASCII PLY (Turk's format, as Open3D, CloudCompare and MeshLab read it):
//! `x y z` as doubles and, optionally, `red green blue` as bytes. Coordinates are written with
//! Rust's shortest round-trip formatting, so they read back bit for bit.
//!
//! The header carries `comment` lines (frame and units, e.g. "base frame B, millimetres").

use std::path::Path;

use super::atomic::write_atomic;
use super::FileError;

/// A point cloud: positions, optional per-point colours, and header comments.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointCloud {
    /// Positions.
    pub points: Vec<[f64; 3]>,
    /// One colour per point, or empty for none.
    pub colors: Vec<[u8; 3]>,
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

/// Writes `cloud` at `path` (atomically). Colours must be absent or one per point.
pub fn write_ply(path: &Path, cloud: &PointCloud) -> Result<(), FileError> {
    let colored = !cloud.colors.is_empty();
    if colored && cloud.colors.len() != cloud.points.len() {
        return Err(FileError::PlyLayout {
            path: path.to_path_buf(),
            line: 0,
            expected: format!("{} colours (one per point)", cloud.points.len()),
            found: format!("{}", cloud.colors.len()),
        });
    }
    write_atomic(path, |w| {
        writeln!(w, "ply\nformat ascii 1.0")?;
        for c in &cloud.comments {
            writeln!(w, "comment {}", c.replace(['\n', '\r'], " "))?;
        }
        writeln!(w, "element vertex {}", cloud.points.len())?;
        writeln!(w, "property double x\nproperty double y\nproperty double z")?;
        if colored {
            writeln!(
                w,
                "property uchar red\nproperty uchar green\nproperty uchar blue"
            )?;
        }
        writeln!(w, "end_header")?;
        for (i, p) in cloud.points.iter().enumerate() {
            write!(w, "{} {} {}", p[0], p[1], p[2])?;
            if colored {
                let c = cloud.colors[i];
                write!(w, " {} {} {}", c[0], c[1], c[2])?;
            }
            writeln!(w)?;
        }
        Ok(())
    })
}

/// Reads an ASCII PLY written by [`write_ply`] (vertex element with x, y, z and optionally
/// red, green, blue; nothing else).
pub fn read_ply(path: &Path) -> Result<PointCloud, FileError> {
    let text = std::fs::read_to_string(path).map_err(|e| FileError::io(path, "read", e))?;
    let bad = |line: usize, expected: &str, found: &str| FileError::PlyLayout {
        path: path.to_path_buf(),
        line,
        expected: expected.to_string(),
        found: found.to_string(),
    };
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let mut next = |expected: &str| lines.next().ok_or_else(|| bad(0, expected, "end of file"));
    let (n, l) = next("\"ply\"")?;
    if l != "ply" {
        return Err(bad(n, "\"ply\"", l));
    }
    let (n, l) = next("\"format ascii 1.0\"")?;
    if l != "format ascii 1.0" {
        return Err(bad(n, "\"format ascii 1.0\"", l));
    }
    let mut cloud = PointCloud::default();
    let mut count = None;
    let mut properties = Vec::new();
    loop {
        let (n, l) = next("a header line")?;
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
            return Err(bad(n, "comment, element vertex, property or end_header", l));
        }
    }
    let xyz = ["double x", "double y", "double z"];
    let rgb = ["uchar red", "uchar green", "uchar blue"];
    let colored = match properties.len() {
        3 => false,
        6 if properties[3..] == rgb => true,
        _ => {
            return Err(bad(
                0,
                "properties x y z [red green blue]",
                &properties.join(", "),
            ))
        }
    };
    if properties[..3] != xyz {
        return Err(bad(0, "properties double x, y, z", &properties.join(", ")));
    }
    let count = count.ok_or_else(|| bad(0, "an \"element vertex N\" line", "none"))?;
    for _ in 0..count {
        let (n, l) = next("a vertex line")?;
        let f: Vec<&str> = l.split_whitespace().collect();
        if f.len() != properties.len() {
            return Err(bad(n, &format!("{} values", properties.len()), l));
        }
        let num = |s: &str| s.parse::<f64>().map_err(|_| bad(n, "a number", s));
        cloud.points.push([num(f[0])?, num(f[1])?, num(f[2])?]);
        if colored {
            let byte = |s: &str| s.parse::<u8>().map_err(|_| bad(n, "a byte 0-255", s));
            cloud.colors.push([byte(f[3])?, byte(f[4])?, byte(f[5])?]);
        }
    }
    Ok(cloud)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_is_exact() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.ply");
        let mut cloud = PointCloud {
            comments: vec!["base frame B, millimetres".into()],
            ..Default::default()
        };
        cloud.push_colored(
            [[0.1, -2.5e-7, 1234.5678901234], [1.0 / 3.0, 2.0, 3.0]],
            [255, 0, 7],
        );
        write_ply(&path, &cloud).unwrap();
        assert_eq!(read_ply(&path).unwrap(), cloud);
        let plain = PointCloud {
            points: vec![[1.0, 2.0, 3.0]],
            ..Default::default()
        };
        write_ply(&path, &plain).unwrap();
        assert_eq!(read_ply(&path).unwrap(), plain);
    }

    #[test]
    fn bad_files_name_the_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.ply");
        std::fs::write(&path, "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\nend_header\n1 2 3\n4 five 6\n").unwrap();
        let e = read_ply(&path).unwrap_err().to_string();
        assert!(e.contains("bad.ply:9") && e.contains("five"), "{e}");
        let mismatched = PointCloud {
            points: vec![[0.0; 3]; 2],
            colors: vec![[0; 3]],
            comments: vec![],
        };
        assert!(write_ply(&path, &mismatched).is_err());
    }
}
