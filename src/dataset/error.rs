//! The error type of the dataset job: a file error (`io::FileError`) or what is wrong with a
//! dataset, a shard, a randomisation file or a sample. Like file errors, every variant names
//! the file or flag it concerns, so that the message is enough to find and fix the problem.

use std::path::PathBuf;

use crate::io::FileError;

/// An error of a dataset run, merge, verification or score.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// Writing or reading one file failed.
    #[error(transparent)]
    File(#[from] FileError),

    /// A bad shard specification: `origin` is the flag (`--shard`) or the environment variable
    /// that holds it.
    #[error("{origin}: {message}")]
    Shard {
        /// `--shard` or the variable's name.
        origin: String,
        /// What was expected and what was found.
        message: String,
    },

    /// A bad domain-randomisation file: unknown key, bad range, or a range the scene cannot take.
    #[error("{}:{line}:{column}: {key}: {message}", path.display())]
    Randomize {
        /// The randomisation file.
        path: PathBuf,
        /// 1-based line of the offending key (1 when the problem is not on one line).
        line: usize,
        /// 1-based column (characters).
        column: usize,
        /// The key (e.g. `glass_thickness_mm`).
        key: String,
        /// What was expected and what was found.
        message: String,
    },

    /// Finished samples whose files are not what their manifest lines record.
    #[error(
        "{samples} finished sample(s) are damaged:\n  {}\nmake them again with `glassscan \
         dataset … --resume` in their dataset directory (it redoes damaged samples), then retry; \
         `glassscan verify DIR` lists the damage of a whole dataset",
        damage.join("\n  ")
    )]
    DamagedSamples {
        /// How many samples are damaged.
        samples: u64,
        /// One message per damaged file.
        damage: Vec<String>,
    },

    /// A line of a dataset manifest (JSON lines) that cannot be read.
    #[error("{}:{line}: {message}", path.display())]
    ManifestLine {
        /// The manifest.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        message: String,
    },

    /// A dataset file or directory that is not there or not what a command needs.
    #[error("{}: {message}", path.display())]
    NotADataset {
        /// The file or directory.
        path: PathBuf,
        /// What is missing and what to do.
        message: String,
    },

    /// A dataset directory holds a run that differs from this one (another scene, seed, …).
    #[error(
        "{} holds a dataset of another run ({}): choose another directory, or repeat the \
         original run's arguments",
        path.display(),
        differences.join("; ")
    )]
    RunMismatch {
        /// The run file of the directory.
        path: PathBuf,
        /// What differs, e.g. "seed 1 there, 2 here".
        differences: Vec<String>,
    },

    /// A dataset output directory that this run may not write into without `--resume`.
    #[error(
        "output directory {} {reason}: pass --resume to continue the run in it, or choose \
         another directory",
        path.display()
    )]
    DatasetDirBusy {
        /// The output directory.
        path: PathBuf,
        /// Why, e.g. "already holds samples of shard 0/1".
        reason: String,
    },

    /// Shard manifests that do not add up to the whole dataset.
    #[error(
        "the shard manifests do not cover samples 0..{count} exactly once: {}",
        coverage(missing, duplicated)
    )]
    MergeCoverage {
        /// The run's sample count.
        count: u64,
        /// Samples no manifest lists.
        missing: Vec<u64>,
        /// Samples listed more than once.
        duplicated: Vec<u64>,
    },

    /// A sample of a dataset could not be made (its randomised scene does not load, …).
    #[error("sample {index}: {message}")]
    Sample {
        /// Sample index.
        index: u64,
        /// What went wrong, with its causes.
        message: String,
    },
}

/// "missing 3, 7; listed twice 4" with long lists cut after 20 entries.
fn coverage(missing: &[u64], duplicated: &[u64]) -> String {
    let list = |v: &[u64]| {
        let mut s: Vec<String> = v.iter().take(20).map(u64::to_string).collect();
        if v.len() > 20 {
            s.push(format!("… ({} in all)", v.len()));
        }
        s.join(", ")
    };
    let mut parts = Vec::new();
    if !missing.is_empty() {
        parts.push(format!("missing {}", list(missing)));
    }
    if !duplicated.is_empty() {
        parts.push(format!("listed more than once {}", list(duplicated)));
    }
    parts.join("; ")
}

impl DatasetError {
    /// Shorthand for a [`FileError::Io`].
    pub(crate) fn io(
        path: impl Into<PathBuf>,
        action: &'static str,
        source: std::io::Error,
    ) -> Self {
        DatasetError::File(FileError::io(path, action, source))
    }
}
