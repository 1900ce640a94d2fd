//! Procedural glass panel: outline, thickness, flat or cylindrically curved, with an edge
//! finish (seamed by default; flat ground, arrissed, pencil, or any polyline section). Yields
//! the triangle mesh and the border curve, and the objects fitted to a panel's true section:
//! the tape and the cover of the paper's edge experiment.
//!
//! Model frame: the outline is centred on the origin in the x–y plane; the bottom face is at
//! z = 0 and the top face at z = thickness (at x = 0 for a curved panel). A cylindrical panel
//! bends along x around an axis parallel to y at (0, ·, −R): a flat point (u, v, h) with
//! height h ∈ [0, t] above the bottom face maps to ((R + h)·sin(u/R), v, (R + h)·cos(u/R) − R),
//! which keeps lengths on the bottom face (an isometric bend) and makes the top face convex.
//!
//! Build steps, one submodule each: `contour` samples the outline (arcs at most 10° and
//! `tessellation_m` per segment, straight edges resampled to `tessellation_m`, on a flat
//! panel to at least `FLAT_FACE_GRID_M`) with outward normals and miters,
//! after `polygon` has checked a user polygon; `edge` gives the edge cross-section (from
//! `profile`'s kinds by `seamed`, `fillet`, `pencil` and `custom`), whose top and bottom face
//! boundaries may sit at different insets: both faces are the one polygon at the larger inset
//! d₀, and the face with the smaller one gets a face strip out to its boundary; `face` cuts
//! that polygon with a square grid, inserting the grid crossings into the rim, and
//! `triangulate`s the pieces; `edge` sweeps the section along the refined rim; `bend` maps
//! everything through the cylinder. `sheet` sweeps open or closed flat-shaded profiles along
//! the same rim for `tape` and `cover`. Units are metres throughout.
//!
//! Invariants of the result: the mesh is closed and watertight by position (every edge, with
//! vertices compared exactly, is shared by two triangles; vertices are duplicated only where
//! normals differ: face/edge seams, facet junctions, sharp corners); triangles wind outward;
//! normals are unit, smooth within an arc and flat within a flat facet (faces: the bent ±z;
//! edge: the section normal rotated with the bend). The border curve runs through mesh
//! vertices: the top face's true boundary (top of the top arris, a fillet's tangent point with
//! the face, a pencil arc's meeting point with the face).

mod bend;
mod contour;
mod cover;
mod custom;
mod edge;
mod face;
mod fillet;
mod pencil;
mod polygon;
mod profile;
mod seamed;
mod sheet;
mod tape;
#[cfg(test)]
mod tests;
mod triangulate;

use nalgebra::{Point3, Vector3};

use super::border::{BorderCurve, BorderVertex};
use super::mesh::{Mesh, SurfacePart};
use contour::RimPoint;
pub use cover::{build_cover, CoverSpec};
use edge::EdgeSection;
use face::FacePatch;
pub use profile::{
    Arris, EdgeProfile, Seamed, DEFAULT_ARRIS_ANGLE_RAD, DEFAULT_ARRIS_WIDTH_M,
    MAX_ARRIS_ANGLE_RAD, MIN_ARRIS_ANGLE_RAD,
};
pub use tape::{build_tape, TapeSpec};

/// The panel outline in the flat (unbent) x–y plane.
#[derive(Clone, Debug, PartialEq)]
pub enum Outline {
    /// A rectangle centred on the origin, with rounded corners.
    Rectangle {
        /// Extent along x (m), > 0.
        width_m: f64,
        /// Extent along y (m), > 0.
        height_m: f64,
        /// Corner radius (m), 0 ≤ r ≤ min(width, height)/2.
        corner_radius_m: f64,
    },
    /// A simple polygon (counter-clockwise or clockwise; normalised internally) whose corners
    /// are rounded with `corner_radius_m`.
    Polygon {
        /// Vertices (m), at least three, no self-intersections.
        vertices_m: Vec<[f64; 2]>,
        /// Corner radius (m), ≥ 0.
        corner_radius_m: f64,
    },
}

/// How the panel is bent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Curvature {
    /// A flat panel.
    Flat,
    /// Bent along x around an axis parallel to y, bottom-face radius `radius_m` (> 0).
    Cylindrical {
        /// Radius of the bottom face (m).
        radius_m: f64,
    },
}

/// Everything needed to build a panel.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelSpec {
    /// Outline in the flat x–y plane.
    pub outline: Outline,
    /// Glass thickness (m), > 0.
    pub thickness_m: f64,
    /// Flat or curved.
    pub curvature: Curvature,
    /// Edge finish cross-section.
    pub edge: EdgeProfile,
    /// Cell size of the square grid that tessellates the faces (face triangles span at most
    /// one cell in x and in y, so their edges are at most √2 times this) and the largest
    /// border-curve segment (m), > 0. Sets the chord error of a curved panel: L²/(8R). On a
    /// flat panel, planar and straight however finely cut, the grid and the straight runs'
    /// segments are at least [`FLAT_FACE_GRID_M`]; arcs keep this length.
    pub tessellation_m: f64,
}

/// A built panel in its model frame.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Closed, watertight triangle mesh with smooth normals and part tags
    /// (`TopFace`, `BottomFace`, `Edge`).
    pub mesh: Mesh,
    /// The border edge curve: where the top face meets the edge finish.
    pub border: BorderCurve,
}

/// Why a panel specification cannot be built. The message names the offending quantity;
/// the scene loader adds file, line and field.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PanelError {
    /// A parameter is out of its range.
    #[error("{field} {message}")]
    InvalidParameter {
        /// The spec field (scene-file name, e.g. `corner_radius_mm`, `seamed.top.angle_deg`).
        field: &'static str,
        /// What was expected and what was given.
        message: String,
    },
    /// One point of a list is out of its range or inconsistent with its neighbours.
    #[error("{field}[{index}] {message}")]
    InvalidPoint {
        /// The spec field of the list (scene-file name, e.g. `section.points_mm`).
        field: &'static str,
        /// Index of the point, from 0.
        index: usize,
        /// What was expected and what was given.
        message: String,
    },
}

/// Most grid cells a face may be cut into: 2²⁰, about 4 million face triangles and 200 MB of
/// mesh; the 550 mm × 420 mm default window reaches it at a tessellation of 0.45 mm.
const MAX_CELLS: f64 = 1_048_576.0;

/// Least grid cell and straight-run segment (m) of a flat panel. Its faces and straight edge
/// runs are planar and straight however finely they are cut, but their triangle count sets the
/// depth of the scene's BVH: edge_study_bare's 300 mm pane has 18,236 triangles cut at the
/// 5 mm default and 524 at 50 mm, and a glass profile of it takes 7 % less CPU time, its
/// profiles equal to 1 µm (issue 11; a coarser cut gained no more).
pub const FLAT_FACE_GRID_M: f64 = 0.05;

/// Builds the triangle mesh and the border curve of the panel `spec` describes, in its model
/// frame, after checking every parameter.
pub fn build_panel(spec: &PanelSpec) -> Result<Panel, PanelError> {
    let (section, patch) = prepare(spec)?;
    let t = spec.thickness_m;
    let mut mesh = MeshBuilder::default();
    add_faces(&mut mesh, &patch, t, &spec.curvature);
    edge::add_band(&mut mesh, &patch.rim, &section, &spec.curvature);
    let border = border_curve(&patch.rim, &section, t, &spec.curvature);
    Ok(Panel {
        mesh: mesh.finish(),
        border,
    })
}

/// Checks `spec` and builds what the panel and the objects fitted to it share: the edge
/// section and the face tessellation, whose rim (every grid crossing inserted) the edge band,
/// the border curve, the tape and the cover all run along.
fn prepare(spec: &PanelSpec) -> Result<(EdgeSection, FacePatch), PanelError> {
    let (t, s) = (spec.thickness_m, spec.tessellation_m);
    require_positive("thickness_mm", t)?;
    require_positive("tessellation_mm", s)?;
    let [w, h] = extent(&spec.outline);
    let cells = (w / s + 2.0) * (h / s + 2.0);
    if cells.is_finite() && cells > MAX_CELLS {
        let message = format!(
            "must be coarser: {s} m cuts the {w} m × {h} m outline into about {cells:.0} grid \
             cells per face, more than {MAX_CELLS}"
        );
        return Err(invalid("tessellation_mm", message));
    }
    let section = EdgeSection::new(&spec.edge, t, s)?;
    // A flat panel's straight runs and faces are straight and planar whatever their sampling.
    let straight = match spec.curvature {
        Curvature::Flat => s.max(FLAT_FACE_GRID_M),
        Curvature::Cylindrical { .. } => s,
    };
    let mut rim = contour::sample(&spec.outline, s, straight)?;
    if let Curvature::Cylindrical { radius_m } = spec.curvature {
        let half_width = rim.iter().map(|p| p.outline.x.abs()).fold(0.0, f64::max);
        check_bend_radius(radius_m, half_width)?;
    }
    let deepest = section.max_inset_m();
    check_corner_radius(&spec.outline, deepest, "corner_radius_mm")?;
    if deepest > section.face_inset_m() {
        // A groove deeper than the faces' inset must fit the outline too.
        contour::inset(&mut rim.clone(), deepest)
            .map_err(|message| invalid(section.inset_field(), message))?;
    }
    contour::inset(&mut rim, section.face_inset_m())
        .map_err(|message| invalid(section.inset_field(), message))?;
    let rim = contour::limit_face_segments(&rim, straight);
    let patch = face::tessellate(&rim, straight).ok_or_else(|| {
        invalid(
            "tessellation_mm",
            format!("{straight} m: could not place the face grid in general position"),
        )
    })?;
    Ok((section, patch))
}

/// A convex rounded corner tighter than an inset would turn inside out at that inset: the
/// corner radius must be 0 or larger than `inset_m`. `field` is reported.
fn check_corner_radius(
    outline: &Outline,
    inset_m: f64,
    field: &'static str,
) -> Result<(), PanelError> {
    let r = corner_radius(outline);
    if r > 0.0 && r <= inset_m {
        // The fields are `_mm` keys, so the message speaks millimetres (to the nanometre, so
        // that 0.0008 m reads 0.8 mm, not 0.8000000000000002).
        let mm = |m: f64| (m * 1e9).round() / 1e6;
        let (inset_mm, r_mm) = (mm(inset_m), mm(r));
        let message = if field == "corner_radius_mm" {
            format!("must be 0 or > the edge finish's deepest inset {inset_mm} mm, got {r_mm} mm")
        } else {
            format!(
                "reaches {inset_mm} mm in from the outline, past the outline's corner radius \
                 {r_mm} mm (the corners would turn inside out); use a smaller value, or a \
                 corner radius of 0 or > {inset_mm} mm"
            )
        };
        return Err(invalid(field, message));
    }
    Ok(())
}

/// Width and height (m) of the outline's bounding box; not finite for malformed input, which the
/// outline's own checks then report.
fn extent(outline: &Outline) -> [f64; 2] {
    match outline {
        Outline::Rectangle {
            width_m, height_m, ..
        } => [*width_m, *height_m],
        Outline::Polygon { vertices_m, .. } => {
            let span = |axis: usize| {
                let values = vertices_m.iter().map(|v| v[axis]);
                values.clone().fold(f64::NEG_INFINITY, f64::max)
                    - values.fold(f64::INFINITY, f64::min)
            };
            [span(0), span(1)]
        }
    }
}

fn corner_radius(outline: &Outline) -> f64 {
    match outline {
        Outline::Rectangle {
            corner_radius_m: r, ..
        }
        | Outline::Polygon {
            corner_radius_m: r, ..
        } => *r,
    }
}

/// The bend must stay under 90° either side of x = 0: R > max |x| / (π/2).
fn check_bend_radius(radius_m: f64, half_width_m: f64) -> Result<(), PanelError> {
    require_positive("radius_mm", radius_m)?;
    let min = half_width_m / std::f64::consts::FRAC_PI_2;
    if radius_m <= min {
        let message = format!(
            "must be > {min} m so that the bend stays under 90° (half-width {half_width_m} m), \
             got {radius_m} m"
        );
        return Err(invalid("radius_mm", message));
    }
    Ok(())
}

fn require_positive(field: &'static str, value: f64) -> Result<(), PanelError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(field, format!("must be > 0, got {value} m")))
    }
}

fn invalid(field: &'static str, message: String) -> PanelError {
    PanelError::InvalidParameter { field, message }
}

/// Top face at height t (normal: the bent +z) and bottom face at 0 (the bent −z, reversed
/// winding), both from the one face tessellation.
fn add_faces(mesh: &mut MeshBuilder, patch: &FacePatch, t: f64, curvature: &Curvature) {
    for (h, sign, part) in [
        (t, 1.0, SurfacePart::TopFace),
        (0.0, -1.0, SurfacePart::BottomFace),
    ] {
        let ids: Vec<u32> = patch
            .points
            .iter()
            .map(|q| {
                let normal = curvature.bend_direction(q.x, Vector3::new(0.0, 0.0, sign));
                mesh.vertex(curvature.bend_point(q.x, q.y, h), normal)
            })
            .collect();
        for &[a, b, c] in &patch.triangles {
            let [a, b, c] = [a, b, c].map(|k| ids[k as usize]);
            mesh.triangle(if sign > 0.0 { [a, b, c] } else { [a, c, b] }, part);
        }
    }
}

/// The border curve: the top face's true boundary (the section's first point) along the rim,
/// through the band's vertices there, with the rim's smooth tangent (at a sharp corner,
/// perpendicular to the bisecting normal) and the top face's normal, bent.
fn border_curve(
    rim: &[RimPoint],
    section: &EdgeSection,
    t: f64,
    curvature: &Curvature,
) -> BorderCurve {
    let vertices = rim
        .iter()
        .map(|p| {
            let n = (p.normal_in + p.normal_out).normalize();
            let q = p.at_inset(section.border_inset_m(), section.face_inset_m());
            let tangent = curvature
                .bend_direction(q.x, Vector3::new(-n.y, n.x, 0.0))
                .normalize();
            let surface_normal = curvature.bend_direction(q.x, Vector3::z()).normalize();
            BorderVertex {
                position: curvature.bend_point(q.x, q.y, t),
                tangent,
                surface_normal,
                outward: tangent.cross(&surface_normal),
            }
        })
        .collect();
    BorderCurve { vertices }
}

/// Collects vertices (with normals) and tagged triangles.
#[derive(Default)]
struct MeshBuilder {
    positions: Vec<Point3<f64>>,
    normals: Vec<Vector3<f64>>,
    triangles: Vec<[u32; 3]>,
    parts: Vec<SurfacePart>,
}

impl MeshBuilder {
    fn vertex(&mut self, position: Point3<f64>, normal: Vector3<f64>) -> u32 {
        debug_assert!((normal.norm() - 1.0).abs() < 1e-12);
        self.positions.push(position);
        self.normals.push(normal);
        (self.positions.len() - 1) as u32
    }

    fn triangle(&mut self, triangle: [u32; 3], part: SurfacePart) {
        self.triangles.push(triangle);
        self.parts.push(part);
    }

    fn finish(self) -> Mesh {
        Mesh {
            positions: self.positions,
            normals: Some(self.normals),
            triangles: self.triangles,
            parts: self.parts,
        }
    }
}
