//! The exact closest point on a closed border polyline, with its interpolated frame.
//!
//! ICP needs the closest point on the *segments*, not the nearest vertex: PITFALLS.md measured
//! that nearest-vertex ICP against a 2 mm-sampled border stalls at 0.47 mm RMS, because below
//! the vertex spacing tangential sliding becomes a fixed point.

use nalgebra::{Point3, Vector3};

use crate::geometry::border::BorderCurve;

/// The point of a border curve closest to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoint {
    /// The closest point on the polyline (in the curve's frame, m).
    pub point: Point3<f64>,
    /// Index of the segment that holds it: from vertex `segment` to vertex `segment + 1`
    /// (wrapping to vertex 0 after the last).
    pub segment: usize,
    /// Position along that segment, in [0, 1].
    pub t: f64,
    /// The ICP normal: normalize(surface_normal + outward), with both vectors interpolated
    /// linearly in `t` between the segment's end vertices. It bisects the top face's normal and
    /// the edge's outward normal, so a BIP off the corner in either face's direction shows up
    /// in the point-to-plane residual.
    pub normal: Vector3<f64>,
    /// Unit direction of the segment (towards increasing vertex index); for a zero-length
    /// segment, the interpolated vertex tangent.
    pub tangent: Vector3<f64>,
    /// Distance from the query point to `point` (m).
    pub distance: f64,
}

/// The exact closest point to `p` on the closed polyline `border` (segments, not vertices).
///
/// Brute force over all segments: one projection and clamp per segment, about 2–3 ns each, so
/// ~1.5 µs for a 500-segment border (a 1 m perimeter sampled every 2 mm). That is fine for
/// a few thousand segments and a few dozen query points per ICP iteration; a grid or BVH over
/// the segments would only pay off for much denser curves or many more points.
///
/// Ties (equidistant segments) go to the lowest segment index. Panics if `border` has no
/// vertex (a precondition; [`super::icp::register`] checks it and returns an error instead).
pub fn closest_on_border(border: &BorderCurve, p: &Point3<f64>) -> ClosestPoint {
    let v = &border.vertices;
    assert!(!v.is_empty(), "closest_on_border needs a non-empty border");
    let n = v.len();
    let mut best = (f64::INFINITY, 0usize, 0.0f64);
    for i in 0..n {
        let a = v[i].position;
        let b = v[(i + 1) % n].position;
        let t = segment_parameter(&a, &b, p);
        let d2 = (a + (b - a) * t - p).norm_squared();
        if d2 < best.0 {
            best = (d2, i, t);
        }
    }
    let (d2, i, t) = best;
    let (a, b) = (&v[i], &v[(i + 1) % n]);
    let surface_normal = a.surface_normal * (1.0 - t) + b.surface_normal * t;
    let outward = a.outward * (1.0 - t) + b.outward * t;
    // The two unit vectors are perpendicular at every vertex, so their sum never vanishes.
    let normal = (surface_normal.normalize() + outward.normalize()).normalize();
    let tangent = (b.position - a.position)
        .try_normalize(1e-15)
        .unwrap_or_else(|| (a.tangent * (1.0 - t) + b.tangent * t).normalize());
    ClosestPoint {
        point: a.position + (b.position - a.position) * t,
        segment: i,
        t,
        normal,
        tangent,
        distance: d2.sqrt(),
    }
}

/// The parameter in [0, 1] of the point of segment ab closest to p (0 for a zero-length one).
fn segment_parameter(a: &Point3<f64>, b: &Point3<f64>, p: &Point3<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::border::BorderVertex;
    use crate::localise::fixtures::flat_pane;

    fn square() -> BorderCurve {
        // A 2 × 2 m square at z = 0, CCW, outward normals by hand.
        let pts = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let vertices = (0..4)
            .map(|i| {
                let (x, y) = pts[i];
                let (xn, yn) = pts[(i + 1) % 4];
                let tangent = Vector3::new(xn - x, yn - y, 0.0).normalize();
                BorderVertex {
                    position: Point3::new(x, y, 0.0),
                    tangent,
                    surface_normal: Vector3::z(),
                    outward: tangent.cross(&Vector3::z()),
                }
            })
            .collect();
        BorderCurve { vertices }
    }

    #[test]
    fn point_above_mid_segment_projects_onto_it() {
        // 0.3 m above and 0.4 m outside the middle of the bottom side: distance 0.5 m exactly,
        // not the 1.1 m+ to the nearest vertex.
        let c = closest_on_border(&square(), &Point3::new(0.0, -1.4, 0.3));
        assert_eq!(c.segment, 0);
        assert!((c.t - 0.5).abs() < 1e-15);
        assert!((c.point - Point3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
        assert!((c.distance - 0.5).abs() < 1e-15);
        // The hand-built square's vertex frames follow each vertex's outgoing side, so at the
        // middle of side 0 the outward normal is the mean of −y (vertex 0) and +x (vertex 1).
        let outward = Vector3::new(1.0, -1.0, 0.0).normalize();
        let expected = (Vector3::z() + outward).normalize();
        assert!((c.normal - expected).norm() < 1e-12);
        assert!((c.tangent - Vector3::x()).norm() < 1e-15);
    }

    #[test]
    fn outside_a_corner_clamps_to_the_vertex() {
        let c = closest_on_border(&square(), &Point3::new(2.0, -2.0, 0.0));
        assert!((c.point - Point3::new(1.0, -1.0, 0.0)).norm() < 1e-15);
        assert!((c.distance - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn points_on_the_border_have_zero_distance_between_vertices() {
        let border = flat_pane();
        let len = border.length();
        for k in 0..37 {
            let s = len * (k as f64 + 0.37) / 37.0;
            let v = border.at_arc_length(s);
            let c = closest_on_border(&border, &v.position);
            assert!(c.distance < 1e-15, "distance {} at s = {s}", c.distance);
            // at_arc_length takes the outward normal from the chord, this module interpolates
            // the vertices' normals: on the 2 mm-sampled 20 mm corners they differ by < 3°.
            let expected = (v.surface_normal + v.outward).normalize();
            assert!((c.normal - expected).norm() < 0.05);
        }
    }
}
