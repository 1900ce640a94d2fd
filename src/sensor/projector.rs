//! The laser sheet: a fan of light from a virtual source at the origin of S, spread in the
//! x–z plane, focused across the sheet (along y) to a Gaussian waist.
//!
//! Thickness follows the Gaussian-beam law w(s) = w0·√(1 + ((s − s0)/zR)²), zR = π·w0²/(M²·λ)
//! (Schäfter+Kirchhoff Rayleigh-range note, docs/parameters.md §4), with s the path length along
//! the fan ray and w the 1/e² intensity radius.

/// Intensity distribution along the laser line.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LineProfile {
    /// Uniform in the tangent of the fan angle, i.e. uniform along x on a plane z = const
    /// (an ideal Powell lens).
    Uniform,
    /// Gaussian in fan angle with the given 1/e² half-angle (rad) (cylinder-lens line),
    /// clipped to the fan.
    Gaussian {
        /// 1/e² half-angle of the Gaussian (rad).
        half_angle_1e2_rad: f64,
    },
}

/// Polarisation state of the laser light.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Polarization {
    /// Linearly polarised, the electric field along the direction at `angle_rad` from the
    /// sensor's x axis (along the line) towards its y axis, projected across each fan ray.
    Linear {
        /// Angle of the polarisation axis from x towards y (rad).
        angle_rad: f64,
    },
    /// Unpolarised light.
    Unpolarized,
}

/// Parameters of the laser sheet.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LaserSheet {
    /// Vacuum wavelength (m); 658 nm for the scanCONTROL 2600 (paper, Section V).
    pub wavelength_m: f64,
    /// Optical power leaving the projector (W).
    pub power_w: f64,
    /// Full fan angle in the x–z plane (rad), in (0, π).
    pub fan_angle_rad: f64,
    /// 1/e² intensity radius of the waist across the sheet (m), > 0.
    pub waist_radius_m: f64,
    /// Path length from the virtual source to the waist (m), ≥ 0.
    pub waist_distance_m: f64,
    /// Beam quality factor M² ≥ 1.
    pub m_squared: f64,
    /// Intensity distribution along the line.
    pub line_profile: LineProfile,
    /// Polarisation of the emitted light.
    pub polarization: Polarization,
}

use nalgebra::{Point3, Vector3};

use crate::optics::warp::{normal_cdf, normal_quantile};

/// How much wider than the beam's own Gaussian the transverse waist offsets are sampled (see
/// [`LaserSheet::sample_ray`]): rays in the beam's tails are drawn 1.5× to 13× more often (at 2σ
/// to 4σ) and carry proportionally less flux, those at the centre 1.5× less often with 1.5× the
/// flux. Chosen by measurement (issue 11): on `edge_study_bare` at 2¹⁶ photons the median
/// column error of z against a 2²² reference fell from 16 to 7 µm (saturated line) and from 6.6
/// to 5.4 µm (0.05 ms, unsaturated); a spread of 2 measured the same within noise.
pub const WAIST_SAMPLING_SPREAD: f64 = 1.5;

/// A laser ray in the sensor frame, with the uniforms it came from resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaserRay {
    /// Origin on the plane z = 0 of S (m).
    pub origin: Point3<f64>,
    /// Unit direction.
    pub direction: Vector3<f64>,
    /// Fan angle φ of the ray in the x–z plane (rad).
    pub fan_angle: f64,
    /// Importance weight p/q of the ray: the beam's density over the sampling density (mean 1
    /// over the sampling density). A photon on this ray carries this many times its share of
    /// the laser's power.
    pub weight: f64,
}

impl LaserSheet {
    /// Rayleigh range zR = π·w0²/(M²·λ) (m).
    pub fn rayleigh_range_m(&self) -> f64 {
        std::f64::consts::PI * self.waist_radius_m.powi(2) / (self.m_squared * self.wavelength_m)
    }

    /// 1/e² half-width of the sheet at path length `s` from the source (m): the Gaussian-beam law.
    pub fn radius_at(&self, s: f64) -> f64 {
        let zr = self.rayleigh_range_m();
        self.waist_radius_m * (1.0 + ((s - self.waist_distance_m) / zr).powi(2)).sqrt()
    }

    /// Far-field 1/e² half-angle divergence θ0 = M²·λ/(π·w0) (rad).
    pub fn divergence_rad(&self) -> f64 {
        self.m_squared * self.wavelength_m / (std::f64::consts::PI * self.waist_radius_m)
    }

    /// Fan angle φ for a uniform number `u` in [0, 1): the inverse CDF of the line profile.
    pub fn fan_angle(&self, u: f64) -> f64 {
        self.ray_sampler().fan_angle(u)
    }

    /// The fraction of the laser's power between the fan's edge at −half the fan angle and the
    /// fan angle `phi` (rad): the CDF of the line profile, inverse of [`LaserSheet::fan_angle`],
    /// clamped to [0, 1] outside the fan.
    pub fn fan_fraction(&self, phi: f64) -> f64 {
        let half = 0.5 * self.fan_angle_rad;
        let u = match self.line_profile {
            LineProfile::Uniform => 0.5 * (phi.tan() / half.tan() + 1.0),
            LineProfile::Gaussian { half_angle_1e2_rad } => {
                let (sigma, lo, hi) = truncated_normal(half_angle_1e2_rad, half);
                (normal_cdf(phi / sigma) - lo) / (hi - lo)
            }
        };
        u.clamp(0.0, 1.0)
    }

    /// Samples one laser ray from four uniforms: `u[0]` → fan angle, `u[1]` → the transverse
    /// position at the waist, `u[2]` → the transverse angle (each by the inverse normal CDF, so
    /// well-spread uniforms give well-spread offsets), `u[3]` unused (kept so the dimension
    /// layout is stable).
    ///
    /// The Gaussian beam is represented by rays whose waist offset y_w ~ N(0, (w0/2)²) and slope
    /// tan ψ ~ N(0, (θ0/2)²) are independent: the Wigner function of a Gaussian beam is Gaussian,
    /// so the second moment of this ray bundle follows w(s)² = w0² + θ0²·(s − s0)² exactly.
    ///
    /// The waist offset is importance-sampled from the wider N(0, (k·w0/2)²),
    /// k = [`WAIST_SAMPLING_SPREAD`], and the ray carries the weight
    /// p/q = k·exp(−n²·(1 − 1/k²)/2) for its normalised offset n: unbiased for every estimate
    /// (E_q[f·p/q] = E_p[f]). Why: a line above the sensor's full scale is located by its flanks,
    /// the beam's 2–3σ tails, which the beam's own density reaches with a few photons per column.
    pub fn sample_ray(&self, u: [f64; 4]) -> LaserRay {
        self.ray_sampler().sample_ray(u)
    }

    /// [`LaserSheet::sample_ray`] with what every ray shares computed once: what a rendering
    /// uses for its photons.
    pub fn ray_sampler(&self) -> LaserRaySampler {
        LaserRaySampler {
            sheet: *self,
            tan_half_fan: (0.5 * self.fan_angle_rad).tan(),
            divergence_rad: self.divergence_rad(),
        }
    }
}

/// Draws the rays of one laser sheet ([`LaserSheet::ray_sampler`]): the same rays as
/// [`LaserSheet::sample_ray`], bit for bit, without the tangent of the half fan angle and the
/// divergence recomputed per ray (a tangent per photon was 1 % of a glass profile's time).
#[derive(Clone, Copy, Debug)]
pub struct LaserRaySampler {
    sheet: LaserSheet,
    tan_half_fan: f64,
    divergence_rad: f64,
}

impl LaserRaySampler {
    /// [`LaserSheet::fan_angle`].
    fn fan_angle(&self, u: f64) -> f64 {
        match self.sheet.line_profile {
            LineProfile::Uniform => ((2.0 * u - 1.0) * self.tan_half_fan).atan(),
            LineProfile::Gaussian { half_angle_1e2_rad } => {
                let half = 0.5 * self.sheet.fan_angle_rad;
                let (sigma, lo, hi) = truncated_normal(half_angle_1e2_rad, half);
                sigma * normal_quantile(lo + u * (hi - lo))
            }
        }
    }

    /// [`LaserSheet::sample_ray`].
    pub fn sample_ray(&self, u: [f64; 4]) -> LaserRay {
        let fan_angle = self.fan_angle(u[0]);
        let k = WAIST_SAMPLING_SPREAD;
        let n1 = k * normal_quantile(u[1]);
        let n2 = normal_quantile(u[2]);
        let weight = k * (-0.5 * n1 * n1 * (1.0 - 1.0 / (k * k))).exp();
        let y_waist = 0.5 * self.sheet.waist_radius_m * n1;
        let slope = 0.5 * self.divergence_rad * n2;
        let d0 = Vector3::new(fan_angle.sin(), 0.0, fan_angle.cos());
        let direction = (d0 + Vector3::y() * slope).normalize();
        let origin = Point3::new(0.0, y_waist - self.sheet.waist_distance_m * slope, 0.0);
        LaserRay {
            origin,
            direction,
            fan_angle,
            weight,
        }
    }
}

/// A Gaussian line of 1/e² half-angle `half_angle_1e2_rad` (intensity ∝ exp(−2φ²/h²): a
/// normal law with σ = h/2) truncated to the fan's ±`half`: σ and the normal CDF at −half and
/// +half.
fn truncated_normal(half_angle_1e2_rad: f64, half: f64) -> (f64, f64, f64) {
    let sigma = 0.5 * half_angle_1e2_rad;
    (sigma, normal_cdf(-half / sigma), normal_cdf(half / sigma))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::preset::scancontrol_2600_100;

    #[test]
    fn ray_bundle_thickness_follows_the_gaussian_beam_law() {
        let laser = scancontrol_2600_100().laser;
        let n = 200_000;
        for s in [0.125, 0.2575, 0.39] {
            let (mut sum2, mut weights) = (0.0, 0.0);
            for i in 0..n {
                // A deterministic, well spread set of uniforms (Kronecker sequence).
                let u1 = (0.5 + i as f64 * 0.754_877_666_246_692_7).fract();
                let u2 = (0.5 + i as f64 * 0.569_840_290_998_053_3).fract();
                let r = laser.sample_ray([0.5, u1, u2, 0.0]);
                let y = r.origin.y + r.direction.y / r.direction.z * s;
                // The importance weights make the sampled bundle the beam's.
                sum2 += r.weight * y * y;
                weights += r.weight;
            }
            // E_q[p/q] = 1: the weights keep the laser's power.
            assert!((weights / n as f64 - 1.0).abs() < 1e-3, "{weights}");
            let w = 2.0 * (sum2 / n as f64).sqrt();
            let expected = laser.radius_at(s);
            assert!(
                (w / expected - 1.0).abs() < 0.01,
                "s = {s}: w = {w}, expected {expected}"
            );
        }
        // docs/parameters.md §4: w(125 mm) = w(390 mm) = 471/2 µm for a 333 µm waist at 257.5 mm.
        let mut l = laser;
        l.waist_radius_m = 0.1665e-3;
        assert!((l.radius_at(0.125) * 2e6 - 471.0).abs() < 1.5);
    }

    #[test]
    fn waist_offsets_are_sampled_wider_and_weighted_back_to_the_beam() {
        // The sampled offsets have the spread k·w0/2; weighted, every moment is the beam's: the
        // fraction of power beyond 2σ (erfc(√2) = 4.55 %) and the fourth moment 3σ⁴ (Gaussian).
        let laser = scancontrol_2600_100().laser;
        let sigma = 0.5 * laser.waist_radius_m;
        let n = 400_000;
        let (mut sampled2, mut tail, mut m4) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let u1 = (i as f64 + 0.5) / n as f64;
            let r = laser.sample_ray([0.5, u1, 0.5, 0.0]);
            // Slope 0 (u2 = 0.5): the origin holds the waist offset.
            let y = r.origin.y / sigma;
            sampled2 += y * y;
            if y.abs() > 2.0 {
                tail += r.weight;
            }
            m4 += r.weight * y.powi(4);
        }
        let k = WAIST_SAMPLING_SPREAD;
        assert!(((sampled2 / n as f64).sqrt() / k - 1.0).abs() < 1e-3);
        assert!(
            (tail / n as f64 - 0.045_500_26).abs() < 1e-4,
            "{}",
            tail / n as f64
        );
        assert!(
            (m4 / n as f64 / 3.0 - 1.0).abs() < 1e-3,
            "{}",
            m4 / n as f64
        );
    }

    #[test]
    fn uniform_line_is_uniform_along_x() {
        let laser = scancontrol_2600_100().laser;
        let half = 0.5 * laser.fan_angle_rad;
        // Uniform in tan φ: equal steps in u give equal steps in x = z·tan φ.
        let x = |u: f64| laser.fan_angle(u).tan();
        assert!((x(0.0) + half.tan()).abs() < 1e-12 && (x(1.0) - half.tan()).abs() < 1e-12);
        assert!(((x(0.75) - x(0.5)) - (x(0.5) - x(0.25))).abs() < 1e-12);
    }
}
