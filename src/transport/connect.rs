//! Connections from a scattering vertex to a point of the lens aperture, straight or through
//! smooth glass.
//!
//! A straight segment that meets no surface is the usual shadow-ray connection, with
//! dω/dA_L = cos θ_L / r². When glass lies in the way, the connection follows the transmitted
//! specular chain instead: the launch direction ω is solved by Newton's method so that the
//! chain, refracted at every glass interface (Snell, with the Fresnel transmission of the
//! Stokes vector and Beer–Lambert absorption), lands exactly on the sampled lens point. The
//! Jacobian ∂(landing point)/∂ω, carried along the chain as two ray differentials (Igehy,
//! "Tracing ray differentials", SIGGRAPH 1999: transfer to each surface, refraction with the
//! change of the interpolated shading normal), gives both the Newton step and the generalised
//! geometry term dω/dA_L = 1/|det J| (the direction-space form
//! of manifold next-event estimation: Hanika, Droske & Fascione, "Manifold Next Event
//! Estimation", EGSR 2015; Walter et al., "Single scattering in refractive media with triangle
//! mesh boundaries", SIGGRAPH 2009).
//!
//! Bias (stated in ARCHITECTURE.md): only chains of transmissions are connected, from at most
//! two seeds (the straight direction and, from a vertex on glass, its mirror image into the
//! glass; a seed stopped by total internal reflection still gives the faces it met to the
//! closed form and to Newton's start); chains with internal reflections (ghost images, ~R² ≈
//! 0.2 % of the transmitted light per pair of reflections) and chains through a rough edge are
//! not connected.

use nalgebra::{Matrix2, Point3, Vector2, Vector3};

use super::layered::{solve_layered, Interface};
use super::lens::Aperture;
use super::scene::TraceScene;
use crate::geometry::accel::Hit;
use crate::geometry::mesh::SurfacePart;
use crate::optics::fresnel::fresnel_dielectric;
use crate::optics::lambert::orthonormal_basis;
use crate::optics::polarization::{apply, mueller_transmission, Stokes};
use crate::optics::refract::refract;

/// Most glass interfaces a connection chain may cross.
pub const MAX_INTERFACES: usize = 8;
/// Newton converges when the chain lands this close to the lens point (m).
const LANDING_TOLERANCE_M: f64 = 1e-10;
const NEWTON_ITERATIONS: usize = 16;
/// A closed-form solution through flat panes is accepted when its traced chain lands this close
/// to the lens point (m): f64 rounding of a ~0.3 m chain is ~1e-16 m; a chain that meets other
/// surfaces than the seed's lands far away and goes to Newton's method.
const LAYERED_LANDING_TOLERANCE_M: f64 = 1e-10;

/// The end of a chain of transmissions on the aperture plane.
#[derive(Clone, Copy, Debug)]
pub struct ChainEnd {
    /// Where it meets the aperture plane.
    pub landing: Point3<f64>,
    /// Its direction there.
    pub dir: Vector3<f64>,
    /// Fraction of the (unpolarised) power that gets there: Fresnel transmissions × absorption.
    pub transmittance: f64,
    /// Whether it crossed glass.
    pub crossed_glass: bool,
}

/// A solved connection.
#[derive(Clone, Copy, Debug)]
pub struct Connection {
    /// Launch direction at the vertex.
    pub dir: Vector3<f64>,
    /// Solid angle per unit aperture-plane area at the lens point, dω/dA_L (1/m²).
    pub dw_da: f64,
    /// The chain's end.
    pub end: ChainEnd,
}

/// Follows a ray from `origin` along `dir` through smooth glass, transmitting at every
/// interface, until it reaches the aperture plane. `None` if it is blocked (an opaque surface,
/// a rough edge, total internal reflection, too many interfaces) or runs away from the lens.
pub fn follow_chain(
    scene: &TraceScene,
    aperture: &Aperture,
    origin: Point3<f64>,
    leaving: u32,
    dir: Vector3<f64>,
) -> Option<ChainEnd> {
    trace_chain::<true>(scene, aperture, origin, leaving, dir, None, None, None)
}

/// Triangles a chain is expected to cross (`trace_chain`).
#[derive(Clone, Copy, Debug)]
struct Hints<'a> {
    /// The triangles, in the order the chain meets them.
    triangles: &'a [u32],
    /// After the last one the chain reaches the aperture plane without a query (the triangles
    /// of a whole earlier chain), or queries find the rest (the first hit of a ray already
    /// queried).
    complete: bool,
}

/// The interfaces a chain crossed, in order (at most [`MAX_INTERFACES`] + 1).
#[derive(Clone, Copy, Debug, Default)]
struct ChainRecord {
    interfaces: [Interface; MAX_INTERFACES + 1],
    /// The triangle of each interface.
    triangles: [u32; MAX_INTERFACES + 1],
    len: usize,
}

/// How a chain's landing point on the aperture plane moves when its launch direction turns:
/// ray differentials (Igehy, "Tracing ray differentials", SIGGRAPH 1999) carried through each
/// transfer and refraction, with the change of the interpolated shading normal, so Newton's
/// method gets its Jacobian from the chain it traces anyway.
#[derive(Clone, Copy, Debug)]
struct LandingDifferentials {
    /// The two launch perturbations: unit vectors orthogonal to the launch direction.
    basis: [Vector3<f64>; 2],
    /// d(landing's plane coordinates)/dθ along each basis vector (m/rad), set when the chain
    /// lands.
    landing: [Vector2<f64>; 2],
}

/// [`follow_chain`], also writing the interfaces it crosses into `record`. With `RADIOMETRY`
/// false only the geometry is followed (where the chain goes, which interfaces it crosses,
/// whether it is blocked: the same decisions from the same arithmetic) and the returned
/// `transmittance` is NaN: what the seed trace of a connection and the Newton method's
/// steps need, without the Stokes vector's frame rotations and Mueller matrices
/// that only the solved chain's transmittance uses. With `differentials`, the landing's
/// Jacobian with respect to the launch direction is carried along too. With `hints`, the ray
/// is taken to cross their triangles in turn without a BVH query while it meets each well
/// inside (`SceneAccel::hit_on_triangle`, the same hit a query on that triangle gives); from
/// the first one it misses on, BVH queries take over. A hinted chain is not checked for
/// anything else in its way: its caller checks the chain it keeps by tracing it with queries.
#[allow(clippy::too_many_arguments)]
fn trace_chain<const RADIOMETRY: bool>(
    scene: &TraceScene,
    aperture: &Aperture,
    origin: Point3<f64>,
    leaving: u32,
    dir: Vector3<f64>,
    mut record: Option<&mut ChainRecord>,
    mut differentials: Option<&mut LandingDifferentials>,
    mut hints: Option<Hints>,
) -> Option<ChainEnd> {
    let (mut o, mut d, mut leaving) = (origin, dir, leaving);
    // (dp, dd) per perturbation: the point's change on the current surface, the direction's.
    let mut diff = differentials
        .as_deref()
        .map(|df| df.basis.map(|b| (Vector3::zeros(), b)));
    let mut stokes = Stokes::unpolarized(&d);
    let mut transmittance = if RADIOMETRY { 1.0 } else { f64::NAN };
    let mut crossed_glass = false;
    for interface in 0..=MAX_INTERFACES {
        let t_plane = aperture.plane_distance(&o, &d)?;
        let query = || scene.closest_hit_leaving(&o, &d, leaving, t_plane);
        let hit = match hints.map(|h| (h.triangles.get(interface), h.complete)) {
            Some((Some(&tri), _)) => {
                scene
                    .accel
                    .hit_on_triangle(tri, &o, &d, t_plane)
                    .or_else(|| {
                        hints = None;
                        query()
                    })
            }
            Some((None, true)) => None,
            _ => query(),
        };
        let Some(hit) = hit else {
            if let (Some(df), Some(diff)) = (differentials.as_deref_mut(), &diff) {
                let den = d.dot(&aperture.axis);
                for (k, (dp, dd)) in diff.iter().enumerate() {
                    // Transfer to the aperture plane: dP = q + d·dt with dP·axis = 0.
                    let q = dp + dd * t_plane;
                    let at = q - d * (q.dot(&aperture.axis) / den);
                    df.landing[k] = Vector2::new(at.dot(&aperture.u), at.dot(&aperture.v));
                }
            }
            return Some(ChainEnd {
                landing: o + d * t_plane,
                dir: d,
                transmittance,
                crossed_glass,
            });
        };
        let glass = scene.glass(hit.material)?;
        if hit.part == SurfacePart::Edge && glass.edge_alpha > 0.0 {
            return None;
        }
        let entering = d.dot(&hit.geometric_normal) < 0.0;
        if RADIOMETRY && !entering {
            transmittance *= (-glass.absorption_per_m * hit.t).exp();
        }
        // Normal on the incident side, and the relative index n_t / n_i.
        let side = if entering { 1.0 } else { -1.0 };
        let n = hit.shading_normal * side;
        let eta = if entering { glass.eta } else { 1.0 / glass.eta };
        let cos_i = -d.dot(&n);
        if cos_i <= 0.0 {
            return None;
        }
        if let Some(r) = record.as_deref_mut() {
            r.interfaces[r.len] = Interface {
                point: hit.point,
                normal: hit.shading_normal,
                index_before: if entering { 1.0 } else { glass.eta },
            };
            r.triangles[r.len] = hit.triangle;
            r.len += 1;
        }
        let wt = if RADIOMETRY {
            let f = fresnel_dielectric(cos_i, eta);
            if f.tir {
                return None;
            }
            stokes.rotate_to_s_axis(&d, &n);
            stokes.s = apply(&mueller_transmission(&f), &stokes.s);
            let intensity = stokes.s[0];
            transmittance *= intensity;
            let (wt, _) = refract(&(-d), &n, eta)?;
            // The s axis of d and n is the transmitted beam's too (`interaction`).
            stokes.s = stokes.s.map(|v| v / intensity);
            wt
        } else {
            // `fresnel_dielectric`'s test for total internal reflection, then Snell.
            let c = cos_i.clamp(0.0, 1.0);
            if (1.0 - c * c) / (eta * eta) >= 1.0 {
                return None;
            }
            refract(&(-d), &n, eta)?.0
        };
        if let Some(diff) = diff.as_mut() {
            // Refraction wt = d/η + (cos_i/η − cos_t)·n (cos_t = −wt·n), differentiated with
            // the point's transfer onto the triangle's plane and the normal's change there.
            let ng = hit.geometric_normal;
            let den = d.dot(&ng);
            let cos_t = -wt.dot(&n);
            for (dp, dd) in diff.iter_mut() {
                let q = *dp + *dd * hit.t;
                let p_change = q - d * (q.dot(&ng) / den);
                let dn =
                    scene
                        .accel
                        .shading_normal_change(hit.triangle, hit.barycentric, &p_change)
                        * side;
                let dcos_i = -(dd.dot(&n) + d.dot(&dn));
                let dcos_t = cos_i * dcos_i / (eta * eta * cos_t);
                *dd = *dd / eta + n * (dcos_i / eta - dcos_t) + dn * (cos_i / eta - cos_t);
                *dp = p_change;
            }
        }
        d = wt;
        o = hit.point;
        leaving = hit.triangle;
        crossed_glass = true;
    }
    None
}

/// Solves for the launch direction from `x` (on triangle `leaving`) whose chain lands on
/// `lens_point`, starting from `seed`. The launch side (the sign of ω·ng) is kept fixed.
/// `first_hit`: the triangle a query from the vertex along `seed` met first, if the caller
/// has made that query (the seed chain then starts there without repeating it).
pub fn solve_connection(
    scene: &TraceScene,
    aperture: &Aperture,
    vertex: &VertexOnSurface,
    lens_point: &Point3<f64>,
    seed: Vector3<f64>,
    first_hit: Option<u32>,
) -> Option<Connection> {
    let VertexOnSurface {
        point,
        ng,
        triangle,
    } = *vertex;
    let side = seed.dot(&ng).signum();
    let target = Vector2::from(aperture.plane_coords(lens_point));
    let land = |w: &Vector3<f64>| -> Option<(Vector2<f64>, ChainEnd)> {
        if w.dot(&ng) * side <= 0.0 {
            return None;
        }
        let end = follow_chain(scene, aperture, point, triangle, *w)?;
        Some((Vector2::from(aperture.plane_coords(&end.landing)), end))
    };
    // Where a launch direction lands, geometry only, and the Jacobian of that landing with
    // respect to the direction (ray differentials along `orthonormal_basis(w)`).
    let land_at = |w: &Vector3<f64>, record: Option<&mut ChainRecord>, hints: Option<Hints>| {
        if w.dot(&ng) * side <= 0.0 {
            return None;
        }
        let (t1, t2) = orthonormal_basis(w);
        let mut df = LandingDifferentials {
            basis: [t1, t2],
            landing: [Vector2::zeros(); 2],
        };
        let end = trace_chain::<false>(
            scene,
            aperture,
            point,
            triangle,
            *w,
            record,
            Some(&mut df),
            hints,
        )?;
        let c = Vector2::from(aperture.plane_coords(&end.landing));
        Some((c, Matrix2::from_columns(&df.landing), t1, t2))
    };
    // Through flat panes: the closed form of `layered`, checked by tracing its direction.
    let mut seed = seed.normalize();
    let mut record = ChainRecord::default();
    // The seed's landing and Jacobian: Newton's first step when the closed form does not apply.
    let first = first_hit.map(|t| [t]);
    let seed_hints = first.as_ref().map(|t| Hints {
        triangles: t,
        complete: false,
    });
    let mut at_seed = land_at(&seed, Some(&mut record), seed_hints);
    // A seed that stopped at a face it meets beyond the critical angle has still recorded that
    // face: from a scatterer inside a pane (a bottom face's imperfections lit from above), the
    // straight line to the lens is often steeper than the critical angle while the refracted
    // chain lands. Its faces give the closed form (verified by tracing it) and, where they
    // curve, Newton's start. Without this those connections were lost: 18 k of 42 k such
    // connections land on the pane at 45° (4 poses at 2^18), 0.1 % of the light on the sensor.
    if at_seed.is_some() || record.len > 0 {
        let crossed = &record.interfaces[..record.len];
        if let Some(sol) = solve_layered(&point, crossed, lens_point, &aperture.axis) {
            if let Some((c, end)) = land(&sol.dir) {
                if (target - c).norm() < LAYERED_LANDING_TOLERANCE_M {
                    return Some(Connection {
                        dir: sol.dir,
                        dw_da: sol.dw_da,
                        end,
                    });
                }
            }
            if at_seed.is_none() {
                seed = sol.dir;
                record = ChainRecord::default();
                at_seed = land_at(&seed, Some(&mut record), None);
            }
        }
    }
    // Newton's steps follow the seed chain's triangles without BVH queries while they stay
    // well inside them (the same hits, so the same steps as with queries); the chain it
    // converges to is traced again with queries, which must land it on the lens point. Should
    // anything else be in the way, or the steps fail, Newton runs again with a query for
    // every step.
    let hints = at_seed.is_some().then_some(Hints {
        triangles: &record.triangles[..record.len],
        complete: true,
    });
    let newton = |hints: Option<Hints>| {
        let mut w = seed;
        let mut at_w = at_seed;
        for _ in 0..NEWTON_ITERATIONS {
            let (c0, j, t1, t2) = at_w?;
            let residual = target - c0;
            if residual.norm() < LANDING_TOLERANCE_M {
                let det = j.determinant().abs();
                if !(det > 0.0 && det.is_finite()) {
                    return None;
                }
                // The same chain again, with its Fresnel transmission and absorption, and
                // with every BVH query.
                let (c, end) = land(&w)?;
                if (target - c).norm() >= LANDING_TOLERANCE_M {
                    return None;
                }
                return Some(Connection {
                    dir: w,
                    dw_da: 1.0 / det,
                    end,
                });
            }
            let step = j.try_inverse()? * residual;
            // Keep steps inside the region where the chain is close to linear.
            let step = if step.norm() > 0.05 {
                step * (0.05 / step.norm())
            } else {
                step
            };
            w = (w + t1 * step.x + t2 * step.y).normalize();
            at_w = land_at(&w, None, hints);
        }
        None
    };
    match hints {
        Some(h) => newton(Some(h)).or_else(|| newton(None)),
        None => newton(None),
    }
}

/// The connection from `vertex` to `lens_point` through the flat slab whose face the straight
/// segment meets at `entry`, if the scene knows that face's far face (`TraceScene::slab_faces`):
/// the closed form of `layered` for the two planes, kept only if the chain traced along its
/// direction lands on the lens point (which also rules out anything else in the way). This
/// skips the seed chain that [`solve_connection`] traces to find the planes, three of the
/// seven ray queries of a connection through a pane; `None` hands the connection to it.
fn through_slab(
    scene: &TraceScene,
    aperture: &Aperture,
    vertex: &VertexOnSurface,
    lens_point: &Point3<f64>,
    entry: &Hit,
) -> Option<Connection> {
    let slab = scene.slab_faces[entry.triangle as usize]?;
    let glass = scene.glass(entry.material)?;
    let chord = lens_point - vertex.point;
    if chord.dot(&entry.geometric_normal) >= 0.0 {
        return None;
    }
    let interfaces = [
        Interface {
            point: entry.point,
            normal: entry.shading_normal,
            index_before: 1.0,
        },
        Interface {
            point: entry.point - entry.geometric_normal * slab.thickness_m,
            normal: slab.normal,
            index_before: glass.eta,
        },
    ];
    let sol = solve_layered(&vertex.point, &interfaces, lens_point, &aperture.axis)?;
    // The launch side of the straight segment, as `solve_connection` keeps it.
    if sol.dir.dot(&vertex.ng) * chord.dot(&vertex.ng) <= 0.0 {
        return None;
    }
    let end = follow_chain(scene, aperture, vertex.point, vertex.triangle, sol.dir)?;
    let landing = Vector2::from(aperture.plane_coords(&end.landing));
    let target = Vector2::from(aperture.plane_coords(lens_point));
    ((target - landing).norm() < LAYERED_LANDING_TOLERANCE_M).then_some(Connection {
        dir: sol.dir,
        dw_da: sol.dw_da,
        end,
    })
}

/// A scattering vertex as the connections need it: the exact surface point, the triangle's
/// outward geometric normal, and the triangle (which rays leaving the vertex skip).
#[derive(Clone, Copy, Debug)]
pub struct VertexOnSurface {
    /// The hit point (m).
    pub point: Point3<f64>,
    /// Outward geometric normal of the triangle (unit).
    pub ng: Vector3<f64>,
    /// The triangle, as in `Hit::triangle`.
    pub triangle: u32,
}

/// The connections from one vertex to one lens point.
#[derive(Clone, Copy, Debug)]
pub struct Connections {
    /// At most two solutions.
    pub found: [Option<Connection>; 2],
    /// Whether the chains through glass were not solved because none of them can land on the
    /// pixel grid (`deviation`).
    pub culled: bool,
}

/// The connections (at most two) from `vertex` to `lens_point`: the straight segment if
/// nothing is in the way, otherwise the transmitted chains from the straight seed and, for a
/// vertex on glass, from its mirror image into the glass. Chains are solved only if the
/// scene's deviation bound allows them to land on the pixel grid; the others cannot
/// contribute, so skipping them changes no image.
pub fn connect(
    scene: &TraceScene,
    aperture: &Aperture,
    vertex: &VertexOnSurface,
    on_glass: bool,
    lens_point: &Point3<f64>,
) -> Connections {
    let mut out = [None, None];
    let (x, ng) = (&vertex.point, &vertex.ng);
    let straight = lens_point - x;
    let dist = straight.norm();
    let s = straight / dist;
    let cos_l = -s.dot(&aperture.axis);
    if cos_l <= 0.0 {
        return Connections {
            found: out,
            culled: false,
        };
    }
    let may_land = || match &scene.deviation {
        None => true,
        Some(bound) => bound
            .arrival_angle(dist)
            .is_none_or(|cone| aperture.can_land(x, lens_point, cone)),
    };
    let mut checked: Option<bool> = None;
    let mut may_land_once = || *checked.get_or_insert_with(may_land);
    match scene.closest_hit_leaving(x, &s, vertex.triangle, dist) {
        None => {
            out[0] = Some(Connection {
                dir: s,
                dw_da: cos_l / (dist * dist),
                end: ChainEnd {
                    landing: *lens_point,
                    dir: s,
                    transmittance: 1.0,
                    crossed_glass: false,
                },
            })
        }
        Some(hit) if scene.glass(hit.material).is_some() => {
            if may_land_once() {
                out[0] = through_slab(scene, aperture, vertex, lens_point, &hit).or_else(|| {
                    solve_connection(scene, aperture, vertex, lens_point, s, Some(hit.triangle))
                });
            }
        }
        Some(_) => {}
    }
    if on_glass && may_land_once() {
        let mirrored = s - ng * (2.0 * s.dot(ng));
        if !scene.cannot_leave(vertex, &mirrored) {
            if let Some(c) = solve_connection(scene, aperture, vertex, lens_point, mirrored, None) {
                if out[0].is_none_or(|o| (o.dir - c.dir).norm() > 1e-9) {
                    out[1] = Some(c);
                }
            }
        }
    }
    Connections {
        found: out,
        culled: checked == Some(false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scan::poses::plan_border_scan;
    use crate::sensor::SensorHead;
    use std::path::Path;

    /// A shipped scene (`scenes/<file>`): the scene, the sensor and its first scan pose.
    fn first_pose_of(file: &str) -> (TraceScene, SensorHead, crate::scan::poses::ScanPose) {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let world = crate::scene::load(&root.join("scenes").join(file)).unwrap();
        let head = SensorHead::new(&world.sensor).unwrap();
        let border = world.true_border_in_base().unwrap();
        let pose = plan_border_scan(&border, &world.scan, &world.mount).remove(0);
        (TraceScene::new(&world).unwrap(), head, pose)
    }

    /// The edge-study pane on its table.
    fn edge_study() -> (TraceScene, SensorHead, crate::scan::poses::ScanPose) {
        first_pose_of("edge_study_bare.toml")
    }

    #[test]
    fn every_face_of_a_flat_pane_knows_its_far_face_and_the_edge_none() {
        let (scene, _, _) = edge_study();
        let (mut faces, mut edges) = (0, 0);
        for i in 0..scene.accel.triangle_count() as u32 {
            let t = scene.accel.triangle(i);
            let slab = scene.slab_faces[i as usize];
            match (scene.glass(t.material), t.part) {
                (Some(_), SurfacePart::Edge) | (None, _) => assert_eq!(slab, None),
                (Some(_), _) => {
                    // edge_study_bare.toml: thickness_mm = 4.
                    let slab = slab.expect("a face of the flat pane");
                    assert!((slab.thickness_m - 4e-3).abs() < 1e-12, "{slab:?}");
                    faces += 1;
                }
            }
            edges += usize::from(t.part == SurfacePart::Edge);
        }
        assert!(
            faces > 100 && edges > 100,
            "{faces} faces, {edges} edge triangles"
        );
    }

    /// Whatever [`TraceScene::cannot_leave`] rules out, the chain's own trace ends inside the
    /// pane: from every glass triangle's centroid of edge_study_bare's pane, 200 directions
    /// into the glass (a spherical Fibonacci set), each traced. The bent car window is no
    /// flat pane.
    #[test]
    fn chains_a_flat_pane_traps_are_those_whose_trace_ends_inside_it() {
        let (scene, head, pose) = edge_study();
        let aperture = Aperture::new(&head.camera, &pose.sensor);
        let (mut trapped, mut tested, mut left) = (0, 0, 0);
        for i in 0..scene.accel.triangle_count() as u32 {
            let t = *scene.accel.triangle(i);
            if scene.glass(t.material).is_none() {
                continue;
            }
            assert!(scene.flat_panes[t.object as usize].is_some());
            let [a, b, c] = t.vertices;
            let point = Point3::from((a.coords + b.coords + c.coords) / 3.0);
            let ng = (b - a).cross(&(c - a)).normalize();
            let vertex = VertexOnSurface {
                point,
                ng,
                triangle: i,
            };
            for k in 0..200 {
                // Spherical Fibonacci directions (golden-angle spiral).
                let z = 1.0 - (2 * k + 1) as f64 / 200.0;
                let phi = k as f64 * 2.399_963_229_728_653;
                let r = (1.0 - z * z).sqrt();
                let w = Vector3::new(r * phi.cos(), r * phi.sin(), z);
                if w.dot(&ng) >= 0.0 {
                    continue;
                }
                tested += 1;
                let traced = follow_chain(&scene, &aperture, point, i, w);
                if scene.cannot_leave(&vertex, &w) {
                    trapped += 1;
                    assert!(traced.is_none(), "triangle {i}, direction {w}: {traced:?}");
                } else {
                    left += usize::from(traced.is_some());
                }
            }
        }
        assert!(
            trapped > tested / 4 && left > 0,
            "{trapped} ruled out, {left} left the pane, of {tested}"
        );
        let (car, _, _) = car_window();
        for i in 0..car.accel.triangle_count() as u32 {
            let t = car.accel.triangle(i);
            if car.glass(t.material).is_some() {
                assert_eq!(car.flat_panes[t.object as usize], None);
            }
        }
    }

    /// The car window over its table.
    fn car_window() -> (TraceScene, SensorHead, crate::scan::poses::ScanPose) {
        first_pose_of("car_side_window.toml")
    }

    /// Opaque points seen through the glass from the aperture's centre, on straight lines past
    /// p_e on a 20 × 20 grid 60 mm wide: where chains through the bent pane start.
    fn points_behind_the_glass(
        scene: &TraceScene,
        aperture: &Aperture,
        pose: &crate::scan::poses::ScanPose,
    ) -> Vec<Hit> {
        let mut out = Vec::new();
        for k in 0..400 {
            let aim = pose.edge_point
                + Vector3::new((k % 20) as f64 - 9.5, (k / 20) as f64 - 9.5, 0.0) * 3e-3;
            let dir = (aim - aperture.center).normalize();
            let Some(first) = scene.accel.closest_hit(&aperture.center, &dir, 0.0, 2.0) else {
                continue;
            };
            if scene.glass(first.material).is_none() {
                continue;
            }
            // The first opaque surface behind the glass along the same line.
            let mut hit = first;
            while scene.glass(hit.material).is_some() {
                match scene
                    .accel
                    .closest_hit_leaving(&hit.point, &dir, hit.triangle, 2.0)
                {
                    Some(h) => hit = h,
                    None => break,
                }
            }
            if scene.glass(hit.material).is_none() {
                out.push(hit);
            }
        }
        out
    }

    #[test]
    fn the_landing_jacobian_of_ray_differentials_is_the_finite_differences_one_on_a_curved_pane() {
        // Table points seen through the car window (bent, smooth-shaded): the Jacobian the
        // chain carries equals central differences of where the chain lands (h = 1e-6 rad,
        // truncation ~h² of the Jacobian): measured 5e-12 to 3e-10 relative on 213 chains;
        // without the shading normal's change it is 8e-4 off, so the test sees the curvature.
        let (scene, head, pose) = car_window();
        let aperture = Aperture::new(&head.camera, &pose.sensor);
        let coords = |end: &ChainEnd| Vector2::from(aperture.plane_coords(&end.landing));
        let mut compared = 0;
        for hit in points_behind_the_glass(&scene, &aperture, &pose) {
            let w = (aperture.center - hit.point).normalize();
            let (t1, t2) = orthonormal_basis(&w);
            let mut df = LandingDifferentials {
                basis: [t1, t2],
                landing: [Vector2::zeros(); 2],
            };
            let trace = |w: Vector3<f64>, df: Option<&mut LandingDifferentials>| {
                trace_chain::<false>(
                    &scene,
                    &aperture,
                    hit.point,
                    hit.triangle,
                    w,
                    None,
                    df,
                    None,
                )
            };
            let Some(end) = trace(w, Some(&mut df)) else {
                continue;
            };
            if !end.crossed_glass {
                continue;
            }
            let h = 1e-6;
            let mut fd = [Vector2::zeros(); 2];
            let mut ok = true;
            for (j, t) in [t1, t2].iter().enumerate() {
                match (
                    trace((w + t * h).normalize(), None),
                    trace((w - t * h).normalize(), None),
                ) {
                    (Some(p), Some(m)) if p.crossed_glass && m.crossed_glass => {
                        fd[j] = (coords(&p) - coords(&m)) / (2.0 * h);
                    }
                    _ => ok = false,
                }
            }
            if !ok {
                continue;
            }
            let (analytic, numeric) = (
                Matrix2::from_columns(&df.landing),
                Matrix2::from_columns(&fd),
            );
            let err = (analytic - numeric).norm() / numeric.norm();
            assert!(err < 1e-8, "relative {err:e}: {analytic} vs {numeric}");
            compared += 1;
        }
        assert!(compared > 50, "only {compared} chains through the window");
    }

    #[test]
    fn a_chain_along_hinted_triangles_is_the_chain_bvh_queries_give() {
        // Chains through the car window from points behind it, turned by 1e-6 to 3e-2 rad as
        // Newton's steps turn them: traced along the first chain's triangles, each gives the
        // same end, landing Jacobian and interfaces, bit for bit, as with a BVH query per
        // interface, both where it stays on those triangles and where it leaves them and the
        // queries take over.
        let (scene, head, pose) = car_window();
        let aperture = Aperture::new(&head.camera, &pose.sensor);
        let (mut on_hints, mut left_hints) = (0, 0);
        for hit in points_behind_the_glass(&scene, &aperture, &pose) {
            let w = (aperture.center - hit.point).normalize();
            let mut seed = ChainRecord::default();
            let trace = |w: Vector3<f64>, record: &mut ChainRecord, hints: Option<Hints>| {
                let (t1, t2) = orthonormal_basis(&w);
                let mut df = LandingDifferentials {
                    basis: [t1, t2],
                    landing: [Vector2::zeros(); 2],
                };
                let end = trace_chain::<false>(
                    &scene,
                    &aperture,
                    hit.point,
                    hit.triangle,
                    w,
                    Some(record),
                    Some(&mut df),
                    hints,
                );
                end.map(|e| (e.landing, e.dir, e.crossed_glass, df.landing))
            };
            if trace(w, &mut seed, None).is_none() || seed.len == 0 {
                continue;
            }
            let hints = &seed.triangles[..seed.len];
            let (t1, t2) = orthonormal_basis(&w);
            for (j, turn) in [1e-6, 1e-4, 3e-3, 3e-2].iter().enumerate() {
                let a = std::f64::consts::TAU * (j as f64 / 4.0 + 0.1);
                let turned = (w + (t1 * a.cos() + t2 * a.sin()) * *turn).normalize();
                let (mut queried, mut hinted) = (ChainRecord::default(), ChainRecord::default());
                let by_queries = trace(turned, &mut queried, None);
                let along_hints = trace(
                    turned,
                    &mut hinted,
                    Some(Hints {
                        triangles: hints,
                        complete: true,
                    }),
                );
                assert_eq!(by_queries, along_hints, "turned by {turn}");
                // Only the first triangle given, queries for the rest (a connection's seed
                // chain after the straight query): the same chain.
                let mut started = ChainRecord::default();
                let from_first = trace(
                    turned,
                    &mut started,
                    Some(Hints {
                        triangles: &hints[..1],
                        complete: false,
                    }),
                );
                assert_eq!(by_queries, from_first, "turned by {turn}, first hinted");
                assert_eq!(
                    queried.triangles[..queried.len],
                    hinted.triangles[..hinted.len]
                );
                if queried.triangles[..queried.len] == *hints {
                    on_hints += 1;
                } else {
                    left_hints += 1;
                }
            }
        }
        eprintln!("{on_hints} chains on the hinted triangles, {left_hints} off them");
        assert!(
            on_hints > 300 && left_hints > 20,
            "{on_hints} chains on the hinted triangles, {left_hints} off them"
        );
    }

    /// The point `d` (m) from p_e towards the pane's centre (the pane is centred on the base
    /// frame's origin), at height `z` (m).
    fn inward_of_p_e(pose: &crate::scan::poses::ScanPose, d: f64, z: f64) -> Point3<f64> {
        let inward = (-pose.edge_point.coords).xy().normalize();
        Point3::new(
            pose.edge_point.x + inward.x * d,
            pose.edge_point.y + inward.y * d,
            z,
        )
    }

    #[test]
    fn a_connection_through_the_slab_is_the_one_the_seed_chain_finds() {
        // Points of the table under the pane, connected to lens points across the aperture:
        // the slab's closed form and the general solver (seed chain, then `layered`) agree.
        let (scene, head, pose) = edge_study();
        let aperture = Aperture::new(&head.camera, &pose.sensor);
        let mut compared = 0;
        for k in 0..40 {
            // Table points 1 to 20 mm from p_e towards the pane's centre.
            let x = inward_of_p_e(&pose, 1e-3 + 0.5e-3 * k as f64, -1e-3);
            // The table's top (z = 0) from below, so the pane above is not met first.
            let Some(floor) = scene.accel.closest_hit(&x, &Vector3::z(), 0.0, 2e-3) else {
                continue;
            };
            if scene.glass(floor.material).is_some() {
                continue;
            }
            let vertex = VertexOnSurface {
                point: floor.point,
                ng: floor.geometric_normal,
                triangle: floor.triangle,
            };
            let lens_point = aperture.point([(k % 5) as f64 * 0.2 - 0.4, 0.3]);
            let s = (lens_point - vertex.point).normalize();
            let dist = (lens_point - vertex.point).norm();
            let Some(entry) =
                scene
                    .accel
                    .closest_hit_leaving(&vertex.point, &s, vertex.triangle, dist)
            else {
                continue;
            };
            let (Some(fast), Some(general)) = (
                through_slab(&scene, &aperture, &vertex, &lens_point, &entry),
                solve_connection(&scene, &aperture, &vertex, &lens_point, s, None),
            ) else {
                continue;
            };
            assert!((fast.dir - general.dir).norm() < 1e-12);
            assert!((fast.dw_da / general.dw_da - 1.0).abs() < 1e-9);
            assert!((fast.end.transmittance - general.end.transmittance).abs() < 1e-12);
            compared += 1;
        }
        assert!(compared >= 20, "{compared} connections compared");
    }

    #[test]
    fn a_scatterer_inside_the_pane_connects_through_the_face_it_sees_beyond_the_critical_angle() {
        // Points of the pane's bottom face seen from inside (an imperfection lit by the laser
        // through the top face), connected to lens points across the aperture, where the
        // straight line to the lens meets the top face beyond the critical angle (its chain
        // stops there). The connection refracts at the top face towards the lens point (Snell,
        // checked at the exit), and its geometry term dω/dA_L equals central differences of
        // the launch direction over the lens point (h = 1 µm): 9e-11 relative at most, measured.
        let (scene, head, pose) = edge_study();
        let aperture = Aperture::new(&head.camera, &pose.sensor);
        let glass = scene
            .surfaces
            .iter()
            .find_map(|m| match m {
                crate::transport::scene::SurfaceModel::Glass(g) => Some(*g),
                _ => None,
            })
            .expect("the pane's glass");
        let (mut beyond, mut connected) = (0, 0);
        for k in 0..40 {
            // Inside the 4 mm pane, 6 to 25.5 mm from p_e (nearer, the chains towards the lens
            // meet the rough edge), looking down at its bottom face.
            let x = inward_of_p_e(&pose, 6e-3 + 0.5e-3 * k as f64, pose.edge_point.z - 2e-3);
            let Some(floor) = scene.accel.closest_hit(&x, &-Vector3::z(), 0.0, 3e-3) else {
                continue;
            };
            assert!(scene.glass(floor.material).is_some(), "the bottom face");
            let vertex = VertexOnSurface {
                point: floor.point,
                ng: floor.geometric_normal,
                triangle: floor.triangle,
            };
            let solve = |lens_point: &Point3<f64>| {
                let s = (lens_point - vertex.point).normalize();
                solve_connection(&scene, &aperture, &vertex, lens_point, s, None)
            };
            let lens_point = aperture.point([(k % 5) as f64 * 0.2 - 0.4, 0.3]);
            let s = (lens_point - vertex.point).normalize();
            if s.z * s.z > 1.0 - 1.0 / (glass.eta * glass.eta) {
                continue; // within the critical angle: the straight seed's chain goes through
            }
            beyond += 1;
            assert!(follow_chain(&scene, &aperture, vertex.point, vertex.triangle, s).is_none());
            let Some(c) = solve(&lens_point) else {
                continue;
            };
            connected += 1;
            assert!(c.end.crossed_glass && c.end.transmittance > 0.0);
            // Snell at the top face: the refracted direction points at the lens point.
            let top = scene
                .accel
                .closest_hit_leaving(&vertex.point, &c.dir, vertex.triangle, 1.0)
                .expect("the top face");
            let (out, _) = refract(&(-c.dir), &(-top.shading_normal), glass.eta.recip())
                .expect("within the critical angle");
            assert!(((lens_point - top.point).normalize() - out).norm() < 1e-9);
            // dω/dA_L by central differences of the launch direction.
            let h = 1e-6;
            let dir_at = |du: f64, dv: f64| {
                solve(&(lens_point + aperture.u * du + aperture.v * dv))
                    .expect("a neighbouring lens point connects too")
                    .dir
            };
            let wu = (dir_at(h, 0.0) - dir_at(-h, 0.0)) / (2.0 * h);
            let wv = (dir_at(0.0, h) - dir_at(0.0, -h)) / (2.0 * h);
            let fd = wu.cross(&wv).norm();
            assert!(
                (fd / c.dw_da - 1.0).abs() < 1e-8,
                "{fd} against {}",
                c.dw_da
            );
        }
        assert!(
            beyond >= 20 && connected == beyond,
            "{connected} of {beyond} connected"
        );
    }
}
