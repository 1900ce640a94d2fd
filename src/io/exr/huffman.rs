//! Huffman codes as deflate stores them (RFC 1951 §3.2.2): each symbol's code length, no
//! longer than a limit, and the canonical codes those lengths define.

/// Code lengths for symbols with frequencies `freqs` (0 = unused, length 0), none longer than
/// `limit`. The code is always complete: a single used symbol is given a partner, so every
/// decoder accepts it. Deterministic: ties are broken by symbol.
///
/// A Huffman code whose longest code exceeds `limit` is rebuilt from the frequencies halved
/// (rounded up, so no used symbol drops out) until it fits: at worst all frequencies are 1 and
/// the code is balanced, ⌈log₂ n⌉ ≤ `limit` bits for deflate's alphabets.
pub(super) fn code_lengths(freqs: &[u32], limit: u8) -> Vec<u8> {
    let mut weights: Vec<u64> = freqs.iter().map(|&f| u64::from(f)).collect();
    let mut used: Vec<usize> = (0..weights.len()).filter(|&s| weights[s] > 0).collect();
    let mut lengths = vec![0u8; weights.len()];
    match used.as_slice() {
        [] => return lengths,
        &[only] => {
            let partner = usize::from(only == 0);
            weights[partner] = 1;
            used = vec![only.min(partner), only.max(partner)];
        }
        _ => {}
    }
    debug_assert!(used.len() <= 1 << limit);
    loop {
        let depths = huffman_depths(&used, &weights);
        if depths.iter().all(|&(_, d)| d <= limit) {
            for (symbol, depth) in depths {
                lengths[symbol] = depth;
            }
            return lengths;
        }
        for &s in &used {
            weights[s] = weights[s].div_ceil(2);
        }
    }
}

/// The depth of each `used` symbol in a Huffman tree of `weights` (at least two used).
fn huffman_depths(used: &[usize], weights: &[u64]) -> Vec<(usize, u8)> {
    // Leaves sorted by weight, then the internal nodes in the order they are made, whose
    // weights never decrease: the two lightest nodes are always at the heads of the two.
    let mut leaves = used.to_vec();
    leaves.sort_by_key(|&s| (weights[s], s));
    let n = leaves.len();
    let mut weight: Vec<u64> = leaves.iter().map(|&s| weights[s]).collect();
    weight.resize(2 * n - 1, 0);
    let mut parent = vec![0usize; 2 * n - 1];
    let (mut next_leaf, mut next_internal) = (0, n);
    for node in n..2 * n - 1 {
        let mut lightest = || {
            let take_leaf = next_leaf < n
                && (next_internal >= node || weight[next_leaf] <= weight[next_internal]);
            if take_leaf {
                next_leaf += 1;
                next_leaf - 1
            } else {
                next_internal += 1;
                next_internal - 1
            }
        };
        let (a, b) = (lightest(), lightest());
        weight[node] = weight[a] + weight[b];
        parent[a] = node;
        parent[b] = node;
    }
    // Parents are made after their children, so one backward pass gives every depth.
    let mut depth = vec![0u8; 2 * n - 1];
    for node in (0..2 * n - 2).rev() {
        depth[node] = depth[parent[node]] + 1;
    }
    leaves.into_iter().zip(depth).collect()
}

/// The canonical codes of `lengths` (RFC 1951 §3.2.2), bit-reversed: deflate writes a code
/// from its most significant bit on, into a stream filled from each byte's least significant
/// bit.
pub(super) fn canonical_codes(lengths: &[u8]) -> Vec<u16> {
    let mut count = [0u16; 16];
    for &len in lengths.iter().filter(|&&len| len > 0) {
        count[usize::from(len)] += 1;
    }
    let mut next = [0u16; 16];
    let mut code = 0u16;
    for bits in 1..16 {
        code = (code + count[bits - 1]) << 1;
        next[bits] = code;
    }
    lengths
        .iter()
        .map(|&len| {
            if len == 0 {
                return 0;
            }
            let code = next[usize::from(len)];
            next[usize::from(len)] += 1;
            code.reverse_bits() >> (16 - len)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Σ 2^-length over the used symbols, times 2^limit: exactly 2^limit for a complete code.
    fn kraft(lengths: &[u8], limit: u8) -> u64 {
        lengths
            .iter()
            .filter(|&&l| l > 0)
            .map(|&l| 1u64 << (limit - l))
            .sum()
    }

    #[test]
    fn codes_are_complete_and_within_the_limit() {
        // Fibonacci frequencies make the deepest possible tree: 40 levels unlimited.
        let mut fib = vec![1u32, 1];
        while fib.len() < 40 {
            fib.push(fib[fib.len() - 1] + fib[fib.len() - 2]);
        }
        let cases: Vec<(Vec<u32>, u8)> = vec![
            (fib.clone(), 15),
            (fib[..19].to_vec(), 7),
            (vec![0, 0, 5, 0], 15),
            (vec![7, 0, 0], 7),
            (vec![1; 286], 15),
            (vec![3, 1, 4, 1, 5, 9, 2, 6], 15),
        ];
        for (freqs, limit) in cases {
            let lengths = code_lengths(&freqs, limit);
            assert!(lengths.iter().all(|&l| l <= limit), "{freqs:?}");
            assert_eq!(kraft(&lengths, limit), 1 << limit, "{freqs:?}");
            for (f, l) in freqs.iter().zip(&lengths) {
                assert!(*f == 0 || *l > 0, "{freqs:?}");
            }
        }
        assert_eq!(code_lengths(&[0, 0, 0], 7), [0, 0, 0]);
    }

    #[test]
    fn an_unlimited_code_is_a_huffman_code() {
        // Frequencies 1, 1, 2, 4: lengths 3, 3, 2, 1.
        assert_eq!(code_lengths(&[4, 2, 1, 1], 15), [1, 2, 3, 3]);
    }

    #[test]
    fn canonical_codes_follow_rfc_1951() {
        // RFC 1951 §3.2.2's example: lengths (3, 3, 3, 3, 3, 2, 4, 4) give
        // 010, 011, 100, 101, 110, 00, 1110, 1111.
        let codes = canonical_codes(&[3, 3, 3, 3, 3, 2, 4, 4]);
        let expected = [0b010, 0b011, 0b100, 0b101, 0b110, 0b00, 0b1110, 0b1111];
        for ((code, expected), len) in codes.iter().zip(expected).zip([3, 3, 3, 3, 3, 2, 4, 4]) {
            let unreversed: u16 = code.reverse_bits() >> (16 - len);
            assert_eq!(unreversed, expected);
        }
    }
}
