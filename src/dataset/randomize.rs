//! Domain randomisation: the ranges of a `--randomize` TOML file, and the per-sample draws.
//!
//! The file holds `name = [min, max]` lines, one per randomised parameter ([`Param`]); a
//! parameter that is absent keeps the scene's value. Draws are uniform in [min, max) and are a
//! pure function of (master seed, sample index): sample i reads dimension `Param::dim` of
//! `PoseSampler::new(seed, STREAM ^ i)`, so a sample is the same whichever shard, thread or
//! resumed run makes it, and adding a key to a file does not change the other keys' draws.
//!
//! Every error names the file, the line and column of the key, the key and what was expected.
//! Whether the scene can take a range is checked by loading the scene at both ends of it
//! (`scene_edit::SceneTemplate::check_range`), so the limits are exactly the scene loader's.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_spanned::Spanned;

use super::DatasetError;
use crate::sampler::PoseSampler;

/// Stream of the per-sample draws, apart from the transport's (the pose index) and the
/// speckle's and the sensor noise's streams.
const STREAM: u64 = 0xda7a_5e70_0000_0000;
/// Sampler dimension of the scan position along the border (always drawn).
const DIM_BORDER: u32 = 0;
/// Sampler dimension of the noise seed (always drawn; used when `noise_seed` has no range).
const DIM_NOISE_SEED: u32 = 1;
/// Largest noise seed: 2^53, the integers a uniform in [0, 1) resolves exactly.
pub const MAX_NOISE_SEED: u64 = 1 << 53;

/// A randomised parameter. The key in the file is [`Param::key`]; units are in the key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Param {
    /// Scan angle α above the surface's tangent plane (deg), `[scan] scan_angle_deg`.
    ScanAngleDeg,
    /// Exposure time (ms), `[sensor] exposure_ms`.
    ExposureMs,
    /// Thickness of the target panel (mm), its `panel.thickness_mm`.
    GlassThicknessMm,
    /// Refractive index of the target's glass at the laser wavelength (replaces a dispersion
    /// law by a plain `ior`).
    RefractiveIndex,
    /// Microfacet roughness α of the target's ground edge.
    EdgeRoughness,
    /// Diffusely scattered fraction of the target's faces.
    FaceImperfection,
    /// Extra distance (mm) by which the objects labelled `table` or `background` are moved
    /// down (−z of the base frame), away from the glass resting above them.
    BackgroundDistanceMm,
    /// Albedo of the objects labelled `table` or `background` (they get a material of their own).
    BackgroundAlbedo,
    /// Shift of the target along x of the base frame (mm), in the table plane.
    PoseJitterXMm,
    /// Shift of the target along y of the base frame (mm), in the table plane.
    PoseJitterYMm,
    /// Rotation of the target about the vertical through its origin (deg).
    PoseJitterRzDeg,
    /// Seed of the sample's light transport, speckle and sensor noise (an integer).
    NoiseSeed,
    /// Face width (mm) of both arrisses of the target panel's seamed edge (0 = a sharp
    /// corner), keeping their angle.
    ArrisWidthMm,
}

impl Param {
    /// Every parameter, in file-documentation order.
    /// New parameters go at the end: a parameter's sampler dimension is its place here.
    pub const ALL: [Param; 13] = [
        Param::ScanAngleDeg,
        Param::ExposureMs,
        Param::GlassThicknessMm,
        Param::RefractiveIndex,
        Param::EdgeRoughness,
        Param::FaceImperfection,
        Param::BackgroundDistanceMm,
        Param::BackgroundAlbedo,
        Param::PoseJitterXMm,
        Param::PoseJitterYMm,
        Param::PoseJitterRzDeg,
        Param::NoiseSeed,
        Param::ArrisWidthMm,
    ];

    /// The key in the randomisation file, in the manifest and in the ground truth.
    pub fn key(self) -> &'static str {
        match self {
            Param::ScanAngleDeg => "scan_angle_deg",
            Param::ExposureMs => "exposure_ms",
            Param::GlassThicknessMm => "glass_thickness_mm",
            Param::RefractiveIndex => "refractive_index",
            Param::EdgeRoughness => "edge_roughness",
            Param::FaceImperfection => "face_imperfection",
            Param::BackgroundDistanceMm => "background_distance_mm",
            Param::BackgroundAlbedo => "background_albedo",
            Param::PoseJitterXMm => "pose_jitter_x_mm",
            Param::PoseJitterYMm => "pose_jitter_y_mm",
            Param::PoseJitterRzDeg => "pose_jitter_rz_deg",
            Param::NoiseSeed => "noise_seed",
            Param::ArrisWidthMm => "arris_width_mm",
        }
    }

    /// The sampler dimension of this parameter's draw: fixed per parameter (dimensions 0 and 1
    /// are the border position and the default noise seed).
    fn dim(self) -> u32 {
        2 + Param::ALL
            .iter()
            .position(|&p| p == self)
            .expect("ALL lists every parameter") as u32
    }

    fn from_key(key: &str) -> Option<Param> {
        Param::ALL.into_iter().find(|p| p.key() == key)
    }
}

/// A declared range `[min, max]` with where it is in the file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Lower end.
    pub min: f64,
    /// Upper end (≥ min).
    pub max: f64,
    /// 1-based line of the key.
    pub line: usize,
    /// 1-based column of the key.
    pub column: usize,
}

/// The parsed randomisation file.
#[derive(Clone, Debug)]
pub struct Randomization {
    /// The file as given.
    pub path: PathBuf,
    /// Its text (recorded in the dataset's run file, so the dataset says how it was made).
    pub text: String,
    /// The declared ranges.
    pub ranges: BTreeMap<Param, Range>,
}

/// The draws of one sample.
#[derive(Clone, Debug, PartialEq)]
pub struct Draw {
    /// Where along the target's border the scan pose sits, as a fraction of its length in [0, 1).
    pub border_fraction: f64,
    /// Seed of the sample's transport, speckle and sensor noise.
    pub noise_seed: u64,
    /// The randomised scene parameters, in [`Param`] order (without `noise_seed`).
    pub values: Vec<(Param, f64)>,
}

impl Draw {
    /// The drawn value of `p`, if it was randomised.
    pub fn get(&self, p: Param) -> Option<f64> {
        self.values.iter().find(|(q, _)| *q == p).map(|(_, v)| *v)
    }
}

impl Randomization {
    /// Reads and parses a randomisation file. Scene-independent checks only: known keys,
    /// `[min, max]` of finite numbers with min ≤ max, integers for `noise_seed`, ≥ 0 for the
    /// background distance. The scene's own limits are checked by
    /// `scene_edit::SceneTemplate::check_randomization`.
    pub fn load(path: &Path) -> Result<Randomization, DatasetError> {
        let text =
            crate::shipped::read_to_string(path).map_err(|e| DatasetError::io(path, "read", e))?;
        Randomization::parse(path, text)
    }

    /// Parses the text of a randomisation file named `path` (for messages).
    pub fn parse(path: &Path, text: String) -> Result<Randomization, DatasetError> {
        let at = |offset: usize| line_column(&text, offset);
        let error = |offset: usize, key: &str, message: String| {
            let (line, column) = at(offset);
            DatasetError::Randomize {
                path: path.to_path_buf(),
                line,
                column,
                key: key.to_owned(),
                message,
            }
        };
        let entries: BTreeMap<Spanned<String>, Spanned<toml::Value>> = toml::from_str(&text)
            .map_err(|e| {
                error(
                    e.span().map_or(0, |s| s.start),
                    "(file)",
                    format!(
                        "expected `name = [min, max]` lines: {}",
                        e.message().trim().replace('\n', ", ")
                    ),
                )
            })?;
        let mut ranges = BTreeMap::new();
        for (key, value) in &entries {
            let offset = key.span().start;
            let name = key.get_ref();
            let Some(param) = Param::from_key(name) else {
                let known: Vec<&str> = Param::ALL.iter().map(|p| p.key()).collect();
                return Err(error(
                    offset,
                    name,
                    format!("unknown key, expected one of {}", known.join(", ")),
                ));
            };
            let bad = |what: String| error(offset, name, what);
            let numbers: Option<Vec<f64>> = match value.get_ref() {
                toml::Value::Array(items) => items
                    .iter()
                    .map(|v| match v {
                        toml::Value::Integer(i) => Some(*i as f64),
                        toml::Value::Float(f) => Some(*f),
                        _ => None,
                    })
                    .collect(),
                _ => None,
            };
            let [min, max] = match numbers.as_deref() {
                Some(&[a, b]) => [a, b],
                _ => {
                    return Err(bad(format!(
                        "expected [min, max] (two numbers), got {}",
                        value.get_ref()
                    )))
                }
            };
            if !(min.is_finite() && max.is_finite()) {
                return Err(bad(format!("expected finite numbers, got [{min}, {max}]")));
            }
            if min > max {
                return Err(bad(format!("expected min ≤ max, got [{min}, {max}]")));
            }
            match param {
                Param::NoiseSeed => {
                    let ok =
                        |v: f64| v.fract() == 0.0 && (0.0..=MAX_NOISE_SEED as f64).contains(&v);
                    if !(ok(min) && ok(max)) {
                        return Err(bad(format!(
                            "expected integers in [0, 2^53], got [{min}, {max}]"
                        )));
                    }
                }
                Param::BackgroundDistanceMm if min < 0.0 => {
                    return Err(bad(format!(
                        "expected min ≥ 0 (a negative distance would push the table into the \
                         glass), got [{min}, {max}]"
                    )));
                }
                _ => {}
            }
            let (line, column) = at(offset);
            ranges.insert(
                param,
                Range {
                    min,
                    max,
                    line,
                    column,
                },
            );
        }
        Ok(Randomization {
            path: path.to_path_buf(),
            text,
            ranges,
        })
    }

    /// The error for `param`'s range, at its key.
    pub fn error(&self, param: Param, message: String) -> DatasetError {
        let r = self.ranges.get(&param);
        DatasetError::Randomize {
            path: self.path.clone(),
            line: r.map_or(1, |r| r.line),
            column: r.map_or(1, |r| r.column),
            key: param.key().to_owned(),
            message,
        }
    }
}

/// The draws of sample `i` under the master `seed`; `randomization` `None` draws only the
/// border position and the noise seed.
pub fn draw(randomization: Option<&Randomization>, seed: u64, i: u64) -> Draw {
    let sampler = PoseSampler::new(seed, STREAM ^ i);
    let u = |dim: u32| sampler.uniform(0, dim);
    let ranges = randomization.map(|r| &r.ranges);
    let noise_seed = match ranges.and_then(|r| r.get(&Param::NoiseSeed)) {
        Some(r) => {
            let (lo, hi) = (r.min as u64, r.max as u64);
            (lo + (u(Param::NoiseSeed.dim()) * (hi - lo + 1) as f64) as u64).min(hi)
        }
        None => (u(DIM_NOISE_SEED) * MAX_NOISE_SEED as f64) as u64,
    };
    let values = ranges
        .into_iter()
        .flatten()
        .filter(|(p, _)| **p != Param::NoiseSeed)
        .map(|(&p, r)| (p, r.min + (r.max - r.min) * u(p.dim())))
        .collect();
    Draw {
        border_fraction: u(DIM_BORDER),
        noise_seed,
        values,
    }
}

/// 1-based line and column (in characters) of a byte offset of `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (
        before.matches('\n').count() + 1,
        before[line_start..].chars().count() + 1,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Randomization, DatasetError> {
        Randomization::parse(Path::new("r.toml"), text.to_owned())
    }

    #[test]
    fn ranges_parse_with_their_location() {
        let r = parse("# comment\nscan_angle_deg = [10, 60]\nrefractive_index = [1.51, 1.53]\n")
            .unwrap();
        assert_eq!(r.ranges.len(), 2);
        let a = r.ranges[&Param::ScanAngleDeg];
        assert_eq!((a.min, a.max, a.line, a.column), (10.0, 60.0, 2, 1));
        assert_eq!(r.ranges[&Param::RefractiveIndex].line, 3);
        assert!(parse("").unwrap().ranges.is_empty());
    }

    #[test]
    fn every_parameter_has_a_distinct_key_and_dimension() {
        let mut keys: Vec<_> = Param::ALL.iter().map(|p| p.key()).collect();
        let mut dims: Vec<_> = Param::ALL.iter().map(|p| p.dim()).collect();
        keys.sort();
        keys.dedup();
        dims.sort();
        dims.dedup();
        assert_eq!(keys.len(), Param::ALL.len());
        assert_eq!(dims.len(), Param::ALL.len());
        assert!(dims.iter().all(|&d| d != DIM_BORDER && d != DIM_NOISE_SEED));
        for p in Param::ALL {
            assert_eq!(Param::from_key(p.key()), Some(p));
        }
    }

    #[test]
    fn bad_files_name_file_line_key_and_expectation() {
        for (text, expected) in [
            (
                "scan_angle_deg = [10, 60]\nthicknes_mm = [3, 5]\n",
                "r.toml:2:1: thicknes_mm: unknown key, expected one of scan_angle_deg",
            ),
            (
                "exposure_ms = [2, 1]\n",
                "r.toml:1:1: exposure_ms: expected min ≤ max, got [2, 1]",
            ),
            (
                "exposure_ms = [1]\n",
                "r.toml:1:1: exposure_ms: expected [min, max] (two numbers), got [1]",
            ),
            (
                "exposure_ms = 1\n",
                "exposure_ms: expected [min, max] (two numbers), got 1",
            ),
            (
                "exposure_ms = [1, \"2\"]\n",
                "exposure_ms: expected [min, max]",
            ),
            (
                "exposure_ms = [1, nan]\n",
                "exposure_ms: expected finite numbers",
            ),
            (
                "exposure_ms = [-inf, 1]\n",
                "exposure_ms: expected finite numbers",
            ),
            (
                "noise_seed = [1.5, 3]\n",
                "noise_seed: expected integers in [0, 2^53]",
            ),
            (
                "noise_seed = [-1, 3]\n",
                "noise_seed: expected integers in [0, 2^53]",
            ),
            (
                "background_distance_mm = [-5, 3]\n",
                "background_distance_mm: expected min ≥ 0",
            ),
            (
                "[scan]\nscan_angle_deg = [1, 2]\n",
                "r.toml:1:2: scan: unknown key",
            ),
            (
                "scan_angle_deg = [1, 2\n",
                "(file): expected `name = [min, max]` lines",
            ),
        ] {
            let message = parse(text).unwrap_err().to_string();
            assert!(message.contains(expected), "{text:?}: {message}");
            assert!(message.starts_with("r.toml:"), "{message}");
        }
    }

    #[test]
    fn draws_depend_on_seed_and_index_only_and_stay_in_range() {
        let r = parse(
            "scan_angle_deg = [10, 60]\nexposure_ms = [0.5, 0.5]\nnoise_seed = [3, 5]\n\
             pose_jitter_x_mm = [-2, 2]\n",
        )
        .unwrap();
        let mut seeds = std::collections::BTreeSet::new();
        let mut angles = Vec::new();
        for i in 0..200 {
            let d = draw(Some(&r), 7, i);
            assert_eq!(d, draw(Some(&r), 7, i));
            assert!((0.0..1.0).contains(&d.border_fraction));
            let a = d.get(Param::ScanAngleDeg).unwrap();
            assert!((10.0..60.0).contains(&a));
            assert_eq!(d.get(Param::ExposureMs), Some(0.5));
            assert!((-2.0..2.0).contains(&d.get(Param::PoseJitterXMm).unwrap()));
            assert_eq!(d.get(Param::NoiseSeed), None);
            assert!((3..=5).contains(&d.noise_seed));
            seeds.insert(d.noise_seed);
            angles.push(a);
        }
        assert_eq!(seeds.len(), 3, "every integer of the range is drawn");
        let mean = angles.iter().sum::<f64>() / angles.len() as f64;
        // Uniform on [10, 60]: mean 35, σ of the mean 14.4/√200 ≈ 1.0.
        assert!((mean - 35.0).abs() < 4.0, "mean {mean}");
        assert_ne!(draw(Some(&r), 8, 0), draw(Some(&r), 7, 0));
        // Adding a key does not move the other keys' draws.
        let more = parse(
            "scan_angle_deg = [10, 60]\nexposure_ms = [0.5, 0.5]\nnoise_seed = [3, 5]\n\
             pose_jitter_x_mm = [-2, 2]\nedge_roughness = [0.1, 0.5]\n",
        )
        .unwrap();
        let (a, b) = (draw(Some(&r), 7, 3), draw(Some(&more), 7, 3));
        assert_eq!(a.get(Param::ScanAngleDeg), b.get(Param::ScanAngleDeg));
        assert_eq!(a.border_fraction, b.border_fraction);
    }

    #[test]
    fn without_ranges_only_position_and_noise_seed_vary() {
        let a = draw(None, 1, 0);
        let b = draw(None, 1, 1);
        assert!(a.values.is_empty());
        assert_ne!(a.noise_seed, b.noise_seed);
        assert_ne!(a.border_fraction, b.border_fraction);
        assert!(a.noise_seed < MAX_NOISE_SEED);
    }
}
