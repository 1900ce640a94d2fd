//! Charge above the full well: what a saturated pixel does with the electrons it cannot hold.
//!
//! - CMOS ([`clip_to_full_well`]): every pixel is read on its own and has no charge transfer
//!   to its neighbours; the excess is drained (anti-blooming reset), so the overflow stays local
//!   and the pixel clips at the full well (docs/parameters.md §2c, M).
//! - CCD ([`bleed_columns`]): the excess spills into the neighbouring wells of the same vertical
//!   transfer column, giving the vertical bleed trail of an overexposed CCD; the channel stops
//!   keep it out of the neighbouring columns (docs/parameters.md §2c, H).
//!
//! The bleed follows LSST imSim's `imsim/bleed_trails.py` (`bleed_channel`): find each run of
//! pixels above the full well in a column, set the run to the full well and hand its excess to
//! the pixels beyond both ends of the run, filling each up to the full well, working outwards.
//! imSim alternates one pixel up, one pixel down; here the excess is split evenly, half up and
//! half down, and each half fills outwards on its own, so a trail grows symmetrically about a
//! saturated spot. Charge that runs off the top or bottom of the sensor is lost (imSim loses
//! it at the readout end only; the split here treats both ends alike).
//!
//! Units: electrons per pixel. Images are row-major, row 0 at the top.

use super::image::Image;

/// Clips every pixel of `electrons` at `full_well` (e⁻, > 0), as a CMOS pixel does, and
/// returns the charge removed (e⁻, ≥ 0). Neighbouring pixels are never touched.
pub fn clip_to_full_well(electrons: &mut Image<f64>, full_well: f64) -> f64 {
    let mut drained = 0.0;
    for q in &mut electrons.data {
        if *q > full_well {
            drained += *q - full_well;
            *q = full_well;
        }
    }
    drained
}

/// Moves the charge above `full_well` (e⁻, > 0) into the pixels above and below it in the same
/// column, as a CCD without anti-blooming drain does, and returns the charge that left the
/// sensor at the top or bottom row (e⁻, ≥ 0).
///
/// Charge is conserved: the sum over the image after the call plus the returned loss equals the
/// sum before, up to f64 rounding. No pixel ends above the full well unless every pixel of its
/// column is full. Columns never exchange charge.
pub fn bleed_columns(electrons: &mut Image<f64>, full_well: f64) -> f64 {
    debug_assert!(full_well > 0.0, "full well {full_well}");
    let (w, h) = (electrons.width, electrons.height);
    let mut lost = 0.0;
    let mut column = vec![0.0; h];
    for c in 0..w {
        if !(0..h).any(|r| electrons.data[r * w + c] > full_well) {
            continue;
        }
        for (r, q) in column.iter_mut().enumerate() {
            *q = electrons.data[r * w + c];
        }
        lost += bleed_column(&mut column, full_well);
        for (r, q) in column.iter().enumerate() {
            electrons.data[r * w + c] = *q;
        }
    }
    lost
}

/// Bleeds one column (top to bottom); returns the charge that left at either end.
fn bleed_column(column: &mut [f64], full_well: f64) -> f64 {
    let h = column.len();
    let mut lost = 0.0;
    let mut r = 0;
    while r < h {
        if column[r] <= full_well {
            r += 1;
            continue;
        }
        // The run [r0, r1) of pixels above the full well. Charge spilled by earlier runs only
        // fills pixels up to the full well, so it never creates or extends a run.
        let r0 = r;
        while r < h && column[r] > full_well {
            r += 1;
        }
        let r1 = r;
        let excess: f64 = column[r0..r1].iter().map(|q| q - full_well).sum();
        column[r0..r1].fill(full_well);
        let up = 0.5 * excess;
        lost += fill(column[..r0].iter_mut().rev(), up, full_well);
        lost += fill(column[r1..].iter_mut(), excess - up, full_well);
    }
    lost
}

/// Pours `charge` into `pixels` in order, each up to the full well; returns what is left over
/// when the pixels run out (the charge that leaves the sensor).
fn fill<'a>(pixels: impl Iterator<Item = &'a mut f64>, mut charge: f64, full_well: f64) -> f64 {
    for q in pixels {
        if charge <= 0.0 {
            break;
        }
        // A pixel at or above the full well passes the charge on (it holds no more).
        let take = (full_well - *q).max(0.0).min(charge);
        *q += take;
        charge -= take;
    }
    charge.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn column_image(values: &[f64]) -> Image<f64> {
        Image {
            width: 1,
            height: values.len(),
            data: values.to_vec(),
        }
    }

    #[test]
    fn excess_splits_evenly_up_and_down_and_is_conserved() {
        // 250 e⁻ over a full well of 100 in the middle of a dark column: 150 spill, 75 each way.
        let mut img = column_image(&[0.0, 0.0, 0.0, 250.0, 0.0, 0.0, 0.0]);
        let lost = bleed_columns(&mut img, 100.0);
        assert_eq!(lost, 0.0);
        assert_eq!(img.data, vec![0.0, 0.0, 75.0, 100.0, 75.0, 0.0, 0.0]);
        // 650 e⁻: 550 spill, 275 each way = 100 + 100 + 75.
        let mut img = column_image(&[0.0, 0.0, 0.0, 0.0, 650.0, 0.0, 0.0, 0.0, 0.0]);
        bleed_columns(&mut img, 100.0);
        assert_eq!(
            img.data,
            vec![0.0, 75.0, 100.0, 100.0, 100.0, 100.0, 100.0, 75.0, 0.0]
        );
    }

    #[test]
    fn charge_leaving_the_sensor_is_reported() {
        // Row 0 holds 400: 300 spill, 150 up (all lost), 150 down (100 + 50).
        let mut img = column_image(&[400.0, 0.0, 0.0, 0.0]);
        let lost = bleed_columns(&mut img, 100.0);
        assert_eq!(lost, 150.0);
        assert_eq!(img.data, vec![100.0, 100.0, 50.0, 0.0]);
        let total: f64 = img.data.iter().sum();
        assert_eq!(total + lost, 400.0);
    }

    #[test]
    fn runs_and_partly_filled_neighbours_are_handled() {
        let before = [10.0, 30.0, 120.0, 180.0, 90.0, 140.0, 0.0, 5.0];
        let mut img = column_image(&before);
        let lost = bleed_columns(&mut img, 100.0);
        let after: f64 = img.data.iter().sum();
        let total: f64 = before.iter().sum();
        assert!((after + lost - total).abs() < 1e-12);
        assert!(img.data.iter().all(|&q| q <= 100.0), "{:?}", img.data);
        // First run (rows 2–3, excess 100): 50 up into row 1 (30 → 80), 50 down into row 4
        // (90 → 100) and on into row 5, which is full and passes it to row 6 (0 → 40). Then
        // row 5's own 40: 20 up, through the full rows 4…2 into row 1 (80 → 100), 20 down
        // into row 6 (40 → 60).
        assert_eq!(
            img.data,
            vec![10.0, 100.0, 100.0, 100.0, 100.0, 100.0, 60.0, 5.0]
        );
    }

    #[test]
    fn columns_do_not_exchange_charge_and_cmos_clips_in_place() {
        let mut img = Image::<f64>::new(3, 5);
        img.data[2 * 3 + 1] = 1000.0;
        img.data[2 * 3] = 7.0;
        let mut ccd = img.clone();
        // 900 spill: 450 each way, 200 fit above and 200 below, 2 × 250 leave the sensor.
        assert_eq!(bleed_columns(&mut ccd, 100.0), 500.0);
        for r in 0..5 {
            assert_eq!(ccd.get(0, r), img.get(0, r));
            assert_eq!(ccd.get(2, r), 0.0);
            assert_eq!(ccd.get(1, r), 100.0);
        }
        let mut cmos = img.clone();
        assert_eq!(clip_to_full_well(&mut cmos, 100.0), 900.0);
        let mut expected = img;
        expected.data[2 * 3 + 1] = 100.0;
        assert_eq!(cmos, expected);
    }
}
