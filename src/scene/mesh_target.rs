//! A mesh object as the scan target: its border found on the mesh (`geometry::mesh_border`)
//! by the rule `[target] border` states, its triangles tagged top face, bottom face or edge
//! finish, so that the border curve feeds p_e, the scan poses and ICP and the rough-edge model
//! applies to the edge, exactly as for a procedural panel.

use serde_spanned::Spanned;

use super::error::{SceneError, SceneSource};
use super::file::{BorderDef, MeshDef, TargetDef};
use super::gltf_material::FileMaterial;
use crate::geometry::border::BorderCurve;
use crate::geometry::mesh::Mesh;
use crate::geometry::mesh_border::{find_border, EdgeRule, DEFAULT_EDGE_DIHEDRAL_DEG};

/// What a mesh object keeps of its glTF file besides the triangles.
pub(super) struct GltfParts {
    /// The materials of its triangles, in the order first met.
    pub(super) materials: Vec<FileMaterial>,
    /// Per triangle, its index in `materials`.
    pub(super) triangle_materials: Vec<usize>,
    /// The border curve, when the mesh is the target (`geometry::mesh_border`).
    pub(super) border: Option<BorderCurve>,
    /// The index in `materials` of the edge finish's material, when the border was found by it.
    pub(super) edge_material: Option<usize>,
}

/// Finds the border of the target mesh object `name` (`geometry::mesh_border`) by the rule
/// `target.border` states, tags its triangles (top face, bottom face, edge finish) and keeps
/// the border and the edge material in `parts`. Without `target.border`, a glTF material whose
/// `extras.glassscan_part` is `"edge"`, or without such extras whose name contains "edge" (any
/// case), marks the edge finish, as a CAD or Blender user names it; without one, creases of
/// [`DEFAULT_EDGE_DIHEDRAL_DEG`] or more do.
pub(super) fn mesh_target(
    mesh: &mut Mesh,
    parts: &mut GltfParts,
    target: &TargetDef,
    name: &str,
    mesh_def: &MeshDef,
    src: &SceneSource,
) -> Result<(), SceneError> {
    let file = mesh_def.file.get_ref();
    let def = target.border.as_ref();
    let none = BorderDef::default();
    let b = def.map_or(&none, Spanned::get_ref);
    let names: Vec<String> = parts.materials.iter().map(|m| m.label.clone()).collect();
    let marked = |k: usize| {
        let flags = parts.triangle_materials.iter().map(|&m| m == k).collect();
        (EdgeRule::Marked(flags), Some(k))
    };
    let (rule, edge_material) = match (&b.dihedral_deg, &b.edge_material) {
        (Some(_), Some(m)) => {
            return Err(src.invalid(
                &m.span(),
                "target.border.edge_material",
                "must not be given with `dihedral_deg`: the edge finish is found one way, \
                 expected one of the two keys",
            ))
        }
        (Some(d), None) => {
            let deg = src.number(
                d,
                "target.border.dihedral_deg",
                |a| a > 0.0 && a < 180.0,
                "must be in (0, 180) degrees",
            )?;
            (
                EdgeRule::Dihedral {
                    threshold_rad: deg.to_radians(),
                },
                None,
            )
        }
        (None, Some(m)) => {
            let wanted = m.get_ref();
            let found = (parts.materials.iter()).position(|f| f.name.as_deref() == Some(wanted));
            let Some(k) = found else {
                return Err(src.invalid(
                    &m.span(),
                    "target.border.edge_material",
                    format!(
                        "`{wanted}` is not a material of `{file}`'s triangles, expected one of: \
                         {}",
                        names.join(", ")
                    ),
                ));
            };
            marked(k)
        }
        (None, None) => {
            let edge: Vec<usize> = (parts.materials.iter().enumerate())
                .filter(|(_, m)| match &m.part {
                    // `extras` say what the material is; otherwise its name does.
                    Some(part) => part == "edge",
                    None => (m.name.as_deref()).is_some_and(|n| n.to_lowercase().contains("edge")),
                })
                .map(|(k, _)| k)
                .collect();
            match edge.as_slice() {
                [] => (
                    EdgeRule::Dihedral {
                        threshold_rad: DEFAULT_EDGE_DIHEDRAL_DEG.to_radians(),
                    },
                    None,
                ),
                [k] => marked(*k),
                several => {
                    let labels: Vec<&str> = several.iter().map(|&k| names[k].as_str()).collect();
                    return Err(src.invalid(
                        &target.object.span(),
                        "target.border",
                        format!(
                            "is missing, and `{file}` has {} materials named like \"edge\" ({}): \
                             expected one; name it with `border = {{ edge_material = \"…\" }}`",
                            several.len(),
                            labels.join(", ")
                        ),
                    ));
                }
            }
        }
    };
    let found = find_border(mesh, &rule).map_err(|e| {
        let (span, field) = match def {
            Some(d) => (d.span(), "target.border"),
            None => (target.object.span(), "target.object"),
        };
        src.invalid(
            &span,
            field,
            format!("names mesh object `{name}`, whose border cannot be found in `{file}`: {e}"),
        )
    })?;
    mesh.parts = found.parts;
    parts.border = Some(found.border);
    parts.edge_material = edge_material;
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use nalgebra::Point3;

    use crate::geometry::cuboid::cuboid;
    use crate::geometry::mesh::{Mesh, SurfacePart};
    use crate::geometry::mesh_border::ring;
    use crate::geometry::panel::{build_panel, Curvature, EdgeProfile, Outline, Panel, PanelSpec};
    use crate::scene::gltf_export::{
        pane_material_of_triangles, pane_materials, write_glb, ExportMaterial,
    };
    use crate::scene::test_scene::{load_error, load_text, location_of};
    use crate::scene::world::{GlassSpec, Material};

    fn glass() -> GlassSpec {
        GlassSpec {
            ior: Some(1.5208),
            cauchy: None,
            sellmeier: None,
            absorption_per_m: 40.0,
            face_imperfection: 0.002,
            edge_roughness: 0.3,
        }
    }

    fn pane() -> Panel {
        build_panel(&PanelSpec {
            outline: Outline::Rectangle {
                width_m: 0.2,
                height_m: 0.1,
                corner_radius_m: 0.01,
            },
            thickness_m: 0.004,
            curvature: Curvature::Cylindrical { radius_m: 1.0 },
            edge: EdgeProfile::default(),
            tessellation_m: 0.01,
        })
        .expect("builds")
    }

    /// Writes `mesh` as `name` in a fresh temporary folder (kept alive by the returned guard).
    fn write(
        mesh: &Mesh,
        material_of: &[usize],
        materials: &[ExportMaterial],
    ) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("part.glb");
        std::fs::write(&path, write_glb(mesh, material_of, materials, "part")).expect("writes");
        (dir, path)
    }

    /// A scene whose target is the mesh file `file`, with `target_extra` lines in `[target]`
    /// and `overrides` as the object's `material_overrides`.
    fn scene(file: &Path, overrides: &str, target_extra: &str) -> String {
        format!(
            "[[objects]]\nname = \"pane\"\nmesh = {{ file = \"{}\" }}\n\
             material_overrides = {{ {overrides} }}\npose = {{ translation_mm = [0, 0, 40] }}\n\n\
             [target]\nobject = \"pane\"\n{target_extra}\n\
             [sensor]\npreset = \"scancontrol-2600-100\"\n",
            file.display()
        )
    }

    /// The mesh of a single-material file: every triangle glass, the edge roughness from TOML.
    fn one_material(mesh: &Mesh) -> (tempfile::TempDir, PathBuf) {
        let [glass, _] = pane_materials(&glass(), 658e-9, 0.004);
        write(mesh, &vec![0; mesh.triangles.len()], &[glass])
    }

    const OVERRIDES: &str = "face_imperfection = 0.002, edge_roughness = 0.3";

    #[test]
    fn a_panel_written_as_gltf_is_a_target_with_the_panels_border_and_edge() {
        let p = pane();
        let materials = pane_materials(&glass(), 658e-9, 0.004);
        let (_dir, file) = write(&p.mesh, &pane_material_of_triangles(&p.mesh), &materials);
        // By the material named "edge" (found without being named), and by the dihedral rule
        // on a one-material file.
        let (_one, single) = one_material(&p.mesh);
        for text in [
            scene(&file, "face_imperfection = 0.002", ""),
            scene(&single, OVERRIDES, "border = { dihedral_deg = 20 }"),
            scene(&single, OVERRIDES, ""),
        ] {
            let world = load_text(&text).unwrap_or_else(|e| panic!("{e}"));
            let target = world.target.as_ref().expect("target");
            let object = &world.objects[target.object];
            let (a, b) = (&target.border.vertices, &p.border.vertices);
            assert_eq!(a.len(), b.len());
            // f32 coordinates in the file: ≤ 2⁻²⁴ of the coordinate, ~3 nm here.
            let far = a
                .iter()
                .zip(b)
                .map(|(u, v)| (u.position - v.position).norm());
            assert!(far.fold(0.0, f64::max) < 1e-8);
            for (u, v) in a.iter().zip(b) {
                assert!((u.surface_normal - v.surface_normal).norm() < 1e-6);
            }
            // As many edge, top and bottom triangles as the panel.
            let count = |parts: &[SurfacePart], k| parts.iter().filter(|&&x| x == k).count();
            for part in [
                SurfacePart::Edge,
                SurfacePart::TopFace,
                SurfacePart::BottomFace,
            ] {
                assert_eq!(count(&object.mesh.parts, part), count(&p.mesh.parts, part));
            }
            let Material::Glass(g) = &world.materials[object.material].material else {
                panic!("glass from the file");
            };
            assert!(
                (g.edge_roughness - 0.3).abs() < 1e-7,
                "{}",
                g.edge_roughness
            );
            assert!((g.absorption_per_m - 40.0).abs() < 1e-4);
        }
        // The edge roughness came from the edge material, and the record says so.
        let world = load_text(&scene(&file, "face_imperfection = 0.002", "")).unwrap();
        let source = &world.material_sources[0];
        assert!(source
            .gltf_material
            .contains("edge finish material 1 \"edge\""));
        let roughness = source.values.iter().find(|v| v.key == "edge_roughness");
        assert_eq!(roughness.map(|v| v.source), Some("file"));
    }

    #[test]
    fn extras_mark_the_edge_material_whatever_its_name() {
        let p = pane();
        let [glass, edge] = pane_materials(&glass(), 658e-9, 0.004);
        // `rim` is the edge by its extras; `edge_glass` is not, by its extras, though named so.
        let rim = ExportMaterial {
            name: "rim".into(),
            ..edge
        };
        let faces = ExportMaterial {
            name: "edge_glass".into(),
            part: Some("face".into()),
            ..glass
        };
        let (_dir, file) = write(&p.mesh, &pane_material_of_triangles(&p.mesh), &[faces, rim]);
        let world = load_text(&scene(&file, "face_imperfection = 0.002", "")).unwrap();
        let target = world.target.as_ref().expect("target");
        assert_eq!(target.border.vertices.len(), p.border.vertices.len());
        let object = &world.objects[target.object];
        assert_eq!(object.mesh.parts, {
            // The file lists the face triangles first, then the edge's.
            let mut parts: Vec<SurfacePart> = p.mesh.parts.clone();
            parts.sort_by_key(|&x| x == SurfacePart::Edge);
            parts
        });
        assert!(world.material_sources[0]
            .gltf_material
            .contains("edge finish material 1 \"rim\""));
    }

    /// The message of a scene whose target is `mesh` (one material), and the place it must
    /// point at.
    fn refused(mesh: &Mesh, target_extra: &str, needle: &str) -> String {
        let (_dir, file) = one_material(mesh);
        let text = scene(&file, OVERRIDES, target_extra);
        let m = load_error(&text);
        let at = location_of(&text, needle);
        assert!(m.starts_with(&at), "expected {at} in: {m}");
        // A mesh that has no border names its file; a bad rule is the scene file's own.
        let names_file = m.contains(&format!("`{}`", file.display()));
        let about_file = m.contains("border cannot be found") || m.contains("not a material of");
        assert_eq!(names_file, about_file, "{m}");
        m
    }

    #[test]
    fn an_open_mesh_is_refused_naming_the_file_the_field_and_a_side() {
        let mut m = pane().mesh;
        m.triangles.truncate(m.triangles.len() - 1);
        m.parts.truncate(m.triangles.len());
        let e = refused(&m, "", "\"pane\"\n\n");
        assert!(e.contains("target.object names mesh object `pane`"), "{e}");
        assert!(e.contains("the mesh is open: the side from ("), "{e}");
        assert!(e.contains("expected a closed mesh"), "{e}");
    }

    #[test]
    fn a_non_manifold_mesh_is_refused() {
        let mut m = cuboid([0.2, 0.1, 0.004]);
        let t = m.triangles[0];
        let apex = m.positions.len() as u32;
        m.positions.push(Point3::new(0.0, 0.0, 0.05));
        m.triangles.extend([[t[0], t[1], apex], [t[1], t[0], apex]]);
        m.parts.extend([SurfacePart::Solid; 2]);
        let e = refused(&m, "", "\"pane\"\n\n");
        assert!(
            e.contains("not a manifold")
                && e.contains("belongs to 4 triangles, expected exactly 2"),
            "{e}"
        );
    }

    #[test]
    fn a_pane_with_a_hole_has_several_borders() {
        let e = refused(&ring(0.1, 0.05, 0.004), "", "\"pane\"\n\n");
        assert!(
            e.contains("several borders: the top face's boundary is 2 closed loops (800.0, 400.0 mm long), expected one"),
            "{e}"
        );
    }

    #[test]
    fn no_border_is_found_when_every_crease_is_below_the_threshold() {
        let e = refused(
            &cuboid([0.2, 0.1, 0.004]),
            "border = { dihedral_deg = 100 }",
            "{ dihedral_deg",
        );
        assert!(e.contains("target.border names mesh object `pane`"), "{e}");
        assert!(e.contains("no border found"), "{e}");
    }

    #[test]
    fn the_border_rule_is_checked() {
        let b = cuboid([0.2, 0.1, 0.004]);
        let e = refused(&b, "border = { dihedral_deg = 180 }", "180");
        assert!(
            e.contains("target.border.dihedral_deg must be in (0, 180) degrees, got 180"),
            "{e}"
        );
        let e = refused(
            &b,
            "border = { dihedral_deg = 20, edge_material = \"x\" }",
            "\"x\"",
        );
        assert!(e.contains("must not be given with `dihedral_deg`"), "{e}");
        let e = refused(&b, "border = { edge_material = \"rim\" }", "\"rim\"");
        assert!(
            e.contains("`rim` is not a material of")
                && e.contains("expected one of: material 0 \"glass\""),
            "{e}"
        );
        // Two materials named like "edge": which one is the finish must be said.
        let [glass, edge] = pane_materials(&glass(), 658e-9, 0.004);
        let second = ExportMaterial {
            name: "Edge.001".into(),
            ..edge.clone()
        };
        let p = pane();
        let mut material_of = pane_material_of_triangles(&p.mesh);
        if let Some(k) = material_of.iter().position(|&m| m == 1) {
            material_of[k] = 2;
        }
        let (_dir, file) = write(&p.mesh, &material_of, &[glass, edge, second]);
        let text = scene(&file, "face_imperfection = 0.002", "");
        let e = load_error(&text);
        assert!(
            e.contains("has 2 materials named like \"edge\" (material 1 \"edge\", material 2 \"Edge.001\")"),
            "{e}"
        );
    }
}
