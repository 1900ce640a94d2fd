//! The output directory of a run: created if missing, and never silently mixed with the files
//! of an earlier run unless the user asks for it.

use std::io;
use std::path::Path;

use super::FileError;

/// Makes `dir` ready to receive output files, before any work starts.
///
/// - Missing: it is created, with its parents.
/// - Existing and empty: accepted.
/// - Existing and not empty: refused with [`FileError::OutputNotEmpty`] unless `force`.
///   With `force` nothing is deleted now; each output file is later replaced atomically, one
///   by one, and the command removes the files of its kind that the new run did not write
///   ([`remove_stale`]).
/// - Existing but not a directory: refused, with or without `force`.
/// - Not writable (read-only, no permission): refused with [`FileError::OutputNotWritable`]:
///   a file is created in it and removed again, so the answer is the file system's own.
pub fn prepare_output_dir(dir: &Path, force: bool) -> Result<(), FileError> {
    match std::fs::metadata(dir) {
        Ok(meta) if meta.is_dir() => {
            if !force && !is_empty_dir(dir)? {
                return Err(FileError::OutputNotEmpty {
                    path: dir.to_path_buf(),
                });
            }
        }
        Ok(_) => {
            return Err(FileError::OutputNotADirectory {
                path: dir.to_path_buf(),
            })
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => std::fs::create_dir_all(dir)
            .map_err(|e| FileError::io(dir, "create the output directory", e))?,
        Err(e) => return Err(FileError::io(dir, "inspect the output directory", e)),
    }
    check_writable(dir)
}

/// Refuses a directory in which a file cannot be created.
pub fn check_writable(dir: &Path) -> Result<(), FileError> {
    let probe = dir.join(format!(".glassscan-write-probe-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(file) => {
            drop(file);
            std::fs::remove_file(&probe)
                .map_err(|e| FileError::io(&probe, "remove the write probe", e))
        }
        Err(source) => Err(FileError::OutputNotWritable {
            path: dir.to_path_buf(),
            source,
        }),
    }
}

/// After a `--force` run: removes the files of `dir` that `is_output` says a run of this
/// command writes (e.g. `pose_007.png`) but that this run did not write, so the directory
/// holds one run, not two mixed. Returns the names removed, sorted.
pub fn remove_stale(
    dir: &Path,
    is_output: impl Fn(&str) -> bool,
    written: &std::collections::BTreeSet<String>,
) -> Result<Vec<String>, FileError> {
    let mut removed = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| FileError::io(dir, "list", e))? {
        let entry = entry.map_err(|e| FileError::io(dir, "list", e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_file = entry.file_type().is_ok_and(|t| t.is_file());
        if is_file && is_output(&name) && !written.contains(&name) {
            let path = entry.path();
            std::fs::remove_file(&path)
                .map_err(|e| FileError::io(&path, "remove the earlier run's file", e))?;
            removed.push(name);
        }
    }
    removed.sort();
    Ok(removed)
}

fn is_empty_dir(dir: &Path) -> Result<bool, FileError> {
    let mut entries =
        std::fs::read_dir(dir).map_err(|e| FileError::io(dir, "list the output directory", e))?;
    match entries.next() {
        None => Ok(true),
        Some(Ok(_)) => Ok(false),
        Some(Err(e)) => Err(FileError::io(dir, "list the output directory", e)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    #[test]
    fn stale_outputs_go_and_everything_else_stays() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["pose_000.png", "pose_003.png", "notes.txt", "manifest.json"] {
            fs::write(dir.path().join(name), "x").unwrap();
        }
        let written = ["pose_000.png".to_string(), "manifest.json".into()].into();
        let removed = remove_stale(dir.path(), |n| n.starts_with("pose_"), &written).unwrap();
        assert_eq!(removed, ["pose_003.png"]);
        let mut left: Vec<String> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["manifest.json", "notes.txt", "pose_000.png"]);
    }

    #[test]
    fn missing_directory_is_created_with_parents() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("a").join("b");
        prepare_output_dir(&dir, false).unwrap();
        assert!(dir.is_dir());
    }

    #[test]
    fn empty_directory_is_accepted() {
        let root = tempfile::tempdir().unwrap();
        prepare_output_dir(root.path(), false).unwrap();
        prepare_output_dir(root.path(), true).unwrap();
    }

    #[test]
    fn non_empty_directory_needs_force_and_force_deletes_nothing() {
        let root = tempfile::tempdir().unwrap();
        let old = root.path().join("profile.csv");
        fs::write(&old, "old run").unwrap();
        let err = prepare_output_dir(root.path(), false).unwrap_err();
        assert!(matches!(err, FileError::OutputNotEmpty { .. }), "{err}");
        let message = err.to_string();
        assert!(
            message.contains(&root.path().display().to_string())
                && message.contains("--force")
                && message.contains("another directory"),
            "{message}"
        );
        prepare_output_dir(root.path(), true).unwrap();
        assert_eq!(fs::read_to_string(&old).unwrap(), "old run");
    }

    #[test]
    fn a_file_is_not_an_output_directory() {
        let root = tempfile::tempdir().unwrap();
        let file = root.path().join("out");
        fs::write(&file, "").unwrap();
        for force in [false, true] {
            let err = prepare_output_dir(&file, force).unwrap_err();
            assert!(
                matches!(err, FileError::OutputNotADirectory { .. }),
                "{err}"
            );
        }
        // A path below a file cannot be created either.
        let err = prepare_output_dir(&file.join("sub"), false).unwrap_err();
        assert!(err.to_string().contains("out"), "{err}");
    }
}
