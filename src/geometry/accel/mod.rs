//! Ray queries against the whole scene: an 8-wide BVH of our own, built from obvhs's binary
//! BVH (the only module that names obvhs).
//!
//! - `build.rs`: obvhs's PLOC binary BVH (`medium_build`, leaves of at most four triangles)
//!   collapsed into nodes of eight children by Ylitie et al.'s SAH dynamic programme (HPG
//!   2017), their boxes as structure of arrays; the triangles copied in BVH order into packets
//!   of four.
//! - `bundle.rs`: up to 64 coherent rays (the laser fan's) traversed as one bundle, its boxes
//!   tested with interval bounds over the rays, each triangle of a leaf against eight rays at
//!   once; every hit the single ray's bit for bit.
//! - `traverse.rs`: single-ray traversal, eight boxes per AVX2 instruction (SSE2 or scalar
//!   where AVX2 is missing, chosen at run time), near to far, a fixed stack, a conservative
//!   f32 box test.
//! - `triangles.rs`: the packets and their f32 test, bit for bit obvhs 0.4.0's Möller–Trumbore.
//! - `queries.rs`: closest hit, closest hit leaving a triangle, any hit.
//!
//! The f32 traversal only *chooses the triangle*: `make_hit` recomputes the distance, point
//! and barycentrics in f64 from each triangle's exact data. Ties (equal f32 distances) go to the
//! lower input index, so the choice is the brute-force loop's, whatever the BVH's layout; the
//! exception is a ray with a zero direction component lying exactly in a box's face, whose box
//! test gives 0 for that face (0·(1/d)), so the box is culled and a triangle it meets only on
//! that face (an edge or vertex shared with the next box's triangles in a closed mesh, the
//! same point) is not chosen (as in any slab test with a reciprocal kept finite, such as
//! Embree's `rcp_safe`; test `bundles_of_rays_hit_what_each_ray_hits`).
//!
//! Units: the BVH sees millimetres, not metres. f32 resolves ~0.06 µm over a metre in mm; the
//! earlier obvhs CWBVH also clamped box entry distances to 10⁻⁴ units, which in metres culled
//! every box a ray left within 0.1 mm of its origin (a ray from a table 10 µm under a glass pane
//! missed the pane). This BVH culls nothing near the origin; the unit stays because the f32
//! triangle test must round exactly as before to choose the same triangles (outputs stay byte
//! for byte what they were), hits are refined in f64 anyway, and `limits` bounds scene lengths
//! for f32 in these units.
//!
//! Rays that leave a surface start at the exact hit point and skip the triangle they leave
//! (`closest_hit_leaving`), so no offset moves a ray's line.

mod build;
// std::arch intrinsics (SIMD loads, AVX2 behind runtime detection): the crate's only unsafe code.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod bundle;
mod queries;
#[allow(unsafe_code)]
mod traverse;
#[allow(unsafe_code)]
mod triangles;

use glam::Vec3A;
use nalgebra::{Point3, Vector3};
use obvhs::rt_triangle::RtTriangle;
use obvhs::triangle::Triangle;

use self::build::WideBvh;
use self::queries::{Any, Closest, Found, HitData, Leaving};
use self::traverse::{traverse, Simd};
use self::triangles::{Ray, LANES};
use super::mesh::SurfacePart;

/// One triangle of the scene in the base frame, with what it belongs to.
#[derive(Clone, Copy, Debug)]
pub struct SceneTriangle {
    /// Vertices (m), counter-clockwise seen from outside.
    pub vertices: [Point3<f64>; 3],
    /// Smooth vertex normals (unit), or `None` to shade with the geometric normal.
    pub normals: Option<[Vector3<f64>; 3]>,
    /// Index of the object in the world.
    pub object: u32,
    /// Index of the material in the world.
    pub material: u32,
    /// Which part of the object.
    pub part: SurfacePart,
}

/// A ray–scene intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) ray direction (m).
    pub t: f64,
    /// Hit point (m).
    pub point: Point3<f64>,
    /// Geometric normal of the triangle, outward (unit).
    pub geometric_normal: Vector3<f64>,
    /// Interpolated shading normal, outward (unit); equals the geometric normal for flat meshes.
    pub shading_normal: Vector3<f64>,
    /// Barycentric coordinates (u, v) with p = (1−u−v)·v0 + u·v1 + v·v2.
    pub barycentric: [f64; 2],
    /// The triangle's object index.
    pub object: u32,
    /// The triangle's material index.
    pub material: u32,
    /// The triangle's surface part.
    pub part: SurfacePart,
    /// Index of the triangle in the input slice given to [`SceneAccel::build`].
    pub triangle: u32,
}

/// An 8-wide BVH over the scene's triangles.
pub struct SceneAccel {
    bvh: WideBvh,
    /// The node test this CPU runs.
    simd: Simd,
    input: Vec<SceneTriangle>,
    /// The f64 quantities of each input triangle that completing a hit needs, computed once
    /// (the same expressions as before, so hits are bit for bit what they were).
    exact: Vec<ExactTriangle>,
}

/// One triangle's f64 edge vectors, normals and Gram matrix (192 bytes, aligned so that they
/// span three cache lines, not four).
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
struct ExactTriangle {
    a: Point3<f64>,
    e1: Vector3<f64>,
    e2: Vector3<f64>,
    /// e1 × e2 (unnormalised).
    cross: Vector3<f64>,
    /// The unit geometric normal.
    normal: Vector3<f64>,
    /// |e1 × e2|.
    cross_norm: f64,
    d00: f64,
    d01: f64,
    d11: f64,
    /// d00·d11 − d01².
    det: f64,
    /// How the shading normal varies over the triangle.
    shading: Shading,
}

/// A triangle's shading normal.
#[derive(Clone, Copy, Debug)]
enum Shading {
    /// Interpolated from three vertex normals that differ (a smooth, curved surface).
    Smooth,
    /// The same at every point: the three vertex normals are one vector (a flat facet of a
    /// smooth-shaded mesh: a pane's faces, a seamed edge's arrisses), this unit vector. The
    /// interpolation would give it back to rounding; taking it as it is skips a normalisation
    /// per hit (issue 11).
    Uniform(Vector3<f64>),
}

impl ExactTriangle {
    fn new(t: &SceneTriangle) -> ExactTriangle {
        let [a, b, c] = t.vertices;
        let (e1, e2) = (b - a, c - a);
        let cross = e1.cross(&e2);
        let (d00, d01, d11) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
        let normal = cross.normalize();
        let shading = match t.normals {
            Some([na, nb, nc]) if na != nb || na != nc => Shading::Smooth,
            Some([na, ..]) => Shading::Uniform(na.try_normalize(1e-12).unwrap_or(normal)),
            None => Shading::Uniform(normal),
        };
        ExactTriangle {
            a,
            e1,
            e2,
            cross,
            normal,
            cross_norm: cross.norm(),
            d00,
            d01,
            d11,
            det: d00 * d11 - d01 * d01,
            shading,
        }
    }

    /// Whether a ray along `dir` meets the triangle's plane steeply enough for the hit to be
    /// recomputed in f64 (Möller–Trumbore's denominator against the triangle's size); grazing
    /// rays keep the f32 test's values.
    fn completes_in_f64(&self, dir: &Vector3<f64>) -> bool {
        dir.dot(&self.cross).abs() > 1e-12 * self.cross_norm
    }
}

/// BVH units per metre (see the module documentation).
const BVH_UNITS_PER_M: f64 = 1e3;

/// Candidates of [`SceneAccel::closest_hit_leaving`] that the f32 test puts closer than this
/// (m) are tested again in f64: f32 rounding of a neighbour's plane at ~1 m from the base
/// frame's origin is ~0.1 µm, and ≤ 3 µm along a ray 2° from grazing.
pub const NEAR_HIT_M: f64 = 1e-5;

/// Least distance (m) from a surface at which a ray leaving it may hit another triangle:
/// far above f64 rounding of hit points (~1e-16 m) and far below any gap in a scene (the shipped
/// scenes keep 10 µm between objects). A ray's line is never moved; it only skips this much.
pub const SELF_HIT_T_MIN_M: f64 = 1e-8;

/// The least barycentric coordinate of a hit that [`SceneAccel::hit_on_triangle`] accepts: f32
/// resolves about 1e-7 of a triangle, so the traversal's f32 test takes such a hit for this
/// triangle too (not its neighbour across an edge).
pub const INTERIOR_MARGIN: f64 = 1e-5;

/// A point in BVH units (f32 mm).
fn to_bvh(p: &Point3<f64>) -> [f32; 3] {
    let p = p * BVH_UNITS_PER_M;
    [p.x as f32, p.y as f32, p.z as f32]
}

fn to_ray(origin: &Point3<f64>, dir: &Vector3<f64>, t_min: f64, t_max: f64) -> Ray {
    // `+ 0.0` turns a negative zero into a positive one. obvhs 0.4.0's CWBVH traversal missed
    // every box for a direction component of −0.0; this BVH's box test does not care, but the
    // triangle test's sign checks see the zero's sign, and keeping +0.0 keeps every hit what it
    // was (regression test below).
    Ray {
        origin: to_bvh(origin),
        dir: [dir.x as f32 + 0.0, dir.y as f32 + 0.0, dir.z as f32 + 0.0],
        t_min: (t_min * BVH_UNITS_PER_M) as f32,
        t_max: (t_max * BVH_UNITS_PER_M).min(f32::MAX as f64) as f32,
    }
}

impl ExactTriangle {
    /// Distance (m) along `origin + t·dir` to the triangle in f64 (Möller–Trumbore), or `None`
    /// if the ray misses it or runs parallel to it.
    fn intersect(&self, origin: &Point3<f64>, dir: &Vector3<f64>) -> Option<f64> {
        let ExactTriangle { a, e1, e2, .. } = *self;
        let p = dir.cross(&e2);
        let det = e1.dot(&p);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let s = origin - a;
        let u = s.dot(&p) * inv;
        let q = s.cross(&e1);
        let v = dir.dot(&q) * inv;
        if u < 0.0 || v < 0.0 || u + v > 1.0 {
            return None;
        }
        Some(e2.dot(&q) * inv)
    }
}

impl SceneAccel {
    /// Builds the BVH. Panics on an empty slice: the scene loader refuses empty scenes.
    pub fn build(triangles: Vec<SceneTriangle>) -> SceneAccel {
        assert!(
            !triangles.is_empty(),
            "cannot build a BVH over no triangles"
        );
        let tris: Vec<Triangle> = triangles
            .iter()
            .map(|t| {
                let [v0, v1, v2] = t.vertices.map(|v| Vec3A::from(to_bvh(&v)));
                Triangle { v0, v1, v2 }
            })
            .collect();
        let bvh = build::build(&tris);
        let exact = triangles.iter().map(ExactTriangle::new).collect();
        SceneAccel {
            bvh,
            simd: Simd::detect(),
            input: triangles,
            exact,
        }
    }

    fn hit_data(&self) -> HitData<'_> {
        HitData {
            exact: &self.exact,
            input: &self.input,
        }
    }

    /// Number of input triangles.
    pub fn triangle_count(&self) -> usize {
        self.input.len()
    }

    /// The input triangle `i`.
    pub fn triangle(&self, i: u32) -> &SceneTriangle {
        &self.input[i as usize]
    }

    /// The closest hit along `origin + t·dir` with t in [t_min, t_max]; `dir` must be unit length.
    ///
    /// The f32 test decides: t = t_max itself is not a hit, and of two triangles at the same
    /// f32 distance the one with the lower input index is chosen.
    pub fn closest_hit(
        &self,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        t_min: f64,
        t_max: f64,
    ) -> Option<Hit> {
        let ray = to_ray(origin, dir, t_min, t_max);
        let mut q = Closest::new(&ray, self.hit_data());
        traverse(&self.bvh, self.simd, &ray, &mut q);
        q.found().map(|f| self.make_bvh_hit(f, &ray, origin, dir))
    }

    /// [`SceneAccel::closest_hit`] of each ray `(origin, unit dir)`, equal to it bit for bit,
    /// into `hits` (cleared first). Where the CPU has AVX2, runs of up to 64 consecutive rays
    /// that leave within a millimetre and 10 mrad of the run's first (the laser fan's rays in fan
    /// order) are traversed as one bundle (`bundle`): 2.4–2.9× the single-ray rate on the laser
    /// fan of `benches/bvh.rs`. Other rays are traced one at a time.
    pub fn closest_hits(
        &self,
        rays: &[(Point3<f64>, Vector3<f64>)],
        t_min: f64,
        t_max: f64,
        hits: &mut Vec<Option<Hit>>,
    ) {
        hits.clear();
        #[cfg(target_arch = "x86_64")]
        if self.simd == Simd::Avx2 {
            let mut bvh_rays =
                [to_ray(&Point3::origin(), &Vector3::z(), 0.0, 1.0); bundle::MAX_BUNDLE];
            for chunk in rays.chunks(bundle::MAX_BUNDLE) {
                for (r, (o, d)) in bvh_rays.iter_mut().zip(chunk) {
                    *r = to_ray(o, d, t_min, t_max);
                }
                let mut start = 0;
                while start < chunk.len() {
                    let end = start + bundle::coherent_prefix(&bvh_rays[start..chunk.len()]);
                    self.trace_bundle(&chunk[start..end], &bvh_rays[start..end], hits);
                    start = end;
                }
            }
            return;
        }
        hits.extend(
            rays.iter()
                .map(|(o, d)| self.closest_hit(o, d, t_min, t_max)),
        );
    }

    /// Appends the closest hits of `rays` (at most `bundle::MAX_BUNDLE`; `bvh_rays` the same
    /// rays made by `to_ray`) traversed as one bundle, or alone if there is one. AVX2 only.
    #[cfg(target_arch = "x86_64")]
    fn trace_bundle(
        &self,
        rays: &[(Point3<f64>, Vector3<f64>)],
        bvh_rays: &[Ray],
        hits: &mut Vec<Option<Hit>>,
    ) {
        debug_assert_eq!(self.simd, Simd::Avx2);
        if let [(o, d)] = rays {
            let mut q = Closest::new(&bvh_rays[0], self.hit_data());
            traverse(&self.bvh, self.simd, &bvh_rays[0], &mut q);
            hits.push(q.found().map(|f| self.make_bvh_hit(f, &bvh_rays[0], o, d)));
            return;
        }
        // SAFETY: `Simd::Avx2` is only chosen where the CPU has AVX2.
        #[allow(unsafe_code)]
        let found = unsafe { bundle::closest_hits(&self.bvh, bvh_rays, self.hit_data()) };
        hits.extend(
            (found.iter().zip(bvh_rays).zip(rays))
                .map(|((f, ray), (o, d))| f.map(|f| self.make_bvh_hit(f, ray, o, d))),
        );
    }

    /// The closest hit along a ray that starts exactly on a surface, at `origin` on triangle
    /// `leaving` (an index as in [`Hit::triangle`]), with t in (0, t_max].
    ///
    /// Secondary rays start at the exact f64 hit point, not offset from the surface: an offset
    /// along the normal moves a refracted ray sideways by ε·(sin θ + cos θ·tan θ_t) per interface,
    /// which triangulation magnifies about threefold (2–9 µm of range through a 6 mm plate
    /// tilted 30–60° with ε = 2 µm, found by an independent check). Instead the triangle just
    /// left is skipped, and candidates that the f32 test puts within [`NEAR_HIT_M`] of the
    /// origin (its neighbours, which the ray leaves at t ≈ 0 up to f32 rounding) are tested
    /// again in f64 and kept only beyond [`SELF_HIT_T_MIN_M`] along the ray: the ray's line is
    /// never moved.
    pub fn closest_hit_leaving(
        &self,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        leaving: u32,
        t_max: f64,
    ) -> Option<Hit> {
        let ray = to_ray(origin, dir, 0.0, t_max);
        let near = (NEAR_HIT_M * BVH_UNITS_PER_M) as f32;
        let mut q = Leaving::new(
            &ray,
            leaving,
            near,
            origin,
            dir,
            self.hit_data(),
            (SELF_HIT_T_MIN_M, t_max),
            BVH_UNITS_PER_M,
        );
        traverse(&self.bvh, self.simd, &ray, &mut q);
        q.found().map(|f| self.make_bvh_hit(f, &ray, origin, dir))
    }

    /// The hit of a ray on triangle `tri` alone, completed in f64 exactly as a BVH query's hit
    /// on that triangle is, when the ray meets it well inside (each barycentric coordinate at
    /// least [`INTERIOR_MARGIN`], where the f32 test of the traversal cannot disagree) at t in
    /// [`NEAR_HIT_M`], `t_max`], and not grazing. Nothing is said about other triangles in the
    /// way: for following a chain of triangles a BVH query found, with the chain checked by
    /// BVH queries afterwards (`transport::connect`).
    pub fn hit_on_triangle(
        &self,
        tri: u32,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        t_max: f64,
    ) -> Option<Hit> {
        self.hit_on_triangle_within(tri, origin, dir, NEAR_HIT_M, t_max)
    }

    /// [`SceneAccel::hit_on_triangle`] with the least distance `t_min` instead of
    /// [`NEAR_HIT_M`]: where nothing else can be hit, a query from a surface keeps a hit down
    /// to [`SELF_HIT_T_MIN_M`] (its near candidates are re-tested in f64).
    pub fn hit_on_triangle_within(
        &self,
        tri: u32,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        t_min: f64,
        t_max: f64,
    ) -> Option<Hit> {
        if !self.exact[tri as usize].completes_in_f64(dir) {
            return None;
        }
        let hit = self.make_hit(tri, origin, dir, || (f64::NAN, f32::NAN, f32::NAN));
        let [u, v] = hit.barycentric;
        let inside = u >= INTERIOR_MARGIN && v >= INTERIOR_MARGIN && 1.0 - u - v >= INTERIOR_MARGIN;
        (inside && hit.t >= t_min && hit.t <= t_max).then_some(hit)
    }

    /// Whether anything blocks `origin + t·dir` for t in [t_min, t_max) (`dir` unit length).
    pub fn occluded(
        &self,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        t_min: f64,
        t_max: f64,
    ) -> bool {
        let ray = to_ray(origin, dir, t_min, t_max);
        let mut q = Any::new(&ray);
        traverse(&self.bvh, self.simd, &ray, &mut q);
        q.hit
    }

    /// Reference closest hit by testing every triangle (for tests and debugging), with obvhs's
    /// scalar f32 test: the least (t, input index) with t in [t_min, t_max].
    pub fn closest_hit_brute_force(
        &self,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        t_min: f64,
        t_max: f64,
    ) -> Option<Hit> {
        let ray = to_ray(origin, dir, t_min, t_max);
        let rt_of = |t: &SceneTriangle| {
            let [v0, v1, v2] = t.vertices.map(|v| Vec3A::from(to_bvh(&v)));
            RtTriangle::new(v0, v1, v2)
        };
        let obvhs_ray = triangles::obvhs_ray(&ray);
        let mut best: Option<(usize, f32)> = None;
        for (i, t) in self.input.iter().enumerate() {
            let d = rt_of(t).intersect(&obvhs_ray);
            if d.is_finite() && best.is_none_or(|(_, b)| d < b) {
                best = Some((i, d));
            }
        }
        best.map(|(i, d)| {
            let (u, v) = triangles::barycentric(&rt_of(&self.input[i]), &ray);
            self.make_hit(i as u32, origin, dir, || (d as f64 / BVH_UNITS_PER_M, u, v))
        })
    }

    /// How the unit shading normal of triangle `tri` (an index as in [`Hit::triangle`]) at
    /// barycentrics `uv` changes when the point moves by `dp` in the triangle's plane: the
    /// derivative of normalize(n_a·(1 − u − v) + n_b·u + n_c·v), with (du, dv) from `dp` by
    /// the triangle's Gram matrix; zero on a flat-shaded triangle. What ray differentials
    /// through smooth-shaded glass need (`transport::connect`'s analytic Jacobian).
    pub fn shading_normal_change(&self, tri: u32, uv: [f64; 2], dp: &Vector3<f64>) -> Vector3<f64> {
        let x = &self.exact[tri as usize];
        let (Shading::Smooth, Some([na, nb, nc])) = (x.shading, &self.input[tri as usize].normals)
        else {
            return Vector3::zeros();
        };
        let (d20, d21) = (dp.dot(&x.e1), dp.dot(&x.e2));
        let du = (x.d11 * d20 - x.d01 * d21) / x.det;
        let dv = (x.d00 * d21 - x.d01 * d20) / x.det;
        let [u, v] = uv;
        let m = na * (1.0 - u - v) + nb * u + nc * v;
        let len = m.norm();
        if len < 1e-12 {
            return Vector3::zeros();
        }
        let n = m / len;
        let dm = (nb - na) * du + (nc - na) * dv;
        (dm - n * n.dot(&dm)) / len
    }

    /// [`Self::make_hit`] for the triangle the traversal `found`; its f32 barycentrics are
    /// computed only if they are needed.
    fn make_bvh_hit(
        &self,
        found: Found,
        ray: &Ray,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
    ) -> Hit {
        self.make_hit(found.id, origin, dir, || {
            let slot = found.slot as usize;
            let rt = self.bvh.packets[slot / LANES].lane(slot % LANES);
            let (u, v) = triangles::barycentric(&rt, ray);
            (found.t as f64 / BVH_UNITS_PER_M, u, v)
        })
    }

    /// Completes a hit found in f32 on input triangle `tri`: the distance, point and
    /// barycentrics are recomputed in f64 against the triangle's f64 vertices, so hit points are
    /// exact to f64 rounding (what the Newton solves of connection paths through glass need).
    /// `f32_hit` gives the f32 test's (t in m, u, v), used only for a ray that grazes the plane.
    fn make_hit(
        &self,
        tri: u32,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        f32_hit: impl FnOnce() -> (f64, f32, f32),
    ) -> Hit {
        let st = &self.input[tri as usize];
        let x = &self.exact[tri as usize];
        let geometric_normal = x.normal;
        let (t, u, v) = if x.completes_in_f64(dir) {
            let denom = dir.dot(&x.cross);
            // Möller–Trumbore in f64 on the same triangle.
            let t = (x.a - origin).dot(&x.cross) / denom;
            let p = origin + dir * t;
            let w = p - x.a;
            let d20 = w.dot(&x.e1);
            let d21 = w.dot(&x.e2);
            (
                t,
                (x.d11 * d20 - x.d01 * d21) / x.det,
                (x.d00 * d21 - x.d01 * d20) / x.det,
            )
        } else {
            let (t, u, v) = f32_hit();
            (t, u as f64, v as f64)
        };
        let shading_normal = match (x.shading, &st.normals) {
            (Shading::Uniform(n), _) => n,
            (Shading::Smooth, Some([na, nb, nc])) => {
                let n = na * (1.0 - u - v) + nb * u + nc * v;
                n.try_normalize(1e-12).unwrap_or(geometric_normal)
            }
            (Shading::Smooth, None) => unreachable!("a smooth triangle has vertex normals"),
        };
        Hit {
            t,
            point: origin + dir * t,
            geometric_normal,
            shading_normal,
            barycentric: [u, v],
            object: st.object,
            material: st.material,
            part: st.part,
            triangle: tri,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3], object: u32) -> SceneTriangle {
        SceneTriangle {
            vertices: [a.into(), b.into(), c.into()],
            normals: None,
            object,
            material: 0,
            part: SurfacePart::Solid,
        }
    }

    /// A deterministic cloud of small random triangles (hash-based, no RNG crate).
    fn cloud(n: usize) -> Vec<SceneTriangle> {
        let h = |k: u64| {
            let mut x = k.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03;
            x ^= x >> 31;
            x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
            x ^= x >> 29;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|i| {
                let k = i as u64 * 16;
                let c = [h(k) - 0.5, h(k + 1) - 0.5, h(k + 2) - 0.5];
                let p = |j: u64| {
                    [
                        c[0] + 0.05 * (h(k + j) - 0.5),
                        c[1] + 0.05 * (h(k + j + 1) - 0.5),
                        c[2] + 0.05 * (h(k + j + 2) - 0.5),
                    ]
                };
                tri(p(3), p(6), p(9), i as u32)
            })
            .collect()
    }

    #[test]
    fn bvh_matches_brute_force() {
        let mut accel = SceneAccel::build(cloud(2000));
        for simd in Simd::available() {
            accel.simd = simd;
            let mut hits = 0;
            for i in 0..2000 {
                let a = i as f64 * 0.618_033_988_75;
                let b = i as f64 * 0.754_877_666_25;
                let dir = Vector3::new(a.sin() * b.cos(), a.sin() * b.sin(), a.cos()).normalize();
                let origin = Point3::new(0.01 * (i % 7) as f64, -0.02, 0.003 * (i % 5) as f64);
                let fast = accel.closest_hit(&origin, &dir, 0.0, 10.0);
                let slow = accel.closest_hit_brute_force(&origin, &dir, 0.0, 10.0);
                match (fast, slow) {
                    (Some(f), Some(s)) => {
                        hits += 1;
                        // Ties go to the lower index in both, so the same triangle and the
                        // same f64 completion.
                        assert_eq!(f.triangle, s.triangle, "{simd:?} ray {i}");
                        assert_eq!(f.t.to_bits(), s.t.to_bits(), "{simd:?} ray {i}");
                    }
                    (None, None) => {}
                    (f, s) => panic!("{simd:?} ray {i}: bvh {f:?} vs brute force {s:?}"),
                }
                assert_eq!(
                    accel.occluded(&origin, &dir, 0.0, 10.0),
                    slow.is_some(),
                    "{simd:?} ray {i}"
                );
            }
            assert!(
                hits > 100,
                "only {hits} hits: the test does not exercise the BVH"
            );
        }
    }

    /// `closest_hit_leaving` by testing every triangle: the least (t, index) over triangles
    /// other than `leaving` whose f32 distance is in [0, t_max) after near candidates are
    /// replaced by their f64 distance (kept only in [SELF_HIT_T_MIN_M, t_max]).
    fn leaving_brute_force(
        accel: &SceneAccel,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        leaving: u32,
        t_max: f64,
    ) -> Option<(u32, f32)> {
        let ray = to_ray(origin, dir, 0.0, t_max);
        let obvhs_ray = triangles::obvhs_ray(&ray);
        let near = (NEAR_HIT_M * BVH_UNITS_PER_M) as f32;
        let mut best: Option<(u32, f32)> = None;
        for (i, tri) in accel.input.iter().enumerate() {
            if i as u32 == leaving {
                continue;
            }
            let [v0, v1, v2] = tri.vertices.map(|v| Vec3A::from(to_bvh(&v)));
            let mut t = RtTriangle::new(v0, v1, v2).intersect(&obvhs_ray);
            if !t.is_finite() {
                continue;
            }
            if t < near {
                match accel.exact[i].intersect(origin, dir) {
                    Some(t64) if (SELF_HIT_T_MIN_M..=t_max).contains(&t64) => {
                        t = (t64 * BVH_UNITS_PER_M) as f32;
                    }
                    _ => continue,
                }
            }
            if t < ray.t_max && best.is_none_or(|(_, b)| t < b) {
                best = Some((i as u32, t));
            }
        }
        best
    }

    /// A wavy height field of n × n quads, two triangles each, over [−0.5, 0.5]² (m): shared
    /// edges and vertices everywhere.
    fn height_field(n: usize) -> Vec<SceneTriangle> {
        let h = |i: usize, j: usize| {
            let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            Point3::new(x, y, 0.01 * (9.0 * x).sin() * (7.0 * y).cos())
        };
        let mut tris = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (h(i, j), h(i + 1, j), h(i + 1, j + 1), h(i, j + 1));
                tris.push(tri(a.into(), b.into(), c.into(), 0));
                tris.push(tri(a.into(), c.into(), d.into(), 0));
            }
        }
        tris
    }

    /// A uniform number in [0, 1) hashed from `k` (SplitMix64's finaliser).
    fn hash_uniform(k: u64) -> f64 {
        let mut x = k.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        x ^= x >> 29;
        x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x ^= x >> 32;
        (x >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Rays leaving a height field (shared edges and vertices, neighbours at t ≈ 0) from exact
    /// points on its triangles, at its vertices and edges included, in every direction: the
    /// BVH chooses what brute force chooses, with every node test.
    #[test]
    fn leaving_rays_match_brute_force() {
        let mut tris = height_field(24);
        // A second sheet 3 µm above the first, so that rays meet it within NEAR_HIT_M.
        let lifted: Vec<SceneTriangle> = tris
            .iter()
            .map(|t| {
                let mut t = *t;
                t.vertices = t.vertices.map(|v| v + Vector3::new(0.0, 0.0, 3e-6));
                t.object = 1;
                t
            })
            .collect();
        tris.extend(lifted);
        let mut accel = SceneAccel::build(tris);
        let count = accel.triangle_count() as u64;
        let mut compared = 0;
        for simd in Simd::available() {
            accel.simd = simd;
            for k in 0..3000u64 {
                let g = |d: u64| hash_uniform(k * 8 + d);
                let leaving = ((g(0) * count as f64) as u32).min(count as u32 - 1);
                let [a, b, c] = accel.input[leaving as usize].vertices;
                // Vertices, edge midpoints and interior points.
                let (u, v) = match k % 4 {
                    0 => (
                        [0.0, 1.0, 0.0][(k / 4 % 3) as usize],
                        [0.0, 0.0, 1.0][(k / 4 % 3) as usize],
                    ),
                    1 => (
                        [0.5, 0.0, 0.5][(k / 4 % 3) as usize],
                        [0.0, 0.5, 0.5][(k / 4 % 3) as usize],
                    ),
                    _ => {
                        let (u, v) = (g(1), g(2));
                        if u + v > 1.0 {
                            (1.0 - u, 1.0 - v)
                        } else {
                            (u, v)
                        }
                    }
                };
                let origin = a + (b - a) * u + (c - a) * v;
                let z = 2.0 * g(3) - 1.0;
                let phi = std::f64::consts::TAU * g(4);
                let r = (1.0 - z * z).sqrt();
                let dir = Vector3::new(r * phi.cos(), r * phi.sin(), z);
                let fast = accel.closest_hit_leaving(&origin, &dir, leaving, 2.0);
                let slow = leaving_brute_force(&accel, &origin, &dir, leaving, 2.0);
                assert_eq!(
                    fast.map(|h| h.triangle),
                    slow.map(|s| s.0),
                    "{simd:?} ray {k} leaving {leaving}"
                );
                compared += fast.is_some() as usize;
            }
        }
        assert!(compared > 2000, "only {compared} hits");
    }

    /// `hit_on_triangle` gives the very hit a BVH query gives on that triangle (every field,
    /// bit for bit) when the ray meets it well inside, and nothing near its edges, behind
    /// `t_max` or on another triangle.
    #[test]
    fn a_hit_on_a_named_triangle_is_the_bvh_query_s_hit() {
        let accel = SceneAccel::build(height_field(16));
        let (mut same, mut declined) = (0, 0);
        for k in 0..4000u64 {
            let g = |d: u64| hash_uniform(k * 8 + d);
            let origin = Point3::new(g(0) - 0.5, g(1) - 0.5, 0.3);
            let dir = Vector3::new(0.2 * (g(2) - 0.5), 0.2 * (g(3) - 0.5), -1.0).normalize();
            let Some(query) = accel.closest_hit(&origin, &dir, 0.0, 2.0) else {
                continue;
            };
            match accel.hit_on_triangle(query.triangle, &origin, &dir, 2.0) {
                Some(hit) => {
                    assert_eq!(hit, query, "ray {k}");
                    same += 1;
                }
                None => {
                    let [u, v] = query.barycentric;
                    assert!(
                        u.min(v).min(1.0 - u - v) < INTERIOR_MARGIN,
                        "ray {k}: {query:?}"
                    );
                    declined += 1;
                }
            }
            // Another triangle, and this one beyond t_max, give nothing.
            let other = (query.triangle + 1) % accel.triangle_count() as u32;
            assert!(accel.hit_on_triangle(other, &origin, &dir, 2.0).is_none());
            assert!(accel
                .hit_on_triangle(query.triangle, &origin, &dir, 0.5 * query.t)
                .is_none());
        }
        assert!(same > 3800, "{same} equal hits, {declined} declined");
        // Rays down onto the middle of a triangle's edge: declined, whichever side the query
        // takes.
        for t in (0..accel.triangle_count()).step_by(7) {
            let [a, b, _] = accel.input[t].vertices;
            let origin = Point3::from((a.coords + b.coords) * 0.5) + Vector3::new(0.0, 0.0, 0.3);
            let dir = -Vector3::z();
            let query = accel
                .closest_hit(&origin, &dir, 0.0, 2.0)
                .expect("the field is below");
            assert!(accel
                .hit_on_triangle(query.triangle, &origin, &dir, 2.0)
                .is_none());
        }
    }

    #[test]
    fn barycentrics_reconstruct_the_hit_point() {
        let accel = SceneAccel::build(vec![tri([0., 0., 1.], [1., 0., 1.], [0., 1., 1.], 0)]);
        let o = Point3::new(0.2, 0.3, 0.0);
        let h = accel.closest_hit(&o, &Vector3::z(), 0.0, 5.0).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        let [u, v] = h.barycentric;
        assert!(
            (u - 0.2).abs() < 1e-6 && (v - 0.3).abs() < 1e-6,
            "u {u} v {v}"
        );
        assert!((h.geometric_normal - Vector3::z()).norm() < 1e-12);
    }

    #[test]
    fn a_flat_facet_shades_with_its_vertex_normal_and_a_curved_one_interpolates() {
        // Both triangles lie in z = 1; the flat one's vertex normals are one tilted vector
        // (a facet of a smooth-shaded mesh), the curved one's differ.
        let n = Vector3::new(0.1, -0.2, 1.0).normalize();
        let (na, nb, nc) = (Vector3::z(), Vector3::new(0.6, 0.0, 0.8), Vector3::y());
        let mut flat = tri([0., 0., 1.], [1., 0., 1.], [0., 1., 1.], 0);
        flat.normals = Some([n; 3]);
        let mut curved = tri([2., 0., 1.], [3., 0., 1.], [2., 1., 1.], 1);
        curved.normals = Some([na, nb, nc]);
        let accel = SceneAccel::build(vec![flat, curved]);
        for (x, y) in [(0.2, 0.3), (0.05, 0.9), (0.6, 0.1)] {
            let h = accel
                .closest_hit(&Point3::new(x, y, 0.0), &Vector3::z(), 0.0, 5.0)
                .unwrap();
            let [u, v] = h.barycentric;
            let interpolated = (n * (1.0 - u - v) + n * u + n * v).normalize();
            assert_eq!(h.shading_normal, n.normalize());
            assert!((h.shading_normal - interpolated).norm() < 1e-15);
            assert_eq!(
                accel.shading_normal_change(h.triangle, h.barycentric, &Vector3::x()),
                Vector3::zeros()
            );
            let h = accel
                .closest_hit(&Point3::new(2.0 + x, y, 0.0), &Vector3::z(), 0.0, 5.0)
                .unwrap();
            let [u, v] = h.barycentric;
            let interpolated = (na * (1.0 - u - v) + nb * u + nc * v).normalize();
            assert_eq!(h.shading_normal, interpolated);
            assert!(
                accel
                    .shading_normal_change(h.triangle, h.barycentric, &Vector3::x())
                    .norm()
                    > 0.1
            );
        }
    }

    /// Rays traced in bundles give each ray's own closest hit, every field bit for bit: a
    /// coherent fan over a height field (its rays slipping through shared edges and vertices,
    /// its thin spread straddling the fan's plane), incoherent rays with mixed direction signs
    /// through a cloud, axis-aligned directions with zero components, rays that start inside
    /// the geometry, miss it or stop short of it (t_min, t_max); `closest_hits` as it splits
    /// them, and every ray forced into bundles of 64, 37, 8 and 2 whatever its neighbours.
    #[test]
    fn bundles_of_rays_hit_what_each_ray_hits() {
        let mut tris = height_field(40);
        tris.extend(cloud(1500));
        let mut accel = SceneAccel::build(tris);
        let source = Point3::new(0.013, -0.007, 0.35);
        let mut rays: Vec<(Point3<f64>, Vector3<f64>)> = (0..2003)
            .map(|i| {
                // A fan in one plane, a thin spread across it, as the laser's.
                let a = -0.6 + 1.2 * (i as f64 + 0.5) / 2003.0;
                let b = 2e-3 * (hash_uniform(i) - 0.5);
                let d = Vector3::new(a.sin(), b, -a.cos()).normalize();
                (source, d)
            })
            .collect();
        rays.extend((0..1500u64).map(|i| {
            let u = |k: u64| 2.0 * hash_uniform(7 * i + k) - 1.0;
            let origin = Point3::new(0.6 * u(1), 0.6 * u(2), 0.6 * u(3));
            let d = Vector3::new(u(4), u(5), u(6));
            (origin, d.try_normalize(1e-9).unwrap_or_else(Vector3::z))
        }));
        let axis_aligned = rays.len();
        for (k, d) in [Vector3::x(), -Vector3::y(), -Vector3::z(), Vector3::z()]
            .into_iter()
            .enumerate()
        {
            rays.extend((0..37).map(|i| {
                (
                    Point3::new(-0.4 + 0.02 * i as f64, 0.1 * k as f64 - 0.2, 0.2),
                    d,
                )
            }));
        }
        let mut hits = Vec::new();
        for (t_min, t_max) in [(0.0, 10.0), (0.1, 0.45), (0.0, 0.2)] {
            let mut ways: Vec<(Simd, Option<usize>)> =
                Simd::available().into_iter().map(|s| (s, None)).collect();
            if Simd::available().contains(&Simd::Avx2) {
                ways.extend([64, 37, 8, 2].map(|n| (Simd::Avx2, Some(n))));
            }
            for (simd, forced) in ways {
                accel.simd = simd;
                match forced {
                    None => accel.closest_hits(&rays, t_min, t_max, &mut hits),
                    #[cfg(target_arch = "x86_64")]
                    Some(n) => {
                        hits.clear();
                        for group in rays.chunks(n) {
                            let bvh_rays: Vec<Ray> = group
                                .iter()
                                .map(|(o, d)| to_ray(o, d, t_min, t_max))
                                .collect();
                            accel.trace_bundle(group, &bvh_rays, &mut hits);
                        }
                    }
                    #[cfg(not(target_arch = "x86_64"))]
                    Some(_) => unreachable!(),
                }
                assert_eq!(hits.len(), rays.len());
                let mut found = 0;
                for (i, ((o, d), h)) in rays.iter().zip(&hits).enumerate() {
                    let single = accel.closest_hit(o, d, t_min, t_max);
                    found += single.is_some() as usize;
                    if forced.is_some() && i >= axis_aligned {
                        // A ray with a zero direction component lying exactly in a box's face:
                        // the single-ray test culls the box (0·(1/d) is 0, see `traverse`), a
                        // bundle with other origins may enter it and choose another of the
                        // triangles meeting at the same point (a vertex of the height field).
                        let point = |h: &Option<Hit>| h.map(|h| h.point.coords.map(f64::to_bits));
                        assert_eq!(point(h), point(&single), "{forced:?} ray {i}");
                        continue;
                    }
                    let bits = |h: &Option<Hit>| {
                        h.map(|h| {
                            (
                                h.triangle,
                                h.t.to_bits(),
                                h.barycentric.map(f64::to_bits),
                                h.point.coords.map(f64::to_bits),
                            )
                        })
                    };
                    assert_eq!(
                        *h, single,
                        "{simd:?} {forced:?} ray {i}, t in [{t_min}, {t_max}]"
                    );
                    assert_eq!(bits(h), bits(&single), "{simd:?} {forced:?} ray {i}");
                }
                assert!(found > 100, "{found} of {} rays hit", rays.len());
            }
        }
    }

    /// Regression: a direction with a −0.0 component (`-Vector3::z()`) missed everything in
    /// obvhs 0.4.0, while the same direction written with +0.0 hit.
    #[test]
    fn directions_with_negative_zero_components_hit() {
        let mut tris = cloud(50);
        tris.push(tri(
            [-1.0, -1.0, -0.5],
            [1.0, -1.0, -0.5],
            [0.0, 1.0, -0.5],
            7,
        ));
        let accel = SceneAccel::build(tris);
        let o = Point3::new(0.0, 0.0, 0.7);
        let down: Vector3<f64> = -Vector3::z();
        assert!(down.x.is_sign_negative());
        let h = accel
            .closest_hit(&o, &down, 0.0, 5.0)
            .expect("the plane below");
        assert!((h.t - 1.2).abs() < 1e-9, "{}", h.t);
        assert!(accel.occluded(&o, &down, 0.0, 5.0));
    }

    /// Regression: obvhs culls BVH nodes left within 1e-4 scene units of the ray origin; in
    /// metres that hid a glass pane 10 µm above a table from rays leaving the table.
    #[test]
    fn surfaces_a_few_micrometres_away_are_hit() {
        let mut tris = cloud(50);
        for (k, z) in [1e-5, 2e-5].into_iter().enumerate() {
            tris.push(tri(
                [-1.0, -1.0, z],
                [1.0, -1.0, z],
                [0.0, 1.0, z],
                100 + k as u32,
            ));
        }
        let accel = SceneAccel::build(tris);
        let o = Point3::new(0.0, 0.0, 2e-6);
        let h = accel
            .closest_hit(&o, &Vector3::z(), 0.0, 1.0)
            .expect("the plane 8 µm above");
        assert_eq!(h.object, 100);
        assert!((h.t - 8e-6).abs() < 1e-12, "{}", h.t);
        assert!(accel.occluded(&o, &Vector3::z(), 0.0, 1.0));
    }
}
