//! The seamed edge's section (automotive edge #3): a flat-ground vertical wall at the outline
//! whose two corners are ground off by arrisses, each junction optionally rounded by a fillet.
//! Sources and defaults: `profile` (IGMA/PPG: 0.8 mm seams at about 45°; Beranek: seaming the
//! sharp corners of a flat #4 edge at 45°; CGC: widths measured on the face).
//!
//! Corners of the section, (inset, height) in metres, top to bottom: the top arris runs from
//! (w_top, t) on the top face to (0, t − w_top·tan a_top) on the wall; the wall runs down to
//! (0, w_bottom·tan a_bottom); the bottom arris to (w_bottom, 0). An arris of width 0 leaves
//! the face/wall corner sharp (or filleted). The arrissed edge is this section with 45°
//! arrisses of the bevel width, top and bottom, and no fillet.

use super::edge::Facet;
use super::fillet;
use super::profile::{Arris, Seamed, MAX_ARRIS_ANGLE_RAD, MIN_ARRIS_ANGLE_RAD};
use super::{invalid, PanelError};

/// The facets of the seamed section `s` on glass `t` thick (m).
pub(super) fn section(s: &Seamed, t: f64, tessellation_m: f64) -> Result<Vec<Facet>, PanelError> {
    check_arris(&s.top, "seamed.top.width_mm", "seamed.top.angle_deg")?;
    check_arris(
        &s.bottom,
        "seamed.bottom.width_mm",
        "seamed.bottom.angle_deg",
    )?;
    let (v_top, v_bottom) = (leg(&s.top), leg(&s.bottom));
    if v_top + v_bottom >= t {
        return Err(invalid(
            "seamed",
            format!(
                "must leave a wall between its arrisses: their vertical legs (width·tan angle) \
                 {v_top} m + {v_bottom} m must be < the thickness {t} m"
            ),
        ));
    }
    let r = s.fillet_radius_m;
    if !(r.is_finite() && r >= 0.0) {
        return Err(invalid(
            "seamed.fillet_radius_mm",
            format!("must be ≥ 0, got {r} m"),
        ));
    }
    let mut corners = Vec::with_capacity(4);
    if s.top.width_m > 0.0 {
        corners.push([s.top.width_m, t]);
    }
    corners.push([0.0, t - v_top]);
    corners.push([0.0, v_bottom]);
    if s.bottom.width_m > 0.0 {
        corners.push([s.bottom.width_m, 0.0]);
    }
    fillet::round(&corners, r, tessellation_m).map_err(|e| {
        let pieces = piece_names(s);
        invalid(
            "seamed.fillet_radius_mm",
            format!(
                "is too large for the section: the fillets at the ends of the {} take {} m of \
                 its {} m, got {r} m",
                pieces[e.piece], e.needed_m, e.length_m
            ),
        )
    })
}

/// The arrissed edge: 45° bevels of width `bevel_m` (0 < b < t/2) top and bottom.
pub(super) fn arrissed(bevel_m: f64, t: f64) -> Result<Vec<Facet>, PanelError> {
    let b = bevel_m;
    if !(b.is_finite() && b > 0.0 && b < 0.5 * t) {
        return Err(invalid(
            "bevel_mm",
            format!("must be > 0 and < thickness/2 = {} m, got {b} m", 0.5 * t),
        ));
    }
    let arris = Arris {
        width_m: b,
        angle_rad: std::f64::consts::FRAC_PI_4,
    };
    let s = Seamed {
        top: arris,
        bottom: arris,
        fillet_radius_m: 0.0,
    };
    // No fillet: the tessellation is not used.
    section(&s, t, f64::INFINITY)
}

/// The vertical leg (m). At exactly 45° it is the width: tan(π/4) rounds to 1 − 2⁻⁵³ in f64.
fn leg(a: &Arris) -> f64 {
    if a.angle_rad == std::f64::consts::FRAC_PI_4 {
        a.width_m
    } else {
        a.vertical_leg_m()
    }
}

fn check_arris(
    a: &Arris,
    width_field: &'static str,
    angle_field: &'static str,
) -> Result<(), PanelError> {
    let w = a.width_m;
    if !(w.is_finite() && w >= 0.0) {
        return Err(invalid(width_field, format!("must be ≥ 0, got {w} m")));
    }
    let angle = a.angle_rad;
    if !(MIN_ARRIS_ANGLE_RAD..=MAX_ARRIS_ANGLE_RAD).contains(&angle) {
        return Err(invalid(
            angle_field,
            format!(
                "must be in [30, 65] degrees, got {} degrees",
                angle.to_degrees()
            ),
        ));
    }
    Ok(())
}

/// Names of the straight pieces between the corners, in order.
fn piece_names(s: &Seamed) -> Vec<&'static str> {
    let mut names = Vec::new();
    if s.top.width_m > 0.0 {
        names.push("top arris");
    }
    names.push("wall");
    if s.bottom.width_m > 0.0 {
        names.push("bottom arris");
    }
    names
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::geometry::panel::edge::SectionPoint;

    const T: f64 = 0.004;

    fn field(r: Result<Vec<Facet>, PanelError>) -> &'static str {
        match r {
            Err(PanelError::InvalidParameter { field, .. }) => field,
            Err(e) => panic!("{e}"),
            Ok(_) => "built",
        }
    }

    fn points(f: &[Facet]) -> Vec<SectionPoint> {
        f.iter().flat_map(|f| f.points.clone()).collect()
    }

    #[test]
    fn default_seam_has_its_legs_and_facet_angles() {
        let f = section(&Seamed::default(), T, 0.005).unwrap();
        assert_eq!(f.len(), 3);
        let p = points(&f);
        assert_eq!([p[0].inset_m, p[0].height_m], [0.8e-3, T]);
        assert_eq!([p[1].inset_m, p[1].height_m], [0.0, T - 0.8e-3]);
        assert_eq!([p[5].inset_m, p[5].height_m], [0.8e-3, 0.0]);
        // The top arris faces out and up at 45°, the wall out, the bottom arris out and down.
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-15;
        assert!(close(f[0].points[0].normal, [r, r]));
        assert_eq!(f[1].points[0].normal, [1.0, 0.0]);
        assert!(close(f[2].points[0].normal, [r, -r]));
    }

    #[test]
    fn arris_angle_sets_the_vertical_leg_and_the_normal() {
        let top = Arris {
            width_m: 0.5e-3,
            angle_rad: 60f64.to_radians(),
        };
        let s = Seamed {
            top,
            ..Seamed::default()
        };
        let f = section(&s, T, 0.005).unwrap();
        let a = &f[0].points;
        assert!((a[1].height_m - (T - 0.5e-3 * 3f64.sqrt())).abs() < 1e-15);
        // The facet normal makes the arris angle with the face normal (0, 1).
        assert!((a[0].normal[1].acos() - PI / 3.0).abs() < 1e-12);
    }

    #[test]
    fn fillets_round_every_junction_and_move_the_border_to_the_tangent_point() {
        let r = 0.2e-3;
        let s = Seamed {
            fillet_radius_m: r,
            ..Seamed::default()
        };
        let f = section(&s, T, 0.005).unwrap();
        // Arc, arris, arc, wall, arc, arris, arc.
        assert_eq!(f.len(), 7);
        let first = f[0].points[0];
        // Face/arris junction turns by 45°: tangent point at r·tan(22.5°) inside the arris top.
        let d = 0.8e-3 + r * (PI / 8.0).tan();
        assert!((first.inset_m - d).abs() < 1e-15 && first.height_m == T);
        assert_eq!(first.normal, [0.0, 1.0]);
        let last = f[6].points.last().unwrap();
        assert!((last.inset_m - d).abs() < 1e-15 && last.height_m == 0.0);
        // Arcs are smooth: each starts with the normal the piece before it ends with.
        for w in f.windows(2) {
            let (a, b) = (w[0].points.last().unwrap().normal, w[1].points[0].normal);
            assert!(
                (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-15,
                "{a:?} {b:?}"
            );
        }
    }

    #[test]
    fn bad_seams_name_their_field() {
        let with = |f: &dyn Fn(&mut Seamed)| {
            let mut s = Seamed::default();
            f(&mut s);
            field(section(&s, T, 0.005))
        };
        assert_eq!(
            with(&|s| s.top.angle_rad = 70f64.to_radians()),
            "seamed.top.angle_deg"
        );
        assert_eq!(
            with(&|s| s.bottom.angle_rad = 29f64.to_radians()),
            "seamed.bottom.angle_deg"
        );
        assert_eq!(with(&|s| s.top.width_m = -1e-4), "seamed.top.width_mm");
        assert_eq!(
            with(&|s| s.bottom.width_m = f64::NAN),
            "seamed.bottom.width_mm"
        );
        // 2 mm + 2 mm of vertical legs leave no wall on 4 mm glass.
        assert_eq!(
            with(&|s| (s.top.width_m, s.bottom.width_m) = (2e-3, 2e-3)),
            "seamed"
        );
        assert_eq!(
            with(&|s| s.fillet_radius_m = -1e-4),
            "seamed.fillet_radius_mm"
        );
        assert_eq!(
            with(&|s| s.fillet_radius_m = 3e-3),
            "seamed.fillet_radius_mm"
        );
        assert_eq!(with(&|s| s.top.width_m = 0.0), "built");
        let e = section(
            &Seamed {
                fillet_radius_m: 3e-3,
                ..Seamed::default()
            },
            T,
            0.005,
        )
        .unwrap_err();
        assert!(e.to_string().contains("top arris"), "{e}");
    }

    #[test]
    fn bevel_must_be_below_half_the_thickness() {
        for b in [0.0, 0.002, -0.001, f64::NAN] {
            assert_eq!(field(arrissed(b, T)), "bevel_mm");
        }
        assert_eq!(field(arrissed(0.001, T)), "built");
    }
}
