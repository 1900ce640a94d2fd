//! One final deflate block with dynamic Huffman codes (RFC 1951 §3.2.5–3.2.7) from a list of
//! literals and matches.

use super::huffman::{canonical_codes, code_lengths};

/// Longest match deflate can say.
pub(super) const MAX_MATCH: usize = 258;
/// Shortest match deflate can say.
pub(super) const MIN_MATCH: usize = 3;
/// Farthest back a match can reach.
pub(super) const WINDOW: usize = 32_768;

/// Literal/length symbols: 256 literals, end of block, 29 length codes.
const LITLEN_SYMBOLS: usize = 286;
const END_OF_BLOCK: usize = 256;
const DISTANCE_SYMBOLS: usize = 30;
/// The code-length alphabet: lengths 0–15, 16 = repeat the previous 3–6 times, 17 = 3–10
/// zeros, 18 = 11–138 zeros.
const CODE_LENGTH_SYMBOLS: usize = 19;
/// The order the code-length code's lengths are stored in (RFC 1951 §3.2.7).
const CODE_LENGTH_ORDER: [usize; CODE_LENGTH_SYMBOLS] = [
    16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15,
];

/// Length codes 257–285: the shortest length of each and its extra bits.
const LENGTH_BASE: [u16; 29] = [
    3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131,
    163, 195, 227, 258,
];
const LENGTH_EXTRA: [u8; 29] = [
    0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0,
];

/// A literal byte or a match, packed in 32 bits: a literal is its value; a match has the top
/// bit set, its length in bits 16–24 and its distance minus one in bits 0–15.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Token(u32);

const MATCH_FLAG: u32 = 1 << 31;

impl Token {
    pub(super) fn literal(byte: u8) -> Token {
        Token(u32::from(byte))
    }

    /// A match of `length` bytes (3–258) starting `distance` bytes back (1–32768).
    pub(super) fn copy(length: usize, distance: usize) -> Token {
        debug_assert!((MIN_MATCH..=MAX_MATCH).contains(&length));
        debug_assert!((1..=WINDOW).contains(&distance));
        Token(MATCH_FLAG | (length as u32) << 16 | (distance - 1) as u32)
    }
}

/// The literal/length symbol of a match length, its extra bits' count and value.
fn length_symbol(length: usize) -> (usize, u32, u32) {
    let code = LENGTH_BASE.partition_point(|&base| usize::from(base) <= length) - 1;
    (
        257 + code,
        u32::from(LENGTH_EXTRA[code]),
        (length - usize::from(LENGTH_BASE[code])) as u32,
    )
}

/// The distance symbol of a distance (1–32768), its extra bits' count and value: codes 0–3 are
/// distances 1–4; above, each power of two is split into two codes.
fn distance_symbol(distance: usize) -> (usize, u32, u32) {
    let d = (distance - 1) as u32;
    if d < 4 {
        return (d as usize, 0, 0);
    }
    let top = 31 - d.leading_zeros(); // ≥ 2
    let extra = top - 1;
    (
        (2 * top + ((d >> extra) & 1)) as usize,
        extra,
        d & ((1 << extra) - 1),
    )
}

/// Symbol counts of a token list, gathered while it is made.
pub(super) struct Frequencies {
    litlen: [u32; LITLEN_SYMBOLS],
    distance: [u32; DISTANCE_SYMBOLS],
    /// `length_symbol` of every length, looked up rather than searched per match.
    length_symbols: [(u16, u8, u8); MAX_MATCH + 1],
}

impl Default for Frequencies {
    fn default() -> Self {
        let mut length_symbols = [(0, 0, 0); MAX_MATCH + 1];
        for (length, entry) in length_symbols.iter_mut().enumerate().skip(MIN_MATCH) {
            let (symbol, extra_bits, extra) = length_symbol(length);
            *entry = (symbol as u16, extra_bits as u8, extra as u8);
        }
        Frequencies {
            litlen: [0; LITLEN_SYMBOLS],
            distance: [0; DISTANCE_SYMBOLS],
            length_symbols,
        }
    }
}

impl Frequencies {
    pub(super) fn clear(&mut self) {
        self.litlen.fill(0);
        self.distance.fill(0);
    }

    #[inline]
    pub(super) fn literal(&mut self, byte: u8) {
        self.litlen[usize::from(byte)] += 1;
    }

    #[inline]
    pub(super) fn copy(&mut self, length: usize, distance: usize) {
        self.litlen[usize::from(self.length_symbols[length].0)] += 1;
        self.distance[distance_symbol(distance).0] += 1;
    }
}

/// Bits written from each byte's least significant bit on.
struct BitWriter {
    out: Vec<u8>,
    bits: u64,
    count: u32,
}

impl BitWriter {
    /// Appends the `count` (≤ 32) low bits of `value`.
    #[inline]
    fn put(&mut self, value: u32, count: u32) {
        debug_assert!(count <= 32 && (count == 32 || value >> count == 0));
        self.bits |= u64::from(value) << self.count;
        self.count += count;
        if self.count >= 32 {
            self.out
                .extend_from_slice(&(self.bits as u32).to_le_bytes());
            self.bits >>= 32;
            self.count -= 32;
        }
    }

    /// The bytes, the last one padded with zero bits.
    fn finish(mut self) -> Vec<u8> {
        let bytes = self.count.div_ceil(8) as usize;
        self.out
            .extend_from_slice(&self.bits.to_le_bytes()[..bytes]);
        self.out
    }
}

/// A code: each symbol's bit-reversed code and its length.
struct Code {
    codes: Vec<u16>,
    lengths: Vec<u8>,
}

impl Code {
    fn new(lengths: Vec<u8>) -> Code {
        Code {
            codes: canonical_codes(&lengths),
            lengths,
        }
    }

    #[inline]
    fn put(&self, w: &mut BitWriter, symbol: usize) {
        w.put(
            u32::from(self.codes[symbol]),
            u32::from(self.lengths[symbol]),
        );
    }
}

/// Appends to `out` the final dynamic-Huffman block of `tokens`, whose symbols `freqs` counted.
pub(super) fn write(tokens: &[Token], freqs: &Frequencies, out: Vec<u8>) -> Vec<u8> {
    let mut litlen_freqs = freqs.litlen;
    litlen_freqs[END_OF_BLOCK] = 1;
    let litlen = Code::new(code_lengths(&litlen_freqs, 15));
    let mut distance_lengths = code_lengths(&freqs.distance, 15);
    if distance_lengths.iter().all(|&l| l == 0) {
        // No match: still a complete code (two one-bit codes), never used.
        distance_lengths[..2].fill(1);
    }
    let distance = Code::new(distance_lengths);

    // Both codes' lengths are sent as one sequence, run-length coded (RFC 1951 §3.2.7).
    let last_used = |lengths: &[u8]| lengths.iter().rposition(|&l| l > 0).unwrap_or(0);
    let litlen_count = (last_used(&litlen.lengths) + 1).max(257);
    let distance_count = last_used(&distance.lengths) + 1;
    let sequence: Vec<u8> = litlen.lengths[..litlen_count]
        .iter()
        .chain(&distance.lengths[..distance_count])
        .copied()
        .collect();
    let runs = run_length_code(&sequence);
    let mut code_length_freqs = [0u32; CODE_LENGTH_SYMBOLS];
    for &(symbol, _) in &runs {
        code_length_freqs[usize::from(symbol)] += 1;
    }
    let code_length = Code::new(code_lengths(&code_length_freqs, 7));
    let code_length_count = (CODE_LENGTH_ORDER
        .iter()
        .rposition(|&s| code_length.lengths[s] > 0)
        .unwrap_or(0)
        + 1)
    .max(4);

    let mut w = BitWriter {
        out,
        bits: 0,
        count: 0,
    };
    w.put(1, 1); // BFINAL: the last block
    w.put(2, 2); // BTYPE: dynamic Huffman codes
    w.put((litlen_count - 257) as u32, 5); // HLIT
    w.put((distance_count - 1) as u32, 5); // HDIST
    w.put((code_length_count - 4) as u32, 4); // HCLEN
    for &symbol in &CODE_LENGTH_ORDER[..code_length_count] {
        w.put(u32::from(code_length.lengths[symbol]), 3);
    }
    for &(symbol, extra) in &runs {
        code_length.put(&mut w, usize::from(symbol));
        match symbol {
            16 => w.put(u32::from(extra), 2),
            17 => w.put(u32::from(extra), 3),
            18 => w.put(u32::from(extra), 7),
            _ => {}
        }
    }
    for &Token(token) in tokens {
        if token & MATCH_FLAG == 0 {
            litlen.put(&mut w, token as usize);
            continue;
        }
        let length = ((token >> 16) & 0x1ff) as usize;
        let (symbol, extra_bits, extra) = freqs.length_symbols[length];
        litlen.put(&mut w, usize::from(symbol));
        w.put(u32::from(extra), u32::from(extra_bits));
        let (symbol, extra_bits, extra) = distance_symbol((token & 0xffff) as usize + 1);
        distance.put(&mut w, symbol);
        w.put(extra, extra_bits);
    }
    litlen.put(&mut w, END_OF_BLOCK);
    w.finish()
}

/// Code lengths in the code-length alphabet: (symbol, its extra bits' value).
fn run_length_code(lengths: &[u8]) -> Vec<(u8, u8)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < lengths.len() {
        let value = lengths[i];
        let run = lengths[i..].iter().take_while(|&&l| l == value).count();
        i += run;
        let mut left = run;
        if value == 0 {
            while left >= 11 {
                let n = left.min(138);
                out.push((18, (n - 11) as u8));
                left -= n;
            }
            if left >= 3 {
                out.push((17, (left - 3) as u8));
                left = 0;
            }
        } else {
            out.push((value, 0));
            left -= 1;
            while left >= 3 {
                let n = left.min(6);
                out.push((16, (n - 3) as u8));
                left -= n;
            }
        }
        out.extend(std::iter::repeat_n((value, 0), left));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn length_symbols_follow_rfc_1951() {
        assert_eq!(length_symbol(3), (257, 0, 0));
        assert_eq!(length_symbol(10), (264, 0, 0));
        assert_eq!(length_symbol(11), (265, 1, 0));
        assert_eq!(length_symbol(12), (265, 1, 1));
        assert_eq!(length_symbol(130), (280, 4, 15));
        assert_eq!(length_symbol(257), (284, 5, 30));
        assert_eq!(length_symbol(258), (285, 0, 0));
    }

    #[test]
    fn distance_symbols_follow_rfc_1951() {
        assert_eq!(distance_symbol(1), (0, 0, 0));
        assert_eq!(distance_symbol(4), (3, 0, 0));
        assert_eq!(distance_symbol(5), (4, 1, 0));
        assert_eq!(distance_symbol(6), (4, 1, 1));
        assert_eq!(distance_symbol(7), (5, 1, 0));
        assert_eq!(distance_symbol(1280), (20, 9, 255)); // 1025–1536
        assert_eq!(distance_symbol(24_577), (29, 13, 0));
        assert_eq!(distance_symbol(32_768), (29, 13, 8191));
    }

    #[test]
    fn code_lengths_are_run_length_coded() {
        let mut lengths = vec![0u8; 150];
        lengths.extend([5; 8]);
        lengths.extend([0, 0, 3, 3]);
        let runs = run_length_code(&lengths);
        assert_eq!(
            runs,
            [
                (18, 127),
                (18, 1),
                (5, 0),
                (16, 3),
                (5, 0),
                (0, 0),
                (0, 0),
                (3, 0),
                (3, 0)
            ]
        );
        // Decoding the runs gives the lengths back.
        let mut decoded: Vec<u8> = Vec::new();
        for (symbol, extra) in runs {
            let extra = usize::from(extra);
            match symbol {
                16 => decoded.extend(std::iter::repeat_n(*decoded.last().unwrap(), 3 + extra)),
                17 => decoded.extend(std::iter::repeat_n(0, 3 + extra)),
                18 => decoded.extend(std::iter::repeat_n(0, 11 + extra)),
                v => decoded.push(v),
            }
        }
        assert_eq!(decoded, lengths);
    }
}
