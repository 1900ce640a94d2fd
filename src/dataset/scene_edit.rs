//! A scene file as a template: the parsed TOML document, edited with a sample's drawn values
//! and loaded again by the scene loader (`scene::load_str`), so a randomised scene goes through
//! exactly the checks of a hand-written one.
//!
//! What each [`Param`] edits (all on the parsed document, in the file's named units):
//! - `scan_angle_deg` → `[scan] scan_angle_deg`; `exposure_ms` → `[sensor] exposure_ms`;
//! - `glass_thickness_mm` → the target object's `panel.thickness_mm`;
//! - `refractive_index`, `edge_roughness`, `face_imperfection` → the target's material, which
//!   must be glass; an index replaces a Cauchy or Sellmeier law by a plain `ior`;
//! - `background_distance_mm` → lowers every object labelled `table` or `background` by that
//!   much (z of its pose), away from the glass that rests above them;
//! - `background_albedo` → gives those objects a new Lambertian material of that albedo (so a
//!   material they share with other objects, e.g. supports, keeps its value);
//! - `pose_jitter_x_mm`, `pose_jitter_y_mm`, `pose_jitter_rz_deg` → the target's true pose
//!   T_BM becomes Trans(t + (dx, dy, 0)) · Rz(θ) · R: moved in the table plane and turned about
//!   the vertical through its origin, so it keeps resting on its support (a lift or a tilt
//!   would make it float or cut the table). The nominal pose stays where the scene puts it.

use std::path::{Path, PathBuf};

use nalgebra::{Translation3, UnitQuaternion, Vector3};
use toml::{Table, Value};

use super::randomize::{Param, Randomization};
use super::DatasetError;
use crate::geometry::pose::{pose_from_mm_deg, pose_to_mm_deg};
use crate::scene::{self, SceneError, World};

/// Name of the material made for the background when its albedo is randomised.
const BACKGROUND_MATERIAL: &str = "randomized_background";

/// A scene file, loaded once as a `World` and kept as a TOML document to edit.
#[derive(Clone, Debug)]
pub struct SceneTemplate {
    /// The scene file as given.
    pub path: PathBuf,
    /// Its text (recorded in the dataset's run file).
    pub text: String,
    /// The scene as written.
    pub world: World,
    doc: Table,
}

impl SceneTemplate {
    /// Loads the scene file at `path` (errors are the scene loader's, with line and column).
    pub fn load(path: &Path) -> Result<SceneTemplate, SceneError> {
        let text = crate::shipped::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_owned(),
            source,
        })?;
        let world = scene::load_str(path, &text)?;
        // The loader accepted the text, so it is valid TOML.
        let doc: Table = text
            .parse()
            .map_err(|e: toml::de::Error| SceneError::Parse {
                path: path.to_owned(),
                line: 1,
                column: 1,
                message: e.message().to_owned(),
            })?;
        Ok(SceneTemplate {
            path: path.to_owned(),
            text,
            world,
            doc,
        })
    }

    /// The scene with `values` applied, loaded. Errors are messages for the caller to place:
    /// a structural problem (no glass target, no background object) or the scene loader's
    /// complaint about an edited value.
    pub fn world_with(&self, values: &[(Param, f64)]) -> Result<World, String> {
        if values.is_empty() {
            return Ok(self.world.clone());
        }
        let mut doc = self.doc.clone();
        apply(&mut doc, values)?;
        let text = toml::to_string(&doc).map_err(|e| format!("cannot re-encode the scene: {e}"))?;
        scene::load_str(&self.path, &text).map_err(|e| describe(&e))
    }

    /// Checks every range of `randomization` against this scene: the scene must have what the
    /// parameter edits, and must load with the parameter at each end of its range.
    pub fn check_randomization(&self, randomization: &Randomization) -> Result<(), DatasetError> {
        for (&param, range) in &randomization.ranges {
            if param == Param::NoiseSeed {
                continue;
            }
            for (end, value) in [("min", range.min), ("max", range.max)] {
                self.world_with(&[(param, value)]).map_err(|m| {
                    randomization.error(
                        param,
                        format!(
                            "{end} {value} is outside what the scene {} accepts: {m}",
                            self.path.display()
                        ),
                    )
                })?;
            }
        }
        Ok(())
    }
}

/// A scene error without the file position: the edited document's line numbers are not the
/// file's, so only the field and what it must be are worth showing.
fn describe(e: &SceneError) -> String {
    match e {
        SceneError::Invalid { field, message, .. } => format!("{field} {message}"),
        other => other.to_string(),
    }
}

fn apply(doc: &mut Table, values: &[(Param, f64)]) -> Result<(), String> {
    let target = target_index(doc);
    let mut jitter = [0.0; 3];
    let mut jittered = false;
    for &(param, v) in values {
        match param {
            Param::ScanAngleDeg => {
                table_entry(doc, "scan")?.insert("scan_angle_deg".into(), Value::Float(v));
            }
            Param::ExposureMs => {
                table_entry(doc, "sensor")?.insert("exposure_ms".into(), Value::Float(v));
            }
            Param::GlassThicknessMm => {
                let object = target_object(doc, target)?;
                let panel = object
                    .get_mut("panel")
                    .and_then(Value::as_table_mut)
                    .ok_or("the target is not a panel")?;
                panel.insert("thickness_mm".into(), Value::Float(v));
            }
            Param::RefractiveIndex | Param::EdgeRoughness | Param::FaceImperfection => {
                let glass = target_glass(doc, target)?;
                let key = match param {
                    Param::RefractiveIndex => {
                        glass.remove("cauchy");
                        glass.remove("sellmeier");
                        "ior"
                    }
                    Param::EdgeRoughness => "edge_roughness",
                    _ => "face_imperfection",
                };
                glass.insert(key.into(), Value::Float(v));
            }
            Param::BackgroundDistanceMm => {
                for object in background_objects(doc)? {
                    let pose = table_in(object, "pose")?;
                    let t = pose
                        .entry("translation_mm")
                        .or_insert_with(|| Value::Array(vec![Value::Float(0.0); 3]));
                    let mut xyz = numbers3(t).ok_or("a pose's translation_mm is not 3 numbers")?;
                    xyz[2] -= v;
                    *t = Value::Array(xyz.iter().map(|&c| Value::Float(c)).collect());
                }
            }
            Param::BackgroundAlbedo => {
                let materials = table_entry(doc, "materials")?;
                if materials.contains_key(BACKGROUND_MATERIAL) {
                    return Err(format!(
                        "the scene already has a material named `{BACKGROUND_MATERIAL}`"
                    ));
                }
                let mut m = Table::new();
                m.insert("kind".into(), Value::String("lambertian".into()));
                m.insert("albedo".into(), Value::Float(v));
                materials.insert(BACKGROUND_MATERIAL.into(), Value::Table(m));
                for object in background_objects(doc)? {
                    object.insert("material".into(), Value::String(BACKGROUND_MATERIAL.into()));
                }
            }
            Param::PoseJitterXMm | Param::PoseJitterYMm | Param::PoseJitterRzDeg => {
                let k = match param {
                    Param::PoseJitterXMm => 0,
                    Param::PoseJitterYMm => 1,
                    _ => 2,
                };
                jitter[k] = v;
                jittered = true;
            }
            Param::NoiseSeed => {}
            Param::ArrisWidthMm => set_arris_width(target_object(doc, target)?, v)?,
        }
    }
    if jittered {
        jitter_target(doc, target, jitter)?;
    }
    Ok(())
}

/// Moves the target by (dx, dy) in the table plane and turns it by θ about the vertical
/// through its origin; pins the nominal pose to the unjittered true pose if the scene left it
/// implicit (it defaults to the true pose).
fn jitter_target(
    doc: &mut Table,
    target: Option<usize>,
    [dx, dy, rz]: [f64; 3],
) -> Result<(), String> {
    let object = target_object(doc, target)?;
    let original = object
        .get("pose")
        .cloned()
        .unwrap_or_else(|| Value::Table(Table::new()));
    let pose_table = original
        .as_table()
        .ok_or("the target's pose is not a table")?;
    let read = |key: &str| match pose_table.get(key) {
        None => Ok([0.0; 3]),
        Some(v) => numbers3(v).ok_or(format!("the target's pose.{key} is not 3 numbers")),
    };
    let pose = pose_from_mm_deg(read("translation_mm")?, read("rotation_deg")?);
    let turned = Translation3::from(pose.translation.vector + Vector3::new(dx, dy, 0.0) * 1e-3)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), rz.to_radians())
        * pose.rotation;
    let (t, r) = pose_to_mm_deg(&turned);
    let mut new_pose = Table::new();
    new_pose.insert("translation_mm".into(), floats(t));
    new_pose.insert("rotation_deg".into(), floats(r));
    object.insert("pose".into(), Value::Table(new_pose));
    let target_table = table_entry(doc, "target")?;
    target_table.entry("nominal_pose").or_insert(original);
    Ok(())
}

fn floats(v: [f64; 3]) -> Value {
    Value::Array(v.iter().map(|&c| Value::Float(c)).collect())
}

fn numbers3(v: &Value) -> Option<[f64; 3]> {
    let a = v.as_array()?;
    let n: Vec<f64> = a
        .iter()
        .map(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
        .collect::<Option<_>>()?;
    n.try_into().ok()
}

/// `doc[key]` as a table, created if missing.
fn table_entry<'a>(doc: &'a mut Table, key: &str) -> Result<&'a mut Table, String> {
    table_in(doc, key)
}

fn table_in<'a>(t: &'a mut Table, key: &str) -> Result<&'a mut Table, String> {
    t.entry(key)
        .or_insert_with(|| Value::Table(Table::new()))
        .as_table_mut()
        .ok_or_else(|| format!("`{key}` is not a table"))
}

fn objects(doc: &mut Table) -> impl Iterator<Item = &mut Table> {
    doc.get_mut("objects")
        .and_then(Value::as_array_mut)
        .into_iter()
        .flatten()
        .filter_map(Value::as_table_mut)
}

/// Index of the target object in `objects`.
fn target_index(doc: &Table) -> Option<usize> {
    let name = doc.get("target")?.get("object")?.as_str()?;
    doc.get("objects")?
        .as_array()?
        .iter()
        .position(|o| o.get("name").and_then(Value::as_str) == Some(name))
}

fn target_object(doc: &mut Table, target: Option<usize>) -> Result<&mut Table, String> {
    let k = target.ok_or("the scene has no [target]")?;
    objects(doc)
        .nth(k)
        .ok_or_else(|| "the scene has no [target]".to_owned())
}

/// Sets the face width of both arrisses of a seamed panel `object` (its `edge` absent, `"seamed"`
/// or `{ seamed = { … } }`), keeping their angles and the fillet.
fn set_arris_width(object: &mut Table, width_mm: f64) -> Result<(), String> {
    let panel = object
        .get_mut("panel")
        .and_then(Value::as_table_mut)
        .ok_or("the target is not a panel")?;
    let mut seamed = match panel.get("edge") {
        None => Table::new(),
        Some(Value::String(s)) if s == "seamed" => Table::new(),
        Some(Value::Table(t)) if t.len() == 1 && t.contains_key("seamed") => t
            .get("seamed")
            .and_then(Value::as_table)
            .cloned()
            .ok_or("the target's edge.seamed is not a table")?,
        Some(_) => {
            return Err(
                "the target's edge is not seamed (arris_width_mm edits a seamed edge)".into(),
            )
        }
    };
    for side in ["top", "bottom"] {
        let arris = seamed
            .entry(side)
            .or_insert_with(|| Value::Table(Table::new()))
            .as_table_mut()
            .ok_or_else(|| format!("the target's edge.seamed.{side} is not a table"))?;
        arris.insert("width_mm".into(), Value::Float(width_mm));
    }
    let mut edge = Table::new();
    edge.insert("seamed".into(), Value::Table(seamed));
    panel.insert("edge".into(), Value::Table(edge));
    Ok(())
}

fn target_glass(doc: &mut Table, target: Option<usize>) -> Result<&mut Table, String> {
    let name = target_object(doc, target)?
        .get("material")
        .and_then(Value::as_str)
        .ok_or("the target has no material")?
        .to_owned();
    let material = doc
        .get_mut("materials")
        .and_then(|m| m.get_mut(&name))
        .and_then(Value::as_table_mut)
        .ok_or_else(|| format!("the target's material `{name}` is not defined"))?;
    if material.get("kind").and_then(Value::as_str) != Some("glass") {
        return Err(format!(
            "the target's material `{name}` is not glass (expected kind = \"glass\")"
        ));
    }
    Ok(material)
}

/// The objects labelled `table` or `background`; an error if there are none.
fn background_objects(doc: &mut Table) -> Result<Vec<&mut Table>, String> {
    let found: Vec<&mut Table> = objects(doc)
        .filter(|o| {
            matches!(
                o.get("label").and_then(Value::as_str),
                Some("table" | "background")
            )
        })
        .collect();
    if found.is_empty() {
        return Err("the scene has no object labelled \"table\" or \"background\"".into());
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::world::Material;

    fn template(name: &str) -> SceneTemplate {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(name);
        SceneTemplate::load(&path).unwrap()
    }

    fn glass(world: &World) -> crate::scene::world::GlassSpec {
        let t = world.target.as_ref().unwrap();
        match &world.materials[world.objects[t.object].material].material {
            Material::Glass(g) => g.clone(),
            other => panic!("{other:?}"),
        }
    }

    fn top_z(world: &World, name: &str) -> f64 {
        let o = world.objects.iter().find(|o| o.name == name).unwrap();
        o.mesh
            .positions
            .iter()
            .map(|p| (o.pose * p).z)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    #[test]
    fn no_values_is_the_scene_as_written() {
        let t = template("edge_study.toml");
        let w = t.world_with(&[]).unwrap();
        assert_eq!(w.objects.len(), t.world.objects.len());
        assert_eq!(w.objects[0].pose, t.world.objects[0].pose);
    }

    #[test]
    fn each_parameter_edits_what_it_says() {
        let t = template("edge_study.toml");
        let w = t
            .world_with(&[
                (Param::ScanAngleDeg, 25.0),
                (Param::ExposureMs, 0.25),
                (Param::GlassThicknessMm, 3.2),
                (Param::RefractiveIndex, 1.51),
                (Param::EdgeRoughness, 0.1),
                (Param::FaceImperfection, 0.004),
                (Param::BackgroundDistanceMm, 30.0),
                (Param::BackgroundAlbedo, 0.7),
            ])
            .unwrap();
        assert!((w.scan.scan_angle_rad.to_degrees() - 25.0).abs() < 1e-12);
        assert!((w.sensor.imager.exposure_s - 0.25e-3).abs() < 1e-15);
        assert!((top_z(&w, "pane") - 0.00321).abs() < 1e-9);
        let g = glass(&w);
        assert_eq!(
            (g.ior, g.edge_roughness, g.face_imperfection),
            (Some(1.51), 0.1, 0.004)
        );
        assert!((top_z(&w, "table") + 0.030).abs() < 1e-12);
        let table = w.objects.iter().find(|o| o.name == "table").unwrap();
        assert_eq!(w.materials[table.material].name, BACKGROUND_MATERIAL);
        assert_eq!(
            w.materials[table.material].material,
            Material::Lambertian { albedo: 0.7 }
        );
    }

    #[test]
    fn jitter_moves_the_true_pose_in_the_table_plane_and_keeps_the_nominal() {
        let t = template("flat_opaque.toml");
        let w = t
            .world_with(&[
                (Param::PoseJitterXMm, 1.5),
                (Param::PoseJitterYMm, -2.0),
                (Param::PoseJitterRzDeg, 3.0),
            ])
            .unwrap();
        let k = w.target.as_ref().unwrap().object;
        let (before, after) = (&t.world.objects[k].pose, &w.objects[k].pose);
        let d = after.translation.vector - before.translation.vector;
        assert!(
            (d - Vector3::new(1.5e-3, -2e-3, 0.0)).norm() < 1e-12,
            "{d:?}"
        );
        let turn = after.rotation * before.rotation.inverse();
        assert!((turn.angle() - 3f64.to_radians()).abs() < 1e-12);
        assert!((turn.axis().unwrap().into_inner() - Vector3::z()).norm() < 1e-9);
        assert_eq!(
            w.target.as_ref().unwrap().nominal_pose,
            t.world.target.as_ref().unwrap().nominal_pose
        );
        // A scene that leaves the nominal pose implicit keeps the unjittered true pose as it.
        let mut doc = t.doc.clone();
        doc["target"].as_table_mut().unwrap().remove("nominal_pose");
        let implicit = SceneTemplate { doc, ..t.clone() };
        let w = implicit.world_with(&[(Param::PoseJitterXMm, 4.0)]).unwrap();
        let target = w.target.as_ref().unwrap();
        assert_eq!(target.nominal_pose, t.world.objects[k].pose);
        assert_ne!(w.objects[k].pose, t.world.objects[k].pose);
    }

    #[test]
    fn ranges_the_scene_refuses_name_the_key_and_the_scene_rule() {
        let t = template("edge_study.toml");
        for (text, expected) in [
            (
                "scan_angle_deg = [10, 95]\n",
                "r.toml:1:1: scan_angle_deg: max 95 is outside what the scene",
            ),
            ("refractive_index = [0.9, 1.5]\n", "min 0.9 is outside"),
            ("face_imperfection = [0, 1]\n", "must be in [0, 1)"),
            ("glass_thickness_mm = [0, 4]\n", "thickness_mm must be > 0"),
        ] {
            let r = Randomization::parse(Path::new("r.toml"), text.into()).unwrap();
            let message = t.check_randomization(&r).unwrap_err().to_string();
            assert!(message.contains(expected), "{text}: {message}");
        }
        let opaque = template("flat_opaque.toml");
        let r = Randomization::parse(Path::new("r.toml"), "edge_roughness = [0.1, 0.2]\n".into())
            .unwrap();
        let message = opaque.check_randomization(&r).unwrap_err().to_string();
        assert!(message.contains("is not glass"), "{message}");
        let ok = Randomization::parse(
            Path::new("r.toml"),
            "scan_angle_deg = [10, 90]\nbackground_albedo = [0, 1]\n".into(),
        )
        .unwrap();
        t.check_randomization(&ok).unwrap();
    }
}
