//! Fresnel equations of a smooth interface between two dielectrics, for s and p polarisation.
//!
//! Amplitude coefficients (Hecht, *Optics*, 5th ed., §4.6, the Fresnel equations), with
//! η = n_t/n_i and θ_t from Snell's law sin θ_t = sin θ_i/η:
//!
//! ```text
//! r_s = (cos θ_i − η cos θ_t)/(cos θ_i + η cos θ_t)    t_s = 2 cos θ_i/(cos θ_i + η cos θ_t)
//! r_p = (η cos θ_i − cos θ_t)/(η cos θ_i + cos θ_t)    t_p = 2 cos θ_i/(η cos θ_i + cos θ_t)
//! ```
//!
//! Sign convention of r_p. The field components are taken in right-handed frames (s, p, d) that
//! follow each beam: s = d × n is shared by the incident, reflected and transmitted beams and
//! p = d × s, so p of the reflected beam is the mirror image of p of the incident beam with its
//! sign reversed. In these frames the formula above (Hecht's) is the one that holds; at normal
//! incidence r_p = −r_s, which is the reversal of the p axis and not a physical difference
//! between s and p. `polarization::mueller_reflection` uses the same frames, so its Mueller
//! matrix at normal incidence is R·diag(1, 1, −1, −1): a mirror flips U and the helicity V.
//!
//! Phase convention: fields ∝ exp(i(k·r − ωt)); under total internal reflection the
//! transmitted wave is evanescent, cos θ_t = i·√(sin²θ_i/η² − 1), and |r_s| = |r_p| = 1 with
//! the retardance δ = δ_s − δ_p given by tan(δ/2) = cos θ_i·√(sin²θ_i − η²)/sin²θ_i
//! (Born & Wolf, *Principles of Optics*, 7th ed., §1.5.4).

/// Power reflection and transmission coefficients of a smooth dielectric interface, per
/// polarisation, with the angles and the reflection retardance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FresnelDielectric {
    /// Cosine of the angle of incidence, in [0, 1].
    pub cos_theta_i: f64,
    /// Cosine of the angle of refraction, in [0, 1]; 0 under total internal reflection.
    pub cos_theta_t: f64,
    /// Reflectance for s (TE, ⊥ to the plane of incidence) polarisation, |r_s|², in [0, 1].
    pub r_s: f64,
    /// Reflectance for p (TM, in the plane of incidence) polarisation, |r_p|², in [0, 1].
    pub r_p: f64,
    /// Transmittance for s polarisation, (η cos θ_t/cos θ_i)·|t_s|² = 1 − r_s (power, not
    /// radiance: it contains no 1/η² solid-angle compression).
    pub t_s: f64,
    /// Transmittance for p polarisation, (η cos θ_t/cos θ_i)·|t_p|² = 1 − r_p.
    pub t_p: f64,
    /// Total internal reflection: sin θ_i > η, no transmitted beam.
    pub tir: bool,
    /// cos δ of the retardance of the reflected beam, δ = δ_s − δ_p = arg r_s − arg r_p
    /// ([`FresnelDielectric::retardance_r`]). Outside total internal reflection r_s and r_p
    /// are real and δ is 0 (same sign) or π (opposite signs) in the frames of the module docs:
    /// cos δ = ±1, sin δ = 0 exactly; under it δ = 2·atan(x) with x = cos θ_i·√(sin²θ_i − η²)/
    /// sin²θ_i, so cos δ = (1 − x²)/(1 + x²) and sin δ = 2x/(1 + x²) (the half-angle
    /// identities: the Mueller matrix needs no trigonometric function, issue 11).
    pub cos_retardance_r: f64,
    /// sin δ of the same retardance, in [0, 1].
    pub sin_retardance_r: f64,
}

impl FresnelDielectric {
    /// Retardance of the reflected beam, δ_s − δ_p (rad) in [0, π]: 0 or π outside total
    /// internal reflection, 2·atan(cos θ_i·√(sin²θ_i − η²)/sin²θ_i) ∈ [0, π) under it.
    pub fn retardance_r(&self) -> f64 {
        self.sin_retardance_r.atan2(self.cos_retardance_r)
    }

    /// Unpolarised reflectance (R_s + R_p)/2.
    pub fn r(&self) -> f64 {
        0.5 * (self.r_s + self.r_p)
    }

    /// Unpolarised transmittance (T_s + T_p)/2.
    pub fn t(&self) -> f64 {
        0.5 * (self.t_s + self.t_p)
    }
}

/// Fresnel coefficients for light arriving at `cos_theta_i` ∈ [0, 1] from the medium of index
/// n_i onto a medium of index n_t, with `eta` = n_t/n_i > 0.
///
/// The caller orients the interface: `cos_theta_i` is the cosine to the normal on the incident
/// side, never negative. When the light arrives from the other side (pbrt's `FrDielectric`
/// receives cos θ < 0 there), pass |cos θ| and 1/η. Out-of-range cosines within rounding are
/// clamped; anything else is a bug in the caller and trips a debug assertion.
pub fn fresnel_dielectric(cos_theta_i: f64, eta: f64) -> FresnelDielectric {
    debug_assert!(
        (-1e-9..=1.0 + 1e-9).contains(&cos_theta_i),
        "cos θ_i = {cos_theta_i} must be in [0, 1]: the caller flips the normal"
    );
    assert!(eta > 0.0, "relative index η = {eta} must be positive");
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let sin2_i = 1.0 - cos_i * cos_i;
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        // Total internal reflection (Born & Wolf §1.5.4). At sin θ_i = η exactly both the TIR
        // and the ordinary formulas give R = 1 and δ = 0, so the boundary is continuous.
        let k = (sin2_i - eta * eta).max(0.0).sqrt();
        let x = if sin2_i > 0.0 {
            cos_i * k / sin2_i
        } else {
            0.0
        };
        let x2 = x * x;
        return FresnelDielectric {
            cos_theta_i: cos_i,
            cos_theta_t: 0.0,
            r_s: 1.0,
            r_p: 1.0,
            t_s: 0.0,
            t_p: 0.0,
            tir: true,
            cos_retardance_r: (1.0 - x2) / (1.0 + x2),
            sin_retardance_r: 2.0 * x / (1.0 + x2),
        };
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    // T = (η cos θ_t/cos θ_i)|t|² written without the division by cos θ_i, so that it stays
    // finite at grazing incidence; with these forms R + T = 1 holds to rounding because
    // (a − b)² + 4ab = (a + b)².
    let four_ab = 4.0 * eta * cos_i * cos_t;
    let t_s = four_ab / (cos_i + eta * cos_t).powi(2);
    let t_p = four_ab / (eta * cos_i + cos_t).powi(2);
    FresnelDielectric {
        cos_theta_i: cos_i,
        cos_theta_t: cos_t,
        r_s: rs * rs,
        r_p: rp * rp,
        t_s,
        t_p,
        tir: false,
        cos_retardance_r: if rs * rp < 0.0 { -1.0 } else { 1.0 },
        sin_retardance_r: 0.0,
    }
}

/// Unpolarised reflectance (R_s + R_p)/2 at `cos_theta_i` ∈ [0, 1] for `eta` = n_t/n_i
/// (pbrt-v4 `FrDielectric` for a non-negative cosine).
pub fn fresnel_unpolarized(cos_theta_i: f64, eta: f64) -> f64 {
    fresnel_dielectric(cos_theta_i, eta).r()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn normal_incidence_gives_the_textbook_reflectance() {
        // ((n − 1)/(n + 1))² = 0.04 for n = 1.5 (Mitsuba `test_fresnel.py`, Hecht §4.6).
        let f = fresnel_dielectric(1.0, 1.5);
        assert!((f.r_s - 0.04).abs() < 1e-15 && (f.r_p - 0.04).abs() < 1e-15);
        assert!((f.t_s - 0.96).abs() < 1e-15 && (f.t_p - 0.96).abs() < 1e-15);
        assert_eq!(f.retardance_r(), PI, "r_p = −r_s at normal incidence");
        // From inside the same interface reflects the same power (Stokes relations).
        let g = fresnel_dielectric(1.0, 1.0 / 1.5);
        assert!((g.r() - 0.04).abs() < 1e-15);
    }

    #[test]
    fn brewster_and_critical_angles() {
        let n: f64 = 1.5;
        let f = fresnel_dielectric(n.atan().cos(), n);
        assert!(f.r_p < 1e-28 && f.r_s > 0.1);
        let crit = (1.0 / n).asin();
        assert!(!fresnel_dielectric((crit - 1e-6).cos(), 1.0 / n).tir);
        let g = fresnel_dielectric((crit + 1e-6).cos(), 1.0 / n);
        assert!(g.tir && g.r() == 1.0 && g.t() == 0.0);
    }

    #[test]
    fn energy_is_conserved_per_polarisation() {
        for eta in [1.0 / 1.7, 1.0 / 1.33, 1.2, 1.5208, 2.4] {
            for k in 0..=100 {
                let f = fresnel_dielectric(k as f64 / 100.0, eta);
                assert!((f.r_s + f.t_s - 1.0).abs() < 1e-14, "{f:?}");
                assert!((f.r_p + f.t_p - 1.0).abs() < 1e-14, "{f:?}");
            }
        }
    }

    #[test]
    fn the_retardance_s_cosine_and_sine_are_those_of_born_and_wolf_s_angle() {
        // Under total internal reflection δ = 2·atan(cos θ_i·√(sin²θ_i − η²)/sin²θ_i) (Born &
        // Wolf, *Principles of Optics*, §1.5.4): the half-angle forms against cos δ and sin δ.
        let eta: f64 = 1.0 / 1.5208;
        for k in 0..=200 {
            let cos_i = k as f64 / 200.0;
            let f = fresnel_dielectric(cos_i, eta);
            let sin2_i = 1.0 - cos_i * cos_i;
            let delta = if f.tir {
                2.0 * (cos_i * (sin2_i - eta * eta).sqrt() / sin2_i).atan()
            } else if f.cos_retardance_r < 0.0 {
                PI
            } else {
                0.0
            };
            assert!((f.cos_retardance_r - delta.cos()).abs() < 1e-15, "{f:?}");
            assert!((f.sin_retardance_r - delta.sin()).abs() < 1e-15, "{f:?}");
            assert!((f.retardance_r() - delta).abs() < 1e-15, "{f:?}");
        }
    }

    #[test]
    fn retardance_is_continuous_at_the_critical_angle() {
        let eta: f64 = 1.0 / 1.5;
        let crit = eta.asin();
        let below = fresnel_dielectric((crit - 1e-9).cos(), eta);
        let above = fresnel_dielectric((crit + 1e-9).cos(), eta);
        assert_eq!(
            below.retardance_r(),
            0.0,
            "internal, between Brewster and critical"
        );
        assert!(above.tir && above.retardance_r() < 1e-3);
        assert_eq!(fresnel_dielectric(0.0, eta).retardance_r(), 0.0);
    }
}
