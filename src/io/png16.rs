//! 16-bit greyscale PNG for sensor images in digital numbers (DN). Values are stored as given;
//! the caller decides the scaling (a 12-bit ADC's DN are not stretched to 16 bits here).
//! Row 0 of an [`Image`] is the first (top) row of the PNG.
//!
//! A sensor image says how it is encoded in the file itself: an `sBIT` chunk with the ADC's bit
//! depth (PNG 1.2 §4.2.6: the original samples are the top `sBIT` bits of each 16-bit sample,
//! which is how [`write_sensor_png16`] stores them) and a `tEXt` `Description` in words
//! ("DN = value >> 6"), with `Software` naming glassscan's version.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use image::codecs::png::PngDecoder;
use image::error::{EncodingError, ImageFormatHint, LimitError, LimitErrorKind};
use image::{ColorType, ImageDecoder, ImageError, ImageFormat, Limits};

use super::atomic::write_atomic;
use super::error::check_image_size;
use super::FileError;
use crate::sensor::image::Image;

/// What a PNG says about its samples besides the pixels.
#[derive(Clone, Debug, Default, PartialEq)]
struct PngNotes {
    /// Significant bits per sample (`sBIT`), if fewer than 16 carry the data.
    significant_bits: Option<u8>,
    /// `tEXt` chunks (keyword, Latin-1 text).
    text: Vec<(&'static str, String)>,
}

/// Writes `img` as a 16-bit greyscale PNG at `path`, atomically.
pub fn write_png16(path: &Path, img: &Image<u16>) -> Result<(), FileError> {
    write_png16_with(path, img, &PngNotes::default())
}

fn write_png16_with(path: &Path, img: &Image<u16>, notes: &PngNotes) -> Result<(), FileError> {
    check_image_size(
        path,
        || "image".to_string(),
        img.width,
        img.height,
        img.data.len(),
    )?;
    let png_error = |source| FileError::Png {
        path: path.to_path_buf(),
        expected: "an image the PNG encoder accepts",
        source,
    };
    let too_large = || {
        png_error(ImageError::Limits(LimitError::from_kind(
            LimitErrorKind::DimensionError,
        )))
    };
    let width = u32::try_from(img.width).map_err(|_| too_large())?;
    let height = u32::try_from(img.height).map_err(|_| too_large())?;

    // PNG samples are big-endian.
    let samples: Vec<u8> = img.data.iter().flat_map(|v| v.to_be_bytes()).collect();
    // Encoding to memory first means an encoder error never leaves a temporary file behind.
    let encoded = encode(&samples, width, height, notes).map_err(|e| {
        png_error(ImageError::Encoding(EncodingError::new(
            ImageFormatHint::Exact(ImageFormat::Png),
            e,
        )))
    })?;
    write_atomic(path, |w| w.write_all(&encoded))
}

/// The PNG file of big-endian 16-bit greyscale `samples`, with `notes` before the image data.
fn encode(
    samples: &[u8],
    width: u32,
    height: u32,
    notes: &PngNotes,
) -> Result<Vec<u8>, png::EncodingError> {
    let mut encoded = Vec::new();
    let mut encoder = png::Encoder::new(&mut encoded, width, height);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Sixteen);
    // fdeflate's fast mode, as image's encoder used: the default (Balanced) makes sensor images
    // 2.8× smaller but costs 25 % more CPU on a 2¹⁴-photon scan (farm-bench, edge_study_bare).
    encoder.set_compression(png::Compression::Fast);
    for (keyword, text) in &notes.text {
        encoder.add_text_chunk((*keyword).to_owned(), text.clone())?;
    }
    let mut writer = encoder.write_header()?;
    if let Some(bits) = notes.significant_bits {
        // sBIT precedes the image data (PNG 1.2 §4.2.6); one byte for greyscale.
        writer.write_chunk(png::chunk::sBIT, &[bits])?;
    }
    writer.write_image_data(samples)?;
    writer.finish()?;
    Ok(encoded)
}

/// Writes a sensor image of `adc_bits`-bit digital numbers left-aligned in 16 bits (DN <<
/// (16 − adc_bits)), as the scanCONTROL SDK's container mode delivers them, with `sBIT` =
/// `adc_bits` and a `Description` that says so.
pub fn write_sensor_png16(path: &Path, img: &Image<u16>, adc_bits: u32) -> Result<(), FileError> {
    let bits = adc_bits.clamp(1, 16);
    let shift = 16 - bits;
    let shifted = Image {
        width: img.width,
        height: img.height,
        data: img.data.iter().map(|v| v << shift).collect(),
    };
    let notes = PngNotes {
        significant_bits: Some(bits as u8),
        text: vec![
            (
                "Description",
                format!(
                    "glassscan sensor image: {bits}-bit digital numbers (DN) left-aligned in \
                     16 bits; DN = value >> {shift}. Row 0 is the top of the sensor."
                ),
            ),
            (
                "Software",
                format!("glassscan {}", env!("CARGO_PKG_VERSION")),
            ),
        ],
    };
    write_png16_with(path, &shifted, &notes)
}

/// Reads a 16-bit greyscale PNG written by [`write_png16`] (or any other L16 PNG). Any other
/// colour type or bit depth is refused with [`FileError::PngFormat`], never converted.
pub fn read_png16(path: &Path) -> Result<Image<u16>, FileError> {
    let file = File::open(path).map_err(|e| FileError::io(path, "open", e))?;
    let png_error = |source| FileError::Png {
        path: path.to_path_buf(),
        expected: "a valid PNG file",
        source,
    };
    // The default limits (512 MiB) keep a corrupt header from asking for an absurd allocation.
    let decoder =
        PngDecoder::with_limits(BufReader::new(file), Limits::default()).map_err(png_error)?;
    let color_type = decoder.color_type();
    if color_type != ColorType::L16 {
        return Err(FileError::PngFormat {
            path: path.to_path_buf(),
            found: format!("{color_type:?}"),
        });
    }
    let (width, height) = decoder.dimensions();
    // Within the decoder's limits, so this fits in memory and in usize.
    let mut bytes = vec![0u8; decoder.total_bytes() as usize];
    decoder.read_image(&mut bytes).map_err(png_error)?;
    // The decoder hands out native-endian samples.
    let data = bytes
        .chunks_exact(2)
        .map(|b| u16::from_ne_bytes([b[0], b[1]]))
        .collect();
    Ok(Image {
        width: width as usize,
        height: height as usize,
        data,
    })
}

/// Reads a sensor image written by [`write_sensor_png16`] as digital numbers: the samples
/// shifted down by 16 − `sBIT` (`sBIT` absent: as stored, every bit significant).
pub fn read_sensor_png16(path: &Path) -> Result<Image<u16>, FileError> {
    let mut img = read_png16(path)?;
    let bits = significant_bits(path)?.unwrap_or(16).clamp(1, 16);
    let shift = 16 - u32::from(bits);
    if shift > 0 {
        img.data.iter_mut().for_each(|v| *v >>= shift);
    }
    Ok(img)
}

/// The greyscale `sBIT` value of the PNG at `path`, if it has one.
fn significant_bits(path: &Path) -> Result<Option<u8>, FileError> {
    let file = File::open(path).map_err(|e| FileError::io(path, "open", e))?;
    // read_info stops at the first image data chunk, after sBIT (PNG 1.2 §4.2.6).
    let reader = png::Decoder::new(BufReader::new(file))
        .read_info()
        .map_err(|e| FileError::Png {
            path: path.to_path_buf(),
            expected: "a valid PNG file",
            source: ImageError::Decoding(image::error::DecodingError::new(
                ImageFormatHint::Exact(ImageFormat::Png),
                e,
            )),
        })?;
    Ok(reader.info().sbit.as_ref().and_then(|b| b.first().copied()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-square 7 × 5 gradient: value grows along rows and, faster, down columns, with the
    /// extremes 0 (top left) and 65535 (bottom right).
    fn gradient() -> Image<u16> {
        let (width, height) = (7, 5);
        let mut img = Image::new(width, height);
        for r in 0..height {
            for c in 0..width {
                img.data[r * width + c] = (r * 1000 + c * 7) as u16;
            }
        }
        img.data[0] = 0;
        img.data[width * height - 1] = u16::MAX;
        img
    }

    #[test]
    fn round_trip_is_bit_exact() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frame.png");
        let img = gradient();
        write_png16(&path, &img).unwrap();
        assert_eq!(read_png16(&path).unwrap(), img);
    }

    #[test]
    fn row_zero_is_the_top_row_of_the_png() {
        // An independent decoder (the `image` crate's generic one, y = 0 at the top) must see
        // the same pixel at (c, r) as `Image::get(c, r)`.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frame.png");
        let img = gradient();
        write_png16(&path, &img).unwrap();
        let decoded = image::open(&path).unwrap().into_luma16();
        assert_eq!(decoded.dimensions(), (7, 5));
        for r in 0..img.height {
            for c in 0..img.width {
                assert_eq!(decoded.get_pixel(c as u32, r as u32).0[0], img.get(c, r));
            }
        }
    }

    #[test]
    fn a_sensor_png_states_its_bit_depth_and_encoding() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sensor.png");
        let mut img = Image::new(3, 2);
        img.data.copy_from_slice(&[0, 1, 2, 511, 1022, 1023]);
        write_sensor_png16(&path, &img, 10).unwrap();
        // An independent reader (the png crate's decoder) finds sBIT = 10 and the text.
        let decoder = png::Decoder::new(BufReader::new(File::open(&path).unwrap()));
        let reader = decoder.read_info().unwrap();
        let info = reader.info();
        assert_eq!(info.sbit.as_deref(), Some(&[10u8][..]));
        let text: Vec<(&str, &str)> = info
            .uncompressed_latin1_text
            .iter()
            .map(|t| (t.keyword.as_str(), t.text.as_str()))
            .collect();
        assert!(
            text.iter()
                .any(|(k, t)| *k == "Description" && t.contains("DN = value >> 6")),
            "{text:?}"
        );
        assert!(text
            .iter()
            .any(|(k, t)| *k == "Software" && t.starts_with("glassscan ")));
        // The samples are the DN << 6.
        let read = read_png16(&path).unwrap();
        let dn: Vec<u16> = read.data.iter().map(|v| v >> 6).collect();
        assert_eq!(dn, img.data);
        assert!(read.data.iter().all(|v| v & 0x3f == 0));
        // read_sensor_png16 undoes the alignment by the file's own sBIT.
        assert_eq!(read_sensor_png16(&path).unwrap(), img);
        for bits in [8, 12, 16] {
            let max = ((1u32 << bits) - 1) as u16;
            img.data.copy_from_slice(&[0, 1, 2, max / 2, max - 1, max]);
            write_sensor_png16(&path, &img, bits).unwrap();
            assert_eq!(read_sensor_png16(&path).unwrap(), img, "{bits} bits");
        }
        // Without sBIT every bit is significant.
        write_png16(&path, &gradient()).unwrap();
        assert_eq!(read_sensor_png16(&path).unwrap(), gradient());
    }

    #[test]
    fn eight_bit_png_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("eight.png");
        image::save_buffer(
            &path,
            &[0u8, 128, 255, 7],
            2,
            2,
            image::ExtendedColorType::L8,
        )
        .unwrap();
        let err = read_png16(&path).unwrap_err();
        assert!(matches!(err, FileError::PngFormat { .. }), "{err}");
        let message = err.to_string();
        assert!(
            message.contains("eight.png") && message.contains("L8"),
            "{message}"
        );
    }

    #[test]
    fn garbage_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("garbage.png");
        std::fs::write(&path, b"not a png at all").unwrap();
        let err = read_png16(&path).unwrap_err();
        assert!(matches!(err, FileError::Png { .. }), "{err}");
        assert!(err.to_string().contains("garbage.png"), "{err}");
    }

    #[test]
    fn inconsistent_image_is_refused_before_any_file_is_made() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frame.png");
        let mut img = gradient();
        img.data.pop();
        let err = write_png16(&path, &img).unwrap_err();
        assert!(matches!(
            err,
            FileError::SampleCount {
                expected: 35,
                found: 34,
                ..
            }
        ));
        let empty = Image::<u16>::new(0, 3);
        let err = write_png16(&path, &empty).unwrap_err();
        assert!(matches!(err, FileError::EmptyImage { .. }), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
