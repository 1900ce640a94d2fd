//! `[sensor]`: a named preset (`sensor::preset`) with every field overridable from the scene
//! file, validated and converted to SI. Cross-field rules are checked on the merged result,
//! and an error points at the override that breaks the rule (or at the preset name when the
//! file overrides nothing involved).

use std::ops::Range;

use serde_spanned::Spanned;

use super::error::{SceneError, SceneSource};
use super::file::{
    CameraDef, ImagerDef, Int, LineProfileDef, PolarizationDef, SensorDef, SensorKindDef,
};
use crate::sensor::camera::Camera;
use crate::sensor::imager::SensorKind;
use crate::sensor::preset;
use crate::sensor::profile::{PeakSelect, Threshold};
use crate::sensor::projector::{LineProfile, Polarization};
use crate::sensor::SensorConfig;

/// The preset named by `sensor.preset`, with the file's overrides applied and checked.
pub(crate) fn resolve_sensor(
    def: &SensorDef,
    src: &SceneSource,
) -> Result<SensorConfig, SceneError> {
    let preset_span = def.preset.span();
    let mut s = preset::by_name(def.preset.get_ref()).ok_or_else(|| {
        let (line, column) = src.line_column(preset_span.start);
        SceneError::UnknownPreset {
            path: src.path.to_owned(),
            line,
            column,
            name: def.preset.get_ref().clone(),
            valid: preset::PRESET_NAMES.iter().map(|&n| n.to_owned()).collect(),
        }
    })?;

    let laser = &mut s.laser;
    if let Some(v) = &def.wavelength_nm {
        laser.wavelength_m = src.positive(v, "sensor.wavelength_nm")? * 1e-9;
    }
    if let Some(v) = &def.laser_power_mw {
        laser.power_w = src.positive(v, "sensor.laser_power_mw")? * 1e-3;
    }
    if let Some(v) = &def.fan_angle_deg {
        let deg = src.number(
            v,
            "sensor.fan_angle_deg",
            |d| d > 0.0 && d < 180.0,
            "must be in (0, 180) degrees",
        )?;
        laser.fan_angle_rad = deg.to_radians();
    }
    if let Some(v) = &def.line_waist_mm {
        // The file gives the 1/e² full width; the Gaussian-beam law uses the radius.
        laser.waist_radius_m = 0.5 * src.positive(v, "sensor.line_waist_mm")? * 1e-3;
    }
    if let Some(v) = &def.waist_distance_mm {
        laser.waist_distance_m = src.non_negative(v, "sensor.waist_distance_mm")? * 1e-3;
    }
    if let Some(v) = &def.m_squared {
        laser.m_squared = src.number(v, "sensor.m_squared", |m| m >= 1.0, "must be ≥ 1")?;
    }
    if let Some(p) = &def.line_profile {
        laser.line_profile = match p.get_ref() {
            LineProfileDef::Uniform => LineProfile::Uniform,
            LineProfileDef::Gaussian { half_angle_1e2_deg } => {
                let deg = src.number(
                    half_angle_1e2_deg,
                    "sensor.line_profile.gaussian.half_angle_1e2_deg",
                    |d| d > 0.0 && d < 90.0,
                    "must be in (0, 90) degrees",
                )?;
                LineProfile::Gaussian {
                    half_angle_1e2_rad: deg.to_radians(),
                }
            }
        };
    }
    if let Some(p) = &def.polarization {
        laser.polarization = match p.get_ref() {
            PolarizationDef::Unpolarized => Polarization::Unpolarized,
            PolarizationDef::Linear { angle_deg } => Polarization::Linear {
                angle_rad: src
                    .number(
                        angle_deg,
                        "sensor.polarization.linear.angle_deg",
                        |d| d.abs() <= 360.0,
                        "must be within ±360 degrees",
                    )?
                    .to_radians(),
            },
        };
    }

    if let Some(v) = &def.z_min_mm {
        s.range.z_min_m = src.positive(v, "sensor.z_min_mm")? * 1e-3;
    }
    if let Some(v) = &def.z_max_mm {
        s.range.z_max_m = src.positive(v, "sensor.z_max_mm")? * 1e-3;
    }
    let (z_min_mm, z_max_mm) = (s.range.z_min_m * 1e3, s.range.z_max_m * 1e3);
    if z_max_mm <= z_min_mm {
        return Err(blame(
            src,
            &def.preset,
            &[
                (
                    span_of(&def.z_max_mm),
                    "sensor.z_max_mm",
                    format!("must be > z_min_mm = {z_min_mm}, got {z_max_mm}"),
                ),
                (
                    span_of(&def.z_min_mm),
                    "sensor.z_min_mm",
                    format!("must be < z_max_mm = {z_max_mm}, got {z_min_mm}"),
                ),
            ],
        ));
    }
    if let Some(v) = &def.x_width_mm {
        s.range.x_width_m = src.positive(v, "sensor.x_width_mm")? * 1e-3;
    }
    if let Some(v) = &def.exposure_ms {
        s.imager.exposure_s = src.positive(v, "sensor.exposure_ms")? * 1e-3;
    }
    if let Some(c) = &def.camera {
        apply_camera(c.get_ref(), &mut s, src)?;
    }
    if let Some(i) = &def.imager {
        apply_imager(i.get_ref(), &mut s, src)?;
    }

    if let Some(v) = &def.points_per_profile {
        s.firmware.points_per_profile =
            src.integer(v, "sensor.points_per_profile", 1, 65_536)? as usize;
    }
    let (columns, points) = (s.camera.columns, s.firmware.points_per_profile);
    if points > columns || columns % points != 0 {
        let columns_span = def
            .camera
            .as_ref()
            .and_then(|c| span_of(&c.get_ref().columns));
        return Err(blame(
            src,
            &def.preset,
            &[
                (
                    span_of(&def.points_per_profile),
                    "sensor.points_per_profile",
                    format!("must divide the camera's {columns} columns, got {points}"),
                ),
                (
                    columns_span,
                    "sensor.camera.columns",
                    format!("must be a multiple of points_per_profile = {points}, got {columns}"),
                ),
            ],
        ));
    }

    let max_dn = (1i64 << s.imager.adc_bits) - 1;
    if let Some(v) = &def.threshold_dn {
        let t = src.integer(v, "sensor.threshold_dn", 0, i64::MAX)?;
        if t > max_dn {
            return Err(src.invalid(
                &v.span(),
                "sensor.threshold_dn",
                format!(
                    "must be ≤ 2^adc_bits − 1 = {max_dn} (adc_bits = {}), got {t}",
                    s.imager.adc_bits
                ),
            ));
        }
        // adc_bits ≤ 16, so t ≤ 65535 fits.
        s.firmware.threshold = Threshold::Fixed(t as u16);
    } else if let Some(preset_t) = fixed_threshold_above(&s.firmware.threshold, max_dn) {
        let span = def
            .imager
            .as_ref()
            .and_then(|i| span_of(&i.get_ref().adc_bits))
            .unwrap_or(preset_span);
        return Err(src.invalid(
            &span,
            "sensor.imager.adc_bits",
            format!(
                "must leave the preset's threshold_dn = {preset_t} ≤ 2^adc_bits − 1 = {max_dn}; \
                 lower sensor.threshold_dn too"
            ),
        ));
    }

    if let Some(v) = &def.auto_threshold {
        if *v.get_ref() {
            s.firmware.threshold = Threshold::Automatic;
        }
    }
    if let Some(v) = &def.peak_select {
        s.firmware.peak_select = v
            .get_ref()
            .parse::<PeakSelect>()
            .map_err(|e| src.invalid(&v.span(), "sensor.peak_select", e.to_string()))?;
    }
    if let Some(v) = &def.peak_width_px {
        let (lo, hi) = integer_range(src, v, "sensor.peak_width_px", 1023)?;
        s.firmware.width_range_px = (lo as u32, hi as u32);
    }
    if let Some(v) = &def.peak_intensity_dn {
        let (lo, hi) = integer_range(src, v, "sensor.peak_intensity_dn", max_dn)?;
        s.firmware.intensity_range_dn = (lo as u16, hi as u16);
    }
    if let Some(v) = &def.speckle {
        if !*v.get_ref() {
            s.speckle = None;
        }
    }
    if let Some(v) = &def.speckle_contrast {
        let c = src.number(
            v,
            "sensor.speckle_contrast",
            |c| c > 0.0 && c <= 1.0,
            "must be in (0, 1]",
        )?;
        if let Some(sp) = &mut s.speckle {
            sp.contrast = c;
        }
    }

    // The camera must image the whole measuring range onto its pixel grid; overriding the
    // optics or the range can break that.
    if let Err(e) = Camera::new(&s.camera, &s.range) {
        let message = format!("gives a camera that cannot image the measuring range: {e}");
        return Err(blame(
            src,
            &def.preset,
            &[
                (
                    def.camera.as_ref().map(Spanned::span),
                    "sensor.camera",
                    message.clone(),
                ),
                (span_of(&def.z_min_mm), "sensor.z_min_mm", message.clone()),
                (span_of(&def.z_max_mm), "sensor.z_max_mm", message.clone()),
                (span_of(&def.x_width_mm), "sensor.x_width_mm", message),
            ],
        ));
    }
    Ok(s)
}

fn apply_camera(c: &CameraDef, s: &mut SensorConfig, src: &SceneSource) -> Result<(), SceneError> {
    let cam = &mut s.camera;
    if let Some(v) = &c.baseline_mm {
        cam.baseline_m = src.positive(v, "sensor.camera.baseline_mm")? * 1e-3;
    }
    if let Some(v) = &c.lens_z_mm {
        cam.lens_z_m = src.finite(v, "sensor.camera.lens_z_mm")? * 1e-3;
    }
    if let Some(v) = &c.aim_distance_mm {
        cam.aim_distance_m = src.positive(v, "sensor.camera.aim_distance_mm")? * 1e-3;
    }
    if let Some(v) = &c.focal_length_mm {
        cam.focal_length_m = src.positive(v, "sensor.camera.focal_length_mm")? * 1e-3;
    }
    if let Some(v) = &c.f_number {
        cam.f_number = src.positive(v, "sensor.camera.f_number")?;
    }
    if let Some(v) = &c.pixel_pitch_um {
        cam.pixel_pitch_m = src.positive(v, "sensor.camera.pixel_pitch_um")? * 1e-6;
    }
    // 65 536 pixels per side is far beyond any line-scan camera head; the bound keeps a typo
    // from allocating a huge image.
    if let Some(v) = &c.columns {
        cam.columns = src.integer(v, "sensor.camera.columns", 1, 65_536)? as usize;
    }
    if let Some(v) = &c.rows {
        cam.rows = src.integer(v, "sensor.camera.rows", 1, 65_536)? as usize;
    }
    Ok(())
}

fn apply_imager(i: &ImagerDef, s: &mut SensorConfig, src: &SceneSource) -> Result<(), SceneError> {
    let im = &mut s.imager;
    if let Some(v) = &i.quantum_efficiency {
        im.quantum_efficiency = src.number(
            v,
            "sensor.imager.quantum_efficiency",
            |q| q > 0.0 && q <= 1.0,
            "must be in (0, 1]",
        )?;
    }
    if let Some(v) = &i.full_well_e {
        im.full_well_e = src.positive(v, "sensor.imager.full_well_e")?;
    }
    if let Some(v) = &i.gain_dn_per_e {
        im.gain_dn_per_e = src.positive(v, "sensor.imager.gain_dn_per_e")?;
    }
    if let Some(v) = &i.adc_bits {
        // 16 bits is the most a `u16` image and `threshold_dn` hold.
        im.adc_bits = src.integer(v, "sensor.imager.adc_bits", 8, 16)? as u32;
    }
    if let Some(k) = &i.sensor_kind {
        im.kind = match k.get_ref() {
            SensorKindDef::Cmos => SensorKind::Cmos,
            SensorKindDef::Ccd => SensorKind::Ccd,
        };
    }
    if let Some(v) = &i.dark_current_e_per_s {
        im.dark_current_e_per_s = src.non_negative(v, "sensor.imager.dark_current_e_per_s")?;
    }
    if let Some(v) = &i.read_noise_e {
        im.read_noise_e = src.non_negative(v, "sensor.imager.read_noise_e")?;
    }
    if let Some(v) = &i.dark_offset_dn {
        // Checked against the ADC range after any adc_bits override above.
        let max_dn = f64::from(im.max_dn());
        im.dark_offset_dn = src.number(
            v,
            "sensor.imager.dark_offset_dn",
            |d| (0.0..=max_dn).contains(&d),
            &format!(
                "must be in [0, 2^adc_bits − 1 = {max_dn}] (adc_bits = {})",
                im.adc_bits
            ),
        )?;
    }
    if let Some(v) = &i.prnu {
        // A relative gain spread of 100 % would make many gains negative.
        im.prnu = src.number(
            v,
            "sensor.imager.prnu",
            |p| (0.0..1.0).contains(&p),
            "must be in [0, 1) (a relative standard deviation: 0.01 = 1 %)",
        )?;
    }
    if let Some(v) = &i.dsnu_e {
        im.dsnu_e = src.non_negative(v, "sensor.imager.dsnu_e")?;
    }
    if let Some(v) = &i.noise {
        im.noise = *v.get_ref();
    }
    Ok(())
}

fn span_of<T>(v: &Option<Spanned<T>>) -> Option<Range<usize>> {
    v.as_ref().map(Spanned::span)
}

/// An error at the first of `candidates` (span, field, message) that the file gives; at the
/// preset name, with the first message, when it gives none of them (the preset itself is
/// inconsistent).
fn blame(
    src: &SceneSource,
    preset: &Spanned<String>,
    candidates: &[(Option<Range<usize>>, &str, String)],
) -> SceneError {
    match candidates.iter().find(|(span, _, _)| span.is_some()) {
        Some((Some(span), field, message)) => src.invalid(span, *field, message.clone()),
        _ => src.invalid(
            &preset.span(),
            "sensor.preset",
            candidates.first().map_or(String::new(), |c| c.2.clone()),
        ),
    }
}

/// A `[min, max]` pair of integers in [0, `max`] with min ≤ max.
fn integer_range(
    src: &SceneSource,
    v: &Spanned<[Int; 2]>,
    field: &str,
    max: i64,
) -> Result<(i64, i64), SceneError> {
    let [lo, hi] = [&v.get_ref()[0], &v.get_ref()[1]].map(|n| src.integer(n, field, 0, max));
    let (lo, hi) = (lo?, hi?);
    if lo > hi {
        return Err(src.invalid(
            &v.span(),
            field,
            format!("must be [min, max] with min ≤ max, got [{lo}, {hi}]"),
        ));
    }
    Ok((lo, hi))
}

/// The fixed threshold of `t`, if it is above `max_dn`.
fn fixed_threshold_above(t: &Threshold, max_dn: i64) -> Option<u16> {
    match *t {
        Threshold::Fixed(v) if i64::from(v) > max_dn => Some(v),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::file::SceneFile;
    use std::path::Path;

    /// Resolves the `[sensor]` table of `text` (a whole scene file).
    fn resolve(text: &str) -> Result<SensorConfig, SceneError> {
        let src = SceneSource {
            path: Path::new("s.toml"),
            text,
        };
        let file: SceneFile = toml::from_str(text).map_err(|e| src.parse_error(&e))?;
        resolve_sensor(file.sensor.get_ref(), &src)
    }

    fn err(text: &str) -> String {
        match resolve(text) {
            Ok(_) => panic!("expected an error for:\n{text}"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn overrides_are_merged_onto_the_preset_in_si() {
        let s = resolve(
            "[sensor]\npreset = \"scancontrol-2600-100\"\nwavelength_nm = 660\n\
             laser_power_mw = 10\nline_waist_mm = 0.4\nexposure_ms = 2\nthreshold_dn = 50\n\
             line_profile = { gaussian = { half_angle_1e2_deg = 10 } }\n\
             points_per_profile = 320\n\
             [sensor.camera]\nf_number = 4\n\
             [sensor.imager]\nadc_bits = 12\nquantum_efficiency = 0.6\n",
        )
        .expect("valid overrides");
        let base = preset::scancontrol_2600_100();
        assert!((s.laser.wavelength_m - 660e-9).abs() < 1e-18);
        assert!((s.laser.power_w - 0.010).abs() < 1e-15);
        assert!(
            (s.laser.waist_radius_m - 0.2e-3).abs() < 1e-15,
            "half the full width"
        );
        assert!((s.imager.exposure_s - 2e-3).abs() < 1e-15);
        assert_eq!(s.firmware.threshold, Threshold::Fixed(50));
        assert_eq!(s.firmware.points_per_profile, 320);
        assert_eq!(s.camera.f_number, 4.0);
        assert_eq!(s.imager.adc_bits, 12);
        assert!(
            matches!(s.laser.line_profile, LineProfile::Gaussian { half_angle_1e2_rad }
            if (half_angle_1e2_rad - 10f64.to_radians()).abs() < 1e-15)
        );
        // Untouched fields keep the preset's values.
        assert_eq!(s.camera.columns, base.camera.columns);
        assert_eq!(s.range, base.range);
        assert_eq!(s.laser.fan_angle_rad, base.laser.fan_angle_rad);
    }

    #[test]
    fn polarization_is_linear_along_the_line_unless_overridden() {
        let preset = "[sensor]\npreset = \"scancontrol-2600-100\"\n";
        let s = resolve(preset).unwrap();
        assert_eq!(
            s.laser.polarization,
            Polarization::Linear { angle_rad: 0.0 }
        );
        let s = resolve(&format!("{preset}polarization = \"unpolarized\"\n")).unwrap();
        assert_eq!(s.laser.polarization, Polarization::Unpolarized);
        let s = resolve(&format!(
            "{preset}polarization = {{ linear = {{ angle_deg = 90 }} }}\n"
        ))
        .unwrap();
        assert!(
            matches!(s.laser.polarization, Polarization::Linear { angle_rad }
            if (angle_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-15)
        );
        let m = err(&format!("{preset}polarization = \"circular\"\n"));
        assert!(
            m.starts_with("s.toml:3:") && m.contains("polarization"),
            "{m}"
        );
    }

    #[test]
    fn unknown_preset_lists_the_valid_names() {
        let m = err("[sensor]\npreset = \"scancontrol-9999\"\n");
        assert!(m.starts_with("s.toml:2:10: sensor.preset"), "{m}");
        assert!(m.contains("unknown preset `scancontrol-9999`"), "{m}");
        assert!(m.contains("`scancontrol-2600-100`"), "{m}");
    }

    #[test]
    fn exposure_must_be_positive() {
        let m = err("[sensor]\npreset = \"scancontrol-2600-100\"\nexposure_ms = 0\n");
        assert!(
            m.starts_with("s.toml:3:15: sensor.exposure_ms must be > 0, got 0"),
            "{m}"
        );
        let m = err("[sensor]\npreset = \"scancontrol-2600-100\"\nexposure_ms = -0.5\n");
        assert!(
            m.contains("s.toml:3:15: sensor.exposure_ms must be > 0, got -0.5"),
            "{m}"
        );
    }

    #[test]
    fn threshold_above_adc_full_scale_is_rejected() {
        let m = err("[sensor]\npreset = \"scancontrol-2600-100\"\nthreshold_dn = 1024\n");
        assert!(
            m.contains("s.toml:3:16: sensor.threshold_dn must be ≤ 2^adc_bits − 1 = 1023"),
            "{m}"
        );
        assert!(m.contains("got 1024"), "{m}");
        // The limit follows an adc_bits override.
        let m = err(
            "[sensor]\npreset = \"scancontrol-2600-100\"\nthreshold_dn = 300\n\
             [sensor.imager]\nadc_bits = 8\n",
        );
        assert!(m.contains("s.toml:3:16: sensor.threshold_dn must be ≤ 2^adc_bits − 1 = 255 (adc_bits = 8), got 300"), "{m}");
        resolve("[sensor]\npreset = \"scancontrol-2600-100\"\nthreshold_dn = 40\n[sensor.imager]\nadc_bits = 8\n")
            .expect("consistent");
    }

    #[test]
    fn points_per_profile_must_divide_columns() {
        let m = err("[sensor]\npreset = \"scancontrol-2600-100\"\npoints_per_profile = 300\n");
        assert!(m.contains("s.toml:3:22: sensor.points_per_profile"), "{m}");
        assert!(
            m.contains("must divide the camera's 640 columns, got 300"),
            "{m}"
        );
        let m =
            err("[sensor]\npreset = \"scancontrol-2600-100\"\n[sensor.camera]\ncolumns = 600\n");
        assert!(m.contains("s.toml:4:11: sensor.camera.columns must be a multiple of points_per_profile = 640, got 600"), "{m}");
        let m = err("[sensor]\npreset = \"scancontrol-2600-100\"\npoints_per_profile = 0\n");
        assert!(
            m.contains("s.toml:3:22: sensor.points_per_profile must be in 1..=65536, got 0"),
            "{m}"
        );
    }

    #[test]
    fn non_finite_and_out_of_range_values_are_rejected() {
        let m = err("[sensor]\npreset = \"scancontrol-2600-100\"\nlaser_power_mw = nan\n");
        assert!(
            m.contains("s.toml:3:18: sensor.laser_power_mw must be a finite number, got NaN"),
            "{m}"
        );
        let m =
            err("[sensor]\npreset = \"scancontrol-2600-100\"\n[sensor.camera]\nf_number = inf\n");
        assert!(
            m.contains("s.toml:4:12: sensor.camera.f_number must be a finite number, got inf"),
            "{m}"
        );
        let m = err("[sensor]\npreset = \"scancontrol-2600-100\"\n[sensor.imager]\nquantum_efficiency = 1.5\n");
        assert!(
            m.contains("s.toml:4:22: sensor.imager.quantum_efficiency must be in (0, 1], got 1.5"),
            "{m}"
        );
        let m = err("[sensor]\npreset = \"scancontrol-2600-100\"\nz_min_mm = 400\n");
        assert!(
            m.contains("s.toml:3:12: sensor.z_min_mm must be < z_max_mm = 390, got 400"),
            "{m}"
        );
    }

    #[test]
    fn imager_noise_overrides_are_merged() {
        let base = preset::scancontrol_2600_100().imager;
        assert_eq!(base.kind, SensorKind::Cmos);
        assert!(base.noise);
        let s = resolve(
            "[sensor]\npreset = \"scancontrol-2600-100\"\n[sensor.imager]\n\
             sensor_kind = \"ccd\"\ndark_current_e_per_s = 50\nread_noise_e = 7.5\n\
             dark_offset_dn = 16\nprnu = 0.02\ndsnu_e = 0\nnoise = false\n",
        )
        .expect("valid imager overrides");
        let im = s.imager;
        assert_eq!(im.kind, SensorKind::Ccd);
        assert_eq!(im.dark_current_e_per_s, 50.0);
        assert_eq!(im.read_noise_e, 7.5);
        assert_eq!(im.dark_offset_dn, 16.0);
        assert_eq!(im.prnu, 0.02);
        assert_eq!(im.dsnu_e, 0.0);
        assert!(!im.noise);
        // Untouched imager fields keep the preset's values.
        assert_eq!(im.full_well_e, base.full_well_e);
        assert_eq!(im.gain_dn_per_e, base.gain_dn_per_e);
    }

    #[test]
    fn bad_imager_noise_values_are_rejected_where_they_stand() {
        let imager = "[sensor]\npreset = \"scancontrol-2600-100\"\n[sensor.imager]\n";
        let cases = [
            (
                "read_noise_e = -1\n",
                "s.toml:4:16: sensor.imager.read_noise_e must be ≥ 0, got -1",
            ),
            (
                "dark_current_e_per_s = nan\n",
                "s.toml:4:24: sensor.imager.dark_current_e_per_s must be a finite number, got NaN",
            ),
            (
                "prnu = 1.5\n",
                "s.toml:4:8: sensor.imager.prnu must be in [0, 1) (a relative standard \
                 deviation: 0.01 = 1 %), got 1.5",
            ),
            (
                "dsnu_e = -0.5\n",
                "s.toml:4:10: sensor.imager.dsnu_e must be ≥ 0, got -0.5",
            ),
            (
                "dark_offset_dn = 1024\n",
                "s.toml:4:18: sensor.imager.dark_offset_dn must be in [0, 2^adc_bits − 1 = \
                 1023] (adc_bits = 10), got 1024",
            ),
            // The limit follows an adc_bits override.
            (
                "adc_bits = 8\ndark_offset_dn = 300\n",
                "s.toml:5:18: sensor.imager.dark_offset_dn must be in [0, 2^adc_bits − 1 = \
                 255] (adc_bits = 8), got 300",
            ),
        ];
        for (text, expected) in cases {
            let m = err(&format!("{imager}{text}"));
            assert!(m.starts_with(expected), "{m}\nexpected: {expected}");
        }
        let m = err(&format!("{imager}sensor_kind = \"cmos2\"\n"));
        assert!(
            m.starts_with("s.toml:4:15: sensor.imager") && m.contains("cmos2"),
            "{m}"
        );
        assert!(m.contains("`cmos`") && m.contains("`ccd`"), "{m}");
        let m = err(&format!("{imager}noise = 1\n"));
        assert!(
            m.starts_with("s.toml:4:9: sensor.imager") && m.contains("bool"),
            "{m}"
        );
    }

    #[test]
    fn camera_that_cannot_image_the_range_is_rejected() {
        let m = err(
            "[sensor]\npreset = \"scancontrol-2600-100\"\n[sensor.camera]\npixel_pitch_um = 2\n",
        );
        assert!(
            m.contains("s.toml:3:1: sensor.camera gives a camera that cannot image"),
            "{m}"
        );
    }

    #[test]
    fn unknown_sensor_key_keeps_its_location_and_table() {
        let m =
            err("[sensor]\npreset = \"scancontrol-2600-100\"\n[sensor.camera]\nfocal_mm = 16\n");
        assert!(
            m.starts_with("s.toml:4:1: sensor.camera: unknown field `focal_mm`"),
            "{m}"
        );
    }
}
