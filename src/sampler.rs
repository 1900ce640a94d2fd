//! Keyed random numbers: every uniform is a pure function of (seed, stream, index, dimension)
//! — for the light transport (seed, pose, photon, dimension), for the image sensor's noise
//! (seed, pose, pixel, dimension).
//!
//! The hash is SplitMix64's finaliser (Steele, Lea & Flood, "Fast splittable pseudorandom
//! number generators", OOPSLA 2014) applied to a combination of the key words; it passes
//! BigCrush as a counter-based generator. Low dimensions of a photon use a Cranley–Patterson
//! rotated Kronecker lattice indexed by the photon, so the photons that fall in one
//! sensor column are well spread over the beam and aperture dimensions.

/// SplitMix64 finaliser: a bijective 64-bit mix.
pub fn mix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// A uniform in [0, 1) with 53 random bits from a 64-bit hash. The 53 bits are converted as a
/// signed integer: the same value (every integer below 2⁵³ is exact either way), but one
/// instruction on x86-64, where an unsigned 64-bit conversion takes a branch and several.
fn unit(h: u64) -> f64 {
    ((h >> 11) as i64) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Kronecker lattice steps. Dimension 0 (the laser's transverse offset) steps by the golden
/// ratio's conjugate: paired with the fan position i/N that stratifies columns, it makes the
/// two-dimensional Fibonacci-like lattice, the best spread there is for any block of consecutive
/// photons (three-gap theorem), so each column's photons cover the beam's profile evenly (with
/// the R_4 step 0.8567, whose continued fraction has a 6, a block covers it less evenly).
/// Dimensions 1–3 use the generalised golden-ratio (R_4) steps α_j = 1/g^j with g the real root
/// of x⁵ = x + 1 (M. Roberts, "The unreasonable effectiveness of quasirandom sequences", 2018).
const LATTICE_STEPS: [f64; 4] = [
    0.618_033_988_749_894_8,
    0.733_891_856_627_126,
    0.628_706_721_037_808_7,
    0.538_597_257_223_610_1,
];

/// The random numbers of one pose.
#[derive(Clone, Copy, Debug)]
pub struct PoseSampler {
    key: u64,
}

impl PoseSampler {
    /// Sampler for `pose` under `seed`.
    pub fn new(seed: u64, pose: u64) -> Self {
        PoseSampler {
            key: mix64(mix64(seed) ^ pose.wrapping_mul(0xD6E8_FEB8_6659_FD93)),
        }
    }

    /// An independent uniform in [0, 1) for (photon, dimension).
    pub fn uniform(&self, photon: u64, dim: u32) -> f64 {
        self.at(photon).uniform(dim)
    }

    /// The uniforms of one photon (or pixel) `index`, its part of the hash computed once: what
    /// takes several dimensions of one index saves a hash per further dimension.
    pub fn at(&self, index: u64) -> IndexUniforms {
        IndexUniforms {
            key: mix64(self.key ^ index),
        }
    }

    /// Four well-spread uniforms for `photon`: the Kronecker lattice point number `photon`, shifted
    /// by a random offset per pose and `set` (Cranley–Patterson rotation keeps each dimension
    /// uniform). The photon sets of one pose (`transport::trace::PhotonSets`) number their
    /// photons from 0 each and take independent shifts.
    pub fn lattice4(&self, photon: u64, set: u32) -> [f64; 4] {
        let set_key = (set as u64).wrapping_mul(0xD1B5_4A32_D192_ED03);
        let mut out = [0.0; 4];
        for (j, o) in out.iter_mut().enumerate() {
            let shift = unit(mix64(self.key ^ (0xA5A5_0000 + j as u64) ^ set_key));
            // (photon · α) mod 1, computed without losing the fraction for large photon counts.
            let step = ((photon % (1 << 40)) as f64 * LATTICE_STEPS[j]).fract();
            *o = (shift + step).fract();
        }
        out
    }
}

/// The uniforms of one index of a [`PoseSampler`] ([`PoseSampler::at`]).
#[derive(Clone, Copy, Debug)]
pub struct IndexUniforms {
    key: u64,
}

impl IndexUniforms {
    /// The uniform of dimension `dim`: `PoseSampler::uniform(index, dim)`, bit for bit.
    pub fn uniform(&self, dim: u32) -> f64 {
        unit(mix64(
            self.key ^ (dim as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniforms_have_the_right_mean_and_variance() {
        let s = PoseSampler::new(7, 3);
        let n = 200_000;
        let (mut m, mut m2) = (0.0, 0.0);
        for i in 0..n {
            let u = s.uniform(i, 5);
            assert!((0.0..1.0).contains(&u));
            m += u;
            m2 += u * u;
        }
        let mean = m / n as f64;
        let var = m2 / n as f64 - mean * mean;
        // z-tests: σ(mean) = √(1/12/n) = 6.5e-4; σ(var) ≈ √(1/180/n) = 1.7e-4.
        assert!((mean - 0.5).abs() < 4.0 * 6.5e-4, "mean {mean}");
        assert!((var - 1.0 / 12.0).abs() < 4.0 * 1.7e-4, "var {var}");
    }

    #[test]
    fn keys_separate_streams() {
        let a = PoseSampler::new(1, 0);
        let b = PoseSampler::new(1, 1);
        let c = PoseSampler::new(2, 0);
        assert_ne!(a.uniform(0, 0), b.uniform(0, 0));
        assert_ne!(a.uniform(0, 0), c.uniform(0, 0));
        assert_ne!(a.uniform(0, 0), a.uniform(0, 1));
        assert_eq!(a.uniform(9, 4), PoseSampler::new(1, 0).uniform(9, 4));
        assert_eq!(a.at(9).uniform(4), a.uniform(9, 4));
    }

    #[test]
    fn the_signed_conversion_is_the_unsigned_one() {
        for h in [0, 1 << 11, u64::MAX, u64::MAX >> 1, 0x9E37_79B9_7F4A_7C15] {
            assert_eq!(unit(h), (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64));
        }
    }

    #[test]
    fn lattice_is_stratified() {
        // Any 1000 consecutive lattice points put 100 ± 10 points in each tenth of every axis;
        // independent uniforms would scatter by σ ≈ 9.5 per bin and routinely break this.
        let s = PoseSampler::new(3, 2);
        for j in 0..4 {
            let mut bins = [0usize; 10];
            for i in 5000..6000 {
                bins[(s.lattice4(i, 0)[j] * 10.0) as usize] += 1;
            }
            assert!(
                bins.iter().all(|&b| (90..=110).contains(&b)),
                "dim {j}: {bins:?}"
            );
        }
    }
}
