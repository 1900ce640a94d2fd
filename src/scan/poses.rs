//! Scan poses along the target's border (see the module documentation of `scan` for the
//! geometry), with the ground-truth edge point p_e of each.

use nalgebra::{Matrix3, Point3, Rotation3, Translation3, UnitQuaternion};

use super::ScanConfig;
use crate::geometry::border::BorderCurve;
use crate::geometry::pose::Pose;

/// One scan pose.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanPose {
    /// Index in the scan (0-based).
    pub index: usize,
    /// Sensor pose T_BS.
    pub sensor: Pose,
    /// Flange pose T_BF = T_BS · T_FS⁻¹.
    pub flange: Pose,
    /// Ground truth p_e in the base frame: where the laser plane cuts the true border curve (m).
    pub edge_point: Point3<f64>,
    /// Position of p_e along the border, as a fraction of its length in [0, 1).
    pub border_fraction: f64,
}

/// Poses spread evenly along `border_b` (the true border curve in the base frame), starting at
/// `scan.start_fraction` of its length.
pub fn plan_border_scan(border_b: &BorderCurve, scan: &ScanConfig, mount: &Pose) -> Vec<ScanPose> {
    let length = border_b.length();
    (0..scan.poses)
        .map(|k| {
            let fraction = (scan.start_fraction + k as f64 / scan.poses as f64).fract();
            let v = border_b.at_arc_length(fraction * length);
            let (sa, ca) = scan.scan_angle_rad.sin_cos();
            let z = (-ca * v.outward - sa * v.surface_normal).normalize();
            let y = v.tangent;
            let x = y.cross(&z).normalize();
            let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                Matrix3::from_columns(&[x, y, z]),
            ));
            let origin = v.position - z * scan.standoff_m;
            let sensor = Pose::from_parts(Translation3::from(origin.coords), rotation);
            ScanPose {
                index: k,
                sensor,
                flange: sensor * mount.inverse(),
                edge_point: v.position,
                border_fraction: fraction,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::border::BorderVertex;
    use nalgebra::Vector3;

    /// A 200 × 100 mm rectangle at height 4 mm, counter-clockwise from above.
    fn rectangle() -> BorderCurve {
        let corners = [(-0.1, -0.05), (0.1, -0.05), (0.1, 0.05), (-0.1, 0.05)];
        let mut vertices = Vec::new();
        for k in 0..4 {
            let (x0, y0) = corners[k];
            let (x1, y1) = corners[(k + 1) % 4];
            let t = Vector3::new(x1 - x0, y1 - y0, 0.0).normalize();
            for s in 0..10 {
                let f = s as f64 / 10.0;
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
    fn laser_plane_contains_the_edge_point_and_is_perpendicular_to_the_border() {
        let scan = ScanConfig {
            scan_angle_rad: 45f64.to_radians(),
            poses: 4,
            standoff_m: 0.2575,
            start_fraction: 0.1,
        };
        let mount = crate::geometry::pose::pose_from_mm_deg([0.0, 0.0, 50.0], [0.0, 0.0, 0.0]);
        let border = rectangle();
        for p in plan_border_scan(&border, &scan, &mount) {
            let local = p.sensor.inverse() * p.edge_point;
            // On the laser plane y = 0, on the laser axis at the standoff.
            assert!(local.coords.norm() > 0.0);
            assert!(
                (local - Point3::new(0.0, 0.0, 0.2575)).norm() < 1e-12,
                "{local:?}"
            );
            // Sensor z makes the scan angle with the surface: sin α = −z_S · n.
            let z = p.sensor.rotation * Vector3::z();
            assert!((-z.dot(&Vector3::z()) - 45f64.to_radians().sin()).abs() < 1e-12);
            // The sensor sits outside the panel's outline.
            let o = p.sensor.translation.vector;
            assert!(
                o.x.abs() > 0.1 || o.y.abs() > 0.05,
                "sensor inside the outline: {o:?}"
            );
            // Flange ∘ mount = sensor.
            let back = p.flange * mount;
            assert!((back.translation.vector - p.sensor.translation.vector).norm() < 1e-12);
        }
    }
}
