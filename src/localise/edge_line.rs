//! The edge-line BIP rule: the top of the chain of returns that the ground edge makes in a
//! profile, for panes whose faces return light and edges whose corners are ground off.
//!
//! The paper's rule (`bip::bip_highest`) assumes the faces return nothing, so that the highest
//! point above the ground lies on the edge. Where a face's faint diffuse return clears the
//! threshold, it picks a face point instead, and on a convex pane (a car window bent up towards
//! its middle) the face rises above its own border, so the highest point is never p_e.
//!
//! What the rule assumes (and so where it holds):
//! - the edge finish is a band a few millimetres tall that rises from the ground side to the
//!   top face; its returns lie on a chain of near neighbours in the profile (every 0.2 mm or so
//!   along the laser line, with gaps of at most `max_gap` where speckle drops a column);
//! - some part of that band is steep (at least `min_steepness_rad` from the ground plane: the
//!   flat-ground wall of a seamed or flat edge, or an arris of 30–65°), and it has the most
//!   collinear returns of any steep line;
//! - the top face, the ground and the background seen through the glass lie within
//!   `min_rise_rad` of the ground plane near the border (a bent window's face within ~11° at its
//!   ends), while every step up the edge finish rises more steeply than that.
//!
//! Then: among the points above the ground, nearby pairs propose steep lines; each line's
//! inliers are cut into runs at gaps over `max_gap`, and the line counts by its longest run,
//! provided that run's own least-squares line is steep too (a flat band of returns crossed at a
//! shallow angle is not an edge). The longest such run wins (ties go to the first pair); drop
//! points off its least-squares line and start at the run's highest point. From there, climb: the next point is the nearest higher one within `max_gap` whose step
//! rises at least `min_rise_rad`; the last point reached is the BIP, where the edge finish meets
//! the transparent face (p_e). On a flat-ground edge the climb ends where it starts, the top of
//! the wall; on a seamed edge it follows the arris from the wall's top to p_e (the longest
//! collinear run alone stops at the arris's lower corner, 0.8–1.1 mm below p_e for the default
//! seam). On a pencil (round) edge, whose arc meets the face tangentially, it stops where the
//! arc turns flatter than `min_rise_rad`: r·sin(min_rise) short of p_e (0.7 mm for the
//! half-round edge of a 4 mm pane at the default 20°).
//!
//! Deterministic; O(n · pair_window · n) for n points above the ground.

use nalgebra::{Matrix3, Point3, Vector3};

use super::bip::is_finite;

/// Settings of [`bip_edge_line`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeLineSettings {
    /// Distance from the line within which a point is an inlier (m).
    pub tolerance: f64,
    /// Least angle between the steep line that seeds the chain and the ground plane (rad).
    pub min_steepness_rad: f64,
    /// Largest gap between consecutive inliers of the run, and largest step of the climb (m).
    pub max_gap: f64,
    /// Least number of inliers in the run the climb starts from.
    pub min_points: usize,
    /// Line candidates are drawn from pairs of points at most this many places apart in the
    /// profile (the edge's points are neighbours in column order).
    pub pair_window: usize,
    /// Least rise of a step of the climb above the ground plane (rad): steeper than the faces
    /// near the border, flatter than any edge finish.
    pub min_rise_rad: f64,
}

impl Default for EdgeLineSettings {
    /// 0.2 mm tolerance (a few times the speckle and roughness scatter of edge points, measured
    /// in the edge study), 25° steepness (below the 30° flattest arris of a seamed edge, above
    /// the ~11° a bent window's face reaches at its ends), 1 mm gap and step (five profile
    /// points at mid range), 3 points, pairs up to 24 places apart (a 4 mm edge spans ~14
    /// columns at 45°), 20° rise.
    fn default() -> Self {
        EdgeLineSettings {
            tolerance: 0.2e-3,
            min_steepness_rad: 25f64.to_radians(),
            max_gap: 1.0e-3,
            min_points: 3,
            pair_window: 24,
            min_rise_rad: 20f64.to_radians(),
        }
    }
}

/// The edge-line rule (see the module docs): the index of the point where the chain of
/// edge returns, climbed from its steepest well-populated run, reaches the top face; `None` if
/// no steep run of `min_points` exists among the points above `ground_z + min_height`.
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
    let seed = steep_run_top(points, &above, settings)?;
    Some(climb(points, &above, seed, settings))
}

/// The highest point of the longest gap-free run of inliers on a steep line whose run is
/// itself steep (its least-squares line at least `min_steepness_rad` from the ground).
fn steep_run_top(
    points: &[Point3<f64>],
    above: &[usize],
    settings: &EdgeLineSettings,
) -> Option<usize> {
    let min_sin = settings.min_steepness_rad.sin();
    let tol2 = settings.tolerance * settings.tolerance;
    let inliers_of = |a: Point3<f64>, dir: Vector3<f64>| {
        above
            .iter()
            .copied()
            .filter(|&k| {
                let d = points[k] - a;
                (d - dir * d.dot(&dir)).norm_squared() <= tol2
            })
            .collect::<Vec<usize>>()
    };
    // Longest gap-free run of inliers (ties: the higher one).
    let longest_run = |mut idx: Vec<usize>| {
        idx.sort_by(|&x, &y| points[x].z.total_cmp(&points[y].z).then(x.cmp(&y)));
        let mut runs: Vec<Vec<usize>> = Vec::new();
        for k in idx {
            match runs.last_mut() {
                Some(run)
                    if (points[k] - points[run[run.len() - 1]]).norm() <= settings.max_gap =>
                {
                    run.push(k)
                }
                _ => runs.push(vec![k]),
            }
        }
        runs.into_iter().rev().max_by_key(|r| r.len())
    };
    // A candidate counts by its run, and only if the run's own least-squares line is steep:
    // a flat band of returns (the ground seen through the pane, ±30 µm of speckle) lies within
    // the tolerance of any line crossing it at 25–30° over ~1 mm, and so would outnumber a
    // short arris that is the only part of the edge above the threshold.
    let mut best: Option<(Vec<usize>, Point3<f64>, Vector3<f64>)> = None;
    let best_len = |b: &Option<(Vec<usize>, Point3<f64>, Vector3<f64>)>| {
        b.as_ref()
            .map_or(settings.min_points.max(1) - 1, |b| b.0.len())
    };
    for (ia, &i) in above.iter().enumerate() {
        for &j in above.iter().skip(ia + 1).take(settings.pair_window) {
            let d = points[j] - points[i];
            let len = d.norm();
            if len < 2.0 * settings.tolerance || d.z.abs() < min_sin * len {
                continue;
            }
            let inliers = inliers_of(points[i], d / len);
            if inliers.len() <= best_len(&best) {
                continue;
            }
            let Some(run) = longest_run(inliers) else {
                continue;
            };
            if run.len() <= best_len(&best) {
                continue;
            }
            let (centre, axis) = principal_line(points, &run);
            if axis.z.abs() < min_sin {
                continue;
            }
            best = Some((run, centre, axis));
        }
    }
    let (run, centre, axis) = best?;
    // The first face point past the corner can sit within the tolerance of a line through two
    // edge points; the least-squares line of the run, with half the tolerance, drops it.
    let tight2 = tol2 / 4.0;
    run.iter()
        .copied()
        .filter(|&k| {
            let d = points[k] - centre;
            (d - axis * d.dot(&axis)).norm_squared() <= tight2
        })
        .max_by(|&x, &y| points[x].z.total_cmp(&points[y].z).then(y.cmp(&x)))
}

/// Climbs from `start`: repeatedly the nearest point within `max_gap` that lies higher and is
/// reached by a step rising at least `min_rise_rad`; returns the last point reached. Each step
/// gains height, so the climb ends.
fn climb(
    points: &[Point3<f64>],
    above: &[usize],
    start: usize,
    settings: &EdgeLineSettings,
) -> usize {
    let min_sin = settings.min_rise_rad.sin();
    let mut current = start;
    loop {
        let c = points[current];
        let next = above
            .iter()
            .copied()
            .filter(|&k| {
                let d = points[k] - c;
                let len = d.norm();
                d.z > 0.0 && len <= settings.max_gap && d.z >= min_sin * len
            })
            .min_by(|&x, &y| {
                let (dx, dy) = ((points[x] - c).norm(), (points[y] - c).norm());
                dx.total_cmp(&dy).then(x.cmp(&y))
            });
        match next {
            Some(k) => current = k,
            None => return current,
        }
    }
}

/// The least-squares (total least squares) line through `points[idx]`: centroid and unit
/// direction of largest spread.
fn principal_line(points: &[Point3<f64>], idx: &[usize]) -> (Point3<f64>, Vector3<f64>) {
    let n = idx.len() as f64;
    let centre = Point3::from(idx.iter().map(|&k| points[k].coords).sum::<Vector3<f64>>() / n);
    let cov = idx
        .iter()
        .map(|&k| {
            let d = points[k] - centre;
            d * d.transpose()
        })
        .sum::<Matrix3<f64>>();
    let eig = cov.symmetric_eigen();
    let k = eig.eigenvalues.imax();
    (centre, eig.eigenvectors.column(k).into_owned().normalize())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::localise::bip::bip_highest;

    /// A deterministic scatter in [−a, a] (m), a hash of `i`.
    fn jitter(i: usize, a: f64) -> f64 {
        let x = (i as f64 * 0.754_877_666_25 + 0.31).fract();
        a * (2.0 * x - 1.0)
    }

    /// Profile of an edge section crossed perpendicularly: the ground (z = 0) out to x = 0
    /// where the outline is, the section `(inset, height)` polyline from the bottom up (inset
    /// grows to the left, i.e. towards +x here), then the top face from the section's top,
    /// sampled every `step` along the laser line, with ±15 µm scatter; `face` keeps the top
    /// face's returns. Returns the points and p_e (the section's top point).
    fn section_profile(
        section: &[(f64, f64)],
        step: f64,
        face: bool,
    ) -> (Vec<Point3<f64>>, Point3<f64>) {
        let mut pts = Vec::new();
        let mut k = 0;
        let mut push = |p: Point3<f64>, pts: &mut Vec<Point3<f64>>| {
            k += 1;
            pts.push(Point3::new(
                p.x + jitter(k, 15e-6),
                0.0,
                p.z + jitter(k + 7, 15e-6),
            ));
        };
        let mut x = -10e-3;
        while x < -0.5e-3 {
            push(Point3::new(x, 0.0, 0.0), &mut pts);
            x += step;
        }
        // Resample the section polyline at `step` arc length.
        for w in section.windows(2) {
            let (a, b) = (w[0], w[1]);
            let len = (b.0 - a.0).hypot(b.1 - a.1);
            let n = (len / step).ceil().max(1.0) as usize;
            for i in 0..n {
                let s = i as f64 / n as f64;
                let p = (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1));
                push(Point3::new(p.0, 0.0, p.1), &mut pts);
            }
        }
        let top = section[section.len() - 1];
        let p_e = Point3::new(top.0, 0.0, top.1);
        if face {
            for i in 0..60 {
                push(Point3::new(top.0 + i as f64 * step, 0.0, top.1), &mut pts);
            }
        } else {
            push(p_e, &mut pts);
        }
        (pts, p_e)
    }

    /// A seamed edge of a pane `t` thick: arrisses of face width `w` at `angle` top and bottom.
    fn seamed(t: f64, w: f64, angle_deg: f64) -> Vec<(f64, f64)> {
        let h = w * angle_deg.to_radians().tan();
        vec![(w, 0.0), (0.0, h), (0.0, t - h), (w, t)]
    }

    /// A half-round (pencil) edge of radius t/2, bottom to top.
    fn pencil(t: f64) -> Vec<(f64, f64)> {
        let r = 0.5 * t;
        (0..=36)
            .map(|i| {
                let phi = std::f64::consts::PI * (i as f64 / 36.0 - 0.5);
                (r - r * phi.cos(), r + r * phi.sin())
            })
            .collect()
    }

    fn bip_error(section: &[(f64, f64)], face: bool) -> f64 {
        let (pts, p_e) = section_profile(section, 0.2e-3, face);
        let i = bip_edge_line(&pts, 0.0, 0.5e-3, &EdgeLineSettings::default()).unwrap();
        let e = (pts[i] - p_e).norm();
        eprintln!("BIP error {:.3} mm (face returns {face})", e * 1e3);
        e
    }

    #[test]
    fn the_climb_reaches_p_e_on_flat_ground_and_seamed_edges() {
        let t = 4e-3;
        // Flat ground: the top of the wall is p_e.
        for face in [false, true] {
            let e = bip_error(&[(0.0, 0.0), (0.0, t)], face);
            assert!(e < 0.1e-3, "flat ground, face {face}: {e}");
        }
        // Seamed, several widths and angles: the top of the arris, not its lower corner.
        for (w, angle) in [
            (0.3e-3, 45.0),
            (0.8e-3, 45.0),
            (1.5e-3, 45.0),
            (0.8e-3, 30.0),
            (0.8e-3, 65.0),
        ] {
            for face in [false, true] {
                let e = bip_error(&seamed(t, w, angle), face);
                assert!(e < 0.15e-3, "seamed {w} m at {angle}°, face {face}: {e}");
            }
        }
    }

    #[test]
    fn the_longest_run_alone_would_stop_at_the_arris_corner() {
        // What the rule did before it climbed: the top of the wall, the arris's lower corner.
        let (pts, p_e) = section_profile(&seamed(4e-3, 0.8e-3, 45.0), 0.2e-3, true);
        let above: Vec<usize> = (0..pts.len()).filter(|&i| pts[i].z > 0.5e-3).collect();
        let s = EdgeLineSettings::default();
        let top_of_run = steep_run_top(&pts, &above, &s).unwrap();
        assert!((pts[top_of_run] - p_e).norm() > 0.9e-3);
    }

    #[test]
    fn a_pencil_edge_stops_where_the_arc_turns_flat() {
        // r·sin(20°) = 0.68 mm for r = 2 mm: the documented limit, not better.
        for face in [false, true] {
            let e = bip_error(&pencil(4e-3), face);
            assert!(e < 0.75e-3, "pencil, face {face}: {e}");
        }
    }

    #[test]
    fn speckle_gaps_do_not_stop_the_climb() {
        let (mut pts, p_e) = section_profile(&seamed(4e-3, 0.8e-3, 45.0), 0.2e-3, true);
        // Drop every third point of the arris (up to 0.6 mm gaps).
        let mut k = 0;
        pts.retain(|p| {
            k += 1;
            !(p.z > 3.2e-3 && p.z < 3.95e-3 && k % 3 == 0)
        });
        let i = bip_edge_line(&pts, 0.0, 0.5e-3, &EdgeLineSettings::default()).unwrap();
        assert!((pts[i] - p_e).norm() < 0.15e-3);
    }

    #[test]
    fn a_lone_arris_beats_a_flat_band_seen_through_the_pane() {
        // At 40° and a short exposure a 0.4 mm arris is the only part of the edge above the
        // threshold (4 returns, simulated in the scan-angle study's finding map), while the table
        // seen through the pane is a band of ~15 returns 1.85 mm below the top face, scattered
        // ±30 µm by speckle: a line crossing the band at 25–30° holds 5 of them within 0.2 mm.
        let t = 4e-3;
        let (w, h) = (0.4e-3, 0.4e-3);
        let p_e = Point3::new(w, 0.0, t);
        let mut pts: Vec<Point3<f64>> = (0..4)
            .map(|i| {
                let s = i as f64 / 3.0;
                Point3::new(
                    s * w + jitter(i, 15e-6),
                    0.0,
                    t - h + s * h + jitter(i + 3, 15e-6),
                )
            })
            .collect();
        pts.extend((0..15).map(|i| {
            Point3::new(
                w + 2.3e-3 + i as f64 * 0.25e-3,
                0.0,
                t - 1.85e-3 + jitter(i + 11, 30e-6),
            )
        }));
        let i = bip_edge_line(&pts, 0.0, 0.5e-3, &EdgeLineSettings::default()).unwrap();
        assert!((pts[i] - p_e).norm() < 0.1e-3, "{:?}", pts[i]);
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
        // longest run and the climb both end at the top of the edge.
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
        let s = EdgeLineSettings::default();
        assert_eq!(bip_edge_line(&flat, 0.0, 0.0, &s), None);
        assert_eq!(bip_edge_line(&[], 0.0, 0.0, &s), None);
        let nan = vec![Point3::new(f64::NAN, 0.0, 1.0); 5];
        assert_eq!(bip_edge_line(&nan, 0.0, 0.0, &s), None);
    }
}
