//! Rough dielectric interfaces (ground and seamed glass edges): the isotropic GGX
//! (Trowbridge–Reitz) microfacet distribution and the rough-dielectric BSDF built on it.
//!
//! Sources: Walter, Marschner, Li & Torrance, "Microfacet Models for Refraction through Rough
//! Surfaces", EGSR 2007 (the BSDF, eqs. 20–21, the generalised half vector, eqs. 13–17, and the
//! GGX D, Λ and G₁, eqs. 33–34); Heitz, "Sampling the GGX Distribution of Visible Normals",
//! JCGT 7(4), 2018 (importance sampling); Heitz, "Understanding the Masking-Shadowing Function
//! in Microfacet-Based BRDFs", JCGT 3(2), 2014 (the visible-normal density D_wo).
//!
//! Everything is in the local frame of the macro-surface: normal +z, which points **out of the
//! glass** (into air); `eta` = n_glass/n_air. Directions point away from the surface, as in the
//! rest of `optics`: wo.z > 0 means wo is in the air, wo.z < 0 inside the glass. Microfacet
//! normals wm are always in the upper hemisphere (they also point out of the glass).
//!
//! Radiance and importance (Veach, *Robust Monte Carlo Methods for Light Transport
//! Simulation*, 1997, §5.2; pbrt-v4 `TransportMode`). [`RoughDielectric::f`] is the radiance
//! BSDF: L(wo) = ∫ f(wo, wi) L(wi) |cos θ_i| dωi, with wi towards the light. Its transmission
//! part carries (n_wo/n_wi)² = 1/η′², the compression of radiance into the denser medium,
//! so f is not symmetric. [`RoughDielectric::f_adjoint`] is the BSDF for transporting
//! importance or flux, f*(wo, wi) = f(wi, wo): the same expression without 1/η′². A light
//! (photon) tracer uses f_adjoint for everything, with wo pointing back towards where the
//! photon came from (the light) and wi where it goes next: both for continuing the photon and
//! for the connection to the camera (then wi points to the camera). The flux a photon keeps,
//! ∫ f*(wo, wi)|cos θ_i| dωi, is ≤ 1 and tends to 1 as α → 0 (validation/physics/optics.rs).

use std::f64::consts::PI;

use nalgebra::Vector3;

use super::fresnel::{fresnel_dielectric, FresnelDielectric};
use super::refract::{reflect, refract};

/// The isotropic GGX / Trowbridge–Reitz distribution of microfacet normals about +z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    /// Roughness α > 0 (the RMS slope is α/√2 per axis; ≈ 0.1 a fine grind, 0.5 a coarse one).
    /// Below ~10⁻³ the surface is numerically a mirror and a smooth model should be used.
    pub alpha: f64,
}

impl Ggx {
    /// A distribution of roughness `alpha` > 0.
    pub fn new(alpha: f64) -> Self {
        assert!(alpha > 0.0, "GGX roughness α = {alpha} must be positive");
        Ggx { alpha }
    }

    /// Density of microfacet normals per unit projected area (1/sr; Walter eq. 33):
    /// D(m) = α²/(π cos⁴θ_m (α² + tan²θ_m)²) = α²/(π (1 + (α² − 1) cos²θ_m)²), zero below the
    /// horizon. Normalised so that ∫ D(m) cos θ_m dωm = 1.
    pub fn d(&self, wm: &Vector3<f64>) -> f64 {
        if wm.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let k = 1.0 + (a2 - 1.0) * wm.z * wm.z;
        a2 / (PI * k * k)
    }

    /// Smith's auxiliary function Λ(w) = (√(1 + α² tan²θ) − 1)/2, even in w.z (Heitz 2014,
    /// §5). Infinite at grazing directions.
    pub fn lambda(&self, w: &Vector3<f64>) -> f64 {
        let cos2 = w.z * w.z;
        if cos2 == 0.0 {
            return f64::INFINITY;
        }
        let x = self.alpha * self.alpha * (w.x * w.x + w.y * w.y) / cos2;
        // (√(1 + x) − 1)/2 without cancellation at small x.
        x / (2.0 * (1.0 + (1.0 + x).sqrt()))
    }

    /// Smith masking G₁(w) = 1/(1 + Λ(w)) (Walter eq. 34), the fraction of the microsurface
    /// visible from w; the facet-side condition is left to the caller.
    pub fn g1(&self, w: &Vector3<f64>) -> f64 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Masking-shadowing G(wo, wi) = G₁(wo)·G₁(wi): Smith's separable (uncorrelated) form, used
    /// by Walter et al. for reflection and transmission alike (eq. 23). pbrt-v4 uses the
    /// height-correlated 1/(1 + Λ(wo) + Λ(wi)) instead; it differs at large α and grazing
    /// angles, where the separable form loses slightly more energy.
    pub fn g(&self, wo: &Vector3<f64>, wi: &Vector3<f64>) -> f64 {
        self.g1(wo) * self.g1(wi)
    }

    /// Draws a microfacet normal from the distribution of normals visible from `wo`,
    /// D_wo(m) = G₁(wo)·max(0, wo·m)·D(m)/cos θ_o (Heitz 2018, listing 1): stretch the view
    /// to the α = 1 configuration, sample the projected hemisphere there, unstretch.
    ///
    /// The result is always in the upper hemisphere. For wo below the surface (inside the
    /// glass) it is drawn for −wo: the same microsurface seen from inside, where facet m faces
    /// wo when wo·m < 0.
    pub fn sample_visible_normal(&self, wo: &Vector3<f64>, u: [f64; 2]) -> Vector3<f64> {
        let w = if wo.z < 0.0 { -wo } else { *wo };
        self.sample_visible_normal_from(&w, u)
    }

    /// Draws a microfacet normal (upper hemisphere) from the normals visible from `w`,
    /// D_w(m) ∝ max(0, w·m)·D(m), for **any** unit `w` but −z: unlike
    /// [`Ggx::sample_visible_normal`], a `w` below the horizon is not flipped. The microsurface
    /// random walk needs this: a ray that leaves a facet downwards in air, or upwards in the
    /// glass, meets the microsurface again from below its mean plane. Heitz 2018's warp covers
    /// that case unchanged: for w.z < 0 the projected visible region is the crescent between the
    /// rim's ellipse and the disk's edge, still reached with the constant Jacobian
    /// s = (1 + w.z)/2 per chord.
    pub fn sample_visible_normal_from(&self, w: &Vector3<f64>, u: [f64; 2]) -> Vector3<f64> {
        let a = self.alpha;
        let vh = Vector3::new(a * w.x, a * w.y, w.z).normalize();
        // Orthonormal basis (t1, t2, vh); any t1 ⊥ z at normal incidence.
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 1e-14 {
            Vector3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
        } else {
            Vector3::x()
        };
        let t2 = vh.cross(&t1);
        // A uniform point of the unit disk, then warped onto the projection of the visible
        // hemisphere: the lower half of the disk shrinks to the ellipse of the hemisphere's rim.
        let r = u[0].sqrt();
        let (sin_phi, cos_phi) = (2.0 * PI * u[1]).sin_cos();
        let p1 = r * cos_phi;
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * sin_phi;
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        Vector3::new(a * nh.x, a * nh.y, nh.z.max(0.0)).normalize()
    }

    /// Density of [`Ggx::sample_visible_normal_from`] (1/sr in wm): max(0, w·wm)·D(wm)/A(w)
    /// with the projected area of the microsurface seen from w, A(w) = ∫ max(0, w·m) D dωm =
    /// cos θ·(1 + Λ(w)) above the horizon and |cos θ|·Λ(w) below it (Heitz et al. 2016, §2:
    /// Λ(−w) = −1 − Λ(w), the area seen from below being what the top view does not cover).
    pub fn pdf_visible_normal_from(&self, w: &Vector3<f64>, wm: &Vector3<f64>) -> f64 {
        let facing = w.dot(wm);
        if facing <= 0.0 || wm.z <= 0.0 {
            return 0.0;
        }
        let area = if w.z > 0.0 {
            w.z * (1.0 + self.lambda(w))
        } else {
            -w.z * self.lambda(w)
        };
        if area.is_finite() && area > 0.0 {
            facing * self.d(wm) / area
        } else {
            0.0
        }
    }

    /// Density of [`Ggx::sample_visible_normal`] (1/sr in wm): G₁(wo)·|wo·wm|·D(wm)/|cos θ_o|
    /// where wm faces wo (wo·wm has the sign of wo.z), zero elsewhere.
    pub fn pdf_visible_normal(&self, wo: &Vector3<f64>, wm: &Vector3<f64>) -> f64 {
        let cos_o = wo.z;
        let facing = wo.dot(wm) * cos_o.signum();
        if cos_o == 0.0 || facing <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * facing * self.d(wm) / cos_o.abs()
    }
}

/// A rough interface between air (+z side) and glass (−z side) with GGX microfacets: reflection
/// and refraction at each facet weighted by its unpolarised Fresnel coefficients (Walter et al.
/// 2007, eqs. 20–21).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    /// The microfacet normal distribution.
    pub distribution: Ggx,
    /// Relative index n_glass/n_air (> 0, ≠ 1): the glass is on the −z side.
    pub eta: f64,
}

/// One scattering lobe (reflection or transmission) about a given microfacet normal, with the
/// facet's Fresnel factor left out so that the caller can apply scalar or Mueller Fresnel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lobe {
    /// Scattered direction (unit).
    pub wi: Vector3<f64>,
    /// True for reflection (wi on the side of wo), false for transmission.
    pub reflected: bool,
    /// η′ = n on wi's side / n on wo's side: η or 1/η for transmission, 1 for reflection.
    pub etap: f64,
    /// Jacobian |∂ωm/∂ωi| of the half-vector map: 1/(4|wi·wm|) for reflection (Walter eq. 14),
    /// |wi·wm|/(wi·wm + wo·wm/η′)² for refraction (eq. 17).
    pub dwm_dwi: f64,
    /// Density of wi (1/sr) when wm is drawn from the normals visible from wo and this lobe is
    /// always taken: D_wo(wm)·|∂ωm/∂ωi|. Multiply by the probability of taking the lobe.
    pub pdf: f64,
    /// Radiance BSDF (1/sr) with the facet's power Fresnel factor (R for reflection, T for
    /// transmission) replaced by 1: D·G/(4|cos θ_o cos θ_i|) for reflection,
    /// D·G·|wi·wm||wo·wm|/(|cos θ_o cos θ_i|(wi·wm + wo·wm/η′)²)/η′² for transmission.
    pub f_unit: f64,
    /// The adjoint (importance, flux) counterpart of `f_unit`: without the 1/η′².
    pub f_unit_adjoint: f64,
}

/// The lobes of the rough dielectric about one microfacet normal, for light from `wo`'s side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughLobes {
    /// Microfacet normal (unit, upper hemisphere).
    pub wm: Vector3<f64>,
    /// Density of wm among the normals visible from wo, D_wo(wm) (1/sr).
    pub pdf_wm: f64,
    /// Fresnel coefficients of the facet for light incident from wo's side at θ = ∠(wo, ±wm);
    /// by reciprocity R and T (per polarisation) are the same for light from wi's side.
    pub fresnel: FresnelDielectric,
    /// The reflection lobe, if the mirrored direction stays on wo's side of the macro-surface.
    pub reflect: Option<Lobe>,
    /// The transmission lobe, unless the facet totally reflects or the refracted direction
    /// does not cross the macro-surface.
    pub transmit: Option<Lobe>,
}

/// A sampled scattering direction of a [`RoughDielectric`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughSample {
    /// Scattered direction (unit).
    pub wi: Vector3<f64>,
    /// Radiance BSDF value f(wo, wi) (1/sr).
    pub f: f64,
    /// Adjoint BSDF value f*(wo, wi) = f(wi, wo) (1/sr), for light (photon) tracing.
    pub f_adjoint: f64,
    /// Density of wi (1/sr), equal to `RoughDielectric::pdf(wo, wi)`.
    pub pdf: f64,
    /// True for reflection, false for transmission.
    pub reflected: bool,
    /// η′ = n on wi's side / n on wo's side (1 for reflection).
    pub etap: f64,
    /// The sampled microfacet normal.
    pub wm: Vector3<f64>,
}

impl RoughDielectric {
    /// A rough interface of roughness `alpha` and relative index `eta` = n_glass/n_air.
    pub fn new(alpha: f64, eta: f64) -> Self {
        assert!(
            eta > 0.0 && eta != 1.0,
            "η = {eta}: an index-matched interface does not scatter"
        );
        RoughDielectric {
            distribution: Ggx::new(alpha),
            eta,
        }
    }

    /// Relative index n_t/n_i for light crossing from wo's side of facet `wm`.
    fn eta_from(&self, dot_o_m: f64) -> f64 {
        if dot_o_m > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        }
    }

    /// The lobe about `wm` that scatters `wo` into `wi`, with its Jacobian and values.
    fn lobe(&self, wo: &Vector3<f64>, wm: &Vector3<f64>, wi: Vector3<f64>, pdf_wm: f64) -> Lobe {
        let (cos_o, cos_i) = (wo.z, wi.z);
        let (dot_o, dot_i) = (wo.dot(wm), wi.dot(wm));
        let dg = self.distribution.d(wm) * self.distribution.g(wo, &wi);
        if cos_o * cos_i > 0.0 {
            let f = dg / (4.0 * (cos_o * cos_i).abs());
            let dwm_dwi = 1.0 / (4.0 * dot_i.abs());
            Lobe {
                wi,
                reflected: true,
                etap: 1.0,
                dwm_dwi,
                pdf: pdf_wm * dwm_dwi,
                f_unit: f,
                f_unit_adjoint: f,
            }
        } else {
            let etap = if cos_o > 0.0 {
                self.eta
            } else {
                1.0 / self.eta
            };
            let denom = (dot_i + dot_o / etap).powi(2);
            let dwm_dwi = dot_i.abs() / denom;
            let f_adj = dg * (dot_i * dot_o).abs() / ((cos_o * cos_i).abs() * denom);
            Lobe {
                wi,
                reflected: false,
                etap,
                dwm_dwi,
                pdf: pdf_wm * dwm_dwi,
                f_unit: f_adj / (etap * etap),
                f_unit_adjoint: f_adj,
            }
        }
    }

    /// Both lobes about the microfacet normal `wm` (e.g. one drawn with
    /// [`Ggx::sample_visible_normal`]), or `None` if wm does not face wo or wo is grazing.
    ///
    /// This is the hook for polarised transport: take the facet's s axis
    /// (`polarization::s_axis(−wo, wm)` in the local frame), choose a lobe with a probability
    /// P of the caller's choosing (e.g. from the Mueller matrices of `fresnel`), then
    /// weight = Mueller·f_unit_adjoint·|cos θ_i|/(lobe.pdf·P).
    pub fn lobes_at(&self, wo: &Vector3<f64>, wm: &Vector3<f64>) -> Option<RoughLobes> {
        let dot_o = wo.dot(wm);
        if wo.z == 0.0 || dot_o * wo.z <= 0.0 {
            return None;
        }
        let pdf_wm = self.distribution.pdf_visible_normal(wo, wm);
        let fresnel = fresnel_dielectric(dot_o.abs(), self.eta_from(dot_o));
        let wr = reflect(wo, wm);
        let reflect = (wr.z * wo.z > 0.0).then(|| self.lobe(wo, wm, wr, pdf_wm));
        let transmit = refract(wo, wm, self.eta)
            .filter(|(wt, _)| wt.z * wo.z < 0.0)
            .map(|(wt, _)| self.lobe(wo, wm, wt, pdf_wm));
        Some(RoughLobes {
            wm: *wm,
            pdf_wm,
            fresnel,
            reflect,
            transmit,
        })
    }

    /// The lobe that connects `wo` to `wi` (the other is `None`), found through the generalised
    /// half vector wm ∝ wo + η′·wi (Walter eqs. 13 and 16), or `None` if no facet facing both
    /// scatters wo into wi. For evaluation, e.g. a connection to the camera.
    pub fn lobes_between(&self, wo: &Vector3<f64>, wi: &Vector3<f64>) -> Option<RoughLobes> {
        let (cos_o, cos_i) = (wo.z, wi.z);
        if cos_o == 0.0 || cos_i == 0.0 {
            return None;
        }
        let reflected = cos_o * cos_i > 0.0;
        let etap = match (reflected, cos_o > 0.0) {
            (true, _) => 1.0,
            (false, true) => self.eta,
            (false, false) => 1.0 / self.eta,
        };
        let h = wo + etap * wi;
        let len = h.norm();
        if len == 0.0 || h.z == 0.0 {
            return None;
        }
        let wm = h * (h.z.signum() / len);
        // Facets seen from the wrong side by either direction contribute nothing (Walter's
        // χ⁺ factors in G₁).
        let (dot_o, dot_i) = (wo.dot(&wm), wi.dot(&wm));
        if dot_o * cos_o <= 0.0 || dot_i * cos_i <= 0.0 {
            return None;
        }
        let pdf_wm = self.distribution.pdf_visible_normal(wo, &wm);
        let fresnel = fresnel_dielectric(dot_o.abs(), self.eta_from(dot_o));
        if !reflected && fresnel.tir {
            return None;
        }
        let lobe = Some(self.lobe(wo, &wm, *wi, pdf_wm));
        Some(RoughLobes {
            wm,
            pdf_wm,
            fresnel,
            reflect: if reflected { lobe } else { None },
            transmit: if reflected { None } else { lobe },
        })
    }

    /// The lobe connecting wo and wi with its unpolarised Fresnel weight (R or 1 − R).
    fn weighted_lobe(&self, wo: &Vector3<f64>, wi: &Vector3<f64>) -> Option<(Lobe, f64)> {
        let lobes = self.lobes_between(wo, wi)?;
        let r = lobes.fresnel.r();
        match (lobes.reflect, lobes.transmit) {
            (Some(l), _) => Some((l, r)),
            (_, Some(l)) => Some((l, 1.0 - r)),
            _ => None,
        }
    }

    /// Radiance BSDF f(wo, wi) (1/sr), unpolarised, reflection and transmission (Walter eqs. 20
    /// and 21); see the module docs for why transmission carries 1/η′².
    pub fn f(&self, wo: &Vector3<f64>, wi: &Vector3<f64>) -> f64 {
        self.weighted_lobe(wo, wi)
            .map_or(0.0, |(l, fr)| l.f_unit * fr)
    }

    /// Adjoint BSDF f*(wo, wi) = f(wi, wo) (1/sr) for importance or flux transport: what a
    /// light tracer uses, with wo towards the light.
    pub fn f_adjoint(&self, wo: &Vector3<f64>, wi: &Vector3<f64>) -> f64 {
        self.weighted_lobe(wo, wi)
            .map_or(0.0, |(l, fr)| l.f_unit_adjoint * fr)
    }

    /// Density (1/sr) with which [`RoughDielectric::sample`] produces `wi` from `wo`. It
    /// integrates to less than one over the sphere: samples that leave on the wrong side are
    /// rejected.
    pub fn pdf(&self, wo: &Vector3<f64>, wi: &Vector3<f64>) -> f64 {
        self.weighted_lobe(wo, wi).map_or(0.0, |(l, p)| l.pdf * p)
    }

    /// Samples wi: a visible normal from `u`, then reflection with probability R (unpolarised
    /// Fresnel of that facet) decided by `uc`, else refraction. `None` if the chosen direction
    /// ends on the wrong side of the macro-surface (a masking loss, as in pbrt-v4).
    /// f·|cos θ_i|/pdf = G₁(wi) for the adjoint and G₁(wi)/η′² for radiance.
    pub fn sample(&self, wo: &Vector3<f64>, uc: f64, u: [f64; 2]) -> Option<RoughSample> {
        if wo.z == 0.0 {
            return None;
        }
        let wm = self.distribution.sample_visible_normal(wo, u);
        let lobes = self.lobes_at(wo, &wm)?;
        let r = lobes.fresnel.r();
        let (lobe, p) = if uc < r {
            (lobes.reflect?, r)
        } else {
            (lobes.transmit?, 1.0 - r)
        };
        Some(RoughSample {
            wi: lobe.wi,
            f: lobe.f_unit * p,
            f_adjoint: lobe.f_unit_adjoint * p,
            pdf: lobe.pdf * p,
            reflected: lobe.reflected,
            etap: lobe.etap,
            wm,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta: f64, phi: f64) -> Vector3<f64> {
        Vector3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * a.abs().max(b.abs())
    }

    #[test]
    fn samples_agree_with_f_and_pdf() {
        let m = RoughDielectric::new(0.3, 1.5208);
        let mut n = [0usize; 2];
        for k in 0..4000 {
            let theta = 0.05 + 3.0 * (k as f64 * 0.618_034).fract();
            let wo = dir(theta, k as f64);
            let u = [
                (k as f64 * 0.754_878).fract(),
                (k as f64 * 0.569_840).fract(),
            ];
            let uc = (k as f64 * 0.414_214).fract();
            let Some(s) = m.sample(&wo, uc, u) else {
                continue;
            };
            n[s.reflected as usize] += 1;
            assert!((s.wi.norm() - 1.0).abs() < 1e-12);
            assert!(close(s.f, m.f(&wo, &s.wi), 1e-9), "{s:?}");
            assert!(close(s.f_adjoint, m.f_adjoint(&wo, &s.wi), 1e-9));
            assert!(close(s.pdf, m.pdf(&wo, &s.wi), 1e-9));
            // The weight of a sample is G₁(wi) (adjoint): the Fresnel factors cancel.
            let w = s.f_adjoint * s.wi.z.abs() / s.pdf;
            assert!(close(w, m.distribution.g1(&s.wi), 1e-9), "{w}");
        }
        assert!(n[0] > 1000 && n[1] > 100, "{n:?}");
    }

    #[test]
    fn adjoint_is_the_transposed_radiance_bsdf() {
        // Veach 1997 §5.2: f*(wo, wi) = f(wi, wo); for reflection f itself is symmetric.
        let m = RoughDielectric::new(0.4, 1.5208);
        for k in 0..400 {
            let wo = dir(3.1 * (k as f64 * 0.618_034).fract(), k as f64 * 0.3);
            let wi = dir(3.1 * (k as f64 * 0.754_878).fract(), k as f64 * 1.7);
            let (a, b) = (m.f_adjoint(&wo, &wi), m.f(&wi, &wo));
            assert!(close(a, b, 1e-12), "{a} {b}");
            if wo.z * wi.z > 0.0 {
                assert_eq!(m.f(&wo, &wi), a);
            }
        }
    }

    #[test]
    fn lobes_at_a_sampled_normal_reproduce_sample() {
        // The polarised transport builds its step from `lobes_at`; with the unpolarised Fresnel
        // as the lobe choice it must be exactly `sample`.
        let m = RoughDielectric::new(0.2, 1.5208);
        for k in 0..2000 {
            let wo = dir(3.1 * (k as f64 * 0.618_034).fract(), k as f64);
            let u = [
                (k as f64 * 0.754_878).fract(),
                (k as f64 * 0.569_840).fract(),
            ];
            let uc = (k as f64 * 0.414_214).fract();
            let wm = m.distribution.sample_visible_normal(&wo, u);
            let lobes = m.lobes_at(&wo, &wm);
            let Some(s) = m.sample(&wo, uc, u) else {
                continue;
            };
            let lobes = lobes.unwrap();
            let r = lobes.fresnel.r();
            let (lobe, p) = if s.reflected {
                (lobes.reflect.unwrap(), r)
            } else {
                (lobes.transmit.unwrap(), 1.0 - r)
            };
            assert_eq!((lobe.wi, lobe.pdf * p, lobe.f_unit * p), (s.wi, s.pdf, s.f));
            assert!(close(lobes.pdf_wm * lobe.dwm_dwi, lobe.pdf, 1e-15));
        }
    }

    #[test]
    fn visible_normals_face_the_viewer() {
        let g = Ggx::new(0.5);
        for k in 0..1000 {
            let wo = dir(3.1 * (k as f64 * 0.618_034).fract(), k as f64);
            let u = [
                (k as f64 * 0.754_878).fract(),
                (k as f64 * 0.569_840).fract(),
            ];
            let wm = g.sample_visible_normal(&wo, u);
            assert!(wm.z >= 0.0 && (wm.norm() - 1.0).abs() < 1e-12);
            assert!(wo.dot(&wm) * wo.z > 0.0 && g.pdf_visible_normal(&wo, &wm) > 0.0);
        }
    }
}
