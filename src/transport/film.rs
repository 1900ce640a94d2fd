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
            data: img
                .data
                .iter()
                .map(|v| irradiance(*v, scale, pixel_area_m2))
                .collect(),
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

    /// [`Film::develop`] when no more light will be added: the film's own images become the
    /// irradiance, scaled in place, bit for bit `develop`'s. A pose's film is twelve 4 MB
    /// images (the total and eleven path classes); developing a copy allocated as many again.
    pub fn into_irradiance(self, pixel_area_m2: f64, scale: f64) -> Irradiance {
        let Film {
            mut total,
            mut by_class,
            lit,
        } = self;
        // A class without light keeps its zeros: 0 · scale / area is +0, what `develop` gives.
        let images = by_class.iter_mut().zip(lit).filter(|(_, lit)| *lit);
        for img in std::iter::once(&mut total).chain(images.map(|(img, _)| img)) {
            img.data
                .iter_mut()
                .for_each(|v| *v = irradiance(*v, scale, pixel_area_m2));
        }
        Irradiance { total, by_class }
    }
}

/// The irradiance (W/m²) of a pixel that received `flux` (W, summed splats) scaled by `scale`.
fn irradiance(flux: f64, scale: f64, pixel_area_m2: f64) -> f64 {
    flux * scale / pixel_area_m2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn developing_the_film_itself_gives_the_developed_copy_bit_for_bit() {
        let mut film = Film::new(7, 5);
        // Two classes lit, several splats on one pixel, fluxes that round when scaled.
        let splats: Vec<Splat> = (0..40u32)
            .map(|i| Splat {
                pixel: (i * 13) % 35,
                class: if i % 3 == 0 {
                    PathClass::Glint
                } else {
                    PathClass::ALL[0]
                },
                flux: 1e-9 * f64::from(i + 1) / 3.0,
            })
            .collect();
        film.add(&splats);
        let (area, scale) = (9.4e-6 * 9.4e-6, 1.0 / 262_144.0);
        let copy = film.develop(area, scale);
        let own = film.into_irradiance(area, scale);
        let bits = |i: &Irradiance| -> Vec<u64> {
            std::iter::once(&i.total)
                .chain(&i.by_class)
                .flat_map(|img| img.data.iter().map(|v| v.to_bits()))
                .collect()
        };
        assert_eq!(bits(&own), bits(&copy));
        assert_eq!(own.by_class.len(), PathClass::ALL.len());
        assert!(own.total.data.iter().any(|&v| v > 0.0));
    }
}
