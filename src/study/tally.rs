//! What a study keeps of one simulated pose: the BIP by each rule and its error against p_e,
//! and the counts behind the saturated-pixel and wrong-surface fractions. Images are dropped,
//! so a study of hundreds of poses holds a few numbers per pose.

use rayon::prelude::*;
use serde::Serialize;

use super::edge_frame::EdgeFrame;
use super::wrong_surface::count_wrong_surface;
use crate::geometry::pose::Pose;
use crate::localise::metrics::Stats;
use crate::scan::adaptive::StopRules;
use crate::scan::bip::{find_bip, BipRule};
use crate::scan::poses::ScanPose;
use crate::scan::simulate::{frame_draws, sense, sense_drawn, Sensed};
use crate::sensor::path_class::PathClass;
use crate::sensor::SensorHead;
use crate::transport::{Irradiance, TraceSettings};

/// The BIP rules every study compares: the paper's highest point, then our edge-line variant.
pub const RULES: [BipRule; 2] = [BipRule::Highest, BipRule::EdgeLine];

/// With the adaptive count a study's pose waits for the BIPs of every rule it tallies.
pub const STOP_RULES: StopRules = StopRules::of(&RULES);

/// The BIP one rule picked at one pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BipOutcome {
    /// The rule.
    pub rule: BipRule,
    /// |BIP − p_e| (mm); `None` when the rule found no BIP.
    pub error_mm: Option<f64>,
    /// The BIP in the edge frame, (out_mm, up_mm).
    pub edge_mm: Option<(f64, f64)>,
    /// The path class of the BIP's peak.
    pub label: Option<PathClass>,
}

/// One pose, reduced.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseTally {
    /// One outcome per rule, in [`RULES`] order.
    pub bips: [BipOutcome; 2],
    /// Pixels at the full well or the ADC's full scale.
    pub saturated_pixels: usize,
    /// Pixels of the image.
    pub pixels: usize,
    /// Valid profile points.
    pub valid_points: usize,
    /// Valid profile points from the wrong surface (`study::wrong_surface`).
    pub wrong_surface_points: usize,
}

impl PoseTally {
    /// Reduces what the sensor at T_BS = `sensor` made of a pose, whose ground truth p_e is
    /// `frame.origin`.
    pub fn new(result: &Sensed, sensor: &Pose, frame: &EdgeFrame) -> PoseTally {
        let bips = RULES.map(|rule| {
            let bip = find_bip(&result.profile, sensor, rule);
            BipOutcome {
                rule,
                error_mm: bip.map(|b| (b.point_b - frame.origin).norm() * 1e3),
                edge_mm: bip.map(|b| frame.coordinates_mm(&b.point_b)),
                label: bip.and_then(|b| b.label),
            }
        });
        let (valid_points, wrong_surface_points) = count_wrong_surface(&result.profile);
        PoseTally {
            bips,
            saturated_pixels: result.saturated_pixels,
            pixels: result.image.data.len(),
            valid_points,
            wrong_surface_points,
        }
    }

    /// One traced pose's light sensed by each of `heads` (settings that leave the light as it
    /// is: exposure, threshold, peak selection), each reduced against `frame`; in `heads`'
    /// order. The sensor's noise is keyed on the seed and the pose, the same for every head.
    pub fn for_heads(
        irradiance: &Irradiance,
        heads: &[SensorHead],
        pose: &ScanPose,
        trace: &TraceSettings,
        frame: &EdgeFrame,
    ) -> Vec<PoseTally> {
        sensed_by_each(irradiance, heads, pose, trace)
            .iter()
            .map(|s| PoseTally::new(s, &pose.sensor, frame))
            .collect()
    }
}

/// One traced pose's light sensed by each of `heads`, in parallel, in `heads`' order: what
/// [`PoseTally::for_heads`] reduces, for a caller that also keeps a profile. The heads are
/// settings of one sensor (a study's exposure axis), so the frame's exposure-independent draws
/// are made once for all of them (`scan::simulate::frame_draws`); each result is
/// [`sense`]'s bit for bit.
pub fn sensed_by_each(
    irradiance: &Irradiance,
    heads: &[SensorHead],
    pose: &ScanPose,
    trace: &TraceSettings,
) -> Vec<Sensed> {
    if heads.len() < 2 {
        return heads
            .iter()
            .map(|head| sense(irradiance, head, pose, trace))
            .collect();
    }
    let draws = frame_draws(irradiance, pose, trace);
    heads
        .par_iter()
        .map(|head| sense_drawn(irradiance, head, &draws))
        .collect()
}

/// Tallies made pose by pose, one per sensor setting (`by_pose[pose][setting]`), regrouped by
/// setting (`[setting][pose]`), as the summaries take them.
pub fn by_setting(by_pose: Vec<Vec<PoseTally>>, settings: usize) -> Vec<Vec<PoseTally>> {
    let mut out = vec![Vec::with_capacity(by_pose.len()); settings];
    for tallies in by_pose {
        for (t, s) in out.iter_mut().zip(tallies) {
            t.push(s);
        }
    }
    out
}

/// BIP error statistics of one rule over a set of poses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RuleSummary {
    /// The rule.
    pub rule: BipRule,
    /// |BIP − p_e| (mm) over the poses with a BIP.
    pub error_mm: Stats,
    /// Poses with a BIP / poses (NaN for no poses).
    pub valid_fraction: f64,
}

impl RuleSummary {
    /// The summary of rule number `k` (in [`RULES`]) over `tallies`.
    pub fn of(tallies: &[PoseTally], k: usize) -> RuleSummary {
        let errors: Vec<f64> = tallies.iter().filter_map(|t| t.bips[k].error_mm).collect();
        RuleSummary {
            rule: RULES[k],
            valid_fraction: errors.len() as f64 / tallies.len() as f64,
            error_mm: Stats::from_values(&errors),
        }
    }

    /// Both rules, in [`RULES`] order.
    pub fn both(tallies: &[PoseTally]) -> [RuleSummary; 2] {
        [RuleSummary::of(tallies, 0), RuleSummary::of(tallies, 1)]
    }
}

/// The JSON form of a rule summary: the error statistics plus `valid_fraction`.
#[derive(Serialize)]
struct RuleJson {
    #[serde(flatten)]
    error_mm: Stats,
    valid_fraction: f64,
}

impl RuleSummary {
    /// `{"mean", "std", "max", "n", "valid_fraction"}` (NaN becomes JSON null).
    pub fn to_json(&self) -> serde_json::Value {
        let v = RuleJson {
            error_mm: self.error_mm,
            valid_fraction: self.valid_fraction,
        };
        serde_json::to_value(v).unwrap_or(serde_json::Value::Null)
    }
}

/// `{"highest": {...}, "edge-line": {...}}` of both rules.
pub fn by_rule_json(rules: &[RuleSummary; 2]) -> serde_json::Value {
    let mut m = serde_json::Map::new();
    for r in rules {
        m.insert(r.rule.name().to_owned(), r.to_json());
    }
    serde_json::Value::Object(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tally(errors: [Option<f64>; 2]) -> PoseTally {
        PoseTally {
            bips: [0, 1].map(|k| BipOutcome {
                rule: RULES[k],
                error_mm: errors[k],
                edge_mm: None,
                label: None,
            }),
            saturated_pixels: 0,
            pixels: 1,
            valid_points: 0,
            wrong_surface_points: 0,
        }
    }

    #[test]
    fn rule_summaries_count_poses_without_a_bip_as_invalid() {
        let t = [
            tally([Some(1.0), None]),
            tally([Some(3.0), Some(0.5)]),
            tally([None, None]),
            tally([None, Some(0.25)]),
        ];
        let [h, e] = RuleSummary::both(&t);
        assert_eq!(h.rule, BipRule::Highest);
        assert_eq!(
            (h.error_mm.mean, h.error_mm.max, h.valid_fraction),
            (2.0, 3.0, 0.5)
        );
        assert_eq!((e.error_mm.mean, e.valid_fraction), (0.375, 0.5));
        let j = by_rule_json(&[h, e]);
        assert_eq!(j["highest"]["mean"], 2.0);
        assert_eq!(j["edge-line"]["valid_fraction"], 0.5);
        // NaN statistics (no BIP anywhere) become null, not an invalid JSON number.
        let none = RuleSummary::of(&t[2..3], 0);
        assert!(none.to_json()["mean"].is_null());
    }
}
