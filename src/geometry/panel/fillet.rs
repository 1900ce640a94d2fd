//! Rounding the junctions of an edge section: circular fillets tangent to both neighbouring
//! facets, the way a ground seam wears its corners round.
//!
//! Input: the section's corner points (inset, height) (m) from the one on the top face to the
//! one on the bottom face. The top face arrives at the first corner running outward and the
//! bottom face leaves the last one running inward, so every corner, the face junctions
//! included, is a junction of two straight pieces. A fillet of radius ρ at a junction that
//! turns by θ touches both pieces at ρ·tan(|θ|/2) from the corner; its centre lies inside the
//! glass at a convex junction and outside at a concave one. Arcs are sampled at most 10° and
//! `tessellation_m` per step, with radial normals, like the pencil arc and the outline's
//! rounded corners. The tangent points on the faces are exact, so the section still ends on
//! the face planes (height t and 0 exactly).
//!
//! Work is done in (x, y) = (outward, up) = (−inset, height): the glass lies on the right of
//! the direction of travel, so the outward normal is the direction turned by +90°.

use nalgebra::Vector2;

use super::contour::{segments, MAX_ARC_STEP};
use super::edge::{Facet, SectionPoint};
use crate::geometry::mesh::SurfacePart;

/// Straight pieces shorter than this (m) between two fillets are dropped: the fillets meet.
const MIN_PIECE_M: f64 = 1e-12;

/// Why the fillets do not fit.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct TooLarge {
    /// Index of the straight piece (0 = from corner 0 to corner 1).
    pub(super) piece: usize,
    /// Length the fillets at its two ends take (m).
    pub(super) needed_m: f64,
    /// Its length (m).
    pub(super) length_m: f64,
}

/// The facets of the section through `corners` (at least two) with every junction rounded
/// with radius `radius_m` (≥ 0; 0 keeps the corners sharp).
pub(super) fn round(
    corners: &[[f64; 2]],
    radius_m: f64,
    tessellation_m: f64,
) -> Result<Vec<Facet>, TooLarge> {
    let p: Vec<Vector2<f64>> = corners.iter().map(|c| Vector2::new(-c[0], c[1])).collect();
    let n = p.len();
    debug_assert!(n >= 2, "a section has at least two corners");
    // Directions: into corner 0 along the top face, between corners, out of the last corner
    // along the bottom face.
    let dir = |k: usize| -> Vector2<f64> {
        match k {
            0 => Vector2::new(1.0, 0.0),
            k if k == n => Vector2::new(-1.0, 0.0),
            k => (p[k] - p[k - 1]).normalize(),
        }
    };
    let turn: Vec<f64> = (0..n)
        .map(|k| {
            let (a, b) = (dir(k), dir(k + 1));
            a.perp(&b).atan2(a.dot(&b))
        })
        .collect();
    let leg: Vec<f64> = turn
        .iter()
        .map(|t| radius_m * (0.5 * t.abs()).tan())
        .collect();
    for k in 0..n.saturating_sub(1) {
        let length_m = (p[k + 1] - p[k]).norm();
        let needed_m = leg[k] + leg[k + 1];
        if needed_m > length_m * (1.0 + 1e-9) {
            return Err(TooLarge {
                piece: k,
                needed_m,
                length_m,
            });
        }
    }
    let mut facets = Vec::new();
    let mut last: Option<Vector2<f64>> = None;
    for k in 0..n {
        let (e_in, e_out) = (dir(k), dir(k + 1));
        let (t_in, t_out) = (p[k] - e_in * leg[k], p[k] + e_out * leg[k]);
        if let Some(prev) = last {
            if (t_in - prev).norm() > MIN_PIECE_M {
                facets.push(Facet::flat(to_section(prev), to_section(t_in)));
            }
        }
        if leg[k] > 0.0 {
            facets.push(arc(
                t_in,
                t_out,
                e_in,
                e_out,
                turn[k],
                radius_m,
                tessellation_m,
            ));
            last = Some(t_out);
        } else {
            last = Some(p[k]);
        }
    }
    Ok(facets)
}

/// The fillet from `t_in` to `t_out` turning by `turn` (rad, < 0 convex), radius `r`.
fn arc(
    t_in: Vector2<f64>,
    t_out: Vector2<f64>,
    e_in: Vector2<f64>,
    e_out: Vector2<f64>,
    turn: f64,
    r: f64,
    tessellation_m: f64,
) -> Facet {
    let left = |e: Vector2<f64>| Vector2::new(-e.y, e.x);
    let (n_in, n_out) = (left(e_in), left(e_out));
    // Convex junction (turning right, towards the glass): the centre lies inside, at r from
    // the tangent point against the normal; concave: outside.
    let side = if turn < 0.0 { 1.0 } else { -1.0 };
    let centre = t_in - n_in * (side * r);
    let steps = segments(turn.abs() / MAX_ARC_STEP).max(segments(r * turn.abs() / tessellation_m));
    let points = (0..=steps)
        .map(|k| {
            let phi = turn * k as f64 / steps as f64;
            let (s, c) = phi.sin_cos();
            // The end points are the exact tangent points, with the pieces' normals.
            let (position, normal) = match k {
                0 => (t_in, n_in),
                k if k == steps => (t_out, n_out),
                _ => {
                    let n = Vector2::new(n_in.x * c - n_in.y * s, n_in.x * s + n_in.y * c);
                    (centre + n * (side * r), n)
                }
            };
            let [inset_m, height_m] = to_section(position);
            SectionPoint {
                inset_m,
                height_m,
                normal: [normal.x, normal.y],
            }
        })
        .collect();
    Facet {
        points,
        part: SurfacePart::Edge,
    }
}

fn to_section(p: Vector2<f64>) -> [f64; 2] {
    // −0.0 would compare equal but print oddly; keep insets non-negative zeros.
    [-p.x + 0.0, p.y]
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: f64 = 0.004;

    fn points(f: &[Facet]) -> Vec<SectionPoint> {
        f.iter().flat_map(|f| f.points.clone()).collect()
    }

    #[test]
    fn sharp_corners_stay_sharp_without_a_radius() {
        let f = round(&[[0.0, T], [0.0, 0.0]], 0.0, 0.005).unwrap();
        assert_eq!(f.len(), 1);
        assert_eq!(f[0].points[0].normal, [1.0, 0.0]);
    }

    #[test]
    fn face_wall_fillets_touch_the_faces_at_the_radius() {
        let r = 0.5e-3;
        let f = round(&[[0.0, T], [0.0, 0.0]], r, 0.005).unwrap();
        // Arc, wall, arc.
        assert_eq!(f.len(), 3);
        let pts = points(&f);
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        assert!((first.inset_m - r).abs() < 1e-18 && first.height_m == T);
        assert!((last.inset_m - r).abs() < 1e-18 && last.height_m == 0.0);
        assert_eq!((first.normal, last.normal), ([0.0, 1.0], [0.0, -1.0]));
        // 90° in 10° steps; every arc point at r from the centre (r, T − r), radial normal.
        assert_eq!(f[0].points.len(), 10);
        for p in &f[0].points {
            let (dx, dy) = (-(p.inset_m - r), p.height_m - (T - r));
            assert!((dx.hypot(dy) - r).abs() < 1e-15);
            assert!((p.normal[0] - dx / r).abs() < 1e-12 && (p.normal[1] - dy / r).abs() < 1e-12);
        }
        assert_eq!(f[1].points[0].height_m, T - r);
    }

    #[test]
    fn fillets_meeting_in_the_middle_leave_no_piece() {
        // Two quarter circles of radius t/2: a half round, no wall between them.
        let f = round(&[[0.0, T], [0.0, 0.0]], T / 2.0, 0.005).unwrap();
        assert_eq!(f.len(), 2);
        assert!(round(&[[0.0, T], [0.0, 0.0]], T / 2.0 * 1.001, 0.005).is_err());
    }

    #[test]
    fn too_large_a_fillet_names_the_piece() {
        // A 45° arris 0.8 mm wide is 1.13 mm long; fillets of 5 mm need more at its ends.
        let c = [[0.8e-3, T], [0.0, T - 0.8e-3], [0.0, 0.0]];
        let e = round(&c, 5e-3, 0.005).unwrap_err();
        assert_eq!(e.piece, 0);
        assert!(e.needed_m > e.length_m);
    }

    #[test]
    fn concave_junctions_curve_outwards() {
        // A groove: out at the top, in to 1 mm at mid-height, out again.
        let c = [[0.0, T], [1e-3, T / 2.0], [0.0, 0.0]];
        let f = round(&c, 0.2e-3, 0.005).unwrap();
        let arc = &f[2];
        // The concave arc's centre lies outside the glass: the fillet fills the bottom of the
        // groove, so no point of it lies deeper than the sharp groove did.
        for p in &arc.points {
            assert!(p.inset_m <= 1e-3 + 1e-15);
        }
        for w in points(&f).windows(2) {
            assert!(w[1].height_m <= w[0].height_m);
        }
    }
}
