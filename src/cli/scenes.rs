//! `glassscan scenes list` and `glassscan scenes export NAME DIR`: the scenes, randomisation
//! files, meshes, scene-file reference and regression suites shipped in the binary
//! (`crate::shipped`).

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use serde_json::json;

use super::{flags, help, progress, CliError};
use crate::io::atomic::write_atomic;
use crate::shipped::{self, FileKind, ShippedFile, FILES};

/// Arguments of `glassscan scenes`.
#[derive(Debug, Args)]
pub struct ScenesArgs {
    /// What to do with the shipped files.
    #[command(subcommand)]
    pub command: ScenesCommand,
}

/// `scenes` subcommands.
#[derive(Debug, Subcommand)]
pub enum ScenesCommand {
    /// List the shipped scenes, randomisation files, meshes, reference and suites: NAME (what
    /// commands and `export` take), KIND, FILE (its path in the repository), DESCRIPTION.
    #[command(after_long_help = help::SCENES_LIST)]
    List(ListArgs),
    /// Write a shipped file (with the meshes a scene references, the baseline of a suite), or
    /// `all` of them, into DIR, byte for byte.
    #[command(after_long_help = help::SCENES_EXPORT)]
    Export(ExportArgs),
}

/// Arguments of `glassscan scenes list`.
#[derive(Debug, Args)]
pub struct ListArgs {
    /// Print the list as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `glassscan scenes export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// A NAME from `glassscan scenes list` (`edge_study`, `fast`, `README.md`,
    /// `meshes/cube.gltf`), a shipped file's repository path (`scenes/edge_study.toml`), or
    /// `all`.
    pub name: String,
    /// Directory to write into (created if missing). Files keep their names: a scene as
    /// DIR/NAME.toml, its meshes under DIR/meshes/.
    pub dir: PathBuf,
    /// Replace files in DIR that differ from the shipped ones (identical files are left as
    /// they are either way).
    #[arg(long)]
    pub force: bool,
}

/// Runs `glassscan scenes …`.
pub fn run(args: ScenesArgs) -> Result<(), CliError> {
    match args.command {
        ScenesCommand::List(a) => list(&a),
        ScenesCommand::Export(a) => export(&a),
    }
}

/// The name a shipped file is listed and exported under: a scene's or suite's stem, else its
/// path inside its folder (`README.md`, `meshes/cube.gltf`, `fast.baseline.json`).
pub fn listed_name(f: &ShippedFile) -> &'static str {
    match f.kind() {
        FileKind::Scene | FileKind::Suite => f.stem(),
        _ => export_path(f),
    }
}

/// Where `export` writes `f`, relative to DIR: its path inside `scenes/` or
/// `validation/check/`.
fn export_path(f: &ShippedFile) -> &'static str {
    f.path
        .strip_prefix("scenes/")
        .or_else(|| f.path.strip_prefix("validation/check/"))
        .unwrap_or(f.path)
}

fn description(f: &ShippedFile) -> String {
    match f.kind() {
        FileKind::Mesh => "glTF mesh (a test fixture of the mesh loader)".into(),
        FileKind::Reference => {
            "the scene-file reference: every key, unit, default and its source".into()
        }
        FileKind::Baseline => format!("baseline metrics of the `{}` suite", suite_of(f)),
        _ => f.description(),
    }
}

/// The suite a baseline belongs to (`fast` for `fast.baseline.json`).
fn suite_of(f: &ShippedFile) -> &'static str {
    f.stem()
}

fn list(args: &ListArgs) -> Result<(), CliError> {
    // Scenes first (what most users want), then the rest by kind.
    let order = [
        FileKind::Scene,
        FileKind::Randomization,
        FileKind::Suite,
        FileKind::Baseline,
        FileKind::Reference,
        FileKind::Mesh,
    ];
    let files: Vec<&ShippedFile> = order.iter().flat_map(|k| shipped::of_kind(*k)).collect();
    if args.json {
        let v: Vec<_> = files
            .iter()
            .map(|f| {
                json!({
                    "name": listed_name(f),
                    "kind": f.kind().name(),
                    "file": f.path,
                    "bytes": f.bytes.len(),
                    "description": description(f),
                })
            })
            .collect();
        return super::print_json(&v);
    }
    let width = |col: fn(&ShippedFile) -> &str, head: &str| {
        files
            .iter()
            .map(|f| col(f).chars().count())
            .chain([head.len()])
            .max()
            .unwrap_or(0)
    };
    let (wn, wk, wf) = (
        width(listed_name, "NAME"),
        width(|f| f.kind().name(), "KIND"),
        width(|f| f.path, "FILE"),
    );
    println!(
        "{:wn$}  {:wk$}  {:wf$}  DESCRIPTION",
        "NAME", "KIND", "FILE"
    );
    for f in &files {
        println!(
            "{:wn$}  {:wk$}  {:wf$}  {}",
            listed_name(f),
            f.kind().name(),
            f.path,
            description(f)
        );
    }
    progress::note(
        "commands take a scene's NAME or a file's path (a path that exists wins); \
         `glassscan scenes export NAME DIR` writes a copy to edit",
    );
    Ok(())
}

/// The files `export NAME` writes: the named file, plus the meshes a scene references and
/// the baseline of a suite; every shipped file for `all`.
fn files_to_export(name: &str) -> Result<Vec<&'static ShippedFile>, CliError> {
    if name == "all" {
        return Ok(FILES.iter().collect());
    }
    let named = FILES.iter().find(|f| {
        listed_name(f) == name
            || export_path(f) == name
            || shipped::file(Path::new(name)).is_some_and(|g| std::ptr::eq(g, *f))
    });
    let Some(f) = named else {
        let names: Vec<&str> = FILES.iter().map(listed_name).collect();
        return Err(CliError::input(anyhow::anyhow!(
            "{name}: glassscan ships no file of that name (expected `all` or one of: {}; \
             `glassscan scenes list` describes them)",
            names.join(", ")
        )));
    };
    let mut out = vec![f];
    match f.kind() {
        FileKind::Scene => {
            for mesh in referenced_meshes(f) {
                match shipped::file(&Path::new("scenes").join(&mesh)) {
                    Some(m) if !out.contains(&m) => out.push(m),
                    Some(_) => {}
                    None => {
                        return Err(CliError::internal(anyhow::anyhow!(
                            "{}: references mesh `{mesh}`, which is not shipped",
                            f.path
                        )))
                    }
                }
            }
        }
        FileKind::Suite => {
            let baseline = format!("validation/check/{}.baseline.json", f.stem());
            out.extend(shipped::file(Path::new(&baseline)));
        }
        _ => {}
    }
    Ok(out)
}

/// The `mesh.file` of every object of a shipped scene, relative to `scenes/`.
pub fn referenced_meshes(scene: &ShippedFile) -> Vec<String> {
    let text = std::str::from_utf8(scene.bytes).unwrap_or("");
    let Ok(doc) = text.parse::<toml::Table>() else {
        return Vec::new();
    };
    doc.get("objects")
        .and_then(toml::Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|o| o.get("mesh")?.get("file")?.as_str().map(str::to_string))
        .collect()
}

fn export(args: &ExportArgs) -> Result<(), CliError> {
    let files = files_to_export(&args.name)?;
    if args.dir.exists() && !args.dir.is_dir() {
        return Err(CliError::input(anyhow::anyhow!(
            "{}: is a file, expected a directory to export into (nothing was written)",
            args.dir.display()
        )));
    }
    // Check every target before writing any: a refusal leaves DIR as it was.
    let mut plan = Vec::new();
    for f in files {
        let target = args.dir.join(export_path(f));
        match std::fs::read(&target) {
            Ok(bytes) if bytes == f.bytes => {
                plan.push((f, target, false));
                continue;
            }
            Ok(_) if !args.force => {
                return Err(flags::bad_flag(
                    "force",
                    format!(
                        "is needed: {} exists and differs from the shipped {} (nothing was \
                         written)",
                        target.display(),
                        f.path
                    ),
                ));
            }
            _ => {}
        }
        if target.is_dir() {
            return Err(CliError::input(anyhow::anyhow!(
                "{}: is a directory, expected the file {} (nothing was written)",
                target.display(),
                f.path
            )));
        }
        plan.push((f, target, true));
    }
    for (f, target, write) in &plan {
        if !write {
            progress::note(format_args!(
                "{} is already the shipped {}",
                target.display(),
                f.path
            ));
            continue;
        }
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| CliError::from_file(crate::io::FileError::io(parent, "create", e)))?;
        }
        write_atomic(target, |w| w.write_all(f.bytes)).map_err(CliError::from_file)?;
        if !progress::is_quiet() {
            eprintln!("wrote {} ({})", target.display(), f.path);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn export_names_are_unique_and_every_file_is_reachable_by_its_listed_name() {
        let mut targets: Vec<&str> = FILES.iter().map(export_path).collect();
        targets.sort_unstable();
        targets.dedup();
        assert_eq!(
            targets.len(),
            FILES.len(),
            "two files would export to one path"
        );
        for f in FILES {
            let got = files_to_export(listed_name(f)).unwrap();
            assert_eq!(got[0].path, f.path);
        }
        let fast = files_to_export("fast").unwrap();
        assert_eq!(
            fast.iter().map(|f| f.path).collect::<Vec<_>>(),
            [
                "validation/check/fast.toml",
                "validation/check/fast.baseline.json"
            ]
        );
        assert_eq!(files_to_export("all").unwrap().len(), FILES.len());
        let e = files_to_export("edge_studdy").unwrap_err();
        assert_eq!(e.code, 2);
        assert!(format!("{}", e.error).contains("edge_study, "));
    }

    #[test]
    fn every_mesh_a_shipped_scene_references_is_shipped_and_self_contained() {
        for scene in shipped::of_kind(FileKind::Scene) {
            files_to_export(scene.stem()).unwrap();
        }
        // The mesh loader reads shipped meshes from memory: no external buffer files.
        for mesh in shipped::of_kind(FileKind::Mesh) {
            // A .glb keeps its JSON in the first chunk (its binary buffer has no uri).
            let json = if mesh.path.ends_with(".glb") {
                gltf::Glb::from_slice(mesh.bytes).unwrap().json.into_owned()
            } else {
                mesh.bytes.to_vec()
            };
            let doc: serde_json::Value = serde_json::from_slice(&json).unwrap();
            for b in doc["buffers"].as_array().into_iter().flatten() {
                let uri = b["uri"].as_str().unwrap_or("data:");
                assert!(uri.starts_with("data:"), "{}: buffer {uri}", mesh.path);
            }
        }
    }
}
