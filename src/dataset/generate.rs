//! The dataset generator: the samples of one shard, simulated in parallel, written one
//! directory each, recorded in the shard's manifest in index order.
//!
//! Samples run in batches of a few per worker thread (rayon, each sample's photons in parallel
//! too); within a batch they finish in any order, but their manifest lines are appended in
//! index order once the batch is done. So the manifest, like every file, is the same for any
//! thread count, and only a batch's worth of samples is ever in memory: memory stays flat as
//! the sample count grows. A run killed mid-batch loses at most that batch's samples, which a
//! resumed run makes again.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::dataset_dir::{prepare_dataset_dir, sweep_temporaries};
use super::manifest::{sort_manifest, ManifestWriter, RunInfo};
use super::randomize::Randomization;
use super::sample::{make_sample, PreparedWorld, SampleContext};
use super::sample_files::{sample_dir_name, write_sample};
use super::scene_edit::SceneTemplate;
use super::shard::Shard;
use super::DatasetError;
use crate::io::ply::PlyEncoding;

/// Samples per worker thread in a batch: enough to keep threads busy when samples take
/// different times, few enough to keep memory small.
const SAMPLES_PER_THREAD: usize = 2;

/// A validated dataset run.
pub struct DatasetRun<'a> {
    /// The scene.
    pub template: &'a SceneTemplate,
    /// The randomisation, already checked against the scene.
    pub randomization: Option<&'a Randomization>,
    /// Master seed.
    pub seed: u64,
    /// Samples of the whole dataset.
    pub count: u64,
    /// Laser photons per sample (with `adaptive`, the most a sample may take).
    pub photons: u64,
    /// Whether each sample stops once its edge-line BIP has converged (`scan::adaptive`).
    pub adaptive: bool,
    /// Longest photon path.
    pub max_depth: u32,
    /// `points.ply` as ASCII instead of binary little-endian.
    pub ply_ascii: bool,
    /// Which samples this process makes.
    pub shard: Shard,
    /// Output directory.
    pub out: &'a Path,
    /// Continue a killed run instead of refusing a directory that holds this shard's samples.
    pub resume: bool,
}

/// What a run did.
#[derive(Debug, serde::Serialize)]
pub struct DatasetOutcome {
    /// The shard's manifest.
    pub manifest: PathBuf,
    /// Samples in the shard.
    pub in_shard: u64,
    /// Samples found finished and kept (resume).
    pub kept: u64,
    /// Samples made by this run.
    pub made: u64,
    /// Finished samples that were found damaged (resume) and made again.
    pub damaged_samples: u64,
    /// What was damaged, one message per file.
    pub damage: Vec<String>,
    /// The warnings of the samples this run made (`scan::warnings`), "sample N: …".
    pub warnings: Vec<String>,
}

impl DatasetRun<'_> {
    /// The run file this run writes (and expects on resume).
    pub fn info(&self) -> RunInfo {
        RunInfo {
            version: env!("CARGO_PKG_VERSION").into(),
            scene: self.template.path.display().to_string(),
            scene_toml: self.template.text.clone(),
            randomize: self.randomization.map(|r| r.path.display().to_string()),
            randomize_toml: self.randomization.map(|r| r.text.clone()),
            seed: self.seed,
            count: self.count,
            photons: self.photons,
            adaptive_photons: self.adaptive,
            max_depth: self.max_depth,
            ply_ascii: self.ply_ascii,
        }
    }

    fn ply_encoding(&self) -> PlyEncoding {
        if self.ply_ascii {
            PlyEncoding::Ascii
        } else {
            PlyEncoding::BinaryLittleEndian
        }
    }

    /// Runs the shard; `progress(k)` is called as each finished sample is recorded (after the
    /// kept ones are reported in one call).
    pub fn execute(&self, progress: impl Fn(u64)) -> Result<DatasetOutcome, DatasetError> {
        let base = PreparedWorld::new(self.template.world.clone()).map_err(|message| {
            DatasetError::Sample {
                index: 0,
                message: format!("{}: {message}", self.template.path.display()),
            }
        })?;
        let info = self.info();
        let prepared = prepare_dataset_dir(self.out, &info, self.shard, self.resume)?;
        let finished = &prepared.finished;
        let manifest = self.out.join(self.shard.manifest_name());
        let mut writer = ManifestWriter::open(&manifest)?;
        let in_shard = self.shard.indices(self.count).count() as u64;
        progress(finished.len);
        for i in self
            .shard
            .indices(self.count)
            .filter(|&i| finished.contains(i))
        {
            sweep_temporaries(&self.out.join(sample_dir_name(i)))?;
        }

        let ctx = SampleContext {
            template: self.template,
            base: &base,
            randomization: self.randomization,
            seed: self.seed,
            photons: self.photons,
            adaptive: self.adaptive,
            max_depth: self.max_depth,
        };
        let batch = rayon::current_num_threads().max(1) * SAMPLES_PER_THREAD;
        let mut todo = self
            .shard
            .indices(self.count)
            .filter(|&i| !finished.contains(i))
            .peekable();
        let mut made = 0;
        let mut warned = Vec::new();
        let remade_any = prepared.damaged_samples > 0;
        while todo.peek().is_some() {
            let indices: Vec<u64> = todo.by_ref().take(batch).collect();
            let lines: Vec<_> = indices
                .par_iter()
                .map(|&i| {
                    let sample = make_sample(&ctx, i)?;
                    let dir = self.out.join(sample_dir_name(i));
                    std::fs::create_dir_all(&dir)
                        .map_err(|e| DatasetError::io(&dir, "create the sample directory", e))?;
                    write_sample(&dir, &sample, self.ply_encoding())
                })
                .collect();
            // Record the batch in index order, up to the first failure.
            for line in lines {
                let line = line?;
                warned.extend(
                    line.warnings
                        .iter()
                        .map(|w| format!("sample {}: {w}", line.index)),
                );
                writer.append(&line)?;
                made += 1;
                progress(1);
            }
        }
        if remade_any {
            // Samples made again after a damaged one were appended after later intact ones;
            // a shard manifest is kept in index order (merge streams it).
            sort_manifest(&manifest)?;
        }
        Ok(DatasetOutcome {
            manifest,
            in_shard,
            kept: finished.len,
            made,
            damaged_samples: prepared.damaged_samples,
            damage: prepared.damaged.iter().map(ToString::to_string).collect(),
            warnings: warned,
        })
    }
}
