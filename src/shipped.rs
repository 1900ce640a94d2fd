//! The scenes and regression suites shipped inside the binary, so that `glassscan scan
//! edge_study`, `glassscan check fast` and `glassscan study scan-angle` work from any
//! directory.
//!
//! Every file of `scenes/` (scene files, the randomisation file, the mesh fixtures, the
//! scene-file reference) and of `validation/check/` (suites and their baselines) is embedded
//! under its path in the repository (`scenes/edge_study.toml`). The one rule, for every file
//! glassscan reads: **a file that exists on disk wins**; a path that does not exist but is the
//! repository path of a shipped file reads the shipped copy. On top of that, the command line
//! takes a shipped scene by name (`edge_study` for `scenes/edge_study.toml`, see
//! [`resolve_scene`]) and a suite by name (`fast`, see [`resolve_suite`]).
//!
//! A leaf module: it knows paths and bytes, nothing of what they mean.

use std::io;
use std::path::{Component, Path, PathBuf};

/// One shipped file: its path in the repository and its bytes, exactly as committed.
#[derive(Debug, PartialEq, Eq)]
pub struct ShippedFile {
    /// Path relative to the repository root, `/`-separated (`scenes/edge_study.toml`).
    pub path: &'static str,
    /// The file's bytes.
    pub bytes: &'static [u8],
}

impl ShippedFile {
    /// The file's name without folder and extension (`edge_study`, `fast.baseline`).
    pub fn stem(&self) -> &'static str {
        let name = self.path.rsplit('/').next().unwrap_or(self.path);
        name.split_once('.').map_or(name, |(stem, _)| stem)
    }

    /// What the file is, for listings.
    pub fn kind(&self) -> FileKind {
        let p = self.path;
        if p.starts_with("validation/check/") {
            if p.ends_with(".baseline.json") {
                FileKind::Baseline
            } else {
                FileKind::Suite
            }
        } else if p.starts_with("scenes/meshes/") {
            FileKind::Mesh
        } else if p.ends_with(".md") {
            FileKind::Reference
        } else if self.stem().starts_with("randomize_") {
            FileKind::Randomization
        } else {
            FileKind::Scene
        }
    }

    /// The first sentence of a TOML file's opening comment, without the `name:` that starts
    /// it, cut to about 100 characters at a word: the one-line description of a scene or suite
    /// (empty when the file has none).
    pub fn description(&self) -> String {
        let text = std::str::from_utf8(self.bytes).unwrap_or("");
        let comment: Vec<&str> = text
            .lines()
            .map_while(|l| l.strip_prefix('#'))
            .map(str::trim)
            .take_while(|l| !l.is_empty())
            .collect();
        let comment = comment.join(" ");
        let comment = comment
            .strip_prefix(&format!("{}:", self.stem()))
            .unwrap_or(&comment)
            .trim();
        // A sentence ends at `. ` before a capital letter (not `Fig. 6`).
        let bytes = comment.as_bytes();
        let end = (0..bytes.len().saturating_sub(2))
            .find(|&i| {
                bytes[i] == b'.' && bytes[i + 1] == b' ' && bytes[i + 2].is_ascii_uppercase()
            })
            .unwrap_or(comment.len());
        let sentence = comment[..end].trim_end_matches(['.', ':', ',', ';']);
        const MAX: usize = 100;
        if sentence.chars().count() <= MAX {
            return sentence.to_string();
        }
        let cut: String = sentence.chars().take(MAX).collect();
        let cut = cut.rsplit_once(' ').map_or(cut.as_str(), |(head, _)| head);
        format!("{}…", cut.trim_end_matches([',', ';', ':']))
    }
}

/// What a shipped file is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A scene file (`scenes/NAME.toml`).
    Scene,
    /// A domain-randomisation file (`scenes/randomize_NAME.toml`).
    Randomization,
    /// A glTF mesh (`scenes/meshes/`).
    Mesh,
    /// Documentation (`scenes/README.md`, the scene-file reference).
    Reference,
    /// A regression suite (`validation/check/NAME.toml`).
    Suite,
    /// A suite's baseline (`validation/check/NAME.baseline.json`).
    Baseline,
}

impl FileKind {
    /// The kind's name in listings.
    pub fn name(self) -> &'static str {
        match self {
            FileKind::Scene => "scene",
            FileKind::Randomization => "randomisation",
            FileKind::Mesh => "mesh",
            FileKind::Reference => "reference",
            FileKind::Suite => "suite",
            FileKind::Baseline => "baseline",
        }
    }
}

macro_rules! shipped {
    ($($path:literal),* $(,)?) => {
        &[$(ShippedFile {
            path: $path,
            bytes: include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/", $path)),
        }),*]
    };
}

/// Every shipped file, sorted by path. `validation/cli_help.rs` checks that this is exactly
/// the set of files in `scenes/` and `validation/check/`.
pub static FILES: &[ShippedFile] = shipped![
    "scenes/README.md",
    "scenes/car_side_window.toml",
    "scenes/car_side_window_gltf.toml",
    "scenes/edge_study.toml",
    "scenes/edge_study_bare.toml",
    "scenes/edge_study_cover.toml",
    "scenes/edge_study_tape.toml",
    "scenes/flat_opaque.toml",
    "scenes/flat_panel.toml",
    "scenes/meshes/car_side_window.glb",
    "scenes/meshes/cube.gltf",
    "scenes/meshes/lines.gltf",
    "scenes/mixed_pixels.toml",
    "scenes/randomize_edge_study.toml",
    "validation/check/fast.baseline.json",
    "validation/check/fast.toml",
    "validation/check/full.baseline.json",
    "validation/check/full.toml",
];

/// The shipped file whose repository path `path` is (`./scenes/x.toml` and `scenes//x.toml`
/// too; an absolute path or one with `..` never is).
pub fn file(path: &Path) -> Option<&'static ShippedFile> {
    let mut parts = Vec::new();
    for c in path.components() {
        match c {
            Component::Normal(s) => parts.push(s.to_str()?),
            Component::CurDir => {}
            _ => return None,
        }
    }
    let key = parts.join("/");
    FILES.iter().find(|f| f.path == key)
}

/// The shipped files of one kind, in path order.
pub fn of_kind(kind: FileKind) -> impl Iterator<Item = &'static ShippedFile> {
    FILES.iter().filter(move |f| f.kind() == kind)
}

/// The names of the shipped scenes (`car_side_window`, `edge_study`, …).
pub fn scene_names() -> Vec<&'static str> {
    of_kind(FileKind::Scene).map(ShippedFile::stem).collect()
}

/// The names of the shipped regression suites (`fast`, `full`).
pub fn suite_names() -> Vec<&'static str> {
    of_kind(FileKind::Suite).map(ShippedFile::stem).collect()
}

/// The shipped copy that `path` reads, if `path` does not exist on disk and is the
/// repository path of a shipped file; `None` when the file on disk is read (or nothing).
pub fn fallback(path: &Path) -> Option<&'static ShippedFile> {
    if path.exists() {
        None
    } else {
        file(path)
    }
}

/// Whether `path` can be read: it exists on disk or is the path of a shipped file.
pub fn is_file(path: &Path) -> bool {
    path.is_file() || fallback(path).is_some()
}

/// Reads `path` from disk, or its shipped copy when it does not exist on disk (the file
/// system's own error otherwise).
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    match std::fs::read(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => match file(path) {
            Some(f) => Ok(f.bytes.to_vec()),
            None => Err(e),
        },
        other => other,
    }
}

/// [`read`] as UTF-8 text.
pub fn read_to_string(path: &Path) -> io::Result<String> {
    String::from_utf8(read(path)?).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
}

/// A scene or suite argument that is neither a file on disk nor a shipped name.
#[derive(Debug, thiserror::Error)]
#[error(
    "{given}: no such file, and glassscan ships no {what} of that name (shipped {what}s: \
     {names}; a file on disk of the same name wins){hint}"
)]
pub struct UnknownName {
    /// The argument as given.
    pub given: String,
    /// `scene` or `suite`.
    pub what: &'static str,
    /// The shipped names, comma-separated.
    pub names: String,
    /// Where to find more (`; see glassscan scenes list`), or nothing.
    pub hint: &'static str,
}

/// The scene a command-line argument names: `arg` itself when it exists on disk (a path that
/// exists wins); else the shipped scene it names, by name (`edge_study`), file name
/// (`edge_study.toml`) or repository path (`scenes/edge_study.toml`), returned as its
/// repository path, which [`read`] reads from the binary.
pub fn resolve_scene(arg: &Path) -> Result<PathBuf, UnknownName> {
    if arg.exists() {
        return Ok(arg.to_path_buf());
    }
    let scene = |p: &Path| file(p).filter(|f| f.kind() == FileKind::Scene);
    let candidates = [
        arg.to_path_buf(),
        Path::new("scenes").join(arg),
        Path::new("scenes").join(arg).with_extension("toml"),
    ];
    let bare_name = arg.components().count() == 1;
    for c in candidates.iter().take(if bare_name { 3 } else { 1 }) {
        if let Some(f) = scene(c) {
            return Ok(PathBuf::from(f.path));
        }
    }
    Err(UnknownName {
        given: arg.display().to_string(),
        what: "scene",
        names: scene_names().join(", "),
        hint: "; `glassscan scenes list` describes them",
    })
}

/// The suite a `glassscan check` argument names: a path that exists (or ends in `.toml`, or
/// has a folder) is a suite file; a name `NAME` is `validation/check/NAME.toml`, read from
/// disk when run from the repository root and from the binary elsewhere.
pub fn resolve_suite(arg: &str) -> Result<PathBuf, UnknownName> {
    let p = Path::new(arg);
    if p.exists() || p.extension().is_some_and(|e| e == "toml") || p.components().count() > 1 {
        return Ok(p.to_path_buf());
    }
    let path = Path::new("validation/check").join(format!("{arg}.toml"));
    if is_file(&path) {
        Ok(path)
    } else {
        Err(UnknownName {
            given: arg.to_string(),
            what: "suite",
            names: suite_names().join(", "),
            hint: "",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_file_is_its_repository_file_byte_for_byte() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        for f in FILES {
            assert_eq!(
                std::fs::read(root.join(f.path)).unwrap(),
                f.bytes,
                "{}",
                f.path
            );
        }
        let mut sorted: Vec<&str> = FILES.iter().map(|f| f.path).collect();
        sorted.sort_unstable();
        assert_eq!(sorted, FILES.iter().map(|f| f.path).collect::<Vec<_>>());
    }

    #[test]
    fn names_paths_and_kinds() {
        assert!(scene_names().contains(&"edge_study"));
        assert!(!scene_names().contains(&"randomize_edge_study"));
        assert_eq!(suite_names(), ["fast", "full"]);
        let want = Path::new("scenes/edge_study.toml");
        // Neither name is a file in the repository root, where the tests run.
        for arg in ["edge_study", "edge_study.toml"] {
            let p = resolve_scene(Path::new(arg)).unwrap();
            assert_eq!(p, want, "{arg}");
        }
        assert!(file(Path::new("./scenes/edge_study.toml")).is_some());
        assert!(file(Path::new("/scenes/edge_study.toml")).is_none());
        assert!(file(Path::new("scenes/../scenes/edge_study.toml")).is_none());
        let e = resolve_scene(Path::new("edge_studdy"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("edge_studdy: no such file"), "{e}");
        assert!(
            e.contains("car_side_window, car_side_window_gltf, edge_study,"),
            "{e}"
        );
        // A randomisation file or a mesh is not a scene.
        assert!(resolve_scene(Path::new("randomize_edge_study")).is_err());
        assert!(resolve_scene(Path::new("other/edge_study.toml")).is_err());
        assert_eq!(
            resolve_suite("fast").unwrap(),
            Path::new("validation/check/fast.toml")
        );
        let e = resolve_suite("fats").unwrap_err().to_string();
        assert!(e.contains("shipped suites: fast, full"), "{e}");
        let f = file(Path::new("scenes/car_side_window.toml")).unwrap();
        assert_eq!(f.kind(), FileKind::Scene);
        assert!(
            f.description()
                .starts_with("the paper's full-pipeline experiment"),
            "{}",
            f.description()
        );
        assert_eq!(
            file(Path::new("validation/check/fast.baseline.json"))
                .unwrap()
                .kind(),
            FileKind::Baseline
        );
    }
}
