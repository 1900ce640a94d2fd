//! The output directory of a dataset run, before any sample is made: refused, started, or
//! cleaned up for a resume.
//!
//! Rules (shard S of a run R writing into DIR):
//! - DIR missing or empty: created, and `run.json` written.
//! - DIR holds a `run.json` of another run: refused, with or without `--resume`.
//! - DIR holds files but no `run.json`: refused (it is not a dataset directory).
//! - DIR holds R's `run.json` but nothing of S (no manifest of S, no sample directory of S):
//!   accepted without `--resume`. This is how the shards of a job array share one DIR.
//! - DIR holds something of S: refused without `--resume`. With `--resume`, a torn last
//!   manifest line is cut off, every finished sample (one in S's manifest) is checked against
//!   its recorded file sizes and SHA-256 ([`super::integrity`]): intact ones are kept as they
//!   are, damaged ones lose their manifest line (the manifest is rewritten atomically) and are
//!   made again, every other sample directory of S is removed (it is partial), and stale
//!   temporaries (`.*.tmp-*`) of S's samples and of `run.json` are removed.

use std::fs;
use std::path::Path;

use super::integrity::{check_sample, Damage};
use super::manifest::{encode_line, for_each_line, repair_torn_tail, RunInfo, RUN_FILE};
use super::sample_files::parse_sample_dir_name;
use super::shard::Shard;
use super::DatasetError;
use crate::io::atomic::write_atomic;
use crate::io::json;

/// The samples of a shard that are already finished, as a bit set over 0..count.
#[derive(Clone, Debug, Default)]
pub struct Finished {
    bits: Vec<u64>,
    /// How many are set.
    pub len: u64,
}

impl Finished {
    fn insert(&mut self, i: u64) -> bool {
        let (w, b) = ((i / 64) as usize, i % 64);
        if self.bits.len() <= w {
            self.bits.resize(w + 1, 0);
        }
        let new = self.bits[w] & (1 << b) == 0;
        self.bits[w] |= 1 << b;
        self.len += u64::from(new);
        new
    }

    /// Whether sample `i` is finished.
    pub fn contains(&self, i: u64) -> bool {
        self.bits
            .get((i / 64) as usize)
            .is_some_and(|w| w & (1 << (i % 64)) != 0)
    }
}

/// What a directory held for a resumed shard.
#[derive(Clone, Debug, Default)]
pub struct Prepared {
    /// The intact finished samples, kept.
    pub finished: Finished,
    /// What was wrong with the finished samples that are made again, per file.
    pub damaged: Vec<Damage>,
    /// How many finished samples were damaged (and are made again).
    pub damaged_samples: u64,
}

/// Makes `dir` ready for shard `shard` of the run `info` (see the module documentation) and
/// returns the samples already finished and intact (empty unless resuming).
pub fn prepare_dataset_dir(
    dir: &Path,
    info: &RunInfo,
    shard: Shard,
    resume: bool,
) -> Result<Prepared, DatasetError> {
    let run_path = dir.join(RUN_FILE);
    match fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(crate::io::FileError::OutputNotADirectory {
                path: dir.to_path_buf(),
            }
            .into())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            fs::create_dir_all(dir)
                .map_err(|e| DatasetError::io(dir, "create the output directory", e))?;
        }
        Err(e) => return Err(DatasetError::io(dir, "inspect the output directory", e)),
    }
    crate::io::output_dir::check_writable(dir)?;
    let names = list(dir)?;
    if run_path.is_file() {
        let recorded: RunInfo = json::read_json(&run_path)?;
        let differences = recorded.differences(info);
        if !differences.is_empty() {
            return Err(DatasetError::RunMismatch {
                path: run_path,
                differences,
            });
        }
    } else if names.iter().any(|n| !is_temporary(n)) {
        return Err(DatasetError::DatasetDirBusy {
            path: dir.to_path_buf(),
            reason: format!("holds files but no {RUN_FILE} (it is not a glassscan dataset)"),
        });
    } else {
        json::write_json_pretty(&run_path, info)?;
    }

    let manifest = dir.join(shard.manifest_name());
    let ours = |n: &String| parse_sample_dir_name(n).is_some_and(|i| shard.contains(i));
    if !resume {
        if manifest.exists() || names.iter().any(ours) {
            return Err(DatasetError::DatasetDirBusy {
                path: dir.to_path_buf(),
                reason: format!("already holds samples of shard {shard}"),
            });
        }
        return Ok(Prepared::default());
    }

    let mut finished = Finished::default();
    let mut damaged_set = Finished::default();
    let mut damaged = Vec::new();
    if manifest.exists() {
        repair_torn_tail(&manifest)?;
        for_each_line(&manifest, |number, line| {
            if line.index >= info.count || !shard.contains(line.index) {
                return Err(DatasetError::ManifestLine {
                    path: manifest.clone(),
                    line: number,
                    message: format!(
                        "sample {} does not belong to shard {shard} of {} samples",
                        line.index, info.count
                    ),
                });
            }
            if finished.contains(line.index) || damaged_set.contains(line.index) {
                return Err(DatasetError::ManifestLine {
                    path: manifest.clone(),
                    line: number,
                    message: format!("sample {} is listed twice", line.index),
                });
            }
            let damage = check_sample(dir, &line);
            if damage.is_empty() {
                finished.insert(line.index);
            } else {
                damaged_set.insert(line.index);
                damaged.extend(damage);
            }
            Ok(())
        })?;
        if damaged_set.len > 0 {
            // Keep the intact lines only, in their order; the damaged samples are made again
            // and appended by this run.
            // (The temporary is renamed over the manifest only once it is complete.)
            write_atomic(&manifest, |w| {
                for_each_line(&manifest, |_, line| {
                    if finished.contains(line.index) {
                        writeln!(w, "{}", encode_line(&line))
                            .map_err(|e| DatasetError::io(&manifest, "rewrite", e))?;
                    }
                    Ok(())
                })
                .map_err(std::io::Error::other)
            })?;
        }
    }
    for name in &names {
        let path = dir.join(name);
        match parse_sample_dir_name(name) {
            Some(i) if shard.contains(i) && !finished.contains(i) => {
                fs::remove_dir_all(&path)
                    .map_err(|e| DatasetError::io(&path, "remove the unfinished sample", e))?;
            }
            _ if is_temporary(name) && name.starts_with(&format!(".{RUN_FILE}.")) => {
                remove_file(&path)?;
            }
            _ => {}
        }
    }
    Ok(Prepared {
        finished,
        damaged,
        damaged_samples: damaged_set.len,
    })
}

/// Removes stale temporaries inside the finished sample directory `dir` (none are expected:
/// a sample is finished only after all its files were renamed into place).
pub fn sweep_temporaries(dir: &Path) -> Result<(), DatasetError> {
    for name in list(dir)? {
        if is_temporary(&name) {
            remove_file(&dir.join(name))?;
        }
    }
    Ok(())
}

/// Whether `name` is a temporary of `atomic::write_atomic` (`.name.tmp-<pid>-<n>`).
fn is_temporary(name: &str) -> bool {
    name.starts_with('.') && name.contains(".tmp-")
}

fn remove_file(path: &Path) -> Result<(), DatasetError> {
    match fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(DatasetError::io(path, "remove the stale temporary", e)),
    }
}

fn list(dir: &Path) -> Result<Vec<String>, DatasetError> {
    let mut names = Vec::new();
    for entry in fs::read_dir(dir).map_err(|e| DatasetError::io(dir, "list", e))? {
        let entry = entry.map_err(|e| DatasetError::io(dir, "list", e))?;
        names.push(entry.file_name().to_string_lossy().into_owned());
    }
    names.sort();
    Ok(names)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::manifest::{ManifestLine, ManifestWriter};

    fn info(seed: u64) -> RunInfo {
        RunInfo {
            version: "0".into(),
            scene: "s.toml".into(),
            scene_toml: "".into(),
            randomize: None,
            randomize_toml: None,
            seed,
            count: 6,
            photons: 4096,
            adaptive_photons: false,
            max_depth: 64,
            ply_ascii: false,
        }
    }

    fn line(index: u64) -> ManifestLine {
        ManifestLine {
            index,
            directory: format!("sample_{index:06}"),
            seed: 0,
            border_fraction: 0.5,
            parameters: Default::default(),
            edge_point_mm: None,
            valid_points: 0,
            labels: Default::default(),
            saturated_pixels: 0,
            files: Vec::new(),
            warnings: Vec::new(),
        }
    }

    fn half() -> Shard {
        Shard { index: 0, count: 2 }
    }

    #[test]
    fn a_new_directory_gets_the_run_file() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("ds");
        let done = prepare_dataset_dir(&dir, &info(1), Shard::ALL, false).unwrap();
        assert_eq!(done.finished.len, 0);
        let read: RunInfo = json::read_json(&dir.join(RUN_FILE)).unwrap();
        assert_eq!(read, info(1));
    }

    #[test]
    fn foreign_files_and_other_runs_are_refused() {
        let root = tempfile::tempdir().unwrap();
        fs::write(root.path().join("precious.txt"), "x").unwrap();
        for resume in [false, true] {
            let e = prepare_dataset_dir(root.path(), &info(1), Shard::ALL, resume).unwrap_err();
            assert!(e.to_string().contains("no run.json"), "{e}");
        }
        assert_eq!(list(root.path()).unwrap(), ["precious.txt"]);
        let other = tempfile::tempdir().unwrap();
        prepare_dataset_dir(other.path(), &info(1), Shard::ALL, false).unwrap();
        let e = prepare_dataset_dir(other.path(), &info(2), Shard::ALL, true).unwrap_err();
        assert!(e.to_string().contains("seed 1 there, 2 here"), "{e}");
    }

    #[test]
    fn shards_share_a_directory_but_a_shard_needs_resume_to_continue() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path();
        prepare_dataset_dir(dir, &info(1), half(), false).unwrap();
        fs::create_dir(dir.join("sample_000000")).unwrap();
        // The other shard starts next to it.
        prepare_dataset_dir(dir, &info(1), Shard { index: 1, count: 2 }, false).unwrap();
        let e = prepare_dataset_dir(dir, &info(1), half(), false).unwrap_err();
        assert!(e.to_string().contains("--resume"), "{e}");
    }

    #[test]
    fn resume_keeps_finished_samples_and_removes_partial_ones() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path();
        prepare_dataset_dir(dir, &info(1), half(), false).unwrap();
        for i in [0, 1, 2, 4] {
            fs::create_dir(dir.join(format!("sample_{i:06}"))).unwrap();
            fs::write(dir.join(format!("sample_{i:06}/image.png")), "x").unwrap();
        }
        fs::write(dir.join(".run.json.tmp-1-0"), "").unwrap();
        let manifest = dir.join(half().manifest_name());
        let mut w = ManifestWriter::open(&manifest).unwrap();
        w.append(&line(0)).unwrap();
        drop(w);
        // A torn second line.
        let mut text = fs::read_to_string(&manifest).unwrap();
        text.push_str("{\"index\": 2, \"direc");
        fs::write(&manifest, text).unwrap();

        let done = prepare_dataset_dir(dir, &info(1), half(), true).unwrap();
        assert_eq!(done.finished.len, 1);
        assert!(done.finished.contains(0) && !done.finished.contains(2));
        // Sample 2 (ours, unfinished) and the temporary are gone; 0 (finished) and 1 (the other
        // shard's) are untouched.
        assert_eq!(
            list(dir).unwrap(),
            [
                "manifest-shard-0-of-2.jsonl",
                "run.json",
                "sample_000000",
                "sample_000001"
            ]
        );
        assert!(fs::read_to_string(&manifest).unwrap().ends_with("}\n"));
    }
}
