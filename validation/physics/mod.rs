//! Analytic physics checks.

mod diffraction;
mod firmware;
mod glass;
mod optics;
mod radiometry;
mod sensor_noise;
mod speckle;
mod triangulation;
