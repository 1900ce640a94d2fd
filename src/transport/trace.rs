//! The light tracer (see the module documentation of `transport` for the estimator).

use nalgebra::{Point3, Vector3};
use rayon::prelude::*;

use super::connect::{connect, VertexOnSurface};
use super::fan_focus::FanFocus;
use super::film::{Film, Irradiance, Splat};
use super::interaction::{scatter_rough, scatter_smooth, RoughVertex, SmoothOutcome};
use super::lens::Aperture;
use super::scene::{GlassSurface, SurfaceModel, TraceScene};
use crate::geometry::accel::Hit;
use crate::geometry::mesh::SurfacePart;
use crate::geometry::pose::Pose;
use crate::optics::lambert::Lambertian;
use crate::optics::polarization::Stokes;
use crate::optics::uniform_stream::{KeyedStream, UniformSource};
use crate::optics::warp::concentric_disk;
use crate::sampler::PoseSampler;
use crate::sensor::path_class::PathClass;
use crate::sensor::projector::{LaserRaySampler, Polarization};
use crate::sensor::SensorHead;

/// Photons per work unit. Fixed (not derived from the thread count) so that results do not
/// depend on how many threads run.
const CHUNK: u64 = 4096;

/// Photons whose laser rays are traced together before their walks (`Tracer::trace_photons`):
/// one bundle of `SceneAccel::closest_hits`, small enough for the photons and hits to stay in
/// the L1 and L2 caches.
const PRIMARY_GROUP: usize = 64;

/// Longest ray considered (m).
const FAR_M: f64 = 100.0;

/// The photon count per pose that every command (and the Python package) uses unless told
/// otherwise: the smallest power of two that passes the convergence test of
/// `study::convergence` on the shipped pane at 10° and 40° (validation/results/convergence/),
/// with the photons focused on the edge (`transport::fan_focus`; 2²⁰ without). At 45° its
/// profiles are within the test's bound but its BIPs are not converged by every criterion,
/// and the count that would be (2²¹ on the car window, more on the pane) costs 5–10× as much.
pub const DEFAULT_PHOTONS: u64 = 1 << 18;

/// Settings of one rendering.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TraceSettings {
    /// Laser photons per pose, ≥ 1; with `adaptive`, the most a pose may take.
    pub photons: u64,
    /// Whether each pose stops at the first photon set after which its BIPs have converged
    /// (`scan::adaptive`; used by `scan::simulate::trace_pose`, not by `render`).
    pub adaptive: bool,
    /// Largest number of surface interactions per photon path (≥ 1), specular ones included.
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
    /// Surface interactions (all depths, specular included).
    pub vertices: u64,
    /// Fresnel reflections at smooth glass.
    pub reflections: u64,
    /// Refractions at smooth glass.
    pub refractions: u64,
    /// Total internal reflections.
    pub tir: u64,
    /// Camera connections attempted (vertex facing the sampled lens point).
    pub connections: u64,
    /// Connections through glass (solved specular chains).
    pub connections_through_glass: u64,
    /// Connections that found no unblocked path (camera-side shadows).
    pub occluded: u64,
    /// Connections whose chains through glass were not solved because the scene's deviation
    /// bound shows that none can land on the pixel grid (`transport::deviation`).
    pub connections_culled: u64,
    /// Contributions that landed off the pixel grid.
    pub off_sensor: u64,
    /// Photons that entered the aperture along a purely specular chain (glints).
    pub glints: u64,
    /// Paths cut while still carrying power: at `max_depth`, trapped light far from the view
    /// (`TRAPPED_LIGHT_CUT_MARGIN_M`), or totally reflected inside a pane that traps it
    /// (`ends_at_total_reflection`).
    pub truncated: u64,
    /// Photons ended by the Russian roulette far from the camera's view.
    pub rouletted: u64,
    /// Total flux splatted on the sensor (W).
    pub flux_on_sensor_w: f64,
    /// Power of the paths cut (W): an upper bound on the bias of the cuts.
    pub truncated_power_w: f64,
    /// Power absorbed in glass (W).
    pub absorbed_w: f64,
}

impl TraceStats {
    /// A path cut while it still carried `power_w` (W): at `max_depth` or by the trapped-light
    /// cuts, the biases `truncated_power_w` bounds.
    fn count_cut(&mut self, power_w: f64) {
        self.truncated += 1;
        self.truncated_power_w += power_w;
    }

    fn add(&mut self, o: &TraceStats) {
        self.photons += o.photons;
        self.laser_hits += o.laser_hits;
        self.vertices += o.vertices;
        self.reflections += o.reflections;
        self.refractions += o.refractions;
        self.tir += o.tir;
        self.connections += o.connections;
        self.connections_through_glass += o.connections_through_glass;
        self.occluded += o.occluded;
        self.connections_culled += o.connections_culled;
        self.off_sensor += o.off_sensor;
        self.glints += o.glints;
        self.truncated += o.truncated;
        self.rouletted += o.rouletted;
        self.flux_on_sensor_w += o.flux_on_sensor_w;
        self.truncated_power_w += o.truncated_power_w;
        self.absorbed_w += o.absorbed_w;
    }
}

/// Russian roulette far from the view plays where a photon meets a surface more than this far
/// from the region the camera looks at (`Aperture::far_from_view`): 50 mm, beyond what the
/// camera sees of the laser plane's neighbourhood through its lens at the triangulation angle.
const ROULETTE_MARGIN_M: f64 = 0.05;

/// The roulette's margin for a photon that has been reflected inside glass without being
/// trapped (a partial reflection at a face, or the rough edge's back-scatter): 10 mm. Such
/// light leaves the pane again and lights the table as a faint ghost of the line; thinned in
/// view, its 8× survivors made spurious profile points that the highest-point BIP picked
/// (on the default study, 14 mm mean error at 40° against 0.09 mm), so it is thinned only
/// off the view (benches/README.md, 2026-12-04 and 2026-12-05).
const REFLECTED_INSIDE_ROULETTE_MARGIN_M: f64 = 0.01;

/// Light trapped by total internal reflection in curved glass (a flat pane or one bent on a
/// cylinder ends it at once: `ends_at_total_reflection`) that survived the roulette ends where
/// it first meets a surface this far from the view (`Aperture::far_from_view`; the margin of
/// partial internal reflections' roulette too), its power counted in
/// `TraceStats::truncated_power_w`. The bias, measured on edge_study_bare at 45° and
/// car_side_window (2²⁰ photons, 4 poses each, same seed with and without the cut):
/// 1.8·10⁻⁴–1.4·10⁻³ and 1·10⁻⁵–2·10⁻⁴ of the light on the sensor, 87–348 pixels of 532,480
/// changed, single pixels by up to full scale (the removed light arrives as the 8× survivors'
/// rare spikes), profile points moved by at most 4.2 µm in at most 3 columns of 640 and one
/// point of 2,560 changed validity; the convergence test's verdicts are unchanged and the
/// default study lost spurious highest-point BIPs (benches/README.md, 2026-12-06: trapped light
/// cut far from the view; measured before flat and cylindrical panes ended such light at
/// once). At 50 mm the cut saved half as many vertices.
const TRAPPED_LIGHT_CUT_MARGIN_M: f64 = 0.01;

/// The survival probability of that roulette: a survivor carries 8× its flux, so a rare one
/// that comes back into view adds a spike (in single pixels up to full scale, measured
/// 2026-12-06); trapped survivors are cut 10 mm off the view (`TRAPPED_LIGHT_CUT_MARGIN_M`).
const ROULETTE_SURVIVAL: f64 = 0.125;

/// Key word of the roulette's own random stream.
const ROULETTE_KEY: u64 = 0x726f_756c_6574_7465;

/// Chunks traced in parallel before their splats are summed: 1 M photons' worth, so a batch's
/// splats take tens of megabytes whatever the photon count.
const CHUNKS_PER_BATCH: u64 = 256;

/// Photons of a rendering's first set; every later set doubles the count so far.
pub const FIRST_PHOTON_SET: u64 = 1 << 16;

/// How a rendering's photons split into sets, each stratified over the laser fan on its own.
///
/// A set's photons take the fan positions (k + u)/size, k = 0..size, paired with a Kronecker
/// lattice over the beam and the aperture (`PoseSampler::lattice4`), so each set covers the fan
/// evenly and the photons of a column are well spread. A fixed photon count is one set. A
/// rendering that grows (the adaptive count, `TraceSettings::adaptive`) takes the sets [0, F),
/// [F, 2F), [2F, 4F), …, F = `FIRST_PHOTON_SET`, the last one ending at its count, so it can
/// stop after any set and add the next without re-tracing; up to F photons both are the same.
#[derive(Clone, Copy, Debug)]
struct PhotonSets {
    /// The rendering's photon count.
    total: u64,
    /// Doubling sets (a growing rendering) instead of one.
    doubling: bool,
}

/// The set photon `i` belongs to.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PhotonSet {
    index: u32,
    start: u64,
    size: u64,
}

impl PhotonSets {
    /// The set of photon `i` (< total).
    fn of(&self, i: u64) -> PhotonSet {
        let (index, start, end) = if !self.doubling {
            (0, 0, self.total)
        } else if i < FIRST_PHOTON_SET {
            (0, 0, FIRST_PHOTON_SET)
        } else {
            // Set k ≥ 1 spans [F·2^(k−1), F·2^k).
            let k = (i / FIRST_PHOTON_SET).ilog2() + 1;
            (k, FIRST_PHOTON_SET << (k - 1), FIRST_PHOTON_SET << k)
        };
        PhotonSet {
            index,
            start,
            size: end.min(self.total) - start,
        }
    }

    /// Whether a rendering may stop after `n` photons and later grow: n ends a set whatever the
    /// final count (0, F, 2F, 4F, …).
    fn is_boundary(n: u64) -> bool {
        n == 0 || (n % FIRST_PHOTON_SET == 0 && (n / FIRST_PHOTON_SET).is_power_of_two())
    }
}

/// The least probability of a smooth face's imperfection connection (`Tracer::glass_vertex`):
/// 25 times the shipped scenes' face_imperfection of 0.002, so their face returns get 25 times
/// the samples for about 0.1 more connections per photon.
pub const IMPERFECTION_CONNECTION_RATE: f64 = 0.05;

/// The random numbers of one vertex, each drawn when it is first needed. Every one is a pure
/// function of (seed, pose, photon, dimension), so drawing only those a vertex uses (a smooth
/// face needs three of the eight dimensions and no microfacet stream) changes none of them.
#[derive(Clone, Copy)]
struct VertexUniforms {
    sampler: PoseSampler,
    photon: u64,
    /// The vertex's first sampler dimension.
    base: u32,
    /// At the laser's first hit, the lattice's aperture point (`Tracer::emit`).
    first_lens: Option<[f64; 2]>,
    /// Key of the microfacet walks' stream: (seed, pose, photon, depth).
    walk_key: [u64; 4],
}

impl VertexUniforms {
    fn u(&self, k: u32) -> f64 {
        self.sampler.uniform(self.photon, self.base + k)
    }

    /// The aperture point of the camera connection (unit square).
    fn lens(&self) -> [f64; 2] {
        self.first_lens.unwrap_or_else(|| [self.u(0), self.u(1)])
    }

    /// The Fresnel split at a smooth face.
    fn fresnel(&self) -> f64 {
        self.u(2)
    }

    /// A diffuse continuation's direction.
    fn diffuse(&self) -> [f64; 2] {
        [self.u(3), self.u(4)]
    }

    /// A smooth face's choice of imperfection scattering.
    fn imperfection(&self) -> f64 {
        self.u(5)
    }

    /// A diffuse surface's Russian roulette on its albedo.
    fn albedo_roulette(&self) -> f64 {
        self.u(6)
    }

    /// A smooth face's choice of an imperfection connection.
    fn imperfection_connection(&self) -> f64 {
        self.u(7)
    }

    /// The rough edge's microfacet walks.
    fn walk(&self) -> KeyedStream {
        KeyedStream::new(&self.walk_key)
    }
}

/// Sampler dimensions used per surface interaction beyond the laser's own.
const DIMS_PER_VERTEX: u32 = 8;

/// Renders the irradiance images (W/m², total and per path class) that the sensor at
/// `sensor_pose` (T_BS) sees, with `settings.photons` photons. `pose_index` keys the random
/// numbers.
pub fn render(
    scene: &TraceScene,
    head: &SensorHead,
    sensor_pose: &Pose,
    settings: &TraceSettings,
    pose_index: u64,
) -> (Irradiance, TraceStats) {
    let mut rendering = Rendering::new(scene, head, sensor_pose, settings, pose_index);
    rendering.trace_to(settings.photons);
    rendering.into_developed()
}

/// A rendering: the photons 0..n traced so far, summed on a film, and developed into images at
/// n (`develop`). With `settings.adaptive` it grows: photons are added a set at a time
/// (`PhotonSets`), photon i takes the same random numbers whatever the final count, and
/// developing after n photons gives what a rendering traced to n at once gives (bit for bit
/// when n is a power of two: the film holds each photon's flux as if it were the only one, and
/// developing divides by n). Without it the photons are one stratified set, traced at once.
pub struct Rendering<'a> {
    scene: &'a TraceScene,
    head: &'a SensorHead,
    sensor_pose: &'a Pose,
    settings: &'a TraceSettings,
    pose_index: u64,
    sampler: PoseSampler,
    film: Film,
    stats: TraceStats,
    traced: u64,
    /// Where the fan's photons are drawn more densely (`None`: the line profile alone).
    focus: Option<FanFocus>,
}

impl<'a> Rendering<'a> {
    /// An empty rendering of the sensor at `sensor_pose` (T_BS); `settings.photons` is not
    /// used (the caller says how many photons to trace), `settings.adaptive` says whether it
    /// can grow.
    pub fn new(
        scene: &'a TraceScene,
        head: &'a SensorHead,
        sensor_pose: &'a Pose,
        settings: &'a TraceSettings,
        pose_index: u64,
    ) -> Self {
        let spec = head.camera.spec();
        Rendering {
            scene,
            head,
            sensor_pose,
            settings,
            pose_index,
            sampler: PoseSampler::new(settings.seed, pose_index),
            film: Film::new(spec.columns, spec.rows),
            stats: TraceStats::default(),
            traced: 0,
            focus: None,
        }
    }

    /// The same rendering with the fan's photons drawn by `focus` (`transport::fan_focus`):
    /// the same images in the mean, less Monte Carlo noise in the focus window, more elsewhere.
    pub fn with_focus(self, focus: Option<FanFocus>) -> Self {
        Rendering { focus, ..self }
    }

    /// Photons traced so far.
    pub fn photons(&self) -> u64 {
        self.traced
    }

    /// Traces photons `self.photons()..n` (nothing if n is not larger). An adaptive rendering
    /// grows in whole photon sets: before a further call, `n` must have been 0, F or F·2^k (F =
    /// `FIRST_PHOTON_SET`); any n can be the last. Any other rendering is traced in one call.
    ///
    /// # Panics
    /// If more photons are added to a rendering that stopped inside a set, or to one that is
    /// not adaptive.
    pub fn trace_to(&mut self, n: u64) {
        if n <= self.traced {
            return;
        }
        let doubling = self.settings.adaptive;
        assert!(
            self.traced == 0 || (doubling && PhotonSets::is_boundary(self.traced)),
            "a rendering of {} photons cannot grow (adaptive: {doubling})",
            self.traced
        );
        let sets = PhotonSets { total: n, doubling };
        // Chunks of CHUNK photons run in parallel a batch at a time and are summed in photon
        // order, so the images are the same for any thread count and memory does not grow with
        // the photon count.
        while self.traced < n {
            let batch_end = n.min(self.traced + CHUNK * CHUNKS_PER_BATCH);
            let starts: Vec<u64> = (self.traced..batch_end).step_by(CHUNK as usize).collect();
            let results: Vec<(Vec<Splat>, TraceStats)> = starts
                .into_par_iter()
                .map(|start| {
                    let mut tracer = Tracer {
                        scene: self.scene,
                        head: self.head,
                        laser_rays: self.head.config.laser.ray_sampler(),
                        aperture: Aperture::new(&self.head.camera, self.sensor_pose),
                        polarization_axis: polarization_axis(self.head, self.sensor_pose),
                        settings: self.settings,
                        sampler: &self.sampler,
                        sets,
                        focus: self.focus,
                        pose_index: self.pose_index,
                        splats: Vec::new(),
                        stats: TraceStats::default(),
                    };
                    tracer.trace_photons(start, (start + CHUNK).min(batch_end));
                    (tracer.splats, tracer.stats)
                })
                .collect();
            for (splats, s) in &results {
                self.film.add(splats);
                self.stats.add(s);
            }
            self.traced = batch_end;
        }
    }

    /// The irradiance images and the counters of the photons traced so far.
    pub fn develop(&self) -> (Irradiance, TraceStats) {
        let per_photon = 1.0 / self.traced.max(1) as f64;
        let image = self.film.develop(self.head.camera.pixel_area(), per_photon);
        (image, self.stats_per_photon(per_photon))
    }

    /// [`Rendering::develop`] at the end of the rendering: the film becomes the images
    /// (`Film::into_irradiance`), bit for bit `develop`'s.
    pub fn into_developed(self) -> (Irradiance, TraceStats) {
        let per_photon = 1.0 / self.traced.max(1) as f64;
        let stats = self.stats_per_photon(per_photon);
        let area = self.head.camera.pixel_area();
        (self.film.into_irradiance(area, per_photon), stats)
    }

    /// The counters, their powers per photon traced.
    fn stats_per_photon(&self, per_photon: f64) -> TraceStats {
        let mut stats = self.stats;
        stats.flux_on_sensor_w *= per_photon;
        stats.truncated_power_w *= per_photon;
        stats.absorbed_w *= per_photon;
        stats
    }
}

/// What a photon carries between interactions.
struct Photon {
    /// Where the current ray starts: the laser's source, then the exact point of the last
    /// interaction (rays are not offset from surfaces; see `SceneAccel::closest_hit_leaving`).
    origin: Point3<f64>,
    /// The triangle the current ray leaves (`None` for the laser's own ray).
    leaving: Option<u32>,
    dir: Vector3<f64>,
    /// Flux (W).
    flux: f64,
    /// Polarisation, normalised to intensity 1.
    stokes: Stokes,
    /// Every interaction so far was specular (a glint candidate).
    all_specular: bool,
    /// The photon has crossed a glass interface.
    crossed_glass: bool,
    /// The photon has been reflected inside glass.
    internal_reflection: bool,
    /// The photon has been totally internally reflected in curved glass (in a flat pane or one
    /// bent on a cylinder it ends there: `ends_at_total_reflection`): it plays the roulette at
    /// its next surface wherever that is.
    trapped: bool,
    /// The photon has been reflected by a glass surface (a face's Fresnel reflection or the
    /// edge's back-scatter), from outside or inside.
    reflected_by_glass: bool,
    /// The photon has passed the Russian roulette far from the view (it plays once).
    rouletted: bool,
}

impl Photon {
    /// Continues from the exact hit point along `dir`.
    fn leave(&mut self, hit: &Hit, dir: Vector3<f64>) {
        self.origin = hit.point;
        self.leaving = Some(hit.triangle);
        self.dir = dir;
    }
}

/// A non-specular vertex that can connect to the camera.
enum Connectable {
    /// Ideal diffuse reflection into the hemisphere of `n` (opaque surfaces, face dust).
    Diffuse { n: Vector3<f64>, albedo: f64 },
    /// The rough glass edge.
    Rough(RoughVertex),
}

/// The polarisation axis of the laser of `head` at `sensor_pose`, in the base frame (`None`:
/// unpolarised): the same for every photon of a pose.
fn polarization_axis(head: &SensorHead, sensor_pose: &Pose) -> Option<Vector3<f64>> {
    match head.config.laser.polarization {
        Polarization::Linear { angle_rad } => {
            let axis = Vector3::new(angle_rad.cos(), angle_rad.sin(), 0.0);
            Some(sensor_pose.rotation * axis)
        }
        Polarization::Unpolarized => None,
    }
}

struct Tracer<'a> {
    scene: &'a TraceScene,
    head: &'a SensorHead,
    /// The laser's rays (`head`'s laser sheet, its shared terms computed once).
    laser_rays: LaserRaySampler,
    aperture: Aperture<'a>,
    settings: &'a TraceSettings,
    sampler: &'a PoseSampler,
    /// The laser's polarisation axis in the base frame, `None` for an unpolarised laser.
    polarization_axis: Option<Vector3<f64>>,
    sets: PhotonSets,
    focus: Option<FanFocus>,
    /// Keys the rough edge's microsurface walks with the seed and the photon.
    pose_index: u64,
    splats: Vec<Splat>,
    stats: TraceStats,
}

impl Tracer<'_> {
    /// Traces photons `start..end` in order, a group at a time: the group's laser rays first,
    /// as one bundle (`SceneAccel::closest_hits`: the fan's rays are coherent, and a bundle of
    /// them costs a fraction of as many single rays), then each photon's walk from its first
    /// hit.
    /// The hits are each ray's own bit for bit and every random number is keyed by the photon,
    /// so the result is that of tracing the photons one by one.
    fn trace_photons(&mut self, start: u64, end: u64) {
        let mut emitted = Vec::with_capacity(PRIMARY_GROUP);
        let mut rays = Vec::with_capacity(PRIMARY_GROUP);
        let mut hits = Vec::with_capacity(PRIMARY_GROUP);
        let mut group = start;
        while group < end {
            let group_end = end.min(group + PRIMARY_GROUP as u64);
            emitted.clear();
            emitted.extend((group..group_end).map(|i| self.emit(i)));
            rays.clear();
            rays.extend(emitted.iter().map(|(p, _)| (p.origin, p.dir)));
            self.scene.accel.closest_hits(&rays, 0.0, FAR_M, &mut hits);
            for ((i, (photon, lens)), hit) in (group..).zip(emitted.drain(..)).zip(hits.drain(..)) {
                self.walk(i, photon, lens, hit);
            }
            group = group_end;
        }
    }

    /// Photon `i` as the laser emits it, and the lens sample of its first vertex.
    fn emit(&mut self, i: u64) -> (Photon, [f64; 2]) {
        let laser = &self.head.config.laser;
        let pose = self.aperture.sensor_pose;
        self.stats.photons += 1;

        // Stratify the fan angle over the photon's set so every column gets an even share.
        let set = self.sets.of(i);
        let k = i - set.start;
        let fan_u = (k as f64 + self.sampler.uniform(i, 0)) / set.size as f64;
        let (fan_u, focus_weight) = self.focus.map_or((fan_u, 1.0), |f| f.warp(fan_u));
        let [b1, b2, l1, l2] = self.sampler.lattice4(k, set.index);
        let ray = self.laser_rays.sample_ray([fan_u, b1, b2, 0.0]);
        let dir = pose.rotation * ray.direction;
        let stokes = match self.polarization_axis {
            Some(axis) => Stokes::linear(&dir, &axis),
            None => Stokes::unpolarized(&dir),
        };
        let photon = Photon {
            origin: pose * ray.origin,
            leaving: None,
            dir,
            // As if it were the only photon: `Rendering::develop` divides by the count.
            flux: ray.weight * focus_weight * laser.power_w,
            stokes,
            all_specular: true,
            crossed_glass: false,
            internal_reflection: false,
            trapped: false,
            reflected_by_glass: false,
            rouletted: false,
        };
        (photon, [l1, l2])
    }

    /// Follows photon `i`, as [`Tracer::emit`] made it, from `first_hit`, its laser ray's
    /// closest hit (`closest_hit(origin, dir, 0, FAR_M)`).
    fn walk(&mut self, i: u64, mut photon: Photon, [l1, l2]: [f64; 2], first_hit: Option<Hit>) {
        for depth in 0..self.settings.max_depth {
            let accel = &self.scene.accel;
            let hit = match photon.leaving {
                _ if depth == 0 => first_hit,
                None => accel.closest_hit(&photon.origin, &photon.dir, 0.0, FAR_M),
                Some(tri) => {
                    self.scene
                        .closest_hit_leaving(&photon.origin, &photon.dir, tri, FAR_M)
                }
            };
            if photon.all_specular && depth > 0 {
                let t_max = hit.as_ref().map_or(FAR_M, |h| h.t);
                if let Some(p) = self.aperture.enters(&photon.origin, &photon.dir, t_max) {
                    self.glint(&photon, &p);
                    return;
                }
            }
            let Some(hit) = hit else { return };
            if depth == 0 {
                self.stats.laser_hits += 1;
            }
            // Russian roulette, once per photon: at its first surface after a total internal
            // reflection in curved glass (in a flat or cylindrical pane such light has ended
            // there: `ends_at_total_reflection`), or else where it first meets a surface far
            // from the camera's view (the table beyond the view; light a pane reflected
            // partially from inside, 10 mm off). It continues with probability
            // ROULETTE_SURVIVAL and its flux divided by it, so every estimate keeps its mean
            // (Arvo & Kirk, "Particle transport and image synthesis", SIGGRAPH 1990). Its own
            // keyed stream leaves every other random number as it was. Trapped light shows the
            // camera only the faint glow of face imperfections but made 42 % of the vertices,
            // most of them in view; why partial reflections are not thinned in view:
            // ARCHITECTURE.md, light transport, step 7.
            let margin = if photon.internal_reflection {
                REFLECTED_INSIDE_ROULETTE_MARGIN_M
            } else {
                ROULETTE_MARGIN_M
            };
            if !photon.rouletted
                && (photon.trapped || self.aperture.far_from_view(&hit.point, margin))
            {
                photon.rouletted = true;
                let u = KeyedStream::new(&[
                    self.settings.seed,
                    self.pose_index,
                    i,
                    depth as u64,
                    ROULETTE_KEY,
                ])
                .next_uniform();
                if u >= ROULETTE_SURVIVAL {
                    self.stats.rouletted += 1;
                    return;
                }
                photon.flux /= ROULETTE_SURVIVAL;
            } else if photon.trapped
                && self
                    .aperture
                    .far_from_view(&hit.point, TRAPPED_LIGHT_CUT_MARGIN_M)
            {
                // A survivor of that roulette ends off the view: a stated bias, like max_depth
                // (TRAPPED_LIGHT_CUT_MARGIN_M says why and how large).
                self.stats.count_cut(photon.flux);
                return;
            }
            self.stats.vertices += 1;
            let u = VertexUniforms {
                sampler: *self.sampler,
                photon: i,
                base: 1 + depth * DIMS_PER_VERTEX,
                first_lens: (depth == 0).then_some([l1, l2]),
                walk_key: [self.settings.seed, self.pose_index, i, depth as u64],
            };
            let alive = match self.scene.surfaces[hit.material as usize] {
                SurfaceModel::Lambertian(l) => self.opaque_vertex(&mut photon, &hit, l, u),
                SurfaceModel::Glass(g) => self.glass_vertex(&mut photon, &hit, &g, u),
            };
            if !alive {
                return;
            }
            if depth + 1 == self.settings.max_depth {
                self.stats.count_cut(photon.flux);
            }
        }
    }

    /// A Lambertian surface: connect, then continue with Russian roulette on the albedo.
    fn opaque_vertex(
        &mut self,
        photon: &mut Photon,
        hit: &Hit,
        lambert: Lambertian,
        u: VertexUniforms,
    ) -> bool {
        let (ng, ns) = facing_normals(hit, &photon.dir);
        // Light that crossed glass is seen where the glass put it; light that glass reflected
        // onto the surface lights it off the laser plane; only the rest is a direct return.
        let class = if photon.crossed_glass {
            PathClass::ThroughGlass
        } else if photon.reflected_by_glass {
            PathClass::GlassReflected
        } else {
            self.scene.direct_class[hit.object as usize]
        };
        self.connect_vertex(
            photon,
            hit,
            &Connectable::Diffuse {
                n: ns,
                albedo: lambert.albedo,
            },
            class,
            false,
            u.lens(),
        );
        photon.all_specular = false;
        if u.albedo_roulette() >= lambert.albedo {
            return false;
        }
        self.continue_diffuse(photon, hit, &ng, &ns, u.diffuse())
    }

    fn continue_diffuse(
        &mut self,
        photon: &mut Photon,
        hit: &Hit,
        ng: &Vector3<f64>,
        ns: &Vector3<f64>,
        u2: [f64; 2],
    ) -> bool {
        let (wi, _) = Lambertian { albedo: 1.0 }.sample_wi(ns, u2);
        if wi.dot(ng) <= 0.0 {
            return false;
        }
        photon.leave(hit, wi);
        photon.stokes = Stokes::unpolarized(&wi);
        true
    }

    /// A glass surface: the rough edge's microfacet scattering, or at a smooth face the
    /// imperfections' diffuse connection and then imperfection scattering or the Fresnel split.
    fn glass_vertex(
        &mut self,
        photon: &mut Photon,
        hit: &Hit,
        glass: &GlassSurface,
        u: VertexUniforms,
    ) -> bool {
        let entering = photon.dir.dot(&hit.geometric_normal) < 0.0;
        if !entering {
            let kept = (-glass.absorption_per_m * hit.t).exp();
            self.stats.absorbed_w += photon.flux * (1.0 - kept);
            photon.flux *= kept;
        }
        let rough_edge = hit.part == SurfacePart::Edge && glass.edge_alpha > 0.0;
        if rough_edge {
            let vertex = RoughVertex::new(hit, glass, &photon.dir, u.walk());
            self.connect_vertex(
                photon,
                hit,
                &Connectable::Rough(vertex),
                PathClass::GlassEdge,
                true,
                u.lens(),
            );
            photon.all_specular = false;
            return match scatter_rough(&vertex, &mut photon.stokes) {
                Some(s) => {
                    photon.flux *= s.weight;
                    photon.leave(hit, s.wi);
                    if s.transmitted {
                        photon.crossed_glass = true;
                    } else {
                        photon.reflected_by_glass = true;
                        if !entering {
                            photon.internal_reflection = true;
                        }
                    }
                    true
                }
                None => false,
            };
        }
        // Imperfections scatter a fraction p = face_imperfection of the light diffusely back
        // into the incident side (albedo 1). Their camera connection is made with probability
        // q = max(p, IMPERFECTION_CONNECTION_RATE) and weight p/q, on its own uniform, so its
        // mean is p times the diffuse connection's, as if the scattering had been picked
        // (probability p, weight 1), with q/p times the samples: the faint face returns, a few
        // photons per column otherwise, are what the profile's face points and the edge-line
        // rule's climb rest on. The photon's continuation is still picked with probability p,
        // without a second connection. (The Bernoulli choice of the connection importance-
        // sampled with q instead of p: splitting of the faint term, as Arvo & Kirk 1990 pair
        // with the Russian roulette above.)
        let p = glass.face_imperfection;
        let q = p.max(IMPERFECTION_CONNECTION_RATE);
        if p > 0.0 && u.imperfection_connection() < q {
            let (_, ns) = facing_normals(hit, &photon.dir);
            let class = if photon.internal_reflection {
                PathClass::InternalReflection
            } else {
                PathClass::GlassFace
            };
            // Albedo 1, times the weight p/q.
            self.connect_vertex(
                photon,
                hit,
                &Connectable::Diffuse {
                    n: ns,
                    albedo: p / q,
                },
                class,
                true,
                u.lens(),
            );
        }
        if u.imperfection() < p {
            let (ng, ns) = facing_normals(hit, &photon.dir);
            photon.all_specular = false;
            return self.continue_diffuse(photon, hit, &ng, &ns, u.diffuse());
        }
        match scatter_smooth(hit, glass, &photon.dir, &mut photon.stokes, u.fresnel()) {
            SmoothOutcome::Reflected { dir, tir } => {
                self.stats.reflections += 1;
                if tir {
                    self.stats.tir += 1;
                    if ends_at_total_reflection(self.scene, hit) {
                        self.stats.count_cut(photon.flux);
                        return false;
                    }
                    photon.trapped = true;
                }
                if !entering {
                    photon.internal_reflection = true;
                }
                photon.reflected_by_glass = true;
                photon.leave(hit, dir);
                true
            }
            SmoothOutcome::Transmitted { dir } => {
                self.stats.refractions += 1;
                photon.crossed_glass = true;
                photon.leave(hit, dir);
                true
            }
            SmoothOutcome::Absorbed => false,
        }
    }

    /// Next-event estimation from a non-specular vertex to a sampled point of the aperture.
    fn connect_vertex(
        &mut self,
        photon: &Photon,
        hit: &Hit,
        vertex: &Connectable,
        class: PathClass,
        on_glass: bool,
        lens_u: [f64; 2],
    ) {
        let lens_point = self.aperture.point(concentric_disk(lens_u));
        let vertex_on_surface = VertexOnSurface {
            point: hit.point,
            ng: hit.geometric_normal,
            triangle: hit.triangle,
        };
        let connections = connect(
            self.scene,
            &self.aperture,
            &vertex_on_surface,
            on_glass,
            &lens_point,
        );
        self.stats.connections += 1;
        if connections.culled {
            self.stats.connections_culled += 1;
        } else if connections.found.iter().all(Option::is_none) {
            self.stats.occluded += 1;
        }
        for c in connections.found.into_iter().flatten() {
            let f_cos = match vertex {
                Connectable::Diffuse { n, albedo } => {
                    let cos = n.dot(&c.dir);
                    if cos <= 0.0 {
                        continue;
                    }
                    albedo / std::f64::consts::PI * cos
                }
                Connectable::Rough(v) => v.f_cos(&photon.stokes, &c.dir),
            };
            if f_cos <= 0.0 {
                continue;
            }
            if c.end.crossed_glass {
                self.stats.connections_through_glass += 1;
            }
            let class = if c.end.crossed_glass && !on_glass {
                PathClass::ThroughGlass
            } else {
                class
            };
            let flux = photon.flux * f_cos * self.aperture.area() * c.dw_da * c.end.transmittance;
            self.splat(&lens_point, &c.end.dir, flux, class);
        }
    }

    fn glint(&mut self, photon: &Photon, lens_point: &Point3<f64>) {
        self.stats.glints += 1;
        self.splat(lens_point, &photon.dir, photon.flux, PathClass::Glint);
    }

    fn splat(&mut self, lens_point: &Point3<f64>, dir: &Vector3<f64>, flux: f64, class: PathClass) {
        let spec = self.head.camera.spec();
        match self.aperture.image_of_ray(lens_point, dir) {
            Some([c, r])
                if c >= 0.0
                    && r >= 0.0
                    && (c as usize) < spec.columns
                    && (r as usize) < spec.rows =>
            {
                self.splats.push(Splat {
                    pixel: (r as usize * spec.columns + c as usize) as u32,
                    class,
                    flux,
                });
                self.stats.flux_on_sensor_w += flux;
            }
            _ => self.stats.off_sensor += 1,
        }
    }
}

/// Whether light totally reflected at `hit` ends there: inside a pane that traps it
/// (`TraceScene::traps_light`: faces parallel to one plane, or on cylinders about one axis
/// within 1 % in radius; a rough edge; no other glass within its bounding box), where the faces
/// keep it inside and it leaves only through a face imperfection or the rough edge, as the
/// pane's faint glow, or, in a bent pane, through a face if its first reflection lay within
/// the window of `cylinder_pane` just above the critical angle. Its power is counted in
/// `TraceStats::truncated_power_w`: a stated bias, like `max_depth`. Followed (1/8 of it, ×8,
/// by the roulette, until 10 mm off the view: `TRAPPED_LIGHT_CUT_MARGIN_M`, which still holds
/// in other curved glass), it made 15 % of the vertices on edge_study_bare at 45° for
/// 1.3·10⁻⁴ of the light on the sensor, and 16 % on car_side_window at 45° for 2.5·10⁻⁴,
/// mostly as the survivors' spikes. What ending it changes, measured on the same seeds:
/// benches/README.md (2026-12-07, trapped light in flat panes ends; 2026-12-07, morning, and
/// in panes bent on a cylinder).
fn ends_at_total_reflection(scene: &TraceScene, hit: &Hit) -> bool {
    scene.traps_light[hit.object as usize]
}

/// Geometric and shading normals turned towards the side the light arrives from.
fn facing_normals(hit: &Hit, dir: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let flip = if hit.geometric_normal.dot(dir) > 0.0 {
        -1.0
    } else {
        1.0
    };
    let ng = hit.geometric_normal * flip;
    let ns = hit.shading_normal * flip;
    (ng, if ns.dot(&-dir) > 0.0 { ns } else { ng })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn photon_sets_double_the_count_and_the_last_ends_at_the_total() {
        const F: u64 = FIRST_PHOTON_SET;
        let set = |total: u64, i: u64| {
            PhotonSets {
                total,
                doubling: true,
            }
            .of(i)
        };
        // A rendering that does not grow is one set.
        let one = PhotonSets {
            total: 5 * F + 3,
            doubling: false,
        };
        let all = PhotonSet {
            index: 0,
            start: 0,
            size: 5 * F + 3,
        };
        assert_eq!(one.of(3 * F), all);
        let whole = |index, start, size| PhotonSet { index, start, size };
        // A count of F or less is one set: the single stratified run.
        assert_eq!(set(1000, 999), whole(0, 0, 1000));
        assert_eq!(set(F, 0), whole(0, 0, F));
        // Then [F, 2F), [2F, 4F), [4F, 8F), …
        assert_eq!(set(8 * F, F), whole(1, F, F));
        assert_eq!(set(8 * F, 2 * F - 1), whole(1, F, F));
        assert_eq!(set(8 * F, 2 * F), whole(2, 2 * F, 2 * F));
        assert_eq!(set(8 * F, 8 * F - 1), whole(3, 4 * F, 4 * F));
        // A count between boundaries ends its last set early; earlier sets are unchanged.
        assert_eq!(set(5 * F, 4 * F), whole(3, 4 * F, F));
        assert_eq!(set(5 * F, 3 * F), whole(2, 2 * F, 2 * F));
        // Where a rendering may stop and grow again.
        for n in [0, F, 2 * F, 4 * F, 1 << 30] {
            assert!(PhotonSets::is_boundary(n), "{n}");
        }
        for n in [1, F - 1, 3 * F, 5 * F, F + 1] {
            assert!(!PhotonSets::is_boundary(n), "{n}");
        }
    }
}
