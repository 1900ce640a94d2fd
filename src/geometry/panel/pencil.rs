//! The pencil edge's section (automotive edge #2; CGC: "slightly curved to form an arc of a
//! circle of selected radius"): one circular arc of radius r ≥ t/2 from the top face to the
//! bottom face, its centre at inset r and mid-height, so the arc's outermost point is the
//! outline. At r = t/2 it is the half-round C edge, meeting both faces tangentially; a larger r
//! gives a flatter arc that meets the faces at a corner, at inset r − √(r² − (t/2)²).
//!
//! A point at angle ψ above the horizontal through the centre is at inset r·(1 − cos ψ) and
//! height t/2 + r·sin ψ, with the radial normal (cos ψ, sin ψ); ψ runs from asin(t/(2r)) down
//! to −asin(t/(2r)), sampled at most 10° and `tessellation_m` per step, in an even number of
//! steps so that a vertex lies on the outline.

use super::contour::{segments, MAX_ARC_STEP};
use super::edge::{Facet, SectionPoint};
use super::{invalid, PanelError};
use crate::geometry::mesh::SurfacePart;

/// The facet of the pencil arc of `radius_m` (`None`: t/2) on glass `t` thick (m), and the
/// scene-file field that sets its face inset.
pub(super) fn section(
    radius_m: Option<f64>,
    t: f64,
    tessellation_m: f64,
) -> Result<(Vec<Facet>, &'static str), PanelError> {
    let half = 0.5 * t;
    let (r, field) = match radius_m {
        None => (half, "thickness_mm"),
        Some(r) => (r, "pencil.radius_mm"),
    };
    if !(r.is_finite() && r >= half) {
        return Err(invalid(
            "pencil.radius_mm",
            format!("must be ≥ thickness/2 = {half} m, got {r} m"),
        ));
    }
    // At r = t/2 the arc is a half circle whose ends touch the faces.
    let half_round = r == half;
    let psi_max = if half_round {
        std::f64::consts::FRAC_PI_2
    } else {
        (half / r).asin()
    };
    let face_inset = if half_round {
        r
    } else {
        // r − √(r² − (t/2)²), written without cancellation for r ≫ t/2.
        half * half / (r + (r * r - half * half).sqrt())
    };
    let span = 2.0 * psi_max;
    // An even number of steps puts a vertex at mid-height, on the outline: the arc's chords
    // then reach the panel's outer extent.
    let steps = segments(span / MAX_ARC_STEP).max(segments(r * span / tessellation_m));
    let steps = steps + steps % 2;
    let points = (0..=steps)
        .map(|k| {
            let psi = psi_max - span * k as f64 / steps as f64;
            let (s, c) = psi.sin_cos();
            // Exact end points: they must lie on the face planes.
            let (inset_m, height_m) = match k {
                0 => (face_inset, t),
                k if k == steps => (face_inset, 0.0),
                k if 2 * k == steps => (0.0, half),
                _ => (r * (1.0 - c), half + r * s),
            };
            let normal = match (k, half_round) {
                (0, true) => [0.0, 1.0],
                (k, true) if k == steps => [0.0, -1.0],
                (k, _) if 2 * k == steps => [1.0, 0.0],
                _ => [c, s],
            };
            SectionPoint {
                inset_m,
                height_m,
                normal,
            }
        })
        .collect();
    Ok((
        vec![Facet {
            points,
            part: SurfacePart::Edge,
        }],
        field,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: f64 = 0.004;

    #[test]
    fn half_round_meets_the_faces_tangentially() {
        let (f, field) = section(None, T, 0.005).unwrap();
        assert_eq!(field, "thickness_mm");
        let p = &f[0].points;
        assert_eq!(p.len(), 19);
        assert_eq!(
            (p[0].inset_m, p[0].height_m, p[0].normal),
            (0.002, T, [0.0, 1.0])
        );
        assert_eq!(p[9].inset_m, 0.0);
        for q in p {
            let (dx, dy) = (0.002 - q.inset_m, q.height_m - 0.002);
            assert!((dx.hypot(dy) - 0.002).abs() < 1e-15);
        }
    }

    #[test]
    fn flatter_arc_meets_the_faces_at_its_corner_inset() {
        let r = 0.003;
        let (f, field) = section(Some(r), T, 0.005).unwrap();
        assert_eq!(field, "pencil.radius_mm");
        let p = &f[0].points;
        let d = r - (r * r - 0.002f64.powi(2)).sqrt();
        assert!((p[0].inset_m - d).abs() < 1e-15 && p[0].height_m == T);
        assert!((p[p.len() - 1].inset_m - d).abs() < 1e-15);
        // Not tangent: the normal at the face makes asin(t/2r) with the horizontal.
        assert!((p[0].normal[1] - 2.0 / 3.0).abs() < 1e-12);
        // Centre at (inset r, height t/2); the middle point is the outline.
        for q in p {
            let (dx, dy) = (r - q.inset_m, q.height_m - 0.002);
            assert!((dx.hypot(dy) - r).abs() < 1e-15);
        }
        assert!(p.iter().any(|q| q.inset_m == 0.0));
        // Steps of at most 10°, an even number: the arc spans 2·asin(2/3) = 83.6°.
        assert_eq!(p.len(), 11);
    }

    #[test]
    fn radius_below_half_the_thickness_is_refused() {
        for r in [0.0019, -1.0, f64::NAN] {
            let e = section(Some(r), T, 0.005).unwrap_err();
            assert!(matches!(
                e,
                PanelError::InvalidParameter {
                    field: "pencil.radius_mm",
                    ..
                }
            ));
        }
        // Exactly t/2 is the half round.
        let (f, _) = section(Some(0.002), T, 0.005).unwrap();
        assert_eq!(f[0].points.len(), 19);
    }
}
