//! Axis-aligned boxes (tables, walls, supports, posts), centred on the
//! origin of their own frame.

use nalgebra::Point3;

use super::mesh::Mesh;

/// A closed box of size `size_m` = (x, y, z) extents (m, each > 0), centred on the origin:
/// 8 vertices, 12 triangles wound counter-clockwise seen from outside, flat shaded
/// (`normals` = `None`), every triangle `SurfacePart::Solid`.
pub fn cuboid(size_m: [f64; 3]) -> Mesh {
    let [hx, hy, hz] = size_m.map(|s| 0.5 * s);
    // Vertex i has x = ±hx by bit 0, y = ±hy by bit 1, z = ±hz by bit 2 (set bit: +).
    let positions = (0..8)
        .map(|i| {
            let sign = |bit: u32| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
            Point3::new(sign(0) * hx, sign(1) * hy, sign(2) * hz)
        })
        .collect();
    // Two triangles per face, each quad listed counter-clockwise seen from outside.
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1], // −z
        [4, 5, 7, 6], // +z
        [0, 1, 5, 4], // −y
        [2, 6, 7, 3], // +y
        [0, 4, 6, 2], // −x
        [1, 3, 7, 5], // +x
    ];
    let triangles: Vec<[u32; 3]> = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    Mesh::solid(positions, triangles)
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::geometry::mesh::SurfacePart;

    #[test]
    fn cuboid_is_watertight_with_outward_normals() {
        let size = [0.3, 0.2, 0.05];
        let mesh = cuboid(size);
        assert_eq!(mesh.triangle_count(), 12);
        assert_eq!(mesh.positions.len(), 8);
        mesh.check().expect("structurally valid");

        // Watertight and consistently oriented: every directed edge appears exactly once and
        // its reverse exactly once.
        let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "directed edge {a}->{b} used {n} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}->{b} has no twin");
        }

        // Outward: each face normal points away from the centre, along an axis.
        for i in 0..mesh.triangle_count() {
            let n = mesh.face_normal(i);
            let [a, b, c] = mesh.triangles[i].map(|k| mesh.positions[k as usize].coords);
            let centroid = (a + b + c) / 3.0;
            assert!(n.dot(&centroid) > 0.0, "triangle {i} faces inwards");
            assert!(
                (n.abs().max() - 1.0).abs() < 1e-12,
                "triangle {i} not axis-aligned"
            );
        }

        // Signed volume (divergence theorem) equals the box volume: positive means outward.
        let volume: f64 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| mesh.positions[k as usize].coords);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum();
        assert!((volume - size[0] * size[1] * size[2]).abs() < 1e-15);
        assert!(mesh.parts.iter().all(|&p| p == SurfacePart::Solid));
        assert!(mesh.normals.is_none());
    }

    #[test]
    fn cuboid_is_centred_with_the_given_extents() {
        let mesh = cuboid([1.0, 0.8, 0.02]);
        for axis in 0..3 {
            let lo = mesh
                .positions
                .iter()
                .map(|p| p[axis])
                .fold(f64::MAX, f64::min);
            let hi = mesh
                .positions
                .iter()
                .map(|p| p[axis])
                .fold(f64::MIN, f64::max);
            assert!((lo + hi).abs() < 1e-15);
            assert!((hi - lo - [1.0, 0.8, 0.02][axis]).abs() < 1e-15);
        }
    }
}
