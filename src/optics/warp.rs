//! Warps from the unit square to disks and hemispheres, with their densities and inverses.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Shirley–Chiu concentric map of the unit square onto the unit disk (area-preserving up to a
/// constant, low distortion; pbrt-v4 `SampleUniformDiskConcentric`). Density 1/π on the disk.
pub fn concentric_disk(u: [f64; 2]) -> [f64; 2] {
    let a = 2.0 * u[0] - 1.0;
    let b = 2.0 * u[1] - 1.0;
    if a == 0.0 && b == 0.0 {
        return [0.0, 0.0];
    }
    let (r, theta) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, FRAC_PI_2 - FRAC_PI_4 * (a / b))
    };
    [r * theta.cos(), r * theta.sin()]
}

/// Inverse of [`concentric_disk`]: the unit-square point that maps to `p`.
pub fn invert_concentric_disk(p: [f64; 2]) -> [f64; 2] {
    let [x, y] = p;
    let r = (x * x + y * y).sqrt();
    let (a, b) = if x.abs() > y.abs() {
        // Sectors around ±x: r = a, θ = (π/4)·b/a.
        let a = r.copysign(x);
        let theta = (y * a.signum()).atan2(x * a.signum());
        (a, a * theta / FRAC_PI_4)
    } else {
        // Sectors around ±y: r = b, θ = π/2 − (π/4)·a/b.
        let b = r.copysign(y);
        let theta = (y * b.signum()).atan2(x * b.signum());
        (b * (FRAC_PI_2 - theta) / FRAC_PI_4, b)
    };
    [(a + 1.0) / 2.0, (b + 1.0) / 2.0]
}

/// Two independent standard normal deviates from two uniforms in [0, 1) (Box & Muller, Ann.
/// Math. Statist. 29, 1958): r = √(−2 ln(1 − u₁)), (r cos 2πu₂, r sin 2πu₂).
pub fn box_muller(u1: f64, u2: f64) -> (f64, f64) {
    let r = (-2.0 * (1.0 - u1).ln()).sqrt();
    let a = 2.0 * PI * u2;
    (r * a.cos(), r * a.sin())
}

/// Cosine-weighted direction on the hemisphere around +z (Malley's method), in local
/// coordinates; density cos θ / π.
pub fn cosine_hemisphere(u: [f64; 2]) -> [f64; 3] {
    let [x, y] = concentric_disk(u);
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    [x, y, z]
}

/// Density of [`cosine_hemisphere`] for a local direction with cosine `cos_theta` (1/sr).
pub fn cosine_hemisphere_pdf(cos_theta: f64) -> f64 {
    cos_theta.max(0.0) / PI
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concentric_disk_round_trips() {
        for i in 0..1000 {
            let u = [
                (0.5 + i as f64 * 0.754_877_666).fract(),
                (0.5 + i as f64 * 0.569_840_291).fract(),
            ];
            let back = invert_concentric_disk(concentric_disk(u));
            assert!(
                (back[0] - u[0]).abs() < 1e-12 && (back[1] - u[1]).abs() < 1e-12,
                "{u:?} → {back:?}"
            );
        }
    }

    #[test]
    fn cosine_hemisphere_is_unit_and_upper() {
        for i in 0..1000 {
            let u = [
                (i as f64 * 0.618_034).fract(),
                (i as f64 * 0.414_214).fract(),
            ];
            let d = cosine_hemisphere(u);
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-12 && d[2] >= 0.0);
        }
    }
}
