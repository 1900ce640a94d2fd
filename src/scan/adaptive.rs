//! The adaptive photon count's stopping rule: a pose takes photons until its BIPs stop moving.
//!
//! The rendering grows by photon sets (`transport::trace::FIRST_PHOTON_SET` F = 2¹⁶, then
//! doubling: 2F, 4F, …), each stratified over the laser fan on its own (the loop is
//! `scan::simulate::simulate_pose` with `TraceSettings::adaptive`). After every doubling from n
//! to 2n photons the pose is sensed three times with the same seed (the same speckle and sensor
//! noise, so only the Monte Carlo differs): from the first n photons (A), from the newest n
//! alone (B) and from all 2n. The pose stops when each BIP rule it converges on picks the same
//! profile point in all three, or none in all three, or the settings' photon count is reached.
//!
//! Which rules: those whose BIPs the command reports ([`StopRules`]). A rule that is not
//! reported must not hold a pose back, and one that is reported must not be left unsettled:
//! - `scan`, `dataset` and Python's `simulate` report profiles, not BIPs; they converge on the
//!   edge-line rule, glassscan's default BIP (`StopRules::EDGE_LINE`).
//! - `locate` registers with one rule and also reports the paper's highest point: both.
//! - the studies tally both rules: both. (With the edge-line rule alone, the study's 10° cells
//!   took one highest-rule BIP 60 mm off at 2¹⁷: a spurious face point only that rule sees.)
//!
//! On a curved pane (`car_side_window`) the highest point wanders over a plateau of face points
//! tens of millimetres wide at every count up to 2²⁰ while the edge-line BIP stays on one point
//! from 2¹⁷: converging on a rule that is not reported would trace such poses to the most
//! photons for nothing.
//!
//! Why this test: A and B are independent estimates at n photons, so their BIPs falling on one
//! profile point is evidence that the BIP at 2n (which averages them) is away from the knife
//! edges where a little more or less of the faint face return moves it by a point; a BIP near
//! such a knife edge differs between the halves and the pose takes more photons. It is the
//! pose-by-pose form of the convergence test's criterion 2 (`study::convergence`), with the
//! Monte Carlo's own halves as the yardstick instead of a 2²²-photon reference, and stricter
//! (the same point, not within 0.2 mm); whether the counts it stops at are converged is what
//! that test measures (validation/results/convergence/README.md).
//!
//! Deterministic: the decisions depend only on the images, which depend only on (seed, pose),
//! not on the thread count. The earliest stop is 2F = 2¹⁷ photons, the count from which the
//! convergence test's column criterion holds on every shipped glass scene tested.

use super::bip::{find_bip, BipRule};
use crate::geometry::pose::Pose;
use crate::sensor::image::Image;
use crate::sensor::profile::Profile;
use crate::transport::Irradiance;

/// The irradiance of the newest half of a rendering of 2n photons: 2·(all 2n) − (first n), per
/// pixel and class (each developed image is a mean over its photons). Rounding can leave a
/// few ulps of negative light where the newest half has none; those are set to zero.
pub fn newest_half(all: &Irradiance, first: &Irradiance) -> Irradiance {
    let half = |a: &Image<f64>, f: &Image<f64>| {
        let mut out = a.clone();
        for (o, v) in out.data.iter_mut().zip(&f.data) {
            *o = (2.0 * *o - v).max(0.0);
        }
        out
    };
    Irradiance {
        total: half(&all.total, &first.total),
        by_class: all
            .by_class
            .iter()
            .zip(&first.by_class)
            .map(|(a, f)| half(a, f))
            .collect(),
    }
}

/// The BIP rules whose points an adaptive pose waits for (with a fixed photon count, none
/// are looked at).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StopRules(&'static [BipRule]);

impl StopRules {
    /// glassscan's default BIP: for commands that report profiles rather than BIPs.
    pub const EDGE_LINE: StopRules = StopRules(&[BipRule::EdgeLine]);
    /// The paper's highest point alone.
    pub const HIGHEST: StopRules = StopRules(&[BipRule::Highest]);
    /// Both rules: `locate` registering with the edge-line rule.
    pub const BOTH: StopRules = StopRules(&[BipRule::EdgeLine, BipRule::Highest]);

    /// Waits for `rules`: those a command reports (a study: the rules it tallies).
    pub const fn of(rules: &'static [BipRule]) -> StopRules {
        StopRules(rules)
    }

    /// The rules a command reports when it registers with `rule` and also reports the paper's
    /// highest point beside it (`locate`).
    pub fn registering_with(rule: BipRule) -> StopRules {
        match rule {
            BipRule::Highest => StopRules::HIGHEST,
            BipRule::EdgeLine => StopRules::BOTH,
        }
    }

    /// The profile points (indices) that the rules pick in `profile`, taken by the sensor at
    /// T_BS = `sensor`, in the rules' order.
    pub fn bip_points(self, profile: &Profile, sensor: &Pose) -> Vec<Option<usize>> {
        self.0
            .iter()
            .map(|&rule| find_bip(profile, sensor, rule).map(|b| b.profile_index))
            .collect()
    }
}

/// Whether the BIPs of the first half, the newest half and the whole agree: for each rule,
/// all the same profile point, or all absent.
pub fn agree(bips: &[Vec<Option<usize>>]) -> bool {
    bips.windows(2).all(|w| w[0] == w[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bips_agree_when_all_are_one_profile_point_or_all_are_missing() {
        let same = |a, b| vec![Some(a), Some(b)];
        assert!(agree(&[same(7, 9), same(7, 9), same(7, 9)]));
        assert!(!agree(&[same(7, 9), same(8, 9), same(7, 9)]));
        assert!(!agree(&[same(7, 9), same(7, 9), same(7, 10)]));
        let absent = || vec![None, Some(3)];
        assert!(agree(&[absent(), absent(), absent()]));
        assert!(!agree(&[same(7, 9), vec![None, Some(9)], same(7, 9)]));
    }
}
