//! The lens's diffraction without speckle (the incoherent Airy PSF integrated over pixels) and
//! the path classes of the light after the lens, on analytic and shipped scenes.

use std::path::Path;

use glassscan::scan::adaptive::StopRules;
use glassscan::scan::poses::{plan_border_scan, ScanPose};
use glassscan::scan::simulate::{sense_pose, trace_pose};
use glassscan::scene::world::World;
use glassscan::sensor::diffraction::AiryPsf;
use glassscan::sensor::image::Image;
use glassscan::sensor::profile::extract;
use glassscan::sensor::SensorHead;
use glassscan::transport::{render, Irradiance, TraceScene, TraceSettings};

use crate::common::{facing_plate, identity_pose, world_of_boxes};

/// Exposure (s) that puts irradiance `e_w_m2` at `dn` DN on `head`'s imager (noise-free).
fn exposure_for(head: &SensorHead, e_w_m2: f64, dn: f64) -> f64 {
    let mut imager = head.config.imager;
    imager.exposure_s = 1.0;
    let per_second = imager.photons(
        e_w_m2,
        head.camera.pixel_area(),
        head.config.laser.wavelength_m,
    ) * imager.quantum_efficiency
        * imager.gain_dn_per_e;
    dn / per_second
}

/// Median over columns of the line's RMS width √(M2/M0 − (M1/M0)²) (px).
fn median_rms_width(img: &Image<f64>) -> f64 {
    let mut widths: Vec<f64> = (0..img.width)
        .filter_map(|c| {
            let (m0, m1, m2) = (0..img.height).fold((0.0, 0.0, 0.0), |(a, b, d), r| {
                let (v, y) = (img.get(c, r), r as f64 + 0.5);
                (a + v, b + v * y, d + v * y * y)
            });
            (m0 > 0.0).then(|| (m2 / m0 - (m1 / m0).powi(2)).max(0.0).sqrt())
        })
        .collect();
    widths.sort_by(f64::total_cmp);
    widths[widths.len() / 2]
}

#[test]
fn a_clean_line_at_f22_with_speckle_off_is_wider_than_two_pixels_and_passes_the_width_filter() {
    // A white plate at mid-range, f/22, speckle and noise off. The traced line is the laser
    // sheet's image (RMS ~0.6 px: 1–2 px above the threshold, depending on its sub-pixel
    // position); the Airy core at f/22 (radius 1.22·λ·N_w ≈ 19 µm = 2 px) widens it.
    let mut world = world_of_boxes(&[facing_plate(257.5, 0.0)]);
    world.sensor.camera.f_number = 22.0;
    let head = SensorHead::new(&world.sensor).unwrap();
    let scene = TraceScene::new(&world).unwrap();
    let settings = TraceSettings {
        photons: 1 << 20,
        adaptive: false,
        max_depth: 16,
        seed: 31,
    };
    let pose = identity_pose();
    let (traced, _) = render(&scene, &head, &pose.sensor, &settings, 0);
    let (lens, stats) = trace_pose(&scene, &head, &pose, &settings, StopRules::EDGE_LINE);
    // Expose so that the lens's line peaks at 600 DN; the traced line at the same exposure.
    let peak = lens.total.data.iter().copied().fold(0.0, f64::max);
    world.sensor.imager.exposure_s = exposure_for(&head, peak, 600.0);
    let head = SensorHead::new(&world.sensor).unwrap();
    let cfg = &head.config;
    let raw_profile = extract(
        &cfg.imager.expose(
            &traced.total,
            head.camera.pixel_area(),
            cfg.laser.wavelength_m,
        ),
        cfg.imager.max_dn(),
        Some(&traced.by_class),
        &head.camera,
        &cfg.firmware,
    );
    let result = sense_pose(lens, stats, &head, &pose, &settings);
    let median = |p: &glassscan::sensor::profile::Profile| {
        let mut w: Vec<u32> = p
            .points
            .iter()
            .filter(|q| q.width > 0)
            .map(|q| q.width)
            .collect();
        w.sort_unstable();
        w.get(w.len() / 2).copied().unwrap_or(0)
    };
    let count =
        |p: &glassscan::sensor::profile::Profile| p.points.iter().filter(|q| q.valid).count();
    let (valid, raw_valid) = (count(&result.profile), count(&raw_profile));
    let (w_raw, w_lens) = (
        median_rms_width(&traced.total),
        median_rms_width(&result.irradiance.total),
    );
    eprintln!(
        "f/22, speckle off: RMS line width {w_raw:.2} px traced → {w_lens:.2} px through the lens; \
         firmware width {} → {} px (filter ≥ {}), valid points {raw_valid} → {valid} of {}",
        median(&raw_profile),
        median(&result.profile),
        cfg.firmware.width_range_px.0,
        result.profile.points.len()
    );
    assert!(
        w_lens > 1.5 * w_raw && median(&result.profile) > 2,
        "{w_raw} → {w_lens} px"
    );
    assert!(
        valid as f64 >= 0.95 * result.profile.points.len() as f64,
        "{valid} valid"
    );
    // Flux: the lens only redistributes the traced light.
    let (sum_traced, sum_lens) = (
        traced.total.data.iter().sum::<f64>(),
        result.irradiance.total.data.iter().sum::<f64>(),
    );
    assert!(
        (sum_lens / sum_traced - 1.0).abs() < 1e-12,
        "{sum_traced} → {sum_lens}"
    );
}

#[test]
fn blur_at_f2_8_keeps_a_synthetic_lines_centre_and_its_flux() {
    // Box-sampled Gaussian lines (σ 0.5 px, the traced line's order) at 20 sub-pixel phases,
    // blurred with the preset head's incoherent PSF at f/2.8 and, for comparison, f/22.
    let world = world_of_boxes(&[]);
    let head = SensorHead::new(&world.sensor).unwrap();
    let n_w = head
        .camera
        .working_f_number(0.0, head.config.range.z_mid_m());
    let (w, h) = (64, 64);
    for f_scale in [1.0, 22.0 / 2.8] {
        let psf = AiryPsf::new(658e-9, n_w * f_scale, 9.4e-6, 8);
        let mut worst: f64 = 0.0;
        for k in 0..20 {
            let centre = 30.0 + k as f64 / 20.0;
            let mut img = Image::new(w, h);
            for y in 0..h {
                // The Gaussian integrated over the pixel by 64 midpoints.
                let v = (0..64)
                    .map(|j| {
                        let d = (y as f64 + (j as f64 + 0.5) / 64.0 - centre) / 0.5;
                        (-0.5 * d * d).exp() / 64.0
                    })
                    .sum::<f64>();
                for x in 0..w {
                    img.data[y * w + x] = v;
                }
            }
            let out = psf.blur(&img);
            let centroid = |im: &Image<f64>, x: usize| {
                let (m0, m1) = (0..h).fold((0.0, 0.0), |(a, b), y| {
                    let v = im.get(x, y);
                    (a + v, b + v * (y as f64 + 0.5))
                });
                m1 / m0
            };
            for x in [0, 20, 63] {
                worst = worst.max((centroid(&out, x) - centroid(&img, x)).abs());
            }
            let (s0, s1) = (img.data.iter().sum::<f64>(), out.data.iter().sum::<f64>());
            assert!((s1 / s0 - 1.0).abs() < 1e-13, "flux {s0} → {s1}");
        }
        eprintln!(
            "N_w {:.2}: pixel kernel {}×{}, largest centroid shift {worst:.1e} px",
            n_w * f_scale,
            2 * psf.pixel_radius() + 1,
            2 * psf.pixel_radius() + 1
        );
        assert!(worst < 0.01, "centroid moved {worst} px");
    }
}

/// The first pose of a shipped scene, its head and trace scene, optionally at another f-number
/// and with speckle off.
fn shipped_first_pose(
    name: &str,
    f_number: Option<f64>,
    speckle: bool,
) -> (World, TraceScene, SensorHead, ScanPose) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let mut world = glassscan::scene::load(&path).expect("shipped scenes load");
    if let Some(n) = f_number {
        world.sensor.camera.f_number = n;
        // Keep the line's brightness: light through the aperture scales as 1/N².
        world.sensor.imager.exposure_s *= (n / 2.8) * (n / 2.8);
    }
    if !speckle {
        world.sensor.speckle = None;
    }
    let head = SensorHead::new(&world.sensor).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let target = world.target.as_ref().unwrap();
    let border = target
        .border
        .transformed(&world.objects[target.object].pose);
    let pose = plan_border_scan(&border, &world.scan, &world.mount).remove(0);
    (world, trace, head, pose)
}

/// Largest |Σ_class − total| relative to the pixel's total (or to 1e-12 of the image's
/// brightest pixel for dark pixels), and the pixels dark in `traced` but lit in `lens`.
fn class_sum_check(traced: &Irradiance, lens: &Irradiance) -> (f64, usize) {
    let max = lens.total.data.iter().copied().fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    let mut newly_lit = 0;
    for (p, &t) in lens.total.data.iter().enumerate() {
        let s: f64 = lens.by_class.iter().map(|l| l.data[p]).sum();
        worst = worst.max((s - t).abs() / t.max(1e-12 * max));
        if traced.total.data[p] == 0.0 && t > 0.0 {
            newly_lit += 1;
        }
    }
    (worst, newly_lit)
}

#[test]
fn every_pixel_and_profile_point_carries_its_path_classes_after_the_lens() {
    // edge_study_bare's first pose (pane edge over the table), 2¹⁶ photons: with speckle and
    // without, at f/2.8 and f/22, the class layers sum to the total in every pixel — also in
    // the pixels that only the PSF lit — and every valid profile point has a label.
    let settings = TraceSettings {
        photons: 1 << 16,
        adaptive: false,
        max_depth: 64,
        seed: 5,
    };
    for (f_number, speckle) in [
        (None, true),
        (None, false),
        (Some(22.0), true),
        (Some(22.0), false),
    ] {
        let (_, trace, head, pose) = shipped_first_pose("edge_study_bare.toml", f_number, speckle);
        let (traced, _) = render(&trace, &head, &pose.sensor, &settings, pose.index as u64);
        let (lens, stats) = trace_pose(&trace, &head, &pose, &settings, StopRules::EDGE_LINE);
        let (err, newly_lit) = class_sum_check(&traced, &lens);
        let result = sense_pose(lens, stats, &head, &pose, &settings);
        let valid: Vec<_> = result.profile.points.iter().filter(|p| p.valid).collect();
        let unlabelled = valid.iter().filter(|p| p.label.is_none()).count();
        eprintln!(
            "edge_study_bare f/{} speckle {speckle}: Σ_class error {err:.1e}, {newly_lit} pixels lit \
             only by the PSF, {} valid points, {unlabelled} unlabelled",
            f_number.unwrap_or(2.8),
            valid.len()
        );
        assert!(err < 1e-12, "{err}");
        assert!(newly_lit > 0);
        assert!(
            valid.len() > 300 && unlabelled == 0,
            "{} valid, {unlabelled} unlabelled",
            valid.len()
        );
    }
}
