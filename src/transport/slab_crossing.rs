//! Rays crossing a flat glass slab from face to face, or leaving it on a side where nothing
//! is, answered without a BVH query.
//!
//! Inside a flat pane light goes from one face to the other: the laser refracted in at the top
//! face, light from the table refracted in at the bottom face, every camera connection through
//! the pane. On edge_study_bare at 45° these crossings were 325 k of a pose's 1.25 M ray
//! queries (26 %; counted with an instrumented build, benches/README.md, 2026-12-07 evening).
//! Their closest hit is where the ray meets the far face's plane, provided nothing else lies
//! along the way: [`SlabCrossings::closest_hit`] computes that point, finds the far-face
//! triangle under it in a grid over the pane, and completes the hit with
//! `SceneAccel::hit_on_triangle`, which gives exactly the hit a BVH query on that triangle
//! gives. A ray leaving a face outward on a side beyond whose plane the scene has nothing (the
//! top face of a pane on a table, which every camera connection through it leaves by) meets
//! nothing. So wherever it answers, the answer is the query's, bit for bit; where it cannot
//! be sure, it answers nothing and the caller queries the BVH.
//!
//! It answers a crossing only when all of these hold, which together leave the BVH no other
//! choice:
//! - the ray leaves a face triangle of a pane whose face triangles all lie on two parallel
//!   planes (within [`LEVEL_TOLERANCE_M`]) and each see the other plane as their far face
//!   (`scene::slab_faces`), heading into the glass at least [`MIN_COS`] from the face plane:
//!   then the f32 test puts the leaving face's other triangles within
//!   f32 rounding / [`MIN_COS`] ≪ `NEAR_HIT_M` of the origin, where the query re-tests them in
//!   f64 and drops them (they lie within [`LEVEL_TOLERANCE_M`] / [`MIN_COS`] = 10⁻⁹ m <
//!   `SELF_HIT_T_MIN_M` of it);
//! - the far point lies well inside exactly one far-face triangle (`hit_on_triangle`'s
//!   barycentric margin, where the f32 test cannot give it to a neighbour);
//! - no other triangle of the scene (the pane's edge finish and arrises, any other object)
//!   comes within the clearance of the segment: an obstacle is a triangle that reaches
//!   between the two planes widened by the clearance, and the segment's projection onto the
//!   face plane must keep the clearance from the projection of every obstacle. The clearance
//!   is 64 f32 ulps of the scene's largest coordinate (4 µm for a scene within 0.5 m of the
//!   base frame's origin; the shipped scenes keep 10 µm between objects), far above the f32
//!   rounding of the distances the query compares, so no obstacle can come before the far
//!   face in the query either.
//!
//! A side is open when no vertex of any other triangle lies more than [`LEVEL_TOLERANCE_M`]
//! beyond its plane: a ray leaving it at least [`MIN_COS`] from the plane could meet such a
//! triangle only within 10⁻⁹ m, where the query drops it too.
//!
//! Measured (benches/README.md, 2026-12-07 evening): 321 k of the 325 k crossings answered
//! per pose; the instructions of a query fall to about half, so a profile gains a few per cent.

use nalgebra::{Point3, Vector3};

use super::scene::SlabFace;
use crate::geometry::accel::{Hit, SceneAccel};
use crate::geometry::mesh::SurfacePart;
use crate::optics::lambert::orthonormal_basis;

/// Least |cos| between a crossing ray and the face normal (about 84° from the normal): rays
/// refracted into glass of n = 1.5 stay within 42° of it (|cos| ≥ 0.74); steeper-than-grazing
/// rays (from the rough edge) go to the BVH.
const MIN_COS: f64 = 0.1;

/// How far (m, along the normal) a face triangle's vertices may lie from their face's plane:
/// f64 rounding of the object's pose moves them by ~1e-16 m.
const LEVEL_TOLERANCE_M: f64 = 1e-10;

/// Cells of the lookup grid along the pane's longer side.
const GRID_CELLS: f64 = 64.0;

/// The clearance in f32 units of the scene's largest coordinate (see the module documentation).
const CLEARANCE_ULPS: f64 = 64.0;

/// The grids of the scene's flat panes, and which triangles are their faces.
pub struct SlabCrossings {
    /// Per triangle (as in `Hit::triangle`): its pane (index into `panes`) and face side (0 or
    /// 1), for a face of a pane with a grid.
    faces: Vec<Option<(u32, u8)>>,
    panes: Vec<PaneGrid>,
}

/// A flat pane's two face planes and its lookup grid over the face plane.
struct PaneGrid {
    /// Unit normal: outward on side 0, inward on side 1.
    normal: Vector3<f64>,
    /// normal · x on the plane of side 0 and of side 1.
    levels: [f64; 2],
    /// Axes of the face plane (with `normal`, an orthonormal frame).
    axes: [Vector3<f64>; 2],
    /// The grid's lower corner in plane coordinates, its cell size and its cells per axis.
    min: [f64; 2],
    cell: f64,
    dims: [usize; 2],
    /// Per cell, three lists in `entries`: the face triangles of side 0, of side 1 (indices
    /// into `faces`, whose projection's box meets the cell), and the obstacles (indices into
    /// `obstacles`, box widened by the clearance). `starts[3·cell + k]..starts[3·cell + k + 1]`.
    starts: Vec<u32>,
    entries: Vec<u32>,
    /// The face triangles (as in `Hit::triangle`) and their projections.
    faces: Vec<(u32, [[f64; 2]; 3])>,
    obstacles: Vec<Obstacle>,
    /// The clearance (m).
    clearance: f64,
    /// Per side: whether nothing of the scene lies beyond its plane (no vertex of another
    /// triangle more than [`LEVEL_TOLERANCE_M`] outside it), so a ray leaving that face
    /// outward meets nothing.
    open: [bool; 2],
}

/// An obstacle's projection onto the face plane: its corners and their box.
#[derive(Clone, Copy, Debug)]
struct Obstacle {
    corners: [[f64; 2]; 3],
    lo: [f64; 2],
    hi: [f64; 2],
}

impl SlabCrossings {
    /// The grids of every flat pane of the scene: the glass objects whose non-edge triangles
    /// are all faces of a flat slab (`slab_faces`, indexed like the triangles) on two planes.
    pub fn new(accel: &SceneAccel, slab_faces: &[Option<SlabFace>]) -> SlabCrossings {
        let n_tri = accel.triangle_count() as u32;
        let largest = (0..n_tri)
            .flat_map(|i| accel.triangle(i).vertices)
            .flat_map(|v| [v.x.abs(), v.y.abs(), v.z.abs()])
            .fold(0.0, f64::max);
        let clearance = CLEARANCE_ULPS * largest * f64::from(f32::EPSILON);
        // Face triangles per object; an object with a face that is not a slab's is left out.
        let objects = (0..n_tri)
            .map(|i| accel.triangle(i).object as usize + 1)
            .max()
            .unwrap_or(0);
        let mut faces_of: Vec<Option<Vec<u32>>> = vec![Some(Vec::new()); objects];
        for i in 0..n_tri {
            let t = accel.triangle(i);
            let k = t.object as usize;
            if t.part == SurfacePart::Edge {
                continue;
            }
            match (slab_faces[i as usize], &mut faces_of[k]) {
                (Some(_), Some(list)) => list.push(i),
                (None, list) => *list = None,
                (Some(_), None) => {}
            }
        }
        let mut faces = vec![None; n_tri as usize];
        let mut panes = Vec::new();
        for list in faces_of {
            let Some(list) = list.filter(|l| !l.is_empty()) else {
                continue;
            };
            let Some((grid, sides)) = PaneGrid::new(accel, &list, clearance) else {
                continue;
            };
            for (&i, side) in list.iter().zip(sides) {
                faces[i as usize] = Some((panes.len() as u32, side));
            }
            panes.push(grid);
        }
        SlabCrossings { faces, panes }
    }

    /// The closest hit of the ray `origin + t·dir` (unit `dir`, t in (0, `t_max`]) leaving
    /// triangle `leaving` at `origin`, where it is certain: `Some` of what
    /// `SceneAccel::closest_hit_leaving` returns, bit for bit, for a ray crossing a flat pane
    /// to its far face with nothing else in the way (the far face's hit) or leaving it on an
    /// open side (nothing). `None`: not certain; query the BVH.
    pub fn closest_hit(
        &self,
        accel: &SceneAccel,
        leaving: u32,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        t_max: f64,
    ) -> Option<Option<Hit>> {
        let (pane, side) = (*self.faces.get(leaving as usize)?)?;
        let g = &self.panes[pane as usize];
        let nd = g.normal.dot(dir);
        // Into the glass: against side 0's outward normal, along side 1's inward one.
        let inward = if side == 0 { -nd } else { nd };
        if inward <= -MIN_COS && g.open[side as usize] {
            return Some(None);
        }
        if inward < MIN_COS {
            return None;
        }
        let t = (g.levels[1 - side as usize] - g.normal.dot(&origin.coords)) / nd;
        if !(t > 0.0 && t <= t_max) {
            return None;
        }
        let a = g.plane_point(origin);
        let b = g.plane_point(&(origin + dir * t));
        let lo = [a[0].min(b[0]), a[1].min(b[1])];
        let hi = [a[0].max(b[0]), a[1].max(b[1])];
        let ([x0, y0], [x1, y1]) = (g.cell_of(lo)?, g.cell_of(hi)?);
        for y in y0..=y1 {
            for x in x0..=x1 {
                for &o in g.list(y * g.dims[0] + x, 2) {
                    if g.obstacles[o as usize].near_segment(a, b, lo, hi, g.clearance) {
                        return None;
                    }
                }
            }
        }
        let [bx, by] = g.cell_of(b)?;
        let mut found = None;
        for &j in g.list(by * g.dims[0] + bx, 1 - side as usize) {
            let (tri, corners) = &g.faces[j as usize];
            // A cheap test first: the far point in (or within a hair of) the projection.
            if !contains(corners, b, g.cell * 1e-6) {
                continue;
            }
            if let Some(hit) = accel.hit_on_triangle(*tri, origin, dir, t_max) {
                if found.is_some() {
                    // Overlapping face triangles: let the query's tie rule decide.
                    return None;
                }
                found = Some(hit);
            }
        }
        found.map(Some)
    }
}

impl PaneGrid {
    /// The grid of object `object`'s face triangles `faces`, and each one's side; `None` if
    /// they do not lie on two parallel planes.
    fn new(accel: &SceneAccel, faces: &[u32], clearance: f64) -> Option<(PaneGrid, Vec<u8>)> {
        let outward = |i: u32| {
            let [a, b, c] = accel.triangle(i).vertices;
            (b - a).cross(&(c - a)).try_normalize(0.0)
        };
        let normal = outward(faces[0])?;
        let mut levels: [Option<(f64, f64)>; 2] = [None; 2];
        let mut sides = Vec::with_capacity(faces.len());
        for &i in faces {
            let side = usize::from(outward(i)?.dot(&normal) < 0.0);
            for v in accel.triangle(i).vertices {
                let h = normal.dot(&v.coords);
                let range = levels[side].get_or_insert((h, h));
                *range = (range.0.min(h), range.1.max(h));
            }
            sides.push(side as u8);
        }
        let [Some(l0), Some(l1)] = levels else {
            return None;
        };
        if l0.1 - l0.0 > LEVEL_TOLERANCE_M || l1.1 - l1.0 > LEVEL_TOLERANCE_M {
            return None;
        }
        // Side 0's outward normal points away from side 1.
        let levels = [(l0.0 + l0.1) / 2.0, (l1.0 + l1.1) / 2.0];
        if levels[0] <= levels[1] {
            return None;
        }
        let (u, v) = orthonormal_basis(&normal);
        let mut g = PaneGrid {
            normal,
            levels,
            axes: [u, v],
            min: [0.0; 2],
            cell: 0.0,
            dims: [0; 2],
            starts: Vec::new(),
            entries: Vec::new(),
            faces: Vec::new(),
            obstacles: Vec::new(),
            clearance,
            open: [true; 2],
        };
        let axes = g.axes;
        let projected = |i: u32| {
            (accel.triangle(i).vertices).map(|p| [axes[0].dot(&p.coords), axes[1].dot(&p.coords)])
        };
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &i in faces {
            for p in projected(i) {
                for a in 0..2 {
                    (lo[a], hi[a]) = (lo[a].min(p[a]), hi[a].max(p[a]));
                }
            }
        }
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        if !(extent > 0.0 && extent.is_finite()) {
            return None;
        }
        g.cell = extent / GRID_CELLS;
        g.min = lo;
        g.dims = [0, 1].map(|a| ((hi[a] - lo[a]) / g.cell).floor() as usize + 1);
        // Obstacles: every other triangle that reaches between the planes, widened.
        let (bottom, top) = (levels[1] - clearance, levels[0] + clearance);
        let is_face: std::collections::HashSet<u32> = faces.iter().copied().collect();
        for i in 0..accel.triangle_count() as u32 {
            if is_face.contains(&i) {
                continue;
            }
            let t = accel.triangle(i);
            let heights = t.vertices.map(|p| normal.dot(&p.coords));
            let (h0, h1) = (
                heights.iter().copied().fold(f64::INFINITY, f64::min),
                heights.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            );
            g.open[0] &= h1 <= levels[0] + LEVEL_TOLERANCE_M;
            g.open[1] &= h0 >= levels[1] - LEVEL_TOLERANCE_M;
            if h1 < bottom || h0 > top {
                continue;
            }
            let corners = projected(i);
            let olo = [0, 1].map(|a| corners.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min));
            let ohi = [0, 1].map(|a| {
                corners
                    .iter()
                    .map(|p| p[a])
                    .fold(f64::NEG_INFINITY, f64::max)
            });
            let grid_hi = [0, 1].map(|a| g.min[a] + g.dims[a] as f64 * g.cell);
            if (0..2).any(|a| ohi[a] + clearance < g.min[a] || olo[a] - clearance > grid_hi[a]) {
                continue;
            }
            g.obstacles.push(Obstacle {
                corners,
                lo: olo,
                hi: ohi,
            });
        }
        // The three lists per cell: boxes widened by a hair (face triangles, so that a point on
        // a cell's border finds the triangle from either side) or by the clearance (obstacles).
        let cells = g.dims[0] * g.dims[1];
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); 3 * cells];
        let hair = g.cell * 1e-6;
        let mut add = |g: &PaneGrid, lo: [f64; 2], hi: [f64; 2], widen: f64, k: usize, id: u32| {
            let clamp = |p: [f64; 2]| {
                [0, 1].map(|a| {
                    (((p[a] - g.min[a]) / g.cell).floor().max(0.0) as usize).min(g.dims[a] - 1)
                })
            };
            let c0 = clamp([lo[0] - widen, lo[1] - widen]);
            let c1 = clamp([hi[0] + widen, hi[1] + widen]);
            for y in c0[1]..=c1[1] {
                for x in c0[0]..=c1[0] {
                    lists[3 * (y * g.dims[0] + x) + k].push(id);
                }
            }
        };
        g.faces = faces.iter().map(|&i| (i, projected(i))).collect();
        for (j, (&i, &side)) in faces.iter().zip(&sides).enumerate() {
            let c = projected(i);
            let lo = [0, 1].map(|a| c.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min));
            let hi = [0, 1].map(|a| c.iter().map(|p| p[a]).fold(f64::NEG_INFINITY, f64::max));
            add(&g, lo, hi, hair, side as usize, j as u32);
        }
        for (j, o) in g.obstacles.iter().enumerate() {
            add(&g, o.lo, o.hi, clearance, 2, j as u32);
        }
        g.starts.push(0);
        for l in &lists {
            g.entries.extend_from_slice(l);
            g.starts.push(g.entries.len() as u32);
        }
        Some((g, sides))
    }

    /// A point's coordinates in the face plane.
    #[inline]
    fn plane_point(&self, p: &Point3<f64>) -> [f64; 2] {
        [self.axes[0].dot(&p.coords), self.axes[1].dot(&p.coords)]
    }

    /// The cell of plane point `p`, or `None` outside the grid.
    #[inline]
    fn cell_of(&self, p: [f64; 2]) -> Option<[usize; 2]> {
        let mut c = [0; 2];
        for a in 0..2 {
            let x = (p[a] - self.min[a]) / self.cell;
            if !(x >= 0.0 && x < self.dims[a] as f64) {
                return None;
            }
            c[a] = x as usize;
        }
        Some(c)
    }

    /// List `k` of cell `cell` (see `starts`).
    #[inline]
    fn list(&self, cell: usize, k: usize) -> &[u32] {
        let i = 3 * cell + k;
        &self.entries[self.starts[i] as usize..self.starts[i + 1] as usize]
    }
}

impl Obstacle {
    /// Whether the segment a–b (box lo–hi) comes within `clearance` of the obstacle's
    /// projection (conservative: `true` when unsure).
    fn near_segment(
        &self,
        a: [f64; 2],
        b: [f64; 2],
        lo: [f64; 2],
        hi: [f64; 2],
        clearance: f64,
    ) -> bool {
        if (0..2).any(|k| self.hi[k] + clearance < lo[k] || self.lo[k] - clearance > hi[k]) {
            return false;
        }
        let [p, q, r] = self.corners;
        // The segment's ends inside the projected triangle (either winding).
        let inside = |x: [f64; 2]| {
            let s = [cross(p, q, x), cross(q, r, x), cross(r, p, x)];
            s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
        };
        if inside(a) || inside(b) {
            return true;
        }
        let edges = [(p, q), (q, r), (r, p)];
        if edges.iter().any(|&(e0, e1)| segments_cross(a, b, e0, e1)) {
            return true;
        }
        let c2 = clearance * clearance;
        edges.iter().any(|&(e0, e1)| {
            point_segment_dist2(a, e0, e1) < c2
                || point_segment_dist2(b, e0, e1) < c2
                || point_segment_dist2(e0, a, b) < c2
        })
    }
}

/// Whether the triangle `corners` (either winding) contains `p` or has it within `hair` of
/// an edge (a conservative test: `SceneAccel::hit_on_triangle` decides).
fn contains(corners: &[[f64; 2]; 3], p: [f64; 2], hair: f64) -> bool {
    let [a, b, c] = *corners;
    let area = cross(a, b, c);
    if area == 0.0 {
        return false;
    }
    // Signed distances from the edges, positive inside.
    let s = area.signum();
    [(a, b), (b, c), (c, a)].iter().all(|&(e0, e1)| {
        let len = ((e1[0] - e0[0]).powi(2) + (e1[1] - e0[1]).powi(2)).sqrt();
        s * cross(e0, e1, p) >= -hair * len
    })
}

/// (b − a) × (c − a).
fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether segments a–b and c–d cross (touching counts).
fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (d1, d2) = (cross(a, b, c), cross(a, b, d));
    let (d3, d4) = (cross(c, d, a), cross(c, d, b));
    (d1 * d2 <= 0.0) && (d3 * d4 <= 0.0)
}

/// Squared distance from p to the segment a–b.
fn point_segment_dist2(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let ap = [p[0] - a[0], p[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let s = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = [ap[0] - s * ab[0], ap[1] - s * ab[1]];
    d[0] * d[0] + d[1] * d[1]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::TraceScene;
    use std::path::Path;

    fn scene_of(text: &str) -> TraceScene {
        let world = crate::scene::load_str(Path::new("test.toml"), text).unwrap();
        TraceScene::new(&world).unwrap()
    }

    fn edge_study_text() -> String {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        std::fs::read_to_string(root.join("scenes/edge_study_bare.toml")).unwrap()
    }

    /// Spherical Fibonacci directions (golden-angle spiral).
    fn directions(n: usize) -> impl Iterator<Item = Vector3<f64>> {
        (0..n).map(move |k| {
            let z = 1.0 - (2 * k + 1) as f64 / n as f64;
            let phi = k as f64 * 2.399_963_229_728_653;
            let r = (1.0 - z * z).sqrt();
            Vector3::new(r * phi.cos(), r * phi.sin(), z)
        })
    }

    /// Every answer against the BVH query, from points spread over every face triangle of the
    /// scene's glass in 400 directions; returns (answered, asked) for rays into the glass
    /// at least 60° from grazing and for rays leaving a face outward.
    fn check_against_the_bvh(scene: &TraceScene) -> ([usize; 2], [usize; 2]) {
        let (mut inward, mut outward) = ([0; 2], [0; 2]);
        for i in 0..scene.accel.triangle_count() as u32 {
            let t = *scene.accel.triangle(i);
            if scene.glass(t.material).is_none() || t.part == SurfacePart::Edge {
                continue;
            }
            let [a, b, c] = t.vertices;
            let ng = (b - a).cross(&(c - a)).normalize();
            for [u, v] in [
                [1.0 / 3.0, 1.0 / 3.0],
                [0.02, 0.03],
                [0.9, 0.05],
                [0.1, 0.85],
            ] {
                let p = a + (b - a) * u + (c - a) * v;
                for w in directions(400) {
                    let answer = scene
                        .slab_crossings
                        .closest_hit(&scene.accel, i, &p, &w, 10.0);
                    let bvh = scene.accel.closest_hit_leaving(&p, &w, i, 10.0);
                    if let Some(answer) = answer {
                        assert_eq!(answer, bvh, "triangle {i}, point {p}, direction {w}");
                    }
                    let cos = w.dot(&ng);
                    let counts = if cos < -0.5 {
                        &mut inward
                    } else if cos > 0.5 {
                        &mut outward
                    } else {
                        continue;
                    };
                    counts[0] += usize::from(answer.is_some());
                    counts[1] += 1;
                }
            }
        }
        (inward, outward)
    }

    #[test]
    fn a_flat_pane_crossed_face_to_face_gives_the_bvh_hit_and_nothing_above_it() {
        let scene = scene_of(&edge_study_text());
        let (inward, outward) = check_against_the_bvh(&scene);
        // Most rays into the pane cross it clear of the edge; those from the rim's triangles
        // near the edge do not, nor do rays out of the bottom face (the table is 10 µm below).
        assert!(
            inward[0] * 10 > inward[1] * 6 && inward[0] < inward[1],
            "{inward:?}"
        );
        // Out of the top face: nothing above the pane, so always answered (none); out of the
        // bottom face: never.
        assert_eq!(2 * outward[0], outward[1], "{outward:?}");
    }

    #[test]
    fn something_inside_the_pane_is_never_skipped() {
        // A 2 × 2 × 1 mm opaque inclusion in the middle of the 4 mm pane, 150 mm in from its
        // edge, and a pane of tape-like foil lying on its top face: the first is in the way of
        // crossings near it, the second closes the open side.
        let text = edge_study_text()
            + r#"
[[objects]]
name = "inclusion"
material = "grey"
box = { size_mm = [2, 2, 1] }
pose = { translation_mm = [0, 0, 2.01] }

[[objects]]
name = "foil"
material = "grey"
box = { size_mm = [10, 10, 0.1] }
pose = { translation_mm = [50, 50, 4.07] }
"#;
        let scene = scene_of(&text);
        let (inward, outward) = check_against_the_bvh(&scene);
        assert!(inward[0] * 10 > inward[1] * 6, "{inward:?}");
        assert_eq!(outward[0], 0, "{outward:?}");
        // Straight up through the inclusion from the bottom face: its hit, not the top face.
        let origin = Point3::new(0.6e-3, 0.3e-3, 0.01e-3);
        let up = Vector3::z();
        let bottom = (0..scene.accel.triangle_count() as u32)
            .find(|&i| {
                let t = scene.accel.triangle(i);
                t.part == SurfacePart::BottomFace
                    && scene
                        .accel
                        .hit_on_triangle(i, &(origin - up * 1e-3), &up, 1.0)
                        .is_some()
            })
            .expect("the bottom face under the inclusion");
        let hit = scene
            .closest_hit_leaving(&origin, &up, bottom, 1.0)
            .unwrap();
        assert_eq!(scene.accel.triangle(hit.triangle).object, 2, "{hit:?}");
        assert!((hit.t - 1.5e-3).abs() < 1e-9, "{hit:?}");
    }
}
