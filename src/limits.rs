//! The valid range of every count and length a user can type, in one place: the scene loader
//! and the command-line flags both check against these, so a flag cannot allow what a scene
//! file refuses, and nothing a user types can overflow the f32 geometry, the sampler or memory.

/// Largest |length| in a scene file or flag (mm): 100 m. The BVH holds coordinates as f32 in
/// millimetres, whose spacing at 10⁵ mm is 7.8 µm (hits are then refined in f64); beyond
/// ~3.4·10³⁸ f32 overflows to infinity and the BVH build fails. Shipped scenes are under 3 m.
pub const MAX_LENGTH_MM: f64 = 1e5;

/// Most scan poses (or study positions) of one run. Each pose holds a few hundred bytes of
/// plan before any is simulated, so 10⁶ is ~0.3 GB, and takes ~1 s to simulate.
pub const MAX_POSES: usize = 1_000_000;

/// Fewest laser photons per pose: below this a profile is mostly empty columns.
pub const MIN_PHOTONS: u64 = 1000;

/// Most laser photons per pose: 2⁴⁰, the period of the sampler's photon lattice
/// (`sampler::PoseSampler::lattice4` takes the index mod 2⁴⁰); about 10⁶ profiles' worth.
pub const MAX_PHOTONS: u64 = 1 << 40;

/// Longest photon path (surface interactions). Each interaction takes 8 sampler dimensions
/// (a u32), and a photon bouncing 4096 times inside glass keeps < 10⁻³⁰ of its flux.
pub const MAX_DEPTH: u32 = 4096;

/// Most samples of one dataset (all shards): the run keeps one bit per sample (12.5 MB).
pub const MAX_SAMPLES: u64 = 100_000_000;

/// Most elements one glTF accessor may hold (vertices, normals or indices of a primitive):
/// 2²⁶ ≈ 6.7·10⁷, i.e. a 1.6 GB position array once read as f64 points and far beyond any
/// part a triangulation sensor scans (a car door is ~10⁶ triangles). A sparse accessor
/// without a buffer view states its count without bytes to back it, so only this bounds it.
pub const MAX_ACCESSOR_COUNT: usize = 1 << 26;

/// Whether the scene key `field` (a dotted path, perhaps with `[i]` indices) is a length by
/// the unit-suffix convention (`_mm`, `_um`), and its largest magnitude in that unit.
pub fn length_bound(field: &str) -> Option<f64> {
    let mut name = field;
    while let Some(open) = name.strip_suffix(']').and_then(|n| n.rfind('[')) {
        name = &name[..open];
    }
    if name.ends_with("_per_mm") {
        None // an inverse length (absorption coefficient)
    } else if name.ends_with("_mm") {
        Some(MAX_LENGTH_MM)
    } else if name.ends_with("_um") {
        Some(MAX_LENGTH_MM * 1e3)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_are_known_by_their_suffix_with_or_without_indices() {
        assert_eq!(length_bound("objects[0].panel.thickness_mm"), Some(1e5));
        assert_eq!(length_bound("pose.translation_mm[2]"), Some(1e5));
        assert_eq!(length_bound("outline.polygon_mm[3][0]"), Some(1e5));
        assert_eq!(length_bound("sensor.pixel_pitch_um"), Some(1e8));
        assert_eq!(length_bound("sensor.exposure_ms"), None);
        assert_eq!(length_bound("material.absorption_per_mm"), None);
    }

    #[test]
    fn f32_holds_every_allowed_length_in_millimetres() {
        assert!((MAX_LENGTH_MM as f32).is_finite());
        // 2⁴⁰ photons fit the lattice's modulus exactly.
        assert_eq!(MAX_PHOTONS % (1 << 40), 0);
    }
}
