//! One dataset sample: draw its parameters, build its scene, place one scan pose on the
//! target's border, simulate the sensor there and cast the ideal profile.
//!
//! Planning: the scan pose is planned on the target's border at the scene's true pose (before
//! any pose jitter), the way a robot plans on the pose it believes; the sample's true pose is
//! the jittered one, and p_e is where the laser plane cuts the *true* border
//! (`scan::locate::laser_plane_crossing`). Without jitter the two borders are the same and p_e
//! is the planned border point. Random numbers: the draws are keyed on (seed, index)
//! (`randomize::draw`); the simulation on the sample's noise seed alone, so a sample can be
//! re-made from its recorded parameters.

use nalgebra::Point3;

use super::ideal_profile::{ideal_profile, IdealPoint};
use super::randomize::{draw, Draw, Randomization};
use super::scene_edit::SceneTemplate;
use super::DatasetError;
use crate::geometry::pose::Pose;
use crate::scan::adaptive::StopRules;
use crate::scan::locate::laser_plane_crossing;
use crate::scan::poses::{plan_border_scan, ScanPose};
use crate::scan::simulate::{simulate_pose, PoseResult};
use crate::scan::ScanConfig;
use crate::scene::World;
use crate::sensor::SensorHead;
use crate::transport::{TraceScene, TraceSettings};

/// A world ready to simulate: its BVH and its sensor head.
pub struct PreparedWorld {
    /// The scene.
    pub world: World,
    /// Its BVH and surface models.
    pub scene: TraceScene,
    /// Its sensor head.
    pub head: SensorHead,
}

impl PreparedWorld {
    /// Builds the BVH and the camera of `world`; errors are messages for the caller to place.
    pub fn new(world: World) -> Result<PreparedWorld, String> {
        PreparedWorld::new_like(world, None)
    }

    /// [`PreparedWorld::new`] for a sample of the dataset whose scene as written is `base`:
    /// the sensor unit's fixed pattern is `base`'s wherever randomisation left it as it was.
    pub fn new_like(world: World, base: Option<&PreparedWorld>) -> Result<PreparedWorld, String> {
        let scene = TraceScene::new(&world).map_err(|e| e.to_string())?;
        let head = SensorHead::new_like(&world.sensor, base.map(|b| &b.head))
            .map_err(|e| format!("[sensor]: {e}"))?;
        Ok(PreparedWorld { world, scene, head })
    }
}

/// Everything about the run that every sample shares.
pub struct SampleContext<'a> {
    /// The scene as written.
    pub template: &'a SceneTemplate,
    /// The scene as written, prepared once (used by samples that randomise nothing).
    pub base: &'a PreparedWorld,
    /// The randomisation, if any.
    pub randomization: Option<&'a Randomization>,
    /// Master seed of the draws.
    pub seed: u64,
    /// Laser photons per sample (with `adaptive`, the most a sample may take).
    pub photons: u64,
    /// Whether each sample stops once its edge-line BIP has converged (`scan::adaptive`).
    pub adaptive: bool,
    /// Longest photon path.
    pub max_depth: u32,
}

/// A simulated sample.
pub struct Sample<'a> {
    /// Sample index.
    pub index: u64,
    /// Its draws.
    pub draw: Draw,
    /// Its scene (borrowed when nothing was randomised).
    pub prepared: SampleWorld<'a>,
    /// The scan pose (planned on the unjittered border; its `edge_point` is the planned point).
    pub pose: ScanPose,
    /// The target's true pose T_BM in this sample.
    pub target_pose: Pose,
    /// Ground truth p_e (base frame, m), if the laser plane crosses the true border.
    pub edge_point: Option<Point3<f64>>,
    /// What the sensor produced.
    pub result: PoseResult,
    /// The first surface hit of each fan ray.
    pub ideal: Vec<IdealPoint>,
}

/// A sample's scene: the shared one when nothing was randomised, its own otherwise.
pub enum SampleWorld<'a> {
    /// The run's scene as written.
    Shared(&'a PreparedWorld),
    /// A randomised scene.
    Own(Box<PreparedWorld>),
}

impl std::ops::Deref for SampleWorld<'_> {
    type Target = PreparedWorld;
    fn deref(&self) -> &PreparedWorld {
        match self {
            SampleWorld::Shared(p) => p,
            SampleWorld::Own(p) => p,
        }
    }
}

/// Makes sample `index`.
pub fn make_sample<'a>(ctx: &SampleContext<'a>, index: u64) -> Result<Sample<'a>, DatasetError> {
    let fail = |message: String| DatasetError::Sample { index, message };
    let draw = draw(ctx.randomization, ctx.seed, index);
    let prepared = if draw.values.is_empty() {
        SampleWorld::Shared(ctx.base)
    } else {
        let world = ctx.template.world_with(&draw.values).map_err(fail)?;
        SampleWorld::Own(Box::new(
            PreparedWorld::new_like(world, Some(ctx.base)).map_err(fail)?,
        ))
    };
    let world = &prepared.world;
    let Some(target) = world.target.as_ref() else {
        return Err(fail(format!(
            "{}: the scene has no [target]: a dataset needs a panel whose border it scans",
            world.source.display()
        )));
    };
    let planned_on = ctx
        .template
        .world
        .target
        .as_ref()
        .map_or(world.objects[target.object].pose, |t| {
            ctx.template.world.objects[t.object].pose
        });
    let target_pose = world.objects[target.object].pose;
    let scan = ScanConfig {
        poses: 1,
        start_fraction: draw.border_fraction,
        ..world.scan
    };
    let pose = plan_border_scan(&target.border.transformed(&planned_on), &scan, &world.mount)
        .pop()
        .expect("one pose is planned");
    let edge_point = laser_plane_crossing(
        &target.border.transformed(&target_pose),
        &pose.sensor,
        scan.standoff_m,
    );
    let settings = TraceSettings {
        photons: ctx.photons,
        adaptive: ctx.adaptive,
        max_depth: ctx.max_depth,
        seed: draw.noise_seed,
    };
    // Simulated looking at the true border's p_e (where the transport draws its photons more
    // densely); the sample keeps the planned pose.
    let looking = ScanPose {
        edge_point: edge_point.unwrap_or(pose.edge_point),
        ..pose.clone()
    };
    let result = simulate_pose(
        &prepared.scene,
        &prepared.head,
        &looking,
        &settings,
        StopRules::EDGE_LINE,
    );
    let rays = world.sensor.firmware.points_per_profile;
    let ideal = ideal_profile(world, &prepared.scene, &prepared.head, &pose.sensor, rays);
    Ok(Sample {
        index,
        draw,
        prepared,
        pose,
        target_pose,
        edge_point,
        result,
        ideal,
    })
}
