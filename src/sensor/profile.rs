//! Profile extraction, first version: per column, threshold, the sub-pixel centroid of the
//! strongest peak, triangulated to (x, z) in the laser plane.

/// One point of a profile (one per reported column).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ProfilePoint {
    /// Sensor column the point comes from.
    pub column: usize,
    /// Sub-pixel row of the peak centroid (pixel centres at integer + 0.5), NaN if invalid.
    pub row: f64,
    /// Position along the laser line (mm), NaN if invalid.
    pub x_mm: f64,
    /// Range (mm), NaN if invalid.
    pub z_mm: f64,
    /// Peak intensity (DN), 0 if invalid.
    pub intensity: u16,
    /// Peak width: number of pixels above threshold (px), 0 if invalid.
    pub width: u32,
    /// Whether the column had a peak above threshold.
    pub valid: bool,
}

/// A line profile: `points_per_profile` points, in column order.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Profile {
    /// The points, one per reported column.
    pub points: Vec<ProfilePoint>,
}

use super::camera::Camera;
use super::image::Image;

/// Settings of the first-version profile extraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtractSettings {
    /// Pixels at or below this value (DN) are background.
    pub threshold_dn: u16,
    /// Points per profile; must divide the number of columns. Column k·(columns/points) +
    /// (columns/points)/2 is reported for point k.
    pub points_per_profile: usize,
}

/// Pixels added on each side of an above-threshold run before taking its centroid.
///
/// A centre of gravity over the run alone cuts the line's tails at the threshold, which pulls
/// the estimate towards the nearest pixel centre ("pixel locking", up to ~0.05 px for a line of
/// σ ≈ 0.6 px). Over a window that holds the whole line, the centroid of a box-sampled Gaussian
/// is exact up to a periodic error of order exp(−2π²σ²) (~0.002 px at σ = 0.6 px).
const CENTROID_MARGIN_PX: usize = 2;

/// A run of contiguous above-threshold pixels in one column, with its centroid window.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Peak {
    first_row: usize,
    last_row: usize,
    max_dn: u16,
    /// Σ I over the window: the zeroth moment.
    m0: f64,
    /// Σ I·(r + 0.5) over the window: the first moment, pixel centres at r + 0.5.
    m1: f64,
}

/// All above-threshold runs of column `col`, top to bottom, with moments taken over each run
/// widened by [`CENTROID_MARGIN_PX`] (never into a neighbouring run).
fn column_peaks(image: &Image<u16>, col: usize, threshold: u16) -> Vec<Peak> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut start = None;
    for row in 0..image.height {
        match (image.get(col, row) > threshold, start) {
            (true, None) => start = Some(row),
            (false, Some(s)) => {
                runs.push((s, row - 1));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        runs.push((s, image.height - 1));
    }
    (0..runs.len())
        .map(|k| {
            let (first_row, last_row) = runs[k];
            let lo_limit = if k > 0 { runs[k - 1].1 + 1 } else { 0 };
            let hi_limit = runs.get(k + 1).map_or(image.height - 1, |r| r.0 - 1);
            let lo = first_row.saturating_sub(CENTROID_MARGIN_PX).max(lo_limit);
            let hi = (last_row + CENTROID_MARGIN_PX).min(hi_limit);
            let (mut m0, mut m1, mut max_dn) = (0.0, 0.0, 0);
            for row in lo..=hi {
                let v = image.get(col, row);
                max_dn = max_dn.max(v);
                m0 += v as f64;
                m1 += v as f64 * (row as f64 + 0.5);
            }
            Peak {
                first_row,
                last_row,
                max_dn,
                m0,
                m1,
            }
        })
        .collect()
}

/// Extracts the profile: per reported column, the strongest above-threshold run (largest
/// M0, ties to the upper one), its centre of gravity M1/M0 over the run's window, and its
/// triangulation through the camera's exact pixel → laser-plane map.
pub fn extract(image: &Image<u16>, camera: &Camera, settings: &ExtractSettings) -> Profile {
    let step = image.width / settings.points_per_profile.max(1);
    let points = (0..settings.points_per_profile)
        .map(|k| {
            let column = k * step + step / 2;
            let best = column_peaks(image, column, settings.threshold_dn)
                .into_iter()
                .fold(None::<Peak>, |best, p| match best {
                    Some(b) if b.m0 >= p.m0 => Some(b),
                    _ => Some(p),
                });
            let located = best.and_then(|p| {
                let row = p.m1 / p.m0;
                camera
                    .pixel_to_laser_plane(column as f64 + 0.5, row)
                    .map(|(x, z)| (p, row, x, z))
            });
            match located {
                Some((p, row, x, z)) => ProfilePoint {
                    column,
                    row,
                    x_mm: x * 1e3,
                    z_mm: z * 1e3,
                    intensity: p.max_dn,
                    width: (p.last_row - p.first_row + 1) as u32,
                    valid: true,
                },
                None => ProfilePoint {
                    column,
                    row: f64::NAN,
                    x_mm: f64::NAN,
                    z_mm: f64::NAN,
                    intensity: 0,
                    width: 0,
                    valid: false,
                },
            }
        })
        .collect();
    Profile { points }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::preset::scancontrol_2600_100;

    /// A synthetic column image with a Gaussian line centred at `centre` (continuous rows).
    fn gaussian_line(
        width: usize,
        height: usize,
        centre: f64,
        sigma: f64,
        peak: f64,
    ) -> Image<u16> {
        let mut img = Image::new(width, height);
        for r in 0..height {
            // Integrate the Gaussian over the pixel with 64 sub-samples (box pixel).
            let v: f64 = (0..64)
                .map(|k| {
                    let y = r as f64 + (k as f64 + 0.5) / 64.0;
                    (-0.5 * ((y - centre) / sigma).powi(2)).exp()
                })
                .sum::<f64>()
                / 64.0;
            for c in 0..width {
                img.data[r * width + c] = (peak * v).round() as u16;
            }
        }
        img
    }

    #[test]
    fn centroid_of_a_synthetic_gaussian_line() {
        let s = scancontrol_2600_100();
        let cam = Camera::new(&s.camera, &s.range).unwrap();
        let settings = ExtractSettings {
            threshold_dn: 20,
            points_per_profile: 640,
        };
        for centre in [400.0, 400.25, 400.5, 400.8] {
            let img = gaussian_line(640, 832, centre, 1.5, 900.0);
            let prof = extract(&img, &cam, &settings);
            let p = prof.points[320];
            assert!(p.valid);
            assert!(
                (p.row - centre).abs() < 0.02,
                "centre {centre}: row {}",
                p.row
            );
            let (x, z) = cam.pixel_to_laser_plane(320.5, p.row).unwrap();
            assert!((p.x_mm - x * 1e3).abs() < 1e-9 && (p.z_mm - z * 1e3).abs() < 1e-9);
        }
    }

    #[test]
    fn strongest_peak_wins_and_empty_columns_are_invalid() {
        let s = scancontrol_2600_100();
        let cam = Camera::new(&s.camera, &s.range).unwrap();
        let mut img = gaussian_line(640, 832, 300.0, 1.0, 400.0);
        let strong = gaussian_line(640, 832, 600.0, 1.0, 900.0);
        for (a, b) in img.data.iter_mut().zip(&strong.data) {
            *a = (*a).max(*b);
        }
        img.data[5] = 0; // column 5 is left as it is; blank column 7 entirely:
        for r in 0..832 {
            img.data[r * 640 + 7] = 0;
        }
        let settings = ExtractSettings {
            threshold_dn: 50,
            points_per_profile: 640,
        };
        let prof = extract(&img, &cam, &settings);
        assert!((prof.points[100].row - 600.0).abs() < 0.05);
        assert!(!prof.points[7].valid && prof.points[7].z_mm.is_nan());
    }
}
