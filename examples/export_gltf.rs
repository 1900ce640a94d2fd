//! Writes a scene's target glass panel as a glTF binary (GLB) with its materials in the
//! Khronos glass extensions (`scene::gltf_export::target_glb`): the CAD-style file a process
//! engineer would bring. It regenerates the shipped `scenes/meshes/car_side_window.glb`:
//!
//! ```sh
//! cargo run --release --example export_gltf -- scenes/car_side_window.toml scenes/meshes/car_side_window.glb
//! ```
//!
//! The file holds the panel in its model frame, +Y up (glTF 2.0 §3.4), in metres; the faces use
//! material `glass`, the ground edge material `edge` (roughnessFactor = √α). The output depends
//! only on the scene: `validation/gltf_target.rs` checks the shipped file against it byte for
//! byte.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let [scene, out] = args.as_slice() else {
        eprintln!("usage: export_gltf SCENE.toml OUT.glb");
        return ExitCode::from(2);
    };
    let world = match glassscan::scene::load(scene) {
        Ok(w) => w,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let glb = match glassscan::scene::gltf_export::target_glb(&world) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    if let Err(e) = std::fs::write(out, &glb) {
        eprintln!("error: cannot write {}: {e}", out.display());
        return ExitCode::from(1);
    }
    eprintln!("wrote {} ({} bytes)", out.display(), glb.len());
    ExitCode::SUCCESS
}
