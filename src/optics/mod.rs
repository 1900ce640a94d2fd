//! Optical models of surfaces, as pure functions of directions and uniform numbers.
//!
//! Direction convention (pbrt): `wo` and `wi` both point away from the surface, all directions
//! are unit vectors, all quantities f64. For opaque reflectors (`lambert`) `n` is the shading
//! normal on the side the light arrives from. For dielectric interfaces `n` (or +z in a local
//! frame) points **out of the glass** and `eta` = n_glass/n_outside; a direction with
//! w·n < 0 is inside the glass, and functions that receive one flip the normal and use 1/η
//! (`refract`), or document that the caller must (`fresnel`). Sampling functions take uniforms
//! in [0, 1), never an RNG, so they are deterministic and χ²-testable.
//!
//! Transport modes: BSDF values named `f` are for radiance (pbrt-v4 `TransportMode::Radiance`);
//! `f_adjoint` is the transposed BSDF, f*(wo, wi) = f(wi, wo), which a light (photon) tracer
//! uses. They differ by (n_wi/n_wo)² for refraction (see `microfacet`).
//!
//! Polarisation (`polarization`): Stokes vectors (I, Q, U, V) in a right-handed frame
//! (x, d × x, d) around the propagation direction d; Q = I_x − I_y; frame rotations use
//! Chandrasekhar's/Mitsuba's rotator. Interfaces act in the (s, p) basis with s = d × n shared
//! by incident, reflected and transmitted beams and p = d × s; in these frames r_p follows
//! Hecht's sign (r_p = −r_s at normal incidence), so a mirror flips U and V.
//!
//! Modules: `lambert` (diffuse), `warp` (disks, hemispheres), `fresnel` (s/p coefficients,
//! TIR, retardance), `refract` (reflect, Snell), `polarization` (Stokes, Mueller),
//! `microfacet` (GGX and the single-scattering rough dielectric), `height_correlated` (its
//! height-correlated masking-shadowing variant), `microfacet_walk` (its
//! multiple scattering by Heitz et al.'s microsurface random walk, what ground edges use),
//! `uniform_stream` (keyed counter-based uniforms for routines that need an unbounded number),
//! `slab` (analytic pane R/T/A).

pub mod fresnel;
pub mod height_correlated;
pub mod lambert;
pub mod microfacet;
pub mod microfacet_walk;
pub mod polarization;
pub mod refract;
pub mod slab;
pub mod uniform_stream;
pub mod warp;
