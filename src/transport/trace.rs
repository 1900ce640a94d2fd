//! The light tracer (see the module documentation of `transport` for the estimator).

use nalgebra::{Point3, Vector3};
use rayon::prelude::*;

use super::film::{develop, Splat};
use super::sampler::PoseSampler;
use super::scene::{SurfaceModel, TraceScene};
use crate::geometry::pose::Pose;
use crate::optics::warp::concentric_disk;
use crate::sensor::image::Image;
use crate::sensor::SensorHead;

/// Photons per work unit. Fixed (not derived from the thread count) so that results do not
/// depend on how many threads run.
const CHUNK: u64 = 4096;

/// Offset of secondary ray origins along the geometric normal (m): well above the f32
/// resolution of the base frame (~0.1 µm at 1 m) and far below any feature size.
const RAY_EPSILON_M: f64 = 2e-6;

/// Longest ray considered (m).
const FAR_M: f64 = 100.0;

/// Settings of one rendering.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TraceSettings {
    /// Laser photons per pose, ≥ 1.
    pub photons: u64,
    /// Largest number of scattering vertices per photon path (≥ 1).
    pub max_depth: u32,
    /// Master seed.
    pub seed: u64,
}

/// Counters of one rendering.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct TraceStats {
    /// Laser photons emitted.
    pub photons: u64,
    /// Laser photons whose first ray hit the scene.
    pub laser_hits: u64,
    /// Scattering vertices (all depths).
    pub vertices: u64,
    /// Camera connections attempted (vertex facing the sampled lens point).
    pub connections: u64,
    /// Connections blocked by geometry (camera-side shadows).
    pub occluded: u64,
    /// Unblocked connections that landed off the pixel grid.
    pub off_sensor: u64,
    /// Paths stopped at `max_depth` while still carrying power.
    pub truncated: u64,
    /// Total flux splatted on the sensor (W).
    pub flux_on_sensor_w: f64,
    /// Power of paths stopped at `max_depth` (W): the truncation bias, an upper bound on the
    /// flux they could still have sent anywhere.
    pub truncated_power_w: f64,
}

impl TraceStats {
    fn add(&mut self, o: &TraceStats) {
        self.photons += o.photons;
        self.laser_hits += o.laser_hits;
        self.vertices += o.vertices;
        self.connections += o.connections;
        self.occluded += o.occluded;
        self.off_sensor += o.off_sensor;
        self.truncated += o.truncated;
        self.flux_on_sensor_w += o.flux_on_sensor_w;
        self.truncated_power_w += o.truncated_power_w;
    }
}

/// Dimensions of the keyed sampler used per vertex beyond the first (lens u, v; direction u, v;
/// roulette).
const DIMS_PER_BOUNCE: u32 = 8;

/// Renders the irradiance image (W/m²) that the sensor at `sensor_pose` (T_BS) sees.
/// `pose_index` keys the random numbers, so poses are independent and reproducible.
pub fn render(
    scene: &TraceScene,
    head: &SensorHead,
    sensor_pose: &Pose,
    settings: &TraceSettings,
    pose_index: u64,
) -> (Image<f64>, TraceStats) {
    let sampler = PoseSampler::new(settings.seed, pose_index);
    let chunks = settings.photons.div_ceil(CHUNK);
    let results: Vec<(Vec<Splat>, TraceStats)> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut splats = Vec::new();
            let mut stats = TraceStats::default();
            let end = ((c + 1) * CHUNK).min(settings.photons);
            for i in c * CHUNK..end {
                trace_photon(
                    scene,
                    head,
                    sensor_pose,
                    settings,
                    &sampler,
                    i,
                    &mut splats,
                    &mut stats,
                );
            }
            (splats, stats)
        })
        .collect();
    let cam = &head.camera;
    let spec = cam.spec();
    let image = develop(
        spec.columns,
        spec.rows,
        cam.pixel_area(),
        results.iter().map(|(s, _)| s.as_slice()),
    );
    let mut stats = TraceStats::default();
    for (_, s) in &results {
        stats.add(s);
    }
    (image, stats)
}

#[allow(clippy::too_many_arguments)]
fn trace_photon(
    scene: &TraceScene,
    head: &SensorHead,
    sensor_pose: &Pose,
    settings: &TraceSettings,
    sampler: &PoseSampler,
    i: u64,
    splats: &mut Vec<Splat>,
    stats: &mut TraceStats,
) {
    let laser = &head.config.laser;
    let cam = &head.camera;
    let spec = cam.spec();
    let flux = laser.power_w / settings.photons as f64;
    stats.photons += 1;

    // Stratify the fan angle over the photon index so every column gets an even share.
    let fan_u = (i as f64 + sampler.uniform(i, 0)) / settings.photons as f64;
    let [b1, b2, l1, l2] = sampler.lattice4(i);
    let ray = laser.sample_ray([fan_u, b1, b2, 0.0]);
    let mut origin: Point3<f64> = sensor_pose * ray.origin;
    let mut dir: Vector3<f64> = sensor_pose.rotation * ray.direction;
    let lens_axis_b = sensor_pose.rotation * cam.axis();
    let inv_pose = sensor_pose.inverse();

    for depth in 0..settings.max_depth {
        let Some(hit) = scene.accel.closest_hit(&origin, &dir, 0.0, FAR_M) else {
            return;
        };
        if depth == 0 {
            stats.laser_hits += 1;
        }
        stats.vertices += 1;
        let SurfaceModel::Lambertian(lambert) = scene.surfaces[hit.material as usize];
        // Shade on the side the light arrives from.
        let wo = -dir;
        let flip = if hit.geometric_normal.dot(&wo) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let ng = hit.geometric_normal * flip;
        let mut ns = hit.shading_normal * flip;
        if ns.dot(&wo) <= 0.0 {
            ns = ng;
        }
        let x = hit.point + ng * RAY_EPSILON_M;

        // Next-event estimation to a point of the aperture.
        let base = 1 + depth * DIMS_PER_BOUNCE;
        let lens_u = if depth == 0 {
            [l1, l2]
        } else {
            [sampler.uniform(i, base), sampler.uniform(i, base + 1)]
        };
        let lens_s = cam.aperture_point(concentric_disk(lens_u));
        let lens_b = sensor_pose * Point3::from(lens_s);
        let to_lens = lens_b - x;
        let dist = to_lens.norm();
        let wi = to_lens / dist;
        let cos_x = ns.dot(&wi);
        let cos_l = -wi.dot(&lens_axis_b);
        if cos_x > 0.0 && cos_l > 0.0 && ng.dot(&wi) > 0.0 {
            stats.connections += 1;
            if scene.accel.occluded(&x, &wi, 0.0, dist * (1.0 - 1e-9)) {
                stats.occluded += 1;
            } else {
                let p_s = inv_pose * hit.point;
                let contribution =
                    flux * lambert.f(&ns, &wo, &wi) * cos_x * cos_l * cam.aperture_area()
                        / (dist * dist);
                match cam.image_point(&p_s.coords, &lens_s) {
                    Some([c, r])
                        if c >= 0.0
                            && r >= 0.0
                            && (c as usize) < spec.columns
                            && (r as usize) < spec.rows =>
                    {
                        splats.push(Splat {
                            pixel: (r as usize * spec.columns + c as usize) as u32,
                            flux: contribution,
                        });
                        stats.flux_on_sensor_w += contribution;
                    }
                    _ => stats.off_sensor += 1,
                }
            }
        }

        // Continue with Russian roulette on the albedo: survivors keep their flux.
        if sampler.uniform(i, base + 4) >= lambert.albedo {
            return;
        }
        if depth + 1 == settings.max_depth {
            stats.truncated += 1;
            stats.truncated_power_w += flux;
            return;
        }
        let (wi, _pdf) = lambert.sample_wi(
            &ns,
            [sampler.uniform(i, base + 2), sampler.uniform(i, base + 3)],
        );
        if wi.dot(&ng) <= 0.0 {
            return;
        }
        origin = x;
        dir = wi;
    }
}
