//! glassscan: a physically based simulator of a laser-line triangulation sensor
//! (scanCONTROL 2600-100 class, 658 nm) looking at glass, plus the localisation
//! pipeline of Adrian & Pham, "Locating Transparent Objects to Millimetre Accuracy".
//!
//! Data flows one way: `scene` → `geometry` → `transport` → `sensor` → `scan` → `cli`.
//! See ARCHITECTURE.md for the code map and the invariants.
// `unsafe` only where a module allows it by name: the BVH's SIMD kernels
// (`geometry::accel::{traverse, triangles}`, std::arch intrinsics).
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod check;
pub mod cli;
pub mod dataset;
pub mod geometry;
pub mod io;
pub mod limits;
pub mod localise;
pub mod optics;
pub mod plot;
pub mod report;
pub mod sampler;
pub mod scan;
pub mod scene;
pub mod sensor;
pub mod shipped;
pub mod study;
pub mod transport;
