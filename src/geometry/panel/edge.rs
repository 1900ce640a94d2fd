//! The edge finish: its cross-section (PARAMETERS.md §3, CGC edge finishes) and the band of
//! quads that sweeps it along the outline.
//!
//! A section point is an inset d ≥ 0 from the outline and a height h ∈ [0, t] above the bottom
//! face, listed from the top face boundary down to the bottom face boundary, with its unit
//! normal in the section plane as (outward component, vertical component). The section is
//! split into facets: quads are made within a facet only, and the point shared by two facets
//! appears in both with each facet's normal, so that arrisses are flat-shaded.

use nalgebra::{Vector2, Vector3};

use super::contour::{RimPoint, MAX_ARC_STEP};
use super::{invalid, Curvature, EdgeProfile, MeshBuilder, PanelError};
use crate::geometry::mesh::SurfacePart;

/// One point of the edge cross-section.
#[derive(Clone, Copy, Debug, PartialEq)]
struct SectionPoint {
    /// Inset from the outline (m), ≥ 0.
    inset_m: f64,
    /// Height above the bottom face (m), in [0, t].
    height_m: f64,
    /// Unit normal in the section: (outward component, vertical component).
    normal: [f64; 2],
}

/// The edge cross-section as facets, top to bottom. The first and the last point have the same
/// inset (the faces' inset), so top and bottom face share one tessellation.
#[derive(Clone, Debug)]
pub(super) struct EdgeSection {
    facets: Vec<Vec<SectionPoint>>,
    /// The scene-file field that sets the inset (for errors when it does not fit the outline).
    inset_field: &'static str,
}

impl EdgeSection {
    /// The section of `edge` on glass `thickness_m` thick (checked > 0 by the caller), with
    /// rounded profiles sampled at most 10° and `tessellation_m` per step.
    pub(super) fn new(
        edge: EdgeProfile,
        thickness_m: f64,
        tessellation_m: f64,
    ) -> Result<Self, PanelError> {
        let t = thickness_m;
        let point = |inset_m, height_m, normal| SectionPoint {
            inset_m,
            height_m,
            normal,
        };
        let (facets, inset_field) = match edge {
            EdgeProfile::FlatGround => (
                vec![vec![point(0.0, t, [1.0, 0.0]), point(0.0, 0.0, [1.0, 0.0])]],
                "thickness_mm",
            ),
            EdgeProfile::Arrissed { bevel_m: b } => {
                if !(b.is_finite() && b > 0.0 && b < 0.5 * t) {
                    return Err(invalid(
                        "bevel_mm",
                        format!("must be > 0 and < thickness/2 = {} m, got {b} m", 0.5 * t),
                    ));
                }
                let up = [
                    std::f64::consts::FRAC_1_SQRT_2,
                    std::f64::consts::FRAC_1_SQRT_2,
                ];
                let down = [up[0], -up[1]];
                let facets = vec![
                    vec![point(b, t, up), point(0.0, t - b, up)],
                    vec![point(0.0, t - b, [1.0, 0.0]), point(0.0, b, [1.0, 0.0])],
                    vec![point(0.0, b, down), point(b, 0.0, down)],
                ];
                (facets, "bevel_mm")
            }
            EdgeProfile::Pencil => {
                // Half circle of radius r = t/2 about (inset r, height r), from the top face
                // round the outside to the bottom face; the normal is radial.
                let r = 0.5 * t;
                let pi = std::f64::consts::PI;
                let steps = ((pi / MAX_ARC_STEP).round() as usize)
                    .max((pi * r / tessellation_m).ceil() as usize);
                let arc = (0..=steps).map(|k| {
                    let phi = pi * k as f64 / steps as f64;
                    let (s, c) = phi.sin_cos();
                    match k {
                        // Exact end points: they must coincide with the face boundaries.
                        0 => point(r, t, [0.0, 1.0]),
                        k if k == steps => point(r, 0.0, [0.0, -1.0]),
                        _ => point(r - r * s, r + r * c, [s, c]),
                    }
                });
                (vec![arc.collect()], "thickness_mm")
            }
        };
        Ok(EdgeSection {
            facets,
            inset_field,
        })
    }

    /// Inset of the face boundaries from the outline (m): 0 flat ground, the bevel leg for an
    /// arrissed edge, t/2 for a pencil edge.
    pub(super) fn face_inset_m(&self) -> f64 {
        self.facets[0][0].inset_m
    }

    /// The scene-file field that sets [`Self::face_inset_m`].
    pub(super) fn inset_field(&self) -> &'static str {
        self.inset_field
    }
}

/// Adds the edge band along the refined rim: one quad per rim segment and section step, tagged
/// `Edge`, wound outward. Sharp rim corners get two vertex columns (one per side) so that each
/// wall keeps its own normal.
pub(super) fn add_band(
    mesh: &mut MeshBuilder,
    rim: &[RimPoint],
    section: &EdgeSection,
    curvature: &Curvature,
) {
    let face_inset = section.face_inset_m();
    let mut column = |p: &RimPoint, plane_normal: Vector2<f64>| -> Vec<u32> {
        let mut ids = Vec::new();
        for sp in section.facets.iter().flatten() {
            // The face boundaries use the rim's exact face point; intermediate insets are
            // computed from the outline, on the same rim parameter.
            let q = if sp.inset_m == face_inset {
                p.face
            } else {
                p.outline - p.miter * sp.inset_m
            };
            let flat = Vector3::new(
                sp.normal[0] * plane_normal.x,
                sp.normal[0] * plane_normal.y,
                sp.normal[1],
            );
            let normal = curvature.bend_direction(q.x, flat).normalize();
            ids.push(mesh.vertex(curvature.bend_point(q.x, q.y, sp.height_m), normal));
        }
        ids
    };
    let n = rim.len();
    let mut starts = Vec::with_capacity(n);
    let mut ends = Vec::with_capacity(n);
    for p in rim {
        let start = column(p, p.normal_out);
        ends.push(if p.is_sharp() {
            column(p, p.normal_in)
        } else {
            start.clone()
        });
        starts.push(start);
    }
    for i in 0..n {
        let (a, b) = (&starts[i], &ends[(i + 1) % n]);
        let mut base = 0;
        for facet in &section.facets {
            for j in base..base + facet.len() - 1 {
                // Rim i → i + 1 runs counter-clockwise and the section runs top → bottom, so
                // (a_j, a_j+1, b_j+1) faces outward.
                mesh.triangle([a[j], a[j + 1], b[j + 1]], SurfacePart::Edge);
                mesh.triangle([a[j], b[j + 1], b[j]], SurfacePart::Edge);
            }
            base += facet.len();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_section(s: &EdgeSection, t: f64) {
        let pts: Vec<_> = s.facets.iter().flatten().collect();
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        assert_eq!((first.height_m, last.height_m), (t, 0.0));
        assert_eq!(first.inset_m, last.inset_m);
        for facet in &s.facets {
            for w in facet.windows(2) {
                // The normal is perpendicular to the facet step and points out (to smaller inset).
                let step = [w[1].inset_m - w[0].inset_m, w[1].height_m - w[0].height_m];
                let n = w[0].normal;
                let len = step[0].hypot(step[1]);
                assert!(len > 0.0);
                // In (outward, vertical) coordinates the step is (−Δd, Δh); turn it by +90°.
                let out = [-step[1] / len, -step[0] / len];
                assert!(n[0] * out[0] + n[1] * out[1] > 0.98, "{n:?} vs {out:?}");
            }
        }
        for p in &pts {
            assert!((p.normal[0].hypot(p.normal[1]) - 1.0).abs() < 1e-15);
            assert!(p.inset_m >= 0.0 && (0.0..=t).contains(&p.height_m));
        }
    }

    #[test]
    fn sections_run_top_to_bottom_with_outward_normals() {
        let t = 0.004;
        let flat = EdgeSection::new(EdgeProfile::FlatGround, t, 0.005).unwrap();
        check_section(&flat, t);
        assert_eq!(flat.face_inset_m(), 0.0);
        let arrissed =
            EdgeSection::new(EdgeProfile::Arrissed { bevel_m: 0.001 }, t, 0.005).unwrap();
        check_section(&arrissed, t);
        assert_eq!((arrissed.facets.len(), arrissed.face_inset_m()), (3, 0.001));
        let pencil = EdgeSection::new(EdgeProfile::Pencil, t, 0.005).unwrap();
        check_section(&pencil, t);
        assert_eq!((pencil.facets[0].len(), pencil.face_inset_m()), (19, 0.002));
    }

    #[test]
    fn bevel_must_be_below_half_the_thickness() {
        for b in [0.0, 0.002, -0.001, f64::NAN] {
            let err =
                EdgeSection::new(EdgeProfile::Arrissed { bevel_m: b }, 0.004, 0.005).unwrap_err();
            assert!(matches!(
                err,
                PanelError::InvalidParameter {
                    field: "bevel_mm",
                    ..
                }
            ));
        }
    }
}
