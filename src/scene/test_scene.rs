//! What the scene modules' tests share: loading a scene text as `bad.toml` and the
//! `bad.toml:line:column:` prefix an error about a given spot of it must carry.

use std::path::Path;

use super::world::World;
use super::{load_str, SceneError};

/// `text` loaded as if it were the file `bad.toml`.
pub fn load_text(text: &str) -> Result<World, SceneError> {
    load_str(Path::new("bad.toml"), text)
}

/// `bad.toml:line:column:` of the first `needle` in `text`.
pub fn location_of(text: &str, needle: &str) -> String {
    let offset = text.find(needle).expect("needle in the scene");
    let line = text[..offset].matches('\n').count() + 1;
    let column = offset - text[..offset].rfind('\n').map_or(0, |i| i + 1) + 1;
    format!("bad.toml:{line}:{column}:")
}

/// The message of loading `text`; panics if it loads.
pub fn load_error(text: &str) -> String {
    match load_text(text) {
        Ok(_) => panic!("{text} loaded"),
        Err(e) => e.to_string(),
    }
}
