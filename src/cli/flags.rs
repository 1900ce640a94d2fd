//! Checks of flags that several subcommands share, so they say the same thing everywhere.

use super::CliError;

/// The bad-input error for `--flag`: exit code 2, the flag named first.
pub fn bad_flag(flag: &str, message: String) -> CliError {
    CliError::input(anyhow::anyhow!("--{flag} {message}"))
}

/// `--scan-angle-deg`: in (0, 90] degrees; returns radians.
pub fn scan_angle_rad(deg: f64) -> Result<f64, CliError> {
    if deg.is_finite() && deg > 0.0 && deg <= 90.0 {
        Ok(deg.to_radians())
    } else {
        Err(bad_flag(
            "scan-angle-deg",
            format!("must be in (0, 90], got {deg}"),
        ))
    }
}

/// `--photons`: at least 1000 per pose.
pub fn photons(n: u64) -> Result<u64, CliError> {
    if n >= 1000 {
        Ok(n)
    } else {
        Err(bad_flag("photons", format!("must be ≥ 1000, got {n}")))
    }
}

/// `--exposure-ms`: positive and finite; returns seconds.
pub fn exposure_s(ms: f64) -> Result<f64, CliError> {
    if ms.is_finite() && ms > 0.0 {
        Ok(ms * 1e-3)
    } else {
        Err(bad_flag("exposure-ms", format!("must be > 0, got {ms}")))
    }
}
