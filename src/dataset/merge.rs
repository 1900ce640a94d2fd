//! Joining shard manifests (`manifest-shard-K-of-N.jsonl`, from one or more dataset
//! directories) into one `manifest.jsonl` sorted by sample index.
//!
//! Checks, before anything is written: every directory has a `run.json` of the same run (scene
//! text, randomisation, seed, count, photons, version); every sample 0..count is listed exactly
//! once (the error lists the missing and the duplicated ones); every listed sample is intact,
//! each of its files of the size and SHA-256 its line records (the error lists every damaged
//! file). The merge streams: pass 1 reads the shards line by line keeping one bit per sample,
//! pass 2 merges the (index-sorted) shard files with a heap of one line per shard, so memory
//! does not grow with the sample count.
//!
//! Sample directories are not moved. A line whose sample lives in another directory than the
//! output gets that directory's absolute path in `directory`; lines of the output directory
//! keep their relative path, so a merge in place reproduces a one-shard run byte for byte.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::fs::{self, File};
use std::io::{BufRead, BufReader, Lines};
use std::path::{Path, PathBuf};

use super::integrity::check_sample;
use super::manifest::{encode_line, for_each_line, parse_line, RunInfo, MANIFEST, RUN_FILE};
use super::shard::Shard;
use super::DatasetError;
use crate::io::atomic::write_atomic;
use crate::io::json;

/// What a merge did.
#[derive(Debug, serde::Serialize)]
pub struct MergeOutcome {
    /// The merged manifest.
    pub manifest: PathBuf,
    /// The shard manifests read.
    pub shards: Vec<PathBuf>,
    /// Samples in the merged manifest.
    pub samples: u64,
}

/// A shard manifest and where its samples live.
struct ShardFile {
    path: PathBuf,
    /// The directory the sample directories are relative to.
    dir: PathBuf,
    /// Whether that is the output directory (relative paths stay relative).
    in_out: bool,
}

/// Merges the shard manifests found in `dirs` into `out/manifest.jsonl`.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<MergeOutcome, DatasetError> {
    if let Some(dir) = dirs.iter().find(|d| !d.is_dir()) {
        return Err(DatasetError::NotADataset {
            path: dir.clone(),
            message: "expected a dataset directory to merge (made by `glassscan dataset`)".into(),
        });
    }
    if out.exists() && !out.is_dir() {
        return Err(DatasetError::NotADataset {
            path: out.to_path_buf(),
            message: "expected a directory to write the merged manifest.jsonl into, found a file"
                .into(),
        });
    }
    let out_canonical =
        fs::canonicalize(out).map_err(|e| DatasetError::io(out, "open the output directory", e))?;
    let mut info: Option<(PathBuf, RunInfo)> = None;
    let mut files = Vec::new();
    for dir in dirs {
        let run_path = dir.join(RUN_FILE);
        let run: RunInfo = json::read_json(&run_path)?;
        match &info {
            None => info = Some((run_path, run)),
            Some((first, expected)) => {
                let differences = expected.differences(&run);
                if !differences.is_empty() {
                    return Err(DatasetError::RunMismatch {
                        path: run_path,
                        differences: vec![format!(
                            "compared with {}: {}",
                            first.display(),
                            differences.join("; ")
                        )],
                    });
                }
            }
        }
        let canonical =
            fs::canonicalize(dir).map_err(|e| DatasetError::io(dir, "open the directory", e))?;
        let mut names: Vec<(Shard, String)> = fs::read_dir(dir)
            .map_err(|e| DatasetError::io(dir, "list", e))?
            .filter_map(|e| e.ok())
            .filter_map(|e| {
                let name = e.file_name().to_string_lossy().into_owned();
                Shard::from_manifest_name(&name).map(|s| (s, name))
            })
            .collect();
        names.sort_by_key(|(s, _)| (s.count, s.index));
        if names.is_empty() {
            return Err(DatasetError::NotADataset {
                path: dir.clone(),
                message: "holds no shard manifest (manifest-shard-K-of-N.jsonl)".into(),
            });
        }
        files.extend(names.into_iter().map(|(_, name)| ShardFile {
            path: dir.join(name),
            dir: canonical.clone(),
            in_out: canonical == out_canonical,
        }));
    }
    let Some((_, info)) = info else {
        return Err(DatasetError::NotADataset {
            path: out.to_path_buf(),
            message: "no dataset directory to merge".into(),
        });
    };

    check_coverage(&files, info.count)?;

    let out_run = out.join(RUN_FILE);
    let manifest = out.join(MANIFEST);
    // A merge writes run.json before its manifest, so a manifest.jsonl without one beside it
    // was not written by a merge (nor by `dataset`): it is someone's file, left as it is.
    if !out_run.exists() && manifest.exists() {
        return Err(DatasetError::NotADataset {
            path: manifest,
            message: format!(
                "exists with no {RUN_FILE} beside it: not a glassscan dataset's manifest, so it \
                 is left as it is; choose another --out"
            ),
        });
    }
    if out_run.exists() {
        let there: RunInfo = json::read_json(&out_run)?;
        let differences = there.differences(&info);
        if !differences.is_empty() {
            return Err(DatasetError::RunMismatch {
                path: out_run,
                differences,
            });
        }
    } else {
        json::write_json_pretty(&out_run, &info)?;
    }

    write_atomic(&manifest, |w| {
        let mut readers: Vec<Lines<BufReader<File>>> = files
            .iter()
            .map(|f| File::open(&f.path).map(|file| BufReader::new(file).lines()))
            .collect::<std::io::Result<_>>()?;
        let mut heap = BinaryHeap::new();
        let next = |k: usize, readers: &mut Vec<Lines<BufReader<File>>>| -> std::io::Result<_> {
            match readers[k].next() {
                None => Ok(None),
                Some(text) => {
                    let text = text?;
                    let mut line =
                        parse_line(&files[k].path, 0, &text).map_err(std::io::Error::other)?;
                    if !files[k].in_out {
                        line.directory = files[k].dir.join(&line.directory).display().to_string();
                    }
                    Ok(Some(line))
                }
            }
        };
        for k in 0..files.len() {
            if let Some(line) = next(k, &mut readers)? {
                heap.push(Reverse((line.index, k, encode_line(&line))));
            }
        }
        while let Some(Reverse((_, k, text))) = heap.pop() {
            writeln!(w, "{text}")?;
            if let Some(line) = next(k, &mut readers)? {
                heap.push(Reverse((line.index, k, encode_line(&line))));
            }
        }
        Ok(())
    })?;
    Ok(MergeOutcome {
        manifest,
        shards: files.into_iter().map(|f| f.path).collect(),
        samples: info.count,
    })
}

/// Pass 1: every sample exactly once, each shard file sorted, every sample directory present.
fn check_coverage(files: &[ShardFile], count: u64) -> Result<(), DatasetError> {
    let mut seen = vec![0u64; count.div_ceil(64) as usize];
    let mut duplicated = Vec::new();
    let (mut damaged, mut damaged_samples) = (Vec::new(), 0u64);
    for f in files {
        let mut last: Option<u64> = None;
        for_each_line(&f.path, |number, line| {
            let bad = |message: String| DatasetError::ManifestLine {
                path: f.path.clone(),
                line: number,
                message,
            };
            if line.index >= count {
                return Err(bad(format!(
                    "sample {} is outside the run's {count} samples",
                    line.index
                )));
            }
            if last.is_some_and(|l| l >= line.index) {
                return Err(bad(format!(
                    "sample {} comes after sample {}: a shard manifest is in index order",
                    line.index,
                    last.unwrap_or(0)
                )));
            }
            last = Some(line.index);
            let damage = check_sample(&f.dir, &line);
            if !damage.is_empty() {
                damaged_samples += 1;
                damaged.extend(damage.iter().map(ToString::to_string));
            }
            let (w, b) = ((line.index / 64) as usize, line.index % 64);
            if seen[w] & (1 << b) != 0 {
                duplicated.push(line.index);
            }
            seen[w] |= 1 << b;
            Ok(())
        })?;
    }
    if !damaged.is_empty() {
        return Err(DatasetError::DamagedSamples {
            samples: damaged_samples,
            damage: damaged,
        });
    }
    let missing: Vec<u64> = (0..count)
        .filter(|i| seen[(i / 64) as usize] & (1 << (i % 64)) == 0)
        .collect();
    if missing.is_empty() && duplicated.is_empty() {
        return Ok(());
    }
    duplicated.sort_unstable();
    duplicated.dedup();
    Err(DatasetError::MergeCoverage {
        count,
        missing,
        duplicated,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::manifest::{ManifestLine, ManifestWriter};

    fn info() -> RunInfo {
        RunInfo {
            version: "0".into(),
            scene: "s.toml".into(),
            scene_toml: "".into(),
            randomize: None,
            randomize_toml: None,
            seed: 1,
            count: 5,
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
            seed: index * 7,
            border_fraction: index as f64 / 10.0,
            parameters: Default::default(),
            edge_point_mm: Some([index as f64, 0.1, 4.0]),
            valid_points: 3,
            labels: Default::default(),
            saturated_pixels: 0,
            files: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// A dataset directory with the given shard manifests (K, N, indices).
    fn dataset(shards: &[(u64, u64, &[u64])]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        json::write_json_pretty(&dir.path().join(RUN_FILE), &info()).unwrap();
        for &(k, n, indices) in shards {
            let shard = Shard { index: k, count: n };
            let mut w = ManifestWriter::open(&dir.path().join(shard.manifest_name())).unwrap();
            for &i in indices {
                fs::create_dir_all(dir.path().join(format!("sample_{i:06}"))).unwrap();
                w.append(&line(i)).unwrap();
            }
        }
        dir
    }

    #[test]
    fn shards_merge_in_index_order() {
        let ds = dataset(&[(0, 2, &[0, 2, 4]), (1, 2, &[1, 3])]);
        let outcome = merge(&[ds.path().to_path_buf()], ds.path()).unwrap();
        assert_eq!(outcome.samples, 5);
        let text = fs::read_to_string(ds.path().join(MANIFEST)).unwrap();
        let expected: String = (0..5).map(|i| encode_line(&line(i)) + "\n").collect();
        assert_eq!(text, expected);
    }

    #[test]
    fn missing_and_duplicated_samples_are_listed() {
        let ds = dataset(&[(0, 2, &[0, 2, 4]), (1, 2, &[1]), (0, 3, &[0])]);
        let message = merge(&[ds.path().to_path_buf()], ds.path())
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("missing 3") && message.contains("listed more than once 0"),
            "{message}"
        );
        assert!(!ds.path().join(MANIFEST).exists());
    }

    #[test]
    fn shards_in_other_directories_are_referenced_by_absolute_path() {
        let a = dataset(&[(0, 2, &[0, 2, 4])]);
        let b = dataset(&[(1, 2, &[1, 3])]);
        merge(&[a.path().to_path_buf(), b.path().to_path_buf()], a.path()).unwrap();
        let text = fs::read_to_string(a.path().join(MANIFEST)).unwrap();
        let lines: Vec<ManifestLine> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 5);
        assert_eq!(lines[0].directory, "sample_000000");
        let b_dir = fs::canonicalize(b.path()).unwrap();
        assert_eq!(
            lines[1].directory,
            b_dir.join("sample_000001").display().to_string()
        );
    }

    #[test]
    fn runs_that_differ_are_not_merged() {
        let a = dataset(&[(0, 2, &[0, 2, 4])]);
        let b = dataset(&[(1, 2, &[1, 3])]);
        let other = RunInfo { seed: 9, ..info() };
        json::write_json_pretty(&b.path().join(RUN_FILE), &other).unwrap();
        let message = merge(&[a.path().to_path_buf(), b.path().to_path_buf()], a.path())
            .unwrap_err()
            .to_string();
        assert!(message.contains("seed 1 there, 9 here"), "{message}");
    }
}
