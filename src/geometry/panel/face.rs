//! Face tessellation. Top and bottom faces are the same planar polygon (the outline inset by the
//! edge finish), cut by a square grid (cell size `tessellation_m`, on a flat panel at least
//! `FLAT_FACE_GRID_M`) so that no triangle spans more than one cell: on a bent panel that
//! bounds the chord error by L²/(8R).
//!
//! Method: every crossing of the rim with a grid line is inserted into the rim first (vertical
//! lines, then horizontal), so each rim segment lies in one closed cell. The grid is placed in
//! general position: rim vertices off the lines keep a clearance from them, and the rim crosses
//! every line it meets (no touching, no segment along a line); a placement that fails this is
//! shifted and retried.
//! Then a cell with rim segments is cut into pieces by walking its boundary (the rectangle case
//! of Weiler–Atherton: from where the rim leaves the cell, go counter-clockwise along the cell
//! to where it next enters, adding the cell corners passed), and each piece is triangulated;
//! a cell without rim segments inside the rim gets two triangles. Neighbouring cells see the
//! same points on their shared side, so the result has no T-junctions, and the rim vertices
//! are exactly those the edge band uses, so the panel mesh is watertight.

use std::collections::{HashMap, HashSet};

use nalgebra::Point2;

use super::contour::RimPoint;
use super::triangulate::triangulate;

/// Placements of the grid tried before giving up.
const GRID_ATTEMPTS: usize = 16;
/// Nearest a rim vertex not on a grid line may come to one, in cells.
const CLEARANCE: f64 = 1e-9;
/// A vertical-line crossing this close to a horizontal line (in cells) is moved onto it.
const SNAP: f64 = 1e-7;

/// The face polygon, refined and triangulated, in the flat x–y plane.
#[derive(Clone, Debug)]
pub(super) struct FacePatch {
    /// The rim with every grid crossing inserted, counter-clockwise.
    pub(super) rim: Vec<RimPoint>,
    /// Face vertices (m): the rim face points first, in rim order, then interior grid corners.
    pub(super) points: Vec<Point2<f64>>,
    /// Triangles, counter-clockwise seen from +z.
    pub(super) triangles: Vec<[u32; 3]>,
}

/// Tessellates the face polygon bounded by the face points of `rim` (counter-clockwise) with
/// a grid of `cell_m`; `None` if no grid placement worked (not seen in practice).
pub(super) fn tessellate(rim: &[RimPoint], cell_m: f64) -> Option<FacePatch> {
    (0..GRID_ATTEMPTS).find_map(|attempt| {
        // The first grid has lines at half-integer multiples of the cell (symmetric about the
        // origin); later ones are shifted by additive recurrences (golden and plastic ratios).
        let shift = |step: f64| (0.5 + attempt as f64 * step).fract() * cell_m;
        let grid = Grid {
            origin: [shift(0.618_033_988_749_895), shift(0.754_877_666_246_693)],
            cell_m,
        };
        try_grid(rim, &grid)
    })
}

fn try_grid(coarse: &[RimPoint], grid: &Grid) -> Option<FacePatch> {
    let rim = insert_crossings(&insert_crossings(coarse, grid, 0), grid, 1);
    let points: Vec<Point2<f64>> = rim.iter().map(|p| p.face).collect();
    let owners = cell_owners(&points, grid)?;
    let mut corners = Corners {
        grid: *grid,
        index: HashMap::new(),
        points,
    };
    for (k, p) in corners.points.iter().enumerate() {
        if let (Some(i), Some(j)) = (grid.line_at(0, p.x), grid.line_at(1, p.y)) {
            corners.index.insert([i, j], k as u32);
        }
    }
    let mut triangles = Vec::new();
    let mut by_cell: Vec<usize> = (0..owners.len()).collect();
    by_cell.sort_by_key(|&k| (owners[k][1], owners[k][0], k));
    for edges in by_cell.chunk_by(|&a, &b| owners[a] == owners[b]) {
        for piece in cell_pieces(owners[edges[0]], edges, &owners, &mut corners)? {
            let outline: Vec<Point2<f64>> =
                piece.iter().map(|&k| corners.points[k as usize]).collect();
            let local = triangulate(&outline)?;
            triangles.extend(local.iter().map(|t| t.map(|k| piece[k])));
        }
    }
    for [i, j] in full_cells(&corners.points[..rim.len()], &owners, grid)? {
        let [a, b, c, d] =
            [[i, j], [i + 1, j], [i + 1, j + 1], [i, j + 1]].map(|ij| corners.get(ij));
        triangles.extend([[a, b, c], [a, c, d]]);
    }
    Some(FacePatch {
        rim,
        points: corners.points,
        triangles,
    })
}

/// A square grid: lines at `origin[axis] + i·cell_m`; cell i spans [line i, line i + 1).
#[derive(Clone, Copy, Debug)]
struct Grid {
    origin: [f64; 2],
    cell_m: f64,
}

impl Grid {
    fn line(&self, axis: usize, i: i64) -> f64 {
        self.origin[axis] + i as f64 * self.cell_m
    }

    /// The cell whose half-open span holds `c`, decided by comparison with [`Self::line`] so
    /// that it agrees with the lines exactly.
    fn cell(&self, axis: usize, c: f64) -> i64 {
        let mut i = ((c - self.origin[axis]) / self.cell_m).floor() as i64;
        while c < self.line(axis, i) {
            i -= 1;
        }
        while c >= self.line(axis, i + 1) {
            i += 1;
        }
        i
    }

    fn nearest(&self, axis: usize, c: f64) -> i64 {
        ((c - self.origin[axis]) / self.cell_m).round() as i64
    }

    /// The index of the grid line exactly at `c`, if any.
    fn line_at(&self, axis: usize, c: f64) -> Option<i64> {
        let i = self.nearest(axis, c);
        (self.line(axis, i) == c).then_some(i)
    }

    fn centre(&self, axis: usize, i: i64) -> f64 {
        0.5 * (self.line(axis, i) + self.line(axis, i + 1))
    }
}

/// Inserts the crossings of every rim segment with the grid lines across `axis`, exactly on
/// the line; the other coordinate is clamped to the segment. Vertical-line crossings that
/// fall next to a horizontal line are moved onto it (the rim passes through a grid corner).
fn insert_crossings(rim: &[RimPoint], grid: &Grid, axis: usize) -> Vec<RimPoint> {
    let other = 1 - axis;
    let n = rim.len();
    let mut out = Vec::with_capacity(2 * n);
    for k in 0..n {
        let (a, b) = (&rim[k], &rim[(k + 1) % n]);
        out.push(*a);
        let (ca, cb) = (a.face[axis], b.face[axis]);
        if ca == cb {
            continue;
        }
        let (lo, hi) = (ca.min(cb), ca.max(cb));
        let first = grid.cell(axis, lo) + 1;
        let last = grid.cell(axis, hi) - i64::from(grid.line(axis, grid.cell(axis, hi)) == hi);
        let lines: Vec<i64> = if ca < cb {
            (first..=last).collect()
        } else {
            (first..=last).rev().collect()
        };
        for i in lines {
            let c = grid.line(axis, i);
            let t = (c - ca) / (cb - ca);
            let mut p = a.lerp(b, t);
            let (oa, ob) = (a.face[other], b.face[other]);
            let mut o = (oa + (ob - oa) * t).clamp(oa.min(ob), oa.max(ob));
            if axis == 0 {
                let y = grid.line(other, grid.nearest(other, o));
                if (o - y).abs() < SNAP * grid.cell_m {
                    o = y;
                }
            }
            p.face[axis] = c;
            p.face[other] = o;
            out.push(p);
        }
    }
    out
}

/// The cell [i, j] that owns each rim segment (k → k + 1), or `None` when the rim is not in
/// general position for this grid.
fn cell_owners(points: &[Point2<f64>], grid: &Grid) -> Option<Vec<[i64; 2]>> {
    let n = points.len();
    let mut owners = Vec::with_capacity(n);
    for k in 0..n {
        let (u, v, w) = (&points[(k + n - 1) % n], &points[k], &points[(k + 1) % n]);
        if v == w {
            return None;
        }
        for axis in 0..2 {
            let c = v[axis];
            let line = grid.line(axis, grid.nearest(axis, c));
            if c == line {
                let crosses = (u[axis] < c && w[axis] > c) || (u[axis] > c && w[axis] < c);
                if !crosses {
                    return None;
                }
            } else if (c - line).abs() < CLEARANCE * grid.cell_m {
                return None;
            }
        }
        let mid = nalgebra::center(v, w);
        let cell = [grid.cell(0, mid.x), grid.cell(1, mid.y)];
        for axis in 0..2 {
            let span = grid.line(axis, cell[axis])..=grid.line(axis, cell[axis] + 1);
            if !(span.contains(&v[axis]) && span.contains(&w[axis])) {
                return None;
            }
        }
        owners.push(cell);
    }
    Some(owners)
}

/// Face vertices with interior grid corners added on demand, shared by all cells.
struct Corners {
    grid: Grid,
    index: HashMap<[i64; 2], u32>,
    points: Vec<Point2<f64>>,
}

impl Corners {
    fn get(&mut self, ij: [i64; 2]) -> u32 {
        let (grid, points) = (&self.grid, &mut self.points);
        *self.index.entry(ij).or_insert_with(|| {
            points.push(Point2::new(grid.line(0, ij[0]), grid.line(1, ij[1])));
            (points.len() - 1) as u32
        })
    }
}

/// Position along the boundary of a cell, counter-clockwise from its lower-left corner: side
/// (0 bottom, 1 right, 2 top, 3 left) and a coordinate increasing along that side.
type BoundaryKey = (u8, f64);

fn key_order(a: &BoundaryKey, b: &BoundaryKey) -> std::cmp::Ordering {
    a.0.cmp(&b.0).then(a.1.total_cmp(&b.1))
}

/// Cuts cell `ij` into the pieces of the face polygon inside it; `edges` are the rim segments
/// the cell owns, in rim order. Each piece is a counter-clockwise list of point indices.
fn cell_pieces(
    ij: [i64; 2],
    edges: &[usize],
    owners: &[[i64; 2]],
    corners: &mut Corners,
) -> Option<Vec<Vec<u32>>> {
    let n = owners.len();
    if edges.len() == n {
        // The whole rim lies in this cell.
        return Some(vec![(0..n as u32).collect()]);
    }
    let grid = corners.grid;
    let (x0, x1) = (grid.line(0, ij[0]), grid.line(0, ij[0] + 1));
    let (y0, y1) = (grid.line(1, ij[1]), grid.line(1, ij[1] + 1));
    let key = |p: &Point2<f64>| -> Option<BoundaryKey> {
        match (p.x, p.y) {
            (x, y) if y == y0 && x < x1 => Some((0, x)),
            (x, y) if x == x1 && y < y1 => Some((1, y)),
            (x, y) if y == y1 && x > x0 => Some((2, -x)),
            (x, y) if x == x0 && y > y0 => Some((3, -y)),
            _ => None,
        }
    };
    let cell_corners: [(BoundaryKey, [i64; 2]); 4] = [
        ((0, x0), ij),
        ((1, y0), [ij[0] + 1, ij[1]]),
        ((2, -x1), [ij[0] + 1, ij[1] + 1]),
        ((3, -y1), [ij[0], ij[1] + 1]),
    ];
    // Chains: maximal runs of owned rim segments, entering and leaving through the boundary.
    let mut chains = Vec::new();
    for &k in edges.iter().filter(|&&k| owners[(k + n - 1) % n] != ij) {
        let mut ids = vec![k as u32];
        let mut e = k;
        while owners[e] == ij {
            e = (e + 1) % n;
            ids.push(e as u32);
        }
        let entry = key(&corners.points[k])?;
        let exit = key(&corners.points[e])?;
        chains.push((ids, entry, exit));
    }
    // Cyclic order after `from`: keys ahead on this lap first, then the wrapped ones.
    let ahead = |from: &BoundaryKey, to: &BoundaryKey| (key_order(to, from).is_le(), *to);
    let before = |a: &(bool, BoundaryKey), b: &(bool, BoundaryKey)| {
        a.0.cmp(&b.0).then(key_order(&a.1, &b.1))
    };
    let mut used = vec![false; chains.len()];
    let mut pieces = Vec::new();
    for first in 0..chains.len() {
        if used[first] {
            continue;
        }
        let mut piece = Vec::new();
        let mut c = first;
        loop {
            if used[c] {
                return None;
            }
            used[c] = true;
            piece.extend_from_slice(&chains[c].0);
            let exit = chains[c].2;
            let next = (0..chains.len()).min_by(|&a, &b| {
                before(&ahead(&exit, &chains[a].1), &ahead(&exit, &chains[b].1))
            })?;
            let entry = ahead(&exit, &chains[next].1);
            let mut passed: Vec<_> = cell_corners
                .iter()
                .map(|(k, ij)| (ahead(&exit, k), *ij))
                .filter(|(k, _)| before(k, &entry).is_lt())
                .collect();
            passed.sort_by(|a, b| before(&a.0, &b.0));
            piece.extend(passed.iter().map(|(_, ij)| corners.get(*ij)));
            if next == first {
                break;
            }
            c = next;
        }
        pieces.push(piece);
    }
    Some(pieces)
}

/// Cells without rim segments whose centre lies inside the rim, row by row: the rim's
/// crossings with each row's centre line, paired, give the inside spans.
fn full_cells(rim: &[Point2<f64>], owners: &[[i64; 2]], grid: &Grid) -> Option<Vec<[i64; 2]>> {
    let n = rim.len();
    let partial: HashSet<[i64; 2]> = owners.iter().copied().collect();
    let mut crossings: Vec<(i64, f64)> = Vec::new();
    for k in 0..n {
        let j = owners[k][1];
        let yc = grid.centre(1, j);
        let (a, b) = (&rim[k], &rim[(k + 1) % n]);
        if (a.y > yc) != (b.y > yc) {
            crossings.push((j, a.x + (yc - a.y) / (b.y - a.y) * (b.x - a.x)));
        }
    }
    crossings.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut cells = Vec::new();
    for row in crossings.chunk_by(|a, b| a.0 == b.0) {
        if row.len() % 2 != 0 {
            return None;
        }
        for span in row.chunks(2) {
            let (j, xa, xb) = (span[0].0, span[0].1, span[1].1);
            for i in grid.cell(0, xa)..=grid.cell(0, xb) {
                let xc = grid.centre(0, i);
                if xc > xa && xc < xb && !partial.contains(&[i, j]) {
                    cells.push([i, j]);
                }
            }
        }
    }
    Some(cells)
}
