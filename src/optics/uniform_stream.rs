//! Unbounded sequences of uniform numbers for sampling routines that need an a priori unknown
//! count of them (the microsurface random walk of `microfacet_walk`).
//!
//! The project's rule is that sampling routines are pure functions of their uniforms: no RNG
//! objects with hidden state, no ambient randomness, the same numbers for any thread count. A
//! routine that consumes a variable number of uniforms therefore takes a [`UniformSource`]: in
//! the tracer a [`KeyedStream`], a counter-based hash of a key made of the photon's identity
//! (seed, pose, photon, depth), so every number is still a function of that identity and of
//! its position in the stream; in tests any closure, e.g. one replaying a fixed list.
//!
//! [`KeyedStream`] is SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number
//! generators", OOPSLA 2014) used as a counter-based generator: the k-th number is
//! `mix64(key + k·γ)` with `mix64` the finaliser of `crate::sampler` (which adds the golden
//! gamma γ = 0x9E3779B97F4A7C15 before mixing), i.e. exactly SplitMix64's k-th output from the
//! state `key`. The key folds the identity words through the same finaliser, starting from a
//! constant that separates these streams from `sampler::PoseSampler`'s.

use crate::sampler::mix64;

/// A supply of independent uniforms in [0, 1).
pub trait UniformSource {
    /// The next uniform in [0, 1).
    fn next_uniform(&mut self) -> f64;
}

/// Any closure that returns uniforms is a source (tests replay fixed numbers this way).
impl<F: FnMut() -> f64> UniformSource for F {
    fn next_uniform(&mut self) -> f64 {
        self()
    }
}

/// SplitMix64's golden gamma, the counter's stride (Steele et al. 2014, §3).
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// Start of the key fold: an arbitrary odd constant ("walk" in ASCII, then padding) that keeps
/// these keys apart from `PoseSampler`'s, which start from `mix64(seed)`.
const DOMAIN: u64 = 0x7761_6C6B_5EED_0001;

/// A keyed counter-based stream of uniforms (see the module docs). `Copy`: a copy replays the
/// same numbers from the same position, which the tracer uses to evaluate a vertex's BSDF
/// several times with one stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyedStream {
    key: u64,
    counter: u64,
}

impl KeyedStream {
    /// The stream keyed by `words`, e.g. `[seed, pose, photon, depth]`, at position 0.
    pub fn new(words: &[u64]) -> Self {
        KeyedStream {
            key: words.iter().fold(DOMAIN, |k, &w| mix64(k ^ w)),
            counter: 0,
        }
    }

    /// An independent stream derived from this one's key and `tag` (e.g. one for sampling and
    /// one for evaluation at the same vertex), at position 0.
    pub fn fork(&self, tag: u64) -> Self {
        KeyedStream::new(&[self.key, tag])
    }
}

impl UniformSource for KeyedStream {
    fn next_uniform(&mut self) -> f64 {
        self.counter = self.counter.wrapping_add(1);
        let h = mix64(self.key.wrapping_add(self.counter.wrapping_mul(GAMMA)));
        // The top 53 bits as a double in [0, 1).
        (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_deterministic_keyed_and_uniform() {
        let mut a = KeyedStream::new(&[1, 2, 3, 4]);
        let mut b = KeyedStream::new(&[1, 2, 3, 4]);
        let mut c = KeyedStream::new(&[1, 2, 3, 5]);
        let first: Vec<f64> = (0..8).map(|_| a.next_uniform()).collect();
        assert_eq!(first, (0..8).map(|_| b.next_uniform()).collect::<Vec<_>>());
        assert_ne!(first[0], c.next_uniform());
        assert_ne!(
            KeyedStream::new(&[1, 2]).fork(0),
            KeyedStream::new(&[1, 2]).fork(1)
        );
        // Mean and variance of 2·10⁵ numbers (σ of the mean 6.5e-4, of the variance 1.7e-4),
        // and the lag-1 correlation (σ ≈ 1/√n = 2.2e-3).
        let mut s = KeyedStream::new(&[9]);
        let n = 200_000;
        let u: Vec<f64> = (0..n).map(|_| s.next_uniform()).collect();
        assert!(u.iter().all(|x| (0.0..1.0).contains(x)));
        let mean = u.iter().sum::<f64>() / n as f64;
        let var = u.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        let lag = u
            .windows(2)
            .map(|w| (w[0] - mean) * (w[1] - mean))
            .sum::<f64>()
            / (n as f64 * var);
        assert!((mean - 0.5).abs() < 4.0 * 6.5e-4, "{mean}");
        assert!((var - 1.0 / 12.0).abs() < 4.0 * 1.7e-4, "{var}");
        assert!(lag.abs() < 4.0 * 2.3e-3, "{lag}");
    }

    #[test]
    fn closures_are_sources() {
        let fixed = [0.25, 0.5];
        let mut k = 0;
        let mut replay = || {
            k += 1;
            fixed[k - 1]
        };
        assert_eq!(replay.next_uniform(), 0.25);
        assert_eq!(replay.next_uniform(), 0.5);
    }
}
