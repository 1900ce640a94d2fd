//! The film: flux splats collected per chunk of photons, summed in chunk order, per path class.

use crate::sensor::image::Image;
use crate::sensor::path_class::PathClass;

/// Flux deposited on one pixel by one camera connection or glint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Row-major pixel index.
    pub pixel: u32,
    /// What produced it.
    pub class: PathClass,
    /// Flux (W).
    pub flux: f64,
}

/// Irradiance on the image plane, in total and per path class (W/m²).
#[derive(Clone, Debug, PartialEq)]
pub struct Irradiance {
    /// The sum of all classes.
    pub total: Image<f64>,
    /// One image per class, in [`PathClass::ALL`] order.
    pub by_class: Vec<Image<f64>>,
}

/// Sums chunks of splats, in the order given, into irradiance images (W/m²).
///
/// The order of summation is the chunk order, never the order threads finish in, so the
/// result is bit-identical for any thread count.
pub fn develop<'a>(
    width: usize,
    height: usize,
    pixel_area_m2: f64,
    chunks: impl IntoIterator<Item = &'a [Splat]>,
) -> Irradiance {
    let mut total = Image::<f64>::new(width, height);
    let mut by_class = vec![Image::<f64>::new(width, height); PathClass::ALL.len()];
    for chunk in chunks {
        for s in chunk {
            total.data[s.pixel as usize] += s.flux;
            by_class[s.class.index()].data[s.pixel as usize] += s.flux;
        }
    }
    for img in std::iter::once(&mut total).chain(by_class.iter_mut()) {
        for v in &mut img.data {
            *v /= pixel_area_m2;
        }
    }
    Irradiance { total, by_class }
}
