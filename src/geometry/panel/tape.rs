//! The tape of the paper's edge experiment (Adrian & Pham, §III-C, step 1): tape laid along
//! the border, over the edge and onto the glass surface, whose readings give the true contour
//! of the glass. Built from the panel's own section, so it fits any edge finish.
//!
//! What it is: one opaque sheet, the tape's outer surface, at d = `gap + thickness` from the
//! glass: on the top face from `onto_face_m` inwards of the border out to the border (offset
//! upwards), then round the finish, each facet offset along its normal by d and each arc to a
//! concentric arc, with miter joins at sharp facet junctions, down to where the offset meets
//! the bottom face plane. Over every facet the sheet is at exactly d; over a convex sharp
//! junction (of the section, or of the outline, which is mitered the same way) the miter tip
//! stands off the junction by d/cos(θ/2) for a turn θ (+8 % at a 45° arris, +41 % at a 90°
//! corner), as a stiff tape folded over a sharp corner does. It ends there rather
//! than at the offset of the bottom face boundary, which would lie below the bottom face (a
//! pane resting 10 µm above a table would push it into the table). Along the rim it is swept
//! like the edge band (miters at sharp outline corners) and bent with the panel. The tape's
//! inner surface is not modelled: the light tracer treats Lambertian surfaces as two-sided
//! (`transport::trace`'s `facing_normals` turns the normals towards the arriving light), so
//! an opaque sheet returns light where a tape of that thickness would, and no light reaches the
//! glass under it except through the sheet's open ends.

use super::contour::MITER_LIMIT;
use super::edge::FinishCorner;
use super::sheet;
use super::{check_corner_radius, invalid, prepare, Curvature, PanelError, PanelSpec};
use crate::geometry::mesh::Mesh;

/// A tape over a panel's edge. Defaults are modelling choices: the paper does not give the
/// tape's dimensions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TapeSpec {
    /// Tape thickness (m), > 0. Default 0.1 mm, a typical paper masking tape.
    pub thickness_m: f64,
    /// Air gap between glass and tape (m), > 0. Default 0.01 mm: surfaces of different
    /// objects must not coincide (a ray leaving one of two coincident faces cannot tell
    /// which it meets first).
    pub gap_m: f64,
    /// How far the tape reaches onto the top face, inwards of the border (m), > 0. Default
    /// 20 mm, as the hand-placed strips had.
    pub onto_face_m: f64,
}

impl Default for TapeSpec {
    fn default() -> Self {
        TapeSpec {
            thickness_m: 0.1e-3,
            gap_m: 0.01e-3,
            onto_face_m: 20e-3,
        }
    }
}

/// The tape sheet on the panel `panel` (in the panel's model frame), after checking `tape`.
/// Errors name `TapeSpec` fields by their scene-file names (`thickness_mm`, `gap_mm`,
/// `onto_face_mm`); the panel itself is checked as `build_panel` does.
pub fn build_tape(panel: &PanelSpec, tape: &TapeSpec) -> Result<Mesh, PanelError> {
    for (field, v) in [
        ("thickness_mm", tape.thickness_m),
        ("gap_mm", tape.gap_m),
        ("onto_face_mm", tape.onto_face_m),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(invalid(field, format!("must be > 0, got {v} m")));
        }
    }
    let (section, patch) = prepare(panel)?;
    let (t, s) = (panel.thickness_m, panel.tessellation_m);
    let d = tape.gap_m + tape.thickness_m;
    // The sheet is the tape's only surface: it is what must clear the glass.
    check_clearance(&panel.curvature, s, d, "gap_mm")?;
    let start = [section.border_inset_m() + tape.onto_face_m, t + d];
    let profile = offset_finish(&section.finish_corners(), d, start)?;
    let deepest = profile.iter().map(|p| p[0]).fold(f64::MIN, f64::max);
    let outermost = profile.iter().map(|p| p[0]).fold(f64::MAX, f64::min);
    check_corner_radius(&panel.outline, deepest, "onto_face_mm")?;
    let face_inset = section.face_inset_m();
    for (inset, field) in [(deepest, "onto_face_mm"), (outermost, "thickness_mm")] {
        let row = sheet::row(&patch.rim, inset, face_inset);
        sheet::check_row(&patch.rim, &row).map_err(|what| {
            invalid(
                field,
                format!("does not fit the outline: the tape {inset} m in from it {what}"),
            )
        })?;
    }
    let profile = sheet::refine(&profile, s, false);
    Ok(sheet::sweep(
        &patch.rim,
        &profile,
        false,
        face_inset,
        &panel.curvature,
    ))
}

/// The finish offset outwards by `d`, after the top strip from `start`, cut where it reaches
/// the bottom face plane: a list of (inset, height) points.
///
/// Each piece (flat facet or arc sample) is offset along its own normal, so flat facets stay
/// parallel at d and arcs become concentric. At a sharp junction the two offsets are joined by
/// a miter: at a convex junction the path goes from the end of the one offset to the miter tip
/// (where the two offset lines meet) and back to the start of the other (one point when both
/// pieces are flat, since the three are then on the two lines); at a concave junction the
/// offsets overlap and the path takes the tip alone.
fn offset_finish(
    corners: &[FinishCorner],
    d: f64,
    start: [f64; 2],
) -> Result<Vec<[f64; 2]>, PanelError> {
    let at = |c: &FinishCorner, n: [f64; 2]| [c.point[0] - d * n[0], c.point[1] + d * n[1]];
    let mut path = vec![start];
    for (k, c) in corners.iter().enumerate() {
        let (a, b) = (c.before, c.after);
        let mut points = Vec::with_capacity(3);
        // Pieces that meet tangentially (an arc and its facet) have equal normals up to
        // rounding: a smooth point.
        if (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-9 {
            points.push(at(c, a));
        } else {
            let cos = a[0] * b[0] + a[1] * b[1];
            // |miter| = 1/cos(θ/2) = √(2/(1 + cos θ)).
            let stretch = (2.0 / (1.0 + cos)).sqrt();
            // Also refuses a turn back (cos θ = −1), where the stretch is not a number.
            if stretch.is_nan() || stretch > MITER_LIMIT {
                return Err(invalid(
                    "thickness_mm",
                    format!(
                        "cannot be offset round the section corner ({:.6}, {:.6}) m: its facets \
                         turn by {:.1}°, so the tape's miter would be {stretch:.1} times its \
                         distance, more than {MITER_LIMIT}",
                        c.point[0],
                        c.point[1],
                        cos.clamp(-1.0, 1.0).acos().to_degrees()
                    ),
                ));
            }
            let tip = at(
                c,
                [(a[0] + b[0]) / (1.0 + cos), (a[1] + b[1]) / (1.0 + cos)],
            );
            // Convex when the normal turns clockwise in (outward, up) coordinates.
            if a[0] * b[1] - a[1] * b[0] < 0.0 {
                points.extend([at(c, a), tip, at(c, b)]);
            } else {
                points.push(tip);
            }
        }
        // The offset of the piece that arrives here must run the way the piece does.
        let prev = *path.last().unwrap_or(&start);
        let (first, step) = (points[0], [points[0][0] - prev[0], points[0][1] - prev[1]]);
        let forward = match k {
            // The top strip runs outward (towards smaller insets).
            0 => step[0] < 0.0,
            _ => {
                let p = corners[k - 1].point;
                step[0] * (c.point[0] - p[0]) + step[1] * (c.point[1] - p[1]) > 0.0
            }
        };
        if !forward && first != prev {
            let (field, what) = if k == 0 {
                (
                    "onto_face_mm",
                    "reach past the offset of the top face boundary",
                )
            } else {
                ("thickness_mm", "fit the facets of the edge section")
            };
            return Err(invalid(
                field,
                format!(
                    "too small or too large: the tape at {d} m from the glass must {what}, \
                     near the section point ({:.6}, {:.6}) m",
                    c.point[0], c.point[1]
                ),
            ));
        }
        for o in points {
            let prev = *path.last().unwrap_or(&start);
            if o[1] < 0.0 {
                // Ends on the bottom face plane.
                let f = prev[1] / (prev[1] - o[1]);
                path.push([prev[0] + (o[0] - prev[0]) * f, 0.0]);
                return Ok(path);
            }
            if o != prev {
                path.push(o);
            }
        }
    }
    Ok(path)
}

/// The flat triangles of a sheet or solid laid `gap_m` off a bent face sag towards it by up to
/// (√2·s)²/(8R) = s²/(4R) (a cell's diagonal as the chord): the gap must be larger. `field`
/// is reported.
pub(super) fn check_clearance(
    curvature: &Curvature,
    tessellation_m: f64,
    gap_m: f64,
    field: &'static str,
) -> Result<(), PanelError> {
    if let Curvature::Cylindrical { radius_m } = curvature {
        let sag = tessellation_m * tessellation_m / (4.0 * radius_m);
        if gap_m <= sag {
            return Err(invalid(
                field,
                format!(
                    "must be > the chord sag {sag} m of {tessellation_m} m triangles on the \
                     {radius_m} m bend (or use a finer tessellation_mm), got {gap_m} m"
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::*;
    use crate::geometry::closest::nearest_on_mesh;
    use crate::geometry::panel::profile::Seamed;
    use crate::geometry::panel::{build_panel, EdgeProfile, Outline};

    fn panel(edge: EdgeProfile, curvature: Curvature, r: f64) -> PanelSpec {
        PanelSpec {
            outline: Outline::Rectangle {
                width_m: 0.06,
                height_m: 0.04,
                corner_radius_m: r,
            },
            thickness_m: 0.004,
            curvature,
            edge,
            tessellation_m: 0.005,
        }
    }

    /// Distances from points on the tape (one per triangle, at barycentric (0.6, 0.3, 0.1), so
    /// that it faces the inside of a glass triangle) to the glass: the largest deviation from
    /// `d` where the nearest glass point is inside a triangle, the range elsewhere (over
    /// convex corners, where the miter lies farther out), and the share of the first kind.
    fn distances(spec: &PanelSpec, tape: &TapeSpec, d: f64) -> (f64, [f64; 2], f64) {
        let glass = build_panel(spec).unwrap().mesh;
        let sheet = build_tape(spec, tape).unwrap();
        let (mut flat, mut corner, mut inside) = (0.0f64, [f64::INFINITY, 0.0f64], 0);
        for t in &sheet.triangles {
            let [a, b, c] = t.map(|k| sheet.positions[k as usize].coords);
            let p = Point3::from(a * 0.6 + b * 0.3 + c * 0.1);
            let nearest = nearest_on_mesh(&glass, &p).expect("the glass has triangles");
            let (dist, interior) = (nearest.distance, nearest.inside);
            if interior {
                flat = flat.max((dist - d).abs());
                inside += 1;
            } else {
                corner = [corner[0].min(dist), corner[1].max(dist)];
            }
        }
        (flat, corner, inside as f64 / sheet.triangles.len() as f64)
    }

    #[test]
    fn tape_lies_at_gap_plus_thickness_from_the_glass() {
        let tape = TapeSpec {
            onto_face_m: 5e-3,
            ..TapeSpec::default()
        };
        let d = tape.gap_m + tape.thickness_m;
        let fillet = EdgeProfile::Seamed(Seamed {
            fillet_radius_m: 0.2e-3,
            ..Seamed::default()
        });
        let pencil = |radius_m| EdgeProfile::Pencil { radius_m };
        let cases = [
            (EdgeProfile::default(), Curvature::Flat, 0.0, 1e-12),
            (EdgeProfile::FlatGround, Curvature::Flat, 0.0, 1e-12),
            (EdgeProfile::default(), Curvature::Flat, 0.008, 1e-6),
            (fillet, Curvature::Flat, 0.0, 1e-6),
            (pencil(None), Curvature::Flat, 0.008, 1e-6),
            (pencil(Some(0.003)), Curvature::Flat, 0.0, 1e-6),
            (
                EdgeProfile::default(),
                Curvature::Cylindrical { radius_m: 0.3 },
                0.008,
                3e-5,
            ),
        ];
        for (edge, curvature, r, tol) in cases {
            let spec = panel(edge.clone(), curvature, r);
            let (flat, [lo, hi], share) = distances(&spec, &tape, d);
            eprintln!(
                "{edge:?}, {curvature:?}, corner radius {r}: |dist − d| ≤ {flat:.2e} m over \
                 the glass ({:.0} % of samples), {lo:.3e} … {hi:.3e} m over its corners",
                share * 100.0
            );
            assert!(flat < tol, "{edge:?}: {flat}");
            assert!(share > 0.3, "{edge:?}: {share}");
            // Never closer than d; over a convex corner a miter lies at most 1/cos(θ/2) out,
            // θ ≤ 90° for these sections and outlines, in the section and along the rim.
            assert!(lo > d - tol && hi < d * 2.0 + tol, "{edge:?}: {lo} … {hi}");
        }
    }

    #[test]
    fn tape_runs_from_the_face_onto_the_edge_down_to_the_bottom_face_plane() {
        let spec = panel(EdgeProfile::default(), Curvature::Flat, 0.0);
        let tape = TapeSpec {
            onto_face_m: 5e-3,
            ..TapeSpec::default()
        };
        let sheet = build_tape(&spec, &tape).unwrap();
        sheet.check().unwrap();
        assert!(sheet.normals.is_none());
        let z_max = sheet.positions.iter().map(|p| p.z).fold(f64::MIN, f64::max);
        let z_min = sheet.positions.iter().map(|p| p.z).fold(f64::MAX, f64::min);
        assert!((z_max - 0.00411).abs() < 1e-15 && z_min == 0.0);
        // The outermost tape point is d out from the wall at x = 30 mm; the innermost reaches
        // 5 mm in from the border at inset 0.8 mm.
        let x_max = sheet.positions.iter().map(|p| p.x).fold(f64::MIN, f64::max);
        assert!((x_max - (0.03 + 0.11e-3)).abs() < 1e-15, "{x_max}");
        let inset = |p: &Point3<f64>| (0.03 - p.x.abs()).min(0.02 - p.y.abs());
        let deepest = sheet.positions.iter().map(inset).fold(f64::MIN, f64::max);
        assert!((deepest - 5.8e-3).abs() < 1e-15, "{deepest}");
    }

    #[test]
    fn bad_tapes_name_their_field() {
        let spec = panel(EdgeProfile::default(), Curvature::Flat, 0.008);
        let field = |spec: &PanelSpec, tape: TapeSpec| match build_tape(spec, &tape) {
            Err(PanelError::InvalidParameter { field, .. }) => field,
            Err(e) => panic!("{e}"),
            Ok(_) => "built",
        };
        let d = TapeSpec::default();
        let onto = |onto_face_m| TapeSpec { onto_face_m, ..d };
        assert_eq!(
            field(
                &spec,
                TapeSpec {
                    thickness_m: 0.0,
                    ..d
                }
            ),
            "thickness_mm"
        );
        assert_eq!(field(&spec, TapeSpec { gap_m: -1.0, ..d }), "gap_mm");
        assert_eq!(field(&spec, onto(f64::NAN)), "onto_face_mm");
        assert_eq!(field(&spec, onto(5e-3)), "built");
        // 20 mm onto a 40 mm tall pane runs into the opposite side; 7.5 mm in from the
        // border at 0.8 mm passes the 8 mm corner radius: the corners would turn inside out.
        assert_eq!(field(&spec, d), "onto_face_mm");
        assert_eq!(field(&spec, onto(7.5e-3)), "onto_face_mm");
        // A concave corner rounded tighter than the tape's 0.11 mm: the offset would fold.
        let l_shape = PanelSpec {
            outline: Outline::Polygon {
                vertices_m: vec![
                    [0.0, 0.0],
                    [0.06, 0.0],
                    [0.06, 0.03],
                    [0.03, 0.03],
                    [0.03, 0.06],
                    [0.0, 0.06],
                ],
                corner_radius_m: 0.05e-3,
            },
            edge: EdgeProfile::FlatGround,
            ..spec.clone()
        };
        assert_eq!(field(&l_shape, onto(0.04e-3)), "thickness_mm");
        // On a tight bend the gap must clear the triangles' sag.
        let bent = panel(
            EdgeProfile::default(),
            Curvature::Cylindrical { radius_m: 0.05 },
            0.008,
        );
        assert_eq!(field(&bent, onto(5e-3)), "gap_mm");
    }
}
