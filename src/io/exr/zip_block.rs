//! One scanline block under OpenEXR's ZIP_COMPRESSION (OpenEXR File Layout, "Scan Line
//! Blocks"; the reordering and the predictor are those of `Zip::compress` in OpenEXR's
//! `ImfZip.cpp`):
//!
//! 1. The block's samples in file order: scanline by scanline, and within a scanline channel
//!    by channel (in the header's, sorted, order), each channel's row of little-endian f32.
//! 2. Reordering: the bytes at even positions of that sequence, then those at odd positions
//!    (for 4-byte samples: every sample's bytes 0 and 2 in the first half, 1 and 3 in the
//!    second), so that the slowly varying high bytes sit together.
//! 3. Predictor: every byte but the first is replaced by its difference from the byte before it
//!    (in the reordered sequence, the first half running on into the second) plus 128, modulo
//!    256; a run of equal bytes becomes a run of 128s.
//! 4. A zlib stream of that. If the stream is not shorter than the block's raw bytes, the raw
//!    bytes of step 1 are stored instead: a reader takes a block whose size equals its raw
//!    size as uncompressed.

use super::zlib;

/// Scanlines per block under ZIP_COMPRESSION.
pub(super) const LINES_PER_BLOCK: usize = 16;

/// One channel's samples, row-major; f64 samples are stored rounded to f32 (`as f32`).
#[derive(Clone, Copy, Debug)]
pub(super) enum Samples<'a> {
    /// Stored as they are.
    F32(&'a [f32]),
    /// Rounded to the nearest f32.
    F64(&'a [f64]),
}

impl Samples<'_> {
    /// Calls `f` with the f32 bits of the samples `start..start + len`, in order.
    #[inline]
    fn for_each_bits(self, start: usize, len: usize, mut f: impl FnMut(u32)) {
        match self {
            Samples::F32(s) => s[start..start + len].iter().for_each(|v| f(v.to_bits())),
            Samples::F64(s) => s[start..start + len]
                .iter()
                .for_each(|&v| f((v as f32).to_bits())),
        }
    }

    /// The f32 bits of the samples `start..start + bits.len()`, into `bits`.
    #[inline]
    fn bits_into(self, start: usize, bits: &mut [u32]) {
        let len = bits.len();
        match self {
            Samples::F32(s) => {
                for (b, v) in bits.iter_mut().zip(&s[start..start + len]) {
                    *b = v.to_bits();
                }
            }
            Samples::F64(s) => {
                for (b, &v) in bits.iter_mut().zip(&s[start..start + len]) {
                    *b = (v as f32).to_bits();
                }
            }
        }
    }

    /// Whether the samples `start..start + len` are all stored as +0 (the bits of f64 +0 are
    /// zero, and so are those of f32 +0). Rows of zeros are common: most path classes are dark.
    #[inline]
    fn all_zero(self, start: usize, len: usize) -> bool {
        match self {
            Samples::F32(s) => s[start..start + len].iter().fold(0, |a, v| a | v.to_bits()) == 0,
            Samples::F64(s) => s[start..start + len].iter().fold(0, |a, v| a | v.to_bits()) == 0,
        }
    }

    /// The f32 bits of sample `i`.
    fn bits(self, i: usize) -> u32 {
        match self {
            Samples::F32(s) => s[i].to_bits(),
            Samples::F64(s) => (s[i] as f32).to_bits(),
        }
    }
}

/// Buffers reused from block to block by one worker.
#[derive(Default)]
pub(super) struct Scratch {
    /// One row's sample bits, after the bits of the sample before the row.
    row: Vec<u32>,
    /// The predicted bytes in pairs, each pair's first byte the least significant (u16 pairs
    /// are what the loop below fills in SIMD registers).
    predicted: Vec<u16>,
    zlib: zlib::Scratch,
}

#[cfg(test)]
impl Scratch {
    /// The predicted bytes of the last block.
    fn predicted(&self) -> &[u8] {
        bytemuck::cast_slice(&self.predicted)
    }
}

/// The stored bytes of the block of scanlines `rows` of `channels` (each `width` samples a
/// row, in the header's order): the ZIP_COMPRESSION stream, or the raw bytes when that is not
/// shorter.
pub(super) fn encode(
    channels: &[Samples],
    width: usize,
    rows: std::ops::Range<usize>,
    scratch: &mut Scratch,
) -> Vec<u8> {
    let raw_len = rows.len() * channels.len() * 4 * width;
    predict(channels, width, rows.clone(), scratch);
    let compressed = zlib::compress(bytemuck::cast_slice(&scratch.predicted), &mut scratch.zlib);
    if compressed.len() < raw_len {
        return compressed;
    }
    let mut raw = Vec::with_capacity(raw_len);
    for y in rows {
        for samples in channels {
            samples.for_each_bits(y * width, width, |b| {
                raw.extend_from_slice(&b.to_le_bytes())
            });
        }
    }
    raw
}

/// (a - b + 128) mod 256 of two bytes, in u32 lanes.
#[inline]
fn delta(a: u32, b: u32) -> u32 {
    (a + 0x180 - b) & 0xff
}

/// Steps 1–3 in one pass, into `scratch.predicted`.
///
/// In the reordered sequence a sample's bytes 0 and 2 follow byte 2 of the sample before it
/// (first half), its bytes 1 and 3 follow that one's byte 3 (second half), so each row's
/// predicted bytes are a function of its samples and the sample before the row alone. Two
/// bytes have other predecessors: the very first byte has none (it is stored as it is), and
/// the second half's first byte follows the first half's last byte, byte 2 of the block's last
/// sample. A made-up sample before the block gives both: byte 2 = 128, byte 3 = that byte.
fn predict(
    channels: &[Samples],
    width: usize,
    rows: std::ops::Range<usize>,
    scratch: &mut Scratch,
) {
    let half = rows.len() * channels.len() * width;
    scratch.predicted.resize(2 * half, 0);
    let (lo, hi) = scratch.predicted.split_at_mut(half);
    let row = &mut scratch.row;
    row.resize(width + 1, 0);
    let last = channels[channels.len() - 1].bits((rows.end - 1) * width + width - 1);
    row[width] = (last >> 16 & 0xff) << 24 | 128 << 16;

    let mut at = 0;
    for y in rows {
        for samples in channels {
            // The sample before this row: the last of the row before.
            let before = row[width];
            let (lo_row, hi_row) = (&mut lo[at..at + width], &mut hi[at..at + width]);
            at += width;
            if samples.all_zero(y * width, width) {
                // Only the first pair differs from 128, 128.
                lo_row.fill(0x8080);
                hi_row.fill(0x8080);
                lo_row[0] = ((delta(0, before >> 16 & 0xff) | 128 << 8) as u16).to_le();
                hi_row[0] = ((delta(0, before >> 24) | 128 << 8) as u16).to_le();
                row[width] = 0;
                continue;
            }
            row[0] = before;
            samples.bits_into(y * width, &mut row[1..]);
            let pairs = lo_row.iter_mut().zip(hi_row);
            for ((&x, &before), (l, h)) in row[1..].iter().zip(&row[..width]).zip(pairs) {
                let (b0, b1, b2, b3) = (x & 0xff, x >> 8 & 0xff, x >> 16 & 0xff, x >> 24);
                let (before2, before3) = (before >> 16 & 0xff, before >> 24);
                *l = ((delta(b0, before2) | delta(b2, b0) << 8) as u16).to_le();
                *h = ((delta(b1, before3) | delta(b3, b1) << 8) as u16).to_le();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block's bytes before compression, by the steps as the module docs state them.
    fn reordered_and_predicted(raw: &[u8]) -> Vec<u8> {
        let mut t: Vec<u8> = raw.iter().step_by(2).copied().collect();
        t.extend(raw.iter().skip(1).step_by(2));
        let mut p = t[0];
        for v in &mut t[1..] {
            let b = *v;
            *v = (i32::from(b) - i32::from(p) + 128 + 256) as u8;
            p = b;
        }
        t
    }

    #[test]
    fn reorder_and_predictor_follow_the_spec() {
        // A 3 × 3 image of four channels: f32 values, f64 values (rounded to f32), a row of
        // zeros between others, and one of zeros first.
        let a: Vec<f32> = (0..9).map(|i| i as f32 * 1.5 - 2.0).collect();
        let b: Vec<f64> = (0..9).map(|i| 1e-30 * f64::from(i) - 3e-31).collect();
        let zeros = vec![0.0f64; 9];
        let mut c = vec![0.0f32; 9];
        c[4] = -0.0;
        c[6] = f32::from_bits(0xffc1_2345);
        let channels = [
            Samples::F64(&zeros),
            Samples::F32(&a),
            Samples::F64(&zeros),
            Samples::F64(&b),
            Samples::F32(&c),
        ];
        let mut scratch = Scratch::default();
        for rows in [0..3, 1..3, 2..3] {
            // Row by row, channel by channel.
            let mut raw = Vec::new();
            for y in rows.clone() {
                for samples in &channels {
                    samples.for_each_bits(y * 3, 3, |v| raw.extend_from_slice(&v.to_le_bytes()));
                }
            }
            let stored = encode(&channels, 3, rows.clone(), &mut scratch);
            assert_eq!(
                scratch.predicted(),
                reordered_and_predicted(&raw),
                "{rows:?}"
            );
            if stored.len() == raw.len() {
                assert_eq!(stored, raw, "{rows:?}");
            } else {
                let inflated = miniz_oxide::inflate::decompress_to_vec_zlib(&stored).unwrap();
                assert_eq!(inflated, reordered_and_predicted(&raw), "{rows:?}");
            }
        }
        // One row of four channels, 48 bytes, does not compress: stored raw.
        let stored = encode(&channels[1..], 3, 1..2, &mut scratch);
        assert_eq!(stored.len(), 48);
    }

    #[test]
    fn a_compressible_block_is_a_zlib_stream_of_the_predicted_bytes() {
        let zeros = vec![0.0f32; 64 * 16];
        let mut scratch = Scratch::default();
        let stored = encode(&[Samples::F32(&zeros)], 64, 0..16, &mut scratch);
        assert!(stored.len() < zeros.len() * 4);
        let inflated = miniz_oxide::inflate::decompress_to_vec_zlib(&stored).unwrap();
        let mut expected = vec![128u8; zeros.len() * 4];
        expected[0] = 0;
        assert_eq!(inflated, expected);
    }
}
