//! Atomic file replacement: every output file is written to a temporary file next to it, synced,
//! and renamed over the target. A reader (or a crashed run) sees either the old file or the
//! complete new one, never a torn one.
//!
//! `rename` is atomic only within one file system, which is why the temporary lives in the
//! target's own directory rather than in `std::env::temp_dir()`.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::FileError;

/// Distinguishes temporaries made by different threads of this process for the same target.
static NEXT_TEMP_ID: AtomicU64 = AtomicU64::new(0);

/// How many temporary names to try before giving up. Collisions only happen with a stale
/// temporary left by an earlier process that had the same pid, so a handful is plenty.
const MAX_TEMP_ATTEMPTS: u32 = 16;

/// Writes `path` atomically: `write` fills a temporary file `.name.tmp-<pid>-<n>` in the same
/// directory, which is flushed, `sync_all`ed and then renamed over `path`.
///
/// On any error (including a panic inside `write`) the temporary is removed and an existing
/// file at `path` is left untouched. The directory entry itself is not fsynced: the guarantee is
/// "no torn files", not durability across power loss.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), FileError> {
    let (mut temp, file) = TempFile::create(path)?;
    let mut writer = BufWriter::new(file);
    write(&mut writer).map_err(|e| FileError::io(path, "write", e))?;
    let file = writer
        .into_inner()
        .map_err(|e| FileError::io(path, "write", e.into_error()))?;
    file.sync_all()
        .map_err(|e| FileError::io(path, "sync", e))?;
    drop(file);
    fs::rename(&temp.path, path)
        .map_err(|e| FileError::io(path, "rename the temporary file onto", e))?;
    temp.renamed = true;
    Ok(())
}

/// A temporary file that removes itself when dropped, unless it has been renamed.
struct TempFile {
    path: PathBuf,
    renamed: bool,
}

impl TempFile {
    fn create(target: &Path) -> Result<(TempFile, File), FileError> {
        let name = target.file_name().ok_or_else(|| FileError::NotAFilePath {
            path: target.to_path_buf(),
        })?;
        let mut attempt = 0;
        loop {
            let id = NEXT_TEMP_ID.fetch_add(1, Ordering::Relaxed);
            let mut temp_name = std::ffi::OsString::from(".");
            temp_name.push(name);
            temp_name.push(format!(".tmp-{}-{id}", std::process::id()));
            let temp_path = target.with_file_name(temp_name);
            // `create_new` makes sure we never write into someone else's temporary.
            match OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&temp_path)
            {
                Ok(file) => {
                    let temp = TempFile {
                        path: temp_path,
                        renamed: false,
                    };
                    return Ok((temp, file));
                }
                Err(e)
                    if e.kind() == io::ErrorKind::AlreadyExists
                        && attempt + 1 < MAX_TEMP_ATTEMPTS =>
                {
                    attempt += 1;
                }
                Err(e) => return Err(FileError::io(target, "create a temporary file next to", e)),
            }
        }
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.renamed {
            // The error that got us here is the one worth reporting; a temporary that cannot be
            // removed either is harmless, and its name says what it is.
            let _ = fs::remove_file(&self.path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_a_new_file_and_replaces_an_old_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        write_atomic(&path, |w| w.write_all(b"first")).unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"first");
        write_atomic(&path, |w| w.write_all(b"second, longer")).unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"second, longer");
        assert_eq!(names_in(dir.path()), ["a.txt"]);
    }

    #[test]
    fn failing_writer_leaves_previous_content_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        fs::write(&path, b"previous").unwrap();
        let err = write_atomic(&path, |w| {
            // Enough bytes to overflow the BufWriter, so part of them reaches the temporary.
            w.write_all(&vec![b'x'; 100_000])?;
            Err(io::Error::other("disk on fire"))
        })
        .unwrap_err();
        assert!(matches!(
            err,
            FileError::Io {
                action: "write",
                ..
            }
        ));
        let message = err.to_string();
        assert!(
            message.contains("a.txt") && message.contains("disk on fire"),
            "{message}"
        );
        assert_eq!(fs::read(&path).unwrap(), b"previous");
        assert_eq!(names_in(dir.path()), ["a.txt"]);
    }

    #[test]
    fn failing_writer_without_previous_file_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        let result = write_atomic(&path, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("stop"))
        });
        assert!(result.is_err());
        assert!(names_in(dir.path()).is_empty());
    }

    #[test]
    fn panicking_writer_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        fs::write(&path, b"previous").unwrap();
        let outcome = std::panic::catch_unwind(|| {
            let _ = write_atomic(&path, |w| {
                w.write_all(b"half")?;
                panic!("writer panicked");
            });
        });
        assert!(outcome.is_err());
        assert_eq!(fs::read(&path).unwrap(), b"previous");
        assert_eq!(names_in(dir.path()), ["a.txt"]);
    }

    #[test]
    fn missing_directory_is_an_io_error_naming_the_target() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing").join("a.txt");
        let err = write_atomic(&path, |w| w.write_all(b"x")).unwrap_err();
        assert!(matches!(err, FileError::Io { .. }));
        assert!(err.to_string().contains("missing"), "{err}");
    }

    #[test]
    fn path_without_file_name_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("..");
        let err = write_atomic(&path, |w| w.write_all(b"x")).unwrap_err();
        assert!(matches!(err, FileError::NotAFilePath { .. }), "{err}");
    }
}
