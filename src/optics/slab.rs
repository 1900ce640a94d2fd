//! Reflectance, transmittance and absorptance of a clean, plane-parallel absorbing slab (a
//! window pane), summing the incoherent multiple reflections between its two faces.
//!
//! Each face reflects R and transmits T = 1 − R of the power of one polarisation (the inner
//! face sees the refraction angle θ_t and index ratio 1/η and, by the Stokes relations, has the
//! same R). One pass through the glass keeps τ = exp(−α·d/cos θ_t) (Beer–Lambert along the
//! oblique path). Summing the geometric series of internal round trips (the incoherent slab
//! of radiative transfer: Siegel & Howell, *Thermal Radiation Heat Transfer*, chapter on
//! partially transparent windows; Rubin, "Optical properties of soda lime silica glasses",
//! Solar Energy Materials 12, 1985):
//!
//! ```text
//! R_slab = R + T²·R·τ²/(1 − R²τ²)
//! T_slab = T²·τ/(1 − R²τ²)
//! A_slab = T·(1 − τ)/(1 − R·τ)
//! ```
//!
//! The three are computed separately, so R + T + A = 1 is a check, not an identity of the
//! code. Coherent (thin-film) interference is averaged out: the pane is far thicker than the
//! laser's coherence length, or its thickness varies by more than λ over the spot.

use super::fresnel::fresnel_dielectric;

/// Fractions of the incident power that a slab reflects, transmits and absorbs, in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rta {
    /// Reflectance (both faces and all internal round trips).
    pub r: f64,
    /// Transmittance.
    pub t: f64,
    /// Absorptance.
    pub a: f64,
}

/// A slab's [`Rta`] for s and p polarisation (⊥ and ∥ to the plane of incidence).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabRta {
    /// s (TE) polarisation.
    pub s: Rta,
    /// p (TM) polarisation.
    pub p: Rta,
}

impl SlabRta {
    /// The average of s and p: unpolarised incident light.
    pub fn unpolarized(&self) -> Rta {
        Rta {
            r: 0.5 * (self.s.r + self.p.r),
            t: 0.5 * (self.s.t + self.p.t),
            a: 0.5 * (self.s.a + self.p.a),
        }
    }
}

/// R, T and A of a slab of relative index `eta` = n_slab/n_outside and thickness
/// `thickness_m` (m) with intensity absorption coefficient `absorption_per_m` (1/m, ≥ 0), for
/// light arriving at `cos_theta_i` ∈ [0, 1] from the outside medium, which surrounds it on
/// both sides.
pub fn slab_rta(cos_theta_i: f64, eta: f64, absorption_per_m: f64, thickness_m: f64) -> SlabRta {
    assert!(absorption_per_m >= 0.0 && thickness_m >= 0.0);
    let f = fresnel_dielectric(cos_theta_i, eta);
    if f.tir {
        // Only possible for η < 1 (a slab of lower index): nothing enters.
        let all = Rta {
            r: 1.0,
            t: 0.0,
            a: 0.0,
        };
        return SlabRta { s: all, p: all };
    }
    let tau = if f.cos_theta_t > 0.0 {
        (-absorption_per_m * thickness_m / f.cos_theta_t).exp()
    } else {
        0.0
    };
    let one = |r: f64, t: f64| Rta {
        r: r + t * t * r * tau * tau / (1.0 - r * r * tau * tau),
        t: t * t * tau / (1.0 - r * r * tau * tau),
        a: t * (1.0 - tau) / (1.0 - r * tau),
    };
    SlabRta {
        s: one(f.r_s, f.t_s),
        p: one(f.r_p, f.t_p),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lossless_pane_at_normal_incidence() {
        // T_slab = (1 − R)/(1 + R) when τ = 1; n = 1.5 → R = 0.04, T_slab = 0.96/1.04.
        let s = slab_rta(1.0, 1.5, 0.0, 4e-3);
        assert!((s.s.t - 0.96 / 1.04).abs() < 1e-15 && s.s.a == 0.0);
        assert!((s.unpolarized().r + s.unpolarized().t - 1.0).abs() < 1e-15);
    }

    #[test]
    fn black_slab_reflects_only_its_front_face() {
        let s = slab_rta(0.8, 1.5, 1e6, 1e-2);
        let f = fresnel_dielectric(0.8, 1.5);
        assert!((s.p.r - f.r_p).abs() < 1e-15 && s.p.t < 1e-300);
        assert!((s.p.a - f.t_p).abs() < 1e-15);
    }
}
