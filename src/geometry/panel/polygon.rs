//! Planar polygon predicates for the panel builder: orientation, signed area, a simplicity
//! test, and the check and normalisation of a user's outline polygon. Points are in the flat x–y plane (m); polygons are
//! closed implicitly (the last vertex connects back to the first).

use nalgebra::Point2;

/// Twice the signed area of the triangle (a, b, c): positive when counter-clockwise.
pub(super) fn orient(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> f64 {
    (b - a).perp(&(c - a))
}

/// Signed area (m²) by the shoelace formula: positive for a counter-clockwise polygon.
pub(super) fn signed_area(poly: &[Point2<f64>]) -> f64 {
    let n = poly.len();
    let twice: f64 = (0..n)
        .map(|i| {
            let (a, b) = (&poly[i], &poly[(i + 1) % n]);
            a.x * b.y - a.y * b.x
        })
        .sum();
    0.5 * twice
}

/// The first pair of edges (i, j), edge i running from vertex i to vertex i + 1, that meet
/// anywhere other than at the vertex two neighbouring edges share; `None` for a simple polygon.
///
/// Candidate pairs come from a sweep over the edges sorted by their smallest x, so an outline
/// of n edges costs about n·log n plus the pairs whose x-ranges overlap.
pub(super) fn self_intersection(poly: &[Point2<f64>]) -> Option<(usize, usize)> {
    let n = poly.len();
    let seg = |i: usize| (poly[i], poly[(i + 1) % n]);
    // Neighbouring edges meet only at their shared vertex unless the outline folds back on itself.
    for i in 0..n {
        let (a, b) = seg(i);
        let c = poly[(i + 2) % n];
        if orient(&a, &b, &c) == 0.0 && (b - a).dot(&(c - b)) < 0.0 {
            return Some((i, (i + 1) % n));
        }
    }
    let min_x = |i: usize| poly[i].x.min(poly[(i + 1) % n].x);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| min_x(a).total_cmp(&min_x(b)));
    for (k, &i) in order.iter().enumerate() {
        let (a, b) = seg(i);
        let max_x = a.x.max(b.x);
        for &j in &order[k + 1..] {
            if min_x(j) > max_x {
                break;
            }
            let neighbours = (i + 1) % n == j || (j + 1) % n == i;
            let (c, d) = seg(j);
            if !neighbours && segments_meet(&a, &b, &c, &d) {
                return Some((i.min(j), i.max(j)));
            }
        }
    }
    None
}

/// Whether the closed segments ab and cd share a point (crossing or touching).
pub(super) fn segments_meet(
    a: &Point2<f64>,
    b: &Point2<f64>,
    c: &Point2<f64>,
    d: &Point2<f64>,
) -> bool {
    let (d1, d2) = (orient(c, d, a), orient(c, d, b));
    let (d3, d4) = (orient(a, b, c), orient(a, b, d));
    let opposite = |u: f64, v: f64| (u > 0.0 && v < 0.0) || (u < 0.0 && v > 0.0);
    if opposite(d1, d2) && opposite(d3, d4) {
        return true;
    }
    let within = |p: &Point2<f64>, q: &Point2<f64>, r: &Point2<f64>| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    (d1 == 0.0 && within(c, d, a))
        || (d2 == 0.0 && within(c, d, b))
        || (d3 == 0.0 && within(a, b, c))
        || (d4 == 0.0 && within(a, b, d))
}

/// Checks a user polygon (at least three finite vertices, edges of at least `min_edge_m`,
/// non-zero area, simple) and returns it counter-clockwise without straight-through vertices;
/// `Err` says what is wrong.
pub(super) fn normalised(
    vertices: &[[f64; 2]],
    min_edge_m: f64,
) -> Result<Vec<Point2<f64>>, String> {
    let n = vertices.len();
    if n < 3 {
        return Err(format!("must hold at least 3 vertices, got {n}"));
    }
    if let Some(k) = vertices
        .iter()
        .position(|v| !(v[0].is_finite() && v[1].is_finite()))
    {
        return Err(format!(
            "must be finite, got vertex {k} = {:?} m",
            vertices[k]
        ));
    }
    let mut poly: Vec<Point2<f64>> = vertices.iter().map(|v| Point2::new(v[0], v[1])).collect();
    for i in 0..n {
        let length = (poly[(i + 1) % n] - poly[i]).norm();
        if length < min_edge_m {
            let j = (i + 1) % n;
            return Err(format!(
                "must be ≥ {min_edge_m} m apart, got vertices {i} and {j} {length} m apart"
            ));
        }
    }
    let area = signed_area(&poly);
    let (lo, hi) = poly
        .iter()
        .fold((poly[0], poly[0]), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    if area.abs() <= 1e-12 * (hi - lo).norm_squared() {
        return Err(format!("must enclose a non-zero area, got {area} m²"));
    }
    if let Some((i, j)) = self_intersection(&poly) {
        return Err(format!(
            "must form a simple polygon, got edges {i} and {j} intersecting"
        ));
    }
    if area < 0.0 {
        poly.reverse();
    }
    // A straight-through vertex is no corner: drop it so that every corner turns.
    loop {
        let m = poly.len();
        let straight = (0..m).find(|&i| {
            let (a, b, c) = (&poly[(i + m - 1) % m], &poly[i], &poly[(i + 1) % m]);
            let (e_in, e_out) = ((b - a).normalize(), (c - b).normalize());
            e_in.perp(&e_out).abs() <= 1e-12 && e_in.dot(&e_out) > 0.0
        });
        match straight {
            Some(i) if m > 3 => {
                poly.remove(i);
            }
            _ => return Ok(poly),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[[f64; 2]]) -> Vec<Point2<f64>> {
        v.iter().map(|p| Point2::new(p[0], p[1])).collect()
    }

    #[test]
    fn shoelace_area_of_unit_square_is_one_and_signed() {
        let sq = pts(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert_eq!(signed_area(&sq), 1.0);
        let rev: Vec<_> = sq.iter().rev().copied().collect();
        assert_eq!(signed_area(&rev), -1.0);
    }

    #[test]
    fn bow_tie_and_fold_back_are_not_simple() {
        let bow = pts(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]);
        assert!(self_intersection(&bow).is_some());
        let fold = pts(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
        assert!(self_intersection(&fold).is_some());
        let touch = pts(&[[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, 0.0], [0.0, 2.0]]);
        assert!(self_intersection(&touch).is_some());
        let l_shape = pts(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ]);
        assert_eq!(self_intersection(&l_shape), None);
    }

    #[test]
    fn clockwise_polygon_is_reversed_and_straight_vertices_dropped() {
        let cw = vec![[0.0, 0.0], [0.0, 0.1], [0.1, 0.1], [0.1, 0.05], [0.1, 0.0]];
        let p = normalised(&cw, 1e-9).unwrap();
        assert_eq!(p.len(), 4);
        assert!(signed_area(&p) > 0.0);
        assert!(orient(&p[0], &p[1], &p[2]) > 0.0);
    }
}
