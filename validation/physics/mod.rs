//! Analytic physics checks.

mod glass;
mod optics;
mod radiometry;
mod triangulation;
