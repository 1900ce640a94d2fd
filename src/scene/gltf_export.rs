//! A minimal glTF 2.0 binary (GLB) writer: one mesh of one node, one primitive per material,
//! the materials as PBR metallic-roughness with the Khronos glass extensions
//! (`KHR_materials_transmission`, `KHR_materials_ior`, `KHR_materials_volume`), the way a CAD
//! or Blender user's file carries them. It exists so that a procedural panel can be written as
//! such a file and read back through `scene::gltf_mesh` (the round-trip validation, the shipped
//! `scenes/meshes/car_side_window.glb`); `scene::gltf_material` documents the reverse mapping.
//!
//! Layout (glTF 2.0 §4.4, GLB file format): a 12-byte header (`glTF`, version 2, total length),
//! a JSON chunk padded with spaces to 4 bytes, a BIN chunk padded with zeros. Per primitive,
//! POSITION and NORMAL are float VEC3 (POSITION with `min`/`max`, which §3.7.2.1 requires) and
//! the indices unsigned int SCALAR, each in its own buffer view (§3.6.2). glassscan is +Z up and
//! glTF +Y up (§3.4), so a point (x, y, z) is written as (x, z, −y): the loader's default
//! `up_axis = "y"` turns it back exactly. Coordinates become f32, as glTF stores them (§3.6.2.2
//! allows no f64): a metre-scale part keeps ~0.03 µm.
//!
//! The output is a pure function of the input (the JSON's keys are written in a fixed order),
//! so a committed file can be checked against a fresh export byte for byte.

use nalgebra::Vector3;
use serde_json::{json, Value};

use super::gltf_mesh::PART_EXTRAS_KEY;
use super::world::{GlassSpec, Material, World};
use crate::geometry::mesh::{Mesh, SurfacePart};

/// A material as written: glTF's PBR metallic-roughness, and glass when `glass` is given.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportMaterial {
    /// `name` (a material named like "edge" marks a target's edge finish, `scene::load`).
    pub name: String,
    /// `baseColorFactor`, linear RGBA.
    pub base_color: [f64; 4],
    /// `metallicFactor`.
    pub metallic: f64,
    /// `roughnessFactor`: the microfacet α is its square (glTF 2.0, Appendix B).
    pub roughness: f64,
    /// `extras.glassscan_part` (`gltf_mesh::PART_EXTRAS_KEY`): `"edge"` marks the edge finish
    /// whatever the name; `None` writes no extras.
    pub part: Option<String>,
    /// Transmission, index and volume; `None` for an opaque material.
    pub glass: Option<ExportGlass>,
}

/// The glass extensions of an [`ExportMaterial`].
#[derive(Clone, Debug, PartialEq)]
pub struct ExportGlass {
    /// `KHR_materials_transmission.transmissionFactor`.
    pub transmission: f64,
    /// `KHR_materials_ior.ior`.
    pub ior: f64,
    /// `KHR_materials_volume.thicknessFactor` (m): the pane's thickness; > 0 makes the
    /// material a volume rather than thin-walled.
    pub thickness_m: f64,
    /// `attenuationDistance` (m) and `attenuationColor` (linear RGB): white light has become
    /// that colour after that distance. `None`: no absorption (the extension's default
    /// distance, +∞).
    pub attenuation: Option<(f64, [f64; 3])>,
}

/// The two materials of a glass pane of thickness `thickness_m` with the glass `spec` at the
/// laser wavelength `wavelength_m`: `glass` for the faces and `edge` for the ground edge, each
/// also saying so in `extras.glassscan_part` (`"face"`, `"edge"`).
/// Both transmit fully with the index n(λ) and the volume: attenuation distance = the
/// thickness, colour exp(−α·t) in all three channels (glassscan knows the absorption at its one
/// wavelength only; the reader takes the red channel). The faces are smooth (roughness 0), the
/// edge's roughness is √α_edge so that the reader's α = roughness² gives `edge_roughness` back.
pub fn pane_materials(
    spec: &GlassSpec,
    wavelength_m: f64,
    thickness_m: f64,
) -> [ExportMaterial; 2] {
    let attenuation = (spec.absorption_per_m > 0.0).then(|| {
        let c = (-spec.absorption_per_m * thickness_m).exp();
        (thickness_m, [c; 3])
    });
    let glass = ExportGlass {
        transmission: 1.0,
        ior: spec.index_at(wavelength_m),
        thickness_m,
        attenuation,
    };
    let material = |name: &str, roughness: f64, part: &str| ExportMaterial {
        name: name.to_owned(),
        base_color: [1.0; 4],
        metallic: 0.0,
        roughness,
        part: Some(part.to_owned()),
        glass: Some(glass.clone()),
    };
    [
        material("glass", 0.0, "face"),
        material("edge", spec.edge_roughness.sqrt(), "edge"),
    ]
}

/// For each triangle of a panel mesh, its material among [`pane_materials`]: 0 for the faces,
/// 1 for the edge finish.
pub fn pane_material_of_triangles(mesh: &Mesh) -> Vec<usize> {
    (mesh.parts.iter())
        .map(|&p| usize::from(p == SurfacePart::Edge))
        .collect()
}

/// The GLB of a scene's target, when it is a glass panel: its mesh in its model frame (the
/// object's `pose` stays in the scene file), faces in material `glass` and the edge finish in
/// material `edge` ([`pane_materials`]). The pane's thickness for the volume extension is the
/// shortest distance from the first top-face vertex to a bottom-face vertex, which is the
/// thickness exactly on a panel (both faces are one tessellation moved along the face normal,
/// `geometry::panel`). Errors say what the scene lacks.
pub fn target_glb(world: &World) -> Result<Vec<u8>, String> {
    let scene = world.source.display();
    let target = (world.target.as_ref()).ok_or_else(|| format!("{scene} has no [target]"))?;
    let object = &world.objects[target.object];
    let Material::Glass(spec) = &world.materials[object.material].material else {
        return Err(format!(
            "{scene}: the target `{}` is not glass, expected a glass panel",
            object.name
        ));
    };
    let mesh = &object.mesh;
    let vertices_of = |part: SurfacePart| {
        (mesh.triangles.iter().zip(&mesh.parts))
            .filter(move |(_, &p)| p == part)
            .flat_map(|(t, _)| t.iter().map(|&k| mesh.positions[k as usize]))
    };
    let top = vertices_of(SurfacePart::TopFace).next();
    let thickness_m = top.and_then(|p| {
        vertices_of(SurfacePart::BottomFace)
            .map(|q| (p - q).norm())
            .min_by(f64::total_cmp)
    });
    let Some(thickness_m) = thickness_m else {
        return Err(format!(
            "{scene}: the target `{}` has no top and bottom face, expected a panel",
            object.name
        ));
    };
    let materials = pane_materials(spec, world.sensor.laser.wavelength_m, thickness_m);
    Ok(write_glb(
        mesh,
        &pane_material_of_triangles(mesh),
        &materials,
        &object.name,
    ))
}

/// glassscan's +Z up to glTF's +Y up: (x, y, z) ↦ (x, z, −y), the inverse of the loader's turn.
fn to_y_up(v: &Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.z as f32, (-v.y) as f32]
}

/// The GLB of `mesh` (metres, +Z up) as one node `name`, its triangles grouped into one
/// primitive per material: triangle t uses `materials[material_of[t]]`. Materials no triangle
/// uses are written all the same. Vertices are written per primitive in their order in
/// `mesh`, with normals when the mesh has them.
pub fn write_glb(
    mesh: &Mesh,
    material_of: &[usize],
    materials: &[ExportMaterial],
    name: &str,
) -> Vec<u8> {
    assert_eq!(
        material_of.len(),
        mesh.triangles.len(),
        "one material per triangle"
    );
    assert!(
        material_of.iter().all(|&m| m < materials.len()),
        "material index out of range"
    );
    let mut bin: Vec<u8> = Vec::new();
    let mut views: Vec<Value> = Vec::new();
    let mut accessors: Vec<Value> = Vec::new();
    let mut primitives: Vec<Value> = Vec::new();
    // One buffer view per accessor, each 4-byte aligned (all components are 4 bytes).
    let mut push_view = |bin: &mut Vec<u8>, bytes: Vec<u8>, target: u32| {
        let offset = bin.len();
        bin.extend_from_slice(&bytes);
        views.push(json!({
            "buffer": 0, "byteOffset": offset, "byteLength": bytes.len(), "target": target
        }));
        views.len() - 1
    };
    for (m, _) in materials.iter().enumerate() {
        let tris: Vec<&[u32; 3]> = (mesh.triangles.iter().zip(material_of))
            .filter(|(_, &k)| k == m)
            .map(|(t, _)| t)
            .collect();
        if tris.is_empty() {
            continue;
        }
        // The vertices this primitive uses, in mesh order, renumbered from 0.
        let mut used: Vec<u32> = tris.iter().flat_map(|t| t.iter().copied()).collect();
        used.sort_unstable();
        used.dedup();
        let mut local = vec![u32::MAX; mesh.positions.len()];
        for (i, &v) in used.iter().enumerate() {
            local[v as usize] = i as u32;
        }
        let positions: Vec<[f32; 3]> = (used.iter())
            .map(|&v| to_y_up(&mesh.positions[v as usize].coords))
            .collect();
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in &positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let floats = |vs: &[[f32; 3]]| -> Vec<u8> {
            vs.iter()
                .flat_map(|v| v.iter().flat_map(|c| c.to_le_bytes()))
                .collect()
        };
        const ARRAY_BUFFER: u32 = 34962;
        const ELEMENT_ARRAY_BUFFER: u32 = 34963;
        const FLOAT: u32 = 5126;
        const UNSIGNED_INT: u32 = 5125;
        let view = push_view(&mut bin, floats(&positions), ARRAY_BUFFER);
        accessors.push(json!({
            "bufferView": view, "componentType": FLOAT, "count": positions.len(), "type": "VEC3",
            "min": lo.map(f64::from), "max": hi.map(f64::from)
        }));
        let mut attributes = serde_json::Map::new();
        attributes.insert("POSITION".into(), json!(accessors.len() - 1));
        if let Some(normals) = &mesh.normals {
            let ns: Vec<[f32; 3]> = used
                .iter()
                .map(|&v| to_y_up(&normals[v as usize]))
                .collect();
            let view = push_view(&mut bin, floats(&ns), ARRAY_BUFFER);
            accessors.push(json!({
                "bufferView": view, "componentType": FLOAT, "count": ns.len(), "type": "VEC3"
            }));
            attributes.insert("NORMAL".into(), json!(accessors.len() - 1));
        }
        let indices: Vec<u8> = (tris.iter())
            .flat_map(|t| t.iter().flat_map(|&v| local[v as usize].to_le_bytes()))
            .collect();
        let count = 3 * tris.len();
        let view = push_view(&mut bin, indices, ELEMENT_ARRAY_BUFFER);
        accessors.push(json!({
            "bufferView": view, "componentType": UNSIGNED_INT, "count": count, "type": "SCALAR"
        }));
        primitives.push(json!({
            "attributes": attributes, "indices": accessors.len() - 1, "material": m, "mode": 4
        }));
    }
    let materials: Vec<Value> = materials.iter().map(material_json).collect();
    let document = json!({
        "asset": { "version": "2.0", "generator": "glassscan scene::gltf_export" },
        "extensionsUsed": [
            "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"
        ],
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "name": name }],
        "meshes": [{ "name": name, "primitives": primitives }],
        "materials": materials,
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": views,
        "accessors": accessors,
    });
    let mut json = serde_json::to_vec(&document).expect("a JSON value serialises");
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

fn material_json(m: &ExportMaterial) -> Value {
    let mut value = json!({
        "name": m.name,
        "pbrMetallicRoughness": {
            "baseColorFactor": m.base_color,
            "metallicFactor": m.metallic,
            "roughnessFactor": m.roughness
        }
    });
    if let Some(part) = &m.part {
        value["extras"] = json!({ PART_EXTRAS_KEY: part });
    }
    if let Some(g) = &m.glass {
        let mut volume = json!({ "thicknessFactor": g.thickness_m });
        if let Some((distance, colour)) = g.attenuation {
            volume["attenuationDistance"] = json!(distance);
            volume["attenuationColor"] = json!(colour);
        }
        value["extensions"] = json!({
            "KHR_materials_transmission": { "transmissionFactor": g.transmission },
            "KHR_materials_ior": { "ior": g.ior },
            "KHR_materials_volume": volume
        });
    }
    value
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::geometry::cuboid::cuboid;
    use crate::scene::gltf_mesh::load_gltf_from_slice;

    fn green_glass() -> GlassSpec {
        GlassSpec {
            ior: Some(1.5208),
            cauchy: None,
            sellmeier: None,
            absorption_per_m: 40.0,
            face_imperfection: 0.002,
            edge_roughness: 0.3,
        }
    }

    #[test]
    fn a_box_reads_back_with_its_materials_and_up_axis() {
        let mut mesh = cuboid([0.3, 0.2, 0.004]);
        // Tag the four side walls (normals along ±x, ±y) as edge.
        for t in 0..mesh.triangles.len() {
            if mesh.face_normal(t).z.abs() < 0.5 {
                mesh.parts[t] = SurfacePart::Edge;
            }
        }
        let materials = pane_materials(&green_glass(), 658e-9, 0.004);
        let glb = write_glb(
            &mesh,
            &pane_material_of_triangles(&mesh),
            &materials,
            "pane",
        );
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(glb.len() % 4, 0);
        let read = load_gltf_from_slice(Path::new("pane.glb"), &glb, 1.0).expect("reads");
        // Written +Y up: the file's y is glassscan's z.
        assert_eq!(read.mesh.triangle_count(), mesh.triangle_count());
        for p in &read.mesh.positions {
            let back = Vector3::new(p.x, -p.z, p.y);
            let nearest = (mesh.positions.iter())
                .map(|q| (back - q.coords).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest < 1e-8,
                "{back:?} is {nearest} m from the box's corners"
            );
        }
        assert_eq!(read.materials.len(), 2);
        let (glass, edge) = (&read.materials[0], &read.materials[1]);
        assert_eq!(glass.name.as_deref(), Some("glass"));
        assert_eq!(edge.name.as_deref(), Some("edge"));
        assert!((glass.ior.unwrap() - 1.5208).abs() < 1e-6);
        assert!((glass.absorption_per_m().unwrap() - 40.0).abs() < 1e-4);
        assert!((edge.roughness * edge.roughness - 0.3).abs() < 1e-6);
        assert_eq!(glass.roughness, 0.0);
        assert_eq!(edge.part.as_deref(), Some("edge"));
        assert_eq!(glass.part.as_deref(), Some("face"));
        // Triangles keep their material: the walls are material 1.
        let walls = mesh
            .parts
            .iter()
            .filter(|&&p| p == SurfacePart::Edge)
            .count();
        assert_eq!(
            read.triangle_materials.iter().filter(|&&m| m == 1).count(),
            walls
        );
        // A pure function of its input.
        assert_eq!(
            glb,
            write_glb(
                &mesh,
                &pane_material_of_triangles(&mesh),
                &materials,
                "pane"
            )
        );
    }
}
