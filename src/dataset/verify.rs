//! `glassscan verify DIR`: is a dataset complete and intact?
//!
//! Reads the directory's `run.json`, then its merged `manifest.jsonl` if there is one (else
//! every shard manifest in it), and checks every listed sample's files against the sizes and
//! SHA-256 hashes its line records ([`super::integrity`]), and that the manifests list every
//! sample of the run exactly once. Nothing is written.

use std::fs;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::integrity::{check_sample_files, Depth};
use super::manifest::{for_each_line, ManifestLine, RunInfo, MANIFEST, RUN_FILE};
use super::shard::Shard;
use super::DatasetError;
use crate::io::json;

/// How many missing sample indices a report lists (it counts them all).
const LISTED_MISSING: usize = 20;

/// What `verify` found.
#[derive(Clone, Debug, Default, Serialize)]
pub struct VerifyReport {
    /// The manifests read.
    pub manifests: Vec<PathBuf>,
    /// Samples of the run (`run.json`'s count).
    pub count: u64,
    /// Samples listed in the manifests and checked.
    pub samples: u64,
    /// Files checked.
    pub files: u64,
    /// Bytes hashed.
    pub bytes: u64,
    /// Samples with at least one damaged file.
    pub damaged_samples: u64,
    /// One message per damaged file or missing sample directory.
    pub damage: Vec<String>,
    /// How many samples of 0..count no manifest lists.
    pub missing: u64,
    /// The first [`LISTED_MISSING`] of them.
    pub missing_first: Vec<u64>,
    /// Samples listed more than once.
    pub duplicated: Vec<u64>,
}

impl VerifyReport {
    /// Every sample of the run is listed once and intact.
    pub fn is_ok(&self) -> bool {
        self.damage.is_empty() && self.missing == 0 && self.duplicated.is_empty()
    }
}

/// Checks the dataset in `dir` (see the module documentation). Errors only when `dir` is not a
/// readable dataset; damage is reported in the result.
pub fn verify_dataset(dir: &Path) -> Result<VerifyReport, DatasetError> {
    verify_dataset_lines(dir, Depth::Hashes).map(|(report, _)| report)
}

/// [`verify_dataset`] to `depth`, also returning the run file and every manifest line read, in
/// manifest order (a merged manifest is sorted by sample index): what a loader indexes.
pub fn verify_dataset_lines(
    dir: &Path,
    depth: Depth,
) -> Result<(VerifyReport, DatasetIndex), DatasetError> {
    if !dir.is_dir() {
        return Err(DatasetError::NotADataset {
            path: dir.to_path_buf(),
            message: "expected a dataset directory (made by `glassscan dataset`)".into(),
        });
    }
    let run_path = dir.join(RUN_FILE);
    if !run_path.is_file() {
        return Err(DatasetError::NotADataset {
            path: dir.to_path_buf(),
            message: format!("holds no {RUN_FILE}: it is not a glassscan dataset"),
        });
    }
    let info: RunInfo = json::read_json(&run_path)?;
    let merged = dir.join(MANIFEST);
    let manifests = if merged.is_file() {
        vec![merged]
    } else {
        let mut shards: Vec<(Shard, PathBuf)> = fs::read_dir(dir)
            .map_err(|e| DatasetError::io(dir, "list", e))?
            .filter_map(|e| e.ok())
            .filter_map(|e| {
                let name = e.file_name().to_string_lossy().into_owned();
                Shard::from_manifest_name(&name).map(|s| (s, dir.join(name)))
            })
            .collect();
        shards.sort_by_key(|(s, _)| (s.count, s.index));
        shards.into_iter().map(|(_, p)| p).collect()
    };
    if manifests.is_empty() {
        return Err(DatasetError::NotADataset {
            path: dir.to_path_buf(),
            message: format!(
                "holds no {MANIFEST} and no shard manifest (manifest-shard-K-of-N.jsonl)"
            ),
        });
    }

    let mut report = VerifyReport {
        count: info.count,
        manifests: manifests.clone(),
        ..VerifyReport::default()
    };
    let mut lines = Vec::new();
    let mut seen = vec![0u64; info.count.div_ceil(64) as usize];
    for manifest in &manifests {
        for_each_line(manifest, |number, line| {
            if line.index >= info.count {
                return Err(DatasetError::ManifestLine {
                    path: manifest.clone(),
                    line: number,
                    message: format!(
                        "sample {} is outside the run's {} samples",
                        line.index, info.count
                    ),
                });
            }
            let (w, b) = ((line.index / 64) as usize, line.index % 64);
            if seen[w] & (1 << b) != 0 {
                report.duplicated.push(line.index);
            }
            seen[w] |= 1 << b;
            report.samples += 1;
            report.files += line.files.len() as u64;
            report.bytes += line.files.iter().map(|f| f.bytes).sum::<u64>();
            let damage = check_sample_files(dir, &line, depth);
            if !damage.is_empty() {
                report.damaged_samples += 1;
                report.damage.extend(damage.iter().map(ToString::to_string));
            }
            lines.push(line);
            Ok(())
        })?;
    }
    for i in 0..info.count {
        if seen[(i / 64) as usize] & (1 << (i % 64)) == 0 {
            report.missing += 1;
            if report.missing_first.len() < LISTED_MISSING {
                report.missing_first.push(i);
            }
        }
    }
    report.duplicated.sort_unstable();
    report.duplicated.dedup();
    Ok((report, DatasetIndex { run: info, lines }))
}

/// A dataset's run file and manifest lines.
#[derive(Clone, Debug)]
pub struct DatasetIndex {
    /// `run.json`.
    pub run: RunInfo,
    /// Every manifest line, in manifest order.
    pub lines: Vec<ManifestLine>,
}
