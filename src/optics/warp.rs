//! Warps from uniforms to disks, hemispheres and the normal distribution, with their densities
//! and inverses.

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

/// Standard normal CDF Φ(x) = erfc(−x/√2)/2.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * erfc(-x / std::f64::consts::SQRT_2)
}

/// Complementary error function, Numerical Recipes (2nd ed.) `erfcc`, |ε| < 1.2e-7.
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// Inverse of the standard normal CDF (P. J. Acklam's rational approximation, relative
/// error < 1.15e-9): a standard normal deviate from one uniform. Monotonic, so well-spread
/// uniforms give well-spread deviates, and 95 % of draws need no logarithm or square root
/// (the central region is one rational function), several times cheaper than Box–Muller.
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let p = p.clamp(1e-300, 1.0 - 1e-16);
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
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

    #[test]
    fn normal_quantile_inverts_the_cdf() {
        for p in [1e-6, 0.01, 0.2, 0.5, 0.9, 0.999] {
            let x = normal_quantile(p);
            assert!((normal_cdf(x) - p).abs() < 2e-7 * p.max(1e-3), "p {p}");
        }
        assert!((normal_quantile(0.975) - 1.959_963_985).abs() < 1e-6);
    }
}
