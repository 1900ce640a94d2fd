//! Shards of a dataset run: shard K of N (0-based K < N) takes the samples i with i % N = K, so
//! N machines (a Slurm job array, a Kubernetes indexed job) can make one dataset together and
//! `glassscan merge` joins their manifests.
//!
//! The shard comes from `--shard K/N`, or else from the scheduler's environment:
//! - Slurm job arrays: `SLURM_ARRAY_TASK_ID` with `SLURM_ARRAY_TASK_COUNT`, or with
//!   `SLURM_ARRAY_TASK_MIN`/`SLURM_ARRAY_TASK_MAX` (and `SLURM_ARRAY_TASK_STEP` for arrays like
//!   `--array=0-14:2`); K = (ID − MIN) / STEP, so `--array=1-8` works as well as `0-7`;
//! - Kubernetes indexed jobs: `JOB_COMPLETION_INDEX` with the count from
//!   `GLASSSCAN_SHARD_COUNT` (the job's `completions`, which Kubernetes does not export).
//!
//! Every error names the flag or variable that holds the bad value.

use super::DatasetError;

/// Shard `index` of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    /// K, in `0..count`.
    pub index: u64,
    /// N ≥ 1.
    pub count: u64,
}

impl Shard {
    /// The whole run: shard 0 of 1.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Whether sample `i` belongs to this shard.
    pub fn contains(&self, i: u64) -> bool {
        i % self.count == self.index
    }

    /// The sample indices of this shard among `0..samples`, in increasing order.
    pub fn indices(&self, samples: u64) -> impl Iterator<Item = u64> {
        (self.index..samples).step_by(self.count as usize)
    }

    /// Name of this shard's manifest: `manifest.jsonl` for an unsharded run (it needs no
    /// merge), `manifest-shard-K-of-N.jsonl` otherwise.
    pub fn manifest_name(&self) -> String {
        if self.count == 1 {
            super::manifest::MANIFEST.to_owned()
        } else {
            format!("manifest-shard-{}-of-{}.jsonl", self.index, self.count)
        }
    }

    /// Parses a shard manifest's file name back into its shard (`None` for other names).
    pub fn from_manifest_name(name: &str) -> Option<Shard> {
        let rest = name
            .strip_prefix("manifest-shard-")?
            .strip_suffix(".jsonl")?;
        let (k, n) = rest.split_once("-of-")?;
        let shard = Shard {
            index: k.parse().ok()?,
            count: n.parse().ok()?,
        };
        (shard.index < shard.count).then_some(shard)
    }

    /// Parses `--shard K/N`.
    pub fn parse_flag(text: &str) -> Result<Shard, DatasetError> {
        let bad = |message: String| DatasetError::Shard {
            origin: "--shard".into(),
            message,
        };
        let Some((k, n)) = text.split_once('/') else {
            return Err(bad(format!(
                "expected K/N with 0 ≤ K < N (e.g. 0/4), got {text:?}"
            )));
        };
        let k = parse_count(k.trim()).ok_or_else(|| {
            bad(format!(
                "expected K/N with K a non-negative integer, got {text:?}"
            ))
        })?;
        let n = parse_count(n.trim()).ok_or_else(|| {
            bad(format!(
                "expected K/N with N a positive integer, got {text:?}"
            ))
        })?;
        check(k, n).map_err(|m| bad(format!("{m}, got {text:?}")))
    }

    /// The shard a scheduler assigned through the environment, read with `var` (the process
    /// environment in the CLI, a map in tests); `None` when no scheduler variable is set.
    pub fn from_env(var: impl Fn(&str) -> Option<String>) -> Result<Option<Shard>, DatasetError> {
        let get = |name: &str| -> Result<Option<u64>, DatasetError> {
            match var(name) {
                None => Ok(None),
                Some(v) => parse_count(v.trim())
                    .map(Some)
                    .ok_or_else(|| DatasetError::Shard {
                        origin: name.into(),
                        message: format!("expected a non-negative integer, got {v:?}"),
                    }),
            }
        };
        if let Some(id) = get("SLURM_ARRAY_TASK_ID")? {
            return slurm(id, &get).map(Some);
        }
        let count = get("GLASSSCAN_SHARD_COUNT")?;
        match (get("JOB_COMPLETION_INDEX")?, count) {
            (Some(k), Some(n)) => check(k, n).map(Some).map_err(|m| DatasetError::Shard {
                origin: "JOB_COMPLETION_INDEX".into(),
                message: format!("{m} (N from GLASSSCAN_SHARD_COUNT = {n}), got K = {k}"),
            }),
            (Some(_), None) => Err(DatasetError::Shard {
                origin: "GLASSSCAN_SHARD_COUNT".into(),
                message: "is not set, but JOB_COMPLETION_INDEX is: set it to the indexed \
                          job's `completions`"
                    .into(),
            }),
            (None, Some(_)) => Err(DatasetError::Shard {
                origin: "JOB_COMPLETION_INDEX".into(),
                message: "is not set, but GLASSSCAN_SHARD_COUNT is: run as a Kubernetes \
                          indexed job, or pass --shard K/N"
                    .into(),
            }),
            (None, None) => Ok(None),
        }
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// A non-negative decimal integer (no sign, no spaces inside).
fn parse_count(text: &str) -> Option<u64> {
    if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    text.parse().ok()
}

fn check(k: u64, n: u64) -> Result<Shard, String> {
    if n == 0 {
        Err("expected N ≥ 1".into())
    } else if k >= n {
        Err(format!(
            "expected K < N (K counts from 0), K = {k}, N = {n}"
        ))
    } else {
        Ok(Shard { index: k, count: n })
    }
}

fn slurm(
    id: u64,
    get: &impl Fn(&str) -> Result<Option<u64>, DatasetError>,
) -> Result<Shard, DatasetError> {
    let bad = |origin: &str, message: String| DatasetError::Shard {
        origin: origin.into(),
        message,
    };
    let min = get("SLURM_ARRAY_TASK_MIN")?;
    let max = get("SLURM_ARRAY_TASK_MAX")?;
    let step = get("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1);
    if step == 0 {
        return Err(bad("SLURM_ARRAY_TASK_STEP", "expected ≥ 1, got 0".into()));
    }
    let count = match (get("SLURM_ARRAY_TASK_COUNT")?, min, max) {
        (Some(n), _, _) => n,
        (None, Some(lo), Some(hi)) if hi >= lo => (hi - lo) / step + 1,
        (None, Some(lo), Some(hi)) => {
            return Err(bad(
                "SLURM_ARRAY_TASK_MAX",
                format!("expected ≥ SLURM_ARRAY_TASK_MIN = {lo}, got {hi}"),
            ))
        }
        _ => {
            return Err(bad(
                "SLURM_ARRAY_TASK_COUNT",
                "is not set, and neither are both SLURM_ARRAY_TASK_MIN and \
                 SLURM_ARRAY_TASK_MAX: cannot tell how many shards the job array has"
                    .into(),
            ))
        }
    };
    let lo = min.unwrap_or(0);
    if id < lo || (id - lo) % step != 0 {
        return Err(bad(
            "SLURM_ARRAY_TASK_ID",
            format!(
                "expected MIN + k·STEP (MIN = {lo}, STEP = {step}), got {id}: only arrays \
                 of evenly spaced task ids can be mapped to shards"
            ),
        ));
    }
    let k = (id - lo) / step;
    check(k, count).map_err(|m| {
        bad(
            "SLURM_ARRAY_TASK_ID",
            format!("{m} (K = (ID − MIN) / STEP, N = the array's task count), got ID {id}"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let map: HashMap<String, String> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |k| map.get(k).cloned()
    }

    fn shard(index: u64, count: u64) -> Shard {
        Shard { index, count }
    }

    #[test]
    fn flag_parses_k_of_n() {
        assert_eq!(Shard::parse_flag("0/1").unwrap(), Shard::ALL);
        assert_eq!(Shard::parse_flag("3/8").unwrap(), shard(3, 8));
        assert_eq!(Shard::parse_flag(" 1 / 2 ").unwrap(), shard(1, 2));
    }

    #[test]
    fn bad_flags_name_the_flag_and_say_what_was_expected() {
        for (text, expected) in [
            ("2/2", "K < N"),
            ("5/2", "K < N"),
            ("0/0", "N ≥ 1"),
            ("1", "K/N"),
            ("-1/2", "non-negative"),
            ("a/2", "non-negative"),
            ("1/x", "positive"),
            ("1/2/3", "positive"),
        ] {
            let message = Shard::parse_flag(text).unwrap_err().to_string();
            assert!(
                message.starts_with("--shard: ") && message.contains(expected),
                "{text}: {message}"
            );
        }
    }

    #[test]
    fn samples_are_dealt_round_robin() {
        let s = shard(1, 3);
        assert_eq!(s.indices(8).collect::<Vec<_>>(), [1, 4, 7]);
        assert!(s.contains(4) && !s.contains(5));
        let all: Vec<u64> = (0..3).flat_map(|k| shard(k, 3).indices(8)).collect();
        assert_eq!(all.len(), 8);
        assert_eq!(Shard::ALL.indices(3).collect::<Vec<_>>(), [0, 1, 2]);
    }

    #[test]
    fn manifest_names_round_trip() {
        assert_eq!(Shard::ALL.manifest_name(), "manifest.jsonl");
        let s = shard(2, 5);
        assert_eq!(s.manifest_name(), "manifest-shard-2-of-5.jsonl");
        assert_eq!(Shard::from_manifest_name(&s.manifest_name()), Some(s));
        for other in [
            "manifest.jsonl",
            "manifest-shard-5-of-5.jsonl",
            "manifest-shard-x-of-5.jsonl",
            "run.json",
        ] {
            assert_eq!(Shard::from_manifest_name(other), None, "{other}");
        }
    }

    #[test]
    fn no_scheduler_means_no_shard() {
        assert_eq!(Shard::from_env(env(&[])).unwrap(), None);
        assert_eq!(
            Shard::from_env(env(&[("SLURM_JOB_ID", "17")])).unwrap(),
            None
        );
    }

    #[test]
    fn slurm_arrays_map_to_shards() {
        let cases: [(&[(&str, &str)], Shard); 4] = [
            (
                &[
                    ("SLURM_ARRAY_TASK_ID", "3"),
                    ("SLURM_ARRAY_TASK_COUNT", "8"),
                ],
                shard(3, 8),
            ),
            (
                &[
                    ("SLURM_ARRAY_TASK_ID", "8"),
                    ("SLURM_ARRAY_TASK_MIN", "1"),
                    ("SLURM_ARRAY_TASK_MAX", "8"),
                ],
                shard(7, 8),
            ),
            (
                &[
                    ("SLURM_ARRAY_TASK_ID", "6"),
                    ("SLURM_ARRAY_TASK_MIN", "0"),
                    ("SLURM_ARRAY_TASK_MAX", "14"),
                    ("SLURM_ARRAY_TASK_STEP", "2"),
                ],
                shard(3, 8),
            ),
            (
                &[
                    ("SLURM_ARRAY_TASK_ID", "0"),
                    ("SLURM_ARRAY_TASK_COUNT", "1"),
                    ("JOB_COMPLETION_INDEX", "5"),
                ],
                Shard::ALL,
            ),
        ];
        for (vars, expected) in cases {
            assert_eq!(
                Shard::from_env(env(vars)).unwrap(),
                Some(expected),
                "{vars:?}"
            );
        }
    }

    #[test]
    fn kubernetes_indexed_jobs_map_to_shards() {
        let vars = [
            ("JOB_COMPLETION_INDEX", "2"),
            ("GLASSSCAN_SHARD_COUNT", "4"),
        ];
        assert_eq!(Shard::from_env(env(&vars)).unwrap(), Some(shard(2, 4)));
    }

    #[test]
    fn bad_environments_name_the_variable() {
        let cases: [(&[(&str, &str)], &str); 7] = [
            (&[("SLURM_ARRAY_TASK_ID", "3")], "SLURM_ARRAY_TASK_COUNT"),
            (
                &[
                    ("SLURM_ARRAY_TASK_ID", "x"),
                    ("SLURM_ARRAY_TASK_COUNT", "8"),
                ],
                "SLURM_ARRAY_TASK_ID",
            ),
            (
                &[
                    ("SLURM_ARRAY_TASK_ID", "8"),
                    ("SLURM_ARRAY_TASK_COUNT", "8"),
                ],
                "SLURM_ARRAY_TASK_ID",
            ),
            (
                &[
                    ("SLURM_ARRAY_TASK_ID", "3"),
                    ("SLURM_ARRAY_TASK_MIN", "0"),
                    ("SLURM_ARRAY_TASK_MAX", "14"),
                    ("SLURM_ARRAY_TASK_STEP", "2"),
                ],
                "SLURM_ARRAY_TASK_ID",
            ),
            (&[("JOB_COMPLETION_INDEX", "2")], "GLASSSCAN_SHARD_COUNT"),
            (
                &[
                    ("JOB_COMPLETION_INDEX", "4"),
                    ("GLASSSCAN_SHARD_COUNT", "4"),
                ],
                "JOB_COMPLETION_INDEX",
            ),
            (&[("GLASSSCAN_SHARD_COUNT", "4")], "JOB_COMPLETION_INDEX"),
        ];
        for (vars, name) in cases {
            let message = Shard::from_env(env(vars)).unwrap_err().to_string();
            assert!(
                message.starts_with(&format!("{name}: ")),
                "{vars:?}: {message}"
            );
        }
    }
}
