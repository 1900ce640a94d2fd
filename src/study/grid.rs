//! The sweep's grid: every combination of scan angle, exposure, threshold and peak-selection
//! mode, in a fixed order (angle-major, then exposure, threshold, peak selection), so that cell
//! indices, tables and plots are the same on every run.

use crate::sensor::profile::{PeakSelect, Threshold};

/// The values of each swept setting.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepGrid {
    /// Scan angles (rad).
    pub angles_rad: Vec<f64>,
    /// Exposure times (s).
    pub exposures_s: Vec<f64>,
    /// Peak-detection thresholds.
    pub thresholds: Vec<Threshold>,
    /// Peak-selection modes.
    pub peak_selects: Vec<PeakSelect>,
}

/// One combination.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// Position in [`SweepGrid::cells`].
    pub index: usize,
    /// Index into `angles_rad`.
    pub angle: usize,
    /// Index into `exposures_s`.
    pub exposure: usize,
    /// Index into `thresholds`.
    pub threshold: usize,
    /// Index into `peak_selects`.
    pub peak_select: usize,
}

impl SweepGrid {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.angles_rad.len() * self.sensor_settings()
    }

    /// Whether the grid has no cell (some list is empty).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sensor settings per angle (exposure × threshold × peak selection): the cells that share
    /// one traced image per pose.
    pub fn sensor_settings(&self) -> usize {
        self.exposures_s.len() * self.thresholds.len() * self.peak_selects.len()
    }

    /// Every cell, angle-major.
    pub fn cells(&self) -> Vec<Cell> {
        let mut cells = Vec::with_capacity(self.len());
        for angle in 0..self.angles_rad.len() {
            for exposure in 0..self.exposures_s.len() {
                for threshold in 0..self.thresholds.len() {
                    for peak_select in 0..self.peak_selects.len() {
                        cells.push(Cell {
                            index: cells.len(),
                            angle,
                            exposure,
                            threshold,
                            peak_select,
                        });
                    }
                }
            }
        }
        cells
    }
}

/// The name of a threshold in tables and file names: the DN value or `auto`.
pub fn threshold_name(t: &Threshold) -> String {
    match t {
        Threshold::Fixed(v) => v.to_string(),
        Threshold::Automatic => "auto".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_cover_the_product_once_in_angle_major_order() {
        let g = SweepGrid {
            angles_rad: vec![0.2, 0.7, 0.8],
            exposures_s: vec![1e-4, 5e-4],
            thresholds: vec![Threshold::Fixed(128), Threshold::Automatic],
            peak_selects: vec![PeakSelect::First],
        };
        let cells = g.cells();
        assert_eq!(cells.len(), 12);
        assert_eq!(g.len(), 12);
        assert_eq!(g.sensor_settings(), 4);
        for (i, c) in cells.iter().enumerate() {
            assert_eq!(c.index, i);
            // Angle-major: the angle index changes every `sensor_settings` cells.
            assert_eq!(c.angle, i / 4);
        }
        assert_eq!((cells[1].exposure, cells[1].threshold), (0, 1));
        assert_eq!((cells[2].exposure, cells[2].threshold), (1, 0));
        let mut keys: Vec<_> = cells
            .iter()
            .map(|c| (c.angle, c.exposure, c.threshold, c.peak_select))
            .collect();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), 12);
        let empty = SweepGrid {
            peak_selects: vec![],
            ..g
        };
        assert!(empty.is_empty() && empty.cells().is_empty());
    }

    #[test]
    fn threshold_names() {
        assert_eq!(threshold_name(&Threshold::Fixed(64)), "64");
        assert_eq!(threshold_name(&Threshold::Automatic), "auto");
    }
}
