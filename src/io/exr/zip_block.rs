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

    /// Writes the reordered bytes of the samples `start..start + lo.len() / 2`: bytes 0 and 2
    /// of each sample into `lo`, bytes 1 and 3 into `hi`.
    #[inline]
    fn reorder_into(self, start: usize, lo: &mut [u8], hi: &mut [u8]) {
        fn split(bits: u32, lo: &mut [u8], hi: &mut [u8]) {
            let [b0, b1, b2, b3] = bits.to_le_bytes();
            lo.copy_from_slice(&[b0, b2]);
            hi.copy_from_slice(&[b1, b3]);
        }
        let len = lo.len() / 2;
        let pairs = lo.chunks_exact_mut(2).zip(hi.chunks_exact_mut(2));
        match self {
            Samples::F32(s) => {
                for (v, (l, h)) in s[start..start + len].iter().zip(pairs) {
                    split(v.to_bits(), l, h);
                }
            }
            Samples::F64(s) => {
                for (&v, (l, h)) in s[start..start + len].iter().zip(pairs) {
                    split((v as f32).to_bits(), l, h);
                }
            }
        }
    }
}

/// Buffers reused from block to block by one worker.
#[derive(Default)]
pub(super) struct Scratch {
    reordered: Vec<u8>,
    predicted: Vec<u8>,
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
    let row_bytes = 4 * width;
    let raw_len = rows.len() * channels.len() * row_bytes;
    // Every sample has 4 bytes, so the halves have equal lengths.
    let half = raw_len / 2;
    let reordered = &mut scratch.reordered;
    reordered.resize(raw_len, 0);
    let (lo, hi) = reordered.split_at_mut(half);
    let half_row = row_bytes / 2;
    let mut at = 0;
    for y in rows.clone() {
        for samples in channels {
            let range = at..at + half_row;
            samples.reorder_into(y * width, &mut lo[range.clone()], &mut hi[range]);
            at += half_row;
        }
    }
    predict(reordered, &mut scratch.predicted);

    let compressed = zlib::compress(&scratch.predicted);
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

/// Step 3: `predicted[0] = bytes[0]`, `predicted[i] = bytes[i] - bytes[i - 1] + 128` (mod 256).
fn predict(bytes: &[u8], predicted: &mut Vec<u8>) {
    predicted.clear();
    predicted.extend_from_slice(&bytes[..1.min(bytes.len())]);
    predicted.extend(
        bytes
            .iter()
            .skip(1)
            .zip(bytes)
            .map(|(&b, &before)| b.wrapping_sub(before).wrapping_add(128)),
    );
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
        let a: Vec<f32> = (0..6).map(|i| i as f32 * 1.5 - 2.0).collect();
        let b: Vec<f64> = (0..6).map(|i| 1e-30 * f64::from(i)).collect();
        let channels = [Samples::F32(&a), Samples::F64(&b)];
        // Rows 1..3 of a 3 × 2 image: row by row, channel by channel.
        let mut raw = Vec::new();
        for y in 1..2 {
            raw.extend(a[y * 3..y * 3 + 3].iter().flat_map(|v| v.to_le_bytes()));
            raw.extend(
                b[y * 3..y * 3 + 3]
                    .iter()
                    .flat_map(|&v| (v as f32).to_le_bytes()),
            );
        }
        let mut scratch = Scratch::default();
        let stored = encode(&channels, 3, 1..2, &mut scratch);
        assert_eq!(scratch.predicted, reordered_and_predicted(&raw));
        // 24 bytes do not compress: stored raw.
        assert_eq!(stored, raw);
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
