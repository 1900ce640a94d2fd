//! Scene files (TOML) → `World`: objects with meshes and true poses, named materials, the
//! target (a panel, or a glass mesh whose border `geometry::mesh_border` finds) with its
//! border curve and nominal pose, the sensor head (a preset plus
//! overrides), the hand-eye mount and the scan settings.
//!
//! `scenes/README.md` is the reference for the file format: every section, field, unit and
//! default, with the source of each default.
//!
//! Invariants of a loaded `World`: at least one object; object names are unique; every object
//! has a non-empty, structurally valid mesh and a material index into `World::materials`, which
//! holds exactly the materials the objects use; a target names a panel or mesh object; every number is
//! finite and in its documented range.
//!
//! Units: scene files use named units (`_mm`, `_deg`, `_ms`, `_nm`, `_mw`, `_um`, `_per_mm`);
//! `World` is in SI (metres, radians, seconds, watts). Errors name the file, the 1-based
//! `line:column` of the offending value and its field path (see [`SceneError`]).
//! Only this module and `dataset` touch the filesystem.

mod edge_def;
mod error;
mod file;
mod fitted;
pub mod gltf_export;
pub mod gltf_material;
pub mod gltf_mesh;
mod load;
mod material;
mod mesh_material;
mod mesh_target;
mod panel;
mod sensor_overrides;
#[cfg(test)]
mod test_scene;
pub mod world;

pub use error::SceneError;
pub use load::{load, load_str};
pub use world::World;
