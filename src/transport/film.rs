//! The film: flux splats collected per chunk of photons, summed in chunk order.

use crate::sensor::image::Image;

/// Flux deposited on one pixel by one camera connection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Row-major pixel index.
    pub pixel: u32,
    /// Flux (W).
    pub flux: f64,
}

/// Sums chunks of splats, in the order given, into an irradiance image (W/m²).
///
/// The order of summation is the chunk order, never the order threads finish in, so the
/// result is bit-identical for any thread count.
pub fn develop<'a>(
    width: usize,
    height: usize,
    pixel_area_m2: f64,
    chunks: impl IntoIterator<Item = &'a [Splat]>,
) -> Image<f64> {
    let mut img = Image::<f64>::new(width, height);
    for chunk in chunks {
        for s in chunk {
            img.data[s.pixel as usize] += s.flux;
        }
    }
    for v in &mut img.data {
        *v /= pixel_area_m2;
    }
    img
}
