//! Analytic physics checks.

mod diffraction;
mod firmware;
mod glass;
mod multiple_scattering;
mod optics;
mod radiometry;
mod sensor_noise;
mod speckle;
mod triangulation;
