//! The cover of the paper's edge experiment (Adrian & Pham, §III-C, step 2): a cover placed on
//! the glass surface that coincides with the edge line, so that the first crossing of the tape
//! and cover profiles marks the border. Built from the panel's own section and rim.
//!
//! What it is: a closed opaque solid ring on the top face. Its outer wall stands on the border
//! curve (the top face's true boundary, `EdgeSection::border_inset_m`), perpendicular to the top
//! face: every outer-wall vertex is a border vertex moved along the top face's normal, so the
//! wall's surface, continued down to the face, contains the border and p_e. The inner wall is
//! `width_m` inwards of the border; the bottom is `gap_m` above the top face and the top
//! `height_m` above it, both following a bent panel (they are the bend map at heights t + gap
//! and t + height, swept along the same rim as the border).

use super::sheet;
use super::tape::check_clearance;
use super::{check_corner_radius, invalid, prepare, PanelError, PanelSpec};
use crate::geometry::mesh::Mesh;

/// A cover on a panel's top face. Defaults are modelling choices: the paper gives no size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoverSpec {
    /// How far the cover reaches inwards of the border (m), > 0. Default 20 mm.
    pub width_m: f64,
    /// Height of its top above the top face (m), > `gap_m`. Default 10 mm.
    pub height_m: f64,
    /// Air gap between the top face and its bottom (m), > 0. Default 0.01 mm: surfaces of
    /// different objects must not coincide (a ray leaving one of two coincident faces
    /// cannot tell which it meets first).
    pub gap_m: f64,
}

impl Default for CoverSpec {
    fn default() -> Self {
        CoverSpec {
            width_m: 20e-3,
            height_m: 10e-3,
            gap_m: 0.01e-3,
        }
    }
}

/// The cover on the panel `panel` (in the panel's model frame), after checking `cover`.
/// Errors name `CoverSpec` fields by their scene-file names (`width_mm`, `height_mm`,
/// `gap_mm`); the panel itself is checked as `build_panel` does.
pub fn build_cover(panel: &PanelSpec, cover: &CoverSpec) -> Result<Mesh, PanelError> {
    for (field, v) in [
        ("width_mm", cover.width_m),
        ("height_mm", cover.height_m),
        ("gap_mm", cover.gap_m),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(invalid(field, format!("must be > 0, got {v} m")));
        }
    }
    if cover.height_m <= cover.gap_m {
        return Err(invalid(
            "height_mm",
            format!(
                "must be > the gap {} m under the cover, got {} m",
                cover.gap_m, cover.height_m
            ),
        ));
    }
    let (section, patch) = prepare(panel)?;
    let (t, s) = (panel.thickness_m, panel.tessellation_m);
    check_clearance(&panel.curvature, s, cover.gap_m, "gap_mm")?;
    let outer = section.border_inset_m();
    let inner = outer + cover.width_m;
    check_corner_radius(&panel.outline, inner, "width_mm")?;
    let row = sheet::row(&patch.rim, inner, section.face_inset_m());
    sheet::check_row(&patch.rim, &row).map_err(|what| {
        invalid(
            "width_mm",
            format!("does not fit the outline: the inner wall {inner} m in from it {what}"),
        )
    })?;
    let (bottom, top) = (t + cover.gap_m, t + cover.height_m);
    // In the edge section's sense: outward along the top, down the outer wall, inward along
    // the bottom, up the inner wall.
    let ring = [[inner, top], [outer, top], [outer, bottom], [inner, bottom]];
    let profile = sheet::refine(&ring, s, true);
    Ok(sheet::sweep(
        &patch.rim,
        &profile,
        true,
        section.face_inset_m(),
        &panel.curvature,
    ))
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use nalgebra::{Point3, Vector3};

    use super::*;
    use crate::geometry::panel::profile::Seamed;
    use crate::geometry::panel::{build_panel, Curvature, EdgeProfile, Outline};

    fn panel(edge: EdgeProfile, curvature: Curvature) -> PanelSpec {
        PanelSpec {
            outline: Outline::Rectangle {
                width_m: 0.3,
                height_m: 0.2,
                corner_radius_m: 0.03,
            },
            thickness_m: 0.004,
            curvature,
            edge,
            tessellation_m: 0.005,
        }
    }

    /// Every directed edge once and its reverse once: closed and consistently wound.
    fn check_closed(mesh: &Mesh) {
        let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1);
            assert_eq!(edges.get(&(b, a)), Some(&1));
        }
    }

    fn volume(mesh: &Mesh) -> f64 {
        let p = |k: u32| mesh.positions[k as usize].coords;
        mesh.triangles
            .iter()
            .map(|t| p(t[0]).dot(&p(t[1]).cross(&p(t[2]))) / 6.0)
            .sum()
    }

    #[test]
    fn cover_is_a_closed_ring_of_the_expected_volume() {
        let spec = panel(EdgeProfile::default(), Curvature::Flat);
        let c = CoverSpec::default();
        let mesh = build_cover(&spec, &c).unwrap();
        mesh.check().unwrap();
        check_closed(&mesh);
        // Ring between the border (inset 0.8 mm) and 20 mm further in, 9.99 mm tall: the area
        // of a rounded rectangle inset by d is (w − 2d)(h − 2d) − (4 − π)(r − d)².
        let area = |d: f64| (0.3 - 2.0 * d) * (0.2 - 2.0 * d) - (4.0 - PI) * (0.03 - d).powi(2);
        use std::f64::consts::PI;
        let expected = (area(0.8e-3) - area(20.8e-3)) * (c.height_m - c.gap_m);
        assert!(
            (volume(&mesh) / expected - 1.0).abs() < 1e-3,
            "{}",
            volume(&mesh)
        );
    }

    #[test]
    fn outer_wall_stands_on_the_border_curve() {
        let fillet = EdgeProfile::Seamed(Seamed {
            fillet_radius_m: 0.3e-3,
            ..Seamed::default()
        });
        for (edge, curvature) in [
            (EdgeProfile::default(), Curvature::Flat),
            (fillet, Curvature::Cylindrical { radius_m: 1.5 }),
            (
                EdgeProfile::Pencil {
                    radius_m: Some(0.004),
                },
                Curvature::Flat,
            ),
        ] {
            let spec = panel(edge, curvature);
            let border = build_panel(&spec).unwrap().border;
            let mesh = build_cover(&spec, &CoverSpec::default()).unwrap();
            // Per rim point the ring has 12 points: the 20 mm top in 4 steps (points 0–4),
            // the 9.99 mm outer wall in 2 (4–6), the bottom in 4 (6–10), the inner wall in 2.
            // The outer wall's top is point 4, its bottom point 6.
            let per_rim = mesh.positions.len() / border.vertices.len();
            assert_eq!(
                (per_rim, per_rim * border.vertices.len()),
                (12, mesh.positions.len())
            );
            for (i, v) in border.vertices.iter().enumerate() {
                for (k, h) in [(4, 10e-3), (6, 0.01e-3)] {
                    let p: Point3<f64> = mesh.positions[i * per_rim + k];
                    let along: Vector3<f64> = p - v.position;
                    // On the top face's normal through the border vertex, at its height.
                    let off = along - v.surface_normal * along.dot(&v.surface_normal);
                    assert!(off.norm() < 1e-12, "{}", off.norm());
                    assert!((along.dot(&v.surface_normal) - h).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn bad_covers_name_their_field() {
        let spec = panel(EdgeProfile::default(), Curvature::Flat);
        let field = |c: CoverSpec| match build_cover(&spec, &c) {
            Err(PanelError::InvalidParameter { field, .. }) => field,
            Err(e) => panic!("{e}"),
            Ok(_) => "built",
        };
        let d = CoverSpec::default();
        assert_eq!(field(CoverSpec { width_m: 0.0, ..d }), "width_mm");
        assert_eq!(
            field(CoverSpec {
                height_m: 0.005e-3,
                ..d
            }),
            "height_mm"
        );
        assert_eq!(
            field(CoverSpec {
                gap_m: f64::INFINITY,
                ..d
            }),
            "gap_mm"
        );
        // The 30 mm corner radius holds 20 mm in from the border at 0.8 mm, not 30 mm.
        assert_eq!(field(d), "built");
        assert_eq!(
            field(CoverSpec {
                width_m: 30e-3,
                ..d
            }),
            "width_mm"
        );
        // 100 mm in from both long sides of a 200 mm pane meet in the middle.
        let sharp = PanelSpec {
            outline: Outline::Rectangle {
                width_m: 0.3,
                height_m: 0.2,
                corner_radius_m: 0.0,
            },
            ..spec.clone()
        };
        let e = build_cover(&sharp, &CoverSpec { width_m: 0.1, ..d }).unwrap_err();
        assert!(
            matches!(
                e,
                PanelError::InvalidParameter {
                    field: "width_mm",
                    ..
                }
            ),
            "{e}"
        );
    }
}
