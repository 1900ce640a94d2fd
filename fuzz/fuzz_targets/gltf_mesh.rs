//! The glTF/GLB mesh loader on arbitrary bytes: a mesh or a `GltfMeshError`, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = std::path::Path::new("corpus/gltf_mesh/input.glb");
    let _ = glassscan::scene::gltf_mesh::load_gltf_mesh_from_slice(path, data, 1.0);
});
