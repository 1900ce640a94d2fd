//! The profile firmware: per reported column, the peaks above a threshold, the peak filter, the
//! selection of a peak (or of all of them), their sub-pixel centroids, and the triangulation to
//! (x, z) in the laser plane.
//!
//! The model follows what the scanCONTROL SDK exposes (docs/parameters.md §1a, §1b, §1d):
//!
//! - Up to 4 peaks ("reflections") per column; each carries its width, maximum intensity and the
//!   threshold it was found with (three 10-bit words in the SDK, §1b), and its moments M0 = Σ I
//!   and M1 = Σ I·row, whose ratio is the centroid (§1b).
//! - The threshold is a fixed value 0…1023 (driver default 128) or "automatic" (§1a; the rule
//!   of [`Threshold::Automatic`] is a modelling choice, the SDK only has the flag).
//! - The peak filter rejects peaks whose width or intensity is out of range (§1a).
//! - The selection modes ALL, FIRST, LAST, LARGEST_AREA, MAX_INTENSITY, SINGLE (§1a, §1d).
//! - 80…640 points per profile on a 26xx (§1a): fewer points than columns decimate the columns.
//!
//! Units: rows and columns in pixels (pixel centres at integer + 0.5), intensities in DN of the
//! digital image, x and z in mm. With the 26xx's 10-bit imager the width, intensity and
//! threshold fit the SDK's 10-bit words (§1a); with a deeper ADC set in a scene file they hold
//! the image's full DN (the real firmware has no such case).
//!
//! Submodules: `peaks` (one column's runs, moments, automatic threshold, labels), `select`
//! (the selection modes).

mod peaks;
mod select;

pub use peaks::{AUTO_THRESHOLD_K, AUTO_THRESHOLD_MIN_MARGIN_DN, CENTROID_MARGIN_PX};
pub use select::{PeakSelect, UnknownPeakSelect};

use super::camera::Camera;
use super::image::Image;
use crate::sensor::path_class::PathClass;
use peaks::Peak;

/// One point of a profile: one peak of one reported column (or an invalid point for a column
/// without a selected peak).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ProfilePoint {
    /// Sensor column the point comes from.
    pub column: usize,
    /// Slot of the peak among the column's peaks that passed the filter, 0…3 from the top of
    /// the image (the near end of the range); 0 for an invalid point.
    pub reflection: u8,
    /// Sub-pixel row of the peak centroid M1/M0 (pixel centres at integer + 0.5), NaN if invalid.
    pub row: f64,
    /// Position along the laser line (mm), NaN if invalid.
    pub x_mm: f64,
    /// Range (mm), NaN if invalid.
    pub z_mm: f64,
    /// Maximum intensity of the peak (DN), 0 if invalid.
    pub intensity: u16,
    /// Peak width: number of pixels above the threshold (px), 0 if invalid.
    pub width: u32,
    /// Threshold the column was evaluated with (DN); set for invalid points too.
    pub threshold: u16,
    /// Zeroth moment M0 = Σ I over the centroid window (DN), 0 if invalid.
    pub m0: f64,
    /// First moment M1 = Σ I·(r + 0.5) over the centroid window (DN·px), 0 if invalid.
    pub m1: f64,
    /// The path class that put the most irradiance into the peak's window; `None` when no
    /// per-class images were given, or for an invalid point.
    pub label: Option<PathClass>,
    /// Whether the point holds a measurement.
    pub valid: bool,
    /// Whether the peak reaches the ADC's full scale: a clipped peak, whose centroid is that
    /// of its flat top rather than of the light, and whose intensity says nothing of how
    /// bright the light was. False for an invalid point.
    pub saturated: bool,
}

impl ProfilePoint {
    /// A point without a measurement.
    fn invalid(column: usize, reflection: u8, threshold: u16) -> ProfilePoint {
        ProfilePoint {
            column,
            reflection,
            row: f64::NAN,
            x_mm: f64::NAN,
            z_mm: f64::NAN,
            intensity: 0,
            width: 0,
            threshold,
            m0: 0.0,
            m1: 0.0,
            label: None,
            valid: false,
            saturated: false,
        }
    }
}

/// A line profile, column-major: reported columns in order, and within a column the selected
/// peaks by reflection index. Every reported column has at least one point (an invalid one if
/// nothing was selected); only [`PeakSelect::All`] gives a column more than one.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Profile {
    /// The points.
    pub points: Vec<ProfilePoint>,
}

/// Peak slots per column in the SDK's PROFILE format (docs/parameters.md §1a, §1b).
pub const MAX_PEAKS: usize = 4;

/// Largest value of the SDK's 10-bit words: width, maximum intensity, threshold, and the peak
/// filter's limits (docs/parameters.md §1a, libmescan.c `calc_max_intensity` etc.).
pub const FIELD_MAX: u16 = 1023;

/// Threshold of the iirob scanCONTROL driver's configuration (docs/parameters.md §1a, H).
pub const DRIVER_DEFAULT_THRESHOLD_DN: u16 = 128;

/// Points per profile on a 26xx: 80…640 in steps of 80 (libmescan.c `check_resolution`,
/// docs/parameters.md §1a).
pub const POINTS_PER_PROFILE_26XX: std::ops::RangeInclusive<usize> = 80..=640;

/// Step of [`POINTS_PER_PROFILE_26XX`].
pub const POINTS_PER_PROFILE_STEP_26XX: usize = 80;

/// How the threshold of a column is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Threshold {
    /// A fixed threshold (DN): pixels at or below it are background. 0…1023 on the sensor
    /// (docs/parameters.md §1a).
    Fixed(u16),
    /// A threshold from the column's own background: median + max(k·σ̂, margin), with
    /// σ̂ = 1.4826·MAD (the median absolute deviation, scaled to the standard deviation of
    /// Gaussian noise; Rousseeuw & Croux, JASA 88 (1993) 1273), k = [`AUTO_THRESHOLD_K`] and
    /// margin = [`AUTO_THRESHOLD_MIN_MARGIN_DN`].
    ///
    /// The SDK only has a THRESHOLD_AUTOMATIC ("dynamic") flag, bit 24 of the processing
    /// register (docs/parameters.md §1a); Micro-Epsilon does not publish the rule, so this one is a
    /// modelling choice: it follows the background and its noise, so a faint line on a dark,
    /// quiet background is found, and the laser line (a few rows of hundreds) does not move
    /// the median.
    Automatic,
}

/// Settings of the profile firmware.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct FirmwareSettings {
    /// How each column's threshold is chosen.
    pub threshold: Threshold,
    /// Which peak of a column is reported (or all of them).
    pub peak_select: PeakSelect,
    /// Peak filter: accepted widths, min and max inclusive (px above threshold). Driver default
    /// 2…1023 (docs/parameters.md §1a).
    pub width_range_px: (u32, u32),
    /// Peak filter: accepted maximum intensities, min and max inclusive (DN). Default 0…1023.
    pub intensity_range_dn: (u16, u16),
    /// Points per profile: 80…640 in steps of 80 on a 26xx; must divide the image columns.
    pub points_per_profile: usize,
    /// Peaks kept per column, 1…4 (the SDK carries 4 slots).
    pub max_peaks: usize,
}

/// Why firmware settings are not possible on the sensor. Each variant names its field.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum FirmwareSettingsError {
    /// Points per profile outside the 26xx's set or not a divisor of the columns.
    #[error(
        "points_per_profile must be 80…640 in steps of 80 (scanCONTROL 26xx) and divide the \
         camera's {columns} columns, got {points}"
    )]
    PointsPerProfile {
        /// The value given.
        points: usize,
        /// Camera columns.
        columns: usize,
    },
    /// `max_peaks` outside 1…4.
    #[error("max_peaks must be 1…4 (the SDK carries 4 peaks per point), got {0}")]
    MaxPeaks(usize),
    /// A fixed threshold above the ADC's largest value.
    #[error("threshold must be ≤ {max_dn} DN (2^adc_bits − 1), got {threshold}")]
    Threshold {
        /// The value given (DN).
        threshold: u16,
        /// The ADC's largest value (DN).
        max_dn: u16,
    },
    /// A width range that is empty or exceeds the 10-bit field.
    #[error("width_range_px must satisfy min ≤ max ≤ 1023, got {min}…{max}")]
    WidthRange {
        /// Lower limit (px).
        min: u32,
        /// Upper limit (px).
        max: u32,
    },
    /// An intensity range that is empty or exceeds the ADC's largest value.
    #[error("intensity_range_dn must satisfy min ≤ max ≤ {max_dn} DN, got {min}…{max}")]
    IntensityRange {
        /// Lower limit (DN).
        min: u16,
        /// Upper limit (DN).
        max: u16,
        /// The ADC's largest value (DN).
        max_dn: u16,
    },
}

impl FirmwareSettingsError {
    /// The name of the offending field of [`FirmwareSettings`].
    pub fn field(&self) -> &'static str {
        match self {
            FirmwareSettingsError::PointsPerProfile { .. } => "points_per_profile",
            FirmwareSettingsError::MaxPeaks(_) => "max_peaks",
            FirmwareSettingsError::Threshold { .. } => "threshold",
            FirmwareSettingsError::WidthRange { .. } => "width_range_px",
            FirmwareSettingsError::IntensityRange { .. } => "intensity_range_dn",
        }
    }
}

impl FirmwareSettings {
    /// The scanCONTROL driver's defaults (iirob `cfg/ScanControl.cfg`, docs/parameters.md §1a, §1d):
    /// FIRST peak, peak filter width 2…1023 and intensity 0…1023, 640 points, 4 peak slots,
    /// with a fixed threshold of `threshold_dn` (the driver's is
    /// [`DRIVER_DEFAULT_THRESHOLD_DN`] = 128).
    pub const fn scancontrol_default(threshold_dn: u16) -> FirmwareSettings {
        FirmwareSettings {
            threshold: Threshold::Fixed(threshold_dn),
            peak_select: PeakSelect::First,
            width_range_px: (2, FIELD_MAX as u32),
            intensity_range_dn: (0, FIELD_MAX),
            points_per_profile: 640,
            max_peaks: MAX_PEAKS,
        }
    }

    /// Checks the settings against what a 26xx accepts, for a camera of `columns` columns and
    /// an ADC whose largest value is `max_dn`.
    pub fn check(&self, columns: usize, max_dn: u16) -> Result<(), FirmwareSettingsError> {
        let points = self.points_per_profile;
        if !POINTS_PER_PROFILE_26XX.contains(&points)
            || points % POINTS_PER_PROFILE_STEP_26XX != 0
            || columns % points != 0
        {
            return Err(FirmwareSettingsError::PointsPerProfile { points, columns });
        }
        if !(1..=MAX_PEAKS).contains(&self.max_peaks) {
            return Err(FirmwareSettingsError::MaxPeaks(self.max_peaks));
        }
        if let Threshold::Fixed(threshold) = self.threshold {
            if threshold > max_dn {
                return Err(FirmwareSettingsError::Threshold { threshold, max_dn });
            }
        }
        let (min, max) = self.width_range_px;
        if min > max || max > FIELD_MAX as u32 {
            return Err(FirmwareSettingsError::WidthRange { min, max });
        }
        let (min, max) = self.intensity_range_dn;
        if min > max || max > max_dn {
            return Err(FirmwareSettingsError::IntensityRange { min, max, max_dn });
        }
        Ok(())
    }

    /// Whether `peak` passes the peak filter.
    fn accepts(&self, peak: &Peak) -> bool {
        let (w_min, w_max) = self.width_range_px;
        let (i_min, i_max) = self.intensity_range_dn;
        (w_min..=w_max).contains(&peak.width_px()) && (i_min..=i_max).contains(&peak.max_dn)
    }
}

/// Extracts the profile of a digital image.
///
/// Reported columns: with k = columns / `points_per_profile`, point i comes from column
/// i·k + k/2, the middle of its group of k. This is the SDK's decimation of the camera columns
/// to 80…640 points (docs/parameters.md §1a, "Points per profile").
///
/// Per reported column:
/// 1. the threshold (fixed, or [`Threshold::Automatic`]);
/// 2. every run of pixels above it, with M0 and M1 over the run widened by
///    [`CENTROID_MARGIN_PX`] on each side (never into a neighbouring run);
/// 3. the peak filter (width and intensity ranges). Of the peaks that pass, the first
///    `max_peaks` from the top are kept: the SDK carries 4 slots (§1a). Filtering before
///    counting is a modelling choice: a filter meant to reject speckle and noise spikes would
///    be useless if those could take the slots first;
/// 4. the selection ([`PeakSelect`]), then the centroid row M1/M0 and the triangulation
///    `camera.pixel_to_laser_plane(column + 0.5, row)`.
///
/// `classes`, if given, holds one irradiance image per path class in [`PathClass::ALL`] order,
/// of the image's size; each point is labelled with the class of largest irradiance summed over
/// its peak's window, or `SensorNoise` when no traced light reached it.
///
/// `full_scale_dn` is the ADC's largest value (2^adc_bits − 1): a point whose peak reaches it is
/// flagged `saturated`.
///
/// Panics if `points_per_profile` is 0 or does not divide the columns, if `max_peaks` is not
/// 1…4, or if `classes` does not match (cheap preconditions: [`FirmwareSettings::check`] and the
/// transport guarantee them).
pub fn extract(
    image: &Image<u16>,
    full_scale_dn: u16,
    classes: Option<&[Image<f64>]>,
    camera: &Camera,
    settings: &FirmwareSettings,
) -> Profile {
    let n_points = settings.points_per_profile;
    assert!(
        n_points > 0 && image.width % n_points == 0,
        "points_per_profile = {n_points} must divide the {} columns",
        image.width
    );
    assert!(
        (1..=MAX_PEAKS).contains(&settings.max_peaks),
        "max_peaks = {} must be 1…{MAX_PEAKS}",
        settings.max_peaks
    );
    if let Some(classes) = classes {
        assert_eq!(
            classes.len(),
            PathClass::ALL.len(),
            "one image per path class"
        );
        assert!(
            classes
                .iter()
                .all(|c| c.width == image.width && c.height == image.height),
            "class images must have the digital image's size"
        );
    }
    let step = image.width / n_points;
    let mut points = Vec::with_capacity(n_points);
    let mut dn = vec![0u16; image.height];
    for i in 0..n_points {
        let column = i * step + step / 2;
        for (row, v) in dn.iter_mut().enumerate() {
            *v = image.get(column, row);
        }
        let threshold = peaks::column_threshold(&dn, settings.threshold);
        let found: Vec<Peak> = peaks::column_peaks(&dn, threshold)
            .into_iter()
            .filter(|p| settings.accepts(p))
            .take(settings.max_peaks)
            .collect();
        let chosen = settings.peak_select.select(&found);
        if chosen.is_empty() {
            points.push(ProfilePoint::invalid(column, 0, threshold));
        }
        for slot in chosen {
            let peak = &found[slot];
            let label = classes.map(|c| peaks::label(c, column, peak.window));
            let mut point = locate(camera, column, slot as u8, threshold, peak, label);
            point.saturated = point.valid && peak.max_dn >= full_scale_dn;
            points.push(point);
        }
    }
    Profile { points }
}

/// The point of `peak`: its centroid row and its triangulation.
fn locate(
    camera: &Camera,
    column: usize,
    reflection: u8,
    threshold: u16,
    peak: &Peak,
    label: Option<PathClass>,
) -> ProfilePoint {
    let row = peak.centroid_row();
    match camera.pixel_to_laser_plane(column as f64 + 0.5, row) {
        Some((x, z)) => ProfilePoint {
            column,
            reflection,
            row,
            x_mm: x * 1e3,
            z_mm: z * 1e3,
            intensity: peak.max_dn,
            width: peak.width_px(),
            threshold,
            m0: peak.m0,
            m1: peak.m1,
            label,
            valid: true,
            saturated: false,
        },
        None => ProfilePoint::invalid(column, reflection, threshold),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::preset::scancontrol_2600_100;

    /// The 10-bit ADC of the synthetic images below.
    const FULL_SCALE_DN: u16 = 1023;

    fn camera() -> Camera {
        let s = scancontrol_2600_100();
        Camera::new(&s.camera, &s.range).unwrap()
    }

    /// A 640 × 832 image holding, in every column, the given Gaussian lines (centre row, σ,
    /// amplitude in DN), box-integrated over each pixel with 64 sub-samples and rounded.
    fn lines(spec: &[(f64, f64, f64)]) -> Image<u16> {
        let (width, height) = (640, 832);
        let mut img = Image::new(width, height);
        for r in 0..height {
            let v: f64 = spec
                .iter()
                .map(|&(centre, sigma, peak)| {
                    peak * (0..64)
                        .map(|k| {
                            let y = r as f64 + (k as f64 + 0.5) / 64.0;
                            (-0.5 * ((y - centre) / sigma).powi(2)).exp()
                        })
                        .sum::<f64>()
                        / 64.0
                })
                .sum();
            img.data[r * width..(r + 1) * width].fill(v.round().min(1023.0) as u16);
        }
        img
    }

    fn settings(peak_select: PeakSelect) -> FirmwareSettings {
        FirmwareSettings {
            peak_select,
            ..FirmwareSettings::scancontrol_default(DRIVER_DEFAULT_THRESHOLD_DN)
        }
    }

    #[test]
    fn centroid_of_a_synthetic_gaussian_line() {
        let cam = camera();
        for centre in [400.0, 400.25, 400.5, 400.8] {
            let img = lines(&[(centre, 1.5, 900.0)]);
            let prof = extract(
                &img,
                FULL_SCALE_DN,
                None,
                &cam,
                &settings(PeakSelect::First),
            );
            assert_eq!(prof.points.len(), 640);
            let p = prof.points[320];
            assert!(p.valid && p.column == 320 && p.threshold == 128);
            assert!(
                (p.row - centre).abs() < 0.02,
                "centre {centre}: row {}",
                p.row
            );
            assert_eq!(p.row, p.m1 / p.m0);
            let (x, z) = cam.pixel_to_laser_plane(320.5, p.row).unwrap();
            assert!((p.x_mm - x * 1e3).abs() < 1e-9 && (p.z_mm - z * 1e3).abs() < 1e-9);
        }
    }

    #[test]
    fn strongest_peak_wins_by_area_or_intensity_and_empty_columns_are_invalid() {
        let cam = camera();
        // Upper line: dimmer but wide (larger M0); lower line: brighter but narrow.
        let mut img = lines(&[(300.0, 3.0, 400.0), (600.0, 0.8, 900.0)]);
        for r in 0..832 {
            img.data[r * 640 + 7] = 0;
        }
        let area = extract(
            &img,
            FULL_SCALE_DN,
            None,
            &cam,
            &settings(PeakSelect::LargestArea),
        );
        let bright = extract(
            &img,
            FULL_SCALE_DN,
            None,
            &cam,
            &settings(PeakSelect::MaxIntensity),
        );
        assert!((area.points[100].row - 300.0).abs() < 0.05);
        assert_eq!(area.points[100].reflection, 0);
        assert!((bright.points[100].row - 600.0).abs() < 0.05);
        assert_eq!(bright.points[100].reflection, 1);
        let blank = area.points[7];
        assert!(!blank.valid && blank.z_mm.is_nan() && blank.threshold == 128);
    }

    #[test]
    fn a_peak_that_reaches_full_scale_is_flagged_saturated() {
        // Two lines: one clipped at the 10-bit full scale (1023 DN), one at 400 DN.
        let cam = camera();
        let img = lines(&[(300.0, 3.0, 2000.0), (600.0, 1.0, 400.0)]);
        let prof = extract(&img, FULL_SCALE_DN, None, &cam, &settings(PeakSelect::All));
        let column: Vec<_> = prof
            .points
            .iter()
            .filter(|p| p.column == prof.points[5].column)
            .collect();
        assert_eq!(column.len(), 2);
        assert!(column[0].valid && column[0].saturated && column[0].intensity == 1023);
        assert!(column[1].valid && !column[1].saturated && column[1].intensity < 1023);
        // With a 12-bit ADC the same image is not clipped.
        let wide = extract(&img, 4095, None, &cam, &settings(PeakSelect::All));
        assert!(wide.points.iter().all(|p| !p.saturated));
    }

    #[test]
    fn check_refuses_what_a_26xx_refuses() {
        let ok = FirmwareSettings::scancontrol_default(128);
        assert_eq!(ok.check(640, 1023), Ok(()));
        let bad = |s: FirmwareSettings| s.check(640, 1023).unwrap_err().field();
        for points in [0, 40, 100, 480, 720] {
            let s = FirmwareSettings {
                points_per_profile: points,
                ..ok
            };
            assert_eq!(bad(s), "points_per_profile", "{points}");
        }
        assert_eq!(
            FirmwareSettings { max_peaks: 5, ..ok }.check(640, 1023),
            Err(FirmwareSettingsError::MaxPeaks(5))
        );
        let s = FirmwareSettings {
            threshold: Threshold::Fixed(300),
            ..ok
        };
        assert_eq!(s.check(640, 1023), Ok(()));
        assert_eq!(s.check(640, 255).unwrap_err().field(), "threshold");
        let s = FirmwareSettings {
            width_range_px: (5, 4),
            ..ok
        };
        assert_eq!(bad(s), "width_range_px");
        let s = FirmwareSettings {
            intensity_range_dn: (0, 1024),
            ..ok
        };
        assert_eq!(bad(s), "intensity_range_dn");
        let message = FirmwareSettings {
            points_per_profile: 100,
            ..ok
        }
        .check(640, 1023)
        .unwrap_err()
        .to_string();
        assert_eq!(
            message,
            "points_per_profile must be 80…640 in steps of 80 (scanCONTROL 26xx) and divide \
             the camera's 640 columns, got 100"
        );
    }
}
