//! Multiple scattering inside a rough dielectric interface: the stochastic microsurface random
//! walk of Heitz, Hanika, d'Eon & Dachsbacher, "Multiple-Scattering Microfacet BSDFs with the
//! Smith Model", ACM TOG 35(4), SIGGRAPH 2016 (their dielectric material), on the GGX
//! microsurface of `microfacet`.
//!
//! **Concept.** Single-scattering microfacet theory (`microfacet::RoughDielectric`) lets light
//! meet the microsurface once and discards what the masking function says would hit it again:
//! at α = 0.3 seen from inside the glass about a tenth of the flux disappears. Heitz et al.
//! show that Smith's microsurface (slopes and heights uncorrelated, GGX slopes) is a random
//! medium that a ray can be traced through exactly: from height h₀ along ω the probability
//! of leaving without another intersection is G₁(ω, h₀) = C₁(h₀)^Λ(ω) (C₁ the height CDF,
//! Λ Smith's function, Λ(−ω) = −1 − Λ(ω) below the horizon), the next intersection height
//! follows by inverting 1 − (C₁(h₀)/C₁(h))^Λ(ω), and the facet hit there is drawn from the
//! normals visible from the ray. There the dielectric's phase function reflects with the
//! facet's Fresnel factor F or refracts with 1 − F, and a refracted ray continues on the
//! other side of the same sheet, which seen from there is the flipped microsurface: heights
//! −h, height CDF 1 − C₁(h). The walk ends when the ray escapes on either side. Each event
//! conserves flux (R + T = 1), so the walk is energy-conserving by construction; the first
//! event alone is the classic microfacet BSDF, with the *height-correlated* masking-shadowing
//! that Smith's microsurface implies (1/(1 + Λ_o + Λ_i) for reflection, the beta function
//! B(1 + Λ_o, 1 + Λ_i) for transmission; Heitz, "Understanding the Masking-Shadowing
//! Function in Microfacet-Based BRDFs", JCGT 3(2), 2014, §6), not the separable G₁·G₁ that
//! `RoughDielectric` uses.
//!
//! **Heights.** The walk only ever uses heights through c = C₁(h) ∈ [0, 1], which is why the
//! result does not depend on the height distribution; we track c directly (equivalently,
//! uniform heights h = 2c − 1 ∈ [−1, 1], the paper's choice). Seen from inside, the flipped
//! sheet's CDF at the same point is 1 − c.
//!
//! **Conventions.** As in `microfacet`: local frame of the macro-surface, +z out of the glass,
//! `eta` = n_glass/n_air, directions point away from the surface, facet normals in the upper
//! hemisphere. Transport is **flux (importance)**: `wo` points back towards the light, the
//! walk starts along −wo and ends along the photon's new direction wi. The walk's exit density
//! is the flux-transport quantity p(wo → wi) = f*(wo, wi)·|cos θ_i| with f* the adjoint BSDF
//! (`microfacet` module docs): no 1/η² on transmission, because each event's phase function
//! is a probability density of directions (Fresnel R or T times the half-vector Jacobian,
//! Walter et al. 2007 eqs. 14 and 17) and flux is not compressed by refraction. The radiance
//! BSDF is f(wo, wi) = f*(wo, wi)·(n_wo/n_wi)², and reciprocity reads
//! f*(wo, wi)/n_wi² = f*(wi, wo)/n_wo² (Veach 1997, §5.2).
//!
//! **Estimators.** [`MultipleScatteringDielectric::sample`] runs the walk: direction and side
//! come out with flux weight 1 (the walk *is* the photon's continuation). With a Stokes vector,
//! each event applies the facet's Fresnel Mueller matrix and picks reflection with the
//! polarised probability I_R/(I_R + I_T); for a lossless interface I_R + I_T = I, so the weight
//! stays exactly 1 (the smooth faces of `transport::interaction` use the same choice). Without
//! one, the unpolarised factor decides. [`MultipleScatteringDielectric::f_adjoint_cos`]
//! evaluates p(wo → wi) as the analytic first order plus Heitz's unbiased estimate of the
//! orders ≥ 2 from one walk started along −wo: at its k-th vertex (k ≥ 2) the phase function
//! towards wi times the probability of escaping along wi from that height.
//!
//! **Bias.** A walk is cut after [`MAX_EVENTS`] events (the photon is dropped, the estimate
//! ignores the rest): no walk of 8·10⁵ at α = 1 from inside the glass (the longest walks) was
//! cut, the longest had 15 events, so the cut flux is < 4·10⁻⁶ (95 %;
//! validation/physics/multiple_scattering.rs). The evaluation is unpolarised (the camera is
//! polarisation-blind); only the photon's continuation carries polarisation. The estimate of
//! the orders ≥ 2 at a fixed direction is unbiased but heavy-tailed where few walks reach:
//! rare connections carry large values (fireflies), which averaging over photons removes.

use nalgebra::Vector3;

use super::fresnel::fresnel_dielectric;
use super::height_correlated;
use super::microfacet::{Ggx, RoughDielectric};
use super::polarization::{apply, mueller_reflection, mueller_transmission, Stokes};
use super::refract::{reflect, refract};
use super::uniform_stream::UniformSource;

/// Longest walk (microfacet events) followed; see the module docs for the flux cut there.
pub const MAX_EVENTS: u32 = 64;

/// A rough dielectric interface with all orders of scattering between its microfacets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultipleScatteringDielectric {
    /// The microsurface (GGX roughness, relative index); also the single-scattering model.
    pub surface: RoughDielectric,
}

/// Where a walk left the microsurface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkSample {
    /// Exit direction (unit, local frame), the photon's new direction.
    pub wi: Vector3<f64>,
    /// True if the photon leaves on the side it came from.
    pub reflected: bool,
    /// Microfacet events in the walk (the scattering order), ≥ 1.
    pub events: u32,
    /// Flux multiplier: 1 up to rounding for the lossless interface.
    pub weight: f64,
}

/// The state of a ray inside the microsurface layer.
#[derive(Clone, Copy, Debug)]
struct Ray {
    /// Direction of travel (unit).
    d: Vector3<f64>,
    /// On the glass side of the sheet.
    in_glass: bool,
    /// C₁ of the current height, seen from the air side.
    c: f64,
}

impl Ray {
    /// A ray entering the layer from far away along −`wo`.
    fn entering(wo: &Vector3<f64>) -> Self {
        let in_glass = wo.z < 0.0;
        Ray {
            d: -wo,
            in_glass,
            c: if in_glass { 0.0 } else { 1.0 },
        }
    }

    /// C₁ of the current height on the ray's own side (1 − c on the glass side).
    fn c_side(&self) -> f64 {
        if self.in_glass {
            1.0 - self.c
        } else {
            self.c
        }
    }
}

impl MultipleScatteringDielectric {
    /// A rough interface of roughness `alpha` and relative index `eta` = n_glass/n_air.
    pub fn new(alpha: f64, eta: f64) -> Self {
        MultipleScatteringDielectric {
            surface: RoughDielectric::new(alpha, eta),
        }
    }

    fn ggx(&self) -> &Ggx {
        &self.surface.distribution
    }

    /// Smith's Λ of a direction of travel `d` on its own side of the sheet: Λ(d) if it moves
    /// away from the sheet, −1 − Λ(d) if towards it (Λ is even in d.z).
    fn lambda_side(&self, d: &Vector3<f64>, in_glass: bool) -> f64 {
        let away = if in_glass { d.z < 0.0 } else { d.z > 0.0 };
        let l = self.ggx().lambda(d);
        if away {
            l
        } else {
            -1.0 - l
        }
    }

    /// Moves the ray to its next intersection, or returns false if it escapes (the inversion
    /// of the free-path distribution P(next height above c′) = 1 − (c/c′)^Λ on the ray's
    /// side, Heitz et al. 2016): c′ = c·U^(−1/Λ) with U uniform in (0, 1]; c′ > 1 means
    /// the ray got out. A ray moving towards the sheet (Λ ≤ −1) always hits it.
    fn next_height(&self, ray: &mut Ray, u: f64) -> bool {
        let lambda = self.lambda_side(&ray.d, ray.in_glass);
        let c = ray.c_side();
        if lambda == 0.0 {
            // Straight out along the normal: nothing above can be hit.
            return false;
        }
        let c_next = if lambda.is_finite() {
            c * (1.0 - u).powf(-1.0 / lambda)
        } else {
            c
        };
        if c_next > 1.0 {
            return false;
        }
        debug_assert!((0.0..=1.0).contains(&c_next), "height CDF {c_next}");
        ray.c = if ray.in_glass { 1.0 - c_next } else { c_next };
        true
    }

    /// The facet normals visible to the ray: facets face −d from the air side and +d from
    /// the glass side (it sees their undersides).
    fn visible_from(ray: &Ray) -> Vector3<f64> {
        if ray.in_glass {
            ray.d
        } else {
            -ray.d
        }
    }

    /// Relative index n_other/n_here for a ray on the given side.
    fn eta_across(&self, in_glass: bool) -> f64 {
        if in_glass {
            1.0 / self.surface.eta
        } else {
            self.surface.eta
        }
    }

    /// One microfacet event (the dielectric phase function, sampled): a visible normal, then
    /// reflection or refraction. With `stokes` (in the local frame, travelling along ray.d)
    /// the choice is polarised and the Mueller matrix applied; returns the flux multiplier.
    fn scatter(&self, ray: &mut Ray, u: [f64; 3], stokes: Option<&mut Stokes>) -> f64 {
        let wm = self
            .ggx()
            .sample_visible_normal_from(&Self::visible_from(ray), [u[0], u[1]]);
        let cos_i = ray.d.dot(&wm).abs().min(1.0);
        let fresnel = fresnel_dielectric(cos_i, self.eta_across(ray.in_glass));
        let (reflected, weight) = match stokes {
            None => (u[2] < fresnel.r(), 1.0),
            Some(s) => {
                s.rotate_to_s_axis(&ray.d, &wm);
                let r = apply(&mueller_reflection(&fresnel), &s.s);
                let t = apply(&mueller_transmission(&fresnel), &s.s);
                let total = r[0] + t[0];
                debug_assert!(
                    (total - s.s[0]).abs() <= 1e-9 * s.s[0],
                    "a lossless facet keeps the intensity: {total} vs {}",
                    s.s[0]
                );
                let reflected = u[2] * total < r[0];
                let out = if reflected { r } else { t };
                // The frame s = d × wm stays ⊥ to the new direction, which lies in the plane
                // of d and wm.
                s.s = out.map(|x| x / out[0]);
                (reflected, total)
            }
        };
        let refracted = (!reflected)
            .then(|| refract(&-ray.d, &wm, self.surface.eta))
            .flatten();
        match refracted {
            Some((wt, _)) => {
                ray.d = wt;
                ray.in_glass = !ray.in_glass;
            }
            // Reflection, or the rounding edge of total internal reflection.
            None => ray.d = reflect(&-ray.d, &wm),
        }
        weight
    }

    /// Samples the photon's continuation by the random walk from `wo` (towards the light).
    /// `stokes`, if given, is the photon's polarisation in the local frame, travelling along
    /// −wo; it ends travelling along the returned `wi`. `None` if the walk was cut at
    /// [`MAX_EVENTS`] (or `wo` is grazing).
    pub fn sample(
        &self,
        wo: &Vector3<f64>,
        uniforms: &mut impl UniformSource,
        mut stokes: Option<&mut Stokes>,
    ) -> Option<WalkSample> {
        if wo.z == 0.0 {
            return None;
        }
        let mut ray = Ray::entering(wo);
        let mut weight = 1.0;
        for events in 0..=MAX_EVENTS {
            if !self.next_height(&mut ray, uniforms.next_uniform()) {
                if events == 0 {
                    // Only a ray along the normal "misses" a sheet it travels towards, at
                    // U = 0 exactly; it has met nothing.
                    return None;
                }
                return Some(WalkSample {
                    wi: ray.d,
                    reflected: (ray.d.z > 0.0) == (wo.z > 0.0),
                    events,
                    weight,
                });
            }
            if events == MAX_EVENTS {
                break;
            }
            let u = [
                uniforms.next_uniform(),
                uniforms.next_uniform(),
                uniforms.next_uniform(),
            ];
            weight *= self.scatter(&mut ray, u, stokes.as_deref_mut());
        }
        None
    }

    /// Flux density of one event's outcome (1/sr): the ray `ray` meets the facet it is at and
    /// leaves along `w` into the medium on w's side of the macro-surface: F·D_v(h)/(4|w·h|)
    /// for reflection, (1 − F)·D_v(h)·η²|w·h|/(v·h + η w·h)² for refraction (Walter et al.
    /// 2007, eqs. 14 and 17 with v = −d and η = n_there/n_here), D_v the density of normals
    /// visible to the ray. It integrates to 1 over w.
    fn phase(&self, ray: &Ray, w: &Vector3<f64>) -> f64 {
        let v = -ray.d;
        let visible = Self::visible_from(ray);
        let here_glass = ray.in_glass;
        let there_glass = w.z < 0.0;
        if here_glass == there_glass {
            let sum = v + w;
            let len = sum.norm();
            if len == 0.0 {
                return 0.0;
            }
            let h = sum * (sum.z.signum() / len);
            let d_v = self.ggx().pdf_visible_normal_from(&visible, &h);
            if d_v == 0.0 {
                return 0.0;
            }
            let f = fresnel_dielectric(v.dot(&h).abs().min(1.0), self.eta_across(here_glass));
            f.r() * d_v / (4.0 * w.dot(&h).abs())
        } else {
            let eta = self.eta_across(here_glass);
            let sum = v + eta * w;
            let len = sum.norm();
            if len == 0.0 {
                return 0.0;
            }
            // v + η w = (v·n − η cos θ_t)·n for the facet normal n on the ray's side, whose
            // coefficient is negative when entering the denser medium.
            let n = if eta > 1.0 { -sum / len } else { sum / len };
            if v.dot(&n) <= 0.0 || w.dot(&n) >= 0.0 {
                return 0.0;
            }
            let h = if here_glass { -n } else { n };
            let d_v = self.ggx().pdf_visible_normal_from(&visible, &h);
            if d_v == 0.0 {
                return 0.0;
            }
            let f = fresnel_dielectric(v.dot(&n).min(1.0), eta);
            let denom = (v.dot(&n) + eta * w.dot(&n)).powi(2);
            (1.0 - f.r()) * d_v * eta * eta * w.dot(&n).abs() / denom
        }
    }

    /// Probability that light leaving the ray's current point along `w` escapes the
    /// microsurface: C₁^Λ(w) with C₁ of the point seen from w's side.
    fn escape(&self, ray: &Ray, w: &Vector3<f64>) -> f64 {
        let c = if w.z < 0.0 { 1.0 - ray.c } else { ray.c };
        c.powf(self.ggx().lambda(w))
    }

    /// The walk's first order in closed form, p₁(wo → wi) = f₁*(wo, wi)·|cos θ_i| (1/sr):
    /// Walter et al.'s BSDF with the height-correlated masking-shadowing of Smith's
    /// microsurface (`height_correlated`; Heitz et al. 2016 use the same as their walk's
    /// single-scattering term).
    pub fn f_adjoint_cos_single(&self, wo: &Vector3<f64>, wi: &Vector3<f64>) -> f64 {
        height_correlated::f_adjoint(&self.surface, wo, wi) * wi.z.abs()
    }

    /// Heitz et al.'s estimate of the orders `first..=last` of p(wo → wi) from one walk along
    /// −wo: Σ over its vertices k in that range of phase(k → wi)·escape(k, wi). Unbiased for
    /// each order; `first` = 1 reproduces [`Self::f_adjoint_cos_single`] on average.
    pub fn f_adjoint_cos_orders(
        &self,
        wo: &Vector3<f64>,
        wi: &Vector3<f64>,
        first: u32,
        last: u32,
        uniforms: &mut impl UniformSource,
    ) -> f64 {
        if wo.z == 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        let mut sum = 0.0;
        self.walk_vertices(wo, last, uniforms, |order, ray| {
            if order >= first {
                let value = self.phase(ray, wi) * self.escape(ray, wi);
                debug_assert!(value.is_finite() && value >= 0.0, "{value}");
                sum += value;
            }
        });
        sum
    }

    /// Runs an unpolarised walk from `wo` and calls `visit(order, ray)` at each of its first
    /// `last` vertices, before the event there is sampled.
    fn walk_vertices(
        &self,
        wo: &Vector3<f64>,
        last: u32,
        uniforms: &mut impl UniformSource,
        mut visit: impl FnMut(u32, &Ray),
    ) {
        let mut ray = Ray::entering(wo);
        for order in 1..=last.min(MAX_EVENTS) {
            if !self.next_height(&mut ray, uniforms.next_uniform()) {
                return;
            }
            visit(order, &ray);
            if order == last {
                return;
            }
            let u = [
                uniforms.next_uniform(),
                uniforms.next_uniform(),
                uniforms.next_uniform(),
            ];
            self.scatter(&mut ray, u, None);
        }
    }

    /// Estimate of p(wo → wi) = f*(wo, wi)·|cos θ_i| (1/sr), unpolarised, for the camera
    /// connection: the analytic first order plus the stochastic orders 2…[`MAX_EVENTS`].
    pub fn f_adjoint_cos(
        &self,
        wo: &Vector3<f64>,
        wi: &Vector3<f64>,
        uniforms: &mut impl UniformSource,
    ) -> f64 {
        self.f_adjoint_cos_single(wo, wi)
            + self.f_adjoint_cos_orders(wo, wi, 2, MAX_EVENTS, uniforms)
    }

    /// A weighted direction for the orders ≥ 2 of the evaluation: (w, weight) with
    /// E[weight·1{w ∈ A}] = ∫_A p_≥2(wo → w) dω for every set A of directions, p_≥2 the
    /// part of [`Self::f_adjoint_cos`] beyond the first order. A fixed-direction estimate is
    /// heavy-tailed where p_≥2 is small (at 130° from +z, sideways, 0.2 % of walks from 35° at
    /// α = 0.3 contribute), so this draws w from the walk's own vertices: one vertex j ≥ 2
    /// uniformly, then its event sampled; an outcome that leaves directly has density
    /// phase_j(w), and the weight is Σ_k phase_k escape_k / ((1/K)·Σ_j phase_j) ≤ K over the
    /// walk's K vertices of order ≥ 2. `None` (weight 0) if the walk had no second vertex or
    /// the drawn event does not leave.
    pub fn higher_orders_sample(
        &self,
        wo: &Vector3<f64>,
        uniforms: &mut impl UniformSource,
    ) -> Option<(Vector3<f64>, f64)> {
        let mut vertices = Vec::new();
        self.walk_vertices(wo, MAX_EVENTS, uniforms, |order, ray| {
            if order >= 2 {
                vertices.push(*ray);
            }
        });
        if vertices.is_empty() {
            return None;
        }
        let k = vertices.len();
        let pick = ((uniforms.next_uniform() * k as f64) as usize).min(k - 1);
        let mut ray = vertices[pick];
        let u = [
            uniforms.next_uniform(),
            uniforms.next_uniform(),
            uniforms.next_uniform(),
        ];
        self.scatter(&mut ray, u, None);
        let w = ray.d;
        // Only an outcome already moving away from the sheet on its side leaves directly; its
        // density is the phase function (the others, e.g. a reflection downwards in air,
        // have w on the other side of z = 0 but are not that outcome).
        if ray.in_glass != (w.z < 0.0) || w.z == 0.0 {
            return None;
        }
        let q: f64 = vertices.iter().map(|v| self.phase(v, &w)).sum::<f64>() / k as f64;
        if q <= 0.0 {
            return None;
        }
        let nee: f64 = vertices
            .iter()
            .map(|v| self.phase(v, &w) * self.escape(v, &w))
            .sum();
        Some((w, nee / q))
    }

    /// A one-sample unbiased estimate of the directional albedo that the evaluation implies,
    /// ∫ [`Self::f_adjoint_cos`](wo, w) dω, split into [reflected, transmitted]: the white
    /// furnace of the camera connections' BSDF. The first order is importance-sampled with the
    /// single-scattering sampler (ratio G₂/G₁(wo) ≤ 1), the rest with
    /// [`Self::higher_orders_sample`].
    pub fn evaluated_albedo(
        &self,
        wo: &Vector3<f64>,
        uniforms: &mut impl UniformSource,
    ) -> [f64; 2] {
        let mut out = [0.0; 2];
        let side = |w: &Vector3<f64>| ((w.z > 0.0) != (wo.z > 0.0)) as usize;
        let u = [
            uniforms.next_uniform(),
            uniforms.next_uniform(),
            uniforms.next_uniform(),
        ];
        if let Some(s) = self.surface.sample(wo, u[0], [u[1], u[2]]) {
            out[side(&s.wi)] += self.f_adjoint_cos_single(wo, &s.wi) / s.pdf;
        }
        if let Some((w, weight)) = self.higher_orders_sample(wo, uniforms) {
            out[side(&w)] += weight;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::optics::uniform_stream::KeyedStream;

    fn dir(theta: f64, phi: f64) -> Vector3<f64> {
        Vector3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    #[test]
    fn a_replayed_first_event_is_the_single_scattering_sample() {
        // The walk's first event uses the visible-normal sampler of `microfacet` and the same
        // Fresnel choice: with identical uniforms its direction is `RoughDielectric::sample`'s.
        let m = MultipleScatteringDielectric::new(0.3, 1.5208);
        let mut s = KeyedStream::new(&[5]);
        let mut compared = 0;
        for k in 0..2000 {
            let wo = dir(3.1 * (k as f64 * 0.618_034).fract() + 0.02, k as f64);
            let u: [f64; 4] = std::array::from_fn(|_| s.next_uniform());
            let mut ray = Ray::entering(&wo);
            assert!(m.next_height(&mut ray, u[0]));
            m.scatter(&mut ray, [u[1], u[2], u[3]], None);
            if let Some(single) = m.surface.sample(&wo, u[3], [u[1], u[2]]) {
                assert!((single.wi - ray.d).norm() < 1e-12, "{single:?} {ray:?}");
                compared += 1;
            }
        }
        assert!(compared > 1500, "{compared}");
    }

    #[test]
    fn walks_conserve_flux_and_polarised_weights_are_one() {
        let m = MultipleScatteringDielectric::new(0.6, 1.5208);
        let mut s = KeyedStream::new(&[6]);
        for k in 0..2000 {
            let wo = dir(3.1 * (k as f64 * 0.618_034).fract() + 0.02, k as f64 * 0.7);
            let mut stokes = Stokes::linear(&-wo, &Vector3::new(0.3, 1.0, 0.2));
            let out = m
                .sample(&wo, &mut s, Some(&mut stokes))
                .expect("a walk ends");
            assert!((out.weight - 1.0).abs() < 1e-9 && (out.wi.norm() - 1.0).abs() < 1e-9);
            assert!(stokes.frame.dot(&out.wi).abs() < 1e-9, "frame ⊥ direction");
            assert!(stokes.degree_of_polarization() <= 1.0 + 1e-9);
        }
    }

    #[test]
    fn phase_is_the_density_of_the_events_that_leave_directly() {
        // The evaluation's phase function against the sampler's events, for rays travelling
        // down and up on both sides (up in air and down in glass meet the sheet from below its
        // mean plane): ∫ phase over each hemisphere by midpoint quadrature vs the fraction of
        // sampled events leaving directly into it (σ ≤ 1.6e-3 for 10⁵ events).
        let m = MultipleScatteringDielectric::new(0.3, 1.5208);
        for (dz, in_glass) in [(-0.8, false), (0.5, false), (0.8, true), (-0.5, true)] {
            let d = Vector3::new((1.0f64 - dz * dz).sqrt(), 0.0, dz);
            let ray = Ray {
                d,
                in_glass,
                c: 0.5,
            };
            let (nz, np) = (1200, 300);
            let mut integral = [0.0; 2];
            for i in 0..nz {
                let z = -1.0 + 2.0 * (i as f64 + 0.5) / nz as f64;
                for j in 0..np {
                    let phi = 2.0 * PI * (j as f64 + 0.5) / np as f64;
                    let r = (1.0 - z * z).sqrt();
                    let w = Vector3::new(r * phi.cos(), r * phi.sin(), z);
                    integral[(z < 0.0) as usize] += m.phase(&ray, &w) * 4.0 * PI / (nz * np) as f64;
                }
            }
            let mut s = KeyedStream::new(&[7]);
            let mut leaving = [0.0; 2];
            for _ in 0..100_000 {
                let mut r = ray;
                let u = [s.next_uniform(), s.next_uniform(), s.next_uniform()];
                m.scatter(&mut r, u, None);
                if r.in_glass == (r.d.z < 0.0) {
                    leaving[(r.d.z < 0.0) as usize] += 1e-5;
                }
            }
            for k in 0..2 {
                assert!(
                    (integral[k] - leaving[k]).abs() < 6e-3,
                    "d.z = {dz}, glass {in_glass}: ∫ phase {integral:?} vs sampled {leaving:?}"
                );
            }
        }
    }
}
