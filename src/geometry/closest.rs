//! Closest points on triangles and meshes, by brute force: the reference for checks of fitted
//! geometry (how far the tape lies from the glass, how far scanned points lie from a surface),
//! not a query for the tracer (that is `accel`'s job). Units are the mesh's (m).

use nalgebra::Point3;

use super::mesh::Mesh;

/// The point of a mesh nearest to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    /// The nearest point.
    pub point: Point3<f64>,
    /// Its distance from the query point.
    pub distance: f64,
    /// The triangle it lies on.
    pub triangle: usize,
    /// Whether it lies inside that triangle rather than on one of its edges or corners.
    pub inside: bool,
}

/// Closest point to `p` on the triangle `[a, b, c]`, and whether it lies inside the triangle
/// rather than on its boundary. Method: the Voronoi regions of the corners, then of the edges,
/// then the face, tested with the barycentric dot products (Ericson, *Real-Time Collision
/// Detection*, 2005, §5.1.5).
pub fn closest_on_triangle(p: &Point3<f64>, [a, b, c]: [Point3<f64>; 3]) -> (Point3<f64>, bool) {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, false);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, false);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), false);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, false);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), false);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 >= d3 && d5 >= d6 {
        return (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), false);
    }
    let denom = 1.0 / (va + vb + vc);
    (a + ab * (vb * denom) + ac * (vc * denom), true)
}

/// The point of `mesh` nearest to `p` (every triangle tried); `None` for a mesh without
/// triangles.
pub fn nearest_on_mesh(mesh: &Mesh, p: &Point3<f64>) -> Option<Nearest> {
    let mut best: Option<Nearest> = None;
    for (triangle, t) in mesh.triangles.iter().enumerate() {
        let (point, inside) = closest_on_triangle(p, t.map(|k| mesh.positions[k as usize]));
        let distance = (p - point).norm();
        if best.is_none_or(|b| distance < b.distance) {
            best = Some(Nearest {
                point,
                distance,
                triangle,
                inside,
            });
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::cuboid::cuboid;

    #[test]
    fn closest_points_by_region() {
        let t = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        // Above the face: straight down, inside.
        let (q, inside) = closest_on_triangle(&Point3::new(0.2, 0.3, 0.5), t);
        assert!((q - Point3::new(0.2, 0.3, 0.0)).norm() < 1e-15 && inside);
        // Beyond a corner, beyond an edge.
        assert_eq!(
            closest_on_triangle(&Point3::new(-1.0, -1.0, 0.0), t),
            (t[0], false)
        );
        let (q, inside) = closest_on_triangle(&Point3::new(1.0, 1.0, 0.0), t);
        assert!((q - Point3::new(0.5, 0.5, 0.0)).norm() < 1e-15 && !inside);
        let (q, _) = closest_on_triangle(&Point3::new(0.5, -2.0, 1.0), t);
        assert!((q - Point3::new(0.5, 0.0, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn nearest_on_a_box_is_the_distance_to_its_faces() {
        let mesh = cuboid([2.0, 2.0, 2.0]);
        let n = nearest_on_mesh(&mesh, &Point3::new(0.3, -0.2, 1.5)).unwrap();
        assert!((n.distance - 0.5).abs() < 1e-15);
        let corner = nearest_on_mesh(&mesh, &Point3::new(2.0, 2.0, 2.0)).unwrap();
        assert!((corner.distance - 3f64.sqrt()).abs() < 1e-15 && !corner.inside);
        assert!(nearest_on_mesh(&Mesh::default(), &Point3::origin()).is_none());
    }
}
