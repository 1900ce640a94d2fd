//! The firmware's peak ("reflection") selection modes (docs/parameters.md §1a, §1d).

use std::fmt;
use std::str::FromStr;

use super::peaks::Peak;

/// Which of a column's peaks become profile points. The SDK's PROC_MULITREFL_* values, bits 2–4
/// of the PROFILE_PROCESSING register 0xF0F00804 (docs/parameters.md §1a).
///
/// Peaks are ordered top to bottom. Rows grow with range z (`camera`), so the top peak is the
/// one nearest the sensor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PeakSelect {
    /// Every peak is a point, with its slot 0…3 as the reflection index.
    All,
    /// The peak nearest the sensor (smallest z, smallest row): the iirob driver's default
    /// (docs/parameters.md §1d).
    First,
    /// The peak farthest from the sensor (largest z, largest row).
    Last,
    /// The peak of largest M0 (summed intensity, the SDK's "area"); ties go to the first.
    LargestArea,
    /// The peak of highest maximum intensity; ties go to the first.
    MaxIntensity,
    /// The only peak; a column with more than one peak is invalid (docs/parameters.md §1d reads
    /// SINGLE this way; the SDK does not document it).
    Single,
}

impl PeakSelect {
    /// Every mode, in SDK order.
    pub const ALL: [PeakSelect; 6] = [
        PeakSelect::All,
        PeakSelect::First,
        PeakSelect::Last,
        PeakSelect::LargestArea,
        PeakSelect::MaxIntensity,
        PeakSelect::Single,
    ];

    /// The SDK name in snake_case, as accepted by [`FromStr`].
    pub fn name(self) -> &'static str {
        match self {
            PeakSelect::All => "all",
            PeakSelect::First => "first",
            PeakSelect::Last => "last",
            PeakSelect::LargestArea => "largest_area",
            PeakSelect::MaxIntensity => "max_intensity",
            PeakSelect::Single => "single",
        }
    }

    /// The SDK's value of the mode (PROC_MULITREFL_ALL = 0 … SINGLE = 5).
    pub fn sdk_code(self) -> u8 {
        match self {
            PeakSelect::All => 0,
            PeakSelect::First => 1,
            PeakSelect::Last => 2,
            PeakSelect::LargestArea => 3,
            PeakSelect::MaxIntensity => 4,
            PeakSelect::Single => 5,
        }
    }

    /// Slots (indices into `peaks`, top to bottom) of the peaks to report, in slot order; empty
    /// if the column has no point.
    pub(super) fn select(self, peaks: &[Peak]) -> Vec<usize> {
        // `max_by` keeps the last of equal elements; comparing reversed indices on ties makes
        // it keep the first.
        let first_best = |key: &dyn Fn(&Peak) -> f64| {
            (0..peaks.len())
                .max_by(|&a, &b| key(&peaks[a]).total_cmp(&key(&peaks[b])).then(b.cmp(&a)))
        };
        let chosen = match self {
            PeakSelect::All => return (0..peaks.len()).collect(),
            PeakSelect::First => (!peaks.is_empty()).then_some(0),
            PeakSelect::Last => peaks.len().checked_sub(1),
            PeakSelect::LargestArea => first_best(&|p| p.m0),
            PeakSelect::MaxIntensity => first_best(&|p| f64::from(p.max_dn)),
            PeakSelect::Single => (peaks.len() == 1).then_some(0),
        };
        chosen.into_iter().collect()
    }
}

impl fmt::Display for PeakSelect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A peak selection name that is not one of the SDK's.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error(
    "unknown peak selection \"{found}\": expected one of all, first, last, largest_area, \
     max_intensity, single"
)]
pub struct UnknownPeakSelect {
    /// The name given.
    pub found: String,
}

impl FromStr for PeakSelect {
    type Err = UnknownPeakSelect;

    /// Parses an SDK mode name, case-insensitively (`first`, `LARGEST_AREA`, …).
    fn from_str(s: &str) -> Result<PeakSelect, UnknownPeakSelect> {
        PeakSelect::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| UnknownPeakSelect {
                found: s.to_owned(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn peak(row: usize, max_dn: u16, m0: f64) -> Peak {
        Peak {
            first_row: row,
            last_row: row,
            window: (row, row),
            max_dn,
            m0,
            m1: m0 * (row as f64 + 0.5),
        }
    }

    #[test]
    fn each_mode_picks_its_peak() {
        let peaks = [
            peak(10, 300, 500.0),
            peak(20, 900, 800.0),
            peak(30, 900, 2000.0),
            peak(40, 200, 2000.0),
        ];
        let pick = |m: PeakSelect| m.select(&peaks);
        assert_eq!(pick(PeakSelect::All), vec![0, 1, 2, 3]);
        assert_eq!(pick(PeakSelect::First), vec![0]);
        assert_eq!(pick(PeakSelect::Last), vec![3]);
        // Ties go to the first: peaks 2 and 3 share M0, peaks 1 and 2 the maximum.
        assert_eq!(pick(PeakSelect::LargestArea), vec![2]);
        assert_eq!(pick(PeakSelect::MaxIntensity), vec![1]);
        assert!(pick(PeakSelect::Single).is_empty());
        assert_eq!(PeakSelect::Single.select(&peaks[1..2]), vec![0]);
        for m in PeakSelect::ALL {
            assert!(m.select(&[]).is_empty(), "{m}");
        }
    }

    #[test]
    fn names_parse_case_insensitively_and_unknown_names_list_the_valid_ones() {
        for (i, m) in PeakSelect::ALL.into_iter().enumerate() {
            assert_eq!(m.sdk_code() as usize, i);
            assert_eq!(m.name().parse(), Ok(m));
            assert_eq!(m.name().to_uppercase().parse(), Ok(m));
        }
        assert_eq!("Largest_Area".parse(), Ok(PeakSelect::LargestArea));
        let err = "strongest".parse::<PeakSelect>().unwrap_err();
        assert_eq!(
            err.to_string(),
            "unknown peak selection \"strongest\": expected one of all, first, last, \
             largest_area, max_intensity, single"
        );
    }
}
