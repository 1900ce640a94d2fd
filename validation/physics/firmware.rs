//! The profile firmware on synthetic images (no light transport): sub-pixel centroids of
//! Gaussian lines, the selection modes on columns with several peaks, the peak filter, the
//! four peak slots, the decimation to fewer points, the automatic threshold and the path-class
//! labels.
//!
//! References: the centres, heights, widths and areas the images are built from; the mode
//! definitions of docs/parameters.md §1a/§1d (ALL, FIRST, LAST, LARGEST_AREA, MAX_INTENSITY,
//! SINGLE); the 4 peak slots and 80…640 points per profile of §1a.

use glassscan::sampler::mix64;
use glassscan::sensor::camera::Camera;
use glassscan::sensor::image::Image;
use glassscan::sensor::path_class::PathClass;
use glassscan::sensor::preset::scancontrol_2600_100;
use glassscan::sensor::profile::{
    extract, FirmwareSettings, PeakSelect, Profile, ProfilePoint, Threshold,
    DRIVER_DEFAULT_THRESHOLD_DN,
};

const COLUMNS: usize = 640;
const ROWS: usize = 832;
/// The 10-bit ADC of the scanCONTROL preset: the firmware flags peaks that reach it.
const FULL_SCALE_DN: u16 = 1023;

fn camera() -> Camera {
    let s = scancontrol_2600_100();
    Camera::new(&s.camera, &s.range).expect("preset camera is valid")
}

/// The driver's defaults (threshold 128, FIRST, width 2…1023) with another selection mode.
fn settings(peak_select: PeakSelect) -> FirmwareSettings {
    FirmwareSettings {
        peak_select,
        ..FirmwareSettings::scancontrol_default(DRIVER_DEFAULT_THRESHOLD_DN)
    }
}

/// A Gaussian line: centre row (continuous, pixel centres at r + 0.5), σ (px), amplitude (DN).
#[derive(Clone, Copy)]
struct Line {
    centre: f64,
    sigma: f64,
    amplitude: f64,
}

/// The line's mean over pixel row `r` (box pixel, 64-point midpoint rule).
fn pixel_value(line: Line, r: usize) -> f64 {
    let sum: f64 = (0..64)
        .map(|k| {
            let y = r as f64 + (k as f64 + 0.5) / 64.0;
            (-0.5 * ((y - line.centre) / line.sigma).powi(2)).exp()
        })
        .sum();
    line.amplitude * sum / 64.0
}

/// A digital image whose column c holds `lines(c)` on top of `background(c, r)` (DN), rounded
/// and clipped to 10 bits like the imager's output.
fn image(
    lines: impl Fn(usize) -> Vec<Line>,
    background: impl Fn(usize, usize) -> f64,
) -> Image<u16> {
    let mut img = Image::new(COLUMNS, ROWS);
    for c in 0..COLUMNS {
        let lines = lines(c);
        for r in 0..ROWS {
            let v: f64 = background(c, r)
                + lines
                    .iter()
                    .filter(|l| (r as f64 + 0.5 - l.centre).abs() < 10.0 * l.sigma + 1.0)
                    .map(|&l| pixel_value(l, r))
                    .sum::<f64>();
            img.data[r * COLUMNS + c] = v.round().clamp(0.0, 1023.0) as u16;
        }
    }
    img
}

/// The same lines in every column, on a black background.
fn uniform(lines: &[Line]) -> Image<u16> {
    image(|_| lines.to_vec(), |_, _| 0.0)
}

fn line(centre: f64, sigma: f64, amplitude: f64) -> Line {
    Line {
        centre,
        sigma,
        amplitude,
    }
}

/// The points of `column`.
fn points_of(profile: &Profile, column: usize) -> Vec<ProfilePoint> {
    profile
        .points
        .iter()
        .filter(|p| p.column == column)
        .copied()
        .collect()
}

#[test]
fn gaussian_line_centroid_is_exact_to_a_fiftieth_of_a_pixel() {
    let cam = camera();
    for sigma in [0.6, 0.8, 1.0, 1.5, 2.0] {
        // A centre that walks 0.613 px per column sweeps every sub-pixel phase.
        let centre = |c: usize| 200.0 + 0.613 * c as f64;
        let img = image(|c| vec![line(centre(c), sigma, 1000.0)], |_, _| 0.0);
        let prof = extract(
            &img,
            FULL_SCALE_DN,
            None,
            &cam,
            &settings(PeakSelect::First),
        );
        assert_eq!(prof.points.len(), COLUMNS);
        let errors: Vec<f64> = prof
            .points
            .iter()
            .map(|p| {
                assert!(p.valid, "σ = {sigma}: column {} invalid", p.column);
                p.row - centre(p.column)
            })
            .collect();
        let max = errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
        let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
        eprintln!("σ = {sigma} px: centroid error max {max:.4} px, rms {rms:.4} px");
        assert!(max < 0.02, "σ = {sigma} px: max centroid error {max} px");
    }
}

/// Four peaks, chosen so that each mode picks a different one: A first, B the largest area
/// (wide), C the brightest (narrow), D last.
const A: Line = Line {
    centre: 150.3,
    sigma: 1.0,
    amplitude: 300.0,
};
const B: Line = Line {
    centre: 300.6,
    sigma: 3.0,
    amplitude: 500.0,
};
const C: Line = Line {
    centre: 450.2,
    sigma: 0.7,
    amplitude: 950.0,
};
const D: Line = Line {
    centre: 600.8,
    sigma: 1.2,
    amplitude: 250.0,
};

/// Asserts that every column of `profile` has exactly the points of the `expected` lines, with
/// their reflection indices. The rows must match within 0.1 px: the peaks are ≥ 150 rows apart,
/// so this identifies the peak; B, wide (σ = 3 px) under a threshold at 26 % of its height, is
/// off by 0.05 px because its window (run ± 2 px = ±2.3σ) cuts its tails unevenly.
fn assert_columns(profile: &Profile, expected: &[(u8, Line)], what: &str) {
    let per_column = expected.len().max(1);
    assert_eq!(profile.points.len(), COLUMNS * per_column, "{what}");
    for (i, chunk) in profile.points.chunks(per_column).enumerate() {
        if expected.is_empty() {
            assert!(
                !chunk[0].valid && chunk[0].column == i,
                "{what}: column {i}"
            );
            continue;
        }
        for (p, &(slot, l)) in chunk.iter().zip(expected) {
            assert!(p.valid && p.column == i, "{what}: column {i}");
            assert_eq!(p.reflection, slot, "{what}: column {i}");
            assert!(
                (p.row - l.centre).abs() < 0.1,
                "{what}: column {i}: row {} instead of {}",
                p.row,
                l.centre
            );
        }
    }
}

#[test]
fn each_selection_mode_picks_its_peak() {
    let cam = camera();
    let img = uniform(&[A, B, C, D]);
    let run = |m: PeakSelect| extract(&img, FULL_SCALE_DN, None, &cam, &settings(m));
    assert_columns(&run(PeakSelect::First), &[(0, A)], "FIRST");
    assert_columns(&run(PeakSelect::Last), &[(3, D)], "LAST");
    assert_columns(&run(PeakSelect::LargestArea), &[(1, B)], "LARGEST_AREA");
    assert_columns(&run(PeakSelect::MaxIntensity), &[(2, C)], "MAX_INTENSITY");
    assert_columns(&run(PeakSelect::Single), &[], "SINGLE, 4 peaks");
    let all = run(PeakSelect::All);
    assert_columns(&all, &[(0, A), (1, B), (2, C), (3, D)], "ALL");

    // Rows grow with range: the first peak is the nearest, the last the farthest.
    let column = points_of(&all, 320);
    assert!(column.windows(2).all(|w| w[0].z_mm < w[1].z_mm));
    let b = column[1];
    let c = column[2];
    eprintln!(
        "column 320, ALL: z = {:.3} / {:.3} / {:.3} / {:.3} mm; M0 of B {:.0} > C {:.0}; \
         max of C {} > B {}",
        column[0].z_mm, b.z_mm, c.z_mm, column[3].z_mm, b.m0, c.m0, c.intensity, b.intensity
    );

    let two = uniform(&[A, C]);
    let single = |img: &Image<u16>| {
        extract(
            img,
            FULL_SCALE_DN,
            None,
            &cam,
            &settings(PeakSelect::Single),
        )
    };
    assert_columns(&single(&two), &[], "SINGLE, 2 peaks");
    assert_columns(&single(&uniform(&[C])), &[(0, C)], "SINGLE, 1 peak");
}

#[test]
fn peak_filter_drops_too_wide_and_too_dim_peaks() {
    let cam = camera();
    let img = uniform(&[A, B, C, D]);
    let narrow = FirmwareSettings {
        width_range_px: (2, 8),
        ..settings(PeakSelect::All)
    };
    let widths: Vec<u32> = points_of(
        &extract(&img, FULL_SCALE_DN, None, &cam, &settings(PeakSelect::All)),
        0,
    )
    .iter()
    .map(|p| p.width)
    .collect();
    eprintln!("widths above 128 DN of A, B, C, D: {widths:?} px");
    let prof = extract(&img, FULL_SCALE_DN, None, &cam, &narrow);
    assert_columns(&prof, &[(0, A), (1, C), (2, D)], "width 2…8");
    let largest = FirmwareSettings {
        peak_select: PeakSelect::LargestArea,
        ..narrow
    };
    assert_columns(
        &extract(&img, FULL_SCALE_DN, None, &cam, &largest),
        &[(1, C)],
        "width 2…8, LARGEST_AREA",
    );
    let bright = FirmwareSettings {
        intensity_range_dn: (400, 1023),
        ..settings(PeakSelect::All)
    };
    let prof = extract(&img, FULL_SCALE_DN, None, &cam, &bright);
    assert_columns(&prof, &[(0, B), (1, C)], "intensity 400…1023");
}

#[test]
fn more_than_four_peaks_keep_the_first_four_from_the_top() {
    let cam = camera();
    let five: Vec<Line> = (0..5)
        .map(|k| line(100.4 + 150.0 * k as f64, 1.0, 600.0))
        .collect();
    let slots: Vec<(u8, Line)> = (0..4).map(|k| (k as u8, five[k])).collect();
    // A one-pixel spike above them all: the width filter (≥ 2 px) drops it before the slots
    // are counted, so it does not take one.
    let spike = |_: usize, r: usize| if r == 40 { 700.0 } else { 0.0 };
    let img = image(|_| five.clone(), spike);
    let all = extract(&img, FULL_SCALE_DN, None, &cam, &settings(PeakSelect::All));
    assert_columns(&all, &slots, "ALL, 5 peaks");
    let last = extract(&img, FULL_SCALE_DN, None, &cam, &settings(PeakSelect::Last));
    assert_columns(&last, &[(3, five[3])], "LAST, 5 peaks");
    let two = FirmwareSettings {
        max_peaks: 2,
        ..settings(PeakSelect::All)
    };
    assert_columns(
        &extract(&img, FULL_SCALE_DN, None, &cam, &two),
        &slots[..2],
        "ALL, max_peaks 2",
    );
}

#[test]
fn fewer_points_report_the_middle_column_of_each_group() {
    let cam = camera();
    let centre = |c: usize| 200.0 + 0.5 * c as f64;
    let img = image(|c| vec![line(centre(c), 1.2, 800.0)], |_, _| 0.0);
    for points in [80, 160, 320, 640] {
        let s = FirmwareSettings {
            points_per_profile: points,
            ..settings(PeakSelect::First)
        };
        assert_eq!(s.check(COLUMNS, 1023), Ok(()));
        let prof = extract(&img, FULL_SCALE_DN, None, &cam, &s);
        assert_eq!(prof.points.len(), points);
        let k = COLUMNS / points;
        for (i, p) in prof.points.iter().enumerate() {
            assert_eq!(p.column, i * k + k / 2, "{points} points");
            assert!(p.valid && (p.row - centre(p.column)).abs() < 0.02);
            let (x, _) = cam
                .pixel_to_laser_plane(p.column as f64 + 0.5, p.row)
                .unwrap();
            assert!((p.x_mm - x * 1e3).abs() < 1e-9);
        }
    }
}

#[test]
fn automatic_threshold_finds_a_faint_line_on_a_noisy_background() {
    let cam = camera();
    // Background 14…26 DN, a deterministic hash of the pixel; a faint line (90 DN above it) in
    // the left half only, so the right half checks for false peaks.
    let background = |c: usize, r: usize| {
        let h = mix64(((c as u64) << 32) ^ r as u64 ^ 0x5EED);
        14.0 + (h % 13) as f64
    };
    let faint = line(400.3, 1.5, 90.0);
    let img = image(
        |c| if c < 320 { vec![faint] } else { Vec::new() },
        background,
    );
    let fixed = extract(
        &img,
        FULL_SCALE_DN,
        None,
        &cam,
        &settings(PeakSelect::First),
    );
    assert!(
        fixed.points.iter().all(|p| !p.valid),
        "the fixed 128 DN sees the line"
    );
    let auto = FirmwareSettings {
        threshold: Threshold::Automatic,
        ..settings(PeakSelect::First)
    };
    let prof = extract(&img, FULL_SCALE_DN, None, &cam, &auto);
    let (left, right) = prof.points.split_at(320);
    assert!(
        right.iter().all(|p| !p.valid),
        "false peaks on the background"
    );
    let errors: Vec<f64> = left
        .iter()
        .map(|p| {
            assert!(p.valid, "column {} missed", p.column);
            p.row - faint.centre
        })
        .collect();
    let max = errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
    let (t_min, t_max) = prof.points.iter().fold((u16::MAX, 0), |(a, b), p| {
        (a.min(p.threshold), b.max(p.threshold))
    });
    eprintln!(
        "automatic threshold {t_min}…{t_max} DN; faint line found in 320/320 columns, \
         centroid error mean {mean:+.4} px, rms {rms:.4} px, max {max:.4} px; \
         0 false peaks in 320 columns"
    );
    // The background under the window (no background subtraction) pulls the centroid towards
    // the window's centre, and the window follows the noisy threshold crossings: that, not the
    // threshold rule, sets the error here.
    assert!(
        mean.abs() < 0.04 && rms < 0.15 && max < 0.4,
        "centroid error on the noisy background"
    );
}

#[test]
fn points_carry_the_path_class_of_their_peak() {
    let cam = camera();
    let table = line(300.4, 1.2, 600.0);
    let edge = line(500.7, 1.0, 400.0);
    // Irradiance per class (arbitrary units): the table's peak, the edge's peak, a weak glass
    // face glow everywhere, and 10 % of the table's light also at the edge's rows.
    let mut classes = vec![Image::<f64>::new(COLUMNS, ROWS); PathClass::ALL.len()];
    for r in 0..ROWS {
        for c in 0..COLUMNS {
            let i = r * COLUMNS + c;
            classes[PathClass::Table.index()].data[i] =
                pixel_value(table, r) + 0.1 * pixel_value(edge, r);
            classes[PathClass::GlassEdge.index()].data[i] = pixel_value(edge, r);
            classes[PathClass::GlassFace.index()].data[i] = 2.0;
        }
    }
    let img = uniform(&[table, edge]);
    let all = extract(
        &img,
        FULL_SCALE_DN,
        Some(&classes),
        &cam,
        &settings(PeakSelect::All),
    );
    assert_columns(&all, &[(0, table), (1, edge)], "ALL");
    for pair in all.points.chunks(2) {
        assert_eq!(pair[0].label, Some(PathClass::Table));
        assert_eq!(pair[1].label, Some(PathClass::GlassEdge));
    }
    let last = extract(
        &img,
        FULL_SCALE_DN,
        Some(&classes),
        &cam,
        &settings(PeakSelect::Last),
    );
    assert!(last
        .points
        .iter()
        .all(|p| p.label == Some(PathClass::GlassEdge)));
    let unlabelled = extract(&img, FULL_SCALE_DN, None, &cam, &settings(PeakSelect::All));
    assert!(unlabelled.points.iter().all(|p| p.label.is_none()));
}
