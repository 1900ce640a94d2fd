//! Flat-shaded surfaces swept along a panel's rim: the tape sheet (an open profile) and the
//! cover (a closed one). A profile is a list of (inset, height) points (m) in the panel's
//! section plane; the inset may be negative (outside the outline) and the height may exceed
//! the thickness. Each profile point is placed at every rim point at `outline − inset·miter`
//! (so sharp outline corners get miters, arcs stay concentric; the face inset uses the rim's
//! exact face point) and bent with the panel, like
//! the edge band; where a deep inset would fold at a sharp corner, the row is closed there
//! (`row`). Profiles listed in the edge section's sense (over the top towards the
//! outside, then down) give triangles whose normals point away from the glass.
//!
//! Triangles are tagged `Solid` and carry no vertex normals: the surfaces are opaque
//! Lambertian objects (tape, cover), shaded flat.

use nalgebra::Point2;

use super::contour::{segments, RimPoint};
use super::{polygon, Curvature};
use crate::geometry::mesh::Mesh;

/// `points` with every segment longer than `max_step_m` split evenly, so that a profile laid
/// across a bent face follows the bend with chords no longer than the face's own.
pub(super) fn refine(points: &[[f64; 2]], max_step_m: f64, closed: bool) -> Vec<[f64; 2]> {
    let n = points.len();
    let spans = if closed { n } else { n.saturating_sub(1) };
    let mut out = Vec::with_capacity(n);
    for i in 0..spans {
        let (a, b) = (points[i], points[(i + 1) % n]);
        out.push(a);
        let steps = segments((b[0] - a[0]).hypot(b[1] - a[1]) / max_step_m);
        for k in 1..steps {
            let f = k as f64 / steps as f64;
            out.push([a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f]);
        }
    }
    if !closed {
        out.extend(points.last());
    }
    out
}

/// The flat points of the profile row at `inset_m` along `rim`, at the rim's exact face points
/// for `face_inset_m`. The rim's samples next to a sharp corner lie closer to it than a deep
/// inset (a 20 mm cover on a square corner, with samples every 5 mm): their inset points fall
/// behind the corner's mitered one, and a sweep would fold there. Such points are moved onto
/// the corner's inset point, which is where the inset outline's corner is.
pub(super) fn row(rim: &[RimPoint], inset_m: f64, face_inset_m: f64) -> Vec<Point2<f64>> {
    let mut q: Vec<Point2<f64>> = rim
        .iter()
        .map(|p| p.at_inset(inset_m, face_inset_m))
        .collect();
    let n = rim.len();
    for c in (0..n).filter(|&c| rim[c].is_sharp()) {
        let (corner, at) = (q[c], rim[c].outline);
        for forward in [true, false] {
            for step in 1..n {
                let j = if forward {
                    (c + step) % n
                } else {
                    (c + n - step) % n
                };
                // Ahead of the corner on the inset row as the rim point is on the outline.
                let along = rim[j].outline - at;
                if rim[j].is_sharp() || (q[j] - corner).dot(&along) > 0.0 {
                    break;
                }
                q[j] = corner;
            }
        }
    }
    q
}

/// Whether a profile row is a simple curve that runs with the outline: no segment reversed (a
/// rounded corner tighter than the inset) and no crossing (an inset past the opposite side).
/// `Err` says where it fails.
pub(super) fn check_row(rim: &[RimPoint], row: &[Point2<f64>]) -> Result<(), String> {
    let n = rim.len();
    let mut distinct: Vec<Point2<f64>> = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (row[i], row[(i + 1) % n]);
        if a == b {
            continue;
        }
        if (b - a).dot(&(rim[(i + 1) % n].outline - rim[i].outline)) <= 0.0 {
            return Err(format!(
                "would turn inside out near ({:.6}, {:.6}) m",
                rim[i].outline.x, rim[i].outline.y
            ));
        }
        distinct.push(a);
    }
    if let Some((i, _)) = polygon::self_intersection(&distinct) {
        return Err(format!(
            "would cross itself near ({:.6}, {:.6}) m",
            distinct[i].x, distinct[i].y
        ));
    }
    Ok(())
}

/// Sweeps `profile` along the closed `rim`; `closed` joins the profile's last point back to its
/// first (a solid ring), otherwise the result is an open sheet. Each profile point makes one
/// `row` (points at the face inset `face_inset_m` are the rim's exact face points, as the
/// panel's faces and border use).
pub(super) fn sweep(
    rim: &[RimPoint],
    profile: &[[f64; 2]],
    closed: bool,
    face_inset_m: f64,
    curvature: &Curvature,
) -> Mesh {
    let m = profile.len();
    let rows: Vec<Vec<Point2<f64>>> = profile
        .iter()
        .map(|&[inset, _]| row(rim, inset, face_inset_m))
        .collect();
    let mut positions = Vec::with_capacity(rim.len() * m);
    for i in 0..rim.len() {
        for (row, &[_, height]) in rows.iter().zip(profile) {
            let q = row[i];
            positions.push(curvature.bend_point(q.x, q.y, height));
        }
    }
    let n = rim.len();
    let spans = if closed { m } else { m - 1 };
    let mut triangles = Vec::with_capacity(2 * n * spans);
    let id = |i: usize, j: usize| ((i % n) * m + j % m) as u32;
    for i in 0..n {
        for j in 0..spans {
            // As in the edge band: rim i → i + 1 counter-clockwise, the profile in the
            // section's sense, so (a_j, a_j+1, b_j+1) faces away from the glass.
            let (a0, a1, b0, b1) = (id(i, j), id(i, j + 1), id(i + 1, j), id(i + 1, j + 1));
            triangles.push([a0, a1, b1]);
            triangles.push([a0, b1, b0]);
        }
    }
    Mesh::solid(positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::panel::{contour, Outline};

    fn square_rim(side_m: f64) -> Vec<RimPoint> {
        let outline = Outline::Rectangle {
            width_m: side_m,
            height_m: side_m,
            corner_radius_m: 0.0,
        };
        contour::sample(&outline, 0.005, 0.005).unwrap()
    }

    #[test]
    fn deep_rows_close_at_sharp_corners_instead_of_folding() {
        // Samples every 5 mm; a 20 mm inset would put the samples next to each corner behind
        // the corner's mitered point.
        let rim = square_rim(0.1);
        let row = row(&rim, 0.02, 0.0);
        check_row(&rim, &row).unwrap();
        for q in &row {
            // Every point lies on the 60 mm square the inset outline is.
            let (x, y) = (q.x.abs(), q.y.abs());
            assert!(x <= 0.03 + 1e-15 && y <= 0.03 + 1e-15);
            assert!((x - 0.03).abs() < 1e-15 || (y - 0.03).abs() < 1e-15, "{q}");
        }
        // Past the middle the row crosses itself and is refused.
        assert!(check_row(&rim, &super::row(&rim, 0.06, 0.0)).is_err());
    }

    #[test]
    fn refine_splits_long_segments_evenly_and_keeps_the_points() {
        let p = refine(&[[0.0, 0.0], [0.0, 0.01], [0.001, 0.01]], 0.004, false);
        assert_eq!(p.len(), 5);
        assert_eq!(p[0], [0.0, 0.0]);
        assert!((p[1][1] - 0.01 / 3.0).abs() < 1e-18);
        assert_eq!(p[3], [0.0, 0.01]);
        assert_eq!(p[4], [0.001, 0.01]);
        // Closed: the closing segment is split too, and the first point is not repeated.
        let c = refine(&[[0.0, 0.0], [0.01, 0.0]], 0.004, true);
        assert_eq!(c.len(), 6);
    }
}
