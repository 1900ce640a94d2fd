//! Synthetic datasets (`glassscan dataset`, `merge`, `verify`, `score`), built on the file
//! formats of `io` and on `scene` and `scan`:
//! - `randomize` (the `--randomize` ranges and the per-sample draws), `scene_edit` (a scene
//!   file edited with the draws and loaded again), `ideal_profile` (the exact cross-section
//!   the laser plane cuts), `sample` (one sample end to end), `sample_files` (its directory);
//! - `manifest` (`run.json` and the JSON-lines manifests), `integrity` (each sample file's
//!   size and SHA-256 in its manifest line, and the check of a finished sample),
//!   `dataset_dir` (refuse, start or resume an output directory), `shard` (`--shard K/N` and
//!   scheduler environments), `generate` (the run loop), `merge` (shard manifests →
//!   `manifest.jsonl`, refused while a sample is damaged), `verify` (a whole dataset against
//!   its manifests), `score` (a user's BIPs against the ground truth).
//!
//! Invariants:
//! - A sample's files are written through `io` (atomically) and recorded in its manifest line
//!   (size and SHA-256) only after all of them are complete, so a finished sample is one whose
//!   manifest line exists and whose files match it.

pub mod dataset_dir;
pub mod error;
pub mod generate;
pub mod ideal_profile;
pub mod integrity;
pub mod manifest;
pub mod merge;
pub mod randomize;
pub mod sample;
pub mod sample_files;
pub mod scene_edit;
pub mod score;
pub mod shard;
pub mod verify;

pub use error::DatasetError;
