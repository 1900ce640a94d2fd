//! `Scene`: a scene file loaded once (BVH, sensor head), simulated at its planned scan poses,
//! located and registered against, as the `scan`, `locate` and `register` commands do.

use std::path::{Path, PathBuf};

use glassscan::cli::embed::{self, SceneOverrides};
use glassscan::cli::CliError;
use glassscan::dataset::ideal_profile::ideal_profile;
use glassscan::dataset::sample::PreparedWorld;
use glassscan::limits::MAX_LENGTH_MM;
use glassscan::scan::adaptive::StopRules;
use glassscan::scan::locate::laser_plane_crossing;
use glassscan::scan::poses::{plan_border_scan, ScanPose};
use glassscan::scan::simulate::simulate_pose;
use glassscan::scan::warnings::pose_warnings;
use glassscan::scene::{self, World};
use glassscan::shipped;
use glassscan::transport::TraceSettings;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::error::{input, to_py};

/// A loaded scene: its objects, sensor and scan settings, with the BVH built.
#[pyclass(module = "glassscan._native", frozen)]
pub struct Scene {
    prepared: PreparedWorld,
    /// The scan poses of `scan` along the target's border (empty without a target).
    poses: Vec<ScanPose>,
}

impl Scene {
    fn new(py: Python<'_>, mut world: World, overrides: &SceneOverrides) -> PyResult<Scene> {
        embed::apply_overrides(&mut world, overrides).map_err(to_py)?;
        // The BVH build is the long part: other Python threads may run meanwhile.
        let prepared = py
            .detach(|| PreparedWorld::new(world))
            .map_err(|e| input(anyhow::anyhow!(e)))?;
        let world = &prepared.world;
        let poses = match world.true_border_in_base() {
            Some(border) => plan_border_scan(&border, &world.scan, &world.mount),
            None => Vec::new(),
        };
        Ok(Scene { prepared, poses })
    }

    fn world(&self) -> &World {
        &self.prepared.world
    }
}

#[pymethods]
impl Scene {
    /// The scene file at `path` (or a shipped scene's name, e.g. "edge_study"), or the TOML `text` (then `path` names it in messages and
    /// anchors relative mesh paths); the keywords override its settings as `scan`'s flags do.
    #[staticmethod]
    #[pyo3(signature = (path, text=None, *, scan_angle_deg=None, poses=None, exposure_ms=None, threshold=None, peak_select=None, sensor_kind=None))]
    #[allow(clippy::too_many_arguments)]
    fn open(
        py: Python<'_>,
        path: PathBuf,
        text: Option<&str>,
        scan_angle_deg: Option<f64>,
        poses: Option<usize>,
        exposure_ms: Option<f64>,
        threshold: Option<String>,
        peak_select: Option<String>,
        sensor_kind: Option<String>,
    ) -> PyResult<Scene> {
        let world = match text {
            // A path that exists, else a shipped scene's name, as the command line's SCENE.
            None => scene::load(&shipped::resolve_scene(&path).map_err(input)?),
            Some(text) => scene::load_str(&path, text),
        }
        .map_err(input)?;
        let overrides = SceneOverrides {
            scan_angle_deg,
            poses,
            exposure_ms,
            threshold,
            peak_select,
            sensor_kind,
        };
        Scene::new(py, world, &overrides)
    }

    /// The scene file (or the name given to `from_toml`).
    #[getter]
    fn path(&self) -> PathBuf {
        self.world().source.clone()
    }

    /// The scene loader's warnings (e.g. a mesh of implausible size, naming `scale`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.world().warnings.clone()
    }

    /// The target object's name, or None.
    #[getter]
    fn target(&self) -> Option<String> {
        let w = self.world();
        w.target.as_ref().map(|t| w.objects[t.object].name.clone())
    }

    /// Scan angle (deg), exposure (ms), planned poses, image shape and ADC bits.
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let w = self.world();
        let spec = self.prepared.head.camera.spec();
        let d = PyDict::new(py);
        d.set_item("scan_angle_deg", w.scan.scan_angle_rad.to_degrees())?;
        d.set_item("standoff_mm", w.scan.standoff_m * 1e3)?;
        d.set_item("poses", w.scan.poses)?;
        d.set_item("exposure_ms", w.sensor.imager.exposure_s * 1e3)?;
        d.set_item("wavelength_nm", w.sensor.laser.wavelength_m * 1e9)?;
        d.set_item("adc_bits", w.sensor.imager.adc_bits)?;
        d.set_item("image_shape", (spec.rows, spec.columns))?;
        d.set_item("points_per_profile", w.sensor.firmware.points_per_profile)?;
        Ok(d)
    }

    /// The planned scan poses: index, sensor and flange poses (4 × 4, mm), p_e and its place
    /// along the border.
    fn scan_poses<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.poses
            .iter()
            .map(|p| {
                let d = PyDict::new(py);
                d.set_item("index", p.index)?;
                d.set_item("sensor_pose", arrays::pose_matrix(py, &p.sensor))?;
                d.set_item("flange_pose", arrays::pose_matrix(py, &p.flange))?;
                let e = p.edge_point * 1e3;
                d.set_item("edge_point_mm", [e.x, e.y, e.z])?;
                d.set_item("border_fraction", p.border_fraction)?;
                Ok(d)
            })
            .collect()
    }

    /// Simulates scan pose `pose` as `scan` does (same seed, same numbers).
    #[pyo3(signature = (pose, *, photons=None, seed, max_depth, threads=None))]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        pose: usize,
        photons: Option<u64>,
        seed: u64,
        max_depth: u32,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (photons, adaptive) = embed::check_light(photons, max_depth).map_err(to_py)?;
        let world = self.world();
        if world.target.is_none() {
            return Err(input(anyhow::anyhow!(
                "{}: the scene has no [target]: `simulate` needs a panel whose border it scans",
                world.source.display()
            )));
        }
        let Some(scan_pose) = self.poses.get(pose) else {
            return Err(input(anyhow::anyhow!(
                "pose {pose} is not a scan pose of {}: it plans {} (indices 0..{})",
                world.source.display(),
                self.poses.len(),
                self.poses.len()
            )));
        };
        if threads == Some(0) {
            return Err(input(anyhow::anyhow!("threads must be ≥ 1, got 0")));
        }
        let settings = TraceSettings {
            photons,
            adaptive,
            max_depth,
            seed,
        };
        let prepared = &self.prepared;
        let work = || {
            let result = simulate_pose(
                &prepared.scene,
                &prepared.head,
                scan_pose,
                &settings,
                StopRules::EDGE_LINE,
            );
            let ideal = ideal_profile(
                world,
                &prepared.scene,
                &prepared.head,
                &scan_pose.sensor,
                world.sensor.firmware.points_per_profile,
            );
            (result, ideal)
        };
        let (result, ideal) = py
            .detach(|| -> Result<_, CliError> {
                match threads {
                    Some(n) => Ok(rayon::ThreadPoolBuilder::new()
                        .num_threads(n)
                        .build()
                        .map_err(CliError::internal)?
                        .install(work)),
                    None => Ok(work()),
                }
            })
            .map_err(to_py)?;

        let d = PyDict::new(py);
        d.set_item("image", arrays::image(py, &result.image))?;
        d.set_item("irradiance", arrays::irradiance(py, &result.irradiance)?)?;
        d.set_item("profile", arrays::profile(py, &result.profile)?)?;
        d.set_item("saturated_pixels", result.saturated_pixels)?;
        d.set_item("warnings", pose_warnings(&result, &world.sensor.range))?;
        let stats =
            serde_json::to_string(&result.stats).map_err(|e| to_py(CliError::internal(e)))?;
        d.set_item("stats_json", stats)?;
        d.set_item("ground_truth", self.ground_truth(py, scan_pose, &ideal)?)?;
        Ok(d)
    }

    /// `glassscan locate` on this scene with the command line's `flags`: its JSON summary.
    fn locate(&self, py: Python<'_>, flags: Vec<String>) -> PyResult<String> {
        let world = self.world().clone();
        let source = world.source.clone();
        let summary = py
            .detach(|| embed::locate(world, &source, &flags))
            .map_err(to_py)?;
        serde_json::to_string(&summary).map_err(|e| to_py(CliError::internal(e)))
    }

    /// `glassscan register` of `points` (N × 3, base frame, mm) to this scene's target from
    /// its nominal pose: its JSON result (`outlier_lines` are row indices here).
    fn register(&self, points: PyReadonlyArray2<'_, f64>) -> PyResult<String> {
        let shape = points.shape();
        if shape.len() != 2 || shape[1] != 3 {
            return Err(input(anyhow::anyhow!(
                "points must be an N × 3 array of x, y, z in mm, got shape {shape:?}"
            )));
        }
        let a = points.as_array();
        let rows: Vec<(usize, [f64; 3])> = a
            .rows()
            .into_iter()
            .enumerate()
            .map(|(i, r)| (i, [r[0], r[1], r[2]]))
            .collect();
        // As `glassscan register` reads its CSV (`io::points_csv`): finite, within the bound
        // every length a user gives has.
        let within = |v: &f64| v.is_finite() && v.abs() <= MAX_LENGTH_MM;
        if let Some((i, _)) = rows.iter().find(|(_, p)| !p.iter().all(within)) {
            return Err(input(anyhow::anyhow!(
                "points: row {i} is not three finite numbers of mm within ±1e5 (100 m)"
            )));
        }
        let world = self.world();
        let summary =
            embed::register(world, &world.source, Path::new("points"), &rows).map_err(to_py)?;
        serde_json::to_string(&summary).map_err(|e| to_py(CliError::internal(e)))
    }
}

impl Scene {
    /// The ground truth of a simulated pose: the poses (4 × 4, mm), p_e and the ideal profile.
    fn ground_truth<'py>(
        &self,
        py: Python<'py>,
        pose: &ScanPose,
        ideal: &[glassscan::dataset::ideal_profile::IdealPoint],
    ) -> PyResult<Bound<'py, PyDict>> {
        let world = self.world();
        let target = world.target.as_ref().expect("checked by simulate");
        let target_pose = world.objects[target.object].pose;
        let d = PyDict::new(py);
        d.set_item("pose_index", pose.index)?;
        d.set_item("border_fraction", pose.border_fraction)?;
        d.set_item("scan_angle_deg", world.scan.scan_angle_rad.to_degrees())?;
        d.set_item("exposure_ms", world.sensor.imager.exposure_s * 1e3)?;
        d.set_item("wavelength_nm", world.sensor.laser.wavelength_m * 1e9)?;
        d.set_item("target", world.objects[target.object].name.clone())?;
        d.set_item("sensor_pose", arrays::pose_matrix(py, &pose.sensor))?;
        d.set_item("flange_pose", arrays::pose_matrix(py, &pose.flange))?;
        d.set_item("mount", arrays::pose_matrix(py, &world.mount))?;
        d.set_item("target_pose", arrays::pose_matrix(py, &target_pose))?;
        d.set_item(
            "target_nominal_pose",
            arrays::pose_matrix(py, &target.nominal_pose),
        )?;
        let border = target.border.transformed(&target_pose);
        let edge = laser_plane_crossing(&border, &pose.sensor, world.scan.standoff_m);
        d.set_item(
            "edge_point_mm",
            edge.map(|p| [p.x * 1e3, p.y * 1e3, p.z * 1e3]),
        )?;
        d.set_item(
            "edge_point_sensor_mm",
            edge.map(|p| {
                let s = pose.sensor.inverse() * p;
                [s.x * 1e3, s.z * 1e3]
            }),
        )?;
        d.set_item("ideal_profile", arrays::ideal_profile(py, ideal)?)?;
        Ok(d)
    }
}
