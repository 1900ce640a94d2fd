//! Light transport: laser photons traced from the projector through the scene, connected to
//! the camera aperture at every non-specular vertex, splatted onto the image plane as flux.
//!
//! Method: a light tracer (particle tracing) with next-event estimation to the lens.
//! - Each photon carries Φ = P/N watts and a Stokes vector (laser polarisation).
//! - Smooth glass faces split it by the polarisation-aware Fresnel equations (the choice of
//!   reflection or transmission has the probability of the Mueller-transformed intensity, so Φ
//!   is kept); Snell refraction, total internal reflection and Beer–Lambert absorption along
//!   every segment inside glass. A fraction `face_imperfection` of face interactions scatters
//!   diffusely instead (dust, micro-defects); its camera connection is made more often than
//!   that fraction, with the weight that keeps its mean (`IMPERFECTION_CONNECTION_RATE`).
//! - Rough glass edges scatter by a GGX microfacet dielectric (reflection and transmission,
//!   Walter et al. 2007), with the Fresnel factor of the sampled microfacet applied to the
//!   Stokes vector.
//! - At every non-specular vertex x (Lambertian surface, face imperfection, rough edge) a point
//!   L of the aperture is sampled uniformly and the vertex is connected to it (`connect`):
//!   straight if nothing is in the way, otherwise through the glass by a Newton-solved chain of
//!   refractions; the flux Φ·f·|cos θ_x|·A·(dω/dA_L)·T_chain is deposited where the thin lens
//!   sends the arriving ray on the Scheimpflug image plane.
//! - A photon whose path so far is purely specular and that enters the aperture deposits its
//!   flux there: a glint.
//! - Diffuse vertices continue with cosine sampling and Russian roulette on the albedo.
//!
//! Bias: the path-length cap `max_depth`, light totally reflected inside a flat pane or a pane
//! bent on a cylinder ended there, and light trapped in other curved glass cut 10 mm off the
//! view (all reported as `truncated_power_w`), and the connection chains' limits stated in
//! `connect` (only transmitted chains from two seeds).
//!
//! Determinism: every random number is a function of (seed, pose, photon, dimension); photons
//! are processed in fixed-size chunks whose splats are summed in chunk order, so the images
//! are bit-identical for any thread count.

pub mod connect;
pub mod cylinder_pane;
pub mod deviation;
pub mod fan_focus;
pub mod film;
pub mod interaction;
pub mod layered;
pub mod lens;
pub mod scene;
pub mod slab_crossing;
pub mod trace;

pub use crate::sensor::path_class::PathClass;
pub use film::Irradiance;
pub use scene::{TraceScene, TransportError};
pub use trace::{
    render, Rendering, TraceSettings, TraceStats, DEFAULT_PHOTONS, FIRST_PHOTON_SET,
    IMPERFECTION_CONNECTION_RATE,
};
