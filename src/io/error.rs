//! The one error type of the file formats. Every variant carries the path of the file it
//! concerns and, where it applies, the line and column, so that a message read in a terminal is
//! enough to find and fix the problem (pbrt's `ErrorExit(&loc, …)` reports file:line the same
//! way).

use std::path::{Path, PathBuf};

/// An error while writing or reading a file.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The operating system refused an operation on `path`.
    #[error("could not {action} {}: {source}", path.display())]
    Io {
        /// The file or directory concerned.
        path: PathBuf,
        /// What was being done, as a verb phrase ("write", "rename the temporary file onto").
        action: &'static str,
        /// The underlying error.
        source: std::io::Error,
    },

    /// A path given to a writer does not end in a file name (it is empty, `/` or ends in `..`).
    #[error("{}: expected a path that names a file", path.display())]
    NotAFilePath {
        /// The offending path.
        path: PathBuf,
    },

    /// The output directory exists and holds files, and overwriting was not asked for.
    #[error(
        "output directory {} is not empty: pass --force to overwrite the files in it, \
         or choose another directory",
        path.display()
    )]
    OutputNotEmpty {
        /// The output directory.
        path: PathBuf,
    },

    /// The output directory exists but a file cannot be created in it.
    #[error(
        "output directory {} is not writable ({source}): choose another directory or fix its \
         permissions",
        path.display()
    )]
    OutputNotWritable {
        /// The output directory.
        path: PathBuf,
        /// The operating system's refusal.
        source: std::io::Error,
    },

    /// The output directory path names something that is not a directory.
    #[error("{}: expected an output directory, but it exists and is not a directory", path.display())]
    OutputNotADirectory {
        /// The offending path.
        path: PathBuf,
    },

    /// Image or layer data does not hold `width × height` samples.
    #[error(
        "{}: {what}: expected {expected} samples (width × height = {width} × {height}), got {found}",
        path.display()
    )]
    SampleCount {
        /// The file being written.
        path: PathBuf,
        /// Which data: "image" or `layer "name"`.
        what: String,
        /// Image width (px).
        width: usize,
        /// Image height (px).
        height: usize,
        /// `width * height`.
        expected: usize,
        /// The length of the data given.
        found: usize,
    },

    /// An image with no pixels, which neither PNG nor EXR can store.
    #[error(
        "{}: expected an image of at least 1 × 1 pixels, got {width} × {height}",
        path.display()
    )]
    EmptyImage {
        /// The file that was to be written.
        path: PathBuf,
        /// Image width (px).
        width: usize,
        /// Image height (px).
        height: usize,
    },

    /// The PNG encoder or decoder failed (corrupt or truncated file, image too large, …).
    #[error("{}: expected {expected}: {source}", path.display())]
    Png {
        /// The file concerned.
        path: PathBuf,
        /// What the file or image should have been, e.g. "a valid PNG file".
        expected: &'static str,
        /// The underlying error.
        source: image::ImageError,
    },

    /// A PNG file that decodes, but is not 16-bit greyscale.
    #[error("{}: expected a 16-bit greyscale PNG (L16), found {found}", path.display())]
    PngFormat {
        /// The file concerned.
        path: PathBuf,
        /// The colour type found, e.g. `L8` or `Rgb16`.
        found: String,
    },

    /// The OpenEXR encoder or decoder failed.
    #[error("{}: expected {expected}: {source}", path.display())]
    Exr {
        /// The file concerned.
        path: PathBuf,
        /// What the file or layers should have been, e.g. "a valid OpenEXR file".
        expected: &'static str,
        /// The underlying error.
        source: exr::error::Error,
    },

    /// An EXR file that decodes, but not into the layout `read_exr_layers` returns, or a layer
    /// list that `write_exr_layers` cannot store.
    #[error("{}: expected {expected}, got {found}", path.display())]
    ExrLayout {
        /// The file concerned.
        path: PathBuf,
        /// What the layout must be, e.g. "a single-part EXR".
        expected: String,
        /// What was found instead.
        found: String,
    },

    /// The first line of a profile CSV is not the expected header.
    #[error("{}:1: expected header \"{expected}\", got \"{found}\"", path.display())]
    CsvHeader {
        /// The file concerned.
        path: PathBuf,
        /// The header the reader understands.
        expected: String,
        /// The first line of the file (empty if the file is empty).
        found: String,
    },

    /// A CSV line with the wrong number of fields (typically a truncated file).
    #[error(
        "{}:{line}: expected {expected} fields separated by '{delimiter}', got {found}",
        path.display()
    )]
    CsvFieldCount {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number (the header is line 1).
        line: usize,
        /// Number of fields in the header.
        expected: usize,
        /// Number of fields on this line.
        found: usize,
        /// The field separator the reader found in the header (or the writer uses).
        delimiter: char,
    },

    /// Text the CSV reader cannot split into records.
    #[error("{}:{line}: not readable as CSV: {message}", path.display())]
    CsvSyntax {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number, 0 when the reader could not tell.
        line: usize,
        /// The CSV reader's message.
        message: String,
    },

    /// A CSV field that does not parse as its column's type.
    #[error(
        "{}:{line}: column {column}: expected {expected}, got \"{found}\"",
        path.display()
    )]
    CsvValue {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number (the header is line 1).
        line: usize,
        /// The column's name as in the header.
        column: &'static str,
        /// What the column holds, e.g. "a number" or "0 or 1".
        expected: &'static str,
        /// The field's text.
        found: String,
    },

    /// A value could not be serialised to JSON (e.g. a map with non-string keys).
    #[error("{}: expected a value that serialises to JSON: {source}", path.display())]
    JsonWrite {
        /// The file that was to be written.
        path: PathBuf,
        /// The underlying error.
        source: serde_json::Error,
    },

    /// A JSON file that is malformed or does not match the expected structure. The source
    /// message carries the line and column.
    #[error("{}: expected JSON matching the target type: {source}", path.display())]
    JsonRead {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error, with line and column.
        source: serde_json::Error,
    },

    /// A PLY file (or a cloud to write) that is not laid out as `ply` reads and writes it.
    #[error("{}:{line}: expected {expected}, got \"{found}\"", path.display())]
    PlyLayout {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number, 0 when the problem is not on one line.
        line: usize,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },

    /// A CSV whose header lacks a required column.
    #[error(
        "{}:1: expected a header with the column `{column}` (required: {required}), got \"{found}\"",
        path.display()
    )]
    CsvMissingColumn {
        /// The file concerned.
        path: PathBuf,
        /// The missing column.
        column: &'static str,
        /// All required columns, comma-separated.
        required: String,
        /// The header line.
        found: String,
    },

    /// A CSV field that is not what its column must hold, with a message that may depend on
    /// the data (e.g. a sample index outside the dataset).
    #[error("{}:{line}: column {column}: {message}", path.display())]
    CsvField {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number (the header is line 1).
        line: usize,
        /// The column's name.
        column: String,
        /// What was expected and what was found.
        message: String,
    },
}

impl FileError {
    /// Shorthand for [`FileError::Io`].
    pub(crate) fn io(
        path: impl Into<PathBuf>,
        action: &'static str,
        source: std::io::Error,
    ) -> Self {
        FileError::Io {
            path: path.into(),
            action,
            source,
        }
    }
}

/// Checks that an image of `width` × `height` has at least one pixel and that `len` samples
/// fill it exactly; `what` names the data in the error ("image", `layer "irradiance"`).
pub(crate) fn check_image_size(
    path: &Path,
    what: impl FnOnce() -> String,
    width: usize,
    height: usize,
    len: usize,
) -> Result<(), FileError> {
    if width == 0 || height == 0 {
        return Err(FileError::EmptyImage {
            path: path.to_path_buf(),
            width,
            height,
        });
    }
    // An overflowing product cannot equal any `len`, so treat it as a mismatch.
    let expected = width.saturating_mul(height);
    if len != expected {
        return Err(FileError::SampleCount {
            path: path.to_path_buf(),
            what: what(),
            width,
            height,
            expected,
            found: len,
        });
    }
    Ok(())
}
