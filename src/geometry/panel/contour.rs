//! The sampled outline: the panel outline as a closed counter-clockwise polyline in the flat
//! x–y plane, rounded corners sampled as arcs and straight edges resampled to the tessellation
//! length, with per-vertex outward normals and the miter vector that insets it.
//!
//! Inset: the outline inset by d (m) is `outline − d·miter`. On arcs and straight edges the
//! miter is the unit outward normal (concentric arcs, parallel lines); at a sharp corner it is
//! (n_in + n_out)/(1 + n_in·n_out), of length 1/cos(half the turning angle), so that the inset
//! stays at distance d from both edges.

use nalgebra::{Point2, Vector2};

use super::polygon;
use super::{invalid, Outline, PanelError};

/// Largest angle (rad) an arc segment of a rounded corner may subtend: 10°.
pub(super) const MAX_ARC_STEP: f64 = std::f64::consts::PI / 18.0;

/// Longest miter accepted at a sharp corner, in units of the inset: the default of SVG's
/// `stroke-miterlimit` (SVG 1.1, §11.4), reached at an interior angle of 29° (or 331°). Beyond
/// it the inset corner reaches far along a thin spike or notch and the edge band degenerates.
pub(super) const MITER_LIMIT: f64 = 4.0;

/// Shortest polygon edge accepted, and shortest rounding arc made (m).
const MIN_EDGE_M: f64 = 1e-9;

/// A vertex of the sampled outline, shared by the faces and the edge band.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct RimPoint {
    /// Point on the face boundary: the outline inset by the edge finish's face inset (m).
    /// Faces and the edge band use this exact value, which keeps the mesh watertight.
    pub(super) face: Point2<f64>,
    /// Point on the outline itself (inset 0) (m).
    pub(super) outline: Point2<f64>,
    /// Inset direction: the outline inset by d is at `outline − d·miter`.
    pub(super) miter: Vector2<f64>,
    /// Unit outward normal of the outline segment that ends here.
    pub(super) normal_in: Vector2<f64>,
    /// Unit outward normal of the outline segment that starts here; differs from `normal_in`
    /// only at a sharp corner.
    pub(super) normal_out: Vector2<f64>,
}

impl RimPoint {
    fn smooth(p: Point2<f64>, normal: Vector2<f64>) -> RimPoint {
        RimPoint {
            face: p,
            outline: p,
            miter: normal,
            normal_in: normal,
            normal_out: normal,
        }
    }

    /// Whether the outline has a corner here (different normals on the two sides).
    pub(super) fn is_sharp(&self) -> bool {
        self.normal_in != self.normal_out
    }

    /// The flat point at `inset_m` from the outline on this rim point's inset line. The face
    /// boundary (`face_inset_m`) uses the exact face point the face tessellation shares, which
    /// keeps the mesh watertight; other insets are computed from the outline.
    pub(super) fn at_inset(&self, inset_m: f64, face_inset_m: f64) -> Point2<f64> {
        if inset_m == face_inset_m {
            self.face
        } else {
            self.outline - self.miter * inset_m
        }
    }

    /// The point at fraction `t` of the segment from `self` to `next`, with the face point
    /// interpolated too (callers that snap it overwrite it).
    pub(super) fn lerp(&self, next: &RimPoint, t: f64) -> RimPoint {
        let normal = self.normal_out.lerp(&next.normal_in, t).normalize();
        RimPoint {
            face: self.face + (next.face - self.face) * t,
            outline: self.outline + (next.outline - self.outline) * t,
            miter: self.miter.lerp(&next.miter, t),
            normal_in: normal,
            normal_out: normal,
        }
    }
}

/// Samples `outline` into a counter-clockwise polyline whose segments are no longer than
/// `tessellation_m` on arcs, where they also subtend at most 10°, and `straight_m` on straight
/// runs. The face points equal the outline points (no inset yet).
pub(super) fn sample(
    outline: &Outline,
    tessellation_m: f64,
    straight_m: f64,
) -> Result<Vec<RimPoint>, PanelError> {
    let (corners, r) = corners(outline)?;
    let n = corners.len();
    let dir = |i: usize| (corners[(i + 1) % n] - corners[i]).normalize();
    let turn: Vec<f64> = (0..n)
        .map(|i| {
            let (e_in, e_out) = (dir((i + n - 1) % n), dir(i));
            e_in.perp(&e_out).atan2(e_in.dot(&e_out))
        })
        .collect();
    // The arc at corner i is tangent to its edges at r·tan(|θ|/2) from the corner.
    let leg = |i: usize| (0.5 * turn[i].abs()).tan();
    let r_max = (0..n)
        .map(|i| (corners[(i + 1) % n] - corners[i]).norm() / (leg(i) + leg((i + 1) % n)))
        .fold(f64::INFINITY, f64::min);
    if r > r_max * (1.0 + 1e-12) {
        return Err(invalid(
            "corner_radius_mm",
            format!("must be ≤ {r_max} m so that each edge holds the arcs at its ends, got {r} m"),
        ));
    }
    let scale = corners.iter().map(|p| p.coords.amax()).fold(0.0, f64::max);
    let arcs: Vec<Vec<RimPoint>> = (0..n)
        .map(|i| {
            corner_arc(
                corners[i],
                dir((i + n - 1) % n),
                dir(i),
                turn[i],
                r,
                tessellation_m,
            )
        })
        .collect();
    let mut out = Vec::new();
    for i in 0..n {
        let (arc, next_arc) = (&arcs[i], &arcs[(i + 1) % n]);
        let (end, start) = (arc[arc.len() - 1], next_arc[0]);
        let length = (start.outline - end.outline).norm();
        // Arcs that use up the whole edge meet: keep one of the two coincident points.
        let merged = length <= 1e-12 * scale;
        out.extend_from_slice(if merged { &arc[..arc.len() - 1] } else { arc });
        if !merged {
            let normal = right(&dir(i));
            let steps = segments(length / straight_m);
            for k in 1..steps {
                let t = k as f64 / steps as f64;
                out.push(RimPoint::smooth(
                    end.outline + (start.outline - end.outline) * t,
                    normal,
                ));
            }
        }
    }
    Ok(out)
}

/// Insets the face points of `contour` by `inset_m`; `Err` says why that inset does not fit.
pub(super) fn inset(contour: &mut [RimPoint], inset_m: f64) -> Result<(), String> {
    for p in contour.iter_mut() {
        p.face = p.outline - p.miter * inset_m;
    }
    if inset_m == 0.0 {
        return Ok(());
    }
    for p in contour.iter().filter(|p| p.is_sharp()) {
        let stretch = p.miter.norm();
        if stretch > MITER_LIMIT {
            let turn = p
                .normal_in
                .perp(&p.normal_out)
                .atan2(p.normal_in.dot(&p.normal_out));
            return Err(format!(
                "the edge finish insets the faces by {inset_m} m; at the sharp corner \
                 ({:.6}, {:.6}) m (interior angle {:.1}°) that takes a miter {stretch:.1} times \
                 as long, more than {MITER_LIMIT}; round the corner (corner_radius_mm)",
                p.outline.x,
                p.outline.y,
                180.0 - turn.to_degrees()
            ));
        }
    }
    let n = contour.len();
    let unfit = |p: &Point2<f64>| {
        format!(
            "the edge finish insets the faces by {inset_m} m, more than the outline allows \
             near ({:.6}, {:.6}) m",
            p.x, p.y
        )
    };
    for i in 0..n {
        let (a, b) = (&contour[i], &contour[(i + 1) % n]);
        if (b.face - a.face).dot(&(b.outline - a.outline)) <= 0.0 {
            return Err(unfit(&a.outline));
        }
    }
    let faces: Vec<Point2<f64>> = contour.iter().map(|p| p.face).collect();
    if let Some((i, _)) = polygon::self_intersection(&faces) {
        return Err(unfit(&contour[i].outline));
    }
    Ok(())
}

/// Splits every face segment of `contour` longer than `max_m` evenly. Insets lengthen
/// segments on concave arcs and next to concave sharp corners; this keeps the face boundary
/// (and so the border curve) within the tessellation length.
pub(super) fn limit_face_segments(contour: &[RimPoint], max_m: f64) -> Vec<RimPoint> {
    let n = contour.len();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (&contour[i], &contour[(i + 1) % n]);
        out.push(*a);
        let steps = segments((b.face - a.face).norm() / max_m);
        out.extend((1..steps).map(|k| a.lerp(b, k as f64 / steps as f64)));
    }
    out
}

/// The outline's corner polygon (counter-clockwise, no collinear vertices) and corner radius.
fn corners(outline: &Outline) -> Result<(Vec<Point2<f64>>, f64), PanelError> {
    match outline {
        Outline::Rectangle {
            width_m: w,
            height_m: h,
            corner_radius_m: r,
        } => {
            let (w, h, r) = (*w, *h, *r);
            super::require_positive("width_mm", w)?;
            super::require_positive("height_mm", h)?;
            let r_max = 0.5 * w.min(h);
            if !(r.is_finite() && (0.0..=r_max).contains(&r)) {
                return Err(invalid(
                    "corner_radius_mm",
                    format!("must be in [0, min(width, height)/2 = {r_max}] m, got {r} m"),
                ));
            }
            let (x, y) = (0.5 * w, 0.5 * h);
            let square = [[-x, -y], [x, -y], [x, y], [-x, y]];
            Ok((square.iter().map(|p| Point2::new(p[0], p[1])).collect(), r))
        }
        Outline::Polygon {
            vertices_m,
            corner_radius_m: r,
        } => {
            if !(r.is_finite() && *r >= 0.0) {
                return Err(invalid(
                    "corner_radius_mm",
                    format!("must be ≥ 0, got {r} m"),
                ));
            }
            let poly = polygon::normalised(vertices_m, MIN_EDGE_M)
                .map_err(|message| invalid("vertices_mm", message))?;
            Ok((poly, *r))
        }
    }
}

/// Samples the rounded corner at `v` between unit edge directions `e_in` and `e_out` (turning
/// angle `turn`, > 0 for a convex corner); with radius 0, the sharp corner itself.
fn corner_arc(
    v: Point2<f64>,
    e_in: Vector2<f64>,
    e_out: Vector2<f64>,
    turn: f64,
    r: f64,
    tessellation_m: f64,
) -> Vec<RimPoint> {
    let (n_in, n_out) = (right(&e_in), right(&e_out));
    // An arc shorter than the shortest edge allowed would only add a needle: keep the corner.
    if r * turn.abs() < MIN_EDGE_M {
        return vec![RimPoint {
            face: v,
            outline: v,
            miter: (n_in + n_out) / (1.0 + n_in.dot(&n_out)),
            normal_in: n_in,
            normal_out: n_out,
        }];
    }
    let leg = r * (0.5 * turn.abs()).tan();
    // The arc centre lies at distance r from both edges, inside a convex corner and outside a
    // concave one; the outward normal rotates from n_in to n_out along the arc.
    let side = turn.signum();
    let centre = v - e_in * leg - n_in * (side * r);
    let steps = segments(turn.abs() / MAX_ARC_STEP).max(segments(r * turn.abs() / tessellation_m));
    (0..=steps)
        .map(|k| {
            let phi = turn * k as f64 / steps as f64;
            let (s, c) = phi.sin_cos();
            // The end normal is n_out exactly, as on the straight edge that follows.
            let normal = match k {
                k if k == steps => n_out,
                _ => Vector2::new(n_in.x * c - n_in.y * s, n_in.x * s + n_in.y * c),
            };
            RimPoint::smooth(centre + normal * (side * r), normal)
        })
        .collect()
}

/// The outward normal of a counter-clockwise outline running along `e`: e turned by −90°.
fn right(e: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(e.y, -e.x)
}

/// Number of equal segments for a span of `ratio` segment lengths (at least one); the margin
/// keeps an exact multiple such as 90°/10° from rounding up to one segment more.
pub(super) fn segments(ratio: f64) -> usize {
    ((ratio - 1e-9).ceil() as usize).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(w: f64, h: f64, r: f64) -> Outline {
        Outline::Rectangle {
            width_m: w,
            height_m: h,
            corner_radius_m: r,
        }
    }

    fn perimeter(c: &[RimPoint]) -> f64 {
        (0..c.len())
            .map(|i| (c[(i + 1) % c.len()].outline - c[i].outline).norm())
            .sum()
    }

    #[test]
    fn rounded_rectangle_is_ccw_fine_and_on_its_arcs() {
        let (w, h, r, s) = (0.55, 0.42, 0.02, 0.005);
        // Straight runs sampled as finely as the arcs, or ten times as coarsely (a flat
        // panel's): the arcs are the same.
        for straight in [s, 10.0 * s] {
            let c = sample(&rect(w, h, r), s, straight).unwrap();
            let pts: Vec<_> = c.iter().map(|p| p.outline).collect();
            assert!(polygon::signed_area(&pts) > 0.0);
            let mut longest: f64 = 0.0;
            for i in 0..c.len() {
                let seg = c[(i + 1) % c.len()].outline - c[i].outline;
                let on_arc = c[i].normal_out != c[(i + 1) % c.len()].normal_in;
                let limit = if on_arc { s } else { straight };
                assert!(seg.norm() <= limit * (1.0 + 1e-12));
                assert!(!on_arc || seg.norm() <= r * MAX_ARC_STEP);
                assert!((c[i].normal_out.norm() - 1.0).abs() < 1e-15 && !c[i].is_sharp());
                // Outward: the normal points away from the segment's left side.
                assert!(seg.perp(&c[i].normal_out) < 0.0);
                longest = longest.max(seg.norm());
            }
            assert!(longest > 0.9 * straight);
            // Chord deficit of 10° arcs: perimeter of the rounded rectangle within 1e-4.
            let exact = 2.0 * (w + h) - (8.0 - 2.0 * std::f64::consts::PI) * r;
            assert!((perimeter(&c) / exact - 1.0).abs() < 1e-4);
        }
    }

    #[test]
    fn sharp_corner_miter_keeps_the_inset_parallel_to_both_edges() {
        let tri = Outline::Polygon {
            vertices_m: vec![[0.0, 0.0], [0.3, 0.0], [0.0, 0.2]],
            corner_radius_m: 0.0,
        };
        let mut c = sample(&tri, 0.05, 0.05).unwrap();
        inset(&mut c, 0.004).unwrap();
        for i in 0..c.len() {
            let (a, b) = (&c[i], &c[(i + 1) % c.len()]);
            let (e, f) = (b.outline - a.outline, b.face - a.face);
            assert!(e.perp(&f).abs() < 1e-15 * e.norm() * f.norm() + 1e-18);
            // Distance between the parallel lines is the inset.
            assert!(((a.face - a.outline).dot(&-right(&e.normalize())) - 0.004).abs() < 1e-12);
        }
    }

    #[test]
    fn oversized_polygon_corner_radius_is_rejected() {
        let tri = Outline::Polygon {
            vertices_m: vec![[0.0, 0.0], [0.1, 0.0], [0.0, 0.1]],
            corner_radius_m: 0.05,
        };
        let err = sample(&tri, 0.01, 0.01).unwrap_err();
        assert!(matches!(
            err,
            PanelError::InvalidParameter {
                field: "corner_radius_mm",
                ..
            }
        ));
    }

    #[test]
    fn sharp_corners_beyond_the_miter_limit_are_rejected() {
        // Interior angles of 33.7° and 18.4°: the limit of 4 lies at 29°.
        let wide = Outline::Polygon {
            vertices_m: vec![[0.0, 0.0], [0.3, 0.0], [0.0, 0.2]],
            corner_radius_m: 0.0,
        };
        assert!(inset(&mut sample(&wide, 0.05, 0.05).unwrap(), 0.001).is_ok());
        let acute = Outline::Polygon {
            vertices_m: vec![[0.0, 0.0], [0.3, 0.0], [0.0, 0.1]],
            corner_radius_m: 0.0,
        };
        let message = inset(&mut sample(&acute, 0.05, 0.05).unwrap(), 0.001).unwrap_err();
        assert!(message.contains("interior angle 18.4°"), "{message}");
        // Without an inset any corner will do.
        assert!(inset(&mut sample(&acute, 0.05, 0.05).unwrap(), 0.0).is_ok());
    }

    #[test]
    fn inset_larger_than_a_narrow_spike_is_rejected() {
        let spike = Outline::Polygon {
            vertices_m: vec![[0.0, 0.0], [0.2, 0.0], [0.2, 0.003], [0.0, 0.003]],
            corner_radius_m: 0.0,
        };
        let mut c = sample(&spike, 0.01, 0.01).unwrap();
        assert!(inset(&mut c, 0.002).is_err());
        assert!(inset(&mut c, 0.001).is_ok());
    }
}
