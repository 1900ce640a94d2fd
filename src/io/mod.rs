//! File formats: what glassscan writes and reads back. Each writer has a matching reader, used
//! by the tests to prove that what is written reads back bit for bit (and by tools that
//! post-process a dataset).
//!
//! - `png16`: sensor images in digital numbers (DN), 16-bit greyscale PNG.
//! - `exr`: radiometric images (irradiance in W/m², one f32 layer per light-path class),
//!   single-part scanline OpenEXR.
//! - `profile_csv`: line profiles (column, sub-pixel row, x and z in mm, intensity in DN,
//!   peak width in px, validity).
//! - `json`: manifests and configurations.
//! - `points_csv`: named-column CSV tables (BIPs) and the x_mm, y_mm, z_mm reader;
//!   `csv_read`: every CSV read (the `csv` crate; separator sniffed, BOM, quotes).
//! - `ply`: point clouds (binary or ASCII PLY: x y z and optional colour, label, intensity) for
//!   Open3D, CloudCompare and `plyfile`.
//! - `atomic`: the one way files are written; `output_dir`: the one check before a run writes.
//!
//! Invariants:
//! - Every output file is written through `atomic` (temporary file in the same directory,
//!   `sync_all`, `rename`): a reader sees the old file or the complete new one, never a torn
//!   file. The one exception is a dataset's JSON-lines manifest, which `dataset::manifest`
//!   appends to one complete line at a time (and repairs a torn last line on resume).
//! - Images are row-major with row 0 at the top, in memory and in every file format.
//! - Readers never convert: a file of another bit depth, sample type or header is an error.
//! - Every error names the file, and the line and column where there is one.

pub mod atomic;
pub mod csv_read;
pub mod error;
pub mod exr;
pub mod json;
pub mod output_dir;
pub mod ply;
pub mod png16;
pub mod points_csv;
pub mod profile_csv;

pub use error::FileError;
