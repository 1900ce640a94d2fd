//! Analytic physics checks.

mod radiometry;
mod triangulation;
