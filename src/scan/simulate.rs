//! One scan pose end to end: light transport → the lens's diffraction (coherent imaging with
//! speckle, or the incoherent PSF) → image sensor (EMVA 1288 noise, full well) → profile
//! firmware.

use std::ops::Range;

use super::adaptive::{agree, newest_half, StopRules};
use super::poses::ScanPose;
use crate::sampler::PoseSampler;
use crate::sensor::diffraction::DIFFRACTION_OVERSAMPLING;
use crate::sensor::emva::{expose_drawn, frame_sampler, Exposure, FrameDraws};
use crate::sensor::image::Image;
use crate::sensor::path_class::PathClass;
use crate::sensor::profile::{extract, Profile};
use crate::sensor::speckle::speckle_image;
use crate::sensor::SensorHead;
use crate::transport::fan_focus::{FanFocus, FOCUS_HALF_WIDTH_M, FOCUS_SHARE};
use crate::transport::{
    Irradiance, Rendering, TraceScene, TraceSettings, TraceStats, FIRST_PHOTON_SET,
};

/// Everything the sensor produced at one pose.
#[derive(Clone, Debug)]
pub struct PoseResult {
    /// The pose.
    pub pose: ScanPose,
    /// Irradiance on the image plane (W/m²), in total and per path class, after the lens's
    /// diffraction (and speckle).
    pub irradiance: Irradiance,
    /// Digital image (DN, `imager.adc_bits` wide).
    pub image: Image<u16>,
    /// Pixels at the full well or at the ADC's full scale.
    pub saturated_pixels: usize,
    /// The extracted profile.
    pub profile: Profile,
    /// Transport counters.
    pub stats: TraceStats,
}

/// Stream of the speckle phases: apart from the transport's (the pose index) and the sensor
/// noise's (`frame_sampler`) streams.
const SPECKLE_STREAM: u64 = 0x5bec_1e00_0000_0000;

/// The lens's diffraction applied to the traced light (which has none), per path class.
///
/// - Rough-surface light (every class but glints), speckle on: all of it interferes together,
///   so one coherent image is made of their sum (`speckle_image`).
/// - Rough-surface light, speckle off: each class is blurred by the incoherent PSF |h|²
///   integrated over pixels (`AiryPsf::blur`), the mean of the coherent image: diffraction
///   belongs to the lens and stays (at f/22 it widens a clean line beyond 2 px).
/// - Glints, in both modes: the incoherent PSF. A glint is the lens's image of a point-like
///   specular source, so its spot is at least the Airy pattern (a lower bound: aberrations and
///   the coherent sum with the rough light are not modelled); at f/2.8 that moves a fraction of
///   its light into the 3 × 3 neighbours, at f/22 it spreads it over ~5 px. Polished faces
///   form no speckle.
///
/// Class shares of the speckled light: pixel p gets class c's share (P∗I_c)(p) / (P∗I)(p) of
/// the speckled rough light, with P the incoherent pixel kernel and I = Σ_c I_c. That is the
/// share of class c in the coherent image's expectation (the mean is P∗I, linear in the
/// classes), and it is defined wherever the PSF brought light, including pixels that the
/// tracer left dark (where the pixel's own mix, used before, had none). Where P∗I = 0 no
/// light can reach and any FFT rounding residue is dropped. Every pixel's layers sum to its
/// total: the total is their sum.
///
/// This is [`trace_pose`]'s stage after the transport (public for the benchmark); `seed` and
/// `pose.index` key the speckle phases.
pub fn apply_lens_psf(irradiance: &mut Irradiance, head: &SensorHead, pose: &ScanPose, seed: u64) {
    let speckle = head.config.speckle;
    let psf = head.lens_psf(speckle.map_or(DIFFRACTION_OVERSAMPLING, |s| s.oversampling));
    let glint = PathClass::Glint.index();
    let (w, h) = (irradiance.total.width, irradiance.total.height);
    // The rows that hold light, per class (`None`: the class is dark): the passes below touch
    // only those rows and the PSF's reach around them, where the rest of the image is exactly
    // zero before and after (a pose lights a few per cent of the pixels).
    let bands: Vec<Option<Range<usize>>> = irradiance.by_class.iter().map(lit_rows).collect();
    let reach = psf.pixel_radius();
    let widen = |r: &Range<usize>| r.start.saturating_sub(reach)..(r.end + reach).min(h);
    // ratio: what multiplies a class's blurred light (1 without speckle).
    let ratio = match speckle {
        None => None,
        Some(settings) => {
            let mut rough = Image::<f64>::new(w, h);
            let mut rough_rows: Option<Range<usize>> = None;
            for (k, layer) in irradiance.by_class.iter().enumerate() {
                if let (Some(rows), false) = (&bands[k], k == glint) {
                    rough_rows = Some(row_hull(rough_rows, rows));
                    let span = rows.start * w..rows.end * w;
                    rough.data[span.clone()]
                        .iter_mut()
                        .zip(&layer.data[span])
                        .for_each(|(r, v)| *r += v);
                }
            }
            let mut speckled = speckle_image(
                &rough,
                &psf,
                settings.contrast,
                &PoseSampler::new(seed, SPECKLE_STREAM ^ pose.index as u64),
            );
            // speckled / (P∗I): the mean of the coherent image is the blurred rough light.
            let mut mean = Image::<f64>::new(w, h);
            psf.blur_rows_onto_zeros(&rough, rough_rows.unwrap_or(0..0), &mut mean);
            for (s, m) in speckled.data.iter_mut().zip(&mean.data) {
                *s = if *m > 0.0 { *s / m } else { 0.0 };
            }
            Some(speckled)
        }
    };
    // All zero before each blur: after the swap it holds the class's unblurred light, which
    // is zero outside the class's lit rows, so clearing those rows zeroes it again.
    let mut blurred = Image::<f64>::new(w, h);
    for (k, layer) in irradiance.by_class.iter_mut().enumerate() {
        let Some(rows) = &bands[k] else {
            continue;
        };
        psf.blur_rows_onto_zeros(layer, rows.clone(), &mut blurred);
        std::mem::swap(layer, &mut blurred);
        blurred.data[rows.start * w..rows.end * w].fill(0.0);
        if let (Some(ratio), false) = (&ratio, k == glint) {
            let span = widen(rows);
            let span = span.start * w..span.end * w;
            layer.data[span.clone()]
                .iter_mut()
                .zip(&ratio.data[span])
                .for_each(|(v, r)| *v *= r);
        }
    }
    // The total is the classes' sum, so it is zero outside their lit rows: clearing those
    // rows clears it.
    let total = &mut irradiance.total;
    let lit = bands
        .iter()
        .flatten()
        .fold(None, |all, r| Some(row_hull(all, r)));
    if let Some(lit) = lit {
        total.data[lit.start * w..lit.end * w].fill(0.0);
    }
    for (layer, rows) in irradiance.by_class.iter().zip(&bands) {
        if let Some(rows) = rows {
            let span = widen(rows);
            let span = span.start * w..span.end * w;
            total.data[span.clone()]
                .iter_mut()
                .zip(&layer.data[span])
                .for_each(|(t, v)| *t += v);
        }
    }
}

/// The smallest range of rows holding `all` (if any) and `rows`.
fn row_hull(all: Option<Range<usize>>, rows: &Range<usize>) -> Range<usize> {
    all.map_or(rows.clone(), |a| {
        a.start.min(rows.start)..a.end.max(rows.end)
    })
}

/// The rows from the first to the last that hold a non-zero pixel; `None` for a dark image.
fn lit_rows(image: &Image<f64>) -> Option<Range<usize>> {
    let w = image.width.max(1);
    let lit = |row: &[f64]| row.iter().any(|&v| v != 0.0);
    let first = image.data.chunks(w).position(lit)?;
    let last = image.data.chunks(w).rposition(lit)?;
    Some(first..last + 1)
}

/// The light that reaches the image plane at `pose`: the traced irradiance per path class
/// after the lens's diffraction and speckle. It does not depend on the exposure, the threshold or the peak selection, so a
/// study that sweeps those traces each pose once and senses it many times ([`sense_pose`]).
/// With `settings.adaptive` the pose takes photons until the BIPs of the rules `stop` settle
/// (`scan::adaptive`), sensed with `settings`' sensor.
pub fn trace_pose(
    scene: &TraceScene,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
    stop: StopRules,
) -> (Irradiance, TraceStats) {
    if settings.adaptive {
        let r = simulate_until_converged(scene, head, pose, settings, stop);
        return (r.irradiance, r.stats);
    }
    let mut rendering = pose_rendering(scene, head, pose, settings);
    rendering.trace_to(settings.photons);
    let (mut irradiance, stats) = rendering.into_developed();
    apply_lens_psf(&mut irradiance, head, pose, settings.seed);
    (irradiance, stats)
}

/// The image sensor and the firmware at `pose`, given the light of [`trace_pose`]: EMVA 1288
/// exposure with the keyed noise of (seed, pose index), then the profile.
pub fn sense_pose(
    irradiance: Irradiance,
    stats: TraceStats,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
) -> PoseResult {
    let Sensed {
        image,
        saturated_pixels,
        profile,
    } = sense(&irradiance, head, pose, settings);
    PoseResult {
        pose: pose.clone(),
        irradiance,
        image,
        saturated_pixels,
        profile,
        stats,
    }
}

/// What the sensor makes of a pose's light.
#[derive(Clone, Debug)]
pub struct Sensed {
    /// Digital image (DN, `imager.adc_bits` wide).
    pub image: Image<u16>,
    /// Pixels at the full well or at the ADC's full scale.
    pub saturated_pixels: usize,
    /// The extracted profile.
    pub profile: Profile,
}

/// [`sense_pose`] without handing the light on: a study senses one pose's light with several
/// sensor settings and keeps only what each makes of it, so the light (tens of megabytes of
/// images per path class) is borrowed rather than copied for each.
pub fn sense(
    irradiance: &Irradiance,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
) -> Sensed {
    let cfg = &head.config;
    let exposure = cfg.imager.expose_noisy(
        &irradiance.total,
        head.camera.pixel_area(),
        cfg.laser.wavelength_m,
        &frame_sampler(settings.seed, pose.index as u64),
        &head.fixed_pattern,
    );
    profile_of(exposure, irradiance, head)
}

/// The frame draws of `pose` under `settings` (the read noise's deviates and the dark charge's
/// uniforms, which no exposure setting changes) for `irradiance`'s grid: what [`sense_drawn`]
/// takes when one pose's light is sensed with several settings of one sensor.
pub fn frame_draws(
    irradiance: &Irradiance,
    pose: &ScanPose,
    settings: &TraceSettings,
) -> FrameDraws {
    FrameDraws::new(
        &frame_sampler(settings.seed, pose.index as u64),
        irradiance.total.width,
        irradiance.total.height,
    )
}

/// [`sense`] with the pose's [`frame_draws`] made beforehand: bit for bit its result.
pub fn sense_drawn(irradiance: &Irradiance, head: &SensorHead, draws: &FrameDraws) -> Sensed {
    let cfg = &head.config;
    let exposure = expose_drawn(
        &cfg.imager,
        &irradiance.total,
        head.camera.pixel_area(),
        cfg.laser.wavelength_m,
        draws,
        &head.fixed_pattern,
    );
    profile_of(exposure, irradiance, head)
}

/// The firmware's profile of an exposure of `irradiance`.
fn profile_of(exposure: Exposure, irradiance: &Irradiance, head: &SensorHead) -> Sensed {
    let cfg = &head.config;
    let profile = extract(
        &exposure.dn,
        cfg.imager.max_dn(),
        Some(&irradiance.by_class),
        &head.camera,
        &cfg.firmware,
    );
    Sensed {
        image: exposure.dn,
        saturated_pixels: exposure.saturated,
        profile,
    }
}

/// The pose's rendering, its photons drawn more densely around the border point p_e
/// (`pose.edge_point`; `transport::fan_focus`): what [`trace_pose`] and [`simulate_pose`]
/// trace.
pub fn pose_rendering<'a>(
    scene: &'a TraceScene,
    head: &'a SensorHead,
    pose: &'a ScanPose,
    settings: &'a TraceSettings,
) -> Rendering<'a> {
    let focus = FanFocus::toward(
        &head.config.laser,
        &(pose.sensor.inverse() * pose.edge_point),
        FOCUS_HALF_WIDTH_M,
        FOCUS_SHARE,
    );
    Rendering::new(scene, head, &pose.sensor, settings, pose.index as u64).with_focus(focus)
}

/// Simulates the sensor `head` at `pose`: [`trace_pose`] then [`sense_pose`]. With
/// `settings.adaptive`, until the BIPs of the rules `stop` settle.
pub fn simulate_pose(
    scene: &TraceScene,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
    stop: StopRules,
) -> PoseResult {
    if settings.adaptive {
        return simulate_until_converged(scene, head, pose, settings, stop);
    }
    let (irradiance, stats) = trace_pose(scene, head, pose, settings, stop);
    sense_pose(irradiance, stats, head, pose, settings)
}

/// Simulates `pose` with photon sets until the BIPs of the rules `stop` have converged
/// (`scan::adaptive`) or `settings.photons` photons are traced: the result of the photons
/// traced (`stats.photons`).
fn simulate_until_converged(
    scene: &TraceScene,
    head: &SensorHead,
    pose: &ScanPose,
    settings: &TraceSettings,
    stop: StopRules,
) -> PoseResult {
    let most = settings.photons;
    let sensed = |(light, stats): (Irradiance, TraceStats)| {
        let mut light = light;
        apply_lens_psf(&mut light, head, pose, settings.seed);
        sense_pose(light, stats, head, pose, settings)
    };
    let bip = |r: &PoseResult| stop.bip_points(&r.profile, &pose.sensor);
    let mut rendering = pose_rendering(scene, head, pose, settings);
    rendering.trace_to(FIRST_PHOTON_SET.min(most));
    let (mut first_n, stats) = rendering.develop();
    let mut result = sensed((first_n.clone(), stats));
    while rendering.photons() < most {
        let n = rendering.photons();
        let all = (2 * n).min(most);
        rendering.trace_to(all);
        let (all_light, stats) = rendering.develop();
        let newest = (all == 2 * n).then(|| newest_half(&all_light, &first_n));
        let bip_first_n = bip(&result);
        // The two sensings are independent (each keyed by seed and pose alone): side by side.
        let (whole, bip_newest) = rayon::join(
            || sensed((all_light.clone(), stats)),
            || newest.map(|light| bip(&sensed((light, stats)))),
        );
        result = whole;
        let Some(bip_newest) = bip_newest else {
            break; // the last set is a part one: nothing is compared after it
        };
        if agree(&[bip_first_n, bip_newest, bip(&result)]) {
            break;
        }
        first_n = all_light;
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::preset::scancontrol_2600_100;
    use crate::sensor::speckle::SpeckleSettings;
    use nalgebra::Point3;

    fn head(f_number: f64, speckle: bool) -> SensorHead {
        let mut config = scancontrol_2600_100();
        config.camera.f_number = f_number;
        if !speckle {
            config.speckle = None;
        }
        SensorHead::new(&config).expect("preset camera")
    }

    fn pose() -> ScanPose {
        ScanPose {
            index: 3,
            sensor: crate::geometry::pose::Pose::identity(),
            flange: crate::geometry::pose::Pose::identity(),
            edge_point: Point3::origin(),
            border_fraction: 0.0,
        }
    }

    /// A traced-like image on the preset's 640 × 832 grid: a table line (1 px, rows 400–401)
    /// over columns 100–300, the glass edge's line crossing it at column 200, a few photons of
    /// background stray light, and a glint. Pixels between the splats are dark.
    fn synthetic(w: usize, h: usize) -> Irradiance {
        let mut by_class = vec![Image::<f64>::new(w, h); PathClass::ALL.len()];
        let put = |layer: &mut Image<f64>, x: usize, y: usize, v: f64| layer.data[y * w + x] += v;
        let (table, edge) = (PathClass::Table.index(), PathClass::GlassEdge.index());
        for x in 100..300 {
            put(&mut by_class[table], x, 400, 80.0);
            put(&mut by_class[table], x, 401, 20.0);
        }
        for x in 180..220 {
            let y = 380 + (x - 180);
            put(&mut by_class[edge], x, y, 30.0);
        }
        for (x, y) in [(20, 20), (600, 700), (350, 405)] {
            put(&mut by_class[PathClass::Background.index()], x, y, 0.5);
        }
        put(&mut by_class[PathClass::Glint.index()], 250, 300, 5e4);
        let mut total = Image::new(w, h);
        for layer in &by_class {
            total
                .data
                .iter_mut()
                .zip(&layer.data)
                .for_each(|(t, v)| *t += v);
        }
        Irradiance { total, by_class }
    }

    /// Largest |Σ_class − total| over the image, relative to the pixel's total (pixels with
    /// light) or to the image's largest total (dark pixels).
    fn class_sum_error(irr: &Irradiance) -> f64 {
        let max = irr.total.data.iter().copied().fold(0.0, f64::max);
        let mut worst: f64 = 0.0;
        for (p, t) in irr.total.data.iter().enumerate() {
            let s: f64 = irr.by_class.iter().map(|l| l.data[p]).sum();
            worst = worst.max((s - t).abs() / t.max(1e-300).max(1e-12 * max));
        }
        worst
    }

    #[test]
    fn class_layers_sum_to_the_total_after_speckle_and_after_the_blur() {
        for (f_number, speckle) in [(2.8, true), (2.8, false), (22.0, true), (22.0, false)] {
            let head = head(f_number, speckle);
            let spec = head.camera.spec();
            let before = synthetic(spec.columns, spec.rows);
            let mut after = before.clone();
            apply_lens_psf(&mut after, &head, &pose(), 1);
            let err = class_sum_error(&after);
            // Light spread into pixels the tracer left dark, and those carry classes.
            let newly_lit = (0..after.total.data.len())
                .filter(|&p| before.total.data[p] == 0.0 && after.total.data[p] > 0.0)
                .count();
            eprintln!("f/{f_number} speckle {speckle}: Σ_class error {err:.1e}, {newly_lit} newly lit pixels");
            assert!(err < 1e-12, "f/{f_number} speckle {speckle}: {err}");
            assert!(newly_lit > 100);
            // The glint is blurred by the incoherent PSF in both modes.
            let glint = PathClass::Glint.index();
            let psf = head.lens_psf(DIFFRACTION_OVERSAMPLING);
            assert_eq!(after.by_class[glint], psf.blur(&before.by_class[glint]));
            // The layers hold all the light: the total is the lens's image of the traced light
            // (speckled rough light plus the blurred glint; or everything blurred).
            let expected = if speckle {
                let mut rough = Image::<f64>::new(spec.columns, spec.rows);
                for (k, layer) in before.by_class.iter().enumerate() {
                    if k != glint {
                        rough
                            .data
                            .iter_mut()
                            .zip(&layer.data)
                            .for_each(|(r, v)| *r += v);
                    }
                }
                let sampler = PoseSampler::new(1, SPECKLE_STREAM ^ 3);
                let mut s = speckle_image(&rough, &psf, 1.0, &sampler);
                let g = psf.blur(&before.by_class[glint]);
                s.data.iter_mut().zip(&g.data).for_each(|(s, g)| *s += g);
                s
            } else {
                psf.blur(&before.total)
            };
            let max = expected.data.iter().copied().fold(0.0, f64::max);
            // The speckle FFT's f32 rounding (`sensor::speckle::fft`): relative to the
            // brightest pixel, not to each pixel.
            for (a, e) in after.total.data.iter().zip(&expected.data) {
                assert!((a - e).abs() <= 2e-6 * max, "{a} vs {e}");
            }
        }
    }

    #[test]
    fn speckle_off_conserves_flux_and_keeps_each_class() {
        let head = head(22.0, false);
        let spec = head.camera.spec();
        let before = synthetic(spec.columns, spec.rows);
        let mut after = before.clone();
        apply_lens_psf(&mut after, &head, &pose(), 1);
        for (b, a) in before.by_class.iter().zip(&after.by_class) {
            let (sb, sa) = (b.data.iter().sum::<f64>(), a.data.iter().sum::<f64>());
            assert!((sa - sb).abs() <= 1e-12 * sb.max(1e-300), "{sb} → {sa}");
        }
        // The line is wider: the table's 2-px line spreads over more than 2 rows.
        let column: Vec<f64> = (380..420).map(|y| after.total.get(150, y)).collect();
        let peak = column.iter().copied().fold(0.0, f64::max);
        assert!(column.iter().filter(|&&v| v > 0.1 * peak).count() > 2);
    }

    #[test]
    fn speckle_on_keeps_the_mean_flux_of_the_rough_light() {
        // One realisation of a 200-column line: the flux of speckle is the incoherent flux
        // within its fluctuation (~1/√(grains) ≈ a few per cent).
        let head = head(2.8, true);
        assert_eq!(
            head.config.speckle,
            Some(SpeckleSettings {
                contrast: 1.0,
                oversampling: 8
            })
        );
        let spec = head.camera.spec();
        let before = synthetic(spec.columns, spec.rows);
        let mut after = before.clone();
        apply_lens_psf(&mut after, &head, &pose(), 1);
        let table = PathClass::Table.index();
        let (sb, sa) = (
            before.by_class[table].data.iter().sum::<f64>(),
            after.by_class[table].data.iter().sum::<f64>(),
        );
        assert!((sa / sb - 1.0).abs() < 0.05, "{sb} → {sa}");
    }
}
