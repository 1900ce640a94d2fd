//! Rigid transforms (SE(3)) in f64.
//!
//! `Pose` maps points of a child frame into its parent frame: `T_BM * p_M = p_B`.
//! Scene files give translations in millimetres and rotations in degrees as fixed-axis
//! x-then-y-then-z angles, i.e. R = Rz(rz)·Ry(ry)·Rx(rx) (nalgebra `from_euler_angles`).

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// A rigid transform from a child frame to its parent frame (metres).
pub type Pose = Isometry3<f64>;

/// Builds a pose from a translation in millimetres and fixed-axis x, y, z rotations in degrees
/// (R = Rz·Ry·Rx).
pub fn pose_from_mm_deg(translation_mm: [f64; 3], rotation_deg: [f64; 3]) -> Pose {
    let t = Vector3::from(translation_mm) * 1e-3;
    let r = UnitQuaternion::from_euler_angles(
        rotation_deg[0].to_radians(),
        rotation_deg[1].to_radians(),
        rotation_deg[2].to_radians(),
    );
    Isometry3::from_parts(Translation3::from(t), r)
}

/// Splits a pose into a translation in millimetres and fixed-axis x, y, z angles in degrees;
/// the inverse of [`pose_from_mm_deg`] (angles in (−180°, 180°], ry in [−90°, 90°]).
pub fn pose_to_mm_deg(pose: &Pose) -> ([f64; 3], [f64; 3]) {
    let t = pose.translation.vector * 1e3;
    let (rx, ry, rz) = pose.rotation.euler_angles();
    (
        [t.x, t.y, t.z],
        [rx.to_degrees(), ry.to_degrees(), rz.to_degrees()],
    )
}

/// The pose as a row-major 4 × 4 homogeneous matrix with the translation in millimetres:
/// `p_parent = M · [p_child, 1]` (column vectors, translation in the last column).
pub fn pose_to_matrix_mm(pose: &Pose) -> [f64; 16] {
    let mut m = pose.to_homogeneous();
    for r in 0..3 {
        m[(r, 3)] *= 1e3;
    }
    std::array::from_fn(|k| m[(k / 4, k % 4)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    #[test]
    fn the_matrix_maps_millimetre_points_as_the_pose_maps_metres() {
        let pose = pose_from_mm_deg([10.0, -20.0, 300.0], [15.0, -30.0, 100.0]);
        let m = pose_to_matrix_mm(&pose);
        let p_mm = [3.0, -4.0, 5.0];
        let mapped: Vec<f64> = (0..3)
            .map(|r| (0..3).map(|c| m[4 * r + c] * p_mm[c]).sum::<f64>() + m[4 * r + 3])
            .collect();
        let expected = pose * Point3::new(3e-3, -4e-3, 5e-3);
        for k in 0..3 {
            assert!((mapped[k] - expected[k] * 1e3).abs() < 1e-9, "{mapped:?}");
        }
        assert_eq!(&m[12..], &[0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn mm_deg_round_trip() {
        let p = pose_from_mm_deg([10.0, -20.0, 30.0], [5.0, -12.0, 170.0]);
        let (t, r) = pose_to_mm_deg(&p);
        let q = pose_from_mm_deg(t, r);
        let x = Point3::new(0.3, -0.1, 0.2);
        assert!((p * x - q * x).norm() < 1e-12);
        assert!((t[0] - 10.0).abs() < 1e-9 && (r[2] - 170.0).abs() < 1e-9);
    }

    #[test]
    fn pose_times_inverse_is_identity() {
        let p = pose_from_mm_deg([1.0, 2.0, 3.0], [30.0, 40.0, 50.0]);
        let x = Point3::new(0.5, 0.25, -0.75);
        assert!(((p * p.inverse()) * x - x).norm() < 1e-14);
    }

    #[test]
    fn rotation_order_is_z_after_y_after_x() {
        // Rx(90°) maps y to z; then Rz(90°) leaves z alone: y → z.
        let p = pose_from_mm_deg([0.0; 3], [90.0, 0.0, 90.0]);
        let v = p.rotation * Vector3::y();
        assert!((v - Vector3::z()).norm() < 1e-12);
    }
}

/// A pose in the forms every output file and report gives it: millimetres and degrees
/// (fixed-axis x, y, z; R = Rz·Ry·Rx, as scene files take it), a row-major 4 × 4 matrix and a
/// unit quaternion, so that a reader needs no Euler convention.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PoseMmDeg {
    /// Translation (mm).
    pub translation_mm: [f64; 3],
    /// Rotation (deg).
    pub rotation_deg: [f64; 3],
    /// Row-major homogeneous matrix, translation in mm: p_parent = M · [p_child, 1]
    /// (`numpy.array(m).reshape(4, 4)`).
    pub matrix_mm: [f64; 16],
    /// The rotation as a unit quaternion (w, x, y, z) with w ≥ 0 (scipy's `from_quat` takes
    /// (x, y, z, w)).
    pub quaternion_wxyz: [f64; 4],
}

impl From<&Pose> for PoseMmDeg {
    fn from(p: &Pose) -> Self {
        let (translation_mm, rotation_deg) = pose_to_mm_deg(p);
        let q = p.rotation.quaternion();
        let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
        PoseMmDeg {
            translation_mm,
            rotation_deg,
            matrix_mm: pose_to_matrix_mm(p),
            quaternion_wxyz: [q.w, q.i, q.j, q.k].map(|v| sign * v),
        }
    }
}
