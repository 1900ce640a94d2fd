//! Regression checks (`glassscan check`): a suite of localisation cases (scene, scan angle,
//! poses, seed, photons, error models, BIP rule), each run end to end, its metrics compared
//! with a committed baseline under per-metric tolerances.
//!
//! A case is deterministic (same seed ⇒ bit-identical results for any thread count), so a
//! metric that moves means the code changed what it computes; the tolerances separate
//! harmless float reordering from a change someone should look at. A metric that gets worse by
//! more than its tolerance is a regression (exit 1); one that improves by more is reported so
//! that the baseline gets updated (`--update-baseline`), and does not fail.
//!
//! - `suite`: the suite file (TOML) and its validation.
//! - `case`: running one case and its metrics.
//! - `baseline`: the committed baseline (JSON) next to the suite.
//! - `compare`: metrics against the baseline, verdicts and the table.

pub mod baseline;
pub mod case;
pub mod compare;
pub mod suite;
