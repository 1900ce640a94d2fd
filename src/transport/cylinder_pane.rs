//! Glass whose faces lie on cylinders about one axis (a pane bent on a cylinder, like the
//! panel's `curvature` or a CAD side window of the same shape), and why light totally reflected
//! inside it stays trapped like light in a flat pane.
//!
//! The ray invariant of a cylindrical light guide (Snyder & Love, *Optical Waveguide Theory*,
//! 1983, §§ 2-3 and 23-3 on bends): write a direction as its axial component d_a and its part
//! in the cross-section, of length √(1 − d_a²). Along a straight ray the cross-section's
//! impact parameter b = r·sin φ (r: distance from the axis, φ: angle between the projected ray
//! and the radial direction) is constant, and a reflection at a surface whose normal is radial
//! keeps both b and d_a. So at every face the ray meets, at radius r,
//!
//! sin²θ(r) = d_a² + (1 − d_a²)·b²/r²,
//!
//! which depends on r alone. Light totally reflected at radius r₁ (sin θ(r₁) ≥ 1/η) meets every
//! later face at sin θ ≥ sin θ(r₁)·r_min/r_max, so with the faces between r_min and r_max it
//! can leave through a face only if its first reflection lies within the window
//! 1/η ≤ sin θ < 1/(η·r_min/r_max) above the critical angle (for the car window of 4 mm on
//! 1500 mm, r_min/r_max = 0.9973: the critical angle plus 0.14°). Otherwise it stays inside
//! until the rough edge or a face imperfection lets it out, as in a flat pane (r_min/r_max = 1).
//!
//! Tessellated faces keep the invariant to the mesh's accuracy: vertex normals are radial, the
//! interpolated shading normal lies in their span (so it is perpendicular to the axis) and
//! points through the axis to within the chord's angular error, and hit points lie on chords a
//! few micrometres inside the arcs: all orders of magnitude below the window.

use nalgebra::{Point3, Vector3};

/// How far a face vertex's normal may lean towards the axis direction, or its normal line pass
/// from the axis (relative to the vertex's radius), for its face to count as part of a cylinder
/// about the axis: well above the f32 rounding of normals read from a mesh file (~1e-7), far
/// below anything that would open the window of the module documentation.
const ON_CYLINDER_TOLERANCE: f64 = 1e-5;

/// Least |n₀ × n₁| of the two normals that fix the axis direction: normals closer to parallel
/// would fix it poorly (and faces whose normals are all parallel form a flat pane).
const AXIS_FROM_NORMALS_MIN_SIN: f64 = 1e-3;

/// A face vertex: its point and unit shading normal, in the base frame.
pub type FaceVertex = (Point3<f64>, Vector3<f64>);

/// The ratio r_min/r_max of the faces' distances from their common axis, if every face vertex
/// (point, unit shading normal, in the base frame) lies on a cylinder about one axis with its
/// normal radial; `None` if they do not (or all normals are parallel: a flat pane).
///
/// Two passes over `vertices` (an iterator, so that a large mesh's vertices need not be
/// copied).
pub fn coaxial_radius_ratio<I>(vertices: I) -> Option<f64>
where
    I: IntoIterator<Item = FaceVertex>,
    I::IntoIter: Clone,
{
    let vertices = vertices.into_iter();
    let (p0, n0) = vertices.clone().next()?;
    // The axis direction: perpendicular to the first normal and to the one least parallel to it.
    let (p1, n1) = vertices.clone().max_by(|a, b| {
        let (sa, sb) = (a.1.cross(&n0).norm(), b.1.cross(&n0).norm());
        sa.total_cmp(&sb)
    })?;
    let axis = n0.cross(&n1);
    if axis.norm() < AXIS_FROM_NORMALS_MIN_SIN {
        return None;
    }
    let axis = axis.normalize();
    // A point of the axis: where the two normal lines meet in the cross-section (p0 + s·n0 =
    // p1 + u·n1, least squares in the plane perpendicular to the axis).
    let flat = |v: Vector3<f64>| v - axis * axis.dot(&v);
    let (m0, m1) = (flat(n0), flat(n1));
    let d = flat(p1 - p0);
    let (a, b, c) = (m0.dot(&m0), m0.dot(&m1), m1.dot(&m1));
    let det = a * c - b * b;
    let s = (c * m0.dot(&d) - b * m1.dot(&d)) / det;
    let centre = p0 + m0 * s;
    let (mut r_min, mut r_max) = (f64::INFINITY, 0.0f64);
    for (p, n) in vertices {
        if n.dot(&axis).abs() > ON_CYLINDER_TOLERANCE {
            return None;
        }
        let q = flat(p - centre);
        let r = q.norm();
        // The normal line through the vertex must pass through the axis: q ∥ n.
        if r == 0.0 || q.cross(&n).norm() > ON_CYLINDER_TOLERANCE * r {
            return None;
        }
        (r_min, r_max) = (r_min.min(r), r_max.max(r));
    }
    Some(r_min / r_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vertices of a pane bent about the axis through `centre` along `axis`, its faces at radii
    /// `r_in` and `r_out`, normals radial (outward on the outer face, inward on the inner).
    fn bent(centre: Point3<f64>, axis: Vector3<f64>, r_in: f64, r_out: f64) -> Vec<FaceVertex> {
        let e1 = axis.cross(&Vector3::new(0.3, -0.2, 0.9)).normalize();
        let e2 = axis.cross(&e1);
        let mut v = Vec::new();
        for i in 0..20 {
            let a = -0.2 + 0.02 * i as f64;
            let radial = e1 * a.cos() + e2 * a.sin();
            for along in [-0.1, 0.05, 0.2] {
                v.push((centre + radial * r_out + axis * along, radial));
                v.push((centre + radial * r_in + axis * along, -radial));
            }
        }
        v
    }

    #[test]
    fn a_pane_bent_on_a_cylinder_gives_its_radius_ratio_in_any_pose() {
        let axis = Vector3::new(0.2, 1.0, -0.1).normalize();
        let v = bent(Point3::new(0.3, -1.2, 0.7), axis, 1.5, 1.504);
        let ratio = coaxial_radius_ratio(v).unwrap();
        assert!((ratio - 1.5 / 1.504).abs() < 1e-12, "{ratio}");
    }

    #[test]
    fn flat_faces_tilted_normals_and_off_axis_normals_are_not_a_cylinder() {
        let axis = Vector3::y();
        let flat = vec![
            (Point3::new(0.0, 0.0, 0.0), Vector3::z()),
            (Point3::new(1.0, 0.0, 0.0), Vector3::z()),
            (Point3::new(0.0, 1.0, 0.004), -Vector3::z()),
        ];
        assert_eq!(coaxial_radius_ratio(flat), None);
        // One normal leaning 1e-4 towards the axis direction.
        let mut tilted = bent(Point3::origin(), axis, 1.5, 1.504);
        tilted[7].1 = (tilted[7].1 + axis * 1e-4).normalize();
        assert_eq!(coaxial_radius_ratio(tilted), None);
        // One vertex whose normal line misses the axis by 1e-3 of its radius (a face that is
        // not part of the cylinder).
        let mut off = bent(Point3::origin(), axis, 1.5, 1.504);
        let tangent = off[9].1.cross(&axis);
        off[9].0 += tangent * 1.5e-3;
        assert_eq!(coaxial_radius_ratio(off), None);
        // A box's faces: normals along three axes.
        let cube = [Vector3::x(), Vector3::y(), Vector3::z()]
            .map(|n| (Point3::from(n * 0.5), n))
            .to_vec();
        assert_eq!(coaxial_radius_ratio(cube), None);
    }
}
