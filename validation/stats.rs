//! Statistical tests shared by the validation checks: Pearson's χ² goodness of fit of a
//! direction-sampling routine against its density, and the z-test of a Monte Carlo mean.
//!
//! The χ² test follows pbrt-v4 `bsdfs_test.cpp` and Mitsuba 3 `chi2.py`: a histogram of ~10⁶
//! sampled directions over a θ×φ grid, the expected count of each cell from the density
//! integrated over the cell (adaptive Simpson), cells with expected count < 5 pooled, and the
//! p-value of Pearson's statistic from the χ² distribution, Q(k/2, χ²/2) with Q the
//! regularised upper incomplete gamma function (Numerical Recipes, 3rd ed., §6.2). Tests
//! reject at significance 0.01 after Šidák's correction for the number of tests in a family.
//! Random numbers come from the crate's keyed sampler, so every run sees the same samples.

use std::f64::consts::PI;

use glassscan::sampler::PoseSampler;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Family-wise significance of the tests (probability of a false alarm in one family).
pub const SIGNIFICANCE: f64 = 0.01;

/// Per-test significance that keeps the family-wise rate at `alpha` over `tests` independent
/// tests (Šidák, JASA 62, 1967): 1 − (1 − α)^(1/m).
pub fn sidak(alpha: f64, tests: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / tests as f64)
}

/// A grid of directions: θ ∈ [theta_min, theta_max] (from +z) in `n_theta` equal steps times
/// φ ∈ [0, 2π) in `n_phi` equal steps.
#[derive(Clone, Copy, Debug)]
pub struct SphereGrid {
    /// Lower polar angle (rad).
    pub theta_min: f64,
    /// Upper polar angle (rad).
    pub theta_max: f64,
    /// Number of θ rows.
    pub n_theta: usize,
    /// Number of φ columns.
    pub n_phi: usize,
}

impl SphereGrid {
    /// The whole sphere.
    pub fn sphere(n_theta: usize, n_phi: usize) -> Self {
        SphereGrid {
            theta_min: 0.0,
            theta_max: PI,
            n_theta,
            n_phi,
        }
    }

    /// The upper hemisphere z ≥ 0.
    pub fn upper_hemisphere(n_theta: usize, n_phi: usize) -> Self {
        SphereGrid {
            theta_max: 0.5 * PI,
            ..Self::sphere(n_theta, n_phi)
        }
    }

    /// Cell index of a direction, or `None` outside the θ band.
    fn cell(&self, w: &Vector3<f64>) -> Option<usize> {
        let theta = (w.z / w.norm()).clamp(-1.0, 1.0).acos();
        let t = (theta - self.theta_min) / (self.theta_max - self.theta_min);
        if !(0.0..=1.0).contains(&t) {
            return None;
        }
        let mut phi = w.y.atan2(w.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let i = ((t * self.n_theta as f64) as usize).min(self.n_theta - 1);
        let j = ((phi / (2.0 * PI) * self.n_phi as f64) as usize).min(self.n_phi - 1);
        Some(i * self.n_phi + j)
    }
}

/// What a χ² test measured.
#[derive(Clone, Debug)]
pub struct Chi2Outcome {
    /// Pearson's statistic Σ (O − E)²/E over the pooled cells.
    pub chi2: f64,
    /// Degrees of freedom: pooled cells − 1.
    pub dof: usize,
    /// Probability of a statistic at least this large if the samples follow the density.
    pub p_value: f64,
    /// Samples that returned `None` or fell outside the grid.
    pub elsewhere: u64,
    /// The density integrated over the grid (1 for a normalised density on it).
    pub integral: f64,
    /// A cell where the integrated density is zero received samples.
    pub impossible_cells: usize,
}

impl Chi2Outcome {
    /// True if the samples are consistent with the density at per-test significance `alpha`.
    pub fn passes(&self, alpha: f64) -> bool {
        self.impossible_cells == 0 && self.p_value >= alpha
    }
}

/// Tests `sample` against `pdf` (1/sr) with `samples` draws, sample `i` receiving the three
/// uniforms `PoseSampler::new(seed, stream).uniform(i, 0..3)`. Draws that return `None`, or
/// fall outside the grid, form one more category whose expected count is N·(1 − ∫_grid pdf),
/// so the density must integrate to the probability of a sample landing on the grid.
pub fn chi2_directions(
    grid: &SphereGrid,
    samples: u64,
    seed: u64,
    stream: u64,
    sample: impl Fn([f64; 3]) -> Option<Vector3<f64>> + Sync,
    pdf: impl Fn(&Vector3<f64>) -> f64 + Sync,
) -> Chi2Outcome {
    let cells = grid.n_theta * grid.n_phi;
    let rng = PoseSampler::new(seed, stream);
    // Integer counts, so the reduction order (and thus the thread count) cannot matter.
    let chunk = 1 << 14;
    let observed: Vec<u64> = (0..samples.div_ceil(chunk))
        .into_par_iter()
        .map(|c| {
            let mut h = vec![0u64; cells + 1];
            for i in c * chunk..((c + 1) * chunk).min(samples) {
                let u = [rng.uniform(i, 0), rng.uniform(i, 1), rng.uniform(i, 2)];
                let k = sample(u).and_then(|w| grid.cell(&w)).unwrap_or(cells);
                h[k] += 1;
            }
            h
        })
        .reduce(
            || vec![0u64; cells + 1],
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(x, y)| *x += y);
                a
            },
        );
    let probabilities = integrate_cells(grid, &pdf);
    let integral: f64 = probabilities.iter().sum();
    let n = samples as f64;
    let mut pairs: Vec<(f64, u64)> = probabilities
        .iter()
        .map(|p| p * n)
        .zip(observed.iter().copied())
        .collect();
    pairs.push(((1.0 - integral).max(0.0) * n, observed[cells]));
    let impossible_cells = pairs.iter().filter(|&&(e, o)| e == 0.0 && o > 0).count();
    let (chi2, dof) = pearson_pooled(pairs);
    Chi2Outcome {
        chi2,
        dof,
        p_value: chi2_p_value(chi2, dof),
        elsewhere: observed[cells],
        integral,
        impossible_cells,
    }
}

/// Pearson's statistic after pooling the cells of smallest expected count until every cell
/// expects at least 5 (Cochran's rule, as in pbrt-v4 and Mitsuba 3); returns (χ², dof).
fn pearson_pooled(mut pairs: Vec<(f64, u64)>) -> (f64, usize) {
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut pool: Option<(f64, u64)> = None;
    let mut kept = Vec::with_capacity(pairs.len());
    for (e, o) in pairs {
        match pool {
            Some((pe, po)) if pe < 5.0 => pool = Some((pe + e, po + o)),
            None if e < 5.0 => pool = Some((e, o)),
            _ => kept.push((e, o)),
        }
    }
    kept.extend(pool);
    let chi2 = kept
        .iter()
        .filter(|(e, _)| *e > 0.0)
        .map(|&(e, o)| (o as f64 - e).powi(2) / e)
        .sum();
    (chi2, kept.len().saturating_sub(1))
}

/// ∫ pdf dω over every cell of the grid (row-major), by adaptive Simpson in φ of adaptive
/// Simpson in θ of pdf·sin θ.
pub fn integrate_cells(
    grid: &SphereGrid,
    pdf: &(impl Fn(&Vector3<f64>) -> f64 + Sync),
) -> Vec<f64> {
    let dt = (grid.theta_max - grid.theta_min) / grid.n_theta as f64;
    let dp = 2.0 * PI / grid.n_phi as f64;
    // An absolute error well below one count in 10⁶ samples per cell.
    let eps = 1e-10;
    (0..grid.n_theta * grid.n_phi)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k / grid.n_phi, k % grid.n_phi);
            let (t0, p0) = (grid.theta_min + i as f64 * dt, j as f64 * dp);
            let row = |phi: f64| {
                let (sp, cp) = phi.sin_cos();
                let f = |theta: f64| {
                    let (st, ct) = theta.sin_cos();
                    pdf(&Vector3::new(st * cp, st * sp, ct)) * st
                };
                adaptive_simpson(&f, t0, t0 + dt, eps / dp, 12)
            };
            adaptive_simpson(&row, p0, p0 + dp, eps, 12)
        })
        .collect()
}

/// ∫_a^b f by adaptive Simpson quadrature with absolute tolerance `eps` and at most `depth`
/// bisections (Lyness, "Notes on the adaptive Simpson quadrature routine", JACM 16, 1969).
pub fn adaptive_simpson(f: &impl Fn(f64) -> f64, a: f64, b: f64, eps: f64, depth: u32) -> f64 {
    let (fa, fm, fb) = (f(a), f(0.5 * (a + b)), f(b));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    simpson_step(f, [a, b], [fa, fm, fb], whole, eps, depth)
}

fn simpson_step(
    f: &impl Fn(f64) -> f64,
    [a, b]: [f64; 2],
    [fa, fm, fb]: [f64; 3],
    whole: f64,
    eps: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let (fl, fr) = (f(0.5 * (a + m)), f(0.5 * (m + b)));
    let left = (m - a) / 6.0 * (fa + 4.0 * fl + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * fr + fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * eps {
        left + right + delta / 15.0
    } else {
        simpson_step(f, [a, m], [fa, fl, fm], left, 0.5 * eps, depth - 1)
            + simpson_step(f, [m, b], [fm, fr, fb], right, 0.5 * eps, depth - 1)
    }
}

/// P(X ≥ chi2) for X ~ χ² with `dof` degrees of freedom.
pub fn chi2_p_value(chi2: f64, dof: usize) -> f64 {
    if dof == 0 {
        return 1.0;
    }
    gamma_q(0.5 * dof as f64, 0.5 * chi2)
}

/// Two-sided p-value of an estimate against its expected value, with a normal sampling
/// distribution of standard error `std_error`: erfc(|z|/√2), z = (estimate − expected)/σ.
pub fn z_test(estimate: f64, std_error: f64, expected: f64) -> f64 {
    let z = (estimate - expected) / std_error;
    gamma_q(0.5, 0.5 * z * z)
}

/// Mean and standard error of the mean of `values`.
pub fn mean_and_error(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut n, mut s, mut s2) = (0.0, 0.0, 0.0);
    for v in values {
        n += 1.0;
        s += v;
        s2 += v * v;
    }
    let mean = s / n;
    let var = (s2 / n - mean * mean).max(0.0) * n / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// ln Γ(x) for x > 0 (Lanczos approximation, g = 7, n = 9; relative error ~10⁻¹⁵).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x)Γ(1 − x) = π/sin(πx).
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let sum = C[0]
        + C[1..]
            .iter()
            .enumerate()
            .map(|(k, c)| c / (x + k as f64 + 1.0))
            .sum::<f64>();
    let t = x + 7.5;
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// Regularised upper incomplete gamma function Q(a, x) = Γ(a, x)/Γ(a): the power series of
/// P = 1 − Q for x < a + 1, Lentz's continued fraction for Q otherwise (Numerical Recipes
/// §6.2).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    assert!(a > 0.0 && x >= 0.0);
    if x == 0.0 {
        return 1.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * prefactor).max(0.0)
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let step = d * c;
            h *= step;
            if (step - 1.0).abs() < 1e-16 {
                break;
            }
        }
        prefactor * h
    }
}

#[test]
fn incomplete_gamma_matches_closed_forms_and_tables() {
    // Q(1, x) = e^(−x); Q(½, x²) = erfc(x), erfc(1) = 0.157 299 207 050 285 (Abramowitz &
    // Stegun, table 7.1); the 1 % point of χ² with 10 dof is 23.209 (A&S table 26.8).
    for x in [0.1f64, 1.0, 3.0, 20.0] {
        assert!((gamma_q(1.0, x) / (-x).exp() - 1.0).abs() < 1e-13, "{x}");
    }
    assert!((gamma_q(0.5, 1.0) - 0.157_299_207_050_285).abs() < 1e-14);
    assert!((chi2_p_value(23.209_251, 10) - 0.01).abs() < 1e-7);
    assert!((chi2_p_value(2.0 * 3.0, 2) - (-3.0f64).exp()).abs() < 1e-14);
    assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-14);
    assert!((ln_gamma(10.0) - 362_880f64.ln()).abs() < 1e-12);
    assert!((z_test(1.0 + 1.959_964, 1.0, 1.0) - 0.05).abs() < 1e-6);
}

#[test]
fn chi2_accepts_the_uniform_sphere_and_rejects_a_wrong_density() {
    // Uniform directions (Archimedes: z uniform in [−1, 1]) against 1/(4π), and against the
    // cosine-weighted density, which must fail.
    let uniform = |u: [f64; 3]| {
        let z = 1.0 - 2.0 * u[0];
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        Some(Vector3::new(r * phi.cos(), r * phi.sin(), z))
    };
    let grid = SphereGrid::sphere(20, 40);
    let good = chi2_directions(&grid, 200_000, 1, 0, uniform, |_| 0.25 / PI);
    eprintln!("χ² uniform sphere: {good:?}");
    assert!(good.passes(sidak(SIGNIFICANCE, 2)) && (good.integral - 1.0).abs() < 1e-9);
    let bad = chi2_directions(&grid, 200_000, 1, 0, uniform, |w| w.z.abs() / (2.0 * PI));
    assert!(!bad.passes(sidak(SIGNIFICANCE, 2)), "{bad:?}");
    let (m, e) = mean_and_error((0..1000).map(|i| i as f64));
    assert!((m - 499.5).abs() < 1e-12 && (e - 9.133_273).abs() < 1e-5);
}
