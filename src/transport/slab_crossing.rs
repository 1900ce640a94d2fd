//! Rays crossing the layers around a flat pane, answered without a BVH query: the glass
//! between its faces, the air between a face and a parallel surface beyond it (the table
//! 10 µm under the pane), and the empty side (nothing above the pane).
//!
//! Most of a glass profile's ray queries are such crossings. On edge_study_bare at 45°, of a
//! pose's 1.25 M queries (counted with an instrumented build, benches/README.md, 2026-12-07
//! evening), 325 k went from face to face inside the pane (the laser refracted in at the top,
//! light from the table refracted in at the bottom, every camera connection through the pane),
//! and most of the others crossed the 10 µm of air between the pane and the table (the laser
//! on its way down, light from the table and the camera connections on their way up) or left
//! the top face into empty space. A crossing's closest hit is where the ray meets the far
//! plane, provided nothing else lies along the way: [`SlabCrossings::closest_hit`] computes
//! that point, finds the far plane's triangle under it in a grid over the pane, and completes
//! the hit with `SceneAccel::hit_on_triangle_within`, which gives exactly the hit a BVH query
//! on that triangle gives. A ray leaving a face into an empty side meets nothing. So wherever
//! it answers, the answer is the query's, bit for bit; where it cannot be sure, it answers
//! nothing and the caller queries the BVH.
//!
//! A layer is two parallel planes: a pane's two faces (its face triangles all on two planes
//! within [`LEVEL_TOLERANCE_M`], each seeing the other as its far face, `scene::slab_faces`),
//! or a face and the nearest plane beyond it, at least [`MIN_GAP_M`] away, of triangles
//! parallel to it (any object's). It answers a crossing only when all of these hold, which
//! together leave the BVH no other choice:
//! - the ray leaves a triangle of one plane toward the other at least [`MIN_COS`] from the
//!   planes: then the f32 test puts the leaving plane's other triangles within
//!   f32 rounding / [`MIN_COS`] ≪ `NEAR_HIT_M` of the origin, where the query re-tests them in
//!   f64 and drops them (they lie within [`LEVEL_TOLERANCE_M`] / [`MIN_COS`] = 10⁻⁹ m <
//!   `SELF_HIT_T_MIN_M` of it);
//! - the far point lies well inside exactly one triangle of the far plane (`hit_on_triangle`'s
//!   barycentric margin, where the f32 test cannot give it to a neighbour), at least
//!   [`MIN_HIT_T_M`] away (the query keeps near hits from `SELF_HIT_T_MIN_M` on);
//! - no other triangle of the scene (the pane's edge finish and arrises, the table's sides,
//!   any other object) comes within the clearance of the segment: an obstacle is a triangle
//!   that reaches between the two planes widened by the clearance, and the segment's
//!   projection onto the planes must keep the clearance from the projection of every
//!   obstacle. The clearance is 64 f32 ulps of the scene's largest coordinate (4 µm for a
//!   scene within 0.5 m of the base frame's origin; the shipped scenes keep 10 µm between
//!   objects), far above the f32 rounding of the distances the query compares, so no
//!   obstacle can come before the far plane in the query either.
//!
//! A side is empty when no vertex of any other triangle lies more than [`LEVEL_TOLERANCE_M`]
//! beyond the face's plane: a ray leaving the face at least [`MIN_COS`] from the plane could
//! meet such a triangle only within 10⁻⁹ m, where the query drops it too.
//!
//! Measured (benches/README.md, 2026-12-07 evening): on edge_study_bare at 45° the BVH's
//! traversal falls from 21 % of a profile's time to 4 %, and the profile takes 0.91× the CPU
//! time, every output byte-identical.

use nalgebra::{Point3, Vector3};

use super::scene::SlabFace;
use crate::geometry::accel::{Hit, SceneAccel, SELF_HIT_T_MIN_M};
use crate::geometry::mesh::SurfacePart;
use crate::geometry::planar::{cross, point_segment_dist2, segments_cross};
use crate::optics::lambert::orthonormal_basis;

/// Least |cos| between a crossing ray and the planes' normal (about 84° from the normal): rays
/// refracted into glass of n = 1.5 stay within 42° of it (|cos| ≥ 0.74); steeper-than-grazing
/// rays (from the rough edge) go to the BVH.
const MIN_COS: f64 = 0.1;

/// How far (m, along the normal) a plane's triangles may lie from it: f64 rounding of the
/// objects' poses moves vertices by ~1e-16 m.
const LEVEL_TOLERANCE_M: f64 = 1e-10;

/// Least gap (m) between a pane's face and a parallel plane beyond it for the air between
/// them to count as a layer: far above `SELF_HIT_T_MIN_M`, below which a query from the face
/// would not see the plane at all.
const MIN_GAP_M: f64 = 1e-7;

/// Least distance (m) of a crossing's hit: ten times the least a query keeps (its f64 re-test
/// of near candidates computes the distance by another formula, equal to ~1e-16 m).
const MIN_HIT_T_M: f64 = 10.0 * SELF_HIT_T_MIN_M;

/// Cells of the lookup grid along the pane's longer side.
const GRID_CELLS: f64 = 64.0;

/// The clearance in f32 units of the scene's largest coordinate (see the module documentation).
const CLEARANCE_ULPS: f64 = 64.0;

/// The layers around the scene's flat panes, and which triangles bound them.
pub struct SlabCrossings {
    /// Per triangle (as in `Hit::triangle`), the layers it bounds:
    /// `members[starts[i]..starts[i + 1]]`.
    starts: Vec<u32>,
    members: Vec<Member>,
    layers: Vec<Layer>,
}

/// A triangle on one of a layer's planes.
#[derive(Clone, Copy, Debug)]
struct Member {
    layer: u32,
    /// 0: the upper plane (along the layer's normal), 1: the lower one.
    side: u8,
}

/// Where a ray leaving a plane goes.
enum Layer {
    /// Nothing of the scene lies beyond the plane in direction `out`.
    Open { out: Vector3<f64> },
    /// Between two parallel planes: the glass of a pane, or the air between a pane's face and
    /// the parallel surface it faces (a table under it).
    Between(Box<LayerGrid>),
}

/// Two parallel planes with their triangles, and the lookup grid over the pane they belong to.
struct LayerGrid {
    /// Unit normal, from the lower plane to the upper one.
    normal: Vector3<f64>,
    /// normal · x on the upper and on the lower plane.
    levels: [f64; 2],
    /// Axes of the planes (with `normal`, an orthonormal frame).
    axes: [Vector3<f64>; 2],
    /// The grid's lower corner in plane coordinates, its cell size (and its inverse) and its
    /// cells per axis.
    min: [f64; 2],
    cell: f64,
    per_cell: f64,
    dims: [usize; 2],
    /// Per cell, three lists in `entries`: the triangles of the upper plane, of the lower one
    /// (indices into `planes`, whose projection's box meets the cell), and the obstacles
    /// (indices into `obstacles`, box widened by the clearance).
    /// `starts[3·cell + k]..starts[3·cell + k + 1]`.
    starts: Vec<u32>,
    entries: Vec<u32>,
    /// The planes' triangles (as in `Hit::triangle`) and their projections' edge lines: the
    /// upper plane's first, `upper_count` of them.
    planes: Vec<(u32, EdgeLines)>,
    upper_count: usize,
    /// The boxes of the planes' projected triangles (while the grid is built).
    boxes: Vec<([f64; 2], [f64; 2])>,
    obstacles: Vec<Obstacle>,
    /// The clearance (m).
    clearance: f64,
}

/// A projected triangle's three edges as lines n·p + c, unit n pointing inside: a point is
/// inside when all three are ≥ 0.
#[derive(Clone, Copy, Debug)]
struct EdgeLines([(f64, f64, f64); 3]);

impl EdgeLines {
    /// The edges of `corners`, or `None` for a degenerate projection.
    fn new(corners: &[[f64; 2]; 3]) -> Option<EdgeLines> {
        let [a, b, c] = *corners;
        let sign = cross(a, b, c).signum();
        if cross(a, b, c) == 0.0 {
            return None;
        }
        let line = |e0: [f64; 2], e1: [f64; 2]| {
            let (dx, dy) = (e1[0] - e0[0], e1[1] - e0[1]);
            let len = (dx * dx + dy * dy).sqrt();
            // Inward normal: the left of the edge for a counter-clockwise triangle.
            let (nx, ny) = (-dy * sign / len, dx * sign / len);
            (nx, ny, -(nx * e0[0] + ny * e0[1]))
        };
        Some(EdgeLines([line(a, b), line(b, c), line(c, a)]))
    }

    /// Whether `p` lies inside or within `hair` of the triangle (conservative: the exact test
    /// is `SceneAccel::hit_on_triangle`'s).
    #[inline]
    fn contains(&self, p: [f64; 2], hair: f64) -> bool {
        self.0
            .iter()
            .all(|&(nx, ny, c)| nx * p[0] + ny * p[1] + c >= -hair)
    }
}

/// An obstacle's projection onto the planes: its corners and their box.
#[derive(Clone, Copy, Debug)]
struct Obstacle {
    corners: [[f64; 2]; 3],
    lo: [f64; 2],
    hi: [f64; 2],
}

/// A flat pane's faces: the normal (outward on the top face), the top and bottom levels along
/// it, and its top and bottom triangles.
struct PaneFaces {
    normal: Vector3<f64>,
    levels: [f64; 2],
    top: Vec<u32>,
    bottom: Vec<u32>,
}

/// What lies beyond a pane's face.
enum Beyond {
    Nothing,
    /// The nearest parallel plane: its level along the outward normal, and its triangles.
    Plane(f64, Vec<u32>),
    /// Something else (nothing to shortcut).
    Other,
}

impl SlabCrossings {
    /// The layers of every flat pane of the scene (the glass objects whose non-edge triangles
    /// are all faces of a flat slab, `slab_faces` indexed like the triangles, on two planes):
    /// its glass, and beyond each face either nothing or the air up to the nearest parallel
    /// plane.
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
        let mut members: Vec<Vec<Member>> = vec![Vec::new(); n_tri as usize];
        let mut layers = Vec::new();
        let mut add = |layer: Layer, upper: &[u32], lower: &[u32]| {
            let id = layers.len() as u32;
            layers.push(layer);
            for (side, tris) in [upper, lower].into_iter().enumerate() {
                for &i in tris {
                    members[i as usize].push(Member {
                        layer: id,
                        side: side as u8,
                    });
                }
            }
        };
        for list in faces_of.into_iter().flatten() {
            let Some(pane) = PaneFaces::new(accel, &list) else {
                continue;
            };
            let Some(extent) = footprint(accel, &pane) else {
                continue;
            };
            let m = pane.normal;
            let slab = LayerGrid::new(accel, m, pane.levels, [&pane.top, &pane.bottom], &extent);
            add(
                Layer::Between(Box::new(slab.with_obstacles(accel, clearance))),
                &pane.top,
                &pane.bottom,
            );
            // Beyond the top face (along m) and beyond the bottom face (along −m).
            for (out, face) in [(m, &pane.top), (-m, &pane.bottom)] {
                let level = out.dot(&accel.triangle(face[0]).vertices[0].coords);
                match beyond(accel, &out, level) {
                    Beyond::Nothing => {
                        let (upper, lower): (&[u32], &[u32]) =
                            if out == m { (&[], face) } else { (face, &[]) };
                        add(Layer::Open { out }, upper, lower)
                    }
                    Beyond::Plane(h, far) => {
                        // Levels along m: the far plane above the top face, below the bottom.
                        let (levels, upper, lower) = if out == m {
                            ([h, pane.levels[0]], &far, face)
                        } else {
                            ([pane.levels[1], -h], face, &far)
                        };
                        let gap = LayerGrid::new(accel, m, levels, [upper, lower], &extent);
                        add(
                            Layer::Between(Box::new(gap.with_obstacles(accel, clearance))),
                            upper,
                            lower,
                        );
                    }
                    Beyond::Other => {}
                }
            }
        }
        let mut starts = Vec::with_capacity(n_tri as usize + 1);
        starts.push(0);
        let mut flat = Vec::new();
        for m in members {
            flat.extend(m);
            starts.push(flat.len() as u32);
        }
        SlabCrossings {
            starts,
            members: flat,
            layers,
        }
    }

    /// The closest hit of the ray `origin + t·dir` (unit `dir`, t in (0, `t_max`]) leaving
    /// triangle `leaving` at `origin`, where it is certain: `Some` of what
    /// `SceneAccel::closest_hit_leaving` returns, bit for bit, for a ray crossing a layer to
    /// its far plane with nothing else in the way (the far plane's hit) or leaving a pane on
    /// an open side (nothing). `None`: not certain; query the BVH.
    pub fn closest_hit(
        &self,
        accel: &SceneAccel,
        leaving: u32,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        t_max: f64,
    ) -> Option<Option<Hit>> {
        let i = leaving as usize;
        let range = *self.starts.get(i)? as usize..*self.starts.get(i + 1)? as usize;
        for m in &self.members[range] {
            match &self.layers[m.layer as usize] {
                Layer::Open { out } => {
                    if out.dot(dir) >= MIN_COS {
                        return Some(None);
                    }
                }
                Layer::Between(g) => {
                    if let Some(hit) = g.crossing(accel, m.side, origin, dir, t_max) {
                        return Some(Some(hit));
                    }
                }
            }
        }
        None
    }
}

impl PaneFaces {
    /// The faces `faces` of one object, split into top and bottom; `None` if they do not lie
    /// on two parallel planes.
    fn new(accel: &SceneAccel, faces: &[u32]) -> Option<PaneFaces> {
        let outward = |i: u32| {
            let [a, b, c] = accel.triangle(i).vertices;
            (b - a).cross(&(c - a)).try_normalize(0.0)
        };
        let normal = outward(*faces.first()?)?;
        let mut levels: [Option<(f64, f64)>; 2] = [None; 2];
        let (mut top, mut bottom) = (Vec::new(), Vec::new());
        for &i in faces {
            let side = usize::from(outward(i)?.dot(&normal) < 0.0);
            for v in accel.triangle(i).vertices {
                let h = normal.dot(&v.coords);
                let range = levels[side].get_or_insert((h, h));
                *range = (range.0.min(h), range.1.max(h));
            }
            [&mut top, &mut bottom][side].push(i);
        }
        let [Some(l0), Some(l1)] = levels else {
            return None;
        };
        if l0.1 - l0.0 > LEVEL_TOLERANCE_M || l1.1 - l1.0 > LEVEL_TOLERANCE_M {
            return None;
        }
        // The top face's outward normal points away from the bottom face.
        let levels = [(l0.0 + l0.1) / 2.0, (l1.0 + l1.1) / 2.0];
        (levels[0] > levels[1]).then_some(PaneFaces {
            normal,
            levels,
            top,
            bottom,
        })
    }
}

/// The box of a pane's faces in the plane frame of its normal: the grid's extent.
fn footprint(accel: &SceneAccel, pane: &PaneFaces) -> Option<([f64; 2], [f64; 2])> {
    let (u, v) = orthonormal_basis(&pane.normal);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &i in pane.top.iter().chain(&pane.bottom) {
        for p in accel.triangle(i).vertices {
            for (a, axis) in [u, v].iter().enumerate() {
                let x = axis.dot(&p.coords);
                (lo[a], hi[a]) = (lo[a].min(x), hi[a].max(x));
            }
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    (extent > 0.0 && extent.is_finite()).then_some((lo, hi))
}

/// What lies beyond the plane at `level` along `out` (unit): nothing (no vertex more than
/// [`LEVEL_TOLERANCE_M`] beyond it), the nearest plane of triangles parallel to it at least
/// [`MIN_GAP_M`] beyond, or something else. The pane's own faces lie on or behind the plane,
/// so they count as neither.
fn beyond(accel: &SceneAccel, out: &Vector3<f64>, level: f64) -> Beyond {
    let mut anything = false;
    let mut nearest: Option<f64> = None;
    let flat_at = |i: u32| -> Option<f64> {
        let h = accel.triangle(i).vertices.map(|p| out.dot(&p.coords));
        let (lo, hi) = (h[0].min(h[1]).min(h[2]), h[0].max(h[1]).max(h[2]));
        (hi - lo <= LEVEL_TOLERANCE_M).then_some((lo + hi) / 2.0)
    };
    for i in 0..accel.triangle_count() as u32 {
        let top = (accel.triangle(i).vertices)
            .iter()
            .map(|p| out.dot(&p.coords))
            .fold(f64::NEG_INFINITY, f64::max);
        if top <= level + LEVEL_TOLERANCE_M {
            continue;
        }
        anything = true;
        if let Some(h) = flat_at(i).filter(|&h| h >= level + MIN_GAP_M) {
            nearest = Some(nearest.map_or(h, |n| n.min(h)));
        }
    }
    match (anything, nearest) {
        (false, _) => Beyond::Nothing,
        (true, None) => Beyond::Other,
        (true, Some(h)) => Beyond::Plane(
            h,
            (0..accel.triangle_count() as u32)
                .filter(|&i| flat_at(i).is_some_and(|f| (f - h).abs() <= LEVEL_TOLERANCE_M))
                .collect(),
        ),
    }
}

impl LayerGrid {
    /// The layer between the planes at `levels` (upper, lower along `normal`) with the
    /// triangles `planes` (upper, lower), gridded over `extent` (plane coordinates in
    /// `orthonormal_basis(normal)`); without obstacles yet.
    fn new(
        accel: &SceneAccel,
        normal: Vector3<f64>,
        levels: [f64; 2],
        planes: [&[u32]; 2],
        extent: &([f64; 2], [f64; 2]),
    ) -> LayerGrid {
        let (u, v) = orthonormal_basis(&normal);
        let (lo, hi) = *extent;
        let cell = (hi[0] - lo[0]).max(hi[1] - lo[1]) / GRID_CELLS;
        let mut g = LayerGrid {
            normal,
            levels,
            axes: [u, v],
            min: lo,
            cell,
            per_cell: 1.0 / cell,
            dims: [0, 1].map(|a| ((hi[a] - lo[a]) / cell).floor() as usize + 1),
            starts: Vec::new(),
            entries: Vec::new(),
            planes: Vec::new(),
            boxes: Vec::new(),
            upper_count: planes[0].len(),
            obstacles: Vec::new(),
            clearance: 0.0,
        };
        for (side, tris) in planes.into_iter().enumerate() {
            for &i in tris {
                let corners = accel.triangle(i).vertices.map(|p| g.plane_point(&p));
                // A triangle seen edge-on is never the far hit of a ray that is not grazing.
                if let Some(lines) = EdgeLines::new(&corners) {
                    g.planes.push((i, lines));
                    g.boxes.push(bounds(&corners));
                } else if side == 0 {
                    g.upper_count -= 1;
                }
            }
        }
        g
    }

    /// The layer with its obstacles: every triangle but the planes' own that reaches between
    /// the planes widened by `clearance`, and the three lists per cell.
    fn with_obstacles(mut self, accel: &SceneAccel, clearance: f64) -> LayerGrid {
        self.clearance = clearance;
        let own: std::collections::HashSet<u32> = self.planes.iter().map(|p| p.0).collect();
        let (bottom, top) = (self.levels[1] - clearance, self.levels[0] + clearance);
        let grid_hi = [0, 1].map(|a| self.min[a] + self.dims[a] as f64 * self.cell);
        for i in 0..accel.triangle_count() as u32 {
            if own.contains(&i) {
                continue;
            }
            let t = accel.triangle(i);
            let h = t.vertices.map(|p| self.normal.dot(&p.coords));
            if h[0].max(h[1]).max(h[2]) < bottom || h[0].min(h[1]).min(h[2]) > top {
                continue;
            }
            let corners = t.vertices.map(|p| self.plane_point(&p));
            let (lo, hi) = bounds(&corners);
            if (0..2).any(|a| hi[a] + clearance < self.min[a] || lo[a] - clearance > grid_hi[a]) {
                continue;
            }
            self.obstacles.push(Obstacle { corners, lo, hi });
        }
        // The three lists per cell: boxes widened by a hair (plane triangles, so that a point on
        // a cell's border finds the triangle from either side) or by the clearance (obstacles).
        let cells = self.dims[0] * self.dims[1];
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); 3 * cells];
        let hair = self.cell * 1e-6;
        let mut add = |g: &LayerGrid, (lo, hi): ([f64; 2], [f64; 2]), widen: f64, k: usize, id| {
            let clamp = |p: [f64; 2], d: f64| {
                [0, 1].map(|a| {
                    (((p[a] + d - g.min[a]) / g.cell).floor().max(0.0) as usize).min(g.dims[a] - 1)
                })
            };
            let (c0, c1) = (clamp(lo, -widen), clamp(hi, widen));
            for y in c0[1]..=c1[1] {
                for x in c0[0]..=c1[0] {
                    lists[3 * (y * g.dims[0] + x) + k].push(id);
                }
            }
        };
        for (j, b) in self.boxes.iter().enumerate() {
            let k = usize::from(j >= self.upper_count);
            add(&self, *b, hair, k, j as u32);
        }
        self.boxes = Vec::new();
        for (j, o) in self.obstacles.iter().enumerate() {
            add(&self, (o.lo, o.hi), clearance, 2, j as u32);
        }
        self.starts = vec![0];
        for l in &lists {
            self.entries.extend_from_slice(l);
            self.starts.push(self.entries.len() as u32);
        }
        self
    }

    /// The hit of a ray leaving plane `side` (0 upper, 1 lower) at `origin` toward the other
    /// plane, if it is certain (see the module documentation).
    #[inline]
    fn crossing(
        &self,
        accel: &SceneAccel,
        side: u8,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        t_max: f64,
    ) -> Option<Hit> {
        let nd = self.normal.dot(dir);
        // Toward the other plane: down from the upper one, up from the lower one.
        let toward = if side == 0 { -nd } else { nd };
        if toward < MIN_COS {
            return None;
        }
        let far = 1 - side as usize;
        let t = (self.levels[far] - self.normal.dot(&origin.coords)) / nd;
        // Clear of `t_max`, which the query compares in f32.
        if !(t > 0.0 && t <= t_max * (1.0 - 1e-5)) {
            return None;
        }
        let a = self.plane_point(origin);
        let b = self.plane_point(&(origin + dir * t));
        // The segment's box spans the cells from a's to b's.
        let (ca, cb) = (self.cell_of(a)?, self.cell_of(b)?);
        let (lo, hi) = (
            [a[0].min(b[0]), a[1].min(b[1])],
            [a[0].max(b[0]), a[1].max(b[1])],
        );
        for y in ca[1].min(cb[1])..=ca[1].max(cb[1]) {
            for x in ca[0].min(cb[0])..=ca[0].max(cb[0]) {
                for &o in self.list(y * self.dims[0] + x, 2) {
                    if self.obstacles[o as usize].near_segment(a, b, lo, hi, self.clearance) {
                        return None;
                    }
                }
            }
        }
        let hair = self.cell * 1e-6;
        // The far point's triangle: the one candidate whose projection holds it. Two (a
        // point within a hair of a shared edge) are told apart by the exact test; two that
        // both pass it overlap, and the query's tie rule decides.
        let candidates = self.list(cb[1] * self.dims[0] + cb[0], far);
        let mut holding = candidates
            .iter()
            .map(|&j| &self.planes[j as usize])
            .filter(|(_, lines)| lines.contains(b, hair));
        let first = holding.next()?;
        let Some(second) = holding.next() else {
            return accel.hit_on_triangle_within(first.0, origin, dir, MIN_HIT_T_M, t_max);
        };
        let mut found = None;
        for (tri, _) in [first, second].into_iter().chain(holding) {
            if let Some(hit) = accel.hit_on_triangle_within(*tri, origin, dir, MIN_HIT_T_M, t_max) {
                if found.is_some() {
                    return None;
                }
                found = Some(hit);
            }
        }
        found
    }

    /// A point's coordinates in the planes.
    #[inline]
    fn plane_point(&self, p: &Point3<f64>) -> [f64; 2] {
        [self.axes[0].dot(&p.coords), self.axes[1].dot(&p.coords)]
    }

    /// The cell of plane point `p`, or `None` outside the grid.
    #[inline]
    fn cell_of(&self, p: [f64; 2]) -> Option<[usize; 2]> {
        let mut c = [0; 2];
        for a in 0..2 {
            let x = (p[a] - self.min[a]) * self.per_cell;
            if !(x >= 0.0 && x < self.dims[a] as f64) {
                return None;
            }
            // x is in [0, dims), so the signed 32-bit conversion is exact; x86-64 has an
            // instruction for it, while `as usize` takes a dozen (callgrind: a third of
            // this function).
            c[a] = x as i32 as usize;
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

/// The box of three plane points.
fn bounds(corners: &[[f64; 2]; 3]) -> ([f64; 2], [f64; 2]) {
    let lo = [0, 1].map(|a| corners.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1].map(|a| {
        corners
            .iter()
            .map(|p| p[a])
            .fold(f64::NEG_INFINITY, f64::max)
    });
    (lo, hi)
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

    /// How many rays of each kind were answered, of how many asked (at least 60° from
    /// grazing): into the glass from the top and the bottom face, out of the top and out of
    /// the bottom face; and how many answers were a hit on each object.
    #[derive(Debug, Default)]
    struct Tally {
        into_from_top: [usize; 2],
        into_from_bottom: [usize; 2],
        out_of_top: [usize; 2],
        out_of_bottom: [usize; 2],
        hits_on: [usize; 4],
    }

    /// Every answer against the BVH query, from points spread over every face triangle of the
    /// scene's glass in 400 directions.
    fn check_against_the_bvh(scene: &TraceScene) -> Tally {
        let mut tally = Tally::default();
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
                        if let Some(h) = answer {
                            tally.hits_on[h.object as usize] += 1;
                        }
                    }
                    let cos = w.dot(&ng);
                    let top = t.part == SurfacePart::TopFace;
                    let counts = match (cos < -0.5, cos > 0.5, top) {
                        (true, _, true) => &mut tally.into_from_top,
                        (true, _, false) => &mut tally.into_from_bottom,
                        (_, true, true) => &mut tally.out_of_top,
                        (_, true, false) => &mut tally.out_of_bottom,
                        _ => continue,
                    };
                    counts[0] += usize::from(answer.is_some());
                    counts[1] += 1;
                }
            }
        }
        tally
    }

    #[test]
    fn a_flat_pane_and_the_air_under_it_are_crossed_as_the_bvh_would() {
        // edge_study_bare: the pane (object 0) lies 10 µm above the table (object 1).
        let scene = scene_of(&edge_study_text());
        let t = check_against_the_bvh(&scene);
        // Most rays into the pane cross it clear of the edge; those from the rim's triangles
        // near the edge do not.
        for counts in [t.into_from_top, t.into_from_bottom] {
            assert!(
                counts[0] * 10 > counts[1] * 6 && counts[0] < counts[1],
                "{t:?}"
            );
        }
        // Out of the top face: nothing above the pane, always answered (none). Out of the
        // bottom face: the table, 10 µm below, answered unless the 10 µm of the way pass
        // within the clearance of the pane's edge (none of these points is that close).
        assert_eq!(t.out_of_top[0], t.out_of_top[1], "{t:?}");
        assert!(t.out_of_bottom[0] * 10 > t.out_of_bottom[1] * 9, "{t:?}");
        assert!(t.hits_on[1] >= t.out_of_bottom[0], "{t:?}");
    }

    /// The triangle of face `part` of the pane at `point` (well inside it).
    fn face_at(scene: &TraceScene, part: SurfacePart, point: &Point3<f64>) -> u32 {
        let up = Vector3::z();
        (0..scene.accel.triangle_count() as u32)
            .find(|&i| {
                scene.accel.triangle(i).part == part
                    && (scene.accel)
                        .hit_on_triangle(i, &(point - up * 1e-3), &up, 1.0)
                        .is_some()
            })
            .unwrap_or_else(|| panic!("no {part:?} triangle at {point}"))
    }

    #[test]
    fn something_inside_the_pane_or_on_it_is_never_skipped() {
        // A 2 × 2 × 1 mm opaque inclusion in the middle of the 4 mm pane, 150 mm in from its
        // edge, and a 10 × 10 × 0.1 mm foil 10 µm above its top face: the first is in the way
        // of crossings near it; the second makes the air above the pane a layer whose far
        // plane is the foil's underside, so rays up from the top face are answered only
        // under the foil.
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
        let t = check_against_the_bvh(&scene);
        assert!(t.into_from_top[0] * 10 > t.into_from_top[1] * 6, "{t:?}");
        assert!(t.out_of_top[0] * 10 < t.out_of_top[1], "{t:?}");
        // Straight up through the inclusion from the bottom face: its hit, not the top face.
        let origin = Point3::new(0.6e-3, 0.3e-3, 0.01e-3);
        let up = Vector3::z();
        let bottom = face_at(&scene, SurfacePart::BottomFace, &origin);
        let hit = scene
            .closest_hit_leaving(&origin, &up, bottom, 1.0)
            .unwrap();
        assert_eq!(scene.accel.triangle(hit.triangle).object, 2, "{hit:?}");
        assert!((hit.t - 1.5e-3).abs() < 1e-9, "{hit:?}");
        // Straight up from the top face under the foil: the foil's underside, 10 µm up.
        let origin = Point3::new(50.3e-3, 50.2e-3, 4.01e-3);
        let top = face_at(&scene, SurfacePart::TopFace, &origin);
        let answer = scene
            .slab_crossings
            .closest_hit(&scene.accel, top, &origin, &up, 1.0);
        let hit = answer.expect("answered").expect("a hit");
        assert_eq!(scene.accel.triangle(hit.triangle).object, 3, "{hit:?}");
        assert_eq!(
            Some(hit),
            scene.accel.closest_hit_leaving(&origin, &up, top, 1.0)
        );
    }
}
