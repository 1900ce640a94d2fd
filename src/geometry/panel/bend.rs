//! The cylindrical bending map from the flat panel (u, v, h) to the model frame.
//!
//! A flat point at abscissa u, ordinate v and height h above the bottom face maps to
//! ((R + h)·sin a, v, (R + h)·cos a − R) with a = u/R: the bottom face (h = 0) rolls onto the
//! cylinder of radius R about the axis (0, ·, −R) without stretching, the top face onto radius
//! R + t. The map's Jacobian is the rotation by a about y times a stretch (R + h)/R along the
//! bent x direction, so directions rotate by a about y; its determinant is positive, so
//! triangle winding (and hence outward orientation) is preserved.

use nalgebra::{Point3, Vector3};

use super::Curvature;

impl Curvature {
    /// Maps a flat point (u, v, h) (m) into the model frame.
    pub(super) fn bend_point(&self, u: f64, v: f64, h: f64) -> Point3<f64> {
        match *self {
            Curvature::Flat => Point3::new(u, v, h),
            Curvature::Cylindrical { radius_m: r } => {
                let a = u / r;
                let (sin_a, cos_a) = a.sin_cos();
                // (R + h)·cos a − R written as h·cos a − 2R·sin²(a/2): no cancellation near a = 0.
                let half = (0.5 * a).sin();
                Point3::new((r + h) * sin_a, v, h * cos_a - 2.0 * r * half * half)
            }
        }
    }

    /// Rotates a direction given in the flat frame at abscissa u (m) into the model frame
    /// (normals of the faces and the edge, border tangents): a rotation by a = u/R about y that
    /// takes +z to the radial direction (sin a, 0, cos a).
    pub(super) fn bend_direction(&self, u: f64, d: Vector3<f64>) -> Vector3<f64> {
        match *self {
            Curvature::Flat => d,
            Curvature::Cylindrical { radius_m: r } => {
                let (sin_a, cos_a) = (u / r).sin_cos();
                Vector3::new(d.x * cos_a + d.z * sin_a, d.y, -d.x * sin_a + d.z * cos_a)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BENT: Curvature = Curvature::Cylindrical { radius_m: 1.5 };

    #[test]
    fn flat_map_is_the_identity() {
        let p = Curvature::Flat.bend_point(0.1, -0.2, 0.004);
        assert_eq!(p, Point3::new(0.1, -0.2, 0.004));
    }

    #[test]
    fn bent_points_lie_on_their_cylinder_and_keep_bottom_arc_length() {
        let (r, h) = (1.5, 0.004);
        for u in [-0.3, -0.01, 0.0, 0.2, 0.275] {
            let p = BENT.bend_point(u, 0.05, h);
            assert!(((p.x * p.x + (p.z + r) * (p.z + r)).sqrt() - (r + h)).abs() < 1e-14);
            // The bottom face is not stretched: the angle subtended is u/R.
            let q = BENT.bend_point(u, 0.0, 0.0);
            assert!((q.x.atan2(q.z + r) - u / r).abs() < 1e-15);
        }
    }

    #[test]
    fn directions_follow_the_jacobian_of_the_map() {
        // The derivative of the map along u at h = 0 is the bent x direction.
        let (u, du) = (0.2, 1e-6);
        let d =
            (BENT.bend_point(u + du, 0.0, 0.0) - BENT.bend_point(u - du, 0.0, 0.0)) / (2.0 * du);
        let x = BENT.bend_direction(u, Vector3::x());
        assert!((d - x).norm() < 1e-9);
        let z = BENT.bend_direction(u, Vector3::z());
        assert!((z - Vector3::new((u / 1.5).sin(), 0.0, (u / 1.5).cos())).norm() < 1e-15);
        assert!(x.dot(&z).abs() < 1e-15);
    }
}
