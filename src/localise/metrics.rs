//! Localisation errors as the paper reports them (Adrian & Pham, Sections V–VI).
//!
//! All lengths returned here are in millimetres and angles in degrees, the units of the
//! paper's tables; inputs are poses and border curves in metres.

use nalgebra::Point3;

use super::nearest::closest_on_border;
use crate::geometry::border::BorderCurve;
use crate::geometry::pose::Pose;

/// Summary of a set of errors (the unit of the values it was built from). Serialises as
/// `{"mean", "std", "max", "n"}`, NaN as JSON null.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Stats {
    /// Arithmetic mean (NaN when `n` = 0).
    pub mean: f64,
    /// Sample standard deviation (n − 1 in the denominator; 0 when `n` = 1, NaN when 0).
    pub std: f64,
    /// Largest value (NaN when `n` = 0).
    pub max: f64,
    /// Number of values.
    pub n: usize,
}

impl Stats {
    /// Mean, sample standard deviation and maximum of `values`.
    pub fn from_values(values: &[f64]) -> Stats {
        let n = values.len();
        if n == 0 {
            return Stats {
                mean: f64::NAN,
                std: f64::NAN,
                max: f64::NAN,
                n,
            };
        }
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = if n > 1 {
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64
        } else {
            0.0
        };
        Stats {
            mean,
            std: var.sqrt(),
            max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            n,
        }
    }
}

/// Pose error of an estimate of T_BM: the distance between the two model origins (mm) and the
/// angle of the relative rotation R_est·R_trueᵀ (degrees, in [0, 180]). The translation part
/// depends on where the model origin is; [`task_error`] does not.
pub fn pose_error(estimate: &Pose, truth: &Pose) -> (f64, f64) {
    let dt = (estimate.translation.vector - truth.translation.vector).norm() * 1e3;
    let dr = (estimate.rotation * truth.rotation.inverse())
        .angle()
        .to_degrees();
    (dt, dr)
}

/// The paper's task error (Section VI, Table 4): for `reference_points` points spread evenly
/// by arc length along the true border (in B), the distance (mm) to the nearest point of the
/// estimated border M′ (in B). The paper touched each reference point with the robot's tooltip
/// and moved to the nearest point of M′; in simulation the touch is exact.
pub fn task_error(
    truth_border_b: &BorderCurve,
    estimate_border_b: &BorderCurve,
    reference_points: usize,
) -> Stats {
    distances_from_samples(truth_border_b, estimate_border_b, reference_points)
}

/// Contour (glue path) error over the whole border: for `samples` points spread evenly by arc
/// length along the estimated border, the distance (mm) to the true border.
pub fn contour_error(truth_b: &BorderCurve, estimate_b: &BorderCurve, samples: usize) -> Stats {
    distances_from_samples(estimate_b, truth_b, samples)
}

/// Distances (mm) from `count` evenly spaced points of `from` to the curve `to`.
fn distances_from_samples(from: &BorderCurve, to: &BorderCurve, count: usize) -> Stats {
    if from.vertices.len() < 2 || to.vertices.is_empty() {
        return Stats::from_values(&[]);
    }
    let length = from.length();
    let values: Vec<f64> = (0..count)
        .map(|k| {
            let p: Point3<f64> = from
                .at_arc_length(length * k as f64 / count as f64)
                .position;
            closest_on_border(to, &p).distance * 1e3
        })
        .collect();
    Stats::from_values(&values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::pose::pose_from_mm_deg;
    use crate::localise::fixtures::flat_pane;

    #[test]
    fn stats_of_known_values() {
        let s = Stats::from_values(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!((s.mean, s.max, s.n), (2.5, 4.0, 4));
        assert!((s.std - (5.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!(Stats::from_values(&[]).mean.is_nan());
        assert_eq!(Stats::from_values(&[7.0]).std, 0.0);
    }

    #[test]
    fn identical_borders_give_zero_error() {
        let truth = pose_from_mm_deg([400.0, -50.0, 10.0], [1.0, -2.0, 35.0]);
        let b = flat_pane().transformed(&truth);
        let (dt, dr) = pose_error(&truth, &truth);
        assert!(dt == 0.0 && dr < 1e-12, "{dt} {dr}");
        let task = task_error(&b, &b, 100);
        let contour = contour_error(&b, &b, 500);
        assert_eq!(task.n, 100);
        assert!(
            task.max < 1e-9 && contour.max < 1e-9,
            "{task:?} {contour:?}"
        );
    }

    #[test]
    fn a_pure_1mm_shift_gives_about_1mm() {
        let truth = pose_from_mm_deg([400.0, -50.0, 0.0], [0.0, 0.0, 35.0]);
        // A 1 mm shift straight up, along the top face's normal: every point is 1 mm off.
        let shifted = pose_from_mm_deg([400.0, -50.0, 1.0], [0.0, 0.0, 35.0]);
        let (dt, dr) = pose_error(&shifted, &truth);
        assert!((dt - 1.0).abs() < 1e-9 && dr < 1e-9);
        let (a, b) = (
            flat_pane().transformed(&truth),
            flat_pane().transformed(&shifted),
        );
        let task = task_error(&a, &b, 200);
        let contour = contour_error(&a, &b, 200);
        for s in [task, contour] {
            assert!(
                (s.mean - 1.0).abs() < 1e-9 && (s.max - 1.0).abs() < 1e-9,
                "{s:?}"
            );
        }
        // A 1 mm shift in the plane along x: the long sides slide along themselves (0 mm), the
        // short sides are 1 mm off, the corners in between; the maximum is 1 mm.
        let sideways = pose_from_mm_deg([1.0, 0.0, 0.0], [0.0; 3]);
        let task = task_error(&flat_pane(), &flat_pane().transformed(&sideways), 400);
        assert!(
            (task.max - 1.0).abs() < 1e-6 && task.mean > 0.2 && task.mean < 0.6,
            "{task:?}"
        );
    }
}
