//! Triangulation of simple polygons for the face tessellation, shaped for bent faces: the
//! worst triangle's largest angle is kept as far from 180° as the polygon allows.

use nalgebra::Point2;

use super::polygon::{orient, segments_meet};

/// Largest polygon triangulated by the optimal (cubic-time) method; bigger ones are ear-clipped.
const OPTIMAL_LIMIT: usize = 48;

/// Triangulates a simple counter-clockwise polygon; returns index triples into `poly`
/// (counter-clockwise), or `None` when it finds no triangulation (the input is not simple to
/// numerical precision).
///
/// The triangulation keeps the largest angle of its worst triangle as far from 180° as it can.
/// That is the shape that matters on a bent panel: the error of a linear interpolant's gradient,
/// here a flat triangle's normal against the cylinder's, grows with 1/sin of the largest angle
/// (the maximum-angle condition, Babuška & Aziz, SIAM J. Numer. Anal. 13(2), 1976), so a
/// nearly flat triangle can face sideways while a needle cannot. Polygons up to 48 vertices
/// (all but whole-outline pieces) get the optimum by dynamic programming over diagonals
/// (Klincsek, Ann. Discrete Math. 9, 1980); larger ones are ear-clipped, best ear first.
pub(super) fn triangulate(poly: &[Point2<f64>]) -> Option<Vec<[usize; 3]>> {
    match poly.len() {
        0..=2 => None,
        n if n <= OPTIMAL_LIMIT => triangulate_optimal(poly),
        _ => triangulate_ears(poly),
    }
}

/// sin of the largest angle of the triangle (a, b, c), 1 for a right angle; ≤ 0 when the
/// triangle is degenerate or clockwise.
fn shape(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> f64 {
    let mut e = [(b - a).norm(), (c - b).norm(), (a - c).norm()];
    e.sort_by(f64::total_cmp);
    // The largest angle lies between the two shorter edges: 2·area = e₀·e₁·sin θ_max.
    let legs = e[0] * e[1];
    if legs > 0.0 {
        orient(a, b, c) / legs
    } else {
        0.0
    }
}

fn triangulate_optimal(poly: &[Point2<f64>]) -> Option<Vec<[usize; 3]>> {
    let n = poly.len();
    let at = |i: usize, j: usize| i * n + j;
    let mut chord = vec![false; n * n];
    for i in 0..n {
        for j in i + 1..n {
            chord[at(i, j)] = j == i + 1 || (i == 0 && j == n - 1) || is_diagonal(poly, i, j);
        }
    }
    // best[i, j]: the worst shape in the best triangulation of the sub-polygon i, i + 1, …, j
    // (closed by chord i–j); split[i, j]: the apex k of its triangle on that chord.
    let mut best = vec![f64::NEG_INFINITY; n * n];
    let mut split = vec![0; n * n];
    for i in 0..n - 1 {
        best[at(i, i + 1)] = f64::INFINITY;
    }
    for len in 2..n {
        for i in 0..n - len {
            let j = i + len;
            if !chord[at(i, j)] {
                continue;
            }
            for k in i + 1..j {
                if !(chord[at(i, k)] && chord[at(k, j)]) {
                    continue;
                }
                let worst = shape(&poly[i], &poly[k], &poly[j])
                    .min(best[at(i, k)])
                    .min(best[at(k, j)]);
                if worst > best[at(i, j)] {
                    best[at(i, j)] = worst;
                    split[at(i, j)] = k;
                }
            }
        }
    }
    if best[at(0, n - 1)] <= 0.0 {
        return None;
    }
    let mut triangles = Vec::with_capacity(n - 2);
    let mut todo = vec![(0, n - 1)];
    while let Some((i, j)) = todo.pop() {
        if j > i + 1 {
            let k = split[at(i, j)];
            triangles.push([i, k, j]);
            todo.extend([(i, k), (k, j)]);
        }
    }
    Some(triangles)
}

/// Whether the segment between vertices i and j (not neighbours) runs inside the polygon
/// without touching its boundary elsewhere (O'Rourke, Computational Geometry in C, §1.6).
fn is_diagonal(poly: &[Point2<f64>], i: usize, j: usize) -> bool {
    let n = poly.len();
    let in_cone = |a: usize, b: usize| {
        let (prev, p, next, q) = (
            &poly[(a + n - 1) % n],
            &poly[a],
            &poly[(a + 1) % n],
            &poly[b],
        );
        if orient(prev, p, next) >= 0.0 {
            orient(p, q, prev) > 0.0 && orient(q, p, next) > 0.0
        } else {
            !(orient(p, q, next) >= 0.0 && orient(q, p, prev) >= 0.0)
        }
    };
    if !(in_cone(i, j) && in_cone(j, i)) {
        return false;
    }
    (0..n).all(|k| {
        let l = (k + 1) % n;
        k == i
            || k == j
            || l == i
            || l == j
            || !segments_meet(&poly[i], &poly[j], &poly[k], &poly[l])
    })
}

/// Ear clipping for large polygons, clipping the best-shaped ear first.
///
/// A vertex on a straight run (collinear with its neighbours) is never an ear tip, and an ear
/// is rejected when any other vertex lies inside it or on its boundary, so no diagonal passes
/// through a vertex: no T-junctions along runs of collinear boundary points.
fn triangulate_ears(poly: &[Point2<f64>]) -> Option<Vec<[usize; 3]>> {
    let n = poly.len();
    let mut ring = Ring {
        prev: (0..n).map(|i| (i + n - 1) % n).collect(),
        next: (0..n).map(|i| (i + 1) % n).collect(),
        alive: vec![true; n],
    };
    let mut quality: Vec<Option<f64>> = (0..n).map(|i| ring.ear_shape(poly, i)).collect();
    let mut triangles = Vec::with_capacity(n - 2);
    for _ in 3..n {
        let mut tip = best_ear(&ring, &quality);
        if tip.is_none() {
            // Clipping a tip can unblock ears that are not its neighbours; look again once.
            quality = (0..n).map(|i| ring.ear_shape(poly, i)).collect();
            tip = best_ear(&ring, &quality);
        }
        let tip = tip?;
        let (p, q) = (ring.prev[tip], ring.next[tip]);
        triangles.push([p, tip, q]);
        ring.alive[tip] = false;
        ring.next[p] = q;
        ring.prev[q] = p;
        quality[p] = ring.ear_shape(poly, p);
        quality[q] = ring.ear_shape(poly, q);
    }
    let a = (0..n).find(|&i| ring.alive[i])?;
    let (b, c) = (ring.next[a], ring.next[ring.next[a]]);
    if orient(&poly[a], &poly[b], &poly[c]) <= 0.0 {
        return None;
    }
    triangles.push([a, b, c]);
    Some(triangles)
}

fn best_ear(ring: &Ring, quality: &[Option<f64>]) -> Option<usize> {
    (0..quality.len())
        .filter(|&i| ring.alive[i])
        .filter_map(|i| quality[i].map(|q| (q, i)))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, i)| i)
}

/// The polygon left to triangulate, as a doubly linked list over the input indices.
struct Ring {
    prev: Vec<usize>,
    next: Vec<usize>,
    alive: Vec<bool>,
}

impl Ring {
    /// The [`shape`] of the ear with tip `i`, or `None` when `i` is not an ear.
    fn ear_shape(&self, poly: &[Point2<f64>], i: usize) -> Option<f64> {
        let (ia, ic) = (self.prev[i], self.next[i]);
        let (a, b, c) = (&poly[ia], &poly[i], &poly[ic]);
        let (ab, bc, ca) = ((b - a).norm(), (c - b).norm(), (a - c).norm());
        // Strictly convex, with a margin so that rounding on straight runs does not count.
        if orient(a, b, c) <= 1e-10 * ab * bc {
            return None;
        }
        let slack = 1e-12 * (ab + bc + ca).powi(2);
        let mut j = self.next[ic];
        while j != ia {
            let p = &poly[j];
            let inside =
                orient(a, b, p) >= -slack && orient(b, c, p) >= -slack && orient(c, a, p) >= -slack;
            if inside {
                return None;
            }
            j = self.next[j];
        }
        Some(shape(a, b, c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::panel::polygon::signed_area;

    fn pts(v: &[[f64; 2]]) -> Vec<Point2<f64>> {
        v.iter().map(|p| Point2::new(p[0], p[1])).collect()
    }

    fn triangulated_area(poly: &[Point2<f64>], tris: &[[usize; 3]]) -> f64 {
        tris.iter()
            .map(|t| 0.5 * orient(&poly[t[0]], &poly[t[1]], &poly[t[2]]))
            .sum()
    }

    #[test]
    fn both_methods_tile_a_concave_polygon_with_collinear_runs() {
        // An L-shape with extra points on its straight edges.
        let l_shape = pts(&[
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.5, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
            [0.0, 1.0],
        ]);
        for tris in [
            triangulate_optimal(&l_shape).unwrap(),
            triangulate_ears(&l_shape).unwrap(),
        ] {
            check_cover(&l_shape, &tris, 3.0);
        }
    }

    #[test]
    fn optimal_triangulation_avoids_flat_triangles_along_a_kinked_run() {
        // A nearly straight chain (a 0.06° kink) closed by two corners: fanning from the corners
        // is the only way to avoid a triangle with an angle near 180°.
        let piece = pts(&[
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 0.5],
            [0.5, 0.7499],
            [0.49998, 0.75],
            [0.0, 1.0],
        ]);
        let tris = triangulate(&piece).unwrap();
        check_cover(&piece, &tris, signed_area(&piece));
        for t in &tris {
            assert!(
                shape(&piece[t[0]], &piece[t[1]], &piece[t[2]]) > 0.01,
                "{t:?}"
            );
        }
    }

    /// The triangles tile the polygon: right count and area, counter-clockwise, and every
    /// boundary edge used by exactly one triangle (no diagonal skips a collinear vertex).
    fn check_cover(poly: &[Point2<f64>], tris: &[[usize; 3]], area: f64) {
        assert_eq!(tris.len(), poly.len() - 2);
        assert!((triangulated_area(poly, tris) - area).abs() < 1e-12);
        for t in tris {
            assert!(orient(&poly[t[0]], &poly[t[1]], &poly[t[2]]) > 0.0);
        }
        let n = poly.len();
        for i in 0..n {
            let (a, b) = (i, (i + 1) % n);
            let uses = tris
                .iter()
                .filter(|t| (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b))
                .count();
            assert_eq!(uses, 1, "boundary edge {a}→{b}");
        }
    }
}
