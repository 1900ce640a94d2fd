//! Smith's height-correlated masking-shadowing and the single-scattering rough dielectric
//! built on it: the first order of the microsurface random walk (`microfacet_walk`).
//!
//! `microfacet::RoughDielectric` uses the separable G = G₁(wo)·G₁(wi) (Walter et al. 2007,
//! eq. 23). On Smith's microsurface (heights and slopes uncorrelated) a point visible from
//! both directions is more likely high up, so masking and shadowing are correlated through
//! the height (Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based
//! BRDFs", JCGT 3(2), 2014, §6): with c = C₁(h) uniform, the height CDF,
//!
//! ```text
//! reflection:    G₂ = ∫₀¹ (1 + Λ_o) c^Λ_o · c^Λ_i dc / (1 + Λ_o) = 1/(1 + Λ_o + Λ_i)
//! transmission:  G₂ = ∫₀¹ c^Λ_o (1 − c)^Λ_i dc            = B(1 + Λ_o, 1 + Λ_i)
//! ```
//!
//! (light leaving through the sheet escapes from below, where the flipped surface's CDF is
//! 1 − c). This is exactly what the random walk's first event produces, and what Heitz et
//! al. 2016 evaluate in closed form. The two forms agree for small Λ; at grazing angles the
//! height-correlated one reflects more and transmits less (at α = 1, 85° from air: first-order
//! albedo 0.16 vs the separable 0.39), which is why the multiple-scattering model's first
//! order is this one and not `RoughDielectric::f_adjoint`.

use std::f64::consts::PI;

use nalgebra::Vector3;

use super::microfacet::RoughDielectric;

/// The height-correlated G₂(wo, wi) (see the module docs), for either side of the surface.
pub fn g2(surface: &RoughDielectric, wo: &Vector3<f64>, wi: &Vector3<f64>) -> f64 {
    let g = &surface.distribution;
    let (lo, li) = (g.lambda(wo), g.lambda(wi));
    if !(lo.is_finite() && li.is_finite()) {
        return 0.0;
    }
    if wo.z * wi.z > 0.0 {
        1.0 / (1.0 + lo + li)
    } else {
        (ln_gamma(1.0 + lo) + ln_gamma(1.0 + li) - ln_gamma(2.0 + lo + li)).exp()
    }
}

/// The adjoint (flux) BSDF f*(wo, wi) (1/sr) of Walter et al. 2007 with G₂ in place of
/// G₁(wo)G₁(wi): `RoughDielectric::f_adjoint` rescaled by G₂/(G₁G₁), unpolarised.
pub fn f_adjoint(surface: &RoughDielectric, wo: &Vector3<f64>, wi: &Vector3<f64>) -> f64 {
    let f_separable = surface.f_adjoint(wo, wi);
    if f_separable == 0.0 {
        return 0.0;
    }
    let g = &surface.distribution;
    f_separable * g2(surface, wo, wi) / (g.g1(wo) * g.g1(wi))
}

/// ln Γ(x) for x > 0: Lanczos' approximation with g = 7 and nine coefficients (Lanczos, SIAM
/// J. Numer. Anal. B 1, 1964; the coefficient set of Godfrey, as tabulated in Press et al.,
/// *Numerical Recipes*, 3rd ed., §6.1, discussion), relative error ~10⁻¹⁵ for x ≥ 1/2.
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    debug_assert!(x >= 0.5, "ln Γ is only needed at 1 + Λ ≥ 1 here");
    let z = x - 1.0;
    let series = C[1..]
        .iter()
        .enumerate()
        .fold(C[0], |acc, (k, c)| acc + c / (z + k as f64 + 1.0));
    let t = z + G + 0.5;
    0.5 * (2.0 * PI).ln() + (z + 0.5) * t.ln() - t + series.ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln_gamma_matches_factorials_and_the_beta_function_its_integral() {
        assert!((ln_gamma(1.0)).abs() < 1e-14 && (ln_gamma(2.0)).abs() < 1e-14);
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-14);
        assert!((ln_gamma(11.0) - 3_628_800f64.ln()).abs() < 1e-12);
        // B(2, 3) = 1/12 = ∫ x (1 − x)² dx.
        let b = (ln_gamma(2.0) + ln_gamma(3.0) - ln_gamma(5.0)).exp();
        assert!((b - 1.0 / 12.0).abs() < 1e-15);
    }

    #[test]
    fn g2_is_symmetric_and_matches_the_separable_form_at_normal_incidence() {
        let s = RoughDielectric::new(0.7, 1.5208);
        let z = Vector3::z();
        // Λ = 0 along the normal: both forms are 1.
        assert_eq!(g2(&s, &z, &z), 1.0);
        assert!((g2(&s, &z, &-z) - 1.0).abs() < 1e-14);
        let a = Vector3::new(0.8, 0.1, 0.3).normalize();
        let b = Vector3::new(-0.2, 0.6, -0.5).normalize();
        assert!((g2(&s, &a, &b) - g2(&s, &b, &a)).abs() < 1e-15);
        // Correlation: reflection ≥ separable ≥ transmission.
        let sep = s.distribution.g1(&a) * s.distribution.g1(&b);
        assert!(g2(&s, &a, &-b) > sep && g2(&s, &a, &b) < sep);
    }
}
