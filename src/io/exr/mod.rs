//! Multi-layer f32 OpenEXR for radiometric images (irradiance, and one layer per light-path
//! class). One single-part scanline file holds one f32 channel per named layer, ZIP-compressed
//! (lossless, so NaN payloads and subnormals such as 1e-30 survive bit for bit).
//!
//! Orientation: OpenEXR's y axis points down and its first scanline is the top row, so row 0
//! of an [`Image`] is the top row of the file, as everywhere else in glassscan.
//!
//! Channel order: the OpenEXR format stores channels sorted by name, so `read_exr_layers`
//! returns the layers in that (byte-wise alphabetical) order, whatever order they were written in.
//!
//! glassscan writes its files itself, for exactly this one layout (single part, scan lines in
//! increasing y, f32 channels, ZIP_COMPRESSION over blocks of 16 scanlines), and reads them with
//! the `exr` crate: [`file`] lays out the file, [`header`] encodes the header, [`zip_block`] one
//! block and [`zlib`] its zlib stream, a [`deflate_block`] with [`huffman`] codes. The zlib
//! streams are glassscan's own too: no deflate library was fast on these images (see [`zlib`]).

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use exr::prelude::{FlatSamples, ReadChannels, ReadLayers};

use super::atomic::write_atomic;
use super::error::check_image_size;
use super::FileError;
use crate::geometry::pose::{pose_to_matrix_mm, Pose};
use crate::sensor::image::Image;
use crate::sensor::path_class::PathClass;
use crate::transport::Irradiance;
use header::Value;
use zip_block::Samples;

mod deflate_block;
mod file;
mod header;
mod huffman;
mod zip_block;
mod zlib;

#[cfg(test)]
mod round_trip_tests;

/// Writes `layers` (name, row-major samples) as one f32 channel each into a `width` × `height`
/// single-part scanline EXR at `path`, atomically.
///
/// Every layer must hold exactly `width * height` samples; names must be distinct, non-empty,
/// Latin-1 (the EXR text type), at most 255 characters long and without NUL.
pub fn write_exr_layers(
    path: &Path,
    width: usize,
    height: usize,
    layers: &[(&str, &[f32])],
) -> Result<(), FileError> {
    let layers: Vec<(&str, Samples)> = layers
        .iter()
        .map(|&(name, samples)| (name, Samples::F32(samples)))
        .collect();
    write_layers(path, width, height, &layers, Vec::new())
}

/// [`write_exr_layers`] of f32 or f64 samples (rounded to f32), with the `extra` header
/// attributes after the standard ones.
fn write_layers(
    path: &Path,
    width: usize,
    height: usize,
    layers: &[(&str, Samples)],
    extra: Vec<(&'static str, Value)>,
) -> Result<(), FileError> {
    let layout_error = |expected: &str, found: String| FileError::ExrLayout {
        path: path.to_path_buf(),
        expected: expected.to_string(),
        found,
    };
    if layers.is_empty() {
        return Err(layout_error("at least one layer", "none".to_string()));
    }
    let mut channels = Vec::with_capacity(layers.len());
    for (i, &(name, samples)) in layers.iter().enumerate() {
        let len = match samples {
            Samples::F32(s) => s.len(),
            Samples::F64(s) => s.len(),
        };
        check_image_size(path, || format!("layer \"{name}\""), width, height, len)?;
        if layers[..i].iter().any(|&(other, _)| other == name) {
            return Err(layout_error(
                "distinct layer names",
                format!("\"{name}\" twice"),
            ));
        }
        let bytes = header::latin1(name)
            .filter(|b| !b.is_empty() && b.len() <= header::NAME_MAX && !b.contains(&0))
            .ok_or_else(|| {
                layout_error(
                    "a non-empty Latin-1 layer name of at most 255 characters, without NUL",
                    format!("\"{name}\""),
                )
            })?;
        channels.push((bytes, samples));
    }
    if !file::fits(width, height, channels.len()) {
        return Err(layout_error(
            "an image whose sizes fit OpenEXR's 32-bit fields",
            format!("{width} × {height} pixels of {} layers", channels.len()),
        ));
    }
    // The format stores channels sorted by name, byte-wise.
    channels.sort_by(|a, b| a.0.cmp(&b.0));
    // Encoding to memory first means an encoder error never leaves a temporary file behind.
    let encoded = file::encode(width, height, &channels, extra);
    write_atomic(path, |w| w.write_all(&encoded))
}

/// What an irradiance image was made with, stored in its EXR header.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IrradianceNotes {
    /// The laser's vacuum wavelength (m).
    pub wavelength_m: f64,
    /// The exposure time (s).
    pub exposure_s: f64,
    /// The sensor's pose in the base frame (sensor → base).
    pub sensor_to_base: Pose,
}

impl IrradianceNotes {
    /// The header attributes: the standard `comments` (which says the unit, W/m²), `expTime`
    /// (s) and `software`, and the custom `sensorToBaseMm` (4 × 4, row-major, mm; f32 as EXR
    /// matrices are: the dataset's ground truth holds it in f64) and `wavelengthNm` (f64).
    fn header(&self) -> Vec<(&'static str, Value)> {
        let text = |t: &str| Value::String(header::latin1(t).expect("ASCII"));
        vec![
            (
                "comments",
                text(
                    "glassscan irradiance at the pixels (W/m^2): 'irradiance' is the total, \
                     'class.<path class>' its part by light path",
                ),
            ),
            ("expTime", Value::Float(self.exposure_s as f32)),
            (
                "software",
                text(&format!("glassscan {}", env!("CARGO_PKG_VERSION"))),
            ),
            (
                "sensorToBaseMm",
                Value::M44f(pose_to_matrix_mm(&self.sensor_to_base).map(|v| v as f32)),
            ),
            ("wavelengthNm", Value::Double(self.wavelength_m * 1e9)),
        ]
    }
}

/// Writes a pose's irradiance (W/m²) as f32 layers: `irradiance` (the total) and
/// `class.<path class>` for each path class, with `notes` in the header.
pub fn write_irradiance_exr(
    path: &Path,
    irradiance: &Irradiance,
    notes: &IrradianceNotes,
) -> Result<(), FileError> {
    let names: Vec<String> = PathClass::ALL
        .iter()
        .map(|c| format!("class.{}", c.name()))
        .collect();
    let mut layers = vec![("irradiance", Samples::F64(&irradiance.total.data))];
    layers.extend(PathClass::ALL.iter().zip(&names).map(|(c, n)| {
        (
            n.as_str(),
            Samples::F64(&irradiance.by_class[c.index()].data),
        )
    }));
    write_layers(
        path,
        irradiance.total.width,
        irradiance.total.height,
        &layers,
        notes.header(),
    )
}

/// Reads every channel of a single-part EXR as an f32 layer, in the file's (alphabetical)
/// channel order. Channels stored as f16 or u32, subsampled channels and multi-part files are
/// refused with [`FileError::ExrLayout`], never converted.
pub fn read_exr_layers(path: &Path) -> Result<Vec<(String, Image<f32>)>, FileError> {
    let file = File::open(path).map_err(|e| FileError::io(path, "open", e))?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_buffered(BufReader::new(file))
        .map_err(|source| FileError::Exr {
            path: path.to_path_buf(),
            expected: "a valid OpenEXR file",
            source,
        })?;
    let layout_error = |expected: String, found: String| FileError::ExrLayout {
        path: path.to_path_buf(),
        expected,
        found,
    };
    let [layer] = image.layer_data.as_slice() else {
        return Err(layout_error(
            "a single-part EXR".to_string(),
            format!("{} parts", image.layer_data.len()),
        ));
    };
    let (width, height) = (layer.size.width(), layer.size.height());
    let mut out = Vec::with_capacity(layer.channel_data.list.len());
    for channel in &layer.channel_data.list {
        let name = channel.name.to_string();
        let data = match &channel.sample_data {
            FlatSamples::F32(data) => data.clone(),
            FlatSamples::F16(_) => {
                return Err(layout_error(
                    format!("f32 samples in channel \"{name}\""),
                    "f16".to_string(),
                ))
            }
            FlatSamples::U32(_) => {
                return Err(layout_error(
                    format!("f32 samples in channel \"{name}\""),
                    "u32".to_string(),
                ))
            }
        };
        // A subsampled channel holds fewer samples than the layer has pixels.
        if data.len() != width * height {
            return Err(layout_error(
                format!(
                    "{} samples (width × height) in channel \"{name}\"",
                    width * height
                ),
                data.len().to_string(),
            ));
        }
        out.push((
            name,
            Image {
                width,
                height,
                data,
            },
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use exr::prelude::{
        AnyChannel, AnyChannels, AttributeValue, Blocks, Compression, Encoding, Layer,
        LayerAttributes, LineOrder, ReadSpecificChannel, SmallVec, Text, WritableImage,
    };

    const WIDTH: usize = 5;
    const HEIGHT: usize = 3;

    /// Layer `a` is a gradient with special values; layer `b` is its negative.
    fn layers() -> (Vec<f32>, Vec<f32>) {
        let mut a: Vec<f32> = (0..WIDTH * HEIGHT).map(|i| i as f32 * 0.25 + 0.1).collect();
        a[0] = f32::NAN;
        a[1] = 1e-30;
        a[2] = -0.0;
        a[3] = f32::INFINITY;
        a[4] = f32::from_bits(1); // The smallest subnormal.
        let b = a.iter().map(|v| -v).collect();
        (a, b)
    }

    fn bits(data: &[f32]) -> Vec<u32> {
        data.iter().map(|v| v.to_bits()).collect()
    }

    #[test]
    fn irradiance_header_holds_units_wavelength_exposure_and_pose() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("pose.exr");
        let mut img = Image::new(3, 2);
        img.data.fill(0.5);
        let irradiance = Irradiance {
            by_class: PathClass::ALL.iter().map(|_| img.clone()).collect(),
            total: img,
        };
        let sensor_to_base =
            crate::geometry::pose::pose_from_mm_deg([10.0, 20.0, 300.0], [180.0, 0.0, 45.0]);
        let notes = IrradianceNotes {
            wavelength_m: 658e-9,
            exposure_s: 5e-4,
            sensor_to_base,
        };
        write_irradiance_exr(&path, &irradiance, &notes).unwrap();
        let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
        let a = &meta.headers[0].own_attributes;
        assert_eq!(a.exposure, Some(5e-4));
        assert!(a.comments.as_ref().unwrap().to_string().contains("W/m^2"));
        let other = |k: &str| a.other.get(&Text::from(k)).cloned();
        // Exactly the two custom attributes (a reader files both under the layer's).
        assert_eq!(a.other.len(), 2, "{:?}", a.other.keys().collect::<Vec<_>>());
        assert_eq!(
            other("wavelengthNm"),
            Some(AttributeValue::F64(658e-9 * 1e9))
        );
        let Some(AttributeValue::Matrix4x4(m)) = other("sensorToBaseMm") else {
            panic!("no sensorToBaseMm matrix");
        };
        assert_eq!(&m[3..4], &[10.0]);
        assert_eq!(&m[7..8], &[20.0]);
        assert_eq!(&m[11..16], &[300.0, 0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn round_trip_is_bit_exact_and_sorted_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("irradiance.exr");
        let (a, b) = layers();
        // Written in non-alphabetical order on purpose.
        write_exr_layers(&path, WIDTH, HEIGHT, &[("irradiance", &a), ("direct", &b)]).unwrap();
        let read = read_exr_layers(&path).unwrap();
        let names: Vec<&str> = read.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["direct", "irradiance"]);
        for ((_, img), expected) in read.iter().zip([&b, &a]) {
            assert_eq!((img.width, img.height), (WIDTH, HEIGHT));
            assert_eq!(bits(&img.data), bits(expected));
        }
        assert!(read[1].1.data[0].is_nan());
        assert_eq!(read[1].1.data[1], 1e-30);
    }

    #[test]
    fn row_zero_is_the_top_scanline() {
        // Read back through exr's per-pixel API, whose position y = 0 is the top scanline.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("irradiance.exr");
        let (a, _) = layers();
        write_exr_layers(&path, WIDTH, HEIGHT, &[("irradiance", &a)]).unwrap();
        let image = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .specific_channels()
            .required("irradiance")
            .collect_pixels(
                |size, _| vec![vec![0.0f32; size.width()]; size.height()],
                |rows: &mut Vec<Vec<f32>>, position, (v,): (f32,)| {
                    rows[position.y()][position.x()] = v
                },
            )
            .first_valid_layer()
            .all_attributes()
            .from_file(&path)
            .unwrap();
        let rows = &image.layer_data.channel_data.pixels;
        assert_eq!((rows[0].len(), rows.len()), (WIDTH, HEIGHT));
        for r in 0..HEIGHT {
            for c in 0..WIDTH {
                assert_eq!(rows[r][c].to_bits(), a[r * WIDTH + c].to_bits());
            }
        }
    }

    #[test]
    fn wrong_sample_count_names_the_layer() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("irradiance.exr");
        let (a, b) = layers();
        let err = write_exr_layers(
            &path,
            WIDTH,
            HEIGHT,
            &[("irradiance", &a), ("direct", &b[1..])],
        )
        .unwrap_err();
        assert!(matches!(
            err,
            FileError::SampleCount {
                expected: 15,
                found: 14,
                ..
            }
        ));
        assert!(err.to_string().contains("layer \"direct\""), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn bad_layer_lists_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("irradiance.exr");
        let (a, b) = layers();
        let none: &[(&str, &[f32])] = &[];
        let too_long = "n".repeat(256);
        for list in [
            none,
            &[("x", &a), ("x", &b)],
            &[("", &a)],
            &[("λ", &a)],
            &[("a\0b", &a)],
            &[(too_long.as_str(), &a)],
        ] {
            let err = write_exr_layers(&path, WIDTH, HEIGHT, list).unwrap_err();
            assert!(matches!(err, FileError::ExrLayout { .. }), "{err}");
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn names_of_255_characters_are_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("irradiance.exr");
        let (a, _) = layers();
        let name = "é".repeat(255);
        write_exr_layers(&path, WIDTH, HEIGHT, &[(name.as_str(), &a)]).unwrap();
        let read = read_exr_layers(&path).unwrap();
        assert_eq!(read[0].0, name);
        assert_eq!(bits(&read[0].1.data), bits(&a));
    }

    #[test]
    fn f16_channel_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("half.exr");
        let half = vec![exr::prelude::f16::from_f32(0.5); WIDTH * HEIGHT];
        let channel = AnyChannel::new("Y", FlatSamples::F16(half));
        let layer = Layer::new(
            (WIDTH, HEIGHT),
            LayerAttributes::default(),
            Encoding {
                compression: Compression::ZIP16,
                blocks: Blocks::ScanLines,
                line_order: LineOrder::Increasing,
            },
            AnyChannels::sort(SmallVec::from_vec(vec![channel])),
        );
        exr::prelude::Image::from_layer(layer)
            .write()
            .to_file(&path)
            .unwrap();
        let err = read_exr_layers(&path).unwrap_err();
        let message = err.to_string();
        assert!(
            message.contains("half.exr") && message.contains("f16"),
            "{message}"
        );
    }
}
