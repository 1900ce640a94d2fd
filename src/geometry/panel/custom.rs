//! A user-drawn edge section: a polyline of (inset, height) points (m), each segment a flat
//! facet, for finishes the named kinds do not cover (an asymmetric seam, a measured profile).
//!
//! Rules, each refused with the index of the offending point:
//! - at least two points, all finite; insets ≥ 0, heights in [0, t];
//! - the first point is the top face boundary (height t), the last the bottom face boundary
//!   (height 0);
//! - heights never increase (the finish runs down from the top face to the bottom face; an
//!   overhang that turns back up is not a finish the builder can sweep);
//! - consecutive points are distinct (at least 1 nm apart);
//! - a horizontal run at height t goes outward and one at height 0 inward (otherwise the
//!   facet would face into the glass), and two horizontal runs in a row do not reverse;
//! - the smallest inset is 0: the outline is the panel's outer extent;
//! - no two segments meet except consecutive ones at their shared point. With heights that
//!   never increase and no reversals this follows from the rules above; it is checked anyway
//!   so that the rule list is not the only guard.

use nalgebra::Point2;

use super::edge::Facet;
use super::polygon::segments_meet;
use super::PanelError;

/// The scene-file field of the points.
const FIELD: &str = "section.points_mm";
/// Shortest segment accepted (m).
const MIN_SEGMENT_M: f64 = 1e-9;

/// The facets of the section through `points` on glass `t` thick (m).
pub(super) fn section(points: &[[f64; 2]], t: f64) -> Result<Vec<Facet>, PanelError> {
    let n = points.len();
    if n < 2 {
        return Err(PanelError::InvalidParameter {
            field: FIELD,
            message: format!("must have at least 2 points, got {n}"),
        });
    }
    for (k, &[d, h]) in points.iter().enumerate() {
        if !(d.is_finite() && d >= 0.0) {
            return Err(bad(k, format!("inset must be ≥ 0, got {d} m")));
        }
        if !(h.is_finite() && (0.0..=t).contains(&h)) {
            return Err(bad(
                k,
                format!("height must be in [0, thickness = {t}] m, got {h} m"),
            ));
        }
    }
    if points[0][1] != t {
        return Err(bad(
            0,
            format!(
                "must be the top face boundary, at height thickness = {t} m, got {} m",
                points[0][1]
            ),
        ));
    }
    if points[n - 1][1] != 0.0 {
        return Err(bad(
            n - 1,
            format!(
                "must be the bottom face boundary, at height 0, got {} m",
                points[n - 1][1]
            ),
        ));
    }
    for k in 1..n {
        let ([d0, h0], [d1, h1]) = (points[k - 1], points[k]);
        if h1 > h0 {
            return Err(bad(
                k,
                format!("heights must not increase along the section, got {h1} m after {h0} m"),
            ));
        }
        if (d1 - d0).hypot(h1 - h0) < MIN_SEGMENT_M {
            return Err(bad(k, "must differ from the point before it".into()));
        }
        if h1 == h0 {
            if h0 == t && d1 > d0 {
                return Err(bad(
                    k,
                    "a horizontal run on the top face must go outward (smaller inset)".into(),
                ));
            }
            if h0 == 0.0 && d1 < d0 {
                return Err(bad(
                    k,
                    "a horizontal run on the bottom face must go inward (larger inset)".into(),
                ));
            }
            if k >= 2 && points[k - 2][1] == h0 && (d1 - d0) * (d0 - points[k - 2][0]) < 0.0 {
                return Err(bad(k, "the section turns back on itself".into()));
            }
        }
    }
    let min_inset = points.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
    if min_inset != 0.0 {
        return Err(PanelError::InvalidParameter {
            field: FIELD,
            message: format!(
                "must reach the outline: the smallest inset must be 0 (the outline is the \
                 panel's outer extent), got {min_inset} m"
            ),
        });
    }
    let p: Vec<Point2<f64>> = points.iter().map(|&[d, h]| Point2::new(d, h)).collect();
    for i in 0..n - 1 {
        for j in i + 2..n - 1 {
            if segments_meet(&p[i], &p[i + 1], &p[j], &p[j + 1]) {
                return Err(bad(j, format!("the segment from here meets segment {i}")));
            }
        }
    }
    Ok(points.windows(2).map(|w| Facet::flat(w[0], w[1])).collect())
}

fn bad(index: usize, message: String) -> PanelError {
    PanelError::InvalidPoint {
        field: FIELD,
        index,
        message,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: f64 = 4.0 * 1e-3;

    fn mm(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
        points.iter().map(|p| [p[0] * 1e-3, p[1] * 1e-3]).collect()
    }

    fn refused_at(points: &[[f64; 2]]) -> Option<usize> {
        match section(&mm(points), T) {
            Err(PanelError::InvalidPoint { index, .. }) => Some(index),
            Err(PanelError::InvalidParameter { .. }) => Some(usize::MAX),
            Ok(_) => None,
        }
    }

    #[test]
    fn a_chamfered_section_makes_one_facet_per_segment() {
        let f = section(&mm(&[[0.6, 4.0], [0.0, 3.4], [0.0, 0.6], [0.6, 0.0]]), T).unwrap();
        assert_eq!(f.len(), 3);
        assert_eq!(f[1].points[0].normal, [1.0, 0.0]);
        // A step: a ledge facing down at mid-height is fine.
        assert_eq!(
            refused_at(&[[0.5, 4.0], [0.0, 2.0], [1.0, 2.0], [1.0, 0.0]]),
            None
        );
        // Different insets top and bottom are fine too.
        assert_eq!(refused_at(&[[0.0, 4.0], [0.0, 1.0], [1.0, 0.0]]), None);
    }

    #[test]
    fn bad_sections_name_the_point() {
        assert_eq!(refused_at(&[[0.0, 4.0]]), Some(usize::MAX));
        assert_eq!(refused_at(&[[-0.1, 4.0], [0.0, 0.0]]), Some(0));
        assert_eq!(refused_at(&[[0.0, 4.0], [0.0, 4.5], [0.0, 0.0]]), Some(1));
        assert_eq!(refused_at(&[[0.0, 3.9], [0.0, 0.0]]), Some(0));
        assert_eq!(refused_at(&[[0.0, 4.0], [0.0, 0.1]]), Some(1));
        assert_eq!(
            refused_at(&[[0.0, 4.0], [0.0, 2.0], [0.0, 3.0], [0.0, 0.0]]),
            Some(2)
        );
        assert_eq!(
            refused_at(&[[0.0, 4.0], [0.0, 2.0], [0.0, 2.0], [0.0, 0.0]]),
            Some(2)
        );
        // Horizontal runs: inward on the top face, outward on the bottom, or doubling back.
        assert_eq!(refused_at(&[[0.0, 4.0], [0.5, 4.0], [0.0, 0.0]]), Some(1));
        assert_eq!(refused_at(&[[0.0, 4.0], [0.5, 0.0], [0.2, 0.0]]), Some(2));
        assert_eq!(
            refused_at(&[[0.0, 4.0], [0.0, 2.0], [1.0, 2.0], [0.5, 2.0], [0.5, 0.0]]),
            Some(3)
        );
        // Not reaching the outline.
        assert_eq!(
            refused_at(&[[0.2, 4.0], [0.1, 2.0], [0.2, 0.0]]),
            Some(usize::MAX)
        );
    }

    #[test]
    fn messages_say_what_is_expected() {
        let e = section(&mm(&[[0.0, 4.0], [0.0, 4.5], [0.0, 0.0]]), T).unwrap_err();
        let m = e.to_string();
        assert!(
            m.starts_with(
                "section.points_mm[1] height must be in [0, thickness = 0.004] m, got 0.0045"
            ),
            "{m}"
        );
    }
}
