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

/// Settings of [`bip_edge_line`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeLineSettings {
    /// Distance from the line within which a point is an inlier (m).
    pub tolerance: f64,
    /// Least angle between the edge line and the ground plane (rad): the ground edge of a
    /// pane stands near perpendicular to its faces, which lie within a few degrees of the
    /// ground.
    pub min_steepness_rad: f64,
    /// Largest gap between consecutive inliers (sorted by height) inside one run (m).
    pub max_gap: f64,
    /// Least number of inliers in the run the BIP is taken from.
    pub min_points: usize,
    /// Line candidates are drawn from pairs of points at most this many places apart in the
    /// profile (the edge's points are neighbours in column order).
    pub pair_window: usize,
}

impl Default for EdgeLineSettings {
    /// 0.2 mm tolerance (a few times the speckle and roughness scatter of edge points, PITFALLS
    /// and the edge study), 45° steepness, 1 mm gap (five profile points at mid range),
    /// 3 points, pairs up to 24 places apart (a 4 mm edge spans ~14 columns at 45°).
    fn default() -> Self {
        EdgeLineSettings {
            tolerance: 0.2e-3,
            min_steepness_rad: 45f64.to_radians(),
            max_gap: 1.0e-3,
            min_points: 3,
            pair_window: 24,
        }
    }
}

/// The "edge line" variant of the paper's rule, for panes whose faces return light: the top
/// of the steep line of returns the ground edge makes in the profile.
///
/// The paper's rule assumes the faces return nothing, so that the highest point above the
/// ground lies on the edge. Where a face's faint diffuse return clears the threshold, the rule
/// picks a face point instead, and on a convex pane (a car window bent up towards its middle)
/// the face rises above its own border, so the highest point is never p_e. The ground edge,
/// though, is a near-perpendicular band a few millimetres tall, which the laser line crosses
/// as a short steep run of collinear points ("the collinear points" of the paper); the faces,
/// the ground and the background seen through the glass lie within a few degrees of the
/// ground plane. So: find the steep line (≥ `min_steepness_rad` from the ground plane) with
/// the most inliers among the points above the ground (pairs of nearby profile points propose
/// lines; ties go to the first pair), keep its largest run without a gap over `max_gap`, and
/// return the highest point of that run: the top of the edge, where it meets the top face.
///
/// Deterministic; O(n · pair_window · n) for n points above the ground.
pub fn bip_edge_line(
    points: &[Point3<f64>],
    ground_z: f64,
    min_height: f64,
    settings: &EdgeLineSettings,
) -> Option<usize> {
    let floor = ground_z + min_height;
    let above: Vec<usize> = (0..points.len())
        .filter(|&i| is_finite(&points[i]) && points[i].z > floor)
        .collect();
    let min_sin = settings.min_steepness_rad.sin();
    let tol2 = settings.tolerance * settings.tolerance;
    let inliers_of = |a: Point3<f64>, dir: nalgebra::Vector3<f64>| {
        above
            .iter()
            .copied()
            .filter(|&k| {
                let d = points[k] - a;
                (d - dir * d.dot(&dir)).norm_squared() <= tol2
            })
            .collect::<Vec<usize>>()
    };
    let mut best: Option<(usize, Point3<f64>, nalgebra::Vector3<f64>)> = None;
    for (ia, &i) in above.iter().enumerate() {
        for &j in above.iter().skip(ia + 1).take(settings.pair_window) {
            let d = points[j] - points[i];
            let len = d.norm();
            if len < 2.0 * settings.tolerance || d.z.abs() < min_sin * len {
                continue;
            }
            let dir = d / len;
            let count = inliers_of(points[i], dir).len();
            if best.is_none_or(|(c, _, _)| count > c) {
                best = Some((count, points[i], dir));
            }
        }
    }
    let (_, a, dir) = best?;
    let mut run_pts = inliers_of(a, dir);
    run_pts.sort_by(|&x, &y| points[x].z.total_cmp(&points[y].z).then(x.cmp(&y)));
    // Split into runs at gaps; keep the longest (ties: the higher one).
    let mut runs: Vec<Vec<usize>> = Vec::new();
    for k in run_pts {
        match runs.last_mut() {
            Some(run) if (points[k] - points[*run.last().unwrap()]).norm() <= settings.max_gap => {
                run.push(k)
            }
            _ => runs.push(vec![k]),
        }
    }
    let run = runs.into_iter().rev().max_by_key(|r| r.len())?;
    if run.len() < settings.min_points {
        return None;
    }
    // The first face point past the corner can sit within the tolerance of a line through two
    // edge points; the least-squares line of the run, with half the tolerance, drops it.
    let (centre, axis) = principal_line(points, &run);
    let tight2 = tol2 / 4.0;
    run.iter()
        .copied()
        .filter(|&k| {
            let d = points[k] - centre;
            (d - axis * d.dot(&axis)).norm_squared() <= tight2
        })
        .max_by(|&x, &y| points[x].z.total_cmp(&points[y].z).then(y.cmp(&x)))
}

/// The least-squares (total least squares) line through `points[idx]`: centroid and unit
/// direction of largest spread.
fn principal_line(points: &[Point3<f64>], idx: &[usize]) -> (Point3<f64>, nalgebra::Vector3<f64>) {
    let n = idx.len() as f64;
    let centre = Point3::from(
        idx.iter()
            .map(|&k| points[k].coords)
            .sum::<nalgebra::Vector3<f64>>()
            / n,
    );
    let cov = idx
        .iter()
        .map(|&k| {
            let d = points[k] - centre;
            d * d.transpose()
        })
        .sum::<nalgebra::Matrix3<f64>>();
    let eig = cov.symmetric_eigen();
    let k = eig.eigenvalues.imax();
    (centre, eig.eigenvectors.column(k).into_owned().normalize())
}

fn is_finite(p: &Point3<f64>) -> bool {
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

    /// A convex pane's profile: ground at z = 0 out to x = 10 mm, the edge from z = 0.5 mm to
    /// 4.5 mm at x = 10 mm (tilted 8° like the ends of a bent window), then the top face rising
    /// at 10° inwards, its faint return every 0.2 mm.
    fn convex_profile() -> (Vec<Point3<f64>>, Point3<f64>) {
        let tilt = 8f64.to_radians();
        let top = Point3::new(10e-3 + 4e-3 * tilt.tan(), 0.5, 4.5e-3);
        let mut pts: Vec<Point3<f64>> = (0..50)
            .map(|i| Point3::new(i as f64 * 0.2e-3, 0.5, 0.0))
            .collect();
        pts.extend((0..=20).map(|i| {
            let z = 0.5e-3 + 4e-3 * i as f64 / 20.0;
            Point3::new(10e-3 + (z - 0.5e-3) * tilt.tan(), 0.5, z)
        }));
        let slope = 10f64.to_radians().tan();
        pts.extend((1..60).map(|i| {
            let dx = i as f64 * 0.2e-3;
            Point3::new(top.x + dx, 0.5, top.z + dx * slope)
        }));
        (pts, top)
    }

    #[test]
    fn the_edge_line_rule_finds_the_top_of_the_edge_on_a_convex_pane() {
        let (pts, top) = convex_profile();
        // The paper's rule takes the far end of the rising face.
        let h = bip_highest(&pts, 0.0, 0.0).unwrap();
        assert!((pts[h] - top).norm() > 10e-3);
        let i = bip_edge_line(&pts, 0.0, 0.0, &EdgeLineSettings::default()).unwrap();
        assert!((pts[i] - top).norm() < 1e-9, "{:?} vs {top:?}", pts[i]);
    }

    #[test]
    fn the_edge_line_rule_ignores_a_steep_outlier_and_needs_a_steep_run() {
        let (mut pts, top) = convex_profile();
        // A lone return 3 mm above the edge's top, on the edge's line: beyond the gap, so the
        // longest run still ends at the top of the edge.
        pts.push(Point3::new(
            top.x + 3e-3 * 8f64.to_radians().tan(),
            0.5,
            top.z + 3e-3,
        ));
        let i = bip_edge_line(&pts, 0.0, 0.0, &EdgeLineSettings::default()).unwrap();
        assert!((pts[i] - top).norm() < 1e-9);
        // Flat returns only (a face seen without its edge): no steep line, no BIP.
        let flat: Vec<Point3<f64>> = (0..80)
            .map(|i| Point3::new(i as f64 * 0.2e-3, 0.0, 4e-3))
            .collect();
        assert_eq!(
            bip_edge_line(&flat, 0.0, 0.0, &EdgeLineSettings::default()),
            None
        );
        assert_eq!(
            bip_edge_line(&[], 0.0, 0.0, &EdgeLineSettings::default()),
            None
        );
        let nan = vec![Point3::new(f64::NAN, 0.0, 1.0); 5];
        assert_eq!(
            bip_edge_line(&nan, 0.0, 0.0, &EdgeLineSettings::default()),
            None
        );
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
