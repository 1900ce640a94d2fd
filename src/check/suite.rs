//! The suite file: `[[case]]` tables with the run's settings and optional per-metric
//! tolerances that override the suite's `[tolerance]` defaults.
//!
//! ```toml
//! [tolerance]                 # defaults for every case (absolute, in the metric's unit)
//! bip_error_mean_mm = 0.02
//!
//! [[case]]
//! name = "car_window_45"
//! scene = "scenes/car_side_window.toml"   # relative to the current directory (a shipped
//!                                          # scene's path also works elsewhere)
//! scan_angle_deg = 45
//! poses = 12
//! seed = 1
//! photons = 262144
//! errors = "off"              # or "default"
//! bip = "edge-line"           # or "highest"
//! tolerance = { task_error_max_mm = 0.05 }
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::compare::METRICS;

/// One case as written in the file.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CaseDef {
    /// Unique name (the baseline's key).
    pub name: String,
    /// Scene file.
    pub scene: PathBuf,
    /// Scan angle (deg); default: the scene's.
    pub scan_angle_deg: Option<f64>,
    /// Number of poses (≥ 3); default: the scene's.
    pub poses: Option<usize>,
    /// Seed.
    pub seed: u64,
    /// Photons per pose (≥ 1000).
    pub photons: u64,
    /// Exposure (ms); default: the scene's.
    pub exposure_ms: Option<f64>,
    /// `off` or `default`.
    #[serde(default = "default_errors")]
    pub errors: String,
    /// `edge-line` or `highest`.
    #[serde(default = "default_bip")]
    pub bip: String,
    /// Per-metric tolerances for this case.
    #[serde(default)]
    pub tolerance: BTreeMap<String, f64>,
}

fn default_errors() -> String {
    "off".into()
}

fn default_bip() -> String {
    "edge-line".into()
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SuiteFile {
    #[serde(default)]
    tolerance: BTreeMap<String, f64>,
    case: Vec<CaseDef>,
}

/// A validated suite.
#[derive(Clone, Debug, PartialEq)]
pub struct Suite {
    /// The suite file.
    pub path: PathBuf,
    /// Its cases, in file order, with tolerances merged (case over suite defaults).
    pub cases: Vec<CaseDef>,
}

impl Suite {
    /// The baseline file that goes with the suite: `NAME.baseline.json` next to `NAME.toml`.
    pub fn baseline_path(&self) -> PathBuf {
        self.path.with_extension("baseline.json")
    }
}

/// Reads and validates a suite file. Errors name the file, the case and the field.
pub fn load_suite(path: &Path) -> anyhow::Result<Suite> {
    let text = crate::shipped::read_to_string(path)
        .map_err(|e| anyhow::anyhow!("{}: could not read the suite: {e}", path.display()))?;
    let file: SuiteFile =
        toml::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let bad = |case: &str, field: &str, what: String| {
        anyhow::anyhow!("{}: case {case:?}: {field} {what}", path.display())
    };
    let check_tolerances = |case: &str, t: &BTreeMap<String, f64>| {
        for (k, v) in t {
            if !METRICS.iter().any(|m| m.name == k) {
                let names: Vec<&str> = METRICS.iter().map(|m| m.name).collect();
                return Err(bad(
                    case,
                    &format!("tolerance.{k}"),
                    format!("is not a metric (expected one of {})", names.join(", ")),
                ));
            }
            if !(v.is_finite() && *v >= 0.0) {
                return Err(bad(
                    case,
                    &format!("tolerance.{k}"),
                    format!("must be a finite number ≥ 0, got {v}"),
                ));
            }
        }
        Ok(())
    };
    check_tolerances("(suite defaults)", &file.tolerance)?;
    let mut cases: Vec<CaseDef> = Vec::new();
    for mut c in file.case {
        if cases.iter().any(|d| d.name == c.name) {
            return Err(bad(&c.name, "name", "is used by another case".into()));
        }
        if let Some(a) = c.scan_angle_deg {
            if !(a.is_finite() && a > 0.0 && a <= 90.0) {
                return Err(bad(
                    &c.name,
                    "scan_angle_deg",
                    format!("must be in (0, 90], got {a}"),
                ));
            }
        }
        if let Some(n) = c.poses {
            if n < 3 {
                return Err(bad(
                    &c.name,
                    "poses",
                    format!("must be ≥ 3 (ICP needs three points), got {n}"),
                ));
            }
        }
        if c.photons < 1000 {
            return Err(bad(
                &c.name,
                "photons",
                format!("must be ≥ 1000, got {}", c.photons),
            ));
        }
        if let Some(e) = c.exposure_ms {
            if !(e.is_finite() && e > 0.0) {
                return Err(bad(&c.name, "exposure_ms", format!("must be > 0, got {e}")));
            }
        }
        if !["off", "default"].contains(&c.errors.as_str()) {
            return Err(bad(
                &c.name,
                "errors",
                format!("must be \"off\" or \"default\", got {:?}", c.errors),
            ));
        }
        if !["edge-line", "highest"].contains(&c.bip.as_str()) {
            return Err(bad(
                &c.name,
                "bip",
                format!("must be \"edge-line\" or \"highest\", got {:?}", c.bip),
            ));
        }
        check_tolerances(&c.name, &c.tolerance)?;
        let mut merged = file.tolerance.clone();
        merged.extend(std::mem::take(&mut c.tolerance));
        c.tolerance = merged;
        cases.push(c);
    }
    if cases.is_empty() {
        return Err(anyhow::anyhow!(
            "{}: expected at least one [[case]]",
            path.display()
        ));
    }
    Ok(Suite {
        path: path.to_path_buf(),
        cases,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(text: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("s.toml");
        std::fs::write(&p, text).unwrap();
        (dir, p)
    }

    const CASE: &str =
        "[[case]]\nname = \"a\"\nscene = \"scenes/flat_opaque.toml\"\nseed = 1\nphotons = 20000\n";

    #[test]
    fn tolerances_merge_case_over_suite() {
        let (_d, p) = write(&format!(
            "[tolerance]\nbip_error_mean_mm = 0.1\npose_translation_mm = 0.2\n{CASE}tolerance = {{ bip_error_mean_mm = 0.01 }}\n"
        ));
        let s = load_suite(&p).unwrap();
        let t = &s.cases[0].tolerance;
        assert_eq!(t["bip_error_mean_mm"], 0.01);
        assert_eq!(t["pose_translation_mm"], 0.2);
        assert_eq!(s.cases[0].errors, "off");
        assert_eq!(s.baseline_path(), p.with_file_name("s.baseline.json"));
    }

    #[test]
    fn bad_suites_name_the_case_and_field() {
        for (extra, needle) in [
            ("poses = 2\n", "poses"),
            ("errors = \"some\"\n", "errors"),
            ("tolerance = { nonsense = 1.0 }\n", "tolerance.nonsense"),
            ("colour = 3\n", "colour"),
        ] {
            let (_d, p) = write(&format!("{CASE}{extra}"));
            let e = load_suite(&p).unwrap_err().to_string();
            assert!(e.contains("s.toml") && e.contains(needle), "{e}");
        }
        let (_d, p) = write(&format!("{CASE}{CASE}"));
        assert!(load_suite(&p)
            .unwrap_err()
            .to_string()
            .contains("another case"));
    }

    #[test]
    fn names_resolve_under_validation_check() {
        assert_eq!(
            crate::shipped::resolve_suite("fast").unwrap(),
            PathBuf::from("validation/check/fast.toml")
        );
        assert_eq!(
            crate::shipped::resolve_suite("x/y.toml").unwrap(),
            PathBuf::from("x/y.toml")
        );
        // The shipped suite loads from the binary when its file is not on disk.
        let shipped = crate::shipped::file(Path::new("validation/check/fast.toml")).unwrap();
        assert!(!shipped.bytes.is_empty());
        assert!(load_suite(Path::new("validation/check/fast.toml")).is_ok());
    }
}
