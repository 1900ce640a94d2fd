//! Point-to-plane ICP of Border Identifier Points against the model border curve M.
//!
//! Formulation: the model stays in its frame M and the BIPs are moved into it. With the current
//! estimate T_MB = T_BM⁻¹, each BIP p_i (frame B) becomes x_i = T_MB·p_i; its closest point q_i
//! on the border polyline ([`super::nearest::closest_on_border`], through the exact
//! [`SegmentGrid`]) gives the ICP normal
//! n_i = normalize(surface normal + outward edge normal) and the segment tangent t_i. Each point
//! contributes two point-to-plane residuals, r = m·(x_i − q_i) for m = n_i and m = b_i =
//! n_i × t_i: the planes through the border's local tangent line, i.e. point-to-line. Gauss–Newton
//! solves for a small twist (ω, v) applied on the left about the points' centroid c,
//! x_i ← c + exp(ω)(x_i − c) + v, whose Jacobian row is [((x_i − c) × m)ᵀ, mᵀ]. The update uses
//! nalgebra's rotation exponential (`Isometry3::new`), equal to the linearisation to first order.
//!
//! Why two planes and not only n_i (the usual point-to-plane recipe, n_i = the normalised sum
//! of the surface normal and the outward edge normal, which converged in 3–4 iterations to
//! ~1e-13 mm on exact points when measured before this crate): n_i alone leaves each BIP free to
//! slide along b_i, and with imperfect BIPs the fit uses that freedom. Measured on the unit tests'
//! 300 × 200 mm pane with 12 BIPs: σ = 0.1 mm noise gave 0.19–0.25 mm pose error with n_i alone,
//! 0.04–0.08 mm with both planes; one 10 mm outlier dragged least squares 8.0 mm with n_i alone
//! (1.9 mm with both), and the robust fit did not converge in 45 iterations with n_i alone (8
//! with both, exact pose). Exact points converge in 4 iterations either way, as that measurement found;
//! the tangential sliding that stalls point-to-point ICP is still free in the linearisation.
//!
//! Robustness is iteratively reweighted least squares in two stages: a Huber kernel
//! ([`IcpSettings::huber_mm`]) while the pose is still far, then, once the steps are small, a
//! Tukey biweight ([`IcpSettings::tukey_mm`]) that gives zero weight to any BIP further than
//! its scale from the curve, so a gross outlier cannot pull the pose. Both kernels act on the
//! full point-to-curve distance |x_i − q_i|, so an outlier is caught whichever way it is off.
//!
//! Conditioning: a border curve constrains each point only across the curve (n_i and b_i), never
//! along it, so a few points on a nearly straight stretch leave the along-border translation
//! (and, if they are collinear, the rotation about that line) free. The 6×6 normal
//! matrix H = Σ w_i J_iᵀ J_i is built in scaled coordinates (L·ω, v), both in metres, with L the
//! RMS distance of the points from their centroid; its eigenvalues give
//! `condition = λ_min / λ_max` (dimensionless). The uncertainty of the weakest direction is
//! 1/√condition times that of the best-constrained one. Below [`IcpSettings::min_condition`]
//! the fit is reported as degenerate, and Gauss–Newton never steps along directions that weak
//! (truncated eigen-solve), so the pose stays at its start along them instead of wandering.

use nalgebra::{Isometry3, Matrix6, Point3, SymmetricEigen, Translation3, Vector3, Vector6};

use super::nearest::{ClosestPoint, SegmentGrid};
use crate::geometry::border::BorderCurve;
use crate::geometry::pose::Pose;

/// ICP parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IcpSettings {
    /// Iteration limit over both robust stages.
    pub max_iterations: usize,
    /// Convergence: the last step moved less than this (m) and…
    pub tolerance_translation: f64,
    /// …turned less than this (rad).
    pub tolerance_rotation: f64,
    /// Huber threshold of the first stage (mm): distances beyond it weigh δ/d. `None`: plain
    /// least squares in the first stage.
    pub huber_mm: Option<f64>,
    /// Tukey biweight scale of the second stage (mm): BIPs further than this from the curve get
    /// zero weight and are reported as outliers. `None`: no second stage, every point is an
    /// inlier.
    pub tukey_mm: Option<f64>,
    /// Smallest acceptable λ_min / λ_max of the scaled normal matrix; below it the result is
    /// `degenerate`.
    pub min_condition: f64,
}

impl IcpSettings {
    /// Robust defaults for BIPs from a laser-line sensor (the paper's BIP errors are ~1 mm):
    /// Huber 1 mm, then Tukey 3 mm; at most 50 iterations; converged when a step moves less
    /// than 1 nm and 1 nrad; degenerate below a condition of 1e-4 (weakest direction 100×
    /// less certain than the best).
    pub const fn robust() -> Self {
        Self {
            max_iterations: 50,
            tolerance_translation: 1e-9,
            tolerance_rotation: 1e-9,
            huber_mm: Some(1.0),
            tukey_mm: Some(3.0),
            min_condition: 1e-4,
        }
    }

    /// Plain least squares (no kernel), otherwise as [`IcpSettings::robust`].
    pub const fn least_squares() -> Self {
        let mut s = Self::robust();
        s.huber_mm = None;
        s.tukey_mm = None;
        s
    }
}

/// The result of [`register`].
#[derive(Clone, Debug, PartialEq)]
pub struct Registration {
    /// The estimate of T_BM (model frame M → base frame B).
    pub pose: Pose,
    /// Gauss–Newton iterations run (both stages).
    pub iterations: usize,
    /// The last step was below the tolerances (and at least 3 points were inliers).
    pub converged: bool,
    /// RMS point-to-curve distance of the inliers at the final pose (mm).
    pub rms_mm: f64,
    /// `condition < min_condition`: the points do not pin the pose down. Do not use `pose`
    /// along `weak_directions` (it is the initial pose there).
    pub degenerate: bool,
    /// The eigenvector of the smallest eigenvalue of the scaled normal matrix, as a unit twist
    /// [L·ωx, L·ωy, L·ωz, vx, vy, vz] in the model frame M (rotation about the inliers'
    /// centroid, L their RMS distance from it); `Some` only when `degenerate`.
    pub weakest_direction: Option<[f64; 6]>,
    /// All eigenvectors whose eigenvalue is below the threshold, weakest first (same units as
    /// `weakest_direction`). With collinear points this space has several dimensions and the
    /// weakest single vector is an arbitrary member of it.
    pub weak_directions: Vec<[f64; 6]>,
    /// λ_min / λ_max of the scaled normal matrix at the final pose, in [0, 1].
    pub condition: f64,
    /// Per input point: false if the robust stage gave it zero weight.
    pub inliers: Vec<bool>,
}

/// Why [`register`] could not run.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum IcpError {
    /// A rigid pose needs at least three points (and only then if they are well spread).
    #[error("ICP needs at least 3 border points, got {0}")]
    TooFewPoints(usize),
    /// A NaN or infinite coordinate in the input points.
    #[error("border point {0} has a non-finite coordinate (NaN or infinity)")]
    NonFinitePoint(usize),
    /// A NaN or infinite initial pose.
    #[error("the initial pose has a non-finite component")]
    NonFinitePose,
    /// The model border has fewer than 2 vertices or a non-finite one.
    #[error("the model border is empty or invalid: {0}")]
    BadModel(String),
}

/// Registers BIPs `points_b` (base frame B) against the border curve `model` (model frame M),
/// starting from `initial` = T_BM0, and returns the estimate of T_BM. See the module docs for
/// the formulation, the robust kernels and the degeneracy test.
pub fn register(
    model: &BorderCurve,
    points_b: &[Point3<f64>],
    initial: &Pose,
    settings: &IcpSettings,
) -> Result<Registration, IcpError> {
    validate(model, points_b, initial)?;
    // Built once per registration: every iteration's closest points come from it, exactly as
    // the brute-force search would give them.
    let grid = SegmentGrid::new(model);
    register_valid(model, &grid, points_b, initial, settings)
}

/// [`register`] with the model's [`SegmentGrid`] built by the caller, for many registrations
/// against one model (a sweep, a Monte Carlo study of ICP): the same result bit for bit, minus
/// the grid's build. `grid` must have been built on `model`.
pub fn register_on_grid(
    model: &BorderCurve,
    grid: &SegmentGrid,
    points_b: &[Point3<f64>],
    initial: &Pose,
    settings: &IcpSettings,
) -> Result<Registration, IcpError> {
    validate(model, points_b, initial)?;
    register_valid(model, grid, points_b, initial, settings)
}

/// The Gauss–Newton iterations on input that [`validate`] accepted.
fn register_valid(
    model: &BorderCurve,
    grid: &SegmentGrid,
    points_b: &[Point3<f64>],
    initial: &Pose,
    settings: &IcpSettings,
) -> Result<Registration, IcpError> {
    let mut t_mb = initial.inverse();
    let mut tukey_stage = settings.huber_mm.is_none() && settings.tukey_mm.is_some();
    let mut iterations = 0;
    let mut converged = false;
    // Per-point buffers allocated once and refilled every iteration.
    let mut work = Workspace::with_capacity(points_b.len());
    while iterations < settings.max_iterations {
        let system = build_system(
            model,
            grid,
            points_b,
            &t_mb,
            settings,
            tukey_stage,
            &mut work,
        );
        let (omega, v) = system.solve(settings.min_condition);
        t_mb = system.apply(omega, v) * t_mb;
        iterations += 1;
        let (step_t, step_r) = (v.norm(), omega.norm());
        if step_t < settings.tolerance_translation && step_r < settings.tolerance_rotation {
            if tukey_stage || settings.tukey_mm.is_none() {
                converged = true;
                break;
            }
            tukey_stage = true;
        } else if !tukey_stage && settings.tukey_mm.is_some() && step_t < 1e-6 && step_r < 1e-6 {
            // Close enough for the redescending kernel: its zero weights are now trustworthy.
            tukey_stage = true;
        }
    }
    let tukey_final = settings.tukey_mm.is_some();
    let system = build_system(
        model,
        grid,
        points_b,
        &t_mb,
        settings,
        tukey_final,
        &mut work,
    );
    let eigen = system.eigen();
    let (condition, weak) = conditioning(&eigen, settings.min_condition);
    let inliers: Vec<bool> = work.weights.iter().map(|&w| w > 0.0).collect();
    let n_in = inliers.iter().filter(|&&b| b).count();
    let sum_d2: f64 = (work.distances.iter().zip(&inliers))
        .filter(|(_, &inlier)| inlier)
        .map(|(d, _)| d * d)
        .sum();
    let degenerate = condition < settings.min_condition;
    Ok(Registration {
        pose: t_mb.inverse(),
        iterations,
        converged: converged && n_in >= 3,
        rms_mm: if n_in > 0 {
            (sum_d2 / n_in as f64).sqrt() * 1e3
        } else {
            f64::NAN
        },
        degenerate,
        weakest_direction: if degenerate {
            weak.first().copied()
        } else {
            None
        },
        weak_directions: weak,
        condition,
        inliers,
    })
}

fn validate(model: &BorderCurve, points_b: &[Point3<f64>], initial: &Pose) -> Result<(), IcpError> {
    if model.vertices.len() < 2 {
        return Err(IcpError::BadModel(format!(
            "{} vertices, need at least 2",
            model.vertices.len()
        )));
    }
    let finite = |v: &Vector3<f64>| v.iter().all(|c| c.is_finite());
    if let Some(i) = (model.vertices.iter()).position(|v| {
        !finite(&v.position.coords) || !finite(&v.surface_normal) || !finite(&v.outward)
    }) {
        return Err(IcpError::BadModel(format!("vertex {i} is not finite")));
    }
    if points_b.len() < 3 {
        return Err(IcpError::TooFewPoints(points_b.len()));
    }
    if let Some(i) = points_b.iter().position(|p| !finite(&p.coords)) {
        return Err(IcpError::NonFinitePoint(i));
    }
    let q = initial.rotation.coords;
    if !finite(&initial.translation.vector) || !q.iter().all(|c| c.is_finite()) {
        return Err(IcpError::NonFinitePose);
    }
    Ok(())
}

/// The weighted normal equations H·y = −g in scaled coordinates y = (L·ω, v).
struct System {
    h: Matrix6<f64>,
    g: Vector6<f64>,
    centroid: Point3<f64>,
    scale: f64,
}

/// The per-point quantities of one iteration: moved points, their closest points on the
/// model, distances and IRLS weights.
struct Workspace {
    xs: Vec<Point3<f64>>,
    closest: Vec<ClosestPoint>,
    distances: Vec<f64>,
    weights: Vec<f64>,
}

impl Workspace {
    fn with_capacity(n: usize) -> Self {
        Workspace {
            xs: Vec::with_capacity(n),
            closest: Vec::with_capacity(n),
            distances: Vec::with_capacity(n),
            weights: Vec::with_capacity(n),
        }
    }
}

fn build_system(
    model: &BorderCurve,
    grid: &SegmentGrid,
    points_b: &[Point3<f64>],
    t_mb: &Pose,
    settings: &IcpSettings,
    tukey_stage: bool,
    work: &mut Workspace,
) -> System {
    let Workspace {
        xs,
        closest,
        distances,
        weights,
    } = work;
    xs.clear();
    xs.extend(points_b.iter().map(|p| t_mb * p));
    closest.clear();
    closest.extend(xs.iter().map(|x| grid.closest(model, x)));
    distances.clear();
    distances.extend(closest.iter().map(|c| c.distance));
    weights.clear();
    weights.extend(
        distances
            .iter()
            .map(|&d| weight(d * 1e3, settings, tukey_stage)),
    );
    // Centroid and length scale of the weighted points, so that H is well scaled and its
    // eigenvalues compare rotations and translations in the same unit (m).
    let w_sum: f64 = weights.iter().sum();
    let centroid = if w_sum > 0.0 {
        Point3::from(
            xs.iter()
                .zip(weights.iter())
                .map(|(x, w)| x.coords * *w)
                .sum::<Vector3<f64>>()
                / w_sum,
        )
    } else {
        xs[0]
    };
    let spread = if w_sum > 0.0 {
        xs.iter()
            .zip(weights.iter())
            .map(|(x, w)| w * (x - centroid).norm_squared())
            .sum::<f64>()
            / w_sum
    } else {
        0.0
    };
    let scale = spread.sqrt().max(1e-6);
    let mut h = Matrix6::zeros();
    let mut g = Vector6::zeros();
    for ((x, c), &w) in xs.iter().zip(closest.iter()).zip(weights.iter()) {
        if w == 0.0 {
            continue;
        }
        // Two planes per point: the ICP normal n and its partner b ⟂ n, both ⟂ the tangent.
        let b = c.normal.cross(&c.tangent).normalize();
        for m in [c.normal, b] {
            let r = m.dot(&(x - c.point));
            let a = (x - centroid).cross(&m) / scale;
            let j = Vector6::new(a.x, a.y, a.z, m.x, m.y, m.z);
            h += j * j.transpose() * w;
            g += j * (w * r);
        }
    }
    System {
        h,
        g,
        centroid,
        scale,
    }
}

/// IRLS weight for a point-to-curve distance `d_mm`.
fn weight(d_mm: f64, settings: &IcpSettings, tukey_stage: bool) -> f64 {
    if tukey_stage {
        if let Some(c) = settings.tukey_mm {
            // Tukey's biweight: (1 − (d/c)²)² inside, zero outside.
            let u = d_mm / c;
            return if u < 1.0 { (1.0 - u * u).powi(2) } else { 0.0 };
        }
    }
    match settings.huber_mm {
        Some(delta) if d_mm > delta => delta / d_mm,
        _ => 1.0,
    }
}

impl System {
    fn eigen(&self) -> SymmetricEigen<f64, nalgebra::U6> {
        SymmetricEigen::new(self.h)
    }

    /// Gauss–Newton step (ω in rad, v in m), dropping eigen-directions weaker than
    /// `min_condition · λ_max` (a truncated pseudo-inverse).
    ///
    /// Most steps drop nothing, and then the step is H⁻¹(−g), solved by Cholesky. That no
    /// direction would be dropped is proved without the eigen-decomposition: Gershgorin's bound
    /// G ≥ λ_max, and H − min_condition·G·I positive definite (its Cholesky factorisation
    /// succeeds) means every λ > min_condition·G ≥ min_condition·λ_max. Otherwise the
    /// eigen-decomposition decides. The two solves are the same linear algebra up to rounding;
    /// the Cholesky path costs a fraction of nalgebra's 6 × 6 eigen-solver (measured: the
    /// eigen-solves were a fifth of a registration's time).
    fn solve(&self, min_condition: f64) -> (Vector3<f64>, Vector3<f64>) {
        (self.untruncated_step(min_condition))
            .unwrap_or_else(|| self.solve_truncated(min_condition))
    }

    /// The step by Cholesky when no eigen-direction would be dropped (see [`System::solve`]),
    /// `None` when that cannot be proved this way.
    fn untruncated_step(&self, min_condition: f64) -> Option<(Vector3<f64>, Vector3<f64>)> {
        let gershgorin = (0..6)
            .map(|i| self.h.row(i).iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let shifted = self.h - Matrix6::identity() * (min_condition * gershgorin);
        if gershgorin == 0.0 || shifted.cholesky().is_none() {
            return None;
        }
        let y = self.h.cholesky()?.solve(&-self.g);
        Some((
            Vector3::new(y[0], y[1], y[2]) / self.scale,
            Vector3::new(y[3], y[4], y[5]),
        ))
    }

    /// The truncated eigen-solve of [`System::solve`], valid for every system.
    fn solve_truncated(&self, min_condition: f64) -> (Vector3<f64>, Vector3<f64>) {
        let eigen = self.eigen();
        let lambda_max = eigen.eigenvalues.max();
        let mut y = Vector6::zeros();
        if lambda_max > 0.0 {
            for k in 0..6 {
                let lambda = eigen.eigenvalues[k];
                if lambda > min_condition * lambda_max {
                    let u = eigen.eigenvectors.column(k);
                    y -= u * (u.dot(&self.g) / lambda);
                }
            }
        }
        (
            Vector3::new(y[0], y[1], y[2]) / self.scale,
            Vector3::new(y[3], y[4], y[5]),
        )
    }

    /// The left update x ← c + exp(ω)(x − c) + v as an isometry.
    fn apply(&self, omega: Vector3<f64>, v: Vector3<f64>) -> Isometry3<f64> {
        let c = self.centroid.coords;
        Translation3::from(c + v) * Isometry3::rotation(omega) * Translation3::from(-c)
    }
}

/// λ_min / λ_max and the eigenvectors below the threshold, weakest first.
fn conditioning(
    eigen: &SymmetricEigen<f64, nalgebra::U6>,
    min_condition: f64,
) -> (f64, Vec<[f64; 6]>) {
    let lambda_max = eigen.eigenvalues.max();
    let lambda_min = eigen.eigenvalues.min().max(0.0);
    let condition = if lambda_max > 0.0 {
        lambda_min / lambda_max
    } else {
        0.0
    };
    let mut order: Vec<usize> = (0..6).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let weak = order
        .into_iter()
        .filter(|&k| eigen.eigenvalues[k] <= min_condition * lambda_max)
        .map(|k| {
            let u = eigen.eigenvectors.column(k);
            [u[0], u[1], u[2], u[3], u[4], u[5]]
        })
        .collect();
    (condition, weak)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::pose::pose_from_mm_deg;
    use crate::localise::fixtures::{curved_pane, flat_pane};
    use crate::localise::metrics::pose_error;
    use crate::sampler::PoseSampler;

    fn truth() -> Pose {
        pose_from_mm_deg([450.0, -120.0, 2.0], [0.5, -0.3, 30.0])
    }

    /// The nominal pose: the truth perturbed by 5 mm and 2° (mostly about the pane's normal).
    fn nominal() -> Pose {
        truth() * pose_from_mm_deg([3.0, -4.0, 0.0], [0.3, -0.2, 2.0])
    }

    /// `n` border points spread evenly along the border from arc length `s0` over `span` (a
    /// fraction of the perimeter), in B.
    fn bips(border: &BorderCurve, n: usize, s0: f64, span: f64) -> Vec<Point3<f64>> {
        let len = border.length();
        (0..n)
            .map(|k| {
                truth()
                    * border
                        .at_arc_length(s0 + span * len * k as f64 / n as f64)
                        .position
            })
            .collect()
    }

    /// Deterministic Gaussian noise, σ in m (Box–Muller on the project's counter-based sampler).
    fn gaussian(sampler: &PoseSampler, i: u64, dim: u32, sigma: f64) -> f64 {
        let (u1, u2) = (sampler.uniform(i, 2 * dim), sampler.uniform(i, 2 * dim + 1));
        sigma * (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    #[test]
    fn exact_points_recover_a_known_transform() {
        for model in [flat_pane(), curved_pane()] {
            let pts = bips(&model, 12, 0.013, 1.0);
            let reg = register(&model, &pts, &nominal(), &IcpSettings::robust()).unwrap();
            let (dt, dr) = pose_error(&reg.pose, &truth());
            println!(
                "exact: {dt:.2e} mm, {dr:.2e}°, {} it, cond {:.3e}",
                reg.iterations, reg.condition
            );
            assert!(reg.converged && !reg.degenerate);
            assert!(dt < 1e-3 && dr < 1e-3, "{dt} mm {dr}°");
            assert!(reg.iterations <= 10, "{} iterations", reg.iterations);
            assert!(reg.inliers.iter().all(|&b| b));
        }
    }

    #[test]
    fn a_grid_built_once_gives_the_same_registration_bit_for_bit() {
        // One grid, several registrations (noisy points, one outlier, both kernels): each
        // equals what `register` returns with its own grid.
        let model = curved_pane();
        let grid = SegmentGrid::new(&model);
        for seed in 0..4 {
            let s = PoseSampler::new(seed, 1);
            let mut pts = bips(&model, 12, 0.05, 1.0);
            for (i, p) in pts.iter_mut().enumerate() {
                *p += Vector3::new(
                    gaussian(&s, i as u64, 0, 2e-4),
                    gaussian(&s, i as u64, 1, 2e-4),
                    gaussian(&s, i as u64, 2, 2e-4),
                );
            }
            pts[seed as usize].x += 0.01;
            for settings in [IcpSettings::robust(), IcpSettings::least_squares()] {
                let own = register(&model, &pts, &nominal(), &settings).unwrap();
                let shared = register_on_grid(&model, &grid, &pts, &nominal(), &settings).unwrap();
                assert_eq!(own, shared);
            }
        }
    }

    #[test]
    fn the_cholesky_step_is_the_truncated_eigen_step_where_nothing_is_truncated() {
        // Systems along real registrations (noisy points with an outlier, both kernels' stages;
        // points on one or two straight sides, where directions must be dropped): where the
        // Cholesky path is taken its step equals the eigen-solve's to rounding; where the
        // eigen-solve drops a direction, the Cholesky path declines.
        let settings = IcpSettings::robust();
        let model = flat_pane();
        let grid = SegmentGrid::new(&model);
        let len = model.length();
        let one_side = bips(&model, 4, 0.02 / len, 0.2 / len);
        let mut two_sides = bips(&model, 2, 0.02 / len, 0.2 / len);
        two_sides.extend(bips(&model, 2, 0.51 / len, 0.2 / len));
        let mut noisy = bips(&model, 12, 0.013, 1.0);
        let s = PoseSampler::new(7, 1);
        for (i, p) in noisy.iter_mut().enumerate() {
            *p += Vector3::new(
                gaussian(&s, i as u64, 0, 2e-4),
                gaussian(&s, i as u64, 1, 2e-4),
                gaussian(&s, i as u64, 2, 2e-4),
            );
        }
        noisy[3].y += 0.01;
        let (mut cholesky, mut declined) = (0, 0);
        for (pts, well_posed) in [(&noisy, true), (&one_side, false), (&two_sides, false)] {
            let mut t_mb = nominal().inverse();
            let mut work = Workspace::with_capacity(pts.len());
            for iteration in 0..12 {
                let tukey = iteration >= 6;
                let system = build_system(&model, &grid, pts, &t_mb, &settings, tukey, &mut work);
                let (omega, v) = system.solve_truncated(settings.min_condition);
                match system.untruncated_step(settings.min_condition) {
                    Some((omega_c, v_c)) => {
                        cholesky += 1;
                        let size = omega.norm() * system.scale + v.norm();
                        let diff = (omega_c - omega).norm() * system.scale + (v_c - v).norm();
                        assert!(diff <= 1e-9 * size + 1e-18, "{diff:e} of {size:e}");
                    }
                    None => declined += 1,
                }
                let truncates = {
                    let e = system.eigen();
                    let max = e.eigenvalues.max();
                    e.eigenvalues
                        .iter()
                        .any(|&l| l <= settings.min_condition * max)
                };
                assert_eq!(truncates, !well_posed);
                if truncates {
                    assert!(system.untruncated_step(settings.min_condition).is_none());
                }
                t_mb = system.apply(omega, v) * t_mb;
            }
        }
        assert_eq!((cholesky, declined), (12, 24));
    }

    #[test]
    fn noisy_points_give_an_error_consistent_with_the_noise() {
        let model = flat_pane();
        let mut worst: f64 = 0.0;
        for seed in 0..5 {
            let s = PoseSampler::new(seed, 0);
            let pts: Vec<_> = (bips(&model, 12, 0.013, 1.0).iter().enumerate())
                .map(|(i, p)| {
                    let i = i as u64;
                    p + Vector3::new(
                        gaussian(&s, i, 0, 1e-4),
                        gaussian(&s, i, 1, 1e-4),
                        gaussian(&s, i, 2, 1e-4),
                    )
                })
                .collect();
            let reg = register(&model, &pts, &nominal(), &IcpSettings::robust()).unwrap();
            let (dt, dr) = pose_error(&reg.pose, &truth());
            println!(
                "noisy seed {seed}: {dt:.3} mm, {dr:.4}°, rms {:.3} mm, {} it",
                reg.rms_mm, reg.iterations
            );
            assert!(reg.converged && !reg.degenerate);
            assert!(reg.inliers.iter().all(|&b| b));
            worst = worst.max(dt);
        }
        assert!(worst < 0.15, "worst {worst} mm");
    }

    #[test]
    fn one_gross_outlier_is_rejected() {
        let model = flat_pane();
        let mut pts = bips(&model, 12, 0.013, 1.0);
        // BIP 5 is 10 mm off the border, outwards and up.
        let v = model.at_arc_length(0.013 * model.length() + 5.0 * model.length() / 12.0);
        pts[5] += truth().rotation * (v.outward + v.surface_normal).normalize() * 0.010;
        let robust = register(&model, &pts, &nominal(), &IcpSettings::robust()).unwrap();
        let (dt, dr) = pose_error(&robust.pose, &truth());
        let plain = register(&model, &pts, &nominal(), &IcpSettings::least_squares()).unwrap();
        let (dt_ls, _) = pose_error(&plain.pose, &truth());
        println!(
            "outlier: robust {dt:.2e} mm {dr:.2e}° ({} it), least squares {dt_ls:.3} mm",
            robust.iterations
        );
        assert!(dt < 0.1 && dr < 0.01, "{dt} mm {dr}°");
        assert!(!robust.inliers[5]);
        assert_eq!(robust.inliers.iter().filter(|&&b| b).count(), 11);
        assert!(robust.converged && robust.rms_mm < 1e-3);
    }

    #[test]
    fn points_on_one_straight_side_are_degenerate() {
        let model = flat_pane();
        // The bottom side runs along +x in M from x = −130 to 130 mm at y = −100 mm; the
        // vertices start at its left end.
        let len = model.length();
        let pts = bips(&model, 4, 0.02 / len, 0.2 / len);
        let reg = register(&model, &pts, &nominal(), &IcpSettings::robust()).unwrap();
        println!(
            "one side: cond {:.2e}, {} weak",
            reg.condition,
            reg.weak_directions.len()
        );
        assert!(reg.degenerate && reg.weakest_direction.is_some());
        // Translation along the side (x in M) lies in the weak subspace.
        let along = Vector6::new(0.0, 0.0, 0.0, 1.0, 0.0, 0.0);
        let in_weak: f64 = (reg.weak_directions.iter())
            .map(|w| Vector6::from(*w).dot(&along).powi(2))
            .sum();
        assert!((in_weak - 1.0).abs() < 1e-6, "{in_weak}");

        // Two points on each long side: only the slide along x is free, and it is the weakest.
        let mut pts = bips(&model, 2, 0.02 / len, 0.2 / len);
        pts.extend(bips(
            &model,
            2,
            (0.02 + 0.26 + 0.16 + 2.0 * 0.01 * std::f64::consts::PI) / len,
            0.2 / len,
        ));
        let reg = register(&model, &pts, &nominal(), &IcpSettings::robust()).unwrap();
        let w = reg.weakest_direction.expect("degenerate");
        println!("two sides: cond {:.2e}, weakest {w:?}", reg.condition);
        assert!(reg.degenerate && reg.weak_directions.len() == 1);
        assert!(w[3].abs() > 0.999, "{w:?}");
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let model = flat_pane();
        let pts = bips(&model, 12, 0.0, 1.0);
        let s = IcpSettings::robust();
        assert_eq!(
            register(&model, &pts[..2], &nominal(), &s),
            Err(IcpError::TooFewPoints(2))
        );
        assert_eq!(
            register(&model, &[], &nominal(), &s),
            Err(IcpError::TooFewPoints(0))
        );
        let mut bad = pts.clone();
        bad[4].y = f64::NAN;
        assert_eq!(
            register(&model, &bad, &nominal(), &s),
            Err(IcpError::NonFinitePoint(4))
        );
        bad[4].y = f64::INFINITY;
        assert_eq!(
            register(&model, &bad, &nominal(), &s),
            Err(IcpError::NonFinitePoint(4))
        );
        let empty = BorderCurve::default();
        let err = register(&empty, &pts, &nominal(), &s).unwrap_err();
        assert!(matches!(err, IcpError::BadModel(_)));
        assert!(err.to_string().contains("0 vertices"), "{err}");
        let mut pose = nominal();
        pose.translation.vector.x = f64::NAN;
        assert_eq!(
            register(&model, &pts, &pose, &s),
            Err(IcpError::NonFinitePose)
        );
    }
}
