//! Geometry: SE(3) poses, triangle meshes with per-triangle part tags, the procedural
//! glass panel and its border curve, the objects fitted to it (tape, cover), brute-force
//! closest points (`closest`, for checks), and the BVH (`accel`, the only module that names obvhs).
//!
//! Units: metres and radians. Poses, border curves and meshes are f64; the BVH works in f32
//! in the base frame (the scene spans about a metre, so f32 resolves ~0.1 µm).

pub mod accel;
pub mod border;
pub mod closest;
pub mod cuboid;
pub mod mesh;
pub mod mesh_border;
pub mod panel;
pub mod planar;
pub mod pose;
