//! A plain row-major image buffer, the currency between transport, imager and profile.

/// A row-major image: pixel (column c, row r) is `data[r * width + c]`; row 0 is the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image<T> {
    /// Number of columns.
    pub width: usize,
    /// Number of rows.
    pub height: usize,
    /// Pixels, `width * height` of them.
    pub data: Vec<T>,
}

impl<T: Clone + Default> Image<T> {
    /// A `width` × `height` image filled with `T::default()`.
    pub fn new(width: usize, height: usize) -> Self {
        Image {
            width,
            height,
            data: vec![T::default(); width * height],
        }
    }
}

impl<T: Copy> Image<T> {
    /// The pixel at column `c`, row `r`.
    pub fn get(&self, c: usize, r: usize) -> T {
        self.data[r * self.width + c]
    }
}
