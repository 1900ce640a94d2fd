//! The edge cross-section as the mesh builder uses it, and the band of quads that sweeps it
//! along the outline.
//!
//! A section point is an inset d ≥ 0 from the outline and a height h ∈ [0, t] above the bottom
//! face, with its unit normal in the section plane as (outward component, vertical component).
//! The section runs from the top face at height t, round the outside, to the bottom face at
//! height 0, and is split into facets: quads are made within a facet only, and the point two
//! facets share appears in both with each facet's normal, so that flat facets are flat-shaded
//! while an arc (one facet of many points with radial normals) is smooth.
//!
//! Both faces are one tessellation at the common face inset d₀ = max(d_top, d_bottom) of the
//! finish's end points. The face whose finish ends at a smaller inset gets a flat strip from d₀
//! to its boundary, tagged as that face (`TopFace`/`BottomFace`, smooth glass), so the rough
//! edge model only sees the ground finish. The border curve lies at d_top: where the top face
//! really meets the finish.

use nalgebra::{Vector2, Vector3};

use super::contour::RimPoint;
use super::profile::EdgeProfile;
use super::{custom, pencil, seamed, Curvature, MeshBuilder, PanelError};
use crate::geometry::mesh::SurfacePart;

/// One point of the edge cross-section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SectionPoint {
    /// Inset from the outline (m).
    pub(super) inset_m: f64,
    /// Height above the bottom face (m), in [0, t].
    pub(super) height_m: f64,
    /// Unit normal in the section: (outward component, vertical component).
    pub(super) normal: [f64; 2],
}

/// A run of section points meshed as one surface piece.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Facet {
    /// At least two points, top to bottom.
    pub(super) points: Vec<SectionPoint>,
    /// `Edge` for the finish, `TopFace`/`BottomFace` for a face strip.
    pub(super) part: SurfacePart,
}

impl Facet {
    /// A flat facet of the finish from `a` to `b`, each (inset, height) (m), with the outward
    /// normal of the step: in (outward, vertical) coordinates the step is (−Δd, Δh), and the
    /// glass lies on its right, so the normal is the step turned by +90°.
    pub(super) fn flat(a: [f64; 2], b: [f64; 2]) -> Facet {
        let (dd, dh) = (b[0] - a[0], b[1] - a[1]);
        let len = dd.hypot(dh);
        let normal = [-dh / len, -dd / len];
        let point = |p: [f64; 2]| SectionPoint {
            inset_m: p[0],
            height_m: p[1],
            normal,
        };
        Facet {
            points: vec![point(a), point(b)],
            part: SurfacePart::Edge,
        }
    }
}

/// A point of the finish's outline with the normals of the surfaces before and after it (equal
/// on a flat facet or an arc, different at a sharp junction): what an offset surface needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FinishCorner {
    /// (inset, height) (m).
    pub(super) point: [f64; 2],
    /// Unit normal of the surface above (the top face's (0, 1) at the first point).
    pub(super) before: [f64; 2],
    /// Unit normal of the surface below (the bottom face's (0, −1) at the last point).
    pub(super) after: [f64; 2],
}

/// The edge cross-section as facets, top to bottom, face strips included.
#[derive(Clone, Debug)]
pub(super) struct EdgeSection {
    facets: Vec<Facet>,
    /// Common inset d₀ of both face polygons (m).
    face_inset_m: f64,
    /// Inset of the top face's true boundary (m): the border curve.
    border_inset_m: f64,
    /// Largest inset of any section point (m).
    max_inset_m: f64,
    /// The scene-file field that sets the insets (for errors when they do not fit the outline).
    inset_field: &'static str,
}

impl EdgeSection {
    /// The section of `edge` on glass `thickness_m` thick (checked > 0 by the caller), with
    /// arcs sampled at most 10° and `tessellation_m` per step.
    pub(super) fn new(
        edge: &EdgeProfile,
        thickness_m: f64,
        tessellation_m: f64,
    ) -> Result<Self, PanelError> {
        let t = thickness_m;
        let (finish, inset_field) = match edge {
            EdgeProfile::FlatGround => (vec![Facet::flat([0.0, t], [0.0, 0.0])], "thickness_mm"),
            EdgeProfile::Seamed(s) => (seamed::section(s, t, tessellation_m)?, "seamed"),
            EdgeProfile::Arrissed { bevel_m } => (seamed::arrissed(*bevel_m, t)?, "bevel_mm"),
            EdgeProfile::Pencil { radius_m } => pencil::section(*radius_m, t, tessellation_m)?,
            EdgeProfile::Section { points_m } => {
                (custom::section(points_m, t)?, "section.points_mm")
            }
        };
        Ok(Self::with_face_strips(finish, inset_field))
    }

    /// Adds the face strip that joins the face with the smaller boundary inset to the common
    /// face polygon at d₀.
    fn with_face_strips(mut facets: Vec<Facet>, inset_field: &'static str) -> Self {
        let first = facets[0].points[0];
        let last = *facets[facets.len() - 1].points.last().unwrap_or(&first);
        let (top, bottom) = (first.inset_m, last.inset_m);
        let face_inset_m = top.max(bottom);
        let max_inset_m = facets
            .iter()
            .flat_map(|f| f.points.iter().map(|p| p.inset_m))
            .fold(face_inset_m, f64::max);
        let strip = |from: f64, to: f64, height_m: f64, normal: [f64; 2], part| Facet {
            points: [from, to]
                .map(|inset_m| SectionPoint {
                    inset_m,
                    height_m,
                    normal,
                })
                .to_vec(),
            part,
        };
        if top < face_inset_m {
            let t = first.height_m;
            facets.insert(
                0,
                strip(face_inset_m, top, t, [0.0, 1.0], SurfacePart::TopFace),
            );
        }
        if bottom < face_inset_m {
            facets.push(strip(
                bottom,
                face_inset_m,
                0.0,
                [0.0, -1.0],
                SurfacePart::BottomFace,
            ));
        }
        EdgeSection {
            facets,
            face_inset_m,
            border_inset_m: top,
            max_inset_m,
            inset_field,
        }
    }

    /// Inset of the face polygons from the outline (m): 0 flat ground, the larger of the two
    /// boundary insets otherwise.
    pub(super) fn face_inset_m(&self) -> f64 {
        self.face_inset_m
    }

    /// Inset of the top face's true boundary (m), where the border curve lies.
    pub(super) fn border_inset_m(&self) -> f64 {
        self.border_inset_m
    }

    /// The largest inset of the section (m): the outline must hold it.
    pub(super) fn max_inset_m(&self) -> f64 {
        self.max_inset_m
    }

    /// The scene-file field that sets the insets.
    pub(super) fn inset_field(&self) -> &'static str {
        self.inset_field
    }

    /// The finish (face strips left out) as distinct points from the top face boundary to the
    /// bottom face boundary, with the normals on either side of each.
    pub(super) fn finish_corners(&self) -> Vec<FinishCorner> {
        let mut out: Vec<FinishCorner> = Vec::new();
        for facet in self.facets.iter().filter(|f| f.part == SurfacePart::Edge) {
            for p in &facet.points {
                let point = [p.inset_m, p.height_m];
                match out.last_mut() {
                    Some(prev) if prev.point == point => prev.after = p.normal,
                    _ => out.push(FinishCorner {
                        point,
                        before: out.last().map_or([0.0, 1.0], |_| p.normal),
                        after: p.normal,
                    }),
                }
            }
        }
        if let Some(last) = out.last_mut() {
            last.after = [0.0, -1.0];
        }
        out
    }
}

/// Adds the edge band along the refined rim: one quad per rim segment and section step, tagged
/// with its facet's part, wound outward. Sharp rim corners get two vertex columns (one per
/// side) so that each wall keeps its own normal.
pub(super) fn add_band(
    mesh: &mut MeshBuilder,
    rim: &[RimPoint],
    section: &EdgeSection,
    curvature: &Curvature,
) {
    let face_inset = section.face_inset_m();
    let mut column = |p: &RimPoint, plane_normal: Vector2<f64>| -> Vec<u32> {
        let mut ids = Vec::new();
        for sp in section.facets.iter().flat_map(|f| &f.points) {
            let normal = Vector3::new(
                sp.normal[0] * plane_normal.x,
                sp.normal[0] * plane_normal.y,
                sp.normal[1],
            );
            let q = p.at_inset(sp.inset_m, face_inset);
            let normal = curvature.bend_direction(q.x, normal).normalize();
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
            for j in base..base + facet.points.len() - 1 {
                // Rim i → i + 1 runs counter-clockwise and the section runs top → bottom, so
                // (a_j, a_j+1, b_j+1) faces outward.
                mesh.triangle([a[j], a[j + 1], b[j + 1]], facet.part);
                mesh.triangle([a[j], b[j + 1], b[j]], facet.part);
            }
            base += facet.points.len();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::panel::profile::{Arris, Seamed};

    /// Checks the invariants every section keeps and returns its points.
    pub(in crate::geometry::panel) fn check_section(s: &EdgeSection, t: f64) -> Vec<SectionPoint> {
        let pts: Vec<SectionPoint> = s.facets.iter().flat_map(|f| f.points.clone()).collect();
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        assert_eq!((first.height_m, last.height_m), (t, 0.0));
        assert_eq!(
            (first.inset_m, last.inset_m),
            (s.face_inset_m, s.face_inset_m)
        );
        // Consecutive facets join.
        for w in s.facets.windows(2) {
            let (a, b) = (w[0].points.last().unwrap(), w[1].points[0]);
            assert_eq!((a.inset_m, a.height_m), (b.inset_m, b.height_m));
        }
        for facet in &s.facets {
            assert!(facet.points.len() >= 2);
            for w in facet.points.windows(2) {
                // The normal is perpendicular to the facet step and points out (to smaller inset).
                let step = [w[1].inset_m - w[0].inset_m, w[1].height_m - w[0].height_m];
                let len = step[0].hypot(step[1]);
                assert!(len > 0.0);
                let out = [-step[1] / len, -step[0] / len];
                for n in [w[0].normal, w[1].normal] {
                    assert!(n[0] * out[0] + n[1] * out[1] > 0.98, "{n:?} vs {out:?}");
                }
            }
        }
        for p in &pts {
            assert!((p.normal[0].hypot(p.normal[1]) - 1.0).abs() < 1e-15);
            assert!(p.inset_m >= 0.0 && (0.0..=t).contains(&p.height_m));
        }
        // The outermost point is the outline.
        assert_eq!(pts.iter().map(|p| p.inset_m).fold(f64::MAX, f64::min), 0.0);
        pts
    }

    #[test]
    fn sections_run_top_to_bottom_with_outward_normals() {
        let t = 0.004;
        let flat = EdgeSection::new(&EdgeProfile::FlatGround, t, 0.005).unwrap();
        check_section(&flat, t);
        assert_eq!(flat.face_inset_m(), 0.0);
        let arrissed =
            EdgeSection::new(&EdgeProfile::Arrissed { bevel_m: 0.001 }, t, 0.005).unwrap();
        check_section(&arrissed, t);
        assert_eq!((arrissed.facets.len(), arrissed.face_inset_m()), (3, 0.001));
        let pencil = EdgeSection::new(&EdgeProfile::Pencil { radius_m: None }, t, 0.005).unwrap();
        check_section(&pencil, t);
        assert_eq!(
            (pencil.facets[0].points.len(), pencil.face_inset_m()),
            (19, 0.002)
        );
        let seamed = EdgeSection::new(&EdgeProfile::default(), t, 0.005).unwrap();
        check_section(&seamed, t);
        assert_eq!((seamed.facets.len(), seamed.border_inset_m()), (3, 0.8e-3));
    }

    #[test]
    fn arrissed_is_the_seamed_section_with_45_degree_arrisses() {
        let t = 0.004;
        let a = EdgeSection::new(&EdgeProfile::Arrissed { bevel_m: 0.001 }, t, 0.005).unwrap();
        let arris = Arris {
            width_m: 0.001,
            angle_rad: std::f64::consts::FRAC_PI_4,
        };
        let s = EdgeProfile::Seamed(Seamed {
            top: arris,
            bottom: arris,
            fillet_radius_m: 0.0,
        });
        let s = EdgeSection::new(&s, t, 0.005).unwrap();
        assert_eq!(a.facets, s.facets);
        let p: Vec<_> = a
            .facets
            .iter()
            .flat_map(|f| f.points.iter().map(|p| [p.inset_m, p.height_m]))
            .collect();
        assert_eq!(
            p,
            [
                [0.001, t],
                [0.0, t - 0.001],
                [0.0, t - 0.001],
                [0.0, 0.001],
                [0.0, 0.001],
                [0.001, 0.0]
            ]
        );
    }

    #[test]
    fn unequal_insets_get_a_face_strip_tagged_as_the_face() {
        let t = 0.004;
        // The default top arris, none at the bottom: the faces share the larger inset, the
        // top's, and the bottom face gets a strip from there out to the outline.
        let s = Seamed {
            bottom: Arris {
                width_m: 0.0,
                ..Arris::default()
            },
            ..Seamed::default()
        };
        let s = EdgeSection::new(&EdgeProfile::Seamed(s), t, 0.005).unwrap();
        let pts = check_section(&s, t);
        assert_eq!((s.face_inset_m(), s.border_inset_m()), (0.8e-3, 0.8e-3));
        let last = s.facets.last().unwrap();
        assert_eq!(last.part, SurfacePart::BottomFace);
        assert_eq!(last.points[0].normal, [0.0, -1.0]);
        assert_eq!(pts.len(), 6);
        // And the other way round: the top face gets the strip, the border stays at the top
        // face's true boundary (the outline itself, a sharp top corner).
        let s = Seamed {
            top: Arris {
                width_m: 0.0,
                ..Arris::default()
            },
            ..Seamed::default()
        };
        let s = EdgeSection::new(&EdgeProfile::Seamed(s), t, 0.005).unwrap();
        check_section(&s, t);
        assert_eq!((s.face_inset_m(), s.border_inset_m()), (0.8e-3, 0.0));
        assert_eq!(s.facets[0].part, SurfacePart::TopFace);
        assert_eq!(s.facets[0].points[1].inset_m, 0.0);
    }

    #[test]
    fn finish_corners_carry_the_normals_on_both_sides() {
        let s = EdgeSection::new(&EdgeProfile::default(), 0.004, 0.005).unwrap();
        let c = s.finish_corners();
        assert_eq!(c.len(), 4);
        assert_eq!(c[0].before, [0.0, 1.0]);
        assert_eq!(c[3].after, [0.0, -1.0]);
        assert_eq!(c[1].after, [1.0, 0.0]);
        assert_eq!(c[1].before, c[0].after);
        let r = std::f64::consts::FRAC_1_SQRT_2;
        assert!((c[0].after[0] - r).abs() < 1e-15 && (c[0].after[1] - r).abs() < 1e-15);
    }
}
