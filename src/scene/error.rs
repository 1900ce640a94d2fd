//! Scene-file errors, and the helpers that turn a bad value into one.
//!
//! Every error names the scene file. When the problem sits at a place in the file, the message
//! starts with `file:line:column:` (1-based, the column counted in characters), followed by the
//! field path in the file (`objects[1].panel.thickness_mm`, array indices from 0) and what was
//! expected, in the style of compiler diagnostics (pbrt's `ErrorExit(&loc, …)`):
//!
//! ```text
//! scenes/x.toml:12:16: objects[1].panel.thickness_mm must be > 0, got -4
//! ```

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde_spanned::Spanned;

/// Why a scene file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: cannot read the scene file: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file is not valid TOML, or does not have the shape of a scene file (unknown key,
    /// missing key, wrong type). `message` starts with the field path when it can be found.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Parse {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column (characters).
        column: usize,
        /// What the parser expected.
        message: String,
    },
    /// A value is out of its range or inconsistent with another one.
    #[error("{}:{line}:{column}: {field} {message}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the offending value.
        line: usize,
        /// 1-based column of the offending value.
        column: usize,
        /// Field path, e.g. `objects[1].panel.thickness_mm`.
        field: String,
        /// What was expected and what was given, e.g. `must be > 0, got -4`.
        message: String,
    },
    /// `sensor.preset` names no known preset.
    #[error(
        "{}:{line}:{column}: sensor.preset: unknown preset `{name}`, expected one of {}",
        path.display(),
        quoted_list(valid)
    )]
    UnknownPreset {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The name given.
        name: String,
        /// The valid preset names.
        valid: Vec<String>,
    },
    /// A mesh file named by an object does not exist.
    #[error(
        "{}:{line}:{column}: {field}: mesh file `{}` not found ({source})",
        path.display(),
        mesh_path.display()
    )]
    MissingMesh {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the `file` value.
        line: usize,
        /// 1-based column of the `file` value.
        column: usize,
        /// Field path, e.g. `objects[2].mesh.file`.
        field: String,
        /// The mesh path, resolved against the scene file's folder.
        mesh_path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A glTF file could not be read or holds no usable geometry.
    #[error(
        "{}:{line}:{column}: {field}: cannot load glTF `{}`: {message}",
        path.display(),
        mesh_path.display()
    )]
    Gltf {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the `file` value.
        line: usize,
        /// 1-based column of the `file` value.
        column: usize,
        /// Field path, e.g. `objects[2].mesh.file`.
        field: String,
        /// The glTF file.
        mesh_path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A glTF primitive draws points or lines: it has no surface to hit.
    #[error(
        "{}:{line}:{column}: {field}: glTF `{}`: mesh {mesh} primitive {primitive} has mode \
         {mode}, expected triangles (TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN)",
        path.display(),
        mesh_path.display()
    )]
    NonTrianglePrimitive {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the `file` value.
        line: usize,
        /// 1-based column of the `file` value.
        column: usize,
        /// Field path, e.g. `objects[2].mesh.file`.
        field: String,
        /// The glTF file.
        mesh_path: PathBuf,
        /// Index of the glTF mesh in the file's `meshes` array.
        mesh: usize,
        /// Index of the primitive within the mesh.
        primitive: usize,
        /// The primitive's mode (`LINES`, `POINTS`, …).
        mode: &'static str,
    },
    /// The scene has no `[[objects]]`.
    #[error(
        "{}: the scene has no objects, expected at least one [[objects]] table",
        path.display()
    )]
    EmptyScene {
        /// The scene file.
        path: PathBuf,
    },
    /// An object names a material that `[materials]` does not define.
    #[error(
        "{}:{line}:{column}: {field}: unknown material `{}`, expected {}",
        path.display(),
        clipped(name),
        one_of(known, "a material defined under [materials] (none are defined)")
    )]
    UnknownMaterial {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Field path, e.g. `objects[0].material`.
        field: String,
        /// The name given.
        name: String,
        /// The materials the file defines.
        known: Vec<String>,
    },
    /// `target.object` names no object.
    #[error(
        "{}:{line}:{column}: {field}: unknown object `{}`, expected {}",
        path.display(),
        clipped(name),
        one_of(known, "an object name")
    )]
    UnknownObject {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Field path (`target.object`).
        field: String,
        /// The name given.
        name: String,
        /// The object names of the scene.
        known: Vec<String>,
    },
    /// `target.object` names an object that is neither a procedural panel nor a mesh, so it
    /// has no border curve to scan.
    #[error(
        "{}:{line}:{column}: {field}: object `{}` is a {kind} object, expected a panel or \
         mesh object (only those have a border curve to scan)",
        path.display(),
        clipped(name)
    )]
    TargetNotPanel {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Field path (`target.object`).
        field: String,
        /// The object named.
        name: String,
        /// What it is instead (`box`, `mesh`, `tape`, `cover`).
        kind: &'static str,
    },
    /// Two objects share a name.
    #[error(
        "{}:{line}:{column}: {field}: duplicate object name `{name}` (first used at \
         {first_line}:{first_column})",
        path.display()
    )]
    DuplicateName {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the second use.
        line: usize,
        /// 1-based column of the second use.
        column: usize,
        /// Field path of the second use, e.g. `objects[3].name`.
        field: String,
        /// The repeated name.
        name: String,
        /// 1-based line of the first use.
        first_line: usize,
        /// 1-based column of the first use.
        first_column: usize,
    },
}

fn quoted_list(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("`{}`", clipped(n)))
        .collect::<Vec<_>>()
        .join(", ")
}

fn one_of(names: &[String], if_empty: &str) -> String {
    if names.is_empty() {
        if_empty.to_owned()
    } else {
        format!("one of {}", quoted_list(names))
    }
}

/// The text of a scene file with its path: turns byte spans into `line:column` and builds
/// located errors.
pub(crate) struct SceneSource<'a> {
    /// The path as the caller gave it (shown in messages).
    pub path: &'a Path,
    /// The file contents.
    pub text: &'a str,
}

impl SceneSource<'_> {
    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_column(&self, offset: usize) -> (usize, usize) {
        let offset = floor_char_boundary(self.text, offset);
        let before = &self.text[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line = before.matches('\n').count() + 1;
        let column = before[line_start..].chars().count() + 1;
        (line, column)
    }

    /// An `Invalid` error at `span`.
    pub fn invalid(
        &self,
        span: &Range<usize>,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> SceneError {
        let (line, column) = self.line_column(span.start);
        SceneError::Invalid {
            path: self.path.to_owned(),
            line,
            column,
            field: field.into(),
            message: message.into(),
        }
    }

    /// Maps a TOML/serde error to a `Parse` error at its span, prefixed with the field path
    /// that encloses the span (serde's messages name the key but not where it lives).
    pub fn parse_error(&self, error: &toml::de::Error) -> SceneError {
        let span = error.span().unwrap_or(0..0);
        let (line, column) = self.line_column(span.start);
        let message = error.message().trim().replace('\n', ", ");
        // An empty span at the very start is where serde reports a key missing from the
        // top-level table; no enclosing table applies.
        let top_level = span == (0..0);
        let context = if top_level {
            None
        } else {
            key_path_at(self.text, span.start)
        };
        let message = match context {
            Some(path) => format!("{path}: {message}"),
            None => message,
        };
        SceneError::Parse {
            path: self.path.to_owned(),
            line,
            column,
            message,
        }
    }

    /// Checks that a number is finite and satisfies `ok`; `expected` completes
    /// "`field` …", e.g. "must be > 0". A length (a key ending in `_mm` or `_um`) must also be
    /// within [`crate::limits::MAX_LENGTH_MM`].
    pub fn number(
        &self,
        value: &Spanned<f64>,
        field: &str,
        ok: impl Fn(f64) -> bool,
        expected: &str,
    ) -> Result<f64, SceneError> {
        let v = *value.get_ref();
        if !v.is_finite() {
            return Err(self.invalid(
                &value.span(),
                field,
                format!("must be a finite number, got {v}"),
            ));
        }
        if !ok(v) {
            return Err(self.invalid(
                &value.span(),
                field,
                format!("{expected}, got {}", shown(v)),
            ));
        }
        if let Some(max) = crate::limits::length_bound(field) {
            if v.abs() > max {
                return Err(self.invalid(
                    &value.span(),
                    field,
                    format!(
                        "must be at most {max:e} in magnitude (100 m), got {}",
                        shown(v)
                    ),
                ));
            }
        }
        Ok(v)
    }

    /// A finite number > 0.
    pub fn positive(&self, value: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        self.number(value, field, |v| v > 0.0, "must be > 0")
    }

    /// A finite number ≥ 0.
    pub fn non_negative(&self, value: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        self.number(value, field, |v| v >= 0.0, "must be ≥ 0")
    }

    /// Any finite number.
    pub fn finite(&self, value: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        self.number(value, field, |_| true, "")
    }

    /// Three finite numbers; the error names the component (`field[1]`).
    pub fn finite3(&self, values: &[Spanned<f64>; 3], field: &str) -> Result<[f64; 3], SceneError> {
        let mut out = [0.0; 3];
        for (i, v) in values.iter().enumerate() {
            out[i] = self.finite(v, &format!("{field}[{i}]"))?;
        }
        Ok(out)
    }

    /// An integer in `lo..=hi`.
    pub fn integer(
        &self,
        value: &Spanned<i64>,
        field: &str,
        lo: i64,
        hi: i64,
    ) -> Result<i64, SceneError> {
        let v = *value.get_ref();
        if v < lo || v > hi {
            let expected = if hi == i64::MAX {
                format!("must be ≥ {lo}")
            } else {
                format!("must be in {lo}..={hi}")
            };
            return Err(self.invalid(&value.span(), field, format!("{expected}, got {v}")));
        }
        Ok(v)
    }
}

/// A name as a message shows it: whole up to 80 characters, else its first 80 and a count (a
/// 5 MB name is not echoed whole).
fn clipped(name: &str) -> String {
    const SHOWN: usize = 80;
    match name.char_indices().nth(SHOWN) {
        None => name.to_owned(),
        Some((cut, _)) => format!("{}… ({} characters)", &name[..cut], name.chars().count()),
    }
}

/// A number as a message shows it: plain, or in scientific notation when plain would be long
/// (`1e300`, not three hundred digits).
fn shown(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-6..1e15).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    if i >= s.len() {
        return s.len();
    }
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// The dotted key path that encloses byte `offset` of a TOML text: the last table header
/// before it (with array-of-tables indices, `objects[1].panel`) and the keys of any inline
/// tables open on its line before it (`pose.translation_mm`). A best-effort reading for error
/// messages: it does not follow values that span several lines.
fn key_path_at(text: &str, offset: usize) -> Option<String> {
    let offset = floor_char_boundary(text, offset);
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[offset..].find('\n').map_or(text.len(), |i| offset + i);
    let mut section: Vec<String> = Vec::new();
    // How many times each array of tables has been opened so far, by its dotted name.
    let mut array_counts: Vec<(String, usize)> = Vec::new();
    for line in text[..line_end].lines() {
        let line = line.trim();
        let (name, rest, is_array) = if let Some(rest) = line.strip_prefix("[[") {
            match rest.split_once("]]") {
                Some((name, rest)) => (name, rest, true),
                None => continue,
            }
        } else if let Some(rest) = line.strip_prefix('[') {
            match rest.split_once(']') {
                Some((name, rest)) => (name, rest, false),
                None => continue,
            }
        } else {
            continue;
        };
        // Lines of a multi-line array (`[0, 0],`) also start with a bracket.
        let rest = rest.trim();
        let is_key = |c: char| c.is_alphanumeric() || "_-. \"'".contains(c);
        if !(rest.is_empty() || rest.starts_with('#')) || !name.chars().all(is_key) {
            continue;
        }
        let parts: Vec<&str> = name.split('.').map(str::trim).collect();
        if is_array {
            let full = parts.join(".");
            match array_counts.iter_mut().find(|(n, _)| *n == full) {
                Some((_, count)) => *count += 1,
                None => array_counts.push((full, 1)),
            }
        }
        section.clear();
        for i in 0..parts.len() {
            let prefix = parts[..=i].join(".");
            let count = array_counts.iter().find(|(n, _)| *n == prefix);
            section.push(match count {
                Some((_, c)) => format!("{}[{}]", parts[i], c - 1),
                None => parts[i].to_owned(),
            });
        }
    }
    let on_line = if text[line_start..].trim_start().starts_with('[') {
        Vec::new()
    } else {
        inline_keys(&text[line_start..offset])
    };
    section.extend(on_line);
    (!section.is_empty()).then(|| section.join("."))
}

/// Keys of the inline tables still open at the end of `prefix` (the start of a line up to an
/// error), plus the key whose value starts there, e.g. `pose = { translation_mm = ` →
/// `[pose, translation_mm]`.
fn inline_keys(prefix: &str) -> Vec<String> {
    let mut stack: Vec<String> = Vec::new();
    let mut pending: Option<String> = None;
    let mut word = String::new();
    let mut in_string: Option<char> = None;
    for ch in prefix.chars() {
        if let Some(q) = in_string {
            if ch == q {
                in_string = None;
            }
            continue;
        }
        match ch {
            '"' | '\'' => in_string = Some(ch),
            '=' => {
                pending = Some(std::mem::take(&mut word));
            }
            '{' => {
                stack.push(pending.take().unwrap_or_default());
                word.clear();
            }
            '}' => {
                stack.pop();
                pending = None;
                word.clear();
            }
            ',' => {
                pending = None;
                word.clear();
            }
            c if c.is_alphanumeric() || c == '_' || c == '-' => word.push(c),
            c if c.is_whitespace() => {}
            _ => word.clear(),
        }
    }
    stack.extend(pending);
    stack.retain(|k| !k.is_empty());
    stack
}

#[cfg(test)]
mod clipping_tests {
    use super::clipped;

    #[test]
    fn long_names_are_clipped_in_messages() {
        assert_eq!(clipped("window"), "window");
        let long = "é".repeat(5_000_000);
        let c = clipped(&long);
        assert!(
            c.ends_with("… (5000000 characters)") && c.chars().count() < 110,
            "{}",
            c.len()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_column_is_one_based_and_counts_characters() {
        let text = "a = 1\nbé = 2\n";
        let src = SceneSource {
            path: Path::new("x.toml"),
            text,
        };
        assert_eq!(src.line_column(0), (1, 1));
        assert_eq!(src.line_column(6), (2, 1));
        // "bé = " is 6 bytes but 5 characters.
        assert_eq!(src.line_column(12), (2, 6));
    }

    #[test]
    fn key_path_follows_headers_arrays_and_inline_tables() {
        let text = "[[objects]]\nname = \"a\"\n[[objects]]\nname = \"b\"\n[objects.panel]\n\
                    pose = { translation_mm = [1, 2] }\n";
        let at = text.find("[1, 2]").unwrap();
        assert_eq!(
            key_path_at(text, at).as_deref(),
            Some("objects[1].panel.pose.translation_mm")
        );
        let header = text.find("[objects.panel]").unwrap();
        assert_eq!(
            key_path_at(text, header).as_deref(),
            Some("objects[1].panel")
        );
        assert_eq!(key_path_at("a = 1", 4).as_deref(), Some("a"));
        assert_eq!(key_path_at("a = 1", 0), None);
    }

    /// Every bad input gives a message that names the file, the line:column of the offending
    /// value, the field and what was expected. The cases edit this valid scene.
    const BASE: &str = r#"[materials.white]
kind = "lambertian"
albedo = 0.8

[materials.glass]
kind = "glass"
ior = 1.52
absorption_per_mm = 0.003
face_imperfection = 0.002
edge_roughness = 0.3

[[objects]]
name = "plate"
material = "white"
[objects.panel]
outline = { width_mm = 300, height_mm = 200, corner_radius_mm = 10 }
thickness_mm = 4

[[objects]]
name = "table"
material = "white"
box = { size_mm = [1000, 800, 20] }
pose = { translation_mm = [0, 0, -10] }

[target]
object = "plate"

[sensor]
preset = "scancontrol-2600-100"

[scan]
poses = 4
"#;

    /// Writes `text` as `bad.toml` into a fresh temporary folder (with the test meshes under
    /// `meshes/`) and loads it.
    fn load_text(text: &str) -> Result<crate::scene::world::World, SceneError> {
        let dir = tempfile::tempdir().expect("temp dir");
        let meshes = dir.path().join("meshes");
        std::fs::create_dir(&meshes).expect("mkdir");
        let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes");
        for name in ["cube.gltf", "lines.gltf"] {
            std::fs::copy(fixtures.join(name), meshes.join(name)).expect("copy fixture");
        }
        let path = dir.path().join("bad.toml");
        std::fs::write(&path, text).expect("write scene");
        crate::scene::load(&path)
    }

    /// `BASE` with `from` replaced by `to` (which must occur), loaded; returns the message.
    fn error_for(from: &str, to: &str) -> String {
        assert!(BASE.contains(from), "test bug: {from:?} not in BASE");
        match load_text(&BASE.replacen(from, to, 1)) {
            Ok(_) => panic!("expected an error after replacing {from:?} with {to:?}"),
            Err(e) => e.to_string(),
        }
    }

    fn assert_message(message: &str, expected: &str) {
        assert!(
            message.contains(expected),
            "\n  message: {message}\n expected: {expected}"
        );
    }

    #[test]
    fn base_scene_is_valid() {
        let world = load_text(BASE).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(world.objects.len(), 2);
        // The unused glass material is validated but not kept.
        assert_eq!(world.materials.len(), 1);
    }

    #[test]
    fn non_finite_numbers_are_rejected() {
        let m = error_for("thickness_mm = 4", "thickness_mm = nan");
        assert_message(
            &m,
            "bad.toml:17:16: objects[0].panel.thickness_mm must be a finite number, got NaN",
        );
        let m = error_for("[0, 0, -10]", "[0, 0, -inf]");
        assert_message(
            &m,
            "bad.toml:23:34: objects[1].pose.translation_mm[2] must be a finite number, got -inf",
        );
        let m = error_for("albedo = 0.8", "albedo = +inf");
        assert_message(
            &m,
            "bad.toml:3:10: materials.white.albedo must be a finite number, got inf",
        );
    }

    #[test]
    fn zero_and_negative_sizes_are_rejected() {
        let m = error_for("thickness_mm = 4", "thickness_mm = -4");
        assert_message(
            &m,
            "bad.toml:17:16: objects[0].panel.thickness_mm must be > 0, got -4",
        );
        let m = error_for("[1000, 800, 20]", "[1000, 0, 20]");
        assert_message(
            &m,
            "bad.toml:22:26: objects[1].box.size_mm[1] must be > 0, got 0",
        );
        let m = error_for("width_mm = 300", "width_mm = 0");
        assert_message(
            &m,
            "bad.toml:16:24: objects[0].panel.outline.width_mm must be > 0, got 0",
        );
        let m = error_for("corner_radius_mm = 10", "corner_radius_mm = -1");
        assert_message(
            &m,
            "bad.toml:16:65: objects[0].panel.outline.corner_radius_mm must be ≥ 0, got -1",
        );
    }

    #[test]
    fn albedo_outside_unit_interval_is_rejected() {
        let m = error_for("albedo = 0.8", "albedo = 1.2");
        assert_message(
            &m,
            "bad.toml:3:10: materials.white.albedo must be in [0, 1], got 1.2",
        );
        let m = error_for("albedo = 0.8", "albedo = -0.1");
        assert_message(
            &m,
            "bad.toml:3:10: materials.white.albedo must be in [0, 1], got -0.1",
        );
    }

    #[test]
    fn unknown_preset_lists_the_presets() {
        let m = error_for("\"scancontrol-2600-100\"", "\"scancontrol-26\"");
        assert_message(&m, "bad.toml:29:10: sensor.preset: unknown preset `scancontrol-26`, expected one of `scancontrol-2600-100`");
    }

    #[test]
    fn unknown_keys_keep_their_location_and_table() {
        let m = error_for("thickness_mm = 4", "thicknes_mm = 4");
        assert_message(
            &m,
            "bad.toml:17:1: objects[0].panel: unknown field `thicknes_mm`, expected",
        );
        let m = error_for("corner_radius_mm = 10", "corner_radius = 10");
        assert_message(
            &m,
            "bad.toml:16:46: objects[0].panel.outline: unknown field `corner_radius`",
        );
        let m = error_for("[scan]\n", "[scan]\nscan_angle = 45\n");
        assert_message(&m, "bad.toml:32:1: scan: unknown field `scan_angle`");
        // A wrong type is a parse error with the field too.
        let m = error_for("poses = 4", "poses = 2.5");
        assert_message(
            &m,
            "bad.toml:32:9: scan.poses: invalid type: floating point `2.5`",
        );
        // So is a syntax error.
        let m = error_for("thickness_mm = 4", "thickness_mm = ");
        assert_message(&m, "bad.toml:17:16: objects[0].panel.thickness_mm: ");
        // A missing top-level table is reported without a table path.
        let m = error_for("[sensor]\npreset = \"scancontrol-2600-100\"\n", "");
        assert_message(&m, "bad.toml:1:1: missing field `sensor`");
    }

    #[test]
    fn missing_mesh_file_names_the_resolved_path() {
        let m = error_for(
            "box = { size_mm = [1000, 800, 20] }",
            "mesh = { file = \"meshes/nope.gltf\" }",
        );
        assert_message(&m, "bad.toml:22:17: objects[1].mesh.file: mesh file `");
        assert_message(&m, "meshes/nope.gltf` not found");
    }

    #[test]
    fn non_triangle_gltf_primitive_is_rejected() {
        let m = error_for(
            "box = { size_mm = [1000, 800, 20] }",
            "mesh = { file = \"meshes/lines.gltf\" }",
        );
        assert_message(&m, "bad.toml:22:17: objects[1].mesh.file: glTF `");
        assert_message(
            &m,
            "lines.gltf`: mesh 0 primitive 0 has mode LINES, expected triangles",
        );
    }

    #[test]
    fn gltf_mesh_object_loads_relative_to_the_scene_with_node_transforms() {
        let text = BASE.replace(
            "box = { size_mm = [1000, 800, 20] }",
            "mesh = { file = \"meshes/cube.gltf\", scale = 0.001 }",
        );
        let world = load_text(&text).unwrap_or_else(|e| panic!("{e}"));
        let mesh = &world.objects[1].mesh;
        assert_eq!(mesh.triangle_count(), 12);
        // Node translations (0, 0, 2) + (1, 0, 0) in file units (mm here).
        let centre = mesh
            .positions
            .iter()
            .map(|p| p.coords)
            .sum::<nalgebra::Vector3<f64>>()
            / 8.0;
        // In the file, (1, 0, 2): glTF's +Y up turned to +Z up, (x, y, z) ↦ (x, −z, y).
        assert!(
            (centre - nalgebra::Vector3::new(0.001, -0.002, 0.0)).norm() < 1e-9,
            "{centre:?}"
        );
        assert!(world.warnings.is_empty(), "{:?}", world.warnings);
        // up_axis = "z" takes the file's axes as they are.
        let z_up = load_text(&BASE.replace(
            "box = { size_mm = [1000, 800, 20] }",
            "mesh = { file = \"meshes/cube.gltf\", scale = 0.001, up_axis = \"z\" }",
        ))
        .unwrap_or_else(|e| panic!("{e}"));
        let mut centre_z = nalgebra::Vector3::zeros();
        for p in &z_up.objects[1].mesh.positions {
            centre_z += p.coords / 8.0;
        }
        assert!(
            (centre_z - nalgebra::Vector3::new(0.001, 0.0, 0.002)).norm() < 1e-9,
            "{centre_z:?}"
        );
        // The conversion is a rotation: outward normals stay outward, lengths stay.
        for (a, b) in mesh.positions.iter().zip(&z_up.objects[1].mesh.positions) {
            assert_eq!((a.x, a.y, a.z), (b.x, -b.z, b.y));
        }
        let m = error_for(
            "box = { size_mm = [1000, 800, 20] }",
            "mesh = { file = \"meshes/cube.gltf\", up_axis = \"x\" }",
        );
        assert_message(&m, "bad.toml:22:");
        assert!(
            m.contains("up_axis") || m.contains("unknown variant"),
            "{m}"
        );
        let m = error_for(
            "box = { size_mm = [1000, 800, 20] }",
            "mesh = { file = \"meshes/cube.gltf\", scale = 0 }",
        );
        assert_message(
            &m,
            "bad.toml:22:45: objects[1].mesh.scale must be > 0, got 0",
        );
    }

    #[test]
    fn empty_scene_is_rejected() {
        let m = match load_text("[sensor]\npreset = \"scancontrol-2600-100\"\n") {
            Err(e) => e.to_string(),
            Ok(_) => panic!("a scene without objects loaded"),
        };
        assert_message(
            &m,
            "bad.toml: the scene has no objects, expected at least one [[objects]] table",
        );
    }

    #[test]
    fn unknown_material_lists_the_materials() {
        let m = error_for(
            "material = \"white\"\n[objects.panel]",
            "material = \"whyte\"\n[objects.panel]",
        );
        assert_message(&m, "bad.toml:14:12: objects[0].material: unknown material `whyte`, expected one of `white`, `glass`");
    }

    #[test]
    fn target_must_name_a_panel_object() {
        let m = error_for("object = \"plate\"", "object = \"table\"");
        assert_message(&m, "bad.toml:26:10: target.object: object `table` is a box object, expected a panel or mesh object");
        let m = error_for("object = \"plate\"", "object = \"plat\"");
        assert_message(&m, "bad.toml:26:10: target.object: unknown object `plat`, expected one of `plate`, `table`");
    }

    #[test]
    fn duplicate_object_names_are_rejected() {
        let m = error_for("name = \"table\"", "name = \"plate\"");
        assert_message(
            &m,
            "bad.toml:20:8: objects[1].name: duplicate object name `plate` (first used at 13:8)",
        );
    }

    #[test]
    fn glass_needs_exactly_one_index_law() {
        let m = error_for("ior = 1.52\n", "");
        assert_message(&m, "bad.toml:5:1: materials.glass must give exactly one index law (`ior`, `cauchy` or `sellmeier`), got none");
        let m = error_for("ior = 1.52\n", "ior = 1.52\ncauchy = [1.5, 0.004]\n");
        assert_message(&m, "bad.toml:8:10: materials.glass must give exactly one index law (`ior`, `cauchy` or `sellmeier`), got both `ior` and `cauchy`");
        let m = error_for(
            "ior = 1.52\n",
            "sellmeier = { b = [1.04, 0.23, 1.01], c = [0.006, 0.02] }\n",
        );
        assert_message(&m, "bad.toml:7:43: materials.glass.sellmeier.c: invalid length 2, expected an array of length 3");
        let m = error_for("ior = 1.52\n", "albedo = 0.5\nior = 1.52\n");
        assert_message(
            &m,
            "bad.toml:7:10: materials.glass.albedo is a lambertian field",
        );
        let m = error_for("albedo = 0.8", "albedo = 0.8\nior = 1.5");
        assert_message(&m, "bad.toml:4:7: materials.white.ior is a glass field");
    }

    #[test]
    fn index_law_must_give_a_physical_index_at_the_laser_wavelength() {
        // Glass used by an object, with a Cauchy law that gives n < 1 at 658 nm.
        let text = BASE
            .replace("ior = 1.52", "cauchy = [0.9, 0.001]")
            .replacen(
                "material = \"white\"\n[objects.panel]",
                "material = \"glass\"\n[objects.panel]",
                1,
            );
        let m = load_text(&text).map(|_| ()).unwrap_err().to_string();
        assert_message(&m, "bad.toml:7:10: materials.glass.cauchy must give a refractive index ≥ 1 at the laser wavelength 658.0 nm");
    }

    #[test]
    fn sensor_cross_checks_are_located() {
        let preset = "preset = \"scancontrol-2600-100\"";
        let m = error_for(preset, &format!("{preset}\nexposure_ms = 0"));
        assert_message(&m, "bad.toml:30:15: sensor.exposure_ms must be > 0, got 0");
        let m = error_for(preset, &format!("{preset}\nthreshold_dn = 2000"));
        assert_message(&m, "bad.toml:30:16: sensor.threshold_dn must be ≤ 2^adc_bits − 1 = 1023 (adc_bits = 10), got 2000");
        let m = error_for(preset, &format!("{preset}\npoints_per_profile = 100"));
        assert_message(&m, "bad.toml:30:22: sensor.points_per_profile must divide the camera's 640 columns, got 100");
    }

    #[test]
    fn scan_settings_are_range_checked() {
        let m = error_for("poses = 4", "poses = 4\nstandoff_mm = 500");
        assert_message(&m, "bad.toml:33:15: scan.standoff_mm must lie in the sensor's z range 125..=390 mm, got 500");
        let m = error_for("poses = 4", "scan_angle_deg = 0");
        assert_message(
            &m,
            "bad.toml:32:18: scan.scan_angle_deg must be in (0, 90] degrees, got 0",
        );
        let m = error_for("poses = 4", "scan_angle_deg = 90.5");
        assert_message(
            &m,
            "bad.toml:32:18: scan.scan_angle_deg must be in (0, 90] degrees, got 90.5",
        );
        let m = error_for("poses = 4", "poses = 0");
        assert_message(
            &m,
            "bad.toml:32:9: scan.poses must be in 1..=1000000, got 0",
        );
        let m = error_for("poses = 4", "start_fraction = 1");
        assert_message(
            &m,
            "bad.toml:32:18: scan.start_fraction must be in [0, 1), got 1",
        );
        load_text(&BASE.replace("poses = 4", "scan_angle_deg = 90"))
            .expect("90° looks straight down");
    }

    #[test]
    fn panel_builder_errors_point_at_their_field() {
        // A corner radius larger than half the shorter side: checked by `build_panel`.
        let m = error_for("corner_radius_mm = 10", "corner_radius_mm = 150");
        assert_message(
            &m,
            "bad.toml:16:65: objects[0].panel.outline.corner_radius_mm ",
        );
        // A bevel as deep as half the thickness.
        let m = error_for(
            "thickness_mm = 4",
            "thickness_mm = 4\nedge = { arrissed = { bevel_mm = 3 } }",
        );
        assert_message(
            &m,
            "bad.toml:18:34: objects[0].panel.edge.arrissed.bevel_mm ",
        );
    }

    #[test]
    fn a_mesh_of_implausible_size_is_loaded_with_a_warning_that_names_scale() {
        let load = |scale: &str| {
            load_text(&BASE.replace(
                "box = { size_mm = [1000, 800, 20] }",
                &format!("mesh = {{ file = \"meshes/cube.gltf\", scale = {scale} }}"),
            ))
            .unwrap_or_else(|e| panic!("{e}"))
        };
        // A unit cube: 1 m (plausible), 1 mm (plausible), 20 m and 0.1 mm (not). (Past
        // 100 m from the origin a mesh is refused: `limits`.)
        assert!(load("1").warnings.is_empty());
        assert!(load("0.001").warnings.is_empty());
        let big = load("20").warnings;
        assert_eq!(big.len(), 1, "{big:?}");
        assert!(
            big[0].starts_with(
                "objects[1].mesh: `meshes/cube.gltf` is 20.0000 × 20.0000 × 20.0000 m"
            ) && big[0].contains("set `scale = 0.001`"),
            "{}",
            big[0]
        );
        let small = load("0.0001").warnings;
        assert!(small[0].contains("check `scale`"), "{small:?}");
    }

    #[test]
    fn object_needs_exactly_one_shape() {
        let m = error_for(
            "pose = { translation_mm = [0, 0, -10] }",
            "mesh = { file = \"meshes/cube.gltf\" }",
        );
        assert_message(&m, "bad.toml:23:8: objects[1] must have exactly one of `panel`, `box`, `mesh`, `tape` or `cover`, got both `box` and `mesh`");
        let m = error_for("box = { size_mm = [1000, 800, 20] }\n", "");
        assert_message(
            &m,
            "bad.toml:19:1: objects[1] must have exactly one of `panel`, `box`, `mesh`, `tape` or `cover`, got none",
        );
    }

    #[test]
    fn unreadable_scene_file_is_an_io_error() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("missing.toml");
        let m = crate::scene::load(&path)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert_message(&m, "missing.toml: cannot read the scene file");
    }
}
