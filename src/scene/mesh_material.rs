//! A mesh object's material taken from its glTF file (`gltf_material`), with the scene file's
//! `material_overrides` on top, checked as a `[materials.NAME]` section's values are, and the
//! record of where each value came from (`World::material_sources`, in the manifests).

use std::ops::Range;

use serde_spanned::Spanned;

use super::error::{SceneError, SceneSource};
use super::file::MaterialOverridesDef;
use super::gltf_material::{FileMaterial, GLTF_DEFAULT_IOR};
use super::world::{GlassSpec, Material, MaterialSource, MaterialValue};

/// The object `name`'s material (at `prefix`, whose `mesh.file` is `file`) from `materials`,
/// the glTF materials of its triangles, and `overrides`. `span` locates the object. `edge` is
/// the material of a target mesh's edge finish (`geometry::mesh_border`), left out of
/// `materials`: the body has one material, and the edge material's `roughnessFactor` r gives
/// the ground edge's microfacet α = r² (glTF 2.0, Appendix B: α = roughness²).
#[allow(clippy::too_many_arguments)]
pub(super) fn mesh_material(
    name: &str,
    prefix: &str,
    span: &Range<usize>,
    file: &str,
    materials: &[FileMaterial],
    edge: Option<&FileMaterial>,
    overrides: Option<&Spanned<MaterialOverridesDef>>,
    src: &SceneSource,
    warnings: &mut Vec<String>,
) -> Result<(Material, MaterialSource), SceneError> {
    let field = |f: &str| format!("{prefix}.material_overrides.{f}");
    let fm = match materials {
        [one] => one,
        several => {
            let labels: Vec<&str> = several.iter().map(|m| m.label.as_str()).collect();
            return Err(src.invalid(
                span,
                format!("{prefix}.material"),
                format!(
                    "is missing, and `{file}` uses {} glTF materials ({}): an object has one \
                     material, so name one with `material`, or split the file into one object \
                     per material",
                    several.len(),
                    labels.join(", ")
                ),
            ));
        }
    };
    let empty = MaterialOverridesDef::default();
    let o = overrides.map_or(&empty, Spanned::get_ref);
    let from_file = |what: String| {
        src.invalid(
            span,
            format!("{prefix}.mesh.file"),
            format!("`{file}`, {}: {what}", fm.label),
        )
    };
    let mut values = Vec::new();
    let mut record = |key: &'static str, value: f64, source: &'static str| {
        values.push(MaterialValue { key, value, source });
        value
    };
    let material = if fm.is_glass() {
        if let Some(a) = &o.albedo {
            return Err(src.invalid(
                &a.span(),
                field("albedo"),
                format!(
                    "is a lambertian value, but {} of `{file}` is glass \
                     (KHR_materials_transmission = {})",
                    fm.label, fm.transmission
                ),
            ));
        }
        let ior = match (&o.ior, fm.ior) {
            (Some(v), _) => record(
                "ior",
                src.number(v, &field("ior"), |n| n >= 1.0, "must be ≥ 1")?,
                "toml",
            ),
            (None, Some(n)) if n.is_finite() && n >= 1.0 => record("ior", n, "file"),
            (None, Some(n)) => {
                return Err(from_file(format!(
                    "KHR_materials_ior.ior must be ≥ 1, got {n}"
                )))
            }
            (None, None) => record("ior", GLTF_DEFAULT_IOR, "gltf default"),
        };
        let absorption_per_mm = match &o.absorption_per_mm {
            Some(v) => record(
                "absorption_per_mm",
                src.non_negative(v, &field("absorption_per_mm"))?,
                "toml",
            ),
            None => match fm.absorption_per_m() {
                Some(a) => record("absorption_per_mm", a * 1e-3, "file"),
                None => {
                    return Err(from_file(
                        "KHR_materials_volume.attenuationColor's red channel must be in (0, 1]"
                            .into(),
                    ))
                }
            },
        };
        let missing = |key: &str| {
            src.invalid(
                &overrides.map_or(span.clone(), Spanned::span),
                format!("{prefix}.material_overrides"),
                format!(
                    "is missing `{key}`: {} of `{file}` is glass, and glTF cannot say how its \
                     faces scatter{}; give \
                     `material_overrides = {{ face_imperfection = …, edge_roughness = … }}` \
                     (the shipped scenes use 0.002 and 0.3, see scenes/README.md)",
                    fm.label,
                    if edge.is_some() {
                        ""
                    } else {
                        " or (without an edge material) how rough its ground edge is"
                    }
                ),
            )
        };
        let imperfection = o
            .face_imperfection
            .as_ref()
            .ok_or_else(|| missing("face_imperfection"))?;
        let face_imperfection = record(
            "face_imperfection",
            src.number(
                imperfection,
                &field("face_imperfection"),
                |f| (0.0..1.0).contains(&f),
                "must be in [0, 1)",
            )?,
            "toml",
        );
        let edge_roughness = match (&o.edge_roughness, edge) {
            (Some(v), _) => record(
                "edge_roughness",
                src.non_negative(v, &field("edge_roughness"))?,
                "toml",
            ),
            (None, Some(e)) if e.roughness.is_finite() && e.roughness >= 0.0 => {
                record("edge_roughness", e.roughness * e.roughness, "file")
            }
            (None, Some(e)) => {
                return Err(from_file(format!(
                    "the edge material {}'s roughnessFactor must be ≥ 0, got {}",
                    e.label, e.roughness
                )))
            }
            (None, None) => return Err(missing("edge_roughness")),
        };
        Material::Glass(GlassSpec {
            ior: Some(ior),
            cauchy: None,
            sellmeier: None,
            absorption_per_m: absorption_per_mm * 1e3,
            face_imperfection,
            edge_roughness,
        })
    } else {
        let glass_only = [
            ("ior", &o.ior),
            ("absorption_per_mm", &o.absorption_per_mm),
            ("face_imperfection", &o.face_imperfection),
            ("edge_roughness", &o.edge_roughness),
        ];
        if let Some((key, Some(v))) = glass_only.iter().find(|(_, v)| v.is_some()) {
            return Err(src.invalid(
                &v.span(),
                field(key),
                format!(
                    "is a glass value, but {} of `{file}` is opaque (no \
                     KHR_materials_transmission): expected only `albedo`",
                    fm.label
                ),
            ));
        }
        let albedo = match &o.albedo {
            Some(v) => record(
                "albedo",
                src.number(
                    v,
                    &field("albedo"),
                    |a| (0.0..=1.0).contains(&a),
                    "must be in [0, 1]",
                )?,
                "toml",
            ),
            None if (0.0..=1.0).contains(&fm.base_red) => record("albedo", fm.base_red, "file"),
            None => {
                return Err(from_file(format!(
                    "baseColorFactor's red channel must be in [0, 1], got {}",
                    fm.base_red
                )))
            }
        };
        if fm.metallic > 0.0 {
            warnings.push(format!(
                "{prefix}: {} of `{file}` is metallic (metallicFactor = {}); glassscan has no \
                 metal model and takes it as Lambertian with albedo {albedo}",
                fm.label, fm.metallic
            ));
        }
        Material::Lambertian { albedo }
    };
    let kind = match material {
        Material::Glass(_) => "glass",
        _ => "lambertian",
    };
    Ok((
        material,
        MaterialSource {
            object: name.to_owned(),
            file: file.to_owned(),
            gltf_material: match edge {
                Some(e) => format!("{}, edge finish {}", fm.label, e.label),
                None => fm.label.clone(),
            },
            kind,
            values,
        },
    ))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use serde_json::{json, Value};

    use crate::scene::world::{Material, World};

    /// The cube fixture with `materials` (JSON) and `extensions` as required, its primitive
    /// using material 0 (or none), written next to a scene whose second object is the mesh
    /// with the object keys `keys`; loaded.
    fn load(materials: Value, required: &[&str], keys: &str) -> Result<World, String> {
        let dir = tempfile::tempdir().unwrap();
        let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/cube.gltf");
        let mut gltf: Value =
            serde_json::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
        if materials.as_array().is_some_and(|m| !m.is_empty()) {
            gltf["materials"] = materials;
            gltf["meshes"][0]["primitives"][0]["material"] = json!(0);
        }
        // KHR_materials_volume is used, never required (the glTF reader refuses it there).
        let used: Vec<&str> = required
            .iter()
            .copied()
            .chain(
                required
                    .contains(&"KHR_materials_transmission")
                    .then_some("KHR_materials_volume"),
            )
            .collect();
        gltf["extensionsUsed"] = json!(used);
        gltf["extensionsRequired"] = json!(required);
        std::fs::write(dir.path().join("part.gltf"), gltf.to_string()).unwrap();
        let text = format!(
            r#"[materials.white]
kind = "lambertian"
albedo = 0.8

[[objects]]
name = "table"
material = "white"
box = {{ size_mm = [1000, 800, 20] }}

[[objects]]
name = "part"
mesh = {{ file = "part.gltf", scale = 0.1 }}
{keys}

[sensor]
preset = "scancontrol-2600-100"
"#
        );
        let path = dir.path().join("scene.toml");
        std::fs::write(&path, &text).unwrap();
        crate::scene::load(&path).map_err(|e| e.to_string())
    }

    fn glass_material() -> Value {
        json!([{
            "name": "Glass",
            "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "roughnessFactor": 0},
            "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_ior": {"ior": 1.52},
                "KHR_materials_volume": {"attenuationDistance": 0.5, "attenuationColor": [0.9, 0.95, 0.97]}
            }
        }])
    }

    const EXTENSIONS: [&str; 2] = ["KHR_materials_transmission", "KHR_materials_ior"];

    #[test]
    fn glass_comes_from_the_file_with_its_sources_recorded() {
        let world = load(
            glass_material(),
            &EXTENSIONS,
            "material_overrides = { face_imperfection = 0.002, edge_roughness = 0.3 }",
        )
        .unwrap();
        let part = &world.objects[1];
        let Material::Glass(g) = &world.materials[part.material].material else {
            panic!("{:?}", world.materials[part.material]);
        };
        assert_eq!(g.ior, Some(1.5199999809265137)); // the f32 the file holds
                                                     // σ = −ln(c_r)/d with d = 0.5 file units × scale 0.1 = 0.05 m.
        let sigma = -(0.9f32 as f64).ln() / (0.5 * 0.1);
        assert!(
            (g.absorption_per_m - sigma).abs() < 1e-9 * sigma,
            "{}",
            g.absorption_per_m
        );
        assert_eq!((g.face_imperfection, g.edge_roughness), (0.002, 0.3));
        let record = &world.material_sources[0];
        assert_eq!(record.object, "part");
        assert_eq!(record.gltf_material, "material 0 \"Glass\"");
        let sources: Vec<(&str, &str)> = record.values.iter().map(|v| (v.key, v.source)).collect();
        assert_eq!(
            sources,
            [
                ("ior", "file"),
                ("absorption_per_mm", "file"),
                ("face_imperfection", "toml"),
                ("edge_roughness", "toml"),
            ]
        );
        // The scene file overrides the index; without KHR_materials_ior it is 1.5.
        let world = load(
            glass_material(),
            &EXTENSIONS,
            "material_overrides = { ior = 1.6, face_imperfection = 0, edge_roughness = 0.5 }",
        )
        .unwrap();
        assert_eq!(world.material_sources[0].values[0].source, "toml");
        let mut m = glass_material();
        m[0]["extensions"]
            .as_object_mut()
            .unwrap()
            .remove("KHR_materials_ior");
        let world = load(
            m,
            &EXTENSIONS[..1],
            "material_overrides = { face_imperfection = 0, edge_roughness = 0.5 }",
        )
        .unwrap();
        let v = &world.material_sources[0].values[0];
        assert_eq!((v.value, v.source), (1.5, "gltf default"));
    }

    #[test]
    fn glass_from_a_file_asks_for_what_gltf_cannot_say() {
        let e = load(glass_material(), &EXTENSIONS, "").unwrap_err();
        assert!(
            e.contains("objects[1].material_overrides is missing `face_imperfection`")
                && e.contains("material 0 \"Glass\" of `part.gltf` is glass"),
            "{e}"
        );
        let e = load(
            glass_material(),
            &EXTENSIONS,
            "material_overrides = { face_imperfection = 0.002, edge_roughness = 0.3, albedo = 0.5 }",
        )
        .unwrap_err();
        assert!(
            e.contains("material_overrides.albedo is a lambertian value"),
            "{e}"
        );
    }

    #[test]
    fn an_opaque_material_is_lambertian_with_the_base_colour_s_red() {
        let m = json!([{"name": "Paint", "pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.5, 0.5, 1], "metallicFactor": 0}}]);
        let world = load(m.clone(), &[], "").unwrap();
        let part = &world.objects[1];
        assert_eq!(
            world.materials[part.material].material,
            Material::Lambertian { albedo: 0.25 }
        );
        assert!(world.warnings.is_empty(), "{:?}", world.warnings);
        let world = load(m.clone(), &[], "material_overrides = { albedo = 0.6 }").unwrap();
        assert_eq!(world.material_sources[0].values[0].source, "toml");
        let e = load(m, &[], "material_overrides = { ior = 1.5 }").unwrap_err();
        assert!(e.contains("material_overrides.ior is a glass value"), "{e}");
        // glTF's default material (none named): white, metallic 1 → a warning.
        let world = load(json!([]), &[], "").unwrap();
        assert_eq!(
            world.material_sources[0].gltf_material,
            "the default material"
        );
        assert!(
            world.warnings[0].contains("is metallic"),
            "{:?}",
            world.warnings
        );
    }

    #[test]
    fn a_named_material_wins_and_overrides_need_a_file_material() {
        let world = load(glass_material(), &EXTENSIONS, "material = \"white\"").unwrap();
        assert!(world.material_sources.is_empty());
        let e = load(
            glass_material(),
            &EXTENSIONS,
            "material = \"white\"\nmaterial_overrides = { albedo = 0.5 }",
        )
        .unwrap_err();
        assert!(
            e.contains("objects[1].material_overrides applies to a material taken from a mesh"),
            "{e}"
        );
    }

    #[test]
    fn required_extensions_glassscan_does_not_read_are_refused_by_name() {
        let e = load(
            glass_material(),
            &["KHR_mesh_quantization", "KHR_materials_ior"],
            "",
        )
        .unwrap_err();
        assert!(
            e.contains("requires the glTF extension(s) KHR_mesh_quantization, which glassscan does not read"),
            "{e}"
        );
        let e = load(glass_material(), &["KHR_materials_volume"], "").unwrap_err();
        assert!(e.contains("list it in extensionsUsed only"), "{e}");
    }
}
