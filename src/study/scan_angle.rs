//! The paper's edge experiment as a study (Adrian & Pham, Section III-C, Figs. 6–7): the pane
//! scanned across its border with tape over the edge (the true contour), with a cover ending at
//! the edge line, and bare, at several scan angles and positions along the border. Every valid
//! profile point goes into the edge frame of its pose's p_e, and the bare pane's BIP is taken
//! by both rules and compared with p_e.
//!
//! The poses are planned on the *true* border (nominal = true pose): the study asks how well a
//! profile shows the edge, not how well a pose is recovered. Pose k at every angle uses the same
//! random streams (they are keyed on the seed and the pose index), so differences between
//! angles are those of the geometry, not of the noise draw (common random numbers).

use nalgebra::Point3;

use super::side_by_side::map_poses;
use crate::geometry::border::BorderCurve;
use crate::geometry::pose::Pose;
use crate::scan::poses::plan_border_scan;
use crate::scan::simulate::{sense, trace_pose};
use crate::scan::ScanConfig;
use crate::sensor::path_class::PathClass;
use crate::sensor::SensorHead;
use crate::transport::{TraceScene, TraceSettings};

use super::as_typed;
use super::edge_frame::EdgeFrame;
use super::tally::{by_setting, sensed_by_each, PoseTally, RuleSummary};
use crate::localise::metrics::Stats;

/// The three steps of the paper's experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// Step 1: tape along the border and onto the glass; reads the true contour.
    Tape,
    /// Step 2: a cover block on the glass whose face is flush with the edge line.
    Cover,
    /// Step 3: the bare pane.
    Bare,
}

impl Variant {
    /// Every variant, in the paper's order.
    pub const ALL: [Variant; 3] = [Variant::Tape, Variant::Cover, Variant::Bare];

    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Tape => "tape",
            Variant::Cover => "cover",
            Variant::Bare => "bare",
        }
    }
}

/// One variant's scene, ready to trace.
pub struct VariantSetup {
    /// Which step of the experiment.
    pub variant: Variant,
    /// The scene's BVH and surface models.
    pub scene: TraceScene,
    /// The sensor.
    pub head: SensorHead,
    /// The true border curve in the base frame (the target's border at its true pose).
    pub border_b: BorderCurve,
    /// Hand-eye mount T_FS.
    pub mount: Pose,
}

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanAngleConfig {
    /// Scan angles of the edge plots (rad), every variant.
    pub angles_rad: Vec<f64>,
    /// Scan angles of the BIP-error curve (rad), bare variant only; may be empty.
    pub sweep_rad: Vec<f64>,
    /// The exposure axis (s): every bare pose is also sensed at each of these exposures (the
    /// light is traced once; only the sensor and the firmware run again). May be empty.
    pub exposures_s: Vec<f64>,
    /// The scene's scan settings (standoff, first position); `poses` is the number of
    /// positions and `scan_angle_rad` is replaced by each angle in turn.
    pub scan: ScanConfig,
    /// Photons, depth and seed.
    pub trace: TraceSettings,
}

impl ScanAngleConfig {
    /// The sweep angles that are not also edge-plot angles: the only ones the sweep must
    /// simulate (the others reuse the bare variant's poses of the edge plots, bit for bit).
    fn sweep_only(&self) -> impl Iterator<Item = f64> + '_ {
        self.sweep_rad
            .iter()
            .copied()
            .filter(|a| !self.angles_rad.contains(a))
    }

    /// Poses to simulate in all: the progress bar's length.
    pub fn simulations(&self, variants: usize) -> usize {
        self.scan.poses * (self.angles_rad.len() * variants + self.sweep_only().count())
    }
}

/// One valid profile point in the edge frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgePoint {
    /// The variant it was measured on.
    pub variant: Variant,
    /// Scan angle (deg).
    pub scan_angle_deg: f64,
    /// Position index along the border (the pose index).
    pub position: usize,
    /// Outward from p_e (mm), negative over the glass.
    pub out_mm: f64,
    /// Above p_e (mm).
    pub up_mm: f64,
    /// Peak maximum intensity (DN).
    pub intensity: u16,
    /// Path class of the peak.
    pub label: Option<PathClass>,
}

/// One variant at one angle.
#[derive(Clone, Debug, PartialEq)]
pub struct VariantAngle {
    /// The variant.
    pub variant: Variant,
    /// One tally per position.
    pub tallies: Vec<PoseTally>,
    /// Per position, the distance from p_e of the nearest valid point (mm); `None` for an
    /// empty profile.
    pub nearest_mm: Vec<Option<f64>>,
    /// Valid points whose peak reached the ADC's full scale.
    pub saturated_points: usize,
    /// Per exposure of [`ScanAngleConfig::exposures_s`], one tally per position (bare variant
    /// only; empty for tape and cover).
    pub by_exposure: Vec<Vec<PoseTally>>,
}

impl VariantAngle {
    /// Statistics of the nearest-point distances over the positions that have points.
    pub fn nearest_stats(&self) -> Stats {
        let v: Vec<f64> = self.nearest_mm.iter().flatten().copied().collect();
        Stats::from_values(&v)
    }

    /// Valid points over all positions.
    pub fn valid_points(&self) -> usize {
        self.tallies.iter().map(|t| t.valid_points).sum()
    }

    /// Saturated pixels / pixels over all positions.
    pub fn saturated_pixel_fraction(&self) -> f64 {
        let s: usize = self.tallies.iter().map(|t| t.saturated_pixels).sum();
        let n: usize = self.tallies.iter().map(|t| t.pixels).sum();
        s as f64 / n as f64
    }

    /// Valid points from the wrong surface / valid points.
    pub fn wrong_surface_fraction(&self) -> f64 {
        let w: usize = self.tallies.iter().map(|t| t.wrong_surface_points).sum();
        w as f64 / self.valid_points() as f64
    }
}

/// One edge-plot angle.
#[derive(Clone, Debug, PartialEq)]
pub struct AngleResult {
    /// Scan angle (deg).
    pub scan_angle_deg: f64,
    /// One entry per variant run, in the order given.
    pub variants: Vec<VariantAngle>,
    /// Every valid point of every variant and position.
    pub points: Vec<EdgePoint>,
}

impl AngleResult {
    /// The bare variant's results, if it was run.
    pub fn bare(&self) -> Option<&VariantAngle> {
        self.variants.iter().find(|v| v.variant == Variant::Bare)
    }

    /// BIP errors of the bare variant by both rules (`None` without a bare variant).
    pub fn bip(&self) -> Option<[RuleSummary; 2]> {
        self.bare().map(|b| RuleSummary::both(&b.tallies))
    }
}

/// One angle of the BIP-error curve (bare variant).
#[derive(Clone, Debug, PartialEq)]
pub struct SweepAngle {
    /// Scan angle (deg).
    pub scan_angle_deg: f64,
    /// Both rules.
    pub rules: [RuleSummary; 2],
    /// One tally per position.
    pub tallies: Vec<PoseTally>,
    /// Both rules per exposure of [`ScanAngleConfig::exposures_s`].
    pub by_exposure: Vec<[RuleSummary; 2]>,
}

/// The whole study.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanAngleStudy {
    /// The edge-plot angles.
    pub angles: Vec<AngleResult>,
    /// The BIP-error curve (empty without a sweep or without a bare variant).
    pub sweep: Vec<SweepAngle>,
}

/// What one pose of a variant gives the study.
struct PoseOutcome {
    /// Its tally at each exposure of the exposure axis.
    by_exposure: Vec<PoseTally>,
    /// Its tally with the scene's own sensor.
    tally: PoseTally,
    /// The valid profile point nearest p_e (mm), if any.
    nearest: Option<f64>,
    /// Valid points at the ADC's full scale.
    saturated_points: usize,
    /// Its valid points in the edge frame.
    points: Vec<EdgePoint>,
}

/// Simulates `setup` at every position for scan angle `angle_rad`.
fn run_variant(
    setup: &VariantSetup,
    cfg: &ScanAngleConfig,
    angle_rad: f64,
    points: Option<&mut Vec<EdgePoint>>,
    on_pose: &(dyn Fn() + Sync),
) -> VariantAngle {
    let scan = ScanConfig {
        scan_angle_rad: angle_rad,
        ..cfg.scan
    };
    let full_scale = setup.head.config.imager.max_dn();
    let heads: Vec<SensorHead> = match setup.variant {
        Variant::Bare => cfg
            .exposures_s
            .iter()
            .map(|&e| {
                let mut head = setup.head.clone();
                head.config.imager.exposure_s = e;
                head
            })
            .collect(),
        Variant::Tape | Variant::Cover => Vec::new(),
    };
    let keep_points = points.is_some();
    let poses = plan_border_scan(&setup.border_b, &scan, &setup.mount);
    let by_pose = map_poses(&poses, on_pose, |pose| {
        let frame = EdgeFrame::of_pose(&setup.border_b, pose);
        let (irradiance, _) = trace_pose(
            &setup.scene,
            &setup.head,
            pose,
            &cfg.trace,
            super::tally::STOP_RULES,
        );
        // The exposure axis: the same light, sensed again (noise keyed on the seed and pose).
        let mut sensed = sensed_by_each(&irradiance, &heads, pose, &cfg.trace);
        let by_exposure = sensed
            .iter()
            .map(|s| PoseTally::new(s, &pose.sensor, &frame))
            .collect();
        // The scene's own sensor is one of the axis's settings by default (0.5 ms): what it
        // makes of the light is then already sensed, bit for bit.
        let result = match heads.iter().position(|h| h.config == setup.head.config) {
            Some(own) => sensed.swap_remove(own),
            None => sense(&irradiance, &setup.head, pose, &cfg.trace),
        };
        let mut nearest: Option<f64> = None;
        let mut saturated_points = 0;
        let mut points = Vec::new();
        for q in result.profile.points.iter().filter(|q| q.valid) {
            saturated_points += (q.intensity >= full_scale) as usize;
            let p_b = pose.sensor * Point3::new(q.x_mm * 1e-3, 0.0, q.z_mm * 1e-3);
            let d = (p_b - frame.origin).norm() * 1e3;
            nearest = Some(nearest.map_or(d, |n| n.min(d)));
            if !keep_points {
                continue;
            }
            let (out_mm, up_mm) = frame.coordinates_mm(&p_b);
            points.push(EdgePoint {
                variant: setup.variant,
                scan_angle_deg: as_typed(angle_rad.to_degrees()),
                position: pose.index,
                out_mm,
                up_mm,
                intensity: q.intensity,
                label: q.label,
            });
        }
        PoseOutcome {
            by_exposure,
            tally: PoseTally::new(&result, &pose.sensor, &frame),
            nearest,
            saturated_points,
            points,
        }
    });
    let mut exposures = Vec::with_capacity(scan.poses);
    let mut tallies = Vec::with_capacity(scan.poses);
    let mut nearest_mm = Vec::with_capacity(scan.poses);
    let mut saturated_points = 0;
    let mut kept = Vec::new();
    for pose in by_pose {
        exposures.push(pose.by_exposure);
        tallies.push(pose.tally);
        nearest_mm.push(pose.nearest);
        saturated_points += pose.saturated_points;
        kept.extend(pose.points);
    }
    if let Some(points) = points {
        points.extend(kept);
    }
    VariantAngle {
        variant: setup.variant,
        tallies,
        nearest_mm,
        saturated_points,
        by_exposure: by_setting(exposures, heads.len()),
    }
}

/// Runs the study on `setups` (any of the three variants; the BIP needs the bare one).
/// `on_pose` is called after each simulated pose (progress).
pub fn run_scan_angle_study(
    setups: &[VariantSetup],
    cfg: &ScanAngleConfig,
    on_pose: &(dyn Fn() + Sync),
) -> ScanAngleStudy {
    let angles: Vec<AngleResult> = cfg
        .angles_rad
        .iter()
        .map(|&a| {
            let mut points = Vec::new();
            let variants = setups
                .iter()
                .map(|s| run_variant(s, cfg, a, Some(&mut points), on_pose))
                .collect();
            AngleResult {
                scan_angle_deg: as_typed(a.to_degrees()),
                variants,
                points,
            }
        })
        .collect();
    let bare = setups.iter().find(|s| s.variant == Variant::Bare);
    let sweep = match bare {
        None => Vec::new(),
        Some(bare) => cfg
            .sweep_rad
            .iter()
            .map(|&a| {
                let reused = cfg
                    .angles_rad
                    .iter()
                    .position(|&b| b == a)
                    .and_then(|i| angles[i].bare().cloned());
                let v = reused.unwrap_or_else(|| run_variant(bare, cfg, a, None, on_pose));
                SweepAngle {
                    scan_angle_deg: as_typed(a.to_degrees()),
                    rules: RuleSummary::both(&v.tallies),
                    by_exposure: v.by_exposure.iter().map(|t| RuleSummary::both(t)).collect(),
                    tallies: v.tallies,
                }
            })
            .collect(),
    };
    ScanAngleStudy { angles, sweep }
}
