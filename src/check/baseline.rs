//! The committed baseline: per case, the metrics of the run it was made from.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::compare::Metrics;
use crate::io::json::{read_json, write_json_pretty};
use crate::io::FileError;

/// A suite's baseline file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Baseline {
    /// glassscan version that wrote it.
    pub glassscan_version: String,
    /// Metrics per case name.
    pub cases: BTreeMap<String, Metrics>,
}

/// Reads a baseline; a missing file is an empty baseline (every case new). A path that does
/// not exist on disk but is a shipped baseline's (`validation/check/fast.baseline.json`, run
/// away from the repository root) reads the copy in the binary (`crate::shipped`).
pub fn read_baseline(path: &Path) -> Result<Baseline, FileError> {
    if let Some(shipped) = crate::shipped::fallback(path) {
        return serde_json::from_slice(shipped.bytes).map_err(|source| FileError::JsonRead {
            path: path.to_path_buf(),
            source,
        });
    }
    if !path.exists() {
        return Ok(Baseline::default());
    }
    read_json(path)
}

/// Writes a baseline, atomically.
pub fn write_baseline(path: &Path, baseline: &Baseline) -> Result<(), FileError> {
    write_json_pretty(path, baseline)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_missing_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("b.baseline.json");
        assert_eq!(read_baseline(&p).unwrap(), Baseline::default());
        let mut b = Baseline {
            glassscan_version: "0.1.0".into(),
            ..Default::default()
        };
        b.cases.insert(
            "a".into(),
            [
                ("bips".to_string(), Some(12.0)),
                ("pose_rotation_deg".to_string(), None),
            ]
            .into(),
        );
        write_baseline(&p, &b).unwrap();
        assert_eq!(read_baseline(&p).unwrap(), b);
        std::fs::write(&p, "{\"cases\": 3}").unwrap();
        assert!(read_baseline(&p)
            .unwrap_err()
            .to_string()
            .contains("b.baseline.json"));
    }
}
