//! The scene as the tracer sees it: all triangles in the base frame in one BVH, and the
//! surface model of every material.

use crate::geometry::accel::{SceneAccel, SceneTriangle};
use crate::optics::lambert::Lambertian;
use crate::scene::world::{Material, World};

/// Why a world cannot be traced.
#[derive(Debug, thiserror::Error)]
pub enum TransportError {
    /// The scene uses a material whose light transport does not exist yet.
    #[error(
        "{scene}: object `{object}` uses material `{material}` (kind = \"glass\"), which cannot \
         be simulated yet: the glass light transport (Fresnel, refraction, rough edges) is \
         issue #3. The scene file itself is valid; use an opaque scene such as \
         scenes/flat_opaque.toml meanwhile"
    )]
    UnsupportedMaterial {
        /// The scene file.
        scene: String,
        /// The object that uses it.
        object: String,
        /// The material's name.
        material: String,
    },
    /// The scene has no triangles.
    #[error("{scene}: the scene has no triangles to trace")]
    Empty {
        /// The scene file.
        scene: String,
    },
}

/// How a surface scatters light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceModel {
    /// Ideal diffuse reflector.
    Lambertian(Lambertian),
}

/// Triangles, BVH and surface models, ready for tracing.
pub struct TraceScene {
    /// The BVH over every triangle, in the base frame.
    pub accel: SceneAccel,
    /// Surface model per world material index.
    pub surfaces: Vec<SurfaceModel>,
}

impl TraceScene {
    /// Places every object at its true pose and builds the BVH.
    pub fn new(world: &World) -> Result<TraceScene, TransportError> {
        let scene = world.source.display().to_string();
        let mut surfaces = Vec::with_capacity(world.materials.len());
        for m in &world.materials {
            surfaces.push(match &m.material {
                Material::Lambertian { albedo } => {
                    SurfaceModel::Lambertian(Lambertian { albedo: *albedo })
                }
                // Refused below, if an object uses it; an unused glass material is harmless.
                Material::Glass(_) => SurfaceModel::Lambertian(Lambertian { albedo: 0.0 }),
            });
        }
        let mut triangles = Vec::new();
        for (k, object) in world.objects.iter().enumerate() {
            let named = &world.materials[object.material];
            if matches!(named.material, Material::Glass(_)) {
                return Err(TransportError::UnsupportedMaterial {
                    scene,
                    object: object.name.clone(),
                    material: named.name.clone(),
                });
            }
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
        Ok(TraceScene {
            accel: SceneAccel::build(triangles),
            surfaces,
        })
    }
}
