//! The exact closest point on a closed border polyline, with its interpolated frame.
//!
//! ICP needs the closest point on the *segments*, not the nearest vertex: measured before this
//! crate was written, nearest-vertex ICP of 12 points against a 2 mm-sampled border stalled at
//! 0.47 mm RMS from all 20 random starts, in every implementation tried (Open3D, small_gicp,
//! numpy, Rust), because below the vertex spacing tangential sliding becomes a fixed point.

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
    let mut best = (f64::INFINITY, 0usize, 0.0f64);
    for i in 0..v.len() {
        consider(border, i, p, &mut best);
    }
    closest_point(border, best)
}

/// Offers segment `i` to the running best (squared distance, segment, parameter): strictly
/// nearer wins; at an equal distance the lower index does, so any visiting order gives the
/// brute-force answer bit for bit.
fn consider(border: &BorderCurve, i: usize, p: &Point3<f64>, best: &mut (f64, usize, f64)) {
    let v = &border.vertices;
    let a = v[i].position;
    let b = v[(i + 1) % v.len()].position;
    let t = segment_parameter(&a, &b, p);
    let d2 = (a + (b - a) * t - p).norm_squared();
    if d2 < best.0 || (d2 == best.0 && i < best.1) {
        *best = (d2, i, t);
    }
}

/// The closest point with its frame, from the winning (squared distance, segment, parameter).
fn closest_point(border: &BorderCurve, (d2, i, t): (f64, usize, f64)) -> ClosestPoint {
    let v = &border.vertices;
    let n = v.len();
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

/// A uniform grid over the border's segments in the x-y plane of the curve's frame, for ICP's
/// many closest-point queries (12 BIPs × ~10 iterations against ~500 segments): each segment
/// is listed in every cell its bounding box overlaps; a query visits rings of cells around its
/// own until the best distance found is below the ring's reach, so it returns exactly what
/// [`closest_on_border`] does (same arithmetic per segment, same tie rule).
#[derive(Clone, Debug)]
pub struct SegmentGrid {
    origin: [f64; 2],
    cell: f64,
    dims: [usize; 2],
    /// Segment indices per cell, row-major, flattened; `starts[c]..starts[c + 1]`.
    starts: Vec<u32>,
    segments: Vec<u32>,
}

impl SegmentGrid {
    /// The grid of `border`'s segments, about two segments per cell along the curve.
    ///
    /// # Panics
    /// If `border` has no vertex.
    pub fn new(border: &BorderCurve) -> Self {
        let v = &border.vertices;
        assert!(!v.is_empty(), "SegmentGrid needs a non-empty border");
        let n = v.len();
        // Segment i runs from vertex i to vertex i + 1, the last one closing the curve (indexed
        // without `% n`: an integer division costs more than the rest of a segment's work here).
        let ends = |i: usize| {
            (
                &v[i].position,
                &v[if i + 1 < n { i + 1 } else { 0 }].position,
            )
        };
        // One pass for the bounds and the perimeter.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut perimeter = 0.0;
        for i in 0..n {
            let (a, b) = ends(i);
            for k in 0..2 {
                lo[k] = lo[k].min(a[k]);
                hi[k] = hi[k].max(a[k]);
            }
            perimeter += (b - a).norm();
        }
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        // Cells of about two segments' length, at most 64 per side (four segments and 32 per
        // side measured 10 % slower queries and no faster build).
        let cell = (2.0 * perimeter / n as f64).max(extent / 64.0).max(1e-9);
        let dims = [0, 1].map(|k| (((hi[k] - lo[k]) / cell).floor() as usize + 1).min(65));
        // Each vertex's cell (x − lo ≥ 0 exactly, lo being the minimum of the same numbers, so
        // truncation is floor); a segment's cell box is its two end vertices' cells' box, as
        // the cell of a coordinate does not decrease with it.
        let (last_x, last_y) = (dims[0] as u32 - 1, dims[1] as u32 - 1);
        let cells: Vec<(u32, u32)> = v
            .iter()
            .map(|x| {
                let p = x.position;
                (
                    (((p.x - lo[0]) / cell) as u32).min(last_x),
                    (((p.y - lo[1]) / cell) as u32).min(last_y),
                )
            })
            .collect();
        let width = dims[0];
        // Calls `f` with every cell of segment i's box.
        let for_cells_of = |i: usize, f: &mut dyn FnMut(usize)| {
            let ((ax, ay), (bx, by)) = (cells[i], cells[if i + 1 < n { i + 1 } else { 0 }]);
            let (x0, x1) = (ax.min(bx) as usize, ax.max(bx) as usize);
            for cy in ay.min(by) as usize..=ay.max(by) as usize {
                for c in cy * width + x0..=cy * width + x1 {
                    f(c);
                }
            }
        };
        // A counting sort into one flat list: two passes over the segments and no per-cell
        // allocation (a list per cell made the build cost more than the whole registration's
        // searches). starts[c] first counts the entries of cells 0..=c (a running sum kept in
        // a register: a sum through the array waits on each store) …
        let cell_count = dims[0] * dims[1];
        let mut starts = vec![0u32; cell_count + 1];
        for i in 0..n {
            for_cells_of(i, &mut |c| starts[c] += 1);
        }
        let mut total = 0;
        for s in &mut starts[..cell_count] {
            total += *s;
            *s = total;
        }
        starts[cell_count] = total;
        // … and each entry placed by counting down from its cell's end leaves starts[c] at the
        // cell's first entry. Placing the segments in reverse keeps each cell's list ascending.
        let mut segments = vec![0u32; total as usize];
        for i in (0..n).rev() {
            for_cells_of(i, &mut |c| {
                starts[c] -= 1;
                segments[starts[c] as usize] = i as u32;
            });
        }
        SegmentGrid {
            origin: lo,
            cell,
            dims,
            starts,
            segments,
        }
    }

    /// The exact closest point to `p` on `border`, which must be the curve the grid was built
    /// on: bit for bit what [`closest_on_border`] returns.
    pub fn closest(&self, border: &BorderCurve, p: &Point3<f64>) -> ClosestPoint {
        let [w, h] = self.dims;
        let rel = [0, 1].map(|k| (p[k] - self.origin[k]) / self.cell);
        // Beyond the grid or not finite: rings would only grow towards it; visit everything.
        let inside = |r: f64, n: usize| r.is_finite() && r > -2.0 && r < n as f64 + 2.0;
        if !(inside(rel[0], w) && inside(rel[1], h)) {
            return closest_on_border(border, p);
        }
        // floor, without the libm call for the usual non-negative case.
        let home = rel.map(|r| if r >= 0.0 { r as i64 } else { r.floor() as i64 });
        let mut best = (f64::INFINITY, 0usize, 0.0f64);
        for ring in 0i64.. {
            // Every cell at Chebyshev distance `ring` from home that lies in the grid.
            let (x0, x1, y0, y1) = (
                home[0] - ring,
                home[0] + ring,
                home[1] - ring,
                home[1] + ring,
            );
            for cy in y0.max(0)..=y1.min(h as i64 - 1) {
                let on_edge_row = cy == y0 || cy == y1;
                let mut cx = x0.max(0);
                while cx <= x1.min(w as i64 - 1) {
                    let c = cy as usize * w + cx as usize;
                    for &s in &self.segments[self.starts[c] as usize..self.starts[c + 1] as usize] {
                        consider(border, s as usize, p, &mut best);
                    }
                    // Inside the ring's rows only its two end columns are new.
                    cx = if on_edge_row || cx == x1 { cx + 1 } else { x1 };
                }
            }
            // A segment in no cell visited so far lies at least `ring` cells beyond p's own
            // cell in x or y, so at least ring·cell away: stop once the best is nearer (strictly,
            // so that an equally near segment further out cannot be missed).
            let covers_grid = x0 <= 0 && y0 <= 0 && x1 >= w as i64 - 1 && y1 >= h as i64 - 1;
            let reach = ring as f64 * self.cell;
            if covers_grid || (best.0.is_finite() && best.0.sqrt() < reach) {
                break;
            }
        }
        closest_point(border, best)
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
    fn the_segment_grid_returns_exactly_the_brute_force_answer() {
        // Points near and far, on and off the pane's plane, inside and outside its outline,
        // exactly on vertices (ties between two segments): identical results, bit for bit.
        for border in [flat_pane(), square()] {
            let grid = SegmentGrid::new(&border);
            for i in 0..3000u64 {
                let f = |k: u64| ((i * 7919 + k * 104_729) as f64 * 0.618_033_988_749_895).fract();
                let scale = [0.01, 0.3, 3.0, 1e4][(i % 4) as usize];
                let p = Point3::new(
                    scale * (2.0 * f(1) - 1.0),
                    scale * (2.0 * f(2) - 1.0),
                    0.01 * (2.0 * f(3) - 1.0),
                );
                assert_eq!(
                    grid.closest(&border, &p),
                    closest_on_border(&border, &p),
                    "{p}"
                );
            }
            for v in &border.vertices {
                let p = v.position;
                assert_eq!(grid.closest(&border, &p), closest_on_border(&border, &p));
            }
            let far = Point3::new(1e300, -1e300, 0.0);
            assert_eq!(
                grid.closest(&border, &far),
                closest_on_border(&border, &far)
            );
        }
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
