//! A Border Identifier Point from one pose's profile: the profile taken into the base frame
//! with the pose the software believes, then one of the BIP rules of `localise::bip`.

use std::str::FromStr;

use nalgebra::Point3;

use crate::geometry::pose::Pose;
use crate::localise::bip::bip_highest;
use crate::localise::edge_line::{bip_edge_line, EdgeLineSettings};
use crate::sensor::path_class::PathClass;
use crate::sensor::profile::Profile;

/// The ground plane of every shipped scene: the table top at z = 0 of the base frame
/// (scenes/README.md). BIPs must lie `MIN_HEIGHT_M` above it.
pub const GROUND_Z_M: f64 = 0.0;
/// Least height of a BIP above the ground (m): half a millimetre keeps table returns out
/// (their scatter is tens of µm) and any pane edge in (≥ 2 mm tall).
pub const MIN_HEIGHT_M: f64 = 0.5e-3;

/// Which rule picks the BIP.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BipRule {
    /// The paper's: the highest point above the ground plane.
    Highest,
    /// The top of the chain of ground-edge returns, climbed from its steepest run (robust to
    /// face returns, convex panes and arrissed corners); see [`bip_edge_line`].
    EdgeLine,
}

impl BipRule {
    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            BipRule::Highest => "highest",
            BipRule::EdgeLine => "edge-line",
        }
    }
}

impl FromStr for BipRule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "highest" => Ok(BipRule::Highest),
            "edge-line" => Ok(BipRule::EdgeLine),
            _ => Err(format!("expected highest or edge-line, got {s:?}")),
        }
    }
}

/// A BIP and where it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bip {
    /// The point in the base frame (m).
    pub point_b: Point3<f64>,
    /// Index of the profile point it came from (in `Profile::points`).
    pub profile_index: usize,
    /// The path class that dominated that point's peak.
    pub label: Option<PathClass>,
    /// The peak's maximum intensity (DN).
    pub intensity: u16,
}

/// The valid points of `profile` in the base frame, with their indices in `profile.points`,
/// converted with the sensor pose T_BS the software believes.
pub fn profile_in_base(profile: &Profile, sensor: &Pose) -> Vec<(usize, Point3<f64>)> {
    profile
        .points
        .iter()
        .enumerate()
        .filter(|(_, q)| q.valid)
        .map(|(i, q)| (i, sensor * Point3::new(q.x_mm * 1e-3, 0.0, q.z_mm * 1e-3)))
        .collect()
}

/// The BIP of `profile` by `rule`, or `None` if the rule finds none.
pub fn find_bip(profile: &Profile, sensor: &Pose, rule: BipRule) -> Option<Bip> {
    let pts = profile_in_base(profile, sensor);
    let xyz: Vec<Point3<f64>> = pts.iter().map(|p| p.1).collect();
    let k = match rule {
        BipRule::Highest => bip_highest(&xyz, GROUND_Z_M, MIN_HEIGHT_M),
        BipRule::EdgeLine => {
            bip_edge_line(&xyz, GROUND_Z_M, MIN_HEIGHT_M, &EdgeLineSettings::default())
        }
    }?;
    let (index, point_b) = pts[k];
    let q = &profile.points[index];
    Some(Bip {
        point_b,
        profile_index: index,
        label: q.label,
        intensity: q.intensity,
    })
}
