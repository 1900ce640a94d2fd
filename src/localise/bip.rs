//! Border Identifier Points: one point per laser profile that stands for the glass border.
//!
//! Adrian & Pham, Section IV-A ("Scanning"): "At each pose, the scanner receives a set of
//! points from the laser line being reflected off the glass edge. We then proceed to filter
//! these collinear points to obtain a single point which we call the Border Identifier Point
//! (BIP). […] we ensure that the BIP selected is the highest point among the collinear points
//! above the ground plane. This point corresponds to the point p_e on the intersection between
//! the transparent glass surface and diffuse glass edge."
//!
//! Profiles come in already expressed in the base frame B (z up, metres); converting the
//! sensor's (x, z) profile with the scan pose T_BS is the caller's job, so this runs unchanged
//! on real scans.

use nalgebra::Point3;

/// The paper's rule: the index of the highest point above the ground plane, i.e. with
/// z > `ground_z + min_height` (m). Points at or below that height, and non-finite points, are
/// ignored; `None` if none is left. Ties go to the lowest index.
pub fn bip_highest(points: &[Point3<f64>], ground_z: f64, min_height: f64) -> Option<usize> {
    let floor = ground_z + min_height;
    let mut best: Option<usize> = None;
    for (i, p) in points.iter().enumerate() {
        if !is_finite(p) || p.z <= floor {
            continue;
        }
        if best.is_none_or(|b| p.z > points[b].z) {
            best = Some(i);
        }
    }
    best
}

/// A robust variant of the paper's rule: the highest point above the ground plane (as in
/// [`bip_highest`]) that has at least `min_neighbours` other finite profile points within
/// `radius` (m, 3-D distance). An isolated return — a glint, a speckle spike, a reflection of
/// the background through the glass — cannot become the BIP, while a point of the edge, which
/// the laser line samples densely, keeps its neighbours.
///
/// Candidates are tried from the highest down and the first supported one is returned, so the
/// cost is O(n) per candidate tried, usually a few.
pub fn bip_highest_supported(
    points: &[Point3<f64>],
    ground_z: f64,
    min_height: f64,
    radius: f64,
    min_neighbours: usize,
) -> Option<usize> {
    let floor = ground_z + min_height;
    let mut candidates: Vec<usize> = (0..points.len())
        .filter(|&i| is_finite(&points[i]) && points[i].z > floor)
        .collect();
    // Highest first; equal heights keep index order (a stable sort).
    candidates.sort_by(|&a, &b| points[b].z.total_cmp(&points[a].z));
    let r2 = radius * radius;
    candidates.into_iter().find(|&i| {
        let neighbours = (points.iter().enumerate())
            .filter(|&(j, q)| j != i && is_finite(q) && (q - points[i]).norm_squared() <= r2)
            .count();
        neighbours >= min_neighbours
    })
}

pub(super) fn is_finite(p: &Point3<f64>) -> bool {
    p.coords.iter().all(|c| c.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A profile across a 4 mm pane's edge: ground at z = 0 out to x = 10 mm, then the top face
    /// at z = 4 mm, every 0.2 mm (the scanCONTROL 2600-100 spacing at mid range).
    fn edge_profile() -> Vec<Point3<f64>> {
        (0..100)
            .map(|i| {
                let x = i as f64 * 0.2e-3;
                let z = if x < 10e-3 {
                    0.0
                } else {
                    4e-3 - 1e-5 * (x - 10e-3) / 10e-3
                };
                Point3::new(x, 0.5, z)
            })
            .collect()
    }

    #[test]
    fn highest_point_above_ground_is_chosen() {
        let pts = edge_profile();
        // The top face slopes down by 10 µm away from the edge, so its first point is highest.
        let i = bip_highest(&pts, 0.0, 0.0).unwrap();
        assert_eq!(i, 50);
        assert!((pts[i].z - 4e-3).abs() < 1e-12);
    }

    #[test]
    fn points_at_or_below_ground_are_ignored() {
        let mut pts: Vec<Point3<f64>> = (0..10)
            .map(|i| Point3::new(i as f64 * 1e-3, 0.0, -1e-3 * i as f64))
            .collect();
        pts[3].z = 0.0;
        assert_eq!(bip_highest(&pts, 0.0, 0.0), None);
        pts[7].z = 0.5e-3;
        assert_eq!(bip_highest(&pts, 0.0, 0.0), Some(7));
        // Below the minimum height above the ground: ignored too.
        assert_eq!(bip_highest(&pts, 0.0, 1e-3), None);
        pts[2].z = f64::NAN;
        assert_eq!(bip_highest(&pts, 0.0, 0.0), Some(7));
        assert_eq!(bip_highest(&[], 0.0, 0.0), None);
    }

    #[test]
    fn an_isolated_spike_is_rejected_by_the_supported_variant() {
        let mut pts = edge_profile();
        // A glint 6 mm above the table, 3 mm away from any other return.
        pts[20] = Point3::new(4e-3, 0.5, 9e-3);
        assert_eq!(bip_highest(&pts, 0.0, 0.0), Some(20));
        let i = bip_highest_supported(&pts, 0.0, 0.0, 0.5e-3, 2).unwrap();
        assert_eq!(i, 50);
        // Too strict a support requirement leaves nothing.
        assert_eq!(bip_highest_supported(&pts, 0.0, 0.0, 0.5e-3, 50), None);
    }
}
