//! The records of a dataset run: `run.json` (how the dataset was made) and the JSON-lines
//! manifests, one line per finished sample.
//!
//! A sample counts as finished exactly when its manifest line is on disk: the line is appended
//! (one `write` of the whole line, then `fsync`) only after every file of the sample has been
//! written atomically. A run killed while appending can leave a torn last line without a
//! newline; [`repair_torn_tail`] cuts it off before a resumed run appends, and readers refuse it.
//!
//! Lines are appended in sample-index order (the generator keeps that order whatever the
//! thread count), so a shard's manifest is sorted and `merge` can stream the shards together.

use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::integrity::FileRecord;
use super::DatasetError;

/// The manifest of a whole (unsharded or merged) dataset.
pub const MANIFEST: &str = "manifest.jsonl";
/// The run file of a dataset directory.
pub const RUN_FILE: &str = "run.json";

/// How a dataset was made; every shard of a run writes the same one. Two runs are the same run
/// when everything but the file paths (which depend on the working directory) is equal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunInfo {
    /// glassscan version.
    pub version: String,
    /// The scene file as given on the command line.
    pub scene: String,
    /// The scene file's text.
    pub scene_toml: String,
    /// The randomisation file as given, if any.
    pub randomize: Option<String>,
    /// The randomisation file's text, if any.
    pub randomize_toml: Option<String>,
    /// Master seed.
    pub seed: u64,
    /// Number of samples of the whole dataset (all shards).
    pub count: u64,
    /// Laser photons traced per sample (with `adaptive_photons`, the most a sample may take).
    pub photons: u64,
    /// Each sample stopped once its edge-line BIP had converged (`--photons` not given); absent (false)
    /// in run files written before the adaptive count existed.
    #[serde(default)]
    pub adaptive_photons: bool,
    /// Longest photon path, in surface interactions.
    pub max_depth: u32,
    /// `points.ply` written as ASCII (`--ply-ascii`) instead of binary; absent (false) in run
    /// files written before the flag existed.
    #[serde(default)]
    pub ply_ascii: bool,
}

impl RunInfo {
    /// What differs between `self` (recorded) and `other` (requested), paths aside.
    pub fn differences(&self, other: &RunInfo) -> Vec<String> {
        let mut d = Vec::new();
        let mut check = |name: &str, a: String, b: String| {
            if a != b {
                d.push(format!("{name} {a} there, {b} here"));
            }
        };
        check("version", self.version.clone(), other.version.clone());
        check("seed", self.seed.to_string(), other.seed.to_string());
        check("count", self.count.to_string(), other.count.to_string());
        check(
            "photons",
            self.photons.to_string(),
            other.photons.to_string(),
        );
        check(
            "adaptive_photons",
            self.adaptive_photons.to_string(),
            other.adaptive_photons.to_string(),
        );
        check(
            "max_depth",
            self.max_depth.to_string(),
            other.max_depth.to_string(),
        );
        check(
            "ply_ascii",
            self.ply_ascii.to_string(),
            other.ply_ascii.to_string(),
        );
        if self.scene_toml != other.scene_toml {
            d.push(format!(
                "the scene text differs ({} there, {} here)",
                self.scene, other.scene
            ));
        }
        if self.randomize_toml != other.randomize_toml {
            let name = |r: &Option<String>| r.clone().unwrap_or_else(|| "none".into());
            d.push(format!(
                "the randomisation differs ({} there, {} here)",
                name(&self.randomize),
                name(&other.randomize)
            ));
        }
        d
    }
}

/// One finished sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestLine {
    /// Sample index in 0..count.
    pub index: u64,
    /// The sample's directory, relative to the manifest's directory (or absolute after a
    /// merge from several directories).
    pub directory: String,
    /// Seed of the sample's transport, speckle and sensor noise.
    pub seed: u64,
    /// Position of the scan pose along the target's border (fraction of its length).
    pub border_fraction: f64,
    /// The randomised parameters drawn for this sample, by key.
    pub parameters: BTreeMap<String, f64>,
    /// Ground truth p_e in the base frame (mm); `None` if the laser plane misses the border.
    pub edge_point_mm: Option<[f64; 3]>,
    /// Valid points of the measured profile.
    pub valid_points: usize,
    /// Valid points per path class of their peak.
    pub labels: BTreeMap<String, usize>,
    /// Pixels at the full well or at the ADC's full scale.
    pub saturated_pixels: usize,
    /// Every file of the sample with its size and SHA-256, as written
    /// ([`super::integrity`]): what `--resume`, `merge` and `verify` check.
    pub files: Vec<FileRecord>,
    /// Why the sample may be physically empty or meaningless (`scan::warnings`); absent when
    /// there is nothing to say.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// Appends manifest lines, one durable line at a time.
pub struct ManifestWriter {
    path: PathBuf,
    file: File,
}

impl ManifestWriter {
    /// Opens (creating if needed) the manifest at `path` for appending.
    pub fn open(path: &Path) -> Result<ManifestWriter, DatasetError> {
        let file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| DatasetError::io(path, "open for appending", e))?;
        Ok(ManifestWriter {
            path: path.to_path_buf(),
            file,
        })
    }

    /// Appends `line` with one write and makes it durable: once this returns, the sample is
    /// finished.
    pub fn append(&mut self, line: &ManifestLine) -> Result<(), DatasetError> {
        let mut text =
            serde_json::to_string(line).map_err(|source| crate::io::FileError::JsonWrite {
                path: self.path.clone(),
                source,
            })?;
        text.push('\n');
        self.file
            .write_all(text.as_bytes())
            .and_then(|()| self.file.flush())
            .and_then(|()| self.file.sync_data())
            .map_err(|e| DatasetError::io(&self.path, "append to", e))
    }
}

/// Cuts a torn last line (bytes after the last newline, left by a run killed while appending)
/// off the manifest at `path`. Returns whether anything was cut. A missing file is fine.
pub fn repair_torn_tail(path: &Path) -> Result<bool, DatasetError> {
    let mut file = match OpenOptions::new().read(true).write(true).open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(DatasetError::io(path, "open", e)),
    };
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes)
        .map_err(|e| DatasetError::io(path, "read", e))?;
    if bytes.is_empty() || bytes.ends_with(b"\n") {
        return Ok(false);
    }
    let keep = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    file.set_len(keep as u64)
        .and_then(|()| file.seek(SeekFrom::End(0)).map(drop))
        .and_then(|()| file.sync_data())
        .map_err(|e| DatasetError::io(path, "truncate the torn last line of", e))?;
    Ok(true)
}

/// Calls `visit(line_number, line)` for every line of the manifest at `path`, in file order,
/// without holding the file in memory. A line that is not a manifest line, or a last line
/// without its newline (an interrupted run), is an error naming the file and line.
pub fn for_each_line(
    path: &Path,
    mut visit: impl FnMut(usize, ManifestLine) -> Result<(), DatasetError>,
) -> Result<(), DatasetError> {
    let file = File::open(path).map_err(|e| DatasetError::io(path, "read", e))?;
    let mut reader = BufReader::new(file);
    let mut text = String::new();
    let mut number = 0;
    loop {
        text.clear();
        let n = reader
            .read_line(&mut text)
            .map_err(|e| DatasetError::io(path, "read", e))?;
        if n == 0 {
            return Ok(());
        }
        number += 1;
        if !text.ends_with('\n') {
            return Err(DatasetError::ManifestLine {
                path: path.to_path_buf(),
                line: number,
                message: "the last line is incomplete (the run was interrupted): run the \
                          dataset command again with --resume"
                    .into(),
            });
        }
        let line = parse_line(path, number, &text)?;
        visit(number, line)?;
    }
}

/// Puts the manifest at `path` in index order, if it is not, without holding it in memory:
/// it is cut into its sorted runs (where an index is not above the one before), which are
/// merged with a heap of one line per run into a temporary renamed over the manifest.
/// Returns whether it was reordered.
pub fn sort_manifest(path: &Path) -> Result<bool, DatasetError> {
    // Pass 1: the line number where each sorted run starts.
    let mut starts = Vec::new();
    let mut last: Option<u64> = None;
    for_each_line(path, |number, line| {
        if last.is_none_or(|l| line.index <= l) {
            starts.push(number);
        }
        last = Some(line.index);
        Ok(())
    })?;
    if starts.len() <= 1 {
        return Ok(false);
    }
    // Pass 2: one reader per run, from its first line to the next run's.
    let ends = starts.iter().skip(1).copied().chain([usize::MAX]);
    let spans: Vec<(usize, usize)> = starts.iter().copied().zip(ends).collect();
    crate::io::atomic::write_atomic(path, |w| {
        let mut runs = spans
            .iter()
            .map(|&(first, end)| SortedRun::open(path, first, end))
            .collect::<std::io::Result<Vec<_>>>()?;
        let mut heap = BinaryHeap::new();
        for (k, run) in runs.iter_mut().enumerate() {
            if let Some((index, text)) = run.next(path)? {
                heap.push(Reverse((index, k, text)));
            }
        }
        while let Some(Reverse((_, k, text))) = heap.pop() {
            writeln!(w, "{text}")?;
            if let Some((index, text)) = runs[k].next(path)? {
                heap.push(Reverse((index, k, text)));
            }
        }
        Ok(())
    })?;
    Ok(true)
}

/// The lines `at..end` (1-based) of a manifest: one sorted run of [`sort_manifest`].
struct SortedRun {
    lines: std::iter::Skip<std::io::Lines<BufReader<File>>>,
    at: usize,
    end: usize,
}

impl SortedRun {
    fn open(path: &Path, first: usize, end: usize) -> std::io::Result<SortedRun> {
        Ok(SortedRun {
            lines: BufReader::new(File::open(path)?).lines().skip(first - 1),
            at: first,
            end,
        })
    }

    /// The run's next (index, line text), `None` past its end.
    fn next(&mut self, path: &Path) -> std::io::Result<Option<(u64, String)>> {
        if self.at >= self.end {
            return Ok(None);
        }
        let Some(text) = self.lines.next() else {
            return Ok(None);
        };
        let text = text?;
        let line = parse_line(path, self.at, &text).map_err(std::io::Error::other)?;
        self.at += 1;
        Ok(Some((line.index, text)))
    }
}

/// Parses one manifest line (`number` is 1-based, for messages).
pub fn parse_line(path: &Path, number: usize, text: &str) -> Result<ManifestLine, DatasetError> {
    serde_json::from_str(text.trim_end()).map_err(|e| DatasetError::ManifestLine {
        path: path.to_path_buf(),
        line: number,
        message: format!("expected a manifest line (a JSON object with index, directory, …): {e}"),
    })
}

/// Encodes `line` as it is stored (without the newline).
pub fn encode_line(line: &ManifestLine) -> String {
    serde_json::to_string(line).expect("a manifest line always serialises")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(index: u64) -> ManifestLine {
        ManifestLine {
            index,
            directory: format!("sample_{index:06}"),
            seed: 1234 + index,
            border_fraction: 1.0 / 3.0,
            parameters: BTreeMap::from([("scan_angle_deg".to_string(), 41.5)]),
            edge_point_mm: (index % 2 == 0).then_some([150.0, -0.1, 4.01]),
            valid_points: 321,
            labels: BTreeMap::from([("table".to_string(), 300), ("glass_edge".into(), 21)]),
            saturated_pixels: 0,
            files: vec![FileRecord {
                name: "image.png".into(),
                bytes: 12,
                sha256: "ab".repeat(32),
            }],
            warnings: Vec::new(),
        }
    }

    fn read_all(path: &Path) -> Result<Vec<ManifestLine>, DatasetError> {
        let mut out = Vec::new();
        for_each_line(path, |_, l| {
            out.push(l);
            Ok(())
        })?;
        Ok(out)
    }

    #[test]
    fn appended_lines_read_back_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(MANIFEST);
        let mut w = ManifestWriter::open(&path).unwrap();
        w.append(&line(0)).unwrap();
        w.append(&line(1)).unwrap();
        drop(w);
        let mut w = ManifestWriter::open(&path).unwrap();
        w.append(&line(2)).unwrap();
        assert_eq!(read_all(&path).unwrap(), [line(0), line(1), line(2)]);
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().count(), 3);
        assert_eq!(text.lines().next().unwrap(), encode_line(&line(0)));
    }

    #[test]
    fn a_torn_tail_is_refused_by_readers_and_cut_by_repair() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(MANIFEST);
        let mut w = ManifestWriter::open(&path).unwrap();
        w.append(&line(0)).unwrap();
        drop(w);
        let whole = encode_line(&line(1));
        let mut f = OpenOptions::new().append(true).open(&path).unwrap();
        f.write_all(&whole.as_bytes()[..whole.len() / 2]).unwrap();
        drop(f);
        let message = read_all(&path).unwrap_err().to_string();
        assert!(
            message.contains("manifest.jsonl:2: the last line is incomplete"),
            "{message}"
        );
        assert!(repair_torn_tail(&path).unwrap());
        assert!(!repair_torn_tail(&path).unwrap());
        assert_eq!(read_all(&path).unwrap(), [line(0)]);
        let mut w = ManifestWriter::open(&path).unwrap();
        w.append(&line(1)).unwrap();
        assert_eq!(read_all(&path).unwrap(), [line(0), line(1)]);
        assert!(!repair_torn_tail(&dir.path().join("missing.jsonl")).unwrap());
    }

    #[test]
    fn sorting_merges_the_sorted_runs_of_a_resumed_manifest() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(MANIFEST);
        let mut w = ManifestWriter::open(&path).unwrap();
        for i in [0, 2, 5, 1, 3, 4, 6, 2 + 5] {
            w.append(&line(i)).unwrap();
        }
        drop(w);
        assert!(sort_manifest(&path).unwrap());
        let indices: Vec<u64> = read_all(&path).unwrap().iter().map(|l| l.index).collect();
        assert_eq!(indices, [0, 1, 2, 3, 4, 5, 6, 7]);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(!sort_manifest(&path).unwrap());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_bad_line_names_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(MANIFEST);
        std::fs::write(
            &path,
            format!("{}\n{{\"index\": \"three\"}}\n", encode_line(&line(0))),
        )
        .unwrap();
        let message = read_all(&path).unwrap_err().to_string();
        assert!(
            message.contains("manifest.jsonl:2: expected a manifest line"),
            "{message}"
        );
    }

    #[test]
    fn runs_differ_in_what_matters_but_not_in_paths() {
        let a = RunInfo {
            version: "0.1.0".into(),
            scene: "scenes/a.toml".into(),
            scene_toml: "x = 1".into(),
            randomize: None,
            randomize_toml: None,
            seed: 1,
            count: 10,
            photons: 4096,
            adaptive_photons: false,
            max_depth: 64,
            ply_ascii: false,
        };
        let moved = RunInfo {
            scene: "/elsewhere/a.toml".into(),
            ..a.clone()
        };
        assert!(a.differences(&moved).is_empty());
        let other = RunInfo {
            seed: 2,
            count: 11,
            scene_toml: "x = 2".into(),
            ..a.clone()
        };
        let d = a.differences(&other);
        assert_eq!(d.len(), 3, "{d:?}");
        assert!(d[0].contains("seed 1 there, 2 here"), "{d:?}");
    }
}
