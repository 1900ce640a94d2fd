//! The output directory of a run: created if missing, and never silently mixed with the files
//! of an earlier run unless the user asks for it.

use std::io;
use std::path::Path;

use super::DatasetError;

/// Makes `dir` ready to receive output files.
///
/// - Missing: it is created, with its parents.
/// - Existing and empty: accepted.
/// - Existing and not empty: refused with [`DatasetError::OutputNotEmpty`] unless `force`.
///   With `force` nothing is deleted; each output file is later replaced atomically, one by one,
///   and files this run does not write stay as they are.
/// - Existing but not a directory: refused, with or without `force`.
pub fn prepare_output_dir(dir: &Path, force: bool) -> Result<(), DatasetError> {
    match std::fs::metadata(dir) {
        Ok(meta) if meta.is_dir() => {
            if !force && !is_empty_dir(dir)? {
                return Err(DatasetError::OutputNotEmpty {
                    path: dir.to_path_buf(),
                });
            }
            Ok(())
        }
        Ok(_) => Err(DatasetError::OutputNotADirectory {
            path: dir.to_path_buf(),
        }),
        Err(e) if e.kind() == io::ErrorKind::NotFound => std::fs::create_dir_all(dir)
            .map_err(|e| DatasetError::io(dir, "create the output directory", e)),
        Err(e) => Err(DatasetError::io(dir, "inspect the output directory", e)),
    }
}

fn is_empty_dir(dir: &Path) -> Result<bool, DatasetError> {
    let mut entries = std::fs::read_dir(dir)
        .map_err(|e| DatasetError::io(dir, "list the output directory", e))?;
    match entries.next() {
        None => Ok(true),
        Some(Ok(_)) => Ok(false),
        Some(Err(e)) => Err(DatasetError::io(dir, "list the output directory", e)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

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
        assert!(matches!(err, DatasetError::OutputNotEmpty { .. }), "{err}");
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
                matches!(err, DatasetError::OutputNotADirectory { .. }),
                "{err}"
            );
        }
        // A path below a file cannot be created either.
        let err = prepare_output_dir(&file.join("sub"), false).unwrap_err();
        assert!(err.to_string().contains("out"), "{err}");
    }
}
