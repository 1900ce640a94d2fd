//! The border edge curve of a panel: where the transparent top face meets the edge finish.
//!
//! This is the ground-truth curve on which the paper's point p_e lies (the laser plane of a
//! scan pose cuts it at p_e) and the model M that ICP registers the Border Identifier Points
//! against. It is a closed polyline in the panel's model frame (metres), densely sampled,
//! with a frame per vertex.

use nalgebra::{Point3, Vector3};

use super::pose::Pose;

/// One sample of the border curve, in the model frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BorderVertex {
    /// Position on the curve (m).
    pub position: Point3<f64>,
    /// Unit tangent, in the direction of increasing vertex index (counter-clockwise seen
    /// from above the top face).
    pub tangent: Vector3<f64>,
    /// Unit normal of the top face at this point (pointing away from the glass).
    pub surface_normal: Vector3<f64>,
    /// Unit vector in the top face's tangent plane, perpendicular to the tangent, pointing
    /// out of the panel (away from its interior).
    pub outward: Vector3<f64>,
}

/// A closed polyline: the last vertex connects back to the first.
#[derive(Clone, Debug, Default)]
pub struct BorderCurve {
    /// Vertices in order, counter-clockwise seen from above the top face.
    pub vertices: Vec<BorderVertex>,
}

impl BorderCurve {
    /// Total length of the closed curve (m).
    pub fn length(&self) -> f64 {
        let n = self.vertices.len();
        (0..n)
            .map(|i| (self.vertices[(i + 1) % n].position - self.vertices[i].position).norm())
            .sum()
    }

    /// The point at arc length `s` (m, wrapped into [0, length)) with its frame, interpolated
    /// linearly along the segment that contains it (frames are re-normalised).
    pub fn at_arc_length(&self, s: f64) -> BorderVertex {
        let n = self.vertices.len();
        assert!(n >= 2, "a border curve needs at least two vertices");
        let total = self.length();
        let mut s = s.rem_euclid(total);
        for i in 0..n {
            let a = &self.vertices[i];
            let b = &self.vertices[(i + 1) % n];
            let len = (b.position - a.position).norm();
            if s <= len || i == n - 1 {
                let t = if len > 0.0 {
                    (s / len).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let lerp = |u: Vector3<f64>, v: Vector3<f64>| (u * (1.0 - t) + v * t).normalize();
                let tangent = (b.position - a.position)
                    .try_normalize(1e-15)
                    .unwrap_or(a.tangent);
                let surface_normal = lerp(a.surface_normal, b.surface_normal);
                // Re-orthogonalise so that (tangent, outward, normal) stays a frame.
                let outward = tangent.cross(&surface_normal).normalize();
                let outward = if outward.dot(&a.outward) < 0.0 {
                    -outward
                } else {
                    outward
                };
                return BorderVertex {
                    position: a.position + (b.position - a.position) * t,
                    tangent,
                    surface_normal,
                    outward,
                };
            }
            s -= len;
        }
        unreachable!("the loop returns on its last segment")
    }

    /// Returns a copy in another frame.
    pub fn transformed(&self, pose: &Pose) -> BorderCurve {
        BorderCurve {
            vertices: self
                .vertices
                .iter()
                .map(|v| BorderVertex {
                    position: pose * v.position,
                    tangent: pose.rotation * v.tangent,
                    surface_normal: pose.rotation * v.surface_normal,
                    outward: pose.rotation * v.outward,
                })
                .collect(),
        }
    }
}
