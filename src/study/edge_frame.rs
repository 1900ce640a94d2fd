//! The edge frame of a scan pose: the paper's Fig. 7 coordinates. Every profile point is placed
//! relative to the ground-truth edge point p_e, so that the readings of all poses (and of the
//! tape, cover and bare variants) can be overlaid and compared with the edge line.
//!
//! - `out_mm`: along the border's outward direction in the top face's tangent plane (horizontal
//!   on a flat pane), positive outside the pane, negative over the glass;
//! - `up_mm`: along the top face's normal, positive above p_e (the table under a 4 mm pane is
//!   at −4 mm).
//!
//! The laser plane of a scan pose is spanned by exactly these two directions (see `scan`), so
//! the two coordinates hold all of a profile point's position.

use nalgebra::{Point3, Vector3};

use crate::geometry::border::{BorderCurve, BorderVertex};
use crate::scan::poses::ScanPose;

/// The frame at p_e: origin, outward and up directions in the base frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeFrame {
    /// p_e in the base frame (m).
    pub origin: Point3<f64>,
    /// Unit outward direction (base frame).
    pub out: Vector3<f64>,
    /// Unit surface normal (base frame).
    pub up: Vector3<f64>,
}

impl EdgeFrame {
    /// The frame of a border vertex (its position is p_e).
    pub fn from_vertex(v: &BorderVertex) -> EdgeFrame {
        EdgeFrame {
            origin: v.position,
            out: v.outward,
            up: v.surface_normal,
        }
    }

    /// The frame at the edge point of `pose`, a pose planned by `scan::poses::plan_border_scan`
    /// on `border_b` (the border in the base frame): the border vertex at the pose's arc-length
    /// fraction, which is where the planner put p_e.
    pub fn of_pose(border_b: &BorderCurve, pose: &ScanPose) -> EdgeFrame {
        let v = border_b.at_arc_length(pose.border_fraction * border_b.length());
        EdgeFrame {
            origin: pose.edge_point,
            ..EdgeFrame::from_vertex(&v)
        }
    }

    /// `(out_mm, up_mm)` of a base-frame point `p_b` (m). The component along the border
    /// tangent is dropped: profile points lie in the laser plane, where it is zero.
    pub fn coordinates_mm(&self, p_b: &Point3<f64>) -> (f64, f64) {
        let d = p_b - self.origin;
        (d.dot(&self.out) * 1e3, d.dot(&self.up) * 1e3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::pose::pose_from_mm_deg;
    use crate::scan::poses::plan_border_scan;
    use crate::scan::ScanConfig;

    /// A 100 × 100 mm square pane, 4 mm tall, counter-clockwise from above.
    fn square() -> BorderCurve {
        let c = [(-0.05, -0.05), (0.05, -0.05), (0.05, 0.05), (-0.05, 0.05)];
        let mut vertices = Vec::new();
        for k in 0..4 {
            let (x0, y0) = c[k];
            let (x1, y1) = c[(k + 1) % 4];
            let t = Vector3::new(x1 - x0, y1 - y0, 0.0).normalize();
            for s in 0..8 {
                let f = s as f64 / 8.0;
                vertices.push(BorderVertex {
                    position: Point3::new(x0 + f * (x1 - x0), y0 + f * (y1 - y0), 0.004),
                    tangent: t,
                    surface_normal: Vector3::z(),
                    outward: t.cross(&Vector3::z()),
                });
            }
        }
        BorderCurve { vertices }
    }

    #[test]
    fn known_points_map_to_known_edge_coordinates() {
        // Fraction 1/8 of the perimeter: the middle of the −y side, p_e = (0, −50, 4) mm,
        // outward −y.
        let scan = ScanConfig {
            scan_angle_rad: 40f64.to_radians(),
            poses: 1,
            standoff_m: 0.2575,
            start_fraction: 0.125,
        };
        let mount = pose_from_mm_deg([0.0; 3], [0.0; 3]);
        let border = square();
        let pose = &plan_border_scan(&border, &scan, &mount)[0];
        let f = EdgeFrame::of_pose(&border, pose);
        assert!((f.origin - Point3::new(0.0, -0.05, 0.004)).norm() < 1e-12);
        let near =
            |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9;
        // 3 mm over the glass on the top face.
        let p = f.coordinates_mm(&Point3::new(0.0, -0.047, 0.004));
        assert!(near(p, (-3.0, 0.0)), "{p:?}");
        // The table 2 mm outside the pane: 4 mm below p_e.
        let p = f.coordinates_mm(&Point3::new(0.0, -0.052, 0.0));
        assert!(near(p, (2.0, -4.0)), "{p:?}");
        // p_e itself, and a point along the tangent (not in the laser plane) keeps (0, 0).
        assert!(near(f.coordinates_mm(&f.origin), (0.0, 0.0)));
        assert!(near(
            f.coordinates_mm(&Point3::new(0.01, -0.05, 0.004)),
            (0.0, 0.0)
        ));
        // A profile point on the sensor's laser axis at the standoff is p_e.
        let on_axis = pose.sensor * Point3::new(0.0, 0.0, scan.standoff_m);
        assert!(near(f.coordinates_mm(&on_axis), (0.0, 0.0)));
        // Along the sensor's x axis (the laser line) the point moves in the edge frame by
        // the scan angle: x_S = y_S × z_S with y_S = +x (the tangent), z_S = −cos α·o − sin α·n,
        // so x_S = sin α·ŷ + cos α·ẑ, which is (−sin α, cos α) in (out, up).
        let a = scan.scan_angle_rad;
        let p = f.coordinates_mm(&(pose.sensor * Point3::new(0.001, 0.0, scan.standoff_m)));
        assert!(near(p, (-a.sin(), a.cos())), "{p:?}");
    }
}
