//! Checks of flags that several subcommands share, so they say the same thing everywhere.

use std::path::PathBuf;

use super::CliError;
use crate::limits::{MAX_DEPTH, MAX_PHOTONS, MAX_POSES, MIN_PHOTONS};

/// `--photons` and `--seed`, shared by the commands that trace light at scan poses.
#[derive(Debug, clap::Args)]
pub struct LightArgs {
    /// Laser photons traced per pose (1000 to 2^40); more means less Monte Carlo noise. `auto`:
    /// each pose stops once the BIPs the command reports have converged (locate: its rule's
    /// and the highest point's; studies: both rules), after 2^17 or 2^18 photons (the default count).
    #[arg(long, value_name = "N|auto", default_value_t = PhotonsArg::default())]
    pub photons: PhotonsArg,
    /// Master seed of all random numbers (light, sensor noise, error draws).
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
}

/// `--max-depth` and `--threads`, for the commands that expose the transport's knobs.
#[derive(Debug, clap::Args)]
pub struct TransportArgs {
    /// Longest photon path, in surface interactions including specular ones (1 to 4096).
    #[arg(long, value_name = "D", default_value_t = 64)]
    pub max_depth: u32,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
}

impl TransportArgs {
    /// Both must be ≥ 1.
    pub fn check(&self) -> Result<(), CliError> {
        if !(1..=MAX_DEPTH).contains(&self.max_depth) {
            return Err(bad_flag(
                "max-depth",
                format!("must be in 1..={MAX_DEPTH}, got {}", self.max_depth),
            ));
        }
        if self.threads == Some(0) {
            return Err(bad_flag("threads", "must be ≥ 1, got 0".into()));
        }
        Ok(())
    }
}

/// Runs `work` on a pool of `threads` workers, or on rayon's global pool (all cores) for
/// `None`.
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> Result<T, CliError> + Send,
) -> Result<T, CliError> {
    match threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(CliError::internal)?
            .install(work),
        None => work(),
    }
}

/// An optional output directory: `--out DIR` and `--force`.
#[derive(Debug, clap::Args)]
pub struct OutArgs {
    /// Write the run's files into DIR (created if missing; must be empty unless --force).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write into a non-empty output directory (files are replaced one by one, atomically).
    #[arg(long)]
    pub force: bool,
}
use crate::sensor::profile::{PeakSelect, Threshold};

/// The bad-input error for `--flag`: exit code 2, the flag named first.
pub fn bad_flag(flag: &str, message: String) -> CliError {
    CliError::input(anyhow::anyhow!("--{flag} {message}"))
}

/// `--scan-angle-deg`: in (0, 90] degrees; returns radians.
pub fn scan_angle_rad(deg: f64) -> Result<f64, CliError> {
    angle_rad("scan-angle-deg", deg)
}

/// A scan angle given by `--flag`: in (0, 90] degrees; returns radians.
pub fn angle_rad(flag: &str, deg: f64) -> Result<f64, CliError> {
    if deg.is_finite() && deg > 0.0 && deg <= 90.0 {
        Ok(deg.to_radians())
    } else {
        Err(bad_flag(flag, format!("must be in (0, 90], got {deg}")))
    }
}

/// What `--photons` says: a count, or `auto` (each pose stops once converged,
/// `scan::adaptive`, at most at the default count).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhotonsArg {
    /// This many photons per pose.
    Count(u64),
    /// The adaptive count.
    Auto,
}

impl Default for PhotonsArg {
    fn default() -> Self {
        PhotonsArg::Count(crate::transport::DEFAULT_PHOTONS)
    }
}

impl std::fmt::Display for PhotonsArg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PhotonsArg::Count(n) => write!(f, "{n}"),
            PhotonsArg::Auto => f.write_str("auto"),
        }
    }
}

/// In JSON summaries: the count as a number, or `"auto"`.
impl serde::Serialize for PhotonsArg {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            PhotonsArg::Count(n) => s.serialize_u64(*n),
            PhotonsArg::Auto => s.serialize_str("auto"),
        }
    }
}

impl std::str::FromStr for PhotonsArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "auto" {
            return Ok(PhotonsArg::Auto);
        }
        s.parse()
            .map(PhotonsArg::Count)
            .map_err(|_| format!("expected a whole number of photons or `auto`, got `{s}`"))
    }
}

/// `--photons`: `auto` or in [`MIN_PHOTONS`, `MAX_PHOTONS`] per pose. Returns the photon count
/// (with `auto`, the most a pose may take) and whether it is adaptive.
pub fn photons(arg: PhotonsArg) -> Result<(u64, bool), CliError> {
    let n = match arg {
        PhotonsArg::Auto => return Ok((crate::transport::DEFAULT_PHOTONS, true)),
        PhotonsArg::Count(n) => n,
    };
    if (MIN_PHOTONS..=MAX_PHOTONS).contains(&n) {
        Ok((n, false))
    } else {
        Err(bad_flag(
            "photons",
            format!("must be in {MIN_PHOTONS}..={MAX_PHOTONS} (2^40), got {n}"),
        ))
    }
}

/// A pose count given by `--flag`: in `min..=MAX_POSES`, the scene file's `scan.poses` range.
pub fn poses(flag: &str, n: usize, min: usize, why: &str) -> Result<usize, CliError> {
    if (min..=MAX_POSES).contains(&n) {
        Ok(n)
    } else {
        Err(bad_flag(
            flag,
            format!("must be in {min}..={MAX_POSES}{why}, got {n}"),
        ))
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

/// `--threshold`: `auto` or a DN value in [0, `max_dn`].
pub fn threshold(t: &str, max_dn: u16) -> Result<Threshold, CliError> {
    if t.eq_ignore_ascii_case("auto") {
        return Ok(Threshold::Automatic);
    }
    match t.parse::<u16>() {
        Ok(v) if v <= max_dn => Ok(Threshold::Fixed(v)),
        _ => Err(bad_flag(
            "threshold",
            format!("must be `auto` or an integer in [0, {max_dn}] (2^adc_bits − 1), got {t:?}"),
        )),
    }
}

/// `--peak-select`: one of the SDK's modes.
pub fn peak_select(m: &str) -> Result<PeakSelect, CliError> {
    m.parse::<PeakSelect>()
        .map_err(|e| bad_flag("peak-select", e.to_string()))
}

/// A comma-separated `--flag` list, each item checked by `item`; an empty list or item is an
/// error.
pub fn list<T>(
    flag: &str,
    s: &str,
    item: impl Fn(&str) -> Result<T, CliError>,
) -> Result<Vec<T>, CliError> {
    let items: Vec<&str> = s.split(',').map(str::trim).collect();
    if items.iter().any(|i| i.is_empty()) {
        return Err(bad_flag(
            flag,
            format!("expects a comma-separated list without empty items, got {s:?}"),
        ));
    }
    items.into_iter().map(item).collect()
}

/// A number given to `--flag`.
pub fn number(flag: &str, s: &str) -> Result<f64, CliError> {
    s.parse::<f64>()
        .map_err(|_| bad_flag(flag, format!("expects numbers, got {s:?}")))
}

/// `--flag START:STOP:STEP` in degrees, both ends included, every angle in (0, 90]; returns
/// radians. The angles are START + k·STEP, so they are exact multiples as typed.
pub fn angle_range_rad(flag: &str, s: &str) -> Result<Vec<f64>, CliError> {
    let parts: Vec<&str> = s.split(':').collect();
    let expected = || {
        bad_flag(
            flag,
            format!("expects START:STOP:STEP in degrees with STEP > 0 and START ≤ STOP, got {s:?}"),
        )
    };
    let [a, b, d] = parts.as_slice() else {
        return Err(expected());
    };
    let (a, b, d) = (number(flag, a)?, number(flag, b)?, number(flag, d)?);
    if !(d > 0.0 && a <= b && (b - a) / d < 10_000.0) {
        return Err(expected());
    }
    let n = ((b - a) / d + 1e-9).floor() as usize;
    (0..=n).map(|k| angle_rad(flag, a + k as f64 * d)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(e: CliError) -> String {
        assert_eq!(e.code, 2);
        format!("{:#}", e.error)
    }

    #[test]
    fn lists_and_ranges() {
        let v = list("exposure-ms", "0.1, 0.5", |s| {
            exposure_s(number("exposure-ms", s)?)
        })
        .unwrap();
        assert_eq!(v, vec![0.1e-3, 0.5e-3]);
        assert!(
            message(list("exposure-ms", "", |s| number("exposure-ms", s)).unwrap_err())
                .starts_with("--exposure-ms ")
        );
        assert!(
            message(list("angles-deg", "10,,40", |s| number("angles-deg", s)).unwrap_err())
                .contains("empty")
        );
        let r = angle_range_rad("sweep-deg", "5:85:5").unwrap();
        assert_eq!(r.len(), 17);
        assert_eq!(r[1], 10f64.to_radians());
        assert_eq!(r[16], 85f64.to_radians());
        for bad in ["5:85", "85:5:5", "5:85:0", "0:85:5", "5:95:5", "a:b:c"] {
            assert!(
                message(angle_range_rad("sweep-deg", bad).unwrap_err()).starts_with("--sweep-deg "),
                "{bad}"
            );
        }
        assert!(message(peak_select("best").unwrap_err()).starts_with("--peak-select "));
        assert_eq!(threshold("AUTO", 1023).unwrap(), Threshold::Automatic);
        assert!(message(threshold("1024", 1023).unwrap_err()).starts_with("--threshold "));
    }
}
