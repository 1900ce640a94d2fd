//! Light transport: laser photons traced from the projector through the scene, connected to
//! the camera aperture at every diffuse vertex, splatted onto the image plane as flux.
//!
//! Method (this issue: opaque Lambertian scenes). A light tracer with next-event estimation to
//! the lens: each photon carries Φ = P/N watts; at every diffuse vertex x a point L of the
//! aperture disk (area A) is sampled uniformly and, if the segment x → L is unoccluded, the flux
//! Φ·(ρ/π)·cos θ_x·cos θ_L·A/|x − L|² is splatted at the point where the thin-lens ray from x
//! through L meets the Scheimpflug image plane; then the photon continues in a cosine-sampled
//! direction with Russian roulette (survival probability ρ, so Φ stays constant). The estimator
//! is unbiased for the flux per pixel; irradiance = flux / pixel area. Photons are traced up to
//! `max_depth` vertices; the light dropped at the cap (ρ^depth of the photon's power on average)
//! is the only bias and is reported in the statistics.
//!
//! Determinism: every random number is a function of (seed, pose, photon, dimension); photons
//! are processed in fixed-size chunks whose splats are summed in chunk order, so the image is
//! bit-identical for any thread count.

pub mod film;
pub mod sampler;
pub mod scene;
pub mod trace;

pub use scene::{TraceScene, TransportError};
pub use trace::{render, TraceSettings, TraceStats};
