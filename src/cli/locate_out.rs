//! The files of `glassscan locate --out DIR`: per-pose profiles, the BIPs of both rules (CSV),
//! the poses and ground truth (JSON), point clouds of the BIPs and the model border before and
//! after registration (PLY), and the summary. Base frame B, millimetres.

use std::path::Path;

use anyhow::Context;
use nalgebra::Point3;
use serde_json::{json, Value};

use super::manifest::PoseMmDeg;
use crate::geometry::border::BorderCurve;
use crate::io::json::write_json_pretty;
use crate::io::ply::{write_ply, PlyEncoding, PointCloud};
use crate::io::points_csv::{write_csv_table, CsvTable};
use crate::io::profile_csv::write_profile_csv;
use crate::scan::bip::Bip;
use crate::scan::locate::{LocateReport, LocatedPose};
use crate::scene::world::World;

const BIP_COLOR: [u8; 3] = [220, 30, 30];
const TRUE_BORDER_COLOR: [u8; 3] = [150, 150, 150];
const NOMINAL_BORDER_COLOR: [u8; 3] = [40, 80, 220];
const ESTIMATE_BORDER_COLOR: [u8; 3] = [30, 170, 60];

fn mm(p: &Point3<f64>) -> [f64; 3] {
    [p.x * 1e3, p.y * 1e3, p.z * 1e3]
}

fn border_mm(b: &BorderCurve) -> impl Iterator<Item = [f64; 3]> + '_ {
    b.vertices.iter().map(|v| mm(&v.position))
}

/// The BIPs of one rule as a table: one row per pose, empty fields where there is none.
fn bips_table(report: &LocateReport, pick: fn(&LocatedPose) -> Option<Bip>) -> CsvTable {
    let columns = [
        "pose",
        "x_mm",
        "y_mm",
        "z_mm",
        "profile_index",
        "label",
        "intensity_dn",
        "pe_x_mm",
        "pe_y_mm",
        "pe_z_mm",
        "error_mm",
    ];
    let rows = report
        .poses
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let b = pick(p);
            let mut row = vec![k.to_string()];
            match b {
                Some(b) => {
                    row.extend(mm(&b.point_b).map(|v| v.to_string()));
                    row.push(b.profile_index.to_string());
                    row.push(b.label.map_or("", |l| l.name()).to_string());
                    row.push(b.intensity.to_string());
                }
                None => row.extend(std::iter::repeat_n(String::new(), 6)),
            }
            match p.edge_point {
                Some(pe) => row.extend(mm(&pe).map(|v| v.to_string())),
                None => row.extend(std::iter::repeat_n(String::new(), 3)),
            }
            row.push(match (b, p.edge_point) {
                (Some(b), Some(pe)) => ((b.point_b - pe).norm() * 1e3).to_string(),
                _ => String::new(),
            });
            row
        })
        .collect();
    CsvTable {
        columns: columns.map(String::from).to_vec(),
        rows,
    }
}

/// Writes every file of a run into `dir` (which exists).
pub fn write_run(
    dir: &Path,
    world: &World,
    report: &LocateReport,
    summary: &Value,
) -> anyhow::Result<()> {
    let target = world.target.as_ref().context("the scene has a target")?;
    let model = &target.border;
    let true_pose = world.objects[target.object].pose;
    let profiles = dir.join("profiles");
    std::fs::create_dir_all(&profiles)
        .with_context(|| format!("could not create {}", profiles.display()))?;
    for (k, p) in report.poses.iter().enumerate() {
        write_profile_csv(
            &profiles.join(format!("pose_{k:03}_profile.csv")),
            &p.result.profile,
        )?;
    }
    write_csv_table(&dir.join("bips.csv"), &bips_table(report, |p| p.bip))?;
    write_csv_table(
        &dir.join("bips_paper_rule.csv"),
        &bips_table(report, |p| p.paper_bip),
    )?;

    let estimate = report.registration.as_ref().ok().map(|r| r.pose);
    let poses: Vec<Value> = report
        .poses
        .iter()
        .map(|p| {
            json!({
                "index": p.planned.index,
                "border_fraction": p.planned.border_fraction,
                "flange_commanded": PoseMmDeg::from(&p.planned.flange),
                "sensor_believed": PoseMmDeg::from(&p.planned.sensor),
                "sensor_true": PoseMmDeg::from(&p.result.pose.sensor),
                "edge_point_mm": p.edge_point.map(|e| mm(&e)),
                "bip_mm": p.bip.map(|b| mm(&b.point_b)),
                "paper_rule_bip_mm": p.paper_bip.map(|b| mm(&b.point_b)),
                "valid_points": p.result.profile.points.iter().filter(|q| q.valid).count(),
                "saturated_pixels": p.result.saturated_pixels,
            })
        })
        .collect();
    write_json_pretty(
        &dir.join("poses.json"),
        &json!({
            "frame": "base frame B, z up, mm and degrees (R = Rz·Ry·Rx)",
            "target_true": PoseMmDeg::from(&true_pose),
            "target_nominal": PoseMmDeg::from(&target.nominal_pose),
            "target_estimate": estimate.as_ref().map(PoseMmDeg::from),
            "mount_calibrated": PoseMmDeg::from(&world.mount),
            "hand_eye_error": PoseMmDeg::from(&report.errors.hand_eye),
            "poses": poses,
        }),
    )?;

    let bips: Vec<[f64; 3]> = report
        .poses
        .iter()
        .filter_map(|p| p.bip.map(|b| mm(&b.point_b)))
        .collect();
    let true_b = model.transformed(&true_pose);
    let cloud = |border: &BorderCurve, color: [u8; 3], what: &str| {
        let mut c = PointCloud {
            comments: vec![
                "glassscan locate: base frame B, millimetres".into(),
                format!("red: BIPs; grey: true border; {what}"),
            ],
            ..Default::default()
        };
        c.push_colored(bips.iter().copied(), BIP_COLOR);
        c.push_colored(border_mm(&true_b), TRUE_BORDER_COLOR);
        c.push_colored(border_mm(border), color);
        c
    };
    write_ply(
        &dir.join("registration_before.ply"),
        &cloud(
            &model.transformed(&target.nominal_pose),
            NOMINAL_BORDER_COLOR,
            "blue: model border at the nominal pose",
        ),
        PlyEncoding::BinaryLittleEndian,
    )?;
    let after = dir.join("registration_after.ply");
    match &estimate {
        Some(e) => write_ply(
            &after,
            &cloud(
                &model.transformed(e),
                ESTIMATE_BORDER_COLOR,
                "green: model border at the estimated pose",
            ),
            PlyEncoding::BinaryLittleEndian,
        )?,
        // No estimate: an earlier run's file would show a registration this one did not make.
        None if after.exists() => std::fs::remove_file(&after)
            .with_context(|| format!("could not remove {}", after.display()))?,
        None => {}
    }
    write_json_pretty(&dir.join("summary.json"), summary)?;
    // A --force run with fewer poses leaves only its own profiles.
    let written: std::collections::BTreeSet<String> = (0..report.poses.len())
        .map(|k| format!("pose_{k:03}_profile.csv"))
        .collect();
    let is_profile = |n: &str| n.starts_with("pose_") && n.ends_with("_profile.csv");
    crate::io::output_dir::remove_stale(&profiles, is_profile, &written)?;
    Ok(())
}
