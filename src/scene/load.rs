//! Scene file → `World`: read, parse, validate, build meshes, convert to SI.
//!
//! Validation happens here, value by value, so that every error can point at the offending
//! value in the file (see `error`). Rules that need the built geometry (a
//! corner radius too large for its outline, a bevel too deep for the glass) are checked by
//! `geometry::panel::build_panel`, whose error names the scene-file field; it is mapped back
//! to that field's location.

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;

use nalgebra::Vector3;
use serde_spanned::Spanned;

use super::error::{SceneError, SceneSource};
use super::file::{
    BoxDef, LabelDef, MaterialDef, MeshDef, ObjectDef, PoseDef, ScanDef, SceneFile, UpAxisDef,
};
use super::fitted::Fitted;
use super::gltf_material::FileMaterial;
use super::gltf_mesh::{load_gltf, GltfMesh, GltfMeshError};
use super::material::material;
use super::mesh_material::mesh_material;
use super::mesh_target::{mesh_target, GltfParts};
use super::panel::panel;
use super::sensor_overrides::resolve_sensor;
use super::world::{Material, NamedMaterial, Object, ObjectLabel, Target, World};
use crate::geometry::border::BorderCurve;
use crate::geometry::cuboid::cuboid;
use crate::geometry::mesh::Mesh;
use crate::geometry::panel::PanelSpec;
use crate::geometry::pose::{pose_from_mm_deg, Pose};
use crate::scan::ScanConfig;
use crate::sensor::SensorConfig;

/// Default scan angle (deg): the paper's "approximately 45 degrees" (Adrian & Pham, §IV-A).
const DEFAULT_SCAN_ANGLE_DEG: f64 = 45.0;
/// Default number of scan poses: the paper's n = 4 (Table 2).
const DEFAULT_POSES: i64 = 4;
/// Default arc-length fraction of the first pose, so that it does not sit on a corner of a
/// rectangle whose border curve starts at one.
const DEFAULT_START_FRACTION: f64 = 0.1;

/// Reads a scene file and builds the `World` it describes, in SI units.
///
/// Mesh files are resolved against the scene file's folder. A path that does not exist on
/// disk but is the repository path of a shipped scene or mesh (`scenes/edge_study.toml`)
/// reads the copy in the binary (`crate::shipped`). Every error names the file and,
/// where it has one, the line and column of the offending value (see [`SceneError`]). Scenes
/// with glass materials load; the light transport decides whether it can simulate them.
pub fn load(path: &Path) -> Result<World, SceneError> {
    let text = crate::shipped::read_to_string(path).map_err(|source| SceneError::Io {
        path: path.to_owned(),
        source,
    })?;
    load_str(path, &text)
}

/// Builds the `World` described by `text`, as if it were the contents of the scene file
/// `path`: errors name `path` (with line and column in `text`) and mesh files are resolved
/// against `path`'s folder. The dataset generator uses it to load a scene whose parsed TOML it
/// edited (domain randomisation), so the edited scene goes through exactly the same checks.
pub fn load_str(path: &Path, text: &str) -> Result<World, SceneError> {
    let src = SceneSource { path, text };
    let file: SceneFile = toml::from_str(text).map_err(|e| src.parse_error(&e))?;
    build_world(&src, &file)
}

/// What kind of shape an object is; a panel keeps its spec (for the objects fitted to it) and
/// its border.
enum Shape<'a> {
    Panel(Box<PanelSpec>, BorderCurve),
    Box,
    /// With the glTF materials its triangles use (and, for the target, its border).
    Mesh(GltfParts),
    /// Built once every object is known: a tape or cover on another object.
    Fitted(Fitted<'a>),
}

impl Shape<'_> {
    fn kind(&self) -> &'static str {
        match self {
            Shape::Panel(..) => "panel",
            Shape::Box => "box",
            Shape::Mesh(_) => "mesh",
            Shape::Fitted(f) => f.key(),
        }
    }
}

fn build_world(src: &SceneSource, file: &SceneFile) -> Result<World, SceneError> {
    // The sensor comes first: dispersion laws are checked at its wavelength.
    let sensor = resolve_sensor(file.sensor.get_ref(), src)?;
    // Materials in file order (the TOML map is sorted by name; the key spans give the order).
    let mut defs: Vec<(&Spanned<String>, &Spanned<MaterialDef>)> = file.materials.iter().collect();
    defs.sort_by_key(|(name, _)| name.span().start);
    let mut materials: Vec<(String, Material)> = Vec::new();
    for (name, def) in defs {
        let material = material(name.get_ref(), def, sensor.laser.wavelength_m, src)?;
        materials.push((name.get_ref().clone(), material));
    }

    if file.objects.is_empty() {
        return Err(SceneError::EmptyScene {
            path: src.path.to_owned(),
        });
    }
    let target_def = file.target.as_ref().map(Spanned::get_ref);
    let mut seen: HashMap<&str, Range<usize>> = HashMap::new();
    let mut objects = Vec::with_capacity(file.objects.len());
    let mut shapes = Vec::with_capacity(file.objects.len());
    let mut used = vec![false; materials.len()];
    let mut warnings = Vec::new();
    let mut material_sources = Vec::new();
    for (i, obj) in file.objects.iter().enumerate() {
        let def = obj.get_ref();
        let prefix = format!("objects[{i}]");
        let name = def.name.get_ref();
        if name.trim().is_empty() {
            return Err(src.invalid(
                &def.name.span(),
                format!("{prefix}.name"),
                "must not be empty",
            ));
        }
        if let Some(first) = seen.get(name.as_str()) {
            let (line, column) = src.line_column(def.name.span().start);
            let (first_line, first_column) = src.line_column(first.start);
            return Err(SceneError::DuplicateName {
                path: src.path.to_owned(),
                line,
                column,
                field: format!("{prefix}.name"),
                name: name.clone(),
                first_line,
                first_column,
            });
        }
        seen.insert(name, def.name.span());

        let named = match &def.material {
            Some(material) => {
                let material_name = material.get_ref();
                let Some(m) = materials.iter().position(|(n, _)| n == material_name) else {
                    let (line, column) = src.line_column(material.span().start);
                    return Err(SceneError::UnknownMaterial {
                        path: src.path.to_owned(),
                        line,
                        column,
                        field: format!("{prefix}.material"),
                        name: material_name.clone(),
                        known: materials.iter().map(|(n, _)| n.clone()).collect(),
                    });
                };
                if let Some(o) = &def.material_overrides {
                    return Err(src.invalid(
                        &o.span(),
                        format!("{prefix}.material_overrides"),
                        format!(
                            "applies to a material taken from a mesh's glTF file; this object \
                             names `{material_name}`, whose values are all in [materials.{material_name}]"
                        ),
                    ));
                }
                Some(m)
            }
            None => None,
        };
        let pose = pose(
            def.pose.as_ref().map(Spanned::get_ref),
            &format!("{prefix}.pose"),
            src,
        )?;
        let (mut mesh, mut shape) = shape(def, obj.span(), &prefix, src, &mut warnings)?;
        if let (Some(t), Shape::Mesh(parts), Some(mesh_def)) = (target_def, &mut shape, &def.mesh) {
            if t.object.get_ref() == name {
                mesh_target(&mut mesh, parts, t, name, mesh_def.get_ref(), src)?;
            }
        }
        let m = match (named, &shape, &def.mesh) {
            (Some(m), ..) => m,
            (None, Shape::Mesh(parts), Some(mesh_def)) => {
                let body: Vec<FileMaterial> = (parts.materials.iter().enumerate())
                    .filter(|(k, _)| Some(*k) != parts.edge_material)
                    .map(|(_, m)| m.clone())
                    .collect();
                let (material, source) = mesh_material(
                    name,
                    &prefix,
                    &obj.span(),
                    mesh_def.get_ref().file.get_ref(),
                    &body,
                    parts.edge_material.map(|k| &parts.materials[k]),
                    def.material_overrides.as_ref(),
                    src,
                    &mut warnings,
                )?;
                material_sources.push(source);
                materials.push((format!("{name} (glTF)"), material));
                used.push(false);
                materials.len() - 1
            }
            (None, ..) => {
                return Err(src.invalid(
                    &obj.span(),
                    prefix,
                    "is missing `material` (only a mesh object may leave it out and take its \
                     glTF file's material)",
                ))
            }
        };
        used[m] = true;
        if let (Shape::Fitted(f), Some(p)) = (&shape, &def.pose) {
            return Err(src.invalid(
                &p.span(),
                format!("{prefix}.pose"),
                format!(
                    "must be absent: a {} is placed at the pose of the panel it is on (`on`)",
                    f.key()
                ),
            ));
        }
        objects.push(Object {
            name: name.clone(),
            mesh,
            pose,
            material: m,
            label: def
                .label
                .as_ref()
                .map_or(ObjectLabel::Other, |l| match l.get_ref() {
                    LabelDef::Table => ObjectLabel::Table,
                    LabelDef::Background => ObjectLabel::Background,
                    LabelDef::Tape => ObjectLabel::Tape,
                    LabelDef::Cover => ObjectLabel::Cover,
                    LabelDef::Other => ObjectLabel::Other,
                }),
        });
        shapes.push(shape);
    }

    fit_objects(file, &mut objects, &shapes, &materials, src)?;

    // Keep the materials that objects use (`World::materials` holds exactly those), in file
    // order, and re-index the objects.
    let mut new_index = vec![usize::MAX; materials.len()];
    let mut world_materials = Vec::new();
    for (k, (name, material)) in materials.into_iter().enumerate() {
        if used[k] {
            new_index[k] = world_materials.len();
            world_materials.push(NamedMaterial { name, material });
        }
    }
    for o in &mut objects {
        o.material = new_index[o.material];
    }

    let target = match &file.target {
        None => None,
        Some(t) => {
            let t = t.get_ref();
            let field = "target.object";
            let wanted = t.object.get_ref();
            let (line, column) = src.line_column(t.object.span().start);
            let Some(k) = objects.iter().position(|o| &o.name == wanted) else {
                return Err(SceneError::UnknownObject {
                    path: src.path.to_owned(),
                    line,
                    column,
                    field: field.to_owned(),
                    name: wanted.clone(),
                    known: objects.iter().map(|o| o.name.clone()).collect(),
                });
            };
            let border = match &shapes[k] {
                Shape::Panel(_, border) => border.clone(),
                Shape::Mesh(GltfParts {
                    border: Some(border),
                    ..
                }) => border.clone(),
                other => {
                    return Err(SceneError::TargetNotPanel {
                        path: src.path.to_owned(),
                        line,
                        column,
                        field: field.to_owned(),
                        name: wanted.clone(),
                        kind: other.kind(),
                    })
                }
            };
            let nominal_pose = match &t.nominal_pose {
                Some(p) => pose(Some(p.get_ref()), "target.nominal_pose", src)?,
                None => objects[k].pose,
            };
            Some(Target {
                object: k,
                border,
                nominal_pose,
            })
        }
    };

    let mount = pose(file.mount.as_ref().map(Spanned::get_ref), "mount", src)?;
    let scan = scan(file.scan.as_ref().map(Spanned::get_ref), &sensor, src)?;
    Ok(World {
        source: src.path.to_owned(),
        objects,
        materials: world_materials,
        target,
        sensor,
        mount,
        scan,
        material_sources,
        warnings,
    })
}

fn pose(def: Option<&PoseDef>, field: &str, src: &SceneSource) -> Result<Pose, SceneError> {
    let Some(def) = def else {
        return Ok(Pose::identity());
    };
    let t = match &def.translation_mm {
        Some(t) => src.finite3(t, &format!("{field}.translation_mm"))?,
        None => [0.0; 3],
    };
    let r = match &def.rotation_deg {
        Some(r) => src.finite3(r, &format!("{field}.rotation_deg"))?,
        None => [0.0; 3],
    };
    Ok(pose_from_mm_deg(t, r))
}

/// Builds the mesh of an object: exactly one of `panel`, `box`, `mesh`, `tape`, `cover`. A
/// tape or cover gets an empty mesh here; `fit_objects` builds it.
fn shape<'a>(
    def: &'a ObjectDef,
    span: Range<usize>,
    prefix: &str,
    src: &SceneSource,
    warnings: &mut Vec<String>,
) -> Result<(Mesh, Shape<'a>), SceneError> {
    let given: Vec<(&str, Range<usize>)> = [
        ("panel", def.panel.as_ref().map(Spanned::span)),
        ("box", def.cuboid.as_ref().map(Spanned::span)),
        ("mesh", def.mesh.as_ref().map(Spanned::span)),
        ("tape", def.tape.as_ref().map(Spanned::span)),
        ("cover", def.cover.as_ref().map(Spanned::span)),
    ]
    .into_iter()
    .filter_map(|(k, s)| s.map(|s| (k, s)))
    .collect();
    const EXPECTED: &str = "must have exactly one of `panel`, `box`, `mesh`, `tape` or `cover`";
    if let [(a, _), (b, second), ..] = given.as_slice() {
        return Err(src.invalid(
            second,
            prefix,
            format!("{EXPECTED}, got both `{a}` and `{b}`"),
        ));
    }
    if let Some(p) = &def.panel {
        let (spec, panel) = panel(p, &format!("{prefix}.panel"), src)?;
        Ok((panel.mesh, Shape::Panel(Box::new(spec), panel.border)))
    } else if let Some(b) = &def.cuboid {
        Ok((
            cuboid_mesh(b.get_ref(), &format!("{prefix}.box"), src)?,
            Shape::Box,
        ))
    } else if let Some(m) = &def.mesh {
        let GltfMesh {
            mesh,
            materials,
            triangle_materials,
        } = gltf(m.get_ref(), &format!("{prefix}.mesh"), src, warnings)?;
        Ok((
            mesh,
            Shape::Mesh(GltfParts {
                materials,
                triangle_materials,
                border: None,
                edge_material: None,
            }),
        ))
    } else if let Some(t) = &def.tape {
        Ok((Mesh::default(), Shape::Fitted(Fitted::Tape(t))))
    } else if let Some(c) = &def.cover {
        Ok((Mesh::default(), Shape::Fitted(Fitted::Cover(c))))
    } else {
        Err(src.invalid(&span, prefix, format!("{EXPECTED}, got none")))
    }
}

/// Builds the tapes and covers on the panels they name, at those panels' poses. They must be
/// Lambertian: each is one opaque surface (`geometry::panel::tape`, `cover`).
fn fit_objects(
    file: &SceneFile,
    objects: &mut [Object],
    shapes: &[Shape],
    materials: &[(String, Material)],
    src: &SceneSource,
) -> Result<(), SceneError> {
    for (i, shape) in shapes.iter().enumerate() {
        let Shape::Fitted(fitted) = shape else {
            continue;
        };
        let prefix = format!("objects[{i}]");
        let key = fitted.key();
        let def = file.objects[i].get_ref();
        if let (name, Material::Glass(_)) = &materials[objects[i].material] {
            return Err(src.invalid(
                &def.material.as_ref().map_or(file.objects[i].span(), Spanned::span),
                format!("{prefix}.material"),
                format!(
                    "must be a lambertian material: a {key} is modelled as one opaque surface,                      and `{name}` is glass"
                ),
            ));
        }
        let on = fitted.on();
        let Some(k) = objects.iter().position(|o| &o.name == on.get_ref()) else {
            let (line, column) = src.line_column(on.span().start);
            return Err(SceneError::UnknownObject {
                path: src.path.to_owned(),
                line,
                column,
                field: format!("{prefix}.{key}.on"),
                name: on.get_ref().clone(),
                known: objects.iter().map(|o| o.name.clone()).collect(),
            });
        };
        let Shape::Panel(spec, _) = &shapes[k] else {
            return Err(src.invalid(
                &on.span(),
                format!("{prefix}.{key}.on"),
                format!(
                    "must name a panel object (a {key} is fitted to a panel's edge), `{}` is a \
                     {} object",
                    on.get_ref(),
                    shapes[k].kind()
                ),
            ));
        };
        objects[i].mesh = fitted.mesh(spec, &prefix, src)?;
        objects[i].pose = objects[k].pose;
    }
    Ok(())
}

fn cuboid_mesh(def: &BoxDef, field: &str, src: &SceneSource) -> Result<Mesh, SceneError> {
    let mut size_m = [0.0; 3];
    for (k, v) in def.size_mm.iter().enumerate() {
        size_m[k] = src.positive(v, &format!("{field}.size_mm[{k}]"))? * 1e-3;
    }
    Ok(cuboid(size_m))
}

/// Largest and smallest plausible extent (bounding-box diagonal) of a mesh object, m: a
/// scanned part, a fixture or a table is between a millimetre and ten metres; outside that
/// range the file's units are the likely cause (a millimetre file read as metres is 1000×).
const PLAUSIBLE_MESH_EXTENT_M: (f64, f64) = (1e-3, 10.0);

/// glTF's +Y up turned to glassscan's +Z up: the rotation by +90° about x,
/// (x, y, z) ↦ (x, −z, y), applied as the permutation it is (exact; a rotation, so windings
/// and outward normals stay as they are).
fn y_up_to_z_up(mut mesh: Mesh) -> Mesh {
    let turn = |v: &mut Vector3<f64>| *v = Vector3::new(v.x, -v.z, v.y);
    mesh.positions.iter_mut().for_each(|p| turn(&mut p.coords));
    if let Some(normals) = &mut mesh.normals {
        normals.iter_mut().for_each(turn);
    }
    mesh
}

/// The warning for a mesh whose size is implausible for a scene, naming `scale`.
fn mesh_size_warning(mesh: &Mesh, field: &str, file: &str, scale: f64) -> Option<String> {
    let (lo, hi) = mesh.positions.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(&p.coords), hi.sup(&p.coords)),
    );
    let size = hi - lo;
    let extent = size.norm();
    let (min, max) = PLAUSIBLE_MESH_EXTENT_M;
    if !extent.is_finite() || (min..=max).contains(&extent) {
        return None;
    }
    let hint = if extent > max {
        "if the file is in millimetres, set `scale = 0.001` (glTF is in metres)"
    } else {
        "if the file is in kilometres or the part is this small on purpose, check `scale`"
    };
    Some(format!(
        "{field}: `{file}` is {:.4} × {:.4} × {:.4} m with `scale = {scale}`, implausible for a \
         scene (expected {min} m to {max} m across); {hint}",
        size.x, size.y, size.z
    ))
}

fn gltf(
    def: &MeshDef,
    prefix: &str,
    src: &SceneSource,
    warnings: &mut Vec<String>,
) -> Result<GltfMesh, SceneError> {
    let scale = match &def.scale {
        Some(s) => src.positive(s, &format!("{prefix}.scale"))?,
        None => 1.0,
    };
    let field = format!("{prefix}.file");
    let span = def.file.span();
    let (line, column) = src.line_column(span.start);
    let base = src.path.parent().unwrap_or(Path::new(""));
    let mesh_path = base.join(def.file.get_ref());
    let GltfMesh {
        mesh,
        materials,
        triangle_materials,
    } = load_gltf(&mesh_path, scale).map_err(|e| match e {
        GltfMeshError::Open { path, source } => SceneError::MissingMesh {
            path: src.path.to_owned(),
            line,
            column,
            field,
            mesh_path: path,
            source,
        },
        GltfMeshError::NonTriangle {
            mesh,
            primitive,
            mode,
        } => SceneError::NonTrianglePrimitive {
            path: src.path.to_owned(),
            line,
            column,
            field,
            mesh_path,
            mesh,
            primitive,
            mode,
        },
        other @ (GltfMeshError::Invalid { .. } | GltfMeshError::Empty) => SceneError::Gltf {
            path: src.path.to_owned(),
            line,
            column,
            field,
            mesh_path,
            message: other.to_string(),
        },
    })?;
    let mesh = match def.up_axis.as_ref().map(|u| *u.get_ref()) {
        None | Some(UpAxisDef::Y) => y_up_to_z_up(mesh),
        Some(UpAxisDef::Z) => mesh,
    };
    warnings.extend(mesh_size_warning(&mesh, prefix, def.file.get_ref(), scale));
    Ok(GltfMesh {
        mesh,
        materials,
        triangle_materials,
    })
}

fn scan(
    def: Option<&ScanDef>,
    sensor: &SensorConfig,
    src: &SceneSource,
) -> Result<ScanConfig, SceneError> {
    let default = ScanDef::default();
    let def = def.unwrap_or(&default);
    let scan_angle_deg = match &def.scan_angle_deg {
        Some(a) => src.number(
            a,
            "scan.scan_angle_deg",
            |a| a > 0.0 && a <= 90.0,
            "must be in (0, 90] degrees",
        )?,
        None => DEFAULT_SCAN_ANGLE_DEG,
    };
    let poses = match &def.poses {
        Some(p) => src.integer(p, "scan.poses", 1, crate::limits::MAX_POSES as i64)?,
        None => DEFAULT_POSES,
    };
    let (z_min_mm, z_max_mm) = (sensor.range.z_min_m * 1e3, sensor.range.z_max_m * 1e3);
    let standoff_m = match &def.standoff_mm {
        Some(s) => {
            src.number(
                s,
                "scan.standoff_mm",
                |s| s >= z_min_mm && s <= z_max_mm,
                &format!("must lie in the sensor's z range {z_min_mm}..={z_max_mm} mm"),
            )? * 1e-3
        }
        None => sensor.range.z_mid_m(),
    };
    let start_fraction = match &def.start_fraction {
        Some(f) => src.number(
            f,
            "scan.start_fraction",
            |f| (0.0..1.0).contains(&f),
            "must be in [0, 1)",
        )?,
        None => DEFAULT_START_FRACTION,
    };
    Ok(ScanConfig {
        scan_angle_rad: scan_angle_deg.to_radians(),
        poses: poses as usize,
        standoff_m,
        start_fraction,
    })
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;
    use crate::geometry::mesh::SurfacePart;

    fn scene(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(name)
    }

    /// Lowest z (m) of an object's mesh in the base frame.
    fn min_z(o: &Object) -> f64 {
        o.mesh
            .positions
            .iter()
            .map(|p| (o.pose * p).z)
            .fold(f64::INFINITY, f64::min)
    }

    /// (objects, materials, glass materials, poses, scan angle in degrees) of a shipped scene,
    /// after checking the invariants every scene keeps: valid meshes, a panel target, and
    /// nothing below the table top except the table (or background board) itself.
    fn summary(name: &str) -> (usize, usize, usize, usize, f64) {
        let world = load(&scene(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        for o in &world.objects {
            o.mesh
                .check()
                .unwrap_or_else(|e| panic!("{name}/{}: {e}", o.name));
            assert!(o.mesh.triangle_count() > 0);
            if o.name != "table" && o.name != "background" {
                assert!(
                    min_z(o) > -1e-9,
                    "{name}/{} dips below the table: {}",
                    o.name,
                    min_z(o)
                );
            }
        }
        let target = world
            .target
            .as_ref()
            .expect("every shipped scene has a target");
        assert!(!target.border.vertices.is_empty());
        let panel = &world.objects[target.object];
        assert!(
            panel.mesh.parts.contains(&SurfacePart::Edge),
            "{name}: target is a panel"
        );
        let glass = world
            .materials
            .iter()
            .filter(|m| matches!(m.material, Material::Glass(_)))
            .count();
        (
            world.objects.len(),
            world.materials.len(),
            glass,
            world.scan.poses,
            world.scan.scan_angle_rad.to_degrees(),
        )
    }

    #[test]
    fn shipped_scenes_load_with_their_objects_and_materials() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        let cases: [(&str, usize, usize, usize, usize, f64); 8] = [
            ("flat_opaque.toml", 2, 2, 0, 4, 45.0),
            ("flat_panel.toml", 6, 3, 1, 4, 88.0),
            ("edge_study.toml", 2, 2, 1, 4, 40.0),
            ("edge_study_bare.toml", 2, 2, 1, 4, 40.0),
            ("edge_study_tape.toml", 3, 3, 1, 4, 40.0),
            ("edge_study_cover.toml", 3, 3, 1, 4, 40.0),
            ("car_side_window.toml", 6, 2, 1, 12, 45.0),
            ("car_side_window_gltf.toml", 6, 2, 1, 12, 45.0),
        ];
        for (name, objects, materials, glass, poses, angle) in cases {
            let (o, m, g, p, a) = summary(name);
            assert_eq!((o, m, g, p), (objects, materials, glass, poses), "{name}");
            assert!(close(a, angle), "{name}: scan angle {a}");
        }
    }

    #[test]
    fn flat_opaque_is_in_si_units() {
        let world = load(&scene("flat_opaque.toml")).expect("loads");
        assert_eq!(world.source, scene("flat_opaque.toml"));
        assert!((world.sensor.imager.exposure_s - 1.5e-5).abs() < 1e-15);
        let target = world.target.expect("target");
        assert_eq!(world.objects[target.object].name, "plate");
        let t = target.nominal_pose.translation.vector;
        assert!((t - nalgebra::Vector3::new(0.002, -0.003, 0.0)).norm() < 1e-15);
        assert!((target.nominal_pose.rotation.angle() - 1f64.to_radians()).abs() < 1e-12);
        // The table's top face is at z = 0.
        let table = &world.objects[1];
        let top = table
            .mesh
            .positions
            .iter()
            .map(|p| (table.pose * p).z)
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(top.abs() < 1e-15);
        assert_eq!(
            world.materials[table.material].material,
            Material::Lambertian { albedo: 0.3 }
        );
        // Defaults: standoff at mid-range, first pose 10 % along the border, identity mount.
        assert!((world.scan.standoff_m - 0.2575).abs() < 1e-12);
        assert!((world.scan.start_fraction - 0.1).abs() < 1e-15);
        assert_eq!(world.mount, Pose::identity());
    }

    #[test]
    fn glass_becomes_a_glass_material_in_si() {
        let world = load(&scene("flat_panel.toml")).expect("loads");
        let pane = &world.objects[0];
        let Material::Glass(g) = &world.materials[pane.material].material else {
            panic!("the pane is glass");
        };
        assert_eq!(g.ior, Some(1.5208));
        assert!((g.absorption_per_m - 3.0).abs() < 1e-12, "0.003 /mm = 3 /m");
        assert!((world.sensor.imager.exposure_s - 5e-3).abs() < 1e-15);
        // The pane's bottom face is 570 mm above the background board, 10 µm clear of the posts.
        assert!((min_z(pane) - 0.57001).abs() < 1e-9);
    }

    #[test]
    fn car_window_rests_above_its_supports() {
        let world = load(&scene("car_side_window.toml")).expect("loads");
        let window = &world.objects[0];
        // Lowest glass point: 40 − 1500·(1 − cos(275/1500)) = 14.86 mm (a little higher where
        // the corners are rounded).
        let low = min_z(window);
        assert!(low > 0.0148 && low < 0.0160, "lowest glass point {low}");
        for support in world
            .objects
            .iter()
            .filter(|o| o.name.starts_with("support"))
        {
            let top = support
                .mesh
                .positions
                .iter()
                .map(|p| (support.pose * p).z)
                .fold(f64::NEG_INFINITY, f64::max);
            assert!((top - 0.023).abs() < 1e-12);
            // Glass bottom above the block's outer edge |x| = 225 mm: 40 + √(R² − x²) − R.
            let r: f64 = 1.5;
            let glass_bottom = 0.040 + (r * r - 0.225f64.powi(2)).sqrt() - r;
            assert!(glass_bottom - top > 0.0, "support penetrates the glass");
        }
        let nominal = world.target.expect("target").nominal_pose;
        let off = nominal.translation.vector - window.pose.translation.vector;
        assert!((off.norm() - 0.005).abs() < 1e-12);
        assert!(
            (nominal.rotation.angle_to(&window.pose.rotation) - 2f64.to_radians()).abs() < 1e-12
        );
    }

    /// toml 0.8 refused `Spanned` fields under header tables (toml-rs#798), so a scene that
    /// spelt its edge with `[objects.panel.edge.seamed.top]` headers failed to load: the
    /// header form must build the same pane as the inline one.
    #[test]
    fn header_tables_and_inline_tables_build_the_same_pane() {
        let text = std::fs::read_to_string(scene("edge_study.toml")).unwrap();
        let inline = text.replace(
            "\nedge = \"seamed\"\n",
            "\nedge = { seamed = { top = { width_mm = 1.2, angle_deg = 40 }, bottom = { width_mm = 0.5 } } }\n",
        );
        let headers = text.replace(
            "\nedge = \"seamed\"\n",
            "\n[objects.panel.edge.seamed.top]\nwidth_mm = 1.2\nangle_deg = 40\n\
             [objects.panel.edge.seamed.bottom]\nwidth_mm = 0.5\n",
        );
        assert_ne!(inline, text);
        let path = scene("edge_study.toml");
        let a = load_str(&path, &inline).unwrap_or_else(|e| panic!("inline: {e}"));
        let b = load_str(&path, &headers).unwrap_or_else(|e| panic!("headers: {e}"));
        let plain = load_str(&path, &text).unwrap();
        assert_eq!(a.objects[0].mesh.positions, b.objects[0].mesh.positions);
        assert_ne!(a.objects[0].mesh.positions, plain.objects[0].mesh.positions);
    }
}
