//! The error sources of a real cell that sit outside the sensor's optics: robot repeatability,
//! hand-eye calibration error and the sensor's linearity error. Off by default, so that a run
//! measures the sensor (and the BIP and ICP) alone; `--errors default` switches on the budget
//! of docs/parameters.md §6, each term separately settable.
//!
//! How each enters (the robot commands flange poses; the software believes T_BS = T_BF · T_FS):
//! - **Robot repeatability**: the flange reaches T_BF · ΔR_k instead of T_BF, a new Gaussian
//!   draw per pose k (σ per axis, translation only: repeatability is specified for position).
//! - **Hand-eye error**: the true mount is T_FS · ΔH, one Gaussian draw per run (σ per axis in
//!   translation and rotation), while the software converts with the calibrated T_FS.
//! - **Linearity**: the sensor reports z + L(z) with L fixed per sensor unit. The datasheet
//!   gives only a bound (±0.16 % of the full scale, UNVERIFIED, docs/parameters.md §6), so L is one
//!   full sine period over the measuring range with that bound as amplitude and a phase drawn
//!   per unit: a modelling choice (L) that is systematic, smooth and within the spec.
//!
//! The light is simulated at the true sensor pose; the profile is converted to the base frame
//! with the believed one. Draws are keyed on (seed, stream, pose index), so they do not depend
//! on the thread count or on the order poses are simulated in.

use nalgebra::{Translation3, UnitQuaternion, Vector3};

use crate::geometry::pose::Pose;
use crate::optics::warp::box_muller;
use crate::sampler::PoseSampler;

/// Streams of the error draws, apart from the transport's, the speckle's and the noise's.
const ROBOT_STREAM: u64 = 0x0e77_0b07_0000_0000;
const HAND_EYE_STREAM: u64 = 0x0e77_4a4d_0000_0000;
const LINEARITY_STREAM: u64 = 0x0e77_114e_0000_0000;

/// The error budget (1σ values unless said otherwise; SI units).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ErrorModel {
    /// Robot repeatability, σ per translation axis (m).
    pub robot_repeatability_m: f64,
    /// Hand-eye calibration error, σ per translation axis (m).
    pub hand_eye_translation_m: f64,
    /// Hand-eye calibration error, σ per rotation axis (rad).
    pub hand_eye_rotation_rad: f64,
    /// Linearity error: amplitude (bound) of the systematic z error (m).
    pub linearity_m: f64,
}

impl ErrorModel {
    /// No error source: the sensor alone.
    pub const OFF: ErrorModel = ErrorModel {
        robot_repeatability_m: 0.0,
        hand_eye_translation_m: 0.0,
        hand_eye_rotation_rad: 0.0,
        linearity_m: 0.0,
    };

    /// docs/parameters.md §6 (the suggested defaults, 1σ): UR e-Series
    /// repeatability 0.03 mm (M); hand-eye residual 0.2 mm / 0.03° (M/L, a good calibration);
    /// linearity ±0.16 % of the 2600-100's 265 mm range = ±0.424 mm (UNVERIFIED, L).
    pub const DEFAULT: ErrorModel = ErrorModel {
        robot_repeatability_m: 0.03e-3,
        hand_eye_translation_m: 0.2e-3,
        hand_eye_rotation_rad: 0.03 * std::f64::consts::PI / 180.0,
        linearity_m: 0.0016 * 265e-3,
    };

    /// Whether any source is on.
    pub fn is_on(&self) -> bool {
        *self != ErrorModel::OFF
    }

    /// The names of the sources that are on, for reports.
    pub fn sources_on(&self) -> Vec<&'static str> {
        let mut on = Vec::new();
        if self.robot_repeatability_m > 0.0 {
            on.push("robot_repeatability");
        }
        if self.hand_eye_translation_m > 0.0 || self.hand_eye_rotation_rad > 0.0 {
            on.push("hand_eye");
        }
        if self.linearity_m > 0.0 {
            on.push("linearity");
        }
        on
    }
}

/// One run's draw of the error sources: what is fixed per run, and how to draw per pose.
#[derive(Clone, Debug)]
pub struct ErrorDraw {
    model: ErrorModel,
    seed: u64,
    /// ΔH: true mount = calibrated mount · ΔH.
    pub hand_eye: Pose,
    /// Phase of the linearity sine (rad).
    pub linearity_phase: f64,
}

/// Six independent standard normals from a keyed sampler.
fn normals(sampler: &PoseSampler, key: u64) -> [f64; 6] {
    let u = |d: u32| sampler.uniform(key, d).max(f64::MIN_POSITIVE);
    let (a, b) = box_muller(u(0), u(1));
    let (c, d) = box_muller(u(2), u(3));
    let (e, f) = box_muller(u(4), u(5));
    [a, b, c, d, e, f]
}

impl ErrorDraw {
    /// Draws the per-run terms of `model` for `seed`.
    pub fn new(model: ErrorModel, seed: u64) -> ErrorDraw {
        let n = normals(&PoseSampler::new(seed, HAND_EYE_STREAM), 0);
        let t = Vector3::new(n[0], n[1], n[2]) * model.hand_eye_translation_m;
        let r = Vector3::new(n[3], n[4], n[5]) * model.hand_eye_rotation_rad;
        let hand_eye = Pose::from_parts(Translation3::from(t), UnitQuaternion::from_scaled_axis(r));
        let phase = PoseSampler::new(seed, LINEARITY_STREAM).uniform(0, 0) * std::f64::consts::TAU;
        ErrorDraw {
            model,
            seed,
            hand_eye,
            linearity_phase: phase,
        }
    }

    /// The model this was drawn from.
    pub fn model(&self) -> &ErrorModel {
        &self.model
    }

    /// ΔR_k: where the flange really is, relative to where it was commanded, at pose `k`.
    pub fn robot_offset(&self, k: usize) -> Pose {
        let n = normals(&PoseSampler::new(self.seed, ROBOT_STREAM), k as u64);
        Pose::from_parts(
            Translation3::from(Vector3::new(n[0], n[1], n[2]) * self.model.robot_repeatability_m),
            UnitQuaternion::identity(),
        )
    }

    /// The true sensor pose for a commanded flange pose T_BF and calibrated mount T_FS at pose
    /// `k`: T_BF · ΔR_k · T_FS · ΔH.
    pub fn true_sensor_pose(&self, flange: &Pose, mount: &Pose, k: usize) -> Pose {
        flange * self.robot_offset(k) * mount * self.hand_eye
    }

    /// The linearity error L(z) (m) at range `z_m` for a sensor measuring over
    /// [`z_min_m`, `z_max_m`].
    pub fn linearity_error(&self, z_m: f64, z_min_m: f64, z_max_m: f64) -> f64 {
        if self.model.linearity_m == 0.0 {
            return 0.0;
        }
        let s = (z_m - z_min_m) / (z_max_m - z_min_m);
        self.model.linearity_m * (std::f64::consts::TAU * s + self.linearity_phase).sin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::pose::pose_from_mm_deg;

    #[test]
    fn off_changes_nothing() {
        let d = ErrorDraw::new(ErrorModel::OFF, 7);
        let flange = pose_from_mm_deg([100.0, 20.0, 300.0], [10.0, 170.0, 5.0]);
        let mount = pose_from_mm_deg([0.0, 50.0, 80.0], [0.0, 0.0, 90.0]);
        assert_eq!(d.true_sensor_pose(&flange, &mount, 3), flange * mount);
        assert_eq!(d.linearity_error(0.2, 0.125, 0.39), 0.0);
        assert!(!ErrorModel::OFF.is_on());
        assert!(ErrorModel::OFF.sources_on().is_empty());
        assert_eq!(ErrorModel::DEFAULT.sources_on().len(), 3);
    }

    /// The robot offsets over many poses have the model's σ per axis and zero mean (z-tests at
    /// 4σ of the estimators' own spread), and are independent of the order they are drawn in.
    #[test]
    fn robot_offsets_have_the_stated_spread() {
        let d = ErrorDraw::new(ErrorModel::DEFAULT, 11);
        let sigma = ErrorModel::DEFAULT.robot_repeatability_m;
        let n = 20_000;
        let t: Vec<Vector3<f64>> = (0..n)
            .map(|k| d.robot_offset(k).translation.vector)
            .collect();
        for axis in 0..3 {
            let mean = t.iter().map(|v| v[axis]).sum::<f64>() / n as f64;
            let var = t.iter().map(|v| (v[axis] - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
            assert!(
                mean.abs() < 4.0 * sigma / (n as f64).sqrt(),
                "axis {axis} mean {mean}"
            );
            // The variance estimator's σ is var·sqrt(2/(n−1)).
            let rel = (var / (sigma * sigma) - 1.0).abs();
            assert!(
                rel < 4.0 * (2.0 / (n - 1) as f64).sqrt(),
                "axis {axis} var ratio {rel}"
            );
        }
        assert_eq!(d.robot_offset(17), d.robot_offset(17));
        assert_ne!(d.robot_offset(17), d.robot_offset(18));
    }

    #[test]
    fn hand_eye_error_is_fixed_per_seed_and_of_the_right_size() {
        let a = ErrorDraw::new(ErrorModel::DEFAULT, 5);
        let b = ErrorDraw::new(ErrorModel::DEFAULT, 5);
        let c = ErrorDraw::new(ErrorModel::DEFAULT, 6);
        assert_eq!(a.hand_eye, b.hand_eye);
        assert_ne!(a.hand_eye, c.hand_eye);
        // Over many seeds the translation's squared norm averages 3σ².
        let m = ErrorModel::DEFAULT;
        let n = 4000;
        let ms = (0..n)
            .map(|s| {
                ErrorDraw::new(m, s)
                    .hand_eye
                    .translation
                    .vector
                    .norm_squared()
            })
            .sum::<f64>()
            / n as f64;
        let expect = 3.0 * m.hand_eye_translation_m.powi(2);
        // χ²₃/3 has relative σ sqrt(2/3); over n draws sqrt(2/(3n)).
        assert!((ms / expect - 1.0).abs() < 4.0 * (2.0 / (3.0 * n as f64)).sqrt());
    }

    #[test]
    fn linearity_stays_within_its_bound_and_is_smooth() {
        let d = ErrorDraw::new(ErrorModel::DEFAULT, 3);
        let bound = ErrorModel::DEFAULT.linearity_m;
        let zs: Vec<f64> = (0..=1000)
            .map(|i| 0.125 + 0.265 * i as f64 / 1000.0)
            .collect();
        let l: Vec<f64> = zs
            .iter()
            .map(|&z| d.linearity_error(z, 0.125, 0.39))
            .collect();
        assert!(l.iter().all(|v| v.abs() <= bound * (1.0 + 1e-12)));
        // It reaches its bound somewhere in the range (one full period).
        assert!(l.iter().any(|v| v.abs() > 0.99 * bound));
        // Slope at most 2π·A/range.
        let max_step = l
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        assert!(max_step <= std::f64::consts::TAU * bound / 1000.0 * (1.0 + 1e-9));
    }
}
