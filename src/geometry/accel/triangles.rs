//! Triangles in BVH order, four to a packet (structure of arrays), and the f32 ray–triangle
//! test that chooses the hit triangle.
//!
//! The test is Möller–Trumbore in the form of madmann91's `bvh` v2 (`e1 = v0 − v1`,
//! `e2 = v2 − v0`, `n = e1 × e2` stored), which obvhs 0.4.0's `RtTriangle::intersect` uses and
//! glassscan used before this module: every lane performs the same IEEE operations in the same
//! order (glam's SSE2 `cross` and `dot`, no fused multiply-add), so a lane's hit distance is bit
//! for bit the one the scalar test gives and the BVH chooses the triangles it chose, rays that
//! slip between two triangles at a shared edge included (the test is not watertight; changing
//! it would change which rays hit). Packets of four are tested at once with SSE2, which every
//! x86-64 CPU has (Embree's `Triangle4` with its Möller intersector is the same idea:
//! Wald et al., "Embree: a kernel framework for efficient CPU ray tracing", ACM TOG 33(4), 2014).
//!
//! Units: millimetres (see the parent module).

use glam::Vec3A;
use obvhs::ray::Ray as ObvhsRay;
use obvhs::rt_triangle::RtTriangle;

/// Lanes per packet.
pub(super) const LANES: usize = 4;

/// Input index of a padding lane (never a hit).
pub(super) const PAD: u32 = u32::MAX;

/// A ray in BVH units (mm), f32.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ray {
    pub origin: [f32; 3],
    /// Unit direction; components are never −0.0 (see `SceneAccel`'s `to_ray`).
    pub dir: [f32; 3],
    pub t_min: f32,
    pub t_max: f32,
}

/// Four triangles: base vertex, the two edges and the unnormalised normal, one array per
/// coordinate, and each lane's input triangle index ([`PAD`] for an empty lane).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(super) struct TrianglePacket {
    pub v0: [[f32; LANES]; 3],
    /// v0 − v1.
    pub e1: [[f32; LANES]; 3],
    /// v2 − v0.
    pub e2: [[f32; LANES]; 3],
    /// e1 × e2.
    pub ng: [[f32; LANES]; 3],
    pub ids: [u32; LANES],
}

impl TrianglePacket {
    /// A packet of empty lanes: zero edges (the test's determinant is 0, never a hit) and
    /// [`PAD`] ids, which every query also masks out.
    pub fn empty() -> TrianglePacket {
        TrianglePacket {
            v0: [[0.0; LANES]; 3],
            e1: [[0.0; LANES]; 3],
            e2: [[0.0; LANES]; 3],
            ng: [[0.0; LANES]; 3],
            ids: [PAD; LANES],
        }
    }

    /// Puts triangle `rt` (input index `id`) into `lane`.
    pub fn set(&mut self, lane: usize, rt: &RtTriangle, id: u32) {
        for k in 0..3 {
            self.v0[k][lane] = rt.v0[k];
            self.e1[k][lane] = rt.e1[k];
            self.e2[k][lane] = rt.e2[k];
            self.ng[k][lane] = rt.ng[k];
        }
        self.ids[lane] = id;
    }

    /// The triangle in `lane` as obvhs's type (for the barycentrics of a grazing ray).
    pub fn lane(&self, lane: usize) -> RtTriangle {
        let v = |a: &[[f32; LANES]; 3]| Vec3A::new(a[0][lane], a[1][lane], a[2][lane]);
        RtTriangle {
            v0: v(&self.v0),
            e1: v(&self.e1),
            e2: v(&self.e2),
            ng: v(&self.ng),
        }
    }

    /// Hit distances of the four lanes and the mask of lanes hit with t in
    /// [`ray.t_min`, `t_max`] (bit i for lane i); padding lanes are not in the mask.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> ([f32; LANES], u32) {
        #[cfg(target_arch = "x86_64")]
        {
            // SSE2 is part of x86-64.
            unsafe { self.intersect_sse2(ray, t_max) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self.intersect_scalar(ray, t_max)
        }
    }

    /// [`Self::intersect`] one lane at a time: the reference the SIMD version equals bit for bit.
    #[cfg_attr(target_arch = "x86_64", allow(dead_code))]
    pub fn intersect_scalar(&self, ray: &Ray, t_max: f32) -> ([f32; LANES], u32) {
        let mut ts = [f32::INFINITY; LANES];
        let mut mask = 0;
        for (lane, t_out) in ts.iter_mut().enumerate() {
            if self.ids[lane] == PAD {
                continue;
            }
            if let Some(t) = intersect_lane(self, lane, ray, t_max) {
                *t_out = t;
                mask |= 1 << lane;
            }
        }
        (ts, mask)
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn intersect_sse2(&self, ray: &Ray, t_max: f32) -> ([f32; LANES], u32) {
        use std::arch::x86_64::*;
        let ld = |a: &[f32; LANES]| _mm_load_ps(a.as_ptr());
        let (ox, oy, oz) = (
            _mm_set1_ps(ray.origin[0]),
            _mm_set1_ps(ray.origin[1]),
            _mm_set1_ps(ray.origin[2]),
        );
        let (dx, dy, dz) = (
            _mm_set1_ps(ray.dir[0]),
            _mm_set1_ps(ray.dir[1]),
            _mm_set1_ps(ray.dir[2]),
        );
        // c = v0 − o
        let cx = _mm_sub_ps(ld(&self.v0[0]), ox);
        let cy = _mm_sub_ps(ld(&self.v0[1]), oy);
        let cz = _mm_sub_ps(ld(&self.v0[2]), oz);
        // r = d × c
        let rx = _mm_sub_ps(_mm_mul_ps(dy, cz), _mm_mul_ps(dz, cy));
        let ry = _mm_sub_ps(_mm_mul_ps(dz, cx), _mm_mul_ps(dx, cz));
        let rz = _mm_sub_ps(_mm_mul_ps(dx, cy), _mm_mul_ps(dy, cx));
        let (nx, ny, nz) = (ld(&self.ng[0]), ld(&self.ng[1]), ld(&self.ng[2]));
        let dot = |ax: __m128, ay: __m128, az: __m128, bx: __m128, by: __m128, bz: __m128| {
            _mm_add_ps(
                _mm_add_ps(_mm_mul_ps(ax, bx), _mm_mul_ps(ay, by)),
                _mm_mul_ps(az, bz),
            )
        };
        let inv_det = _mm_div_ps(_mm_set1_ps(1.0), dot(nx, ny, nz, dx, dy, dz));
        let u = _mm_mul_ps(
            dot(
                rx,
                ry,
                rz,
                ld(&self.e2[0]),
                ld(&self.e2[1]),
                ld(&self.e2[2]),
            ),
            inv_det,
        );
        let v = _mm_mul_ps(
            dot(
                rx,
                ry,
                rz,
                ld(&self.e1[0]),
                ld(&self.e1[1]),
                ld(&self.e1[2]),
            ),
            inv_det,
        );
        let w = _mm_sub_ps(_mm_sub_ps(_mm_set1_ps(1.0), u), v);
        let t = _mm_mul_ps(dot(nx, ny, nz, cx, cy, cz), inv_det);
        // Valid: inv_det ≠ 0 (true for NaN, as the scalar `!=`), no sign bit on u, v, w
        // (−0.0 is a miss, as in the scalar test), t_min ≤ t ≤ t_max (false for NaN).
        let signs = _mm_movemask_ps(_mm_or_ps(_mm_or_ps(u, v), w)) as u32;
        let nonzero = _mm_movemask_ps(_mm_cmpneq_ps(inv_det, _mm_setzero_ps())) as u32;
        let in_range = _mm_movemask_ps(_mm_and_ps(
            _mm_cmpge_ps(t, _mm_set1_ps(ray.t_min)),
            _mm_cmple_ps(t, _mm_set1_ps(t_max)),
        )) as u32;
        let ids = _mm_load_si128(self.ids.as_ptr() as *const __m128i);
        let pad = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(
            ids,
            _mm_set1_epi32(PAD as i32),
        ))) as u32;
        let mask = !signs & nonzero & in_range & !pad & 0xF;
        let mut ts = [0.0f32; LANES];
        _mm_storeu_ps(ts.as_mut_ptr(), t);
        (ts, mask)
    }
}

/// One lane of the test, exactly obvhs 0.4.0's `RtTriangle::intersect` (with glam's SSE2
/// `cross` x = a.y·b.z − a.z·b.y and `dot` (x·x' + y·y') + z·z').
fn intersect_lane(p: &TrianglePacket, lane: usize, ray: &Ray, t_max: f32) -> Option<f32> {
    let g = |a: &[[f32; LANES]; 3]| [a[0][lane], a[1][lane], a[2][lane]];
    let (v0, e1, e2, ng) = (g(&p.v0), g(&p.e1), g(&p.e2), g(&p.ng));
    let d = ray.dir;
    let c = [
        v0[0] - ray.origin[0],
        v0[1] - ray.origin[1],
        v0[2] - ray.origin[2],
    ];
    let r = [
        d[1] * c[2] - d[2] * c[1],
        d[2] * c[0] - d[0] * c[2],
        d[0] * c[1] - d[1] * c[0],
    ];
    let dot = |a: [f32; 3], b: [f32; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let inv_det = 1.0 / dot(ng, d);
    let u = dot(r, e2) * inv_det;
    let v = dot(r, e1) * inv_det;
    let w = 1.0 - u - v;
    let signs = u.to_bits() | v.to_bits() | w.to_bits();
    if inv_det != 0.0 && signs & 0x8000_0000 == 0 {
        let t = dot(ng, c) * inv_det;
        if t >= ray.t_min && t <= t_max {
            return Some(t);
        }
    }
    None
}

/// Asks the CPU to fetch `*r` into the cache (a hint; no effect on results).
#[inline(always)]
pub(super) fn prefetch<T>(r: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = r as *const T as *const i8;
        let n = std::mem::size_of::<T>();
        let mut off = 0;
        while off < n {
            // SAFETY: a prefetch never faults; the addresses are inside `*r`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.add(off)) };
            off += 64;
        }
        // SAFETY: as above (the last byte, whose line the loop may not have reached).
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p.add(n - 1)) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = r;
}

/// The ray as obvhs's type (origin, direction and range; the reciprocal is unused here).
pub(super) fn obvhs_ray(ray: &Ray) -> ObvhsRay {
    ObvhsRay {
        origin: Vec3A::from(ray.origin),
        direction: Vec3A::from(ray.dir),
        inv_direction: Vec3A::ONE,
        tmin: ray.t_min,
        tmax: ray.t_max,
    }
}

/// obvhs's f32 barycentrics (u, v) of the ray on `rt` (p = (1−u−v)·v0 + u·v1 + v·v2), used
/// only where the f64 completion finds the ray parallel to the triangle's plane.
pub(super) fn barycentric(rt: &RtTriangle, ray: &Ray) -> (f32, f32) {
    let b = rt.compute_barycentric(&obvhs_ray(ray));
    (b.x, b.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every lane of the SSE2 test equals obvhs's scalar `RtTriangle::intersect` bit for bit,
    /// including rays through shared edges and vertices, grazing rays and degenerate triangles.
    #[test]
    fn packet_test_equals_obvhs_bit_for_bit() {
        let h = |k: u64| {
            let mut x = k.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03;
            x ^= x >> 31;
            x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
            x ^= x >> 29;
            (x >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut checked = 0;
        for i in 0..20_000u64 {
            let k = i * 32;
            // Vertices on a coarse grid so that edges and vertices are often hit exactly.
            let q = |j: u64| (h(k + j) * 8.0).floor() - 4.0;
            let vert = |j: u64| Vec3A::new(q(j), q(j + 1), q(j + 2) * 0.25);
            let tris = [vert(0), vert(3), vert(6), vert(9), vert(12)];
            let rts = [
                RtTriangle::new(tris[0], tris[1], tris[2]),
                RtTriangle::new(tris[2], tris[1], tris[3]),
                RtTriangle::new(tris[0], tris[0], tris[4]),
                RtTriangle::new(tris[3], tris[4], tris[0]),
            ];
            let mut p = TrianglePacket::empty();
            for (lane, rt) in rts.iter().enumerate() {
                p.set(lane, rt, lane as u32);
            }
            let origin = Vec3A::new(q(15) * 0.5, q(16) * 0.5, 5.0 + q(17));
            let target = Vec3A::new(q(18) * 0.5, q(19) * 0.5, q(20) * 0.25);
            let dir = (target - origin).normalize_or_zero() + Vec3A::ZERO;
            if dir == Vec3A::ZERO {
                continue;
            }
            let ray = Ray {
                origin: origin.into(),
                dir: dir.into(),
                t_min: 0.0,
                t_max: 100.0,
            };
            let obvhs_ray = ObvhsRay::new(origin, dir, 0.0, 100.0);
            let (ts, mask) = p.intersect(&ray, 100.0);
            let (ts_scalar, mask_scalar) = p.intersect_scalar(&ray, 100.0);
            assert_eq!(mask, mask_scalar);
            for (lane, rt) in rts.iter().enumerate() {
                let t = rt.intersect(&obvhs_ray);
                let hit = mask & (1 << lane) != 0;
                assert_eq!(hit, t.is_finite(), "case {i} lane {lane}");
                if hit {
                    assert_eq!(ts[lane].to_bits(), t.to_bits(), "case {i} lane {lane}");
                    assert_eq!(ts_scalar[lane].to_bits(), t.to_bits());
                    checked += 1;
                }
            }
        }
        assert!(checked > 5_000, "only {checked} hits compared");
    }
}
