//! What happens to a photon at glass: the Fresnel split at a smooth face (with its Stokes
//! vector) and microfacet scattering at a rough edge.

use nalgebra::Vector3;

use super::scene::GlassSurface;
use crate::geometry::accel::Hit;
use crate::optics::fresnel::fresnel_dielectric;
use crate::optics::lambert::orthonormal_basis;
use crate::optics::microfacet::RoughDielectric;
use crate::optics::polarization::{
    apply, mueller_reflection, mueller_transmission, s_axis, Stokes,
};
use crate::optics::refract::{reflect, refract};

/// Outcome of a smooth-face interaction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SmoothOutcome {
    /// Fresnel (or total internal) reflection.
    Reflected {
        /// New direction.
        dir: Vector3<f64>,
        /// Whether it was total internal reflection.
        tir: bool,
    },
    /// Refraction into the other medium.
    Transmitted {
        /// New direction.
        dir: Vector3<f64>,
    },
    /// The shading normal sent the photon to the wrong side of the surface: dropped.
    Absorbed,
}

/// Splits a photon travelling along `dir` at a smooth glass face: reflection or transmission
/// is chosen with the probabilities of the polarisation-aware Fresnel equations applied to its
/// Stokes vector (s and p relative to the plane of incidence), so the photon's flux is kept and
/// its Stokes vector becomes the normalised reflected or transmitted one.
pub fn scatter_smooth(
    hit: &Hit,
    glass: &GlassSurface,
    dir: &Vector3<f64>,
    stokes: &mut Stokes,
    u: f64,
) -> SmoothOutcome {
    let entering = dir.dot(&hit.geometric_normal) < 0.0;
    let side = if entering { 1.0 } else { -1.0 };
    let ng = hit.geometric_normal * side;
    let mut n = hit.shading_normal * side;
    if n.dot(dir) >= 0.0 {
        n = ng;
    }
    let eta = if entering { glass.eta } else { 1.0 / glass.eta };
    let f = fresnel_dielectric(-dir.dot(&n), eta);
    stokes.rotate_frame(dir, &s_axis(dir, &n));
    let reflected = apply(&mueller_reflection(&f), &stokes.s);
    let transmitted = apply(&mueller_transmission(&f), &stokes.s);
    let (pr, pt) = (reflected[0], transmitted[0]);
    if u * (pr + pt) < pr {
        let wr = reflect(&(-dir), &n);
        if wr.dot(&ng) <= 0.0 {
            return SmoothOutcome::Absorbed;
        }
        stokes.s = reflected.map(|v| v / pr);
        SmoothOutcome::Reflected {
            dir: wr,
            tir: f.tir,
        }
    } else {
        let Some((wt, _)) = refract(&(-dir), &n, eta) else {
            return SmoothOutcome::Absorbed;
        };
        if wt.dot(&ng) >= 0.0 {
            return SmoothOutcome::Absorbed;
        }
        stokes.s = transmitted.map(|v| v / pt);
        stokes.rotate_frame(&wt, &s_axis(&wt, &n));
        SmoothOutcome::Transmitted { dir: wt }
    }
}

/// A photon arriving at the rough edge, in the edge's local frame (+z = outward normal).
#[derive(Clone, Copy, Debug)]
pub struct RoughVertex {
    t: Vector3<f64>,
    b: Vector3<f64>,
    n: Vector3<f64>,
    /// Direction back towards where the photon came from, local.
    wo: Vector3<f64>,
    bsdf: RoughDielectric,
}

impl RoughVertex {
    /// The vertex of a photon travelling along `dir` that hit the rough edge at `hit`.
    pub fn new(hit: &Hit, glass: &GlassSurface, dir: &Vector3<f64>) -> Self {
        let n = hit.shading_normal;
        let (t, b) = orthonormal_basis(&n);
        let wo = -dir;
        RoughVertex {
            t,
            b,
            n,
            wo: Vector3::new(wo.dot(&t), wo.dot(&b), wo.dot(&n)),
            bsdf: RoughDielectric::new(glass.edge_alpha, glass.eta),
        }
    }

    fn local(&self, w: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(w.dot(&self.t), w.dot(&self.b), w.dot(&self.n))
    }

    fn world(&self, w: &Vector3<f64>) -> Vector3<f64> {
        self.t * w.x + self.b * w.y + self.n * w.z
    }

    /// BSDF × |cos θ| towards `wi` (world), for flux carried by photons (the adjoint BSDF).
    /// The camera does not see polarisation, so the unpolarised Fresnel factor is used.
    pub fn f_cos(&self, _stokes: &Stokes, wi: &Vector3<f64>) -> f64 {
        let wi = self.local(wi);
        self.bsdf.f_adjoint(&self.wo, &wi) * wi.z.abs()
    }
}

/// A continuation sampled at the rough edge.
#[derive(Clone, Copy, Debug)]
pub struct RoughContinuation {
    /// New direction (world).
    pub wi: Vector3<f64>,
    /// Flux multiplier f·|cos θ|/pdf, corrected for the photon's polarisation.
    pub weight: f64,
    /// Whether the photon crossed the surface.
    pub transmitted: bool,
}

/// Samples where a photon goes after the rough edge (visible-normal sampling of GGX, Walter et
/// al. 2007 / Heitz 2018). The lobe was chosen with the unpolarised Fresnel factor; the weight
/// is corrected by the ratio of the polarised to the unpolarised Fresnel factor of the sampled
/// microfacet, and the Stokes vector takes that microfacet's Mueller matrix.
pub fn scatter_rough(
    v: &RoughVertex,
    stokes: &mut Stokes,
    uc: f64,
    u: [f64; 2],
) -> Option<RoughContinuation> {
    let s = v.bsdf.sample(&v.wo, uc, u)?;
    if s.pdf <= 0.0 {
        return None;
    }
    let mut weight = s.f_adjoint * s.wi.z.abs() / s.pdf;
    // Polarisation at the microfacet: s and p relative to the plane of (wo, wm).
    let wm = v.world(&s.wm);
    let dir_in = -v.world(&v.wo);
    let mut m = if wm.dot(&dir_in) < 0.0 { wm } else { -wm };
    if m.norm_squared() == 0.0 {
        m = v.n;
    }
    let entering = dir_in.dot(&v.n) < 0.0;
    let eta = if entering {
        v.bsdf.eta
    } else {
        1.0 / v.bsdf.eta
    };
    let f = fresnel_dielectric((-dir_in.dot(&m)).clamp(0.0, 1.0), eta);
    stokes.rotate_frame(&dir_in, &s_axis(&dir_in, &m));
    let (mueller, unpolarized) = if s.reflected {
        (mueller_reflection(&f), f.r())
    } else {
        (mueller_transmission(&f), f.t())
    };
    let out = apply(&mueller, &stokes.s);
    if unpolarized > 0.0 && out[0] > 0.0 {
        weight *= out[0] / unpolarized;
        stokes.s = out.map(|x| x / out[0]);
    } else {
        stokes.depolarize();
    }
    let wi = v.world(&s.wi);
    stokes.rotate_frame(&wi, &s_axis(&wi, &m));
    Some(RoughContinuation {
        wi,
        weight,
        transmitted: !s.reflected,
    })
}
