//! JSON files (manifests, run configurations, metrics): pretty-printed on write, typed on read.
//!
//! Finite f64 values read back bit for bit only with serde_json's `float_roundtrip` feature
//! enabled in Cargo.toml: the default parser is faster but can be one ulp off (about one value
//! in ten in the millimetre range). `tests::round_trip_is_exact` checks that it is enabled.
//!
//! Non-finite floats have no JSON form: `serde_json` writes NaN and ±∞ as `null`, which does not
//! read back as an f64. Values that may be non-finite belong in `Option<f64>` or in the CSV and
//! EXR files.

use std::path::Path;

use serde::de::DeserializeOwned;
use serde::Serialize;

use super::atomic::write_atomic;
use super::FileError;

/// A setting converted between units (ms → s → ms, deg → rad → deg) as the decimal the user
/// typed: `x` rounded to 15 significant digits, so that `0.015000000000000001` prints as
/// `0.015`. Every decimal of at most 15 digits survives the round trip through the nearest f64
/// and back (IEEE 754 binary64 holds 15 decimal digits exactly), so a typed value comes back
/// exactly; any other value moves by at most 5·10⁻¹⁵ of itself. For settings only: measured
/// numbers are written as they are.
pub fn tidy_decimal(x: f64) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    format!("{x:.14e}").parse().unwrap_or(x)
}

/// Writes `value` as compact JSON on one line (with a trailing newline) at `path`, atomically:
/// one record per file that `pandas.read_json(path, lines=True)` reads as one row.
pub fn write_json_line<T: Serialize + ?Sized>(path: &Path, value: &T) -> Result<(), FileError> {
    write_encoded(path, serde_json::to_vec(value))
}

/// Writes `value` as pretty-printed JSON (two-space indent, trailing newline) at `path`,
/// atomically.
pub fn write_json_pretty<T: Serialize + ?Sized>(path: &Path, value: &T) -> Result<(), FileError> {
    write_encoded(path, serde_json::to_vec_pretty(value))
}

/// Writes serialised JSON and a final newline at `path`, atomically. Serialising to memory
/// first means a serialisation error never leaves a temporary behind.
fn write_encoded(
    path: &Path,
    encoded: Result<Vec<u8>, serde_json::Error>,
) -> Result<(), FileError> {
    let mut encoded = encoded.map_err(|source| FileError::JsonWrite {
        path: path.to_path_buf(),
        source,
    })?;
    encoded.push(b'\n');
    write_atomic(path, |w| w.write_all(&encoded))
}

/// Reads a JSON file into a `T`. Malformed JSON and JSON of another shape are reported with the
/// path, line and column.
pub fn read_json<T: DeserializeOwned>(path: &Path) -> Result<T, FileError> {
    let bytes = std::fs::read(path).map_err(|e| FileError::io(path, "read", e))?;
    serde_json::from_slice(&bytes).map_err(|source| FileError::JsonRead {
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn tidy_decimal_recovers_typed_settings_and_moves_others_by_under_5e15() {
        // A scene's `exposure_ms = 0.015` is held as seconds and written back as ms.
        assert_eq!(0.015_f64 * 1e-3 * 1e3, 0.015000000000000001);
        assert_eq!(tidy_decimal(0.015_f64 * 1e-3 * 1e3), 0.015);
        assert_eq!(tidy_decimal(45f64.to_radians().to_degrees()), 45.0);
        assert_eq!(tidy_decimal(257.5e-3 * 1e3), 257.5);
        for x in [
            1.0 / 3.0,
            std::f64::consts::PI,
            1e-300,
            -2.5e17,
            123.456_789_012_345_67,
        ] {
            let t = tidy_decimal(x);
            assert!(((t - x) / x).abs() <= 5e-15, "{x} → {t}");
        }
        assert_eq!(tidy_decimal(0.0), 0.0);
        assert!(tidy_decimal(f64::NAN).is_nan());
    }

    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Manifest {
        name: String,
        seed: u64,
        exposure_s: f64,
        poses: Vec<[f64; 3]>,
        missing: Option<f64>,
        counts: BTreeMap<String, u32>,
    }

    fn manifest() -> Manifest {
        Manifest {
            name: "pane \"A\" — λ = 658 nm".to_string(),
            seed: u64::MAX,
            exposure_s: 1.0 / 3.0,
            // 90.08966719419209 and 365.87992443022756 read back one ulp off unless serde_json
            // has its `float_roundtrip` feature (its default float parser is not exact).
            poses: vec![
                [0.1, -0.0, 5e-324],
                [1e300, -2.5, std::f64::consts::PI],
                [90.089_667_194_192_09, 365.879_924_430_227_56, -1e-75],
            ],
            missing: None,
            counts: BTreeMap::from([("tir".to_string(), 3), ("direct".to_string(), 12)]),
        }
    }

    #[test]
    fn round_trip_is_exact() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("manifest.json");
        let value = manifest();
        write_json_pretty(&path, &value).unwrap();
        let read: Manifest = read_json(&path).unwrap();
        let bits = |m: &Manifest| {
            let mut b = vec![m.exposure_s.to_bits()];
            b.extend(m.poses.iter().flatten().map(|v| v.to_bits()));
            b
        };
        assert_eq!(
            bits(&read),
            bits(&value),
            "f64 values changed on the way through JSON: Cargo.toml must enable serde_json's \
             `float_roundtrip` feature"
        );
        assert_eq!(read, value);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.starts_with("{\n  \"name\"") && text.ends_with("}\n"),
            "{text}"
        );
    }

    #[test]
    fn wrong_shape_names_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("manifest.json");
        std::fs::write(&path, "{\n  \"name\": 3\n}\n").unwrap();
        let err = read_json::<Manifest>(&path).unwrap_err();
        assert!(matches!(err, FileError::JsonRead { .. }), "{err}");
        let message = err.to_string();
        assert!(
            message.contains("manifest.json") && message.contains("line 2"),
            "{message}"
        );
    }

    #[test]
    fn unserialisable_value_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.json");
        // JSON object keys must be strings; a tuple key cannot be serialised.
        let value = BTreeMap::from([((1, 2), 3)]);
        let err = write_json_pretty(&path, &value).unwrap_err();
        assert!(matches!(err, FileError::JsonWrite { .. }), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
