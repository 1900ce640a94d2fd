//! What happens to a photon at glass: the Fresnel split at a smooth face (with its Stokes
//! vector) and multiple microfacet scattering at a rough edge.

use nalgebra::Vector3;

use super::scene::GlassSurface;
use crate::geometry::accel::Hit;
use crate::optics::fresnel::fresnel_dielectric;
use crate::optics::lambert::orthonormal_basis;
use crate::optics::microfacet_walk::MultipleScatteringDielectric;
use crate::optics::polarization::{apply, mueller_reflection, mueller_transmission, Stokes};
use crate::optics::refract::{reflect, refract};
use crate::optics::uniform_stream::KeyedStream;

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
    stokes.rotate_to_s_axis(dir, &n);
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
        // The frame s = d × n / |d × n| stays: the transmitted direction lies in the plane
        // of d and n, so its own s axis, wt × n / |wt × n|, is the same vector.
        stokes.s = transmitted.map(|v| v / pt);
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
    bsdf: MultipleScatteringDielectric,
    /// The vertex's random numbers (keyed by seed, pose, photon and depth): one fork for the
    /// continuation's walk, one for the camera connections' evaluation walks.
    stream: KeyedStream,
}

/// Fork tags of a vertex's stream.
const SAMPLE_STREAM: u64 = 0;
const EVAL_STREAM: u64 = 1;

impl RoughVertex {
    /// The vertex of a photon travelling along `dir` that hit the rough edge at `hit`;
    /// `stream` supplies the microsurface walks' uniforms.
    pub fn new(hit: &Hit, glass: &GlassSurface, dir: &Vector3<f64>, stream: KeyedStream) -> Self {
        let n = hit.shading_normal;
        let (t, b) = orthonormal_basis(&n);
        debug_assert!(
            (t.cross(&b) - n).norm() < 1e-9,
            "a right-handed frame keeps U and V"
        );
        let wo = -dir;
        RoughVertex {
            t,
            b,
            n,
            wo: Vector3::new(wo.dot(&t), wo.dot(&b), wo.dot(&n)),
            bsdf: MultipleScatteringDielectric::new(glass.edge_alpha, glass.eta),
            stream,
        }
    }

    fn local(&self, w: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(w.dot(&self.t), w.dot(&self.b), w.dot(&self.n))
    }

    fn world(&self, w: &Vector3<f64>) -> Vector3<f64> {
        self.t * w.x + self.b * w.y + self.n * w.z
    }

    /// BSDF × |cos θ| towards `wi` (world), for flux carried by photons (the adjoint BSDF),
    /// all orders of microfacet scattering: the single-scattering term in closed form plus an
    /// unbiased one-walk estimate of the rest (`optics::microfacet_walk`). Every call at this
    /// vertex replays the same evaluation stream. The camera does not see polarisation, so the
    /// unpolarised Fresnel factors are used.
    pub fn f_cos(&self, _stokes: &Stokes, wi: &Vector3<f64>) -> f64 {
        let wi = self.local(wi);
        let mut stream = self.stream.fork(EVAL_STREAM);
        self.bsdf.f_adjoint_cos(&self.wo, &wi, &mut stream)
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

/// Samples where a photon goes after the rough edge: the microsurface random walk of Heitz et
/// al. 2016 (`optics::microfacet_walk`), every order of scattering between the microfacets.
/// At each facet the Stokes vector takes that facet's Fresnel Mueller matrix and the lobe is
/// chosen with the polarised probability, so the flux weight is 1. `None` if the walk was cut
/// at `microfacet_walk::MAX_EVENTS` events.
pub fn scatter_rough(v: &RoughVertex, stokes: &mut Stokes) -> Option<RoughContinuation> {
    let mut local = Stokes {
        s: stokes.s,
        frame: v.local(&stokes.frame),
    };
    let mut stream = v.stream.fork(SAMPLE_STREAM);
    let s = v.bsdf.sample(&v.wo, &mut stream, Some(&mut local))?;
    stokes.s = local.s;
    stokes.frame = v.world(&local.frame);
    Some(RoughContinuation {
        wi: v.world(&s.wi),
        weight: s.weight,
        transmitted: !s.reflected,
    })
}
