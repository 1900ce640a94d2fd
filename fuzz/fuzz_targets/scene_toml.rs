//! The scene loader on arbitrary text: every input is a scene or a `SceneError`, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = glassscan::scene::load_str(std::path::Path::new("fuzz.toml"), text);
    }
});
