//! Rays traversed as one bundle: the laser fan's primary rays, which leave one source within a
//! few milliradians of each other and, taken in fan order, meet the same nodes and leaves.
//!
//! The bundle is tested like one ray whose origin and reciprocal direction are intervals. Its
//! rays are grouped by the signs of their direction (a beam's rays straddle the plane its axis
//! lies in), and per group and axis the least and greatest origin and reciprocal direction are
//! kept. A node's eight boxes are tested at once, one AVX2 register per plane as in the
//! single-ray test, a box being entered if any ray of the bundle might enter it; at a leaf,
//! each triangle is tested against eight rays at a time (rays across the lanes). A node thus
//! costs the bundle about what it costs one ray, whatever the number of rays, and only the
//! leaves are paid per ray: on the 1M-triangle field's laser fan a bundle of 64 rays visits
//! ~14 nodes and ~2.2 leaves where one ray alone visits 7.3 nodes and 1.06 leaves
//! (benches/README.md, 2026-12-08). Interval culling for ray packets: Wald, Boulos & Shirley,
//! "Ray tracing deformable scenes using dynamic bounding volume hierarchies", ACM TOG 26(1),
//! 2007; Reshetov, Soupikov & Hurley, "Multi-level ray tracing algorithm", SIGGRAPH 2005;
//! triangles against many rays: Embree's hybrid intersectors (Wald et al., ACM TOG 33(4),
//! 2014).
//!
//! Exactness: for each ray, the single-ray box test computes per axis fl(fl(plane − o)·inv)
//! with its own origin o and reciprocal inv (`Prepared`). IEEE rounding is monotone and the
//! product is monotone in each factor for a fixed sign of the other, so over a group's origins
//! and reciprocals the least entry value of an axis is the lesser of the two products of
//! (near plane − the origin bound that makes the difference least) with the two reciprocal
//! bounds, and the greatest exit value likewise. A group's box entry is therefore at most each
//! of its rays' and its exit (with the greatest of the rays' current bounds, times the same
//! [`FAR_SCALE`]) at least each of its rays': a box that some ray would enter is entered. At
//! the leaves every lane runs the SSE2 packet test's operations in the same order for its ray
//! and triangle (`triangles`), so each (ray, triangle) distance and verdict is the single
//! ray's, and each ray keeps the least (t, input index) over the triangles its test hits, as
//! `queries::Closest` does: its closest hit is the single ray's bit for bit. The bundle may
//! visit boxes and test triangles that a ray alone would have skipped, which costs time but
//! changes no answer.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;

use super::build::{Node, WideBvh, WIDTH};
use super::queries::{better, Found, HitData};
use super::traverse::{run_loop, with_stack, BoxTest, Prepared, Visitor, FAR_SCALE};
use super::triangles::{Ray, TrianglePacket, LANES, PAD};

/// Most rays in a bundle: eight AVX2 registers of rays at the leaves.
pub(super) const MAX_BUNDLE: usize = 64;

/// Rays of a bundle whose directions share their signs, as intervals: per axis, the plane
/// indices of the near and far sides (as the common sign chooses them), the origin bound that
/// makes the entry distance least (used with the near plane) and the one that makes the exit
/// greatest (with the far plane), and the reciprocal direction's bounds.
#[derive(Clone, Copy)]
struct Group {
    near: [usize; 3],
    far: [usize; 3],
    origin_near: [f32; 3],
    origin_far: [f32; 3],
    inv_lo: [f32; 3],
    inv_hi: [f32; 3],
    t_min: f32,
}

/// The bundle's rays in groups of one direction sign pattern each: a beam's rays straddle the
/// planes its axis lies in (the laser's divergence), and an interval of reciprocal directions
/// across a sign change would bound nothing on that axis.
pub(super) struct Bundle {
    groups: [Group; 8],
    count: usize,
}

impl Bundle {
    fn new(rays: &[Ray]) -> Bundle {
        // Per sign pattern (bit a set where 1/d_a < 0): origin and reciprocal bounds.
        let mut o_lo = [[f32::INFINITY; 3]; 8];
        let mut o_hi = [[f32::NEG_INFINITY; 3]; 8];
        let mut inv_lo = [[f32::INFINITY; 3]; 8];
        let mut inv_hi = [[f32::NEG_INFINITY; 3]; 8];
        let mut t_min = [f32::INFINITY; 8];
        let mut present = 0u32;
        for ray in rays {
            let p = Prepared::new(ray);
            let pattern = (0..3)
                .map(|a| usize::from(p.inv[a] < 0.0) << a)
                .sum::<usize>();
            present |= 1 << pattern;
            t_min[pattern] = t_min[pattern].min(p.t_min);
            for a in 0..3 {
                o_lo[pattern][a] = o_lo[pattern][a].min(p.origin[a]);
                o_hi[pattern][a] = o_hi[pattern][a].max(p.origin[a]);
                inv_lo[pattern][a] = inv_lo[pattern][a].min(p.inv[a]);
                inv_hi[pattern][a] = inv_hi[pattern][a].max(p.inv[a]);
            }
        }
        let mut b = Bundle {
            groups: [Group {
                near: [0; 3],
                far: [0; 3],
                origin_near: [0.0; 3],
                origin_far: [0.0; 3],
                inv_lo: [0.0; 3],
                inv_hi: [0.0; 3],
                t_min: 0.0,
            }; 8],
            count: 0,
        };
        for pattern in (0..8).filter(|p| present & (1 << p) != 0) {
            let g = &mut b.groups[b.count];
            b.count += 1;
            g.t_min = t_min[pattern];
            g.inv_lo = inv_lo[pattern];
            g.inv_hi = inv_hi[pattern];
            for a in 0..3 {
                // Where 1/d ≥ 0 the near side is the box's minimum (`Prepared`) and
                // (plane − o)·inv falls as o grows: the least entry takes the greatest origin,
                // the greatest exit the least. Where 1/d < 0 it is the other way round.
                (g.near[a], g.far[a], g.origin_near[a], g.origin_far[a]) =
                    if pattern & (1 << a) == 0 {
                        (2 * a, 2 * a + 1, o_hi[pattern][a], o_lo[pattern][a])
                    } else {
                        (2 * a + 1, 2 * a, o_lo[pattern][a], o_hi[pattern][a])
                    };
            }
        }
        b
    }
}

/// The bundle's eight-box test (AVX2).
struct Avx2BundleBoxes;

impl BoxTest for Avx2BundleBoxes {
    type Rays = Bundle;

    #[inline(always)]
    unsafe fn test(node: &Node, b: &Bundle, bound: f32, t_near: &mut [f32; WIDTH]) -> u32 {
        let ld = |plane: usize| _mm256_load_ps(node.planes.get_unchecked(plane).as_ptr());
        let far_bound = _mm256_set1_ps(bound);
        let mut entered = _mm256_setzero_ps();
        let mut nearest = _mm256_set1_ps(f32::INFINITY);
        for g in b.groups.get_unchecked(..b.count) {
            let mut tn = _mm256_set1_ps(g.t_min);
            let mut tf = far_bound;
            for a in 0..3 {
                let (lo, hi) = (_mm256_set1_ps(g.inv_lo[a]), _mm256_set1_ps(g.inv_hi[a]));
                let xn = _mm256_sub_ps(ld(g.near[a]), _mm256_set1_ps(g.origin_near[a]));
                let xf = _mm256_sub_ps(ld(g.far[a]), _mm256_set1_ps(g.origin_far[a]));
                tn = _mm256_max_ps(
                    tn,
                    _mm256_min_ps(_mm256_mul_ps(xn, lo), _mm256_mul_ps(xn, hi)),
                );
                tf = _mm256_min_ps(
                    tf,
                    _mm256_max_ps(_mm256_mul_ps(xf, lo), _mm256_mul_ps(xf, hi)),
                );
            }
            let tf = _mm256_mul_ps(tf, _mm256_set1_ps(FAR_SCALE));
            let hit = _mm256_cmp_ps::<_CMP_LE_OQ>(tn, tf);
            entered = _mm256_or_ps(entered, hit);
            nearest = _mm256_min_ps(nearest, _mm256_blendv_ps(nearest, tn, hit));
        }
        _mm256_storeu_ps(t_near.as_mut_ptr(), nearest);
        _mm256_movemask_ps(entered) as u32
    }
}

/// The bundle's rays in structure of arrays, eight to an AVX2 register ([`CHUNKS`] registers),
/// and each ray's closest hit so far.
#[repr(C, align(32))]
struct Chunks {
    origin: [[[f32; 8]; CHUNKS]; 3],
    dir: [[[f32; 8]; CHUNKS]; 3],
    t_min: [[f32; 8]; CHUNKS],
    best: [[f32; 8]; CHUNKS],
}

/// Registers of eight rays in a bundle.
const CHUNKS: usize = MAX_BUNDLE / 8;

/// Closest hits of a bundle's rays, each the least (t, input index) over the triangles its test
/// hits, as `queries::Closest` finds it for the ray alone: a leaf's triangles are tested one at
/// a time against eight rays at once, each lane the SSE2 packet test's arithmetic for that
/// ray and triangle (`triangles`), so each (ray, triangle) distance and verdict is the same.
struct ClosestBundle<'a> {
    rays: Chunks,
    count: usize,
    found: [Option<Found>; MAX_BUNDLE],
    data: HitData<'a>,
    /// The greatest of the rays' current bounds.
    bound: f32,
}

impl<'a> ClosestBundle<'a> {
    fn new(rays: &[Ray], data: HitData<'a>) -> ClosestBundle<'a> {
        let mut c = Chunks {
            origin: [[[0.0; 8]; CHUNKS]; 3],
            dir: [[[0.0; 8]; CHUNKS]; 3],
            t_min: [[0.0; 8]; CHUNKS],
            // Lanes without a ray: nothing is ever below −∞.
            best: [[f32::NEG_INFINITY; 8]; CHUNKS],
        };
        for (k, ray) in rays.iter().enumerate() {
            let (i, l) = (k / 8, k % 8);
            for a in 0..3 {
                c.origin[a][i][l] = ray.origin[a];
                c.dir[a][i][l] = ray.dir[a];
            }
            c.t_min[i][l] = ray.t_min;
            c.best[i][l] = ray.t_max;
        }
        let bound = rays
            .iter()
            .map(|r| r.t_max)
            .fold(f32::NEG_INFINITY, f32::max);
        ClosestBundle {
            rays: c,
            count: rays.len(),
            found: [None; MAX_BUNDLE],
            data,
            bound,
        }
    }

    /// Tests triangle `lane` of packet `p` (packet index `pi`) against every ray.
    #[inline(always)]
    unsafe fn test_triangle(&mut self, p: &TrianglePacket, pi: usize, lane: usize) {
        let id = p.ids[lane];
        let b = |a: &[[f32; LANES]; 3], k: usize| _mm256_set1_ps(*a[k].get_unchecked(lane));
        let (v0x, v0y, v0z) = (b(&p.v0, 0), b(&p.v0, 1), b(&p.v0, 2));
        let (e1x, e1y, e1z) = (b(&p.e1, 0), b(&p.e1, 1), b(&p.e1, 2));
        let (e2x, e2y, e2z) = (b(&p.e2, 0), b(&p.e2, 1), b(&p.e2, 2));
        let (nx, ny, nz) = (b(&p.ng, 0), b(&p.ng, 1), b(&p.ng, 2));
        let dot = |ax: __m256, ay: __m256, az: __m256, bx: __m256, by: __m256, bz: __m256| {
            _mm256_add_ps(
                _mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)),
                _mm256_mul_ps(az, bz),
            )
        };
        let chunks = self.count.div_ceil(8);
        for i in 0..chunks {
            let r = &self.rays;
            let ld = |x: &[[f32; 8]; CHUNKS]| _mm256_load_ps(x.get_unchecked(i).as_ptr());
            let (ox, oy, oz) = (ld(&r.origin[0]), ld(&r.origin[1]), ld(&r.origin[2]));
            let (dx, dy, dz) = (ld(&r.dir[0]), ld(&r.dir[1]), ld(&r.dir[2]));
            let best = ld(&r.best);
            // The SSE2 packet test (`TrianglePacket::intersect_sse2`) with the roles of
            // rays and triangles exchanged: the same operations in the same order per lane.
            let cx = _mm256_sub_ps(v0x, ox);
            let cy = _mm256_sub_ps(v0y, oy);
            let cz = _mm256_sub_ps(v0z, oz);
            let rx = _mm256_sub_ps(_mm256_mul_ps(dy, cz), _mm256_mul_ps(dz, cy));
            let ry = _mm256_sub_ps(_mm256_mul_ps(dz, cx), _mm256_mul_ps(dx, cz));
            let rz = _mm256_sub_ps(_mm256_mul_ps(dx, cy), _mm256_mul_ps(dy, cx));
            let inv_det = _mm256_div_ps(_mm256_set1_ps(1.0), dot(nx, ny, nz, dx, dy, dz));
            let u = _mm256_mul_ps(dot(rx, ry, rz, e2x, e2y, e2z), inv_det);
            let v = _mm256_mul_ps(dot(rx, ry, rz, e1x, e1y, e1z), inv_det);
            let w = _mm256_sub_ps(_mm256_sub_ps(_mm256_set1_ps(1.0), u), v);
            let t = _mm256_mul_ps(dot(nx, ny, nz, cx, cy, cz), inv_det);
            let signs = _mm256_movemask_ps(_mm256_or_ps(_mm256_or_ps(u, v), w)) as u32;
            let nonzero =
                _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_NEQ_UQ>(inv_det, _mm256_setzero_ps()))
                    as u32;
            let in_range = _mm256_movemask_ps(_mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GE_OQ>(t, ld(&r.t_min)),
                _mm256_cmp_ps::<_CMP_LE_OQ>(t, best),
            )) as u32;
            let mut mask = !signs & nonzero & in_range & 0xFF;
            if mask == 0 {
                continue;
            }
            let mut ts = [0.0f32; 8];
            _mm256_storeu_ps(ts.as_mut_ptr(), t);
            while mask != 0 {
                let l = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let k = 8 * i + l;
                let t = ts[l];
                let best = self.rays.best.get_unchecked_mut(i).get_unchecked_mut(l);
                let found = self.found.get_unchecked_mut(k);
                if better(t, id, *best, found) {
                    self.data.prefetch(id);
                    *best = t;
                    *found = Some(Found {
                        id,
                        slot: (pi * LANES + lane) as u32,
                        t,
                    });
                }
            }
        }
    }
}

impl Visitor for ClosestBundle<'_> {
    const ORDERED: bool = true;

    #[inline(always)]
    fn bound(&self) -> f32 {
        self.bound
    }

    #[inline(always)]
    fn leaf(&mut self, packets: &[TrianglePacket], first: usize) -> bool {
        for (k, p) in packets.iter().enumerate() {
            for lane in 0..LANES {
                if p.ids[lane] != PAD {
                    // SAFETY: a `ClosestBundle` is only made in `closest_hits`, which runs only
                    // where the CPU has AVX2.
                    unsafe { self.test_triangle(p, first + k, lane) };
                }
            }
        }
        self.bound = self
            .rays
            .best
            .iter()
            .flatten()
            .fold(f32::NEG_INFINITY, |m, &b| m.max(b));
        false
    }
}

/// The closest hit of each of `rays` (at most [`MAX_BUNDLE`]), as `traverse::traverse` with a
/// `queries::Closest` visitor finds it for each ray alone.
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn closest_hits(
    bvh: &WideBvh,
    rays: &[Ray],
    data: HitData<'_>,
) -> [Option<Found>; MAX_BUNDLE] {
    assert!(rays.len() <= MAX_BUNDLE);
    if rays.is_empty() {
        return [None; MAX_BUNDLE];
    }
    let bundle = Bundle::new(rays);
    let mut closest = ClosestBundle::new(rays, data);
    with_stack(bvh, |stack| {
        run_loop::<Avx2BundleBoxes, _>(bvh, &bundle, &mut closest, stack)
    });
    closest.found
}

/// How many of `rays`' first rays (at least one, at most [`MAX_BUNDLE`]) to trace as one
/// bundle: those within [`COHERENT_COS`] of the first ray's direction and [`COHERENT_MM`] of its
/// origin. A bundle's cost grows with the region its rays sweep (every ray tests every leaf any
/// of them enters), so incoherent rays are better traced one at a time; the choice changes
/// only the time, never a hit.
pub(super) fn coherent_prefix(rays: &[Ray]) -> usize {
    let Some(first) = rays.first() else {
        return 0;
    };
    let near = |r: &Ray| {
        let cos = (0..3).map(|a| r.dir[a] * first.dir[a]).sum::<f32>();
        let gap = (0..3)
            .map(|a| (r.origin[a] - first.origin[a]).abs())
            .fold(0.0, f32::max);
        cos >= COHERENT_COS && gap <= COHERENT_MM
    };
    1 + rays[1..rays.len().min(MAX_BUNDLE)]
        .iter()
        .take_while(|r| near(r))
        .count()
}

/// Least cosine between a bundle's first ray and the others: 10 mrad, eight times the laser's
/// far-field divergence (1.2 mrad) plus its fan over 64 photons of 2¹⁶ (0.1 mrad).
const COHERENT_COS: f32 = 0.99995;

/// Greatest distance (mm, BVH units, per axis) between a bundle's first origin and the others:
/// the laser's rays leave within its waist radius (0.175 mm) of the emitter's axis.
const COHERENT_MM: f32 = 1.0;
