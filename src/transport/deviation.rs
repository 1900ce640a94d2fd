//! How far the glass of a scene can bend a camera connection: a bound that lets the tracer skip
//! the Newton solve of connections that cannot reach the pixel grid.
//!
//! A connection through glass (`connect`) is a chain of straight segments in air, a₀ … a_k, and
//! of segments inside glass, from the vertex x to the lens point L; a_k is the direction in
//! which it arrives at L, and that direction alone decides where it lands on the sensor
//! (`Aperture::image_of_ray`). Split the chord L − x into the air segments s_j·a_j and the glass
//! segments. If each crossing of a glass body turns the direction by at most δ and runs at most
//! ℓ inside the glass, a chain of at most k crossings has ∠(a_j, a_k) ≤ k·δ and the component
//! of L − x across a_k is at most S_air·sin(k·δ) + k·ℓ, with S_air ≤ (R₀ + k·ℓ)/cos(k·δ) and
//! R₀ = |L − x|. So the arrival direction lies within γ of the straight direction (L − x)/R₀,
//!
//!   sin γ ≤ tan(k·δ)·(1 + k·ℓ/R₀) + k·ℓ/R₀,
//!
//! and a vertex whose whole γ-cone misses the pixel grid cannot contribute.
//!
//! The turn δ of one crossing: a body whose entry and exit faces are parallel (a flat pane)
//! returns every ray to its original direction, δ = 0 exactly (Snell's law at two parallel
//! planes). A bent pane's faces are parallel only locally: over the horizontal reach of a ray
//! inside the glass, t·tan θ_c (θ_c the critical angle), its normals turn by at most
//! β = κ·(t·tan θ_c + h/2) + μ, with κ the largest turn of the shading normal per metre over a
//! triangle edge, h the longest face-triangle edge (interpolated normals depart from the exact
//! ones by a fraction of κ·h inside a triangle; h/2 is generous) and μ the largest misalignment
//! of the two faces' normals measured through the glass; a wedge of angle β turns a ray by at most the
//! in-plane maximum δ_w(β, n) (computed here over all incidences up to total internal
//! reflection) and we take δ = 2·δ_w for skew rays. ℓ = 1.1·t/cos θ_c: inside a slab entered from
//! air the ray is within θ_c of the normal.
//!
//! Only glass bodies whose transmitted chains use two near-parallel faces get a bound:
//! procedural panels and glTF mesh targets (whose triangles `geometry::mesh_border` tagged as
//! faces and edge) whose edge is rough (connection chains stop at a rough edge, `connect`).
//! A glass box, an imported glass mesh that is not the target or a panel with a smooth edge
//! can act as a prism; then
//! the scene has no bound and every connection is solved, as before. The test
//! `validation/physics/glass.rs` checks that images are bit-identical with and without the
//! bound on the shipped glass scenes.

use nalgebra::{Point3, Vector3};

use super::scene::SurfaceModel;
use crate::geometry::accel::{SceneAccel, SceneTriangle};
use crate::geometry::mesh::SurfacePart;

/// A bound on the arrival direction of transmitted connection chains (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct DeviationBound {
    /// Most crossings of glass bodies one chain can make (k).
    pub crossings: u32,
    /// Largest turn of the direction per crossing (rad), δ.
    pub turn_rad: f64,
    /// Longest path inside glass per crossing (m), ℓ.
    pub path_m: f64,
}

impl DeviationBound {
    /// The largest angle (rad) between the straight direction from a vertex to a lens point
    /// `distance_m` away and the arrival direction of any transmitted chain between them;
    /// `None` when the bound says nothing (the chain could arrive from anywhere).
    pub fn arrival_angle(&self, distance_m: f64) -> Option<f64> {
        let k = self.crossings as f64;
        let turn = k * self.turn_rad;
        if distance_m.is_nan() || distance_m <= 0.0 || turn >= 0.5 * std::f64::consts::FRAC_PI_2 {
            return None;
        }
        let lateral = k * self.path_m / distance_m;
        let sin = turn.tan() * (1.0 + lateral) + lateral;
        (sin < 0.5).then(|| sin.asin())
    }

    /// The bound for the glass of a scene, or `None` if some glass body can act as a prism.
    /// `max_interfaces` is the longest chain `connect` follows; `triangles` are the BVH's
    /// input triangles (base frame) and `surfaces` the models per material.
    pub fn of_scene(
        accel: &SceneAccel,
        surfaces: &[SurfaceModel],
        max_interfaces: usize,
    ) -> Option<DeviationBound> {
        let mut bodies: Vec<(u32, f64)> = Vec::new(); // (object, η) of each glass body
        let n = accel.triangle_count();
        for i in 0..n {
            let t = accel.triangle(i as u32);
            if let SurfaceModel::Glass(g) = surfaces[t.material as usize] {
                let chains_cross_edge = t.part == SurfacePart::Edge && g.edge_alpha <= 0.0;
                if t.part == SurfacePart::Solid || chains_cross_edge || t.normals.is_none() {
                    return None;
                }
                if !bodies.iter().any(|b| b.0 == t.object) {
                    bodies.push((t.object, g.eta));
                }
            }
        }
        let mut bound = DeviationBound {
            // Each crossing uses two interfaces; a bent pane can be crossed twice by one line.
            crossings: (max_interfaces / 2).min(2 * bodies.len()) as u32,
            turn_rad: 0.0,
            path_m: 0.0,
        };
        for &(object, eta) in &bodies {
            if eta.is_nan() || eta <= 1.0 {
                return None;
            }
            let slab = measure_slab(accel, object)?;
            let critical = (1.0 / eta).asin();
            let reach = slab.thickness_m * critical.tan();
            let wedge = slab.normal_turn_per_m * (reach + 0.5 * slab.longest_edge_m)
                + slab.misalignment_rad;
            bound.turn_rad = bound.turn_rad.max(2.0 * wedge_turn(wedge, eta)?);
            bound.path_m = bound.path_m.max(1.1 * slab.thickness_m / critical.cos());
        }
        Some(bound)
    }
}

/// What the bound needs of one glass body's two faces.
#[derive(Clone, Copy, Debug)]
struct Slab {
    /// Largest distance through the glass from a face triangle to the other face (m).
    thickness_m: f64,
    /// Largest angle between a face triangle's normal and the reversed normal of the other face
    /// where the ray along it lands (rad).
    misalignment_rad: f64,
    /// Largest turn of the shading normal per length of a face-triangle edge (rad/m).
    normal_turn_per_m: f64,
    /// Longest face-triangle edge (m).
    longest_edge_m: f64,
}

/// Measures the faces of glass body `object` by casting, from every face triangle's centroid, a
/// ray along its inward normal to the other face. `None` if no cast reaches the other face.
fn measure_slab(accel: &SceneAccel, object: u32) -> Option<Slab> {
    let mut slab = Slab {
        thickness_m: 0.0,
        misalignment_rad: 0.0,
        normal_turn_per_m: 0.0,
        longest_edge_m: 0.0,
    };
    let mut hits = 0usize;
    for i in 0..accel.triangle_count() as u32 {
        let t: &SceneTriangle = accel.triangle(i);
        let other = match t.part {
            SurfacePart::TopFace => SurfacePart::BottomFace,
            SurfacePart::BottomFace => SurfacePart::TopFace,
            _ => continue,
        };
        if t.object != object {
            continue;
        }
        let normals = t.normals?;
        for k in 0..3 {
            let (a, b) = (k, (k + 1) % 3);
            let edge = (t.vertices[b] - t.vertices[a]).norm();
            slab.longest_edge_m = slab.longest_edge_m.max(edge);
            if edge > 0.0 {
                let turn = angle(&normals[a], &normals[b]);
                slab.normal_turn_per_m = slab.normal_turn_per_m.max(turn / edge);
            }
        }
        // From the centroid (a ray from a vertex may meet the other face exactly on a vertex
        // or an edge, where the f32 test can miss), along the interpolated inward normal.
        let centroid = Point3::from(
            (t.vertices[0].coords + t.vertices[1].coords + t.vertices[2].coords) / 3.0,
        );
        let Some(normal) = (normals[0] + normals[1] + normals[2]).try_normalize(1e-12) else {
            continue;
        };
        let inward = -normal;
        // Rim triangles may reach the edge finish instead: those chains stop there anyway.
        let Some(hit) = accel.closest_hit_leaving(&centroid, &inward, i, 1.0) else {
            continue;
        };
        if hit.object == object && hit.part == other {
            hits += 1;
            slab.thickness_m = slab.thickness_m.max(hit.t);
            let misalignment = angle(&hit.shading_normal, &inward);
            slab.misalignment_rad = slab.misalignment_rad.max(misalignment);
        }
    }
    (hits > 0).then_some(slab)
}

/// Angle between two unit vectors (rad), accurate for small angles.
fn angle(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

/// The largest turn (rad) of a ray crossing a wedge of apex angle `wedge` (rad) and index
/// `eta` in the plane of its normals, over every incidence that is not totally reflected:
/// entering at θ_in to the first normal, refracted to θ₁ (sin θ_in = η·sin θ₁), meeting the second
/// face at θ₂ = θ₁ − β and leaving at θ_out (sin θ_out = η·sin θ₂), the ray turns by
/// |θ_out + β − θ_in|; zero for β = 0 (Snell's law; Hecht, *Optics*, §5.5 on prisms).
/// `None` for a wedge too steep to bound (≥ 5°).
fn wedge_turn(wedge: f64, eta: f64) -> Option<f64> {
    if wedge == 0.0 {
        return Some(0.0);
    }
    if !(wedge > 0.0 && wedge < 5f64.to_radians()) {
        return None;
    }
    let turn = |theta_in: f64| -> Option<f64> {
        let theta_1 = (theta_in.sin() / eta).asin();
        let s = eta * (theta_1 - wedge).sin();
        (s.abs() <= 1.0).then(|| (s.asin() + wedge - theta_in).abs())
    };
    let limit = std::f64::consts::FRAC_PI_2;
    const STEPS: usize = 200_000;
    let mut worst: f64 = 0.0;
    for i in 0..=STEPS {
        let theta_in = -limit + 2.0 * limit * i as f64 / STEPS as f64;
        if let Some(t) = turn(theta_in) {
            worst = worst.max(t);
        }
    }
    // The turn is steepest where the exit grazes (θ₂ = ±θ_c): evaluate there exactly too.
    let critical = (1.0 / eta).asin();
    for theta_2 in [critical, -critical] {
        let s = eta * (theta_2 + wedge).sin();
        if s.abs() <= 1.0 {
            if let Some(t) = turn(s.asin()) {
                worst = worst.max(t);
            }
        }
    }
    Some(worst)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parallel_slab_does_not_turn_and_a_thin_wedge_turns_little() {
        assert_eq!(wedge_turn(0.0, 1.52), Some(0.0));
        // A thin prism at small incidence deviates by (n − 1)·β (Hecht §5.5); near grazing exit
        // it turns more, so the maximum is larger than that.
        let beta = 1e-3;
        let worst = wedge_turn(beta, 1.52).unwrap();
        assert!(worst >= 0.52 * beta, "{worst}");
        assert!(worst < 0.1, "{worst}");
        assert_eq!(wedge_turn(0.2, 1.52), None);
    }

    #[test]
    fn the_arrival_angle_grows_with_glass_and_shrinks_with_distance() {
        let b = DeviationBound {
            crossings: 2,
            turn_rad: 0.0,
            path_m: 5e-3,
        };
        let near = b.arrival_angle(0.1).unwrap();
        let far = b.arrival_angle(1.0).unwrap();
        assert!(near > far && far > 0.0);
        // sin γ = k·ℓ/R₀ for a flat pane.
        assert!((far.sin() - 0.01).abs() < 1e-12);
        assert_eq!(b.arrival_angle(0.01), None);
        let bent = DeviationBound {
            turn_rad: 1e-3,
            ..b
        };
        assert!(bent.arrival_angle(1.0).unwrap() > far);
    }
}
