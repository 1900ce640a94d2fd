//! What makes a simulated pose physically empty or meaningless, said in words: the profile
//! has no valid point, the frame is flooded (a large share of all pixels at full scale, where
//! the firmware still reports "valid" points), or the ground-truth border point p_e lies
//! outside the sensor's measuring range. The library returns the warnings; the commands print
//! them on stderr and record them in their JSON.

use super::simulate::PoseResult;
use crate::sensor::MeasuringRange;

/// Above this share of all pixels at full scale a frame is flooded: a laser line covers about
/// 640 columns × 5–40 rows (< 5 % of the 640 × 832 frame), so beyond it the image is mostly
/// saturated background or stray light and the profile's positions mean little.
pub const FLOODED_FRACTION: f64 = 0.05;

/// The warnings of one simulated pose, each a sentence starting with "pose N:".
pub fn pose_warnings(result: &PoseResult, range: &MeasuringRange) -> Vec<String> {
    let index = result.pose.index;
    let mut out = Vec::new();
    if !result.profile.points.iter().any(|p| p.valid) {
        out.push(format!(
            "pose {index}: no valid profile point (the laser line is outside the view, or no \
             peak is above the threshold)"
        ));
    }
    let pixels = result.image.data.len().max(1);
    let fraction = result.saturated_pixels as f64 / pixels as f64;
    if fraction > FLOODED_FRACTION {
        out.push(format!(
            "pose {index}: {} of {pixels} pixels ({:.0} %) are saturated: the exposure or \
             the laser power is far too high for this scene",
            result.saturated_pixels,
            100.0 * fraction
        ));
    }
    let p = result.pose.sensor.inverse() * result.pose.edge_point;
    let half_width = 0.5 * range.x_width_m * (p.z / range.z_max_m).max(0.0);
    if !(range.z_min_m..=range.z_max_m).contains(&p.z) || p.x.abs() > half_width {
        out.push(format!(
            "pose {index}: the border point p_e is outside the measuring range (x = {:.1} mm, \
             z = {:.1} mm; the range is z = {:.0}…{:.0} mm, |x| ≤ {:.1} mm there)",
            p.x * 1e3,
            p.z * 1e3,
            range.z_min_m * 1e3,
            range.z_max_m * 1e3,
            half_width * 1e3
        ));
    }
    out
}
