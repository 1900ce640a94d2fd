//! The paper's localisation run against ground truth: scan poses along the *nominal* border,
//! the sensor at each, a Border Identifier Point per profile, ICP of the BIPs against the model
//! border, and the errors (Adrian & Pham, Sections IV–VI).

use std::time::Instant;

use nalgebra::Point3;

use super::adaptive::StopRules;
use super::bip::{find_bip, Bip, BipRule};
use super::errors::{ErrorDraw, ErrorModel};
use super::poses::{plan_border_scan, ScanPose};
use super::simulate::{simulate_pose, PoseResult};
use super::ScanConfig;
use crate::geometry::border::BorderCurve;
use crate::geometry::pose::Pose;
use crate::localise::icp::{register, IcpError, IcpSettings, Registration};
use crate::localise::metrics::{contour_error, pose_error, task_error, Stats};
use crate::scene::World;
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

/// How a localisation run picks its BIPs and which error sources it simulates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocateSettings {
    /// The BIP rule whose points are registered (the paper's is reported alongside).
    pub rule: BipRule,
    /// Robot, hand-eye and linearity errors (`ErrorModel::OFF` for the sensor alone).
    pub errors: ErrorModel,
}

/// One scan pose of a localisation run.
#[derive(Clone, Debug)]
pub struct LocatedPose {
    /// The pose as planned (on the nominal border) and as the software believes it is: T_BS
    /// from the commanded flange and the calibrated mount.
    pub planned: ScanPose,
    /// The simulation, at the pose the sensor really had (`result.pose.sensor`).
    pub result: PoseResult,
    /// Ground truth p_e: the true laser plane ∩ the true border (base frame), if they cross.
    pub edge_point: Option<Point3<f64>>,
    /// The BIP by the run's rule, in the base frame as the software computes it.
    pub bip: Option<Bip>,
    /// The BIP by the paper's rule (the same as `bip` when that is the run's rule).
    pub paper_bip: Option<Bip>,
}

/// A localisation run's outcome.
#[derive(Debug)]
pub struct LocateReport {
    /// Per pose.
    pub poses: Vec<LocatedPose>,
    /// The settings it ran with.
    pub settings: LocateSettings,
    /// The per-run error draw (hand-eye error, linearity phase).
    pub errors: ErrorDraw,
    /// The registration, if there were enough BIPs.
    pub registration: Result<Registration, IcpError>,
    /// |BIP − p_e| of the run's rule over the poses that have both (mm).
    pub bip_error_mm: Stats,
    /// The same for the paper's rule.
    pub paper_bip_error_mm: Stats,
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
/// `true_pose` its true pose T_BM, `nominal` the coarse pose T_BM0 the robot plans with,
/// `mount` the calibrated hand-eye mount T_FS. `on_pose` is called after each pose (progress).
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
    settings: &LocateSettings,
    on_pose: &(dyn Fn() + Sync),
) -> LocateReport {
    let started = Instant::now();
    let nominal_b = model_m.transformed(nominal);
    let true_b = model_m.transformed(true_pose);
    let draw = ErrorDraw::new(settings.errors, trace.seed);
    let range = head.config.range;
    let planned: Vec<ScanPose> = plan_border_scan(&nominal_b, scan, mount);
    // Both BIPs it reports (the registering rule's and the paper's) settle before a pose stops.
    let stop = StopRules::registering_with(settings.rule);
    let poses: Vec<LocatedPose> = planned
        .into_iter()
        .map(|p| {
            let sensor = draw.true_sensor_pose(&p.flange, mount, p.index);
            let edge_point = laser_plane_crossing(&true_b, &sensor, scan.standoff_m);
            // The sensor at its true pose, looking at the true border's p_e (where the
            // transport draws its photons more densely).
            let actual = ScanPose {
                sensor,
                edge_point: edge_point.unwrap_or(p.edge_point),
                ..p.clone()
            };
            let mut result = simulate_pose(scene, head, &actual, trace, stop);
            for q in result.profile.points.iter_mut().filter(|q| q.valid) {
                q.z_mm += 1e3 * draw.linearity_error(q.z_mm * 1e-3, range.z_min_m, range.z_max_m);
            }
            let bip = find_bip(&result.profile, &p.sensor, settings.rule);
            let paper_bip = match settings.rule {
                BipRule::Highest => bip,
                _ => find_bip(&result.profile, &p.sensor, BipRule::Highest),
            };
            on_pose();
            LocatedPose {
                planned: p,
                result,
                edge_point,
                bip,
                paper_bip,
            }
        })
        .collect();
    let scanning_s = started.elapsed().as_secs_f64();

    let errors_of = |pick: fn(&LocatedPose) -> Option<Bip>| {
        let e: Vec<f64> = poses
            .iter()
            .filter_map(|p| Some((pick(p)?.point_b - p.edge_point?).norm() * 1e3))
            .collect();
        Stats::from_values(&e)
    };
    let bips: Vec<Point3<f64>> = poses
        .iter()
        .filter_map(|p| p.bip.map(|b| b.point_b))
        .collect();
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
        bip_error_mm: errors_of(|p| p.bip),
        paper_bip_error_mm: errors_of(|p| p.paper_bip),
        poses,
        settings: *settings,
        errors: draw,
        registration,
        pose_error: pose_err,
        task_error_mm: task,
        contour_error_mm: contour,
        timings_s: (scanning_s, icp_s),
    }
}

/// [`locate`] on a whole scene: its target (true pose, nominal pose, border), its sensor and
/// mount. Errors: no target, or a sensor or scene the simulator cannot build (bad input).
pub fn locate_world(
    world: &World,
    scan: &ScanConfig,
    trace: &TraceSettings,
    settings: &LocateSettings,
    on_pose: &(dyn Fn() + Sync),
) -> anyhow::Result<LocateReport> {
    let target = world.target.as_ref().ok_or_else(|| {
        anyhow::anyhow!(
            "{}: the scene has no [target] whose border could be located",
            world.source.display()
        )
    })?;
    let head = SensorHead::new(&world.sensor)?;
    let trace_scene = TraceScene::new(world)?;
    Ok(locate(
        &trace_scene,
        &head,
        &target.border,
        &world.objects[target.object].pose,
        &target.nominal_pose,
        &world.mount,
        scan,
        trace,
        settings,
        on_pose,
    ))
}
