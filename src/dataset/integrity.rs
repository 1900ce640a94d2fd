//! What a finished sample's files must be: each file's size and SHA-256, recorded in its
//! manifest line when the sample is written, and checked by `--resume`, `merge` and
//! `glassscan verify`.
//!
//! Why both: the size catches a truncated file (a preempted job, a full disk, an NFS client
//! that lost its cache) without reading it; the hash catches everything else, a file
//! overwritten with other bytes of the same length, or a sample directory of another run
//! (same names, other content). SHA-256 (FIPS 180-4, the RustCrypto `sha2` crate, SHA-NI
//! where the CPU has it) reads about a megabyte per sample: well under a millisecond against
//! the seconds a sample's simulation takes, so finished samples are always hashed, never only
//! on request.

use std::fmt;
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::manifest::ManifestLine;
use super::DatasetError;

/// One file of a sample as it was written.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileRecord {
    /// File name inside the sample directory.
    pub name: String,
    /// Size in bytes.
    pub bytes: u64,
    /// SHA-256 of the content, 64 lowercase hexadecimal digits.
    pub sha256: String,
}

/// Size and SHA-256 of the file at `path`, read in 64 KiB blocks.
pub fn hash_file(path: &Path) -> std::io::Result<(u64, String)> {
    let mut file = File::open(path)?;
    let mut hasher = Sha256::new();
    let mut buffer = vec![0u8; 1 << 16];
    let mut bytes = 0u64;
    loop {
        let n = file.read(&mut buffer)?;
        if n == 0 {
            break;
        }
        hasher.update(&buffer[..n]);
        bytes += n as u64;
    }
    let hex = hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    Ok((bytes, hex))
}

/// The records of the files `names` in the sample directory `dir`, as they are on disk now.
pub fn record_files(dir: &Path, names: &[&str]) -> Result<Vec<FileRecord>, DatasetError> {
    names
        .iter()
        .map(|&name| {
            let path = dir.join(name);
            let (bytes, sha256) =
                hash_file(&path).map_err(|e| DatasetError::io(&path, "read back", e))?;
            Ok(FileRecord {
                name: name.to_owned(),
                bytes,
                sha256,
            })
        })
        .collect()
}

/// How a finished sample differs from its manifest line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Damage {
    /// The sample directory is gone.
    DirectoryMissing {
        /// The directory the line names.
        path: PathBuf,
    },
    /// A recorded file is gone.
    FileMissing {
        /// The file.
        path: PathBuf,
    },
    /// A recorded file has another size (truncated, or overwritten).
    Size {
        /// The file.
        path: PathBuf,
        /// The recorded size (bytes).
        recorded: u64,
        /// The size on disk (bytes).
        found: u64,
    },
    /// A recorded file has its size but other content.
    Content {
        /// The file.
        path: PathBuf,
    },
    /// A recorded file could not be read.
    Unreadable {
        /// The file.
        path: PathBuf,
        /// The operating system's message.
        message: String,
    },
}

impl Damage {
    /// The file or directory concerned.
    pub fn path(&self) -> &Path {
        match self {
            Damage::DirectoryMissing { path }
            | Damage::FileMissing { path }
            | Damage::Size { path, .. }
            | Damage::Content { path }
            | Damage::Unreadable { path, .. } => path,
        }
    }
}

impl fmt::Display for Damage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Damage::DirectoryMissing { path } => {
                write!(f, "{}: the sample directory is missing", path.display())
            }
            Damage::FileMissing { path } => write!(f, "{}: missing", path.display()),
            Damage::Size {
                path,
                recorded,
                found,
            } => write!(
                f,
                "{}: {found} bytes, the manifest records {recorded} (truncated or overwritten)",
                path.display()
            ),
            Damage::Content { path } => write!(
                f,
                "{}: its SHA-256 is not the one the manifest records (overwritten, or a \
                 sample of another run)",
                path.display()
            ),
            Damage::Unreadable { path, message } => {
                write!(f, "{}: could not be read: {message}", path.display())
            }
        }
    }
}

/// Checks the sample of `line` (its directory relative to `dataset_dir`, or absolute) against
/// its file records: every file present, of its recorded size and hash. Empty when intact.
pub fn check_sample(dataset_dir: &Path, line: &ManifestLine) -> Vec<Damage> {
    check_sample_files(dataset_dir, line, Depth::Hashes)
}

/// How far [`check_sample_files`] looks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Depth {
    /// Every file present with its recorded size (a `stat` per file: what a loader can afford
    /// on every open).
    Sizes,
    /// Sizes, and every file's SHA-256 (reads every byte).
    Hashes,
}

/// [`check_sample`] to `depth`.
pub fn check_sample_files(dataset_dir: &Path, line: &ManifestLine, depth: Depth) -> Vec<Damage> {
    let dir = dataset_dir.join(&line.directory);
    if !dir.is_dir() {
        return vec![Damage::DirectoryMissing { path: dir }];
    }
    let mut damage = Vec::new();
    for record in &line.files {
        let path = dir.join(&record.name);
        let found = match std::fs::metadata(&path) {
            Ok(m) => m.len(),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                damage.push(Damage::FileMissing { path });
                continue;
            }
            Err(e) => {
                damage.push(Damage::Unreadable {
                    message: e.to_string(),
                    path,
                });
                continue;
            }
        };
        if found != record.bytes {
            damage.push(Damage::Size {
                path,
                recorded: record.bytes,
                found,
            });
            continue;
        }
        if depth == Depth::Sizes {
            continue;
        }
        match hash_file(&path) {
            Ok((_, hash)) if hash == record.sha256 => {}
            Ok(_) => damage.push(Damage::Content { path }),
            Err(e) => damage.push(Damage::Unreadable {
                message: e.to_string(),
                path,
            }),
        }
    }
    damage
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn sha256_matches_the_fips_180_example() {
        // FIPS 180-4 / NIST CSRC example "abc", and the empty message.
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("abc");
        std::fs::write(&p, "abc").unwrap();
        assert_eq!(
            hash_file(&p).unwrap(),
            (
                3,
                "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad".into()
            )
        );
        std::fs::write(&p, "").unwrap();
        assert_eq!(
            hash_file(&p).unwrap().1,
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
        // Longer than one read block.
        std::fs::write(&p, vec![7u8; (1 << 16) + 5]).unwrap();
        assert_eq!(hash_file(&p).unwrap().0, (1 << 16) + 5);
    }

    fn line(files: Vec<FileRecord>) -> ManifestLine {
        ManifestLine {
            index: 0,
            directory: "sample_000000".into(),
            seed: 0,
            border_fraction: 0.0,
            parameters: BTreeMap::new(),
            edge_point_mm: None,
            valid_points: 0,
            labels: BTreeMap::new(),
            saturated_pixels: 0,
            files,
            warnings: Vec::new(),
        }
    }

    #[test]
    fn each_kind_of_damage_is_told_apart() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("sample_000000");
        std::fs::create_dir(&dir).unwrap();
        for (name, text) in [("a", "alpha"), ("b", "bravo"), ("c", "charlie"), ("d", "x")] {
            std::fs::write(dir.join(name), text).unwrap();
        }
        let l = line(record_files(&dir, &["a", "b", "c", "d"]).unwrap());
        assert!(check_sample(root.path(), &l).is_empty());

        std::fs::write(dir.join("a"), "alp").unwrap(); // truncated
        std::fs::write(dir.join("b"), "BRAVO").unwrap(); // same size, other bytes
        std::fs::remove_file(dir.join("c")).unwrap();
        // A size check sees the truncation and the missing file, not the same-size rewrite.
        let sizes = check_sample_files(root.path(), &l, Depth::Sizes);
        assert_eq!(sizes.len(), 2, "{sizes:?}");
        assert!(matches!(sizes[0], Damage::Size { .. }));
        assert!(matches!(sizes[1], Damage::FileMissing { .. }));
        let damage = check_sample(root.path(), &l);
        assert_eq!(
            damage,
            [
                Damage::Size {
                    path: dir.join("a"),
                    recorded: 5,
                    found: 3
                },
                Damage::Content {
                    path: dir.join("b")
                },
                Damage::FileMissing {
                    path: dir.join("c")
                },
            ]
        );
        assert!(damage[0]
            .to_string()
            .contains("3 bytes, the manifest records 5"));
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(
            check_sample(root.path(), &l),
            [Damage::DirectoryMissing { path: dir }]
        );
    }
}
