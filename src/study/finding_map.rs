//! Where the paper's scan-angle finding holds: the BIP error at the paper's shallow angle (10°)
//! against its steep one (40°) over a grid of the edge's arris width × roughness, at each
//! exposure of the study's exposure axis.
//!
//! The paper (Adrian & Pham, §III-C, Fig. 7) found the edge readings at 40° closer to p_e than
//! at 10°. Whether a simulated pane shows that depends on its edge section (the arris seen
//! nearly head-on at 40–45° but at 35° at 10°), on how widely its ground finish back-scatters
//! (roughness) and on the exposure (which parts clear the threshold). Each cell of the map is
//! the bare scene with both arrisses set to one face width and the edge to one GGX roughness
//! (`dataset::scene_edit`), scanned at both angles on the same positions (poses planned on the
//! true border; common random numbers across cells and angles, since the streams are keyed on
//! the seed and the pose index), traced once per pose and sensed at every exposure.
//!
//! The finding "holds" in a cell when the 10° error is at least [`HOLDS_RATIO`] times the 40°
//! error and larger by at least [`HOLDS_MARGIN_MM`]: clearly worse, not only in ratio (both can
//! be small). Cells where a rule finds no BIP at an angle are reported with that angle's valid
//! fraction and no verdict.

use super::edge_frame::EdgeFrame;
use super::side_by_side::map_poses;
use super::tally::{by_setting, PoseTally, RuleSummary};
use crate::dataset::randomize::Param;
use crate::dataset::scene_edit::SceneTemplate;
use crate::scan::poses::plan_border_scan;
use crate::scan::simulate::trace_pose;
use crate::scan::ScanConfig;
use crate::sensor::SensorHead;
use crate::transport::{TraceScene, TraceSettings};

/// The 10° error must be at least this many times the 40° error for the finding to hold.
pub const HOLDS_RATIO: f64 = 2.0;
/// … and larger by at least this much (mm): about the profile's resolution at a corner (one
/// column is ~0.2 mm along the laser line), so that two errors within a column do not count.
pub const HOLDS_MARGIN_MM: f64 = 0.2;

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct FindingMapConfig {
    /// Face widths of the arrisses (mm), both corners; 0 is a sharp (flat-ground) edge.
    pub arris_widths_mm: Vec<f64>,
    /// GGX roughness values α of the ground edge.
    pub roughness: Vec<f64>,
    /// The shallow and the steep scan angle (rad): the paper's 10° and 40°.
    pub angles_rad: [f64; 2],
    /// Exposures (s) at which every pose is sensed.
    pub exposures_s: Vec<f64>,
    /// Scan settings: `poses` positions per angle; the angle is replaced.
    pub scan: ScanConfig,
    /// Photons, depth and seed.
    pub trace: TraceSettings,
}

impl FindingMapConfig {
    /// Poses to trace in all (the progress bar's length).
    pub fn simulations(&self) -> usize {
        self.arris_widths_mm.len() * self.roughness.len() * 2 * self.scan.poses
    }
}

/// One (arris width, roughness) cell.
#[derive(Clone, Debug, PartialEq)]
pub struct MapCell {
    /// Arris face width (mm).
    pub arris_width_mm: f64,
    /// GGX roughness α.
    pub roughness: f64,
    /// Per exposure, per angle (shallow, steep), both rules.
    pub rules: Vec<[[RuleSummary; 2]; 2]>,
}

impl MapCell {
    /// Per exposure, the ratio of the shallow to the steep angle's mean BIP error by rule `k`
    /// (NaN if either has no BIP).
    pub fn ratio(&self, exposure: usize, k: usize) -> f64 {
        let [shallow, steep] = &self.rules[exposure];
        shallow[k].error_mm.mean / steep[k].error_mm.mean
    }

    /// Whether the paper's finding holds at `exposure` by rule `k` (see the module docs);
    /// `None` when a rule found no BIP at some position of either angle.
    pub fn holds(&self, exposure: usize, k: usize) -> Option<bool> {
        let [shallow, steep] = &self.rules[exposure];
        if shallow[k].valid_fraction < 1.0 || steep[k].valid_fraction < 1.0 {
            return None;
        }
        let (a, b) = (shallow[k].error_mm.mean, steep[k].error_mm.mean);
        Some(a >= HOLDS_RATIO * b && a - b >= HOLDS_MARGIN_MM)
    }
}

/// Runs every cell of the map on `template` (the bare scene). `on_pose` is called after each
/// traced pose. Errors are a cell's scene refusing its edit (a message naming the value).
pub fn run_finding_map(
    template: &SceneTemplate,
    cfg: &FindingMapConfig,
    on_pose: &(dyn Fn() + Sync),
) -> Result<Vec<MapCell>, String> {
    let mut cells = Vec::new();
    for &w in &cfg.arris_widths_mm {
        for &alpha in &cfg.roughness {
            let world = template
                .world_with(&[(Param::ArrisWidthMm, w), (Param::EdgeRoughness, alpha)])
                .map_err(|m| format!("arris width {w} mm, roughness {alpha}: {m}"))?;
            let scene = TraceScene::new(&world).map_err(|e| e.to_string())?;
            let head = SensorHead::new(&world.sensor).map_err(|e| e.to_string())?;
            let border_b = world
                .true_border_in_base()
                .ok_or("the scene has no [target]")?;
            let heads: Vec<SensorHead> = cfg
                .exposures_s
                .iter()
                .map(|&e| {
                    let mut h = head.clone();
                    h.config.imager.exposure_s = e;
                    h
                })
                .collect();
            // tallies[angle][exposure][position]
            let mut tallies = [Vec::new(), Vec::new()];
            for (a, &angle) in cfg.angles_rad.iter().enumerate() {
                let scan = ScanConfig {
                    scan_angle_rad: angle,
                    ..cfg.scan
                };
                let poses = plan_border_scan(&border_b, &scan, &world.mount);
                let by_pose = map_poses(&poses, on_pose, |pose| {
                    let frame = EdgeFrame::of_pose(&border_b, pose);
                    let (irradiance, _) =
                        trace_pose(&scene, &head, pose, &cfg.trace, super::tally::STOP_RULES);
                    PoseTally::for_heads(&irradiance, &heads, pose, &cfg.trace, &frame)
                });
                tallies[a] = by_setting(by_pose, heads.len());
            }
            let rules = (0..heads.len())
                .map(|e| {
                    [
                        RuleSummary::both(&tallies[0][e]),
                        RuleSummary::both(&tallies[1][e]),
                    ]
                })
                .collect();
            cells.push(MapCell {
                arris_width_mm: w,
                roughness: alpha,
                rules,
            });
        }
    }
    Ok(cells)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::localise::metrics::Stats;
    use crate::study::tally::RULES;

    fn summary(k: usize, mean: f64, valid: f64) -> RuleSummary {
        RuleSummary {
            rule: RULES[k],
            error_mm: Stats::from_values(&[mean, mean]),
            valid_fraction: valid,
        }
    }

    fn cell(shallow: f64, steep: f64, valid: f64) -> MapCell {
        MapCell {
            arris_width_mm: 0.8,
            roughness: 0.3,
            rules: vec![[
                [summary(0, shallow, 1.0), summary(1, shallow, 1.0)],
                [summary(0, steep, valid), summary(1, steep, valid)],
            ]],
        }
    }

    #[test]
    fn the_finding_holds_only_when_10_degrees_is_clearly_worse() {
        assert_eq!(cell(1.0, 0.1, 1.0).holds(0, 1), Some(true));
        assert!((cell(1.0, 0.1, 1.0).ratio(0, 1) - 10.0).abs() < 1e-12);
        // Twice as bad but within a column: no.
        assert_eq!(cell(0.16, 0.08, 1.0).holds(0, 1), Some(false));
        // 10° better: no.
        assert_eq!(cell(0.1, 1.0, 1.0).holds(0, 0), Some(false));
        // A position without a BIP at 40°: no verdict.
        assert_eq!(cell(1.0, 0.1, 0.75).holds(0, 1), None);
    }
}
