//! glassscan's validation suite: physics checks against analytic results, pipeline checks on
//! shipped scenes, and the command line's behaviour on good and bad input. Each check cites
//! the source of its reference value; validation/README.md lists what each one proves.

mod accel;
mod adaptive;
mod bad_input;
mod binary;
mod cli;
mod cli_help;
mod common;
mod convergence;
mod dataset;
mod gltf_target;
mod physics;
mod report;
mod scenes;
mod stats;
mod study;
