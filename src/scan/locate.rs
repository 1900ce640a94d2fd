//! The paper's localisation run against ground truth: scan poses along the *nominal* border,
//! the sensor at each, a Border Identifier Point per profile, ICP of the BIPs against the model
//! border, and the errors (Adrian & Pham, Sections IV–VI).

use std::time::Instant;

use nalgebra::Point3;

use super::poses::{plan_border_scan, ScanPose};
use super::simulate::{simulate_pose, PoseResult};
use super::ScanConfig;
use crate::geometry::border::BorderCurve;
use crate::geometry::pose::Pose;
use crate::localise::bip::bip_highest;
use crate::localise::icp::{register, IcpError, IcpSettings, Registration};
use crate::localise::metrics::{contour_error, pose_error, task_error, Stats};
use crate::sensor::SensorHead;
use crate::transport::{TraceScene, TraceSettings};

/// Where the laser plane (y = 0 of the sensor frame) of `sensor` cuts `border_b`: the crossing
/// nearest the point at `standoff_m` on the laser axis. This is the ground-truth p_e.
pub fn laser_plane_crossing(
    border_b: &BorderCurve,
    sensor: &Pose,
    standoff_m: f64,
) -> Option<Point3<f64>> {
    let to_sensor = sensor.inverse();
    let aim = Point3::new(0.0, 0.0, standoff_m);
    let v = &border_b.vertices;
    (0..v.len())
        .filter_map(|i| {
            let a = to_sensor * v[i].position;
            let b = to_sensor * v[(i + 1) % v.len()].position;
            if (a.y > 0.0) == (b.y > 0.0) || a.y == b.y {
                return None;
            }
            let t = a.y / (a.y - b.y);
            let p = a + (b - a) * t;
            Some((p, (p - aim).norm()))
        })
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map(|(p, _)| sensor * p)
}

/// One scan pose of a localisation run.
#[derive(Clone, Debug)]
pub struct LocatedPose {
    /// The pose as commanded (planned on the nominal border) and its simulation.
    pub result: PoseResult,
    /// Ground truth p_e: the laser plane ∩ the true border (base frame), if they cross.
    pub edge_point: Option<Point3<f64>>,
    /// The BIP in the base frame, and the index of the profile point it came from.
    pub bip: Option<(Point3<f64>, usize)>,
}

/// A localisation run's outcome.
#[derive(Debug)]
pub struct LocateReport {
    /// Per pose.
    pub poses: Vec<LocatedPose>,
    /// The registration, if there were enough BIPs.
    pub registration: Result<Registration, IcpError>,
    /// |BIP − p_e| over the poses that have both (mm).
    pub bip_error_mm: Stats,
    /// Pose error of the estimate (mm, deg), if registered.
    pub pose_error: Option<(f64, f64)>,
    /// Task error (paper's Table 4 metric), mm.
    pub task_error_mm: Option<Stats>,
    /// Contour error over the whole border, mm.
    pub contour_error_mm: Option<Stats>,
    /// Wall-clock seconds: scanning (simulation) and pose estimation (ICP).
    pub timings_s: (f64, f64),
}

/// Runs the scan-BIP-ICP pipeline. `model_m` is the target's border in its model frame,
/// `true_pose` its true pose T_BM, `nominal` the coarse pose T_BM0 the robot plans with.
#[allow(clippy::too_many_arguments)]
pub fn locate(
    scene: &TraceScene,
    head: &SensorHead,
    model_m: &BorderCurve,
    true_pose: &Pose,
    nominal: &Pose,
    mount: &Pose,
    scan: &ScanConfig,
    trace: &TraceSettings,
) -> LocateReport {
    let started = Instant::now();
    let nominal_b = model_m.transformed(nominal);
    let true_b = model_m.transformed(true_pose);
    let planned: Vec<ScanPose> = plan_border_scan(&nominal_b, scan, mount);
    let poses: Vec<LocatedPose> = planned
        .into_iter()
        .map(|p| {
            let result = simulate_pose(scene, head, &p, trace);
            let edge_point = laser_plane_crossing(&true_b, &p.sensor, scan.standoff_m);
            let points_b: Vec<Point3<f64>> = result
                .profile
                .points
                .iter()
                .filter(|q| q.valid)
                .map(|q| p.sensor * Point3::new(q.x_mm * 1e-3, 0.0, q.z_mm * 1e-3))
                .collect();
            let bip = bip_highest(&points_b, 0.0, 0.5e-3).map(|i| (points_b[i], i));
            LocatedPose {
                result,
                edge_point,
                bip,
            }
        })
        .collect();
    let scanning_s = started.elapsed().as_secs_f64();

    let bip_errors: Vec<f64> = poses
        .iter()
        .filter_map(|p| Some((p.bip?.0 - p.edge_point?).norm() * 1e3))
        .collect();
    let bips: Vec<Point3<f64>> = poses.iter().filter_map(|p| p.bip.map(|b| b.0)).collect();
    let t0 = Instant::now();
    let registration = register(model_m, &bips, nominal, &IcpSettings::robust());
    let icp_s = t0.elapsed().as_secs_f64();
    let (pose_err, task, contour) = match &registration {
        Ok(r) => {
            let estimate_b = model_m.transformed(&r.pose);
            (
                Some(pose_error(&r.pose, true_pose)),
                Some(task_error(&true_b, &estimate_b, 100)),
                Some(contour_error(&true_b, &estimate_b, 1000)),
            )
        }
        Err(_) => (None, None, None),
    };
    LocateReport {
        poses,
        registration,
        bip_error_mm: Stats::from_values(&bip_errors),
        pose_error: pose_err,
        task_error_mm: task,
        contour_error_mm: contour,
        timings_s: (scanning_s, icp_s),
    }
}
