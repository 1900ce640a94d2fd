//! Localisation: from a few laser profiles to the pose of the glass (Adrian & Pham, Sections
//! IV–VI).
//!
//! The pipeline is the paper's: each profile, already expressed in the robot base frame B,
//! gives one Border Identifier Point ([`bip`]: the paper's highest point; [`edge_line`]: the
//! top of the chain of edge returns); the n BIPs are registered against the model's
//! border curve M with a point-to-plane ICP ([`icp`]) that starts from the nominal pose T_BM0;
//! [`metrics`] scores the result as the paper does (pose error, Table 4's task error, and a
//! contour error over the whole border). [`nearest`] is the exact closest point on a border
//! polyline that both ICP and the metrics use.
//!
//! Invariants:
//! - This module depends on `geometry` (the border curve and poses) and nalgebra only, never on
//!   `transport`, `sensor` or `scan`: it runs unchanged on BIPs measured by a real sensor.
//! - Inside, lengths are metres and angles radians (f64); names ending in `_mm` / `_deg` are in
//!   millimetres / degrees, which is how errors are reported.
//! - Nothing here panics on bad measurements: ICP returns an [`icp::IcpError`] for too few or
//!   non-finite points, and reports a badly conditioned fit as `degenerate` instead of a pose.

pub mod bip;
pub mod edge_line;
pub mod icp;
pub mod metrics;
pub mod nearest;

pub use bip::{bip_highest, bip_highest_supported};
pub use icp::{register, IcpError, IcpSettings, Registration};
pub use metrics::{contour_error, pose_error, task_error, Stats};
pub use nearest::{closest_on_border, ClosestPoint};

/// Synthetic borders shared by the unit tests of this module.
#[cfg(test)]
pub(crate) mod fixtures {
    use crate::geometry::border::{BorderCurve, BorderVertex};
    use nalgebra::{Point3, Vector3};

    /// A rounded rectangle `width` × `height` (m) centred on the origin, corner radius
    /// `radius`, sampled about every `step` (m), counter-clockwise seen from above, lying on
    /// the surface z = `surface(x, y).0` with unit normal `surface(x, y).1`.
    pub fn rounded_rectangle(
        width: f64,
        height: f64,
        radius: f64,
        step: f64,
        surface: impl Fn(f64, f64) -> (f64, Vector3<f64>),
    ) -> BorderCurve {
        let (hx, hy) = (width / 2.0 - radius, height / 2.0 - radius);
        // The outline in the xy plane: four straight sides and four quarter circles, CCW.
        let mut xy: Vec<(f64, f64)> = Vec::new();
        let corners = [(hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)];
        let side_len = [2.0 * hy, 2.0 * hx, 2.0 * hy, 2.0 * hx];
        let arc_n = ((std::f64::consts::FRAC_PI_2 * radius) / step)
            .ceil()
            .max(1.0) as usize;
        for k in 0..4 {
            // Side k ends at corner k (starting with the bottom side towards (hx, −hy)).
            let (cx, cy) = corners[k];
            let a0 = -std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::FRAC_PI_2;
            let (px, py) = corners[(k + 3) % 4];
            let (sx, sy) = (px + radius * a0.cos(), py + radius * a0.sin());
            let (ex, ey) = (cx + radius * a0.cos(), cy + radius * a0.sin());
            let len = side_len[(k + 1) % 4];
            let side_n = (len / step).ceil().max(1.0) as usize;
            for i in 0..side_n {
                let t = i as f64 / side_n as f64;
                xy.push((sx + (ex - sx) * t, sy + (ey - sy) * t));
            }
            for i in 0..arc_n {
                let a = a0 + std::f64::consts::FRAC_PI_2 * i as f64 / arc_n as f64;
                xy.push((cx + radius * a.cos(), cy + radius * a.sin()));
            }
        }
        let n = xy.len();
        let vertices = (0..n)
            .map(|i| {
                let (x, y) = xy[i];
                let (z, normal) = surface(x, y);
                let (xp, yp) = xy[(i + n - 1) % n];
                let (xn, yn) = xy[(i + 1) % n];
                let (zp, _) = surface(xp, yp);
                let (zn, _) = surface(xn, yn);
                let chord = Point3::new(xn, yn, zn) - Point3::new(xp, yp, zp);
                let tangent = (chord - normal * chord.dot(&normal)).normalize();
                BorderVertex {
                    position: Point3::new(x, y, z),
                    tangent,
                    surface_normal: normal,
                    outward: tangent.cross(&normal).normalize(),
                }
            })
            .collect();
        BorderCurve { vertices }
    }

    /// The 300 × 200 mm flat pane of the tests: 20 mm corners, 2 mm sampling, top at z = 4 mm.
    pub fn flat_pane() -> BorderCurve {
        rounded_rectangle(0.3, 0.2, 0.02, 0.002, |_, _| (0.004, Vector3::z()))
    }

    /// The same outline on a cylinder of radius 1.5 m (axis along y, bulging up), 4 mm thick.
    pub fn curved_pane() -> BorderCurve {
        let r = 1.5;
        rounded_rectangle(0.3, 0.2, 0.02, 0.002, move |x, _| {
            let zc = (r * r - x * x).sqrt();
            (0.004 + zc - r, Vector3::new(x, 0.0, zc) / r)
        })
    }
}
