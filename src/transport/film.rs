//! The film: flux splats of each chunk of photons, summed in chunk order, per path class.

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

/// Splats summed into images as they come, in the order given (flux per pixel, W). The
/// tracer adds chunks in chunk order, never in the order threads finish them, so the result
/// is bit-identical for any thread count.
#[derive(Clone, Debug)]
pub struct Film {
    total: Image<f64>,
    by_class: Vec<Image<f64>>,
    /// Whether class k received a splat. A pose lights about half of the classes; the others
    /// stay untouched zero pages, which developing would otherwise write over (a few ms and
    /// 4 MB of page faults each).
    lit: Vec<bool>,
}

impl Film {
    /// An unexposed film of `width × height` pixels.
    pub fn new(width: usize, height: usize) -> Film {
        Film {
            total: Image::<f64>::new(width, height),
            by_class: (0..PathClass::ALL.len())
                .map(|_| Image::<f64>::new(width, height))
                .collect(),
            lit: vec![false; PathClass::ALL.len()],
        }
    }

    /// Adds one chunk's splats, in order.
    pub fn add(&mut self, chunk: &[Splat]) {
        for s in chunk {
            self.total.data[s.pixel as usize] += s.flux;
            self.by_class[s.class.index()].data[s.pixel as usize] += s.flux;
            self.lit[s.class.index()] = true;
        }
    }

    /// The irradiance (W/m²) for pixels of `pixel_area_m2`, each splat's flux scaled by
    /// `scale` (the tracer's 1/photons). The film stays as it is, so more can be added.
    pub fn develop(&self, pixel_area_m2: f64, scale: f64) -> Irradiance {
        let develop = |img: &Image<f64>| Image {
            width: img.width,
            height: img.height,
            data: img.data.iter().map(|v| v * scale / pixel_area_m2).collect(),
        };
        let by_class = self
            .by_class
            .iter()
            .zip(&self.lit)
            .map(|(img, &lit)| {
                if lit {
                    develop(img)
                } else {
                    Image::<f64>::new(img.width, img.height)
                }
            })
            .collect();
        Irradiance {
            total: develop(&self.total),
            by_class,
        }
    }
}
