//! zlib streams (RFC 1950) of ZIP blocks, made for what OpenEXR's predictor leaves of an
//! irradiance image: most of it runs of 128 (zero samples: many path classes are dark in a
//! pose, and the rest mostly so), some noise-like bytes (the lit pixels' low mantissa bytes),
//! and rows repeated a few kilobytes back (the `irradiance` total equals a class wherever one
//! class carries all the light).
//!
//! One deflate block with dynamic Huffman codes ([`super::deflate_block`]) of greedy matches:
//! at each byte the run of the byte before it (a match at distance 1, found 8 bytes at a time)
//! and the last earlier position with the same 4 bytes (a hash table, looked up and filled
//! only where no 258-byte run goes on, so long runs cost one comparison per 8 bytes) are
//! compared, and the longer match wins, else a literal. The Adler-32 checksum of a run is
//! computed in closed form, so runs are never summed byte by byte.
//!
//! Candidates measured (2026-12-03, the project's 2-core machine, shared: best of 5, one
//! thread) on the predicted blocks of real irradiance images (`glassscan scan
//! scenes/edge_study_bare.toml`, 640 × 832 × 12 f32 = 25.6 MB raw a pose): ms and bytes a
//! pose, mean of 6 poses at 1000 and 65 536 photons, and one pose at 2^20 photons. "Runs +
//! hash" is this module's algorithm as first written (a prototype in the same harness; the
//! module since scans runs 32 bytes a step and reduces Adler-32 once a megabyte).
//!
//! | zlib encoder | 1000 / 65 536 photons | 2^20 photons |
//! |---|---|---|
//! | miniz_oxide level 4 (the `exr` crate's) | 31–43 ms, 62.8 kB | 33–49 ms, 248 kB |
//! | miniz_oxide level 1 | 8–11 ms, 161 kB | 10–15 ms, 357 kB |
//! | zlib-rs (flate2) level 1 | 16–20 ms, 282 kB | 16–24 ms, 464 kB |
//! | zlib-rs (flate2) level 2 | 16–22 ms, 64.3 kB | 22–26 ms, 254 kB |
//! | libdeflate (libdeflater, C) level 3 | 26–37 ms, 65.6 kB | 27–39 ms, 255 kB |
//! | fdeflate (the `png` crate's) | 19–25 ms, nothing gained: every block stored raw | same |
//! | runs only (distance 1) | 2.0–2.6 ms, 89.0 kB | 3.4–3.5 ms, 400 kB |
//! | runs + hash (this module) | 2.5–3.0 ms, 64.4 kB | 4.6–4.7 ms, 254 kB |
//!
//! fdeflate only matches runs of zero bytes and codes literals with a table made for PNG: here
//! the runs are of 128. The hash table brings the size down to miniz_oxide's: byte strings other
//! than runs repeat too (for one, the `irradiance` total repeats a class's row wherever that
//! class carries all the light).

use super::deflate_block::{self, Frequencies, Token, MAX_MATCH, MIN_MATCH, WINDOW};

/// log₂ of the hash table's size.
const HASH_BITS: u32 = 15;
/// Bytes a hash covers, the shortest match looked up by hash (runs are taken from 3 bytes).
const HASHED: usize = 4;

/// Buffers reused from stream to stream by one worker.
#[derive(Default)]
pub(super) struct Scratch {
    tokens: Vec<Token>,
    freqs: Frequencies,
    /// The hash table: the last position with each hash, plus `base`.
    table: Vec<u32>,
    /// What this stream's positions are stored plus: above every entry of earlier streams, so
    /// those are told from this one's and never used, and a stream depends on its data alone,
    /// not on what the worker compressed before (the table is not cleared for every stream).
    base: u32,
}

/// The zlib stream of `data` (at most 2^31 bytes).
pub(super) fn compress(data: &[u8], scratch: &mut Scratch) -> Vec<u8> {
    let Scratch {
        tokens,
        freqs,
        table,
        base,
    } = scratch;
    tokens.clear();
    freqs.clear();
    let n = data.len();
    let base = match base.checked_add(1).and_then(|b| b.checked_add(n as u32)) {
        Some(next) if !table.is_empty() => std::mem::replace(base, next),
        _ => {
            // First use, or the stored positions would overflow: start afresh.
            table.clear();
            table.resize(1 << HASH_BITS, 0);
            *base = 1 + n as u32;
            1
        }
    };
    let mut adler = Adler32::default();
    let mut i = 0;
    while i < n {
        let run = if i > 0 { run_length(data, i) } else { 0 };
        let (mut length, mut distance) = (run, 1);
        if run < MAX_MATCH && i + HASHED <= n {
            let slot = &mut table[hash(&data[i..i + HASHED])];
            let stored = *slot;
            *slot = base + i as u32;
            if stored >= base && i - (stored - base) as usize <= WINDOW {
                let earlier = (stored - base) as usize;
                let common = common_length(data, earlier, i);
                if common >= HASHED && common > run {
                    (length, distance) = (common, i - earlier);
                }
            }
        }
        if length >= MIN_MATCH {
            tokens.push(Token::copy(length, distance));
            freqs.copy(length, distance);
            if distance == 1 {
                adler.run(data[i - 1], length);
            } else {
                data[i..i + length].iter().for_each(|&b| adler.byte(b));
            }
            i += length;
        } else {
            tokens.push(Token::literal(data[i]));
            freqs.literal(data[i]);
            adler.byte(data[i]);
            i += 1;
        }
    }
    let mut out = Vec::with_capacity(64 + tokens.len() * 5 / 4);
    // CMF: deflate with a 32 KiB window; FLG: no dictionary, "fastest", and the check bits
    // that make CMF·256 + FLG a multiple of 31.
    out.extend_from_slice(&[0x78, 0x01]);
    let mut out = deflate_block::write(tokens, freqs, out);
    out.extend_from_slice(&adler.finish().to_be_bytes());
    out
}

/// How many bytes from `at` on (at most [`MAX_MATCH`]) equal the byte before `at`.
#[inline]
fn run_length(data: &[u8], at: usize) -> usize {
    let end = (at + MAX_MATCH).min(data.len());
    let byte = data[at - 1];
    let pattern = u64::from_ne_bytes([byte; 8]);
    let mut i = at;
    // 32 bytes a step through long runs, then 8 to find where the run ends.
    let word = |i: usize| u64::from_le_bytes(data[i..i + 8].try_into().expect("8 bytes"));
    while i + 32 <= end {
        let x = (word(i) ^ pattern)
            | (word(i + 8) ^ pattern)
            | (word(i + 16) ^ pattern)
            | (word(i + 24) ^ pattern);
        if x != 0 {
            break;
        }
        i += 32;
    }
    while i + 8 <= end {
        let x = word(i) ^ pattern;
        if x != 0 {
            return i - at + (x.trailing_zeros() / 8) as usize;
        }
        i += 8;
    }
    i - at + data[i..end].iter().take_while(|&&b| b == byte).count()
}

/// How many bytes from `at` on (at most [`MAX_MATCH`]) equal those from `earlier` on.
#[inline]
fn common_length(data: &[u8], earlier: usize, at: usize) -> usize {
    let limit = MAX_MATCH.min(data.len() - at);
    let word = |i: usize| u64::from_le_bytes(data[i..i + 8].try_into().expect("8 bytes"));
    let mut k = 0;
    while k + 8 <= limit {
        let x = word(earlier + k) ^ word(at + k);
        if x != 0 {
            return k + (x.trailing_zeros() / 8) as usize;
        }
        k += 8;
    }
    k + data[earlier + k..earlier + limit]
        .iter()
        .zip(&data[at + k..at + limit])
        .take_while(|(a, b)| a == b)
        .count()
}

/// The hash table slot of 4 bytes (Fibonacci hashing).
#[inline]
fn hash(bytes: &[u8]) -> usize {
    let v = u32::from_le_bytes(bytes.try_into().expect("4 bytes"));
    (v.wrapping_mul(0x9e37_79b1) >> (32 - HASH_BITS)) as usize
}

/// The Adler-32 checksum (RFC 1950 §8.2): a = 1 + Σ bytes, b = Σ a after each byte, mod 65521.
/// Kept in u64 and reduced every [`ADLER_REDUCE`] bytes: one division per megabyte, not per
/// run.
struct Adler32 {
    a: u64,
    b: u64,
    /// Bytes added since a and b were last reduced.
    pending: u64,
}

const ADLER_MOD: u64 = 65_521;
/// Bytes after which a and b are reduced: from reduced values, b stays below
/// 65521·(1 + N) + 255·N(N + 1)/2 < 2^48 for N = 2^20 + 258 (a run may end past the mark).
const ADLER_REDUCE: u64 = 1 << 20;

impl Default for Adler32 {
    fn default() -> Self {
        Adler32 {
            a: 1,
            b: 0,
            pending: 0,
        }
    }
}

impl Adler32 {
    #[inline]
    fn byte(&mut self, byte: u8) {
        self.a += u64::from(byte);
        self.b += self.a;
        self.pending += 1;
        if self.pending >= ADLER_REDUCE {
            self.reduce();
        }
    }

    /// `length` (≤ 258) bytes of `byte`: a gains length·byte, b gains length·a plus
    /// byte·length(length + 1)/2.
    #[inline]
    fn run(&mut self, byte: u8, length: usize) {
        let (v, l) = (u64::from(byte), length as u64);
        self.b += l * self.a + v * (l * (l + 1) / 2);
        self.a += l * v;
        self.pending += l;
        if self.pending >= ADLER_REDUCE {
            self.reduce();
        }
    }

    fn reduce(&mut self) {
        self.a %= ADLER_MOD;
        self.b %= ADLER_MOD;
        self.pending = 0;
    }

    fn finish(mut self) -> u32 {
        self.reduce();
        (self.b << 16 | self.a) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Adler-32 straight from RFC 1950.
    fn adler32_by_definition(data: &[u8]) -> u32 {
        let (mut a, mut b) = (1u64, 0u64);
        for &x in data {
            a = (a + u64::from(x)) % 65_521;
            b = (b + a) % 65_521;
        }
        (b << 16 | a) as u32
    }

    /// Byte strings that exercise every path: runs of every length around 258, runs of 0 and
    /// 255, repeats far back, noise, and the edges of the window.
    fn samples() -> Vec<Vec<u8>> {
        let mut state = 1u64;
        let mut noise = |n: usize| -> Vec<u8> {
            (0..n)
                .map(|_| {
                    state = state
                        .wrapping_mul(6_364_136_223_846_793_005)
                        .wrapping_add(1);
                    (state >> 56) as u8
                })
                .collect()
        };
        let mut out = vec![vec![], vec![7], vec![0, 0], vec![128; 3]];
        for run in [1, 2, 3, 4, 257, 258, 259, 260, 261, 516, 517, 10_000] {
            let mut v = noise(5);
            v.extend(std::iter::repeat_n(255, run));
            v.extend(noise(3));
            v.extend(std::iter::repeat_n(0, run));
            out.push(v);
        }
        out.push(noise(100_000));
        // A row repeated 32 768 and 32 769 bytes back: the first is in the window, not the
        // second.
        for gap in [WINDOW, WINDOW + 1, 1280, 5] {
            let row = noise(300);
            let mut v = row.clone();
            v.extend(noise(gap - row.len().min(gap)));
            v.truncate(gap);
            v.extend(&row);
            out.push(v);
        }
        // What the predictor makes of a dark image with a few lit pixels.
        let mut v = vec![128u8; 200_000];
        v[0] = 0;
        for (i, b) in noise(2000).into_iter().enumerate() {
            v[(i * 97) % 200_000] = b;
        }
        out.push(v);
        out
    }

    #[test]
    fn streams_inflate_to_the_data_by_two_independent_decoders() {
        let mut scratch = Scratch::default();
        for data in samples() {
            let stream = compress(&data, &mut scratch);
            assert_eq!(
                miniz_oxide::inflate::decompress_to_vec_zlib(&stream).unwrap(),
                data,
                "miniz_oxide, {} bytes",
                data.len()
            );
            assert_eq!(
                fdeflate::decompress_to_vec(&stream).unwrap(),
                data,
                "fdeflate, {} bytes",
                data.len()
            );
            let checksum = u32::from_be_bytes(stream[stream.len() - 4..].try_into().unwrap());
            assert_eq!(checksum, adler32_by_definition(&data));
            assert_eq!(stream[..2], [0x78, 0x01]);
        }
    }

    #[test]
    fn runs_and_repeats_compress() {
        let mut scratch = Scratch::default();
        let zeros = vec![128u8; 500_000];
        assert!(compress(&zeros, &mut scratch).len() < 2500);
        let mut state = 9u32;
        let row: Vec<u8> = (0..1280)
            .map(|_| {
                state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                (state >> 24) as u8
            })
            .collect();
        let rows = row.repeat(20);
        assert!(compress(&rows, &mut scratch).len() < 2 * row.len());
    }

    #[test]
    fn a_stream_does_not_depend_on_the_scratch_history() {
        let data = samples().pop().unwrap();
        let fresh = compress(&data, &mut Scratch::default());
        let mut used = Scratch::default();
        for other in samples() {
            compress(&other, &mut used);
        }
        assert_eq!(compress(&data, &mut used), fresh);
        // Stored positions about to overflow: the table starts afresh.
        used.base = u32::MAX - 10;
        assert_eq!(compress(&data, &mut used), fresh);
        assert_eq!(compress(&data, &mut used), fresh);
    }

    #[test]
    fn adler32_of_runs_is_the_definitions() {
        for (byte, length) in [(0u8, 3usize), (255, 258), (128, 100), (1, 257)] {
            let mut prefix: Vec<u8> = (0..6000u32).map(|i| (i * 7) as u8).collect();
            let mut adler = Adler32::default();
            prefix.iter().for_each(|&b| adler.byte(b));
            adler.run(byte, length);
            prefix.extend(std::iter::repeat_n(byte, length));
            assert_eq!(adler.finish(), adler32_by_definition(&prefix));
        }
        // Past the reduction mark, by bytes of 255 and by runs of it.
        let mut adler = Adler32::default();
        let mut data = Vec::new();
        while data.len() < 3 * ADLER_REDUCE as usize {
            adler.run(255, 258);
            data.extend([255; 258]);
            for b in [255, 254, 0] {
                adler.byte(b);
                data.push(b);
            }
        }
        assert_eq!(adler.finish(), adler32_by_definition(&data));
    }
}
