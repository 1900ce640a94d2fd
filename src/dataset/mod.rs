//! Output files on disk. Each writer has a matching reader, used by the tests to prove that
//! what is written reads back bit for bit (and by tools that post-process a dataset).
//!
//! - `png16`: sensor images in digital numbers (DN), 16-bit greyscale PNG.
//! - `exr`: radiometric images (irradiance in W/m², one f32 layer per light-path class),
//!   single-part scanline OpenEXR.
//! - `profile_csv`: line profiles (column, sub-pixel row, x and z in mm, intensity in DN,
//!   peak width in px, validity).
//! - `json`: manifests and configurations.
//! - `points_csv`: named-column CSV tables (BIPs) and the x_mm, y_mm, z_mm reader.
//! - `ply`: point clouds (ASCII PLY, x y z and optional colours) for Open3D and CloudCompare.
//! - `atomic`: the one way files are written; `output_dir`: the one check before a run writes.
//!
//! Synthetic datasets (`glassscan dataset`, `merge`, `verify`, `score`), built on the writers
//! above and on `scene` and `scan`:
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
//! - Only `scene` (reading inputs) and `dataset` (writing outputs) touch the file system.
//! - Every file is written atomically (temporary file in the same directory, `sync_all`,
//!   `rename`): a reader sees the old file or the complete new one, never a torn file.
//! - Images are row-major with row 0 at the top, in memory and in every file format.
//! - Readers never convert: a file of another bit depth, sample type or header is an error.
//! - Every error names the file, and the line and column where there is one.

pub mod atomic;
pub mod dataset_dir;
pub mod error;
pub mod exr;
pub mod generate;
pub mod ideal_profile;
pub mod integrity;
pub mod json;
pub mod manifest;
pub mod merge;
pub mod output_dir;
pub mod ply;
pub mod png16;
pub mod points_csv;
pub mod profile_csv;
pub mod randomize;
pub mod sample;
pub mod sample_files;
pub mod scene_edit;
pub mod score;
pub mod shard;
pub mod verify;

pub use error::DatasetError;
