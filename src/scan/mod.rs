//! Scan poses: where the robot puts the sensor to scan the target's border.
//!
//! For a border point p with tangent t, outward direction o (in the top face's tangent plane)
//! and surface normal n, the laser plane is the plane through p spanned by o and n (so the
//! laser line crosses the edge), and the sensor's z axis makes the scan angle α with the
//! tangent plane, looking from outside and above: z_S = −cos α·o − sin α·n. The sensor sits at
//! `standoff` along −z_S from p, so p is at range `standoff` on the laser axis.

pub mod adaptive;
pub mod bip;
pub mod errors;
pub mod locate;
pub mod poses;
pub mod simulate;
pub mod warnings;

/// Scan settings from the scene's `[scan]` section, overridable from the command line.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ScanConfig {
    /// Scan angle α between the sensor's z axis and the surface's tangent plane (rad), in (0, π/2].
    pub scan_angle_rad: f64,
    /// Number of poses spread evenly along the border, ≥ 1.
    pub poses: usize,
    /// Distance from the sensor origin to the border point along z_S (m).
    pub standoff_m: f64,
    /// Arc-length fraction of the border (in [0, 1)) where the first pose sits.
    pub start_fraction: f64,
}
