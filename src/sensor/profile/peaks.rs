//! One column's peaks: the threshold (fixed or automatic), the runs of pixels above it, their
//! moments over a widened window, and the path class that lit each window.

use super::Threshold;
use crate::sensor::image::Image;
use crate::sensor::path_class::PathClass;

/// Pixels added on each side of an above-threshold run before taking its moments.
///
/// A centre of gravity over the run alone cuts the line's tails at the threshold, which pulls
/// the estimate towards the nearest pixel centre ("pixel locking", up to ~0.05 px for a line of
/// σ ≈ 0.6 px). Over a window that holds the whole line, the centroid of a box-sampled Gaussian
/// is exact up to a periodic error of order exp(−2π²σ²) (~0.002 px at σ = 0.6 px).
pub const CENTROID_MARGIN_PX: usize = 2;

/// k of the automatic threshold median + k·σ̂: 6σ̂ of Gaussian noise is exceeded with
/// probability 1e-9 per pixel, ~5e-4 false peaks per 640 × 832 image.
pub const AUTO_THRESHOLD_K: f64 = 6.0;

/// Smallest margin (DN) of the automatic threshold above the background median, so that a
/// noise-free or quantised background (MAD = 0) does not turn every 1-DN ripple into a peak:
/// 16 DN is 1.6 % of the 10-bit scale. A modelling choice, like the whole automatic rule.
pub const AUTO_THRESHOLD_MIN_MARGIN_DN: u16 = 16;

/// Scale from the median absolute deviation to the standard deviation of Gaussian noise,
/// 1/Φ⁻¹(3/4) (Rousseeuw & Croux, JASA 88 (1993) 1273).
const MAD_TO_SIGMA: f64 = 1.4826;

/// A run of contiguous above-threshold pixels in one column, with its moments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Peak {
    /// First row above the threshold.
    pub first_row: usize,
    /// Last row above the threshold.
    pub last_row: usize,
    /// Rows lo..=hi the moments are taken over: the run widened by [`CENTROID_MARGIN_PX`].
    pub window: (usize, usize),
    /// Largest pixel value of the run (DN).
    pub max_dn: u16,
    /// Σ I over the window: the zeroth moment (DN).
    pub m0: f64,
    /// Σ I·(r + 0.5) over the window: the first moment, pixel centres at r + 0.5 (DN·px).
    pub m1: f64,
}

impl Peak {
    /// Pixels above the threshold.
    pub fn width_px(&self) -> u32 {
        (self.last_row - self.first_row + 1) as u32
    }

    /// Centre of gravity M1/M0 (rows; M0 > 0 because every run pixel is above a threshold ≥ 0).
    pub fn centroid_row(&self) -> f64 {
        self.m1 / self.m0
    }
}

/// The threshold (DN) for a column whose pixels, top to bottom, are `column`.
pub(super) fn column_threshold(column: &[u16], threshold: Threshold) -> u16 {
    match threshold {
        Threshold::Fixed(t) => t,
        Threshold::Automatic => automatic_threshold(column),
    }
}

/// median + max(k·1.4826·MAD, margin), rounded up and saturated at `u16::MAX` (see
/// [`Threshold::Automatic`]). Lower medians for even counts, so the result is an integer rule.
fn automatic_threshold(column: &[u16]) -> u16 {
    if column.is_empty() {
        return 0;
    }
    let mut v = column.to_vec();
    let median = lower_median(&mut v);
    for x in v.iter_mut() {
        *x = x.abs_diff(median);
    }
    let mad = lower_median(&mut v);
    let margin = (AUTO_THRESHOLD_K * MAD_TO_SIGMA * f64::from(mad))
        .ceil()
        .max(f64::from(AUTO_THRESHOLD_MIN_MARGIN_DN));
    (f64::from(median) + margin).min(f64::from(u16::MAX)) as u16
}

/// The lower median of `v` (reorders `v`).
fn lower_median(v: &mut [u16]) -> u16 {
    let mid = (v.len() - 1) / 2;
    *v.select_nth_unstable(mid).1
}

/// All runs of pixels above `threshold` in `column`, top to bottom, with moments over each run
/// widened by [`CENTROID_MARGIN_PX`] on each side but never into a neighbouring run (two
/// windows may share gap pixels).
pub(super) fn column_peaks(column: &[u16], threshold: u16) -> Vec<Peak> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut start = None;
    for (row, &v) in column.iter().enumerate() {
        match (v > threshold, start) {
            (true, None) => start = Some(row),
            (false, Some(s)) => {
                runs.push((s, row - 1));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        runs.push((s, column.len() - 1));
    }
    (0..runs.len())
        .map(|k| {
            let (first_row, last_row) = runs[k];
            let lo_limit = if k > 0 { runs[k - 1].1 + 1 } else { 0 };
            let hi_limit = runs.get(k + 1).map_or(column.len() - 1, |r| r.0 - 1);
            let lo = first_row.saturating_sub(CENTROID_MARGIN_PX).max(lo_limit);
            let hi = (last_row + CENTROID_MARGIN_PX).min(hi_limit);
            let (mut m0, mut m1) = (0.0, 0.0);
            for (row, &v) in column.iter().enumerate().take(hi + 1).skip(lo) {
                m0 += f64::from(v);
                m1 += f64::from(v) * (row as f64 + 0.5);
            }
            // The margins are at or below the threshold, so the run holds the maximum.
            let max_dn = column[first_row..=last_row]
                .iter()
                .copied()
                .max()
                .unwrap_or(0);
            Peak {
                first_row,
                last_row,
                window: (lo, hi),
                max_dn,
                m0,
                m1,
            }
        })
        .collect()
}

/// The path class with the largest irradiance summed over rows `window` of `column` in
/// `classes` (one image per class, [`PathClass::ALL`] order); ties go to the earlier class.
/// [`PathClass::SensorNoise`] if no class put any light there: the peak is the sensor's noise.
pub(super) fn label(classes: &[Image<f64>], column: usize, window: (usize, usize)) -> PathClass {
    let mut best: Option<(PathClass, f64)> = None;
    for (&class, image) in PathClass::ALL.iter().zip(classes) {
        let sum: f64 = (window.0..=window.1).map(|r| image.get(column, r)).sum();
        if sum > best.map_or(0.0, |b| b.1) {
            best = Some((class, sum));
        }
    }
    best.map_or(PathClass::SensorNoise, |b| b.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_moments_and_windows_stop_at_neighbouring_runs() {
        //           rows: 0  1  2   3   4  5  6   7  8  9  10  11
        let column = [0, 5, 9, 200, 300, 9, 7, 400, 8, 6, 4, 200];
        let peaks = column_peaks(&column, 10);
        assert_eq!(peaks.len(), 3);
        // Run 3..=4 widens to 1..=6 (row 7 is the next run); run 7..=7 to 5..=9; the last
        // run, at the bottom edge, to 9..=11.
        assert_eq!(peaks[0].window, (1, 6));
        assert_eq!(peaks[1].window, (5, 9));
        assert_eq!(peaks[2].window, (9, 11));
        assert_eq!((peaks[0].width_px(), peaks[0].max_dn), (2, 300));
        assert_eq!((peaks[1].width_px(), peaks[1].max_dn), (1, 400));
        let m0: f64 = [5.0, 9.0, 200.0, 300.0, 9.0, 7.0].iter().sum();
        let m1: f64 = [5.0, 9.0, 200.0, 300.0, 9.0, 7.0]
            .iter()
            .zip(1..)
            .map(|(v, r)| v * (r as f64 + 0.5))
            .sum();
        assert_eq!((peaks[0].m0, peaks[0].m1), (m0, m1));
        // Pixels equal to the threshold are background.
        assert!(column_peaks(&[10, 10, 10], 10).is_empty());
    }

    #[test]
    fn automatic_threshold_follows_the_background_and_its_spread() {
        // Flat background: the minimum margin.
        let flat = vec![30u16; 100];
        assert_eq!(
            automatic_threshold(&flat),
            30 + AUTO_THRESHOLD_MIN_MARGIN_DN
        );
        // Background uniform over 90…110 (ten pixels of each value): median 100, MAD 5, so
        // 100 + ⌈6·1.4826·5⌉ = 145. A bright line over a few rows does not move it.
        let mut noisy: Vec<u16> = (0..210).map(|r| 90 + (r % 21) as u16).collect();
        assert_eq!(automatic_threshold(&noisy), 145);
        noisy[50..55].fill(900);
        assert_eq!(automatic_threshold(&noisy), 145);
        assert_eq!(automatic_threshold(&[u16::MAX; 4]), u16::MAX);
    }

    #[test]
    fn label_is_the_class_with_most_light_in_the_window() {
        let mut classes = vec![Image::<f64>::new(2, 6); PathClass::ALL.len()];
        let table = PathClass::Table.index();
        let edge = PathClass::GlassEdge.index();
        classes[table].data[2 * 2 + 1] = 3.0;
        classes[edge].data[3 * 2 + 1] = 2.0;
        classes[edge].data[4 * 2 + 1] = 2.0;
        assert_eq!(label(&classes, 1, (0, 3)), PathClass::Table);
        assert_eq!(label(&classes, 1, (0, 5)), PathClass::GlassEdge);
        assert_eq!(label(&classes, 0, (0, 5)), PathClass::SensorNoise);
    }
}
