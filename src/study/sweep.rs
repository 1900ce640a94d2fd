//! The process engineer's sweep: BIP error, valid fraction, saturation and wrong-surface
//! fraction over a grid of scan angle × exposure × threshold × peak selection
//! (`study::grid`), poses planned on the true border (nominal = true pose).
//!
//! The light reaching the image plane depends on the scan angle only, not on the exposure, the
//! threshold or the peak selection. So each (angle, pose) is traced once
//! (`scan::simulate::trace_pose`) and then sensed once per sensor setting
//! (`scan::simulate::sense`), in parallel over the settings and with the poses side by side
//! (`study::side_by_side`); each setting gives exactly what `simulate_pose` with that setting
//! would, since the noise is keyed on the seed and the pose index alone. Results are collected in cell order, so they do not depend on the thread
//! count.

use super::edge_frame::EdgeFrame;
use super::grid::{Cell, SweepGrid};
use super::side_by_side::map_poses;
use super::tally::{by_setting, PoseTally, RuleSummary};
use crate::geometry::border::BorderCurve;
use crate::geometry::pose::Pose;
use crate::scan::poses::plan_border_scan;
use crate::scan::simulate::trace_pose;
use crate::scan::ScanConfig;
use crate::sensor::SensorHead;
use crate::transport::{TraceScene, TraceSettings};

/// One cell's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct CellResult {
    /// The cell.
    pub cell: Cell,
    /// One tally per pose.
    pub tallies: Vec<PoseTally>,
    /// BIP error by both rules.
    pub rules: [RuleSummary; 2],
}

impl CellResult {
    fn new(cell: Cell, tallies: Vec<PoseTally>) -> CellResult {
        CellResult {
            cell,
            rules: RuleSummary::both(&tallies),
            tallies,
        }
    }

    /// Saturated pixels / all pixels over the poses.
    pub fn saturated_pixel_fraction(&self) -> f64 {
        let s: usize = self.tallies.iter().map(|t| t.saturated_pixels).sum();
        let n: usize = self.tallies.iter().map(|t| t.pixels).sum();
        s as f64 / n as f64
    }

    /// Valid points over the poses.
    pub fn valid_points(&self) -> usize {
        self.tallies.iter().map(|t| t.valid_points).sum()
    }

    /// Valid points from the wrong surface / valid points (`study::wrong_surface`); NaN when
    /// no point is valid.
    pub fn wrong_surface_fraction(&self) -> f64 {
        let w: usize = self.tallies.iter().map(|t| t.wrong_surface_points).sum();
        w as f64 / self.valid_points() as f64
    }
}

/// The head of one sensor setting: `base` with the cell's exposure, threshold and peak
/// selection. The camera does not depend on them, so it is reused as built.
pub fn head_for(base: &SensorHead, grid: &SweepGrid, cell: &Cell) -> SensorHead {
    let mut head = base.clone();
    head.config.imager.exposure_s = grid.exposures_s[cell.exposure];
    head.config.firmware.threshold = grid.thresholds[cell.threshold];
    head.config.firmware.peak_select = grid.peak_selects[cell.peak_select];
    head
}

/// Runs every cell of `grid`: `scan.poses` poses per angle on `border_b` (the true border in
/// the base frame). `on_pose` is called after each traced (angle, pose), from any thread.
#[allow(clippy::too_many_arguments)]
pub fn run_sweep(
    scene: &TraceScene,
    base: &SensorHead,
    border_b: &BorderCurve,
    mount: &Pose,
    scan: &ScanConfig,
    grid: &SweepGrid,
    trace: &TraceSettings,
    on_pose: &(dyn Fn() + Sync),
) -> Vec<CellResult> {
    let cells = grid.cells();
    let per_angle = grid.sensor_settings();
    let mut results = Vec::with_capacity(cells.len());
    for (angle, angle_cells) in cells.chunks(per_angle.max(1)).enumerate() {
        let heads: Vec<SensorHead> = angle_cells
            .iter()
            .map(|c| head_for(base, grid, c))
            .collect();
        let scan = ScanConfig {
            scan_angle_rad: grid.angles_rad[angle],
            ..*scan
        };
        let poses = plan_border_scan(border_b, &scan, mount);
        let by_pose = map_poses(&poses, on_pose, |pose| {
            let frame = EdgeFrame::of_pose(border_b, pose);
            let (irradiance, _) = trace_pose(scene, base, pose, trace, super::tally::STOP_RULES);
            PoseTally::for_heads(&irradiance, &heads, pose, trace, &frame)
        });
        let tallies = by_setting(by_pose, heads.len());
        results.extend(
            angle_cells
                .iter()
                .zip(tallies)
                .map(|(c, t)| CellResult::new(*c, t)),
        );
    }
    results
}
