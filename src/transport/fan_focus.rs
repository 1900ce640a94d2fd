//! Photons of the laser fan drawn more densely near the border point p_e (importance sampling
//! of the fan angle; unbiased).
//!
//! What a pose is simulated for is decided in a few millimetres of the laser line around the
//! glass edge: the edge finish's returns, the arrisses, the faint face returns next to them and
//! the table seen through the pane's rim are what a BIP rule climbs through. Drawn with the
//! line's own intensity profile, a few per cent of a pose's photons land there (the line is
//! ~100–140 mm long; the edge region ±[`FOCUS_HALF_WIDTH_M`]). A share [`FOCUS_SHARE`] of the
//! photons is instead drawn uniformly (in the line profile's own measure) inside that window,
//! the rest from the line profile over the whole fan, and each photon carries the weight p/q
//! of the line's density over the mixture's. Every estimate keeps its mean (E_q[f·p/q] =
//! E_p[f]); the edge region gets about `1 − s + s/f` times its photons (f: its share of the
//! line's power, s the focus share), the rest of the line `1 − s` times, so its Monte Carlo
//! error grows by 1/√(1 − s). The mixture is a defensive one (Hesterberg 1995, Technometrics
//! 37(2)): no photon carries more than 1/(1 − s) times its share of the laser's power, so
//! columns away from the edge get no fireflies.
//!
//! The warp acts on the fan's uniform number after the photon set's stratification, so the
//! photons stay stratified over the mixture, and it is a fixed function of the pose: the same
//! seed gives the same photons for any thread count.

use nalgebra::Point3;

use crate::sensor::projector::LaserSheet;

/// Half-width (m), along the laser line at p_e's range, of the window the focused photons are
/// drawn in. Chosen by the convergence test (validation/results/convergence/, 2026-12-06): the
/// first window, ±8 mm with half the photons, left the BIPs at 45° ~10 µm closer to p_e than
/// 2²² photons put them, because the faint returns a BIP rule climbs through, within a
/// millimetre or two of p_e, were undersampled. Of eight windows tried on two photon draws,
/// ±2 mm with 0.6 of the photons passed every criterion on the pane at 10°, 40° and 45°, and did
/// again on a third, held-out draw.
pub const FOCUS_HALF_WIDTH_M: f64 = 0.002;

/// The share of a pose's photons drawn inside the window. 0.6 rather than more: the rest of the
/// line keeps 0.4 of them, so its columns' Monte Carlo error grows by √(0.5/0.4) ≈ 1.12 over
/// the first window's (6.1 against 4.8 µm on the pane at 10°, within the test's 7.25 µm), where
/// 0.75 grew it by 1.4.
pub const FOCUS_SHARE: f64 = 0.6;

/// A mixture density over the fan's uniform number u ∈ [0, 1) (u = the line profile's CDF at
/// the fan angle): 1 − share everywhere plus share / (hi − lo) on the window [lo, hi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FanFocus {
    lo: f64,
    hi: f64,
    share: f64,
}

impl FanFocus {
    /// The focus on the window of half-width `half_width_m` along the laser line around
    /// `point_s` (sensor frame; its distance from the laser plane is ignored), with `share` of
    /// the photons in it. `None` where the window holds no part of the fan (p_e behind the
    /// source or out of the fan), where `share` is not in (0, 1), or for a window of no width.
    pub fn toward(
        laser: &LaserSheet,
        point_s: &Point3<f64>,
        half_width_m: f64,
        share: f64,
    ) -> Option<FanFocus> {
        if !(share > 0.0 && share < 1.0 && half_width_m > 0.0 && point_s.z > 0.0) {
            return None;
        }
        let at = |x: f64| laser.fan_fraction(x.atan2(point_s.z));
        let (lo, hi) = (at(point_s.x - half_width_m), at(point_s.x + half_width_m));
        // A window the fan's float resolution cannot tell from a point is no window.
        (hi - lo > 1e-9).then_some(FanFocus { lo, hi, share })
    }

    /// The photon's fan number u′ for a uniform `u` in [0, 1) (the mixture's inverse CDF,
    /// monotone, so stratified u stay stratified) and its weight p/q = 1/q(u′).
    pub fn warp(&self, u: f64) -> (f64, f64) {
        let FanFocus { lo, hi, share } = *self;
        let base = 1.0 - share;
        let inside = base + share / (hi - lo);
        // The mixture's CDF at the window's ends.
        let (at_lo, at_hi) = (base * lo, base * hi + share);
        if u < at_lo {
            (u / base, 1.0 / base)
        } else if u < at_hi {
            ((lo + (u - at_lo) / inside).min(hi), 1.0 / inside)
        } else {
            ((hi + (u - at_hi) / base).min(1.0), 1.0 / base)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::preset::scancontrol_2600_100;
    use crate::sensor::projector::LineProfile;

    fn focus(point: Point3<f64>) -> FanFocus {
        let laser = scancontrol_2600_100().laser;
        FanFocus::toward(&laser, &point, FOCUS_HALF_WIDTH_M, FOCUS_SHARE).expect("in the fan")
    }

    #[test]
    fn the_warp_is_monotone_continuous_and_onto() {
        let f = focus(Point3::new(0.02, 0.0, 0.25));
        let n = 100_000;
        let mut last = -1.0;
        for i in 0..=n {
            let u = (i as f64 / n as f64).min(1.0 - f64::EPSILON);
            let (v, w) = f.warp(u);
            assert!((0.0..=1.0).contains(&v) && w > 0.0);
            assert!(v >= last, "not monotone at {u}");
            // Continuous: a step of 1/n in u moves u′ by at most 1/(n·min q) = 1/(n(1 − s)).
            assert!(last < 0.0 || v - last <= 1.0 / (n as f64 * (1.0 - FOCUS_SHARE)) + 1e-12);
            last = v;
        }
        assert!(f.warp(0.0).0 == 0.0 && last > 1.0 - 1e-4);
    }

    #[test]
    fn weighted_photons_keep_every_part_of_the_line_its_power() {
        // Stratified uniforms warped: the weights sum to the line's power share on any interval
        // of the fan (here the window, its two halves, and the rest), and the window gets
        // (1 − s)·f + s of the photons.
        let f = focus(Point3::new(-0.03, 0.001, 0.3));
        let n = 1_000_000;
        let intervals = [
            (0.0, f.lo),
            (f.lo, 0.5 * (f.lo + f.hi)),
            (0.5 * (f.lo + f.hi), f.hi),
            (f.hi, 1.0),
        ];
        let mut power = [0.0; 4];
        let mut count = [0usize; 4];
        for i in 0..n {
            let (v, w) = f.warp((i as f64 + 0.5) / n as f64);
            let k = intervals
                .iter()
                .position(|&(a, b)| v >= a && v < b)
                .unwrap();
            power[k] += w / n as f64;
            count[k] += 1;
        }
        for (k, &(a, b)) in intervals.iter().enumerate() {
            assert!(
                (power[k] - (b - a)).abs() < 1e-5,
                "{k}: {} vs {}",
                power[k],
                b - a
            );
        }
        let window = f.hi - f.lo;
        let in_window = (count[1] + count[2]) as f64 / n as f64;
        let expected = (1.0 - FOCUS_SHARE) * window + FOCUS_SHARE;
        assert!(
            (in_window - expected).abs() < 1e-5,
            "{in_window} vs {expected}"
        );
        // The edge region of a 100 mm line at 0.3 m is a few per cent of it.
        assert!(window > 0.03 && window < 0.3, "{window}");
    }

    #[test]
    fn the_window_is_the_fan_angles_of_the_points_beside_the_target() {
        for profile in [
            LineProfile::Uniform,
            LineProfile::Gaussian {
                half_angle_1e2_rad: 0.2,
            },
        ] {
            let mut laser = scancontrol_2600_100().laser;
            laser.line_profile = profile;
            let p = Point3::new(0.01, 0.0, 0.26);
            let f = FanFocus::toward(&laser, &p, 0.005, 0.5).unwrap();
            // fan_angle is the inverse of fan_fraction (for the Gaussian line up to the normal
            // CDF's 1.2e-7, `optics::warp::erfc`: nanometres here).
            let x_at = |u: f64| laser.fan_angle(u).tan() * p.z;
            assert!((x_at(f.lo) - 0.005).abs() < 1e-8, "{}", x_at(f.lo));
            assert!((x_at(f.hi) - 0.015).abs() < 1e-8, "{}", x_at(f.hi));
        }
    }

    #[test]
    fn no_focus_behind_the_source_outside_the_fan_or_without_a_share() {
        let laser = scancontrol_2600_100().laser;
        let w = FOCUS_HALF_WIDTH_M;
        assert!(FanFocus::toward(&laser, &Point3::new(0.0, 0.0, -0.2), w, 0.5).is_none());
        assert!(FanFocus::toward(&laser, &Point3::new(5.0, 0.0, 0.2), w, 0.5).is_none());
        assert!(FanFocus::toward(&laser, &Point3::new(0.0, 0.0, 0.2), w, 0.0).is_none());
        assert!(FanFocus::toward(&laser, &Point3::new(0.0, 0.0, 0.2), w, 1.0).is_none());
        // Half in the fan: the window is clipped to it.
        let half = 0.5 * laser.fan_angle_rad;
        let edge_x = half.tan() * 0.2;
        let f = FanFocus::toward(&laser, &Point3::new(edge_x, 0.0, 0.2), w, 0.5).unwrap();
        assert!(f.hi == 1.0 && f.lo < 1.0);
    }
}
