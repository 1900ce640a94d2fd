//! 16-bit greyscale PNG for sensor images in digital numbers (DN). Values are stored as given;
//! the caller decides the scaling (a 12-bit ADC's DN are not stretched to 16 bits here).
//! Row 0 of an [`Image`] is the first (top) row of the PNG.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use image::codecs::png::{PngDecoder, PngEncoder};
use image::error::{LimitError, LimitErrorKind};
use image::{ColorType, ExtendedColorType, ImageDecoder, ImageEncoder, ImageError, Limits};

use super::atomic::write_atomic;
use super::error::check_image_size;
use super::FileError;
use crate::sensor::image::Image;

/// Writes `img` as a 16-bit greyscale PNG at `path`, atomically.
pub fn write_png16(path: &Path, img: &Image<u16>) -> Result<(), FileError> {
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

    // The encoder takes native-endian bytes and writes PNG's big-endian samples itself.
    let samples: Vec<u8> = img.data.iter().flat_map(|v| v.to_ne_bytes()).collect();
    // Encoding to memory first means an encoder error never leaves a temporary file behind.
    let mut encoded = Vec::new();
    PngEncoder::new(&mut encoded)
        .write_image(&samples, width, height, ExtendedColorType::L16)
        .map_err(png_error)?;
    write_atomic(path, |w| w.write_all(&encoded))
}

/// Writes a sensor image of `adc_bits`-bit digital numbers left-aligned in 16 bits (DN <<
/// (16 − adc_bits)), as the SDK's container mode does (PARAMETERS.md §1b).
pub fn write_sensor_png16(path: &Path, img: &Image<u16>, adc_bits: u32) -> Result<(), FileError> {
    let shift = 16u32.saturating_sub(adc_bits);
    let shifted = Image {
        width: img.width,
        height: img.height,
        data: img.data.iter().map(|v| v << shift).collect(),
    };
    write_png16(path, &shifted)
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
    fn eight_bit_png_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("eight.png");
        image::save_buffer(&path, &[0u8, 128, 255, 7], 2, 2, ExtendedColorType::L8).unwrap();
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
