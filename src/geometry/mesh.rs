//! Triangle meshes in an object's own frame, with optional smooth vertex normals and a
//! per-triangle surface part (face, edge, …) that later issues use for path labels and
//! for the glass edge finish.

use nalgebra::{Point3, Vector3};

use super::pose::Pose;

/// Which part of an object a triangle belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfacePart {
    /// The top (outer, +normal side) face of a panel.
    TopFace,
    /// The bottom face of a panel (the side that rests on the table).
    BottomFace,
    /// The edge band of a panel: the ground/seamed finish between the two faces.
    Edge,
    /// Any other surface: boxes, imported meshes.
    Solid,
}

/// An indexed triangle mesh in its object's frame (metres).
///
/// Invariants: every index is `< positions.len()`; `normals`, when present, has one unit
/// vector per position; `parts` has one entry per triangle. Triangles wind counter-clockwise
/// seen from outside, so the geometric normal (v1 − v0) × (v2 − v0) points outwards.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions (m).
    pub positions: Vec<Point3<f64>>,
    /// Smooth shading normals, one per vertex (unit length), or `None` for flat shading.
    pub normals: Option<Vec<Vector3<f64>>>,
    /// Vertex indices, three per triangle.
    pub triangles: Vec<[u32; 3]>,
    /// Surface part of each triangle.
    pub parts: Vec<SurfacePart>,
}

impl Mesh {
    /// A flat-shaded mesh whose triangles are all `SurfacePart::Solid`.
    pub fn solid(positions: Vec<Point3<f64>>, triangles: Vec<[u32; 3]>) -> Mesh {
        let parts = vec![SurfacePart::Solid; triangles.len()];
        Mesh {
            positions,
            normals: None,
            triangles,
            parts,
        }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Appends `other`, re-indexing its triangles. Normals are kept only if both have them.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        let had_positions = !self.positions.is_empty();
        self.normals = match (self.normals.take(), &other.normals) {
            (Some(mut a), Some(b)) => {
                a.extend_from_slice(b);
                Some(a)
            }
            (None, Some(b)) if !had_positions => Some(b.clone()),
            _ => None,
        };
        self.positions.extend_from_slice(&other.positions);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
        self.parts.extend_from_slice(&other.parts);
    }

    /// Returns a copy with every vertex and normal transformed by `pose`.
    pub fn transformed(&self, pose: &Pose) -> Mesh {
        Mesh {
            positions: self.positions.iter().map(|p| pose * p).collect(),
            normals: self
                .normals
                .as_ref()
                .map(|ns| ns.iter().map(|n| pose.rotation * n).collect()),
            triangles: self.triangles.clone(),
            parts: self.parts.clone(),
        }
    }

    /// Geometric (face) normal of triangle `i`, unit length, outward for CCW winding.
    pub fn face_normal(&self, i: usize) -> Vector3<f64> {
        let [a, b, c] = self.triangles[i].map(|k| self.positions[k as usize]);
        (b - a).cross(&(c - a)).normalize()
    }

    /// Checks the structural invariants; returns a description of the first violation.
    pub fn check(&self) -> Result<(), String> {
        let n = self.positions.len() as u32;
        if let Some((i, t)) = self
            .triangles
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&k| k >= n))
        {
            return Err(format!("triangle {i} has index {t:?} out of {n} vertices"));
        }
        if self.parts.len() != self.triangles.len() {
            return Err(format!(
                "{} part tags for {} triangles",
                self.parts.len(),
                self.triangles.len()
            ));
        }
        if let Some(ns) = &self.normals {
            if ns.len() != self.positions.len() {
                return Err(format!("{} normals for {} vertices", ns.len(), n));
            }
        }
        if let Some((i, p)) = (self.positions.iter().enumerate())
            .find(|(_, p)| !p.coords.iter().all(|c| c.is_finite()))
        {
            return Err(format!(
                "vertex {i} is not finite ({}, {}, {})",
                p.x, p.y, p.z
            ));
        }
        let max_m = crate::limits::MAX_LENGTH_MM * 1e-3;
        if let Some((i, p)) = (self.positions.iter().enumerate())
            .find(|(_, p)| p.coords.iter().any(|c| c.abs() > max_m))
        {
            return Err(format!(
                "vertex {i} at ({:e}, {:e}, {:e}) m is more than 100 m from the origin (a file \
                 in other units needs `scale`)",
                p.x, p.y, p.z
            ));
        }
        let area2 = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|k| self.positions[k as usize]);
            (b - a).cross(&(c - a)).norm()
        };
        if !self.triangles.is_empty() && self.triangles.iter().all(|t| area2(t) == 0.0) {
            return Err(format!(
                "all {} triangles have zero area (a degenerate mesh, which no ray can hit)",
                self.triangles.len()
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(c: Point3<f64>) -> Mesh {
        Mesh {
            positions: vec![Point3::origin(), Point3::new(1.0, 0.0, 0.0), c],
            triangles: vec![[0, 1, 2]],
            parts: vec![SurfacePart::Solid],
            ..Mesh::default()
        }
    }

    #[test]
    fn check_names_the_bad_vertex_and_refuses_meshes_no_ray_can_hit() {
        assert_eq!(triangle(Point3::new(0.0, 1.0, 0.0)).check(), Ok(()));
        let e = triangle(Point3::new(f64::NAN, 1.0, 0.0))
            .check()
            .unwrap_err();
        assert!(e.starts_with("vertex 2 is not finite"), "{e}");
        let e = triangle(Point3::new(0.0, 1e300, 0.0)).check().unwrap_err();
        assert!(e.contains("vertex 2") && e.contains("`scale`"), "{e}");
        // Collinear: zero area.
        let e = triangle(Point3::new(2.0, 0.0, 0.0)).check().unwrap_err();
        assert!(e.contains("all 1 triangles have zero area"), "{e}");
    }
}
