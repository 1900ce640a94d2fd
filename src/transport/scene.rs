//! The scene as the tracer sees it: all triangles in the base frame in one BVH, the surface
//! model of every material at the laser wavelength, and each object's label.

use nalgebra::{Point3, Vector3};

use super::connect::{VertexOnSurface, MAX_INTERFACES};
use super::cylinder_pane::{coaxial_radius_ratio, FaceVertex};
use super::deviation::DeviationBound;
use super::slab_crossing::SlabCrossings;
use crate::geometry::accel::{Hit, SceneAccel, SceneTriangle};
use crate::geometry::mesh::SurfacePart;
use crate::optics::lambert::Lambertian;
use crate::scene::world::{Material, ObjectLabel, World};
use crate::sensor::path_class::PathClass;

/// Why a world cannot be traced.
#[derive(Debug, thiserror::Error)]
pub enum TransportError {
    /// The scene has no triangles.
    #[error("{scene}: the scene has no triangles to trace")]
    Empty {
        /// The scene file.
        scene: String,
    },
}

/// Glass at the laser wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlassSurface {
    /// Refractive index n (glass relative to the surrounding air).
    pub eta: f64,
    /// Beer–Lambert absorption coefficient (1/m).
    pub absorption_per_m: f64,
    /// Probability that a face interaction scatters diffusely (imperfections) instead of
    /// following Fresnel's law.
    pub face_imperfection: f64,
    /// GGX roughness α of the ground edge; 0 makes the edge as smooth as the faces.
    pub edge_alpha: f64,
}

/// How a surface scatters light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceModel {
    /// Ideal diffuse reflector.
    Lambertian(Lambertian),
    /// Glass: smooth faces with imperfections, rough edges, absorbing bulk.
    Glass(GlassSurface),
}

/// Triangles, BVH and surface models, ready for tracing.
pub struct TraceScene {
    /// The BVH over every triangle, in the base frame.
    pub accel: SceneAccel,
    /// Surface model per world material index.
    pub surfaces: Vec<SurfaceModel>,
    /// Per world object index, the class of the light an opaque object returns directly (no
    /// glass on the path): from its label, and `Target` for the scene's target.
    pub direct_class: Vec<PathClass>,
    /// How far the scene's glass can bend a camera connection, if it can be bounded: lets the
    /// tracer skip connections that cannot land on the sensor. `None` solves every one (set it
    /// to `None` to check that the bound changes nothing).
    pub deviation: Option<DeviationBound>,
    /// Per triangle (as in `Hit::triangle`): for a face of a flat glass slab, its far face,
    /// which lets a camera connection through the slab be solved without tracing a seed chain
    /// first (`connect`); `None` elsewhere.
    pub slab_faces: Vec<Option<SlabFace>>,
    /// The layers around the flat panes (their glass, the air up to a parallel surface beyond a
    /// face, an empty side): a ray crossing one gets its closest hit without a BVH query
    /// ([`TraceScene::closest_hit_leaving`]).
    pub slab_crossings: SlabCrossings,
    /// Per world object index: for a flat pane with a rough edge that no other glass
    /// overlaps, its faces' normal and index, which tell at once which chains launched into it
    /// cannot leave it ([`TraceScene::cannot_leave`]).
    pub flat_panes: Vec<Option<FlatPane>>,
    /// Per world object index: whether light totally reflected at its faces stays inside it
    /// until the rough edge or a face imperfection lets it out (`trace::ends_at_total_reflection`):
    /// a flat pane, or a pane bent on a cylinder no thicker than [`MIN_BENT_RADIUS_RATIO`]
    /// allows, with the flat pane's other conditions (`cylinder_pane` says why).
    pub traps_light: Vec<bool>,
}

/// Least r_min/r_max of a bent pane's faces about their axis for light totally reflected in it
/// to count as trapped: its faces then let out only light whose first total internal
/// reflection lies within 1/η ≤ sin θ < 1/(0.99·η), under a degree above the critical angle
/// (`cylinder_pane`); panes of 4 mm bent on radii of 400 mm or more. Car side windows are bent
/// on ~1–2 m (the shipped car window: 0.9973).
pub const MIN_BENT_RADIUS_RATIO: f64 = 0.99;

/// A glass object whose face triangles (every one not tagged `Edge`) are parallel to one
/// plane, with a rough edge finish, and whose bounding box no other glass object's meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatPane {
    /// The faces' unit normal (either orientation).
    pub normal: Vector3<f64>,
    /// Its refractive index.
    pub eta: f64,
}

/// How much beyond the critical angle (in (1 − cos²θ)·η² ≥ 1 + this) a chain must meet a
/// pane's faces for [`TraceScene::cannot_leave`] to rule it out: far above the rounding of the
/// face triangles' shading normals against the pane's one normal (~1e-16), so the chain's own
/// test of total internal reflection could not decide otherwise.
const TRAPPED_MARGIN: f64 = 1e-9;

/// The panes of the scene, per object index: the flat ones (see [`FlatPane`]), and whether
/// each traps light totally reflected in it (flat, or bent on a cylinder: see
/// [`TraceScene::traps_light`]).
fn panes(
    accel: &SceneAccel,
    surfaces: &[SurfaceModel],
    objects: usize,
) -> (Vec<Option<FlatPane>>, Vec<bool>) {
    let mut normal: Vec<Option<Vector3<f64>>> = vec![None; objects];
    let mut flat = vec![true; objects];
    let mut rough_edge = vec![true; objects];
    // Face triangles with shading normals; `None` for an object with a face that has none
    // (facets are not a cylinder).
    let mut smooth_faces: Vec<Option<Vec<u32>>> = vec![Some(Vec::new()); objects];
    let mut glass = vec![None; objects];
    let mut bounds = vec![
        (
            Point3::from([f64::INFINITY; 3]),
            Point3::from([f64::NEG_INFINITY; 3])
        );
        objects
    ];
    for i in 0..accel.triangle_count() as u32 {
        let t = accel.triangle(i);
        let k = t.object as usize;
        for v in &t.vertices {
            bounds[k] = (bounds[k].0.inf(v), bounds[k].1.sup(v));
        }
        let SurfaceModel::Glass(g) = surfaces[t.material as usize] else {
            rough_edge[k] = false;
            continue;
        };
        glass[k] = Some(g);
        if t.part == SurfacePart::Edge {
            rough_edge[k] &= g.edge_alpha > 0.0;
            continue;
        }
        match (&mut smooth_faces[k], t.normals) {
            (Some(faces), Some(_)) => faces.push(i),
            (faces, _) => *faces = None,
        }
        let [a, b, c] = t.vertices;
        let Some(n) = (b - a).cross(&(c - a)).try_normalize(0.0) else {
            flat[k] = false;
            continue;
        };
        let reference = *normal[k].get_or_insert(n);
        let shading = t.normals.unwrap_or([n; 3]);
        flat[k] &= std::iter::once(n)
            .chain(shading)
            .all(|m| m.cross(&reference).norm() <= SLAB_PARALLEL_RAD);
    }
    let overlaps = |a: usize, b: usize| {
        (0..3).all(|j| bounds[a].0[j] <= bounds[b].1[j] && bounds[b].0[j] <= bounds[a].1[j])
    };
    // Glass with a rough edge and no other glass within its bounding box: a pane, if its faces
    // are flat or on cylinders.
    let pane: Vec<Option<GlassSurface>> = (0..objects)
        .map(|k| {
            let alone = (0..objects).all(|o| o == k || glass[o].is_none() || !overlaps(k, o));
            glass[k].filter(|_| rough_edge[k] && alone)
        })
        .collect();
    let flat_panes: Vec<Option<FlatPane>> = (0..objects)
        .map(|k| {
            let (Some(g), Some(n), true) = (pane[k], normal[k], flat[k]) else {
                return None;
            };
            Some(FlatPane {
                normal: n,
                eta: g.eta,
            })
        })
        .collect();
    let traps_light = (0..objects)
        .map(|k| {
            flat_panes[k].is_some()
                || pane[k].is_some()
                    && smooth_faces[k]
                        .as_deref()
                        .and_then(|faces| coaxial_radius_ratio(face_vertices(accel, faces)))
                        .is_some_and(|ratio| ratio >= MIN_BENT_RADIUS_RATIO)
        })
        .collect();
    (flat_panes, traps_light)
}

/// The vertices of the smooth-shaded triangles `faces`, each with its shading normal.
fn face_vertices<'a>(
    accel: &'a SceneAccel,
    faces: &'a [u32],
) -> impl Iterator<Item = FaceVertex> + Clone + 'a {
    faces.iter().flat_map(move |&i| {
        let t = accel.triangle(i);
        let normals = t.normals.expect("a smooth face triangle");
        t.vertices.into_iter().zip(normals)
    })
}

/// The far face of a flat glass slab, as seen from one of its face triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabFace {
    /// Distance between the two faces' planes along the near face's normal (m).
    pub thickness_m: f64,
    /// The far face's shading normal (outward, anti-parallel to the near face's).
    pub normal: Vector3<f64>,
}

/// Two face normals count as anti-parallel (a flat slab) within this angle (rad): the
/// tolerance of `layered`, whose closed form is exact for them.
const SLAB_PARALLEL_RAD: f64 = 1e-12;

/// The far faces of the flat glass slabs: from the centroid of every glass face triangle, a ray
/// into the glass along the inward normal; the face it meets is the far face if it belongs to
/// the same object and material, is not the edge finish and is anti-parallel. One ray per glass
/// face triangle, once per scene. Only a hint: a connection solved with it is kept only if its
/// traced chain lands on the lens point.
fn slab_faces(accel: &SceneAccel, surfaces: &[SurfaceModel]) -> Vec<Option<SlabFace>> {
    (0..accel.triangle_count() as u32)
        .map(|i| {
            let t = accel.triangle(i);
            let glass = matches!(surfaces[t.material as usize], SurfaceModel::Glass(_));
            if !glass || t.part == SurfacePart::Edge {
                return None;
            }
            let [a, b, c] = t.vertices;
            let n = (b - a).cross(&(c - a)).try_normalize(0.0)?;
            let centroid = Point3::from((a.coords + b.coords + c.coords) / 3.0);
            let far = accel.closest_hit_leaving(&centroid, &-n, i, 1.0)?;
            let same_slab = far.object == t.object
                && far.material == t.material
                && far.part != SurfacePart::Edge
                && far.geometric_normal.cross(&n).norm() <= SLAB_PARALLEL_RAD
                && far.geometric_normal.dot(&n) < 0.0
                && far.shading_normal.cross(&n).norm() <= SLAB_PARALLEL_RAD;
            same_slab.then_some(SlabFace {
                thickness_m: far.t,
                normal: far.shading_normal,
            })
        })
        .collect()
}

impl TraceScene {
    /// Places every object at its true pose, resolves materials at `wavelength_m` and builds the
    /// BVH.
    pub fn new(world: &World) -> Result<TraceScene, TransportError> {
        let scene = world.source.display().to_string();
        let wavelength_m = world.sensor.laser.wavelength_m;
        let surfaces: Vec<SurfaceModel> = world
            .materials
            .iter()
            .map(|m| match &m.material {
                Material::Lambertian { albedo } => {
                    SurfaceModel::Lambertian(Lambertian { albedo: *albedo })
                }
                Material::Glass(g) => SurfaceModel::Glass(GlassSurface {
                    eta: g.index_at(wavelength_m),
                    absorption_per_m: g.absorption_per_m,
                    face_imperfection: g.face_imperfection,
                    edge_alpha: g.edge_roughness,
                }),
            })
            .collect();
        let mut triangles = Vec::new();
        for (k, object) in world.objects.iter().enumerate() {
            let mesh = object.mesh.transformed(&object.pose);
            for (i, tri) in mesh.triangles.iter().enumerate() {
                let idx = tri.map(|v| v as usize);
                triangles.push(SceneTriangle {
                    vertices: idx.map(|v| mesh.positions[v]),
                    normals: mesh.normals.as_ref().map(|ns| idx.map(|v| ns[v])),
                    object: k as u32,
                    material: object.material as u32,
                    part: mesh.parts[i],
                });
            }
        }
        if triangles.is_empty() {
            return Err(TransportError::Empty { scene });
        }
        let target = world.target.as_ref().map(|t| t.object);
        let direct_class = (world.objects.iter().enumerate())
            .map(|(k, o)| {
                if Some(k) == target {
                    PathClass::Target
                } else {
                    label_class(o.label)
                }
            })
            .collect();
        let accel = SceneAccel::build(triangles);
        let deviation = DeviationBound::of_scene(&accel, &surfaces, MAX_INTERFACES);
        let slab_faces = slab_faces(&accel, &surfaces);
        let slab_crossings = SlabCrossings::new(&accel, &slab_faces);
        let (flat_panes, traps_light) = panes(&accel, &surfaces, world.objects.len());
        Ok(TraceScene {
            accel,
            surfaces,
            direct_class,
            deviation,
            slab_faces,
            slab_crossings,
            flat_panes,
            traps_light,
        })
    }

    /// Whether a chain of transmissions launched from `vertex` along `dir` into the glass of a
    /// [`FlatPane`] surely ends inside it: it meets the faces beyond the critical angle (total
    /// internal reflection, which chains do not follow), or the rough edge, or an opaque object
    /// (no other glass lies within the pane's bounding box), whichever comes first. Such a
    /// chain's trace returns nothing, so a connection may skip it (issue 11: 86 % of the seeds
    /// mirrored into edge_study_bare's pane at 45°, 53 % at 10°).
    pub fn cannot_leave(&self, vertex: &VertexOnSurface, dir: &Vector3<f64>) -> bool {
        let object = self.accel.triangle(vertex.triangle).object as usize;
        let Some(pane) = self.flat_panes[object] else {
            return false;
        };
        let w = dir.normalize();
        let c = w.dot(&pane.normal);
        w.dot(&vertex.ng) < 0.0 && (1.0 - c * c) * pane.eta * pane.eta >= 1.0 + TRAPPED_MARGIN
    }

    /// `SceneAccel::closest_hit_leaving`, bit for bit; a ray crossing a layer around a flat pane
    /// with nothing else in the way gets its hit without a BVH query (`slab_crossing`).
    pub fn closest_hit_leaving(
        &self,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        leaving: u32,
        t_max: f64,
    ) -> Option<Hit> {
        self.slab_crossings
            .closest_hit(&self.accel, leaving, origin, dir, t_max)
            .unwrap_or_else(|| self.accel.closest_hit_leaving(origin, dir, leaving, t_max))
    }

    /// The glass surface model of material `m`, if it is glass.
    pub fn glass(&self, material: u32) -> Option<&GlassSurface> {
        match &self.surfaces[material as usize] {
            SurfaceModel::Glass(g) => Some(g),
            SurfaceModel::Lambertian(_) => None,
        }
    }
}

/// The class of light returned directly by an opaque object labelled `label`.
fn label_class(label: ObjectLabel) -> PathClass {
    match label {
        ObjectLabel::Table => PathClass::Table,
        ObjectLabel::Tape | ObjectLabel::Cover => PathClass::TapeCover,
        ObjectLabel::Background => PathClass::Background,
        ObjectLabel::Other => PathClass::Other,
    }
}
