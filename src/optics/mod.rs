//! Optical models of surfaces, as pure functions of directions and uniform numbers.
//!
//! Direction convention (pbrt): `wo` and `wi` both point away from the surface; `n` is the
//! shading normal on the side the light arrives from. Sampling functions take uniforms in
//! [0, 1), never an RNG, so they are deterministic and χ²-testable.
//!
//! This issue has the Lambertian reflector; Fresnel, refraction and the rough dielectric of
//! ground glass edges arrive with the glass transport (#3).

pub mod lambert;
pub mod warp;
