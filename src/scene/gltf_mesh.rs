//! glTF 2.0 import: every triangle primitive of every node of the default scene, placed by
//! the node transforms (accumulated parent → child, glTF 2.0 §3.5.2), scaled to metres.
//!
//! glTF positions are in metres by the specification (§3.4), so `scale` is 1 for a conforming
//! file; a file exported in millimetres needs 0.001. Images are not read. A node whose transform has a negative determinant mirrors
//! its mesh, so its triangles are re-wound to keep counter-clockwise = outward (glTF 2.0
//! §3.7.2.1). Vertex normals are kept, transformed by the inverse transpose, when every
//! primitive has them; otherwise the mesh is flat shaded. The materials the triangles use are
//! read too (`gltf_material`); the scene loader decides whether they apply.

use std::path::{Path, PathBuf};

use gltf::mesh::Mode;
use nalgebra::{Matrix3, Matrix4, Point3, Vector3};

use super::gltf_material::{FileMaterial, HANDLED_EXTENSIONS, REQUIRABLE_EXTENSIONS};
use crate::geometry::mesh::{Mesh, SurfacePart};

/// Why a glTF file could not be turned into a mesh. The scene loader adds the scene file's
/// location.
#[derive(Debug, thiserror::Error)]
pub enum GltfMeshError {
    /// The file does not exist or cannot be opened.
    #[error("cannot open `{}`: {source}", path.display())]
    Open {
        /// The glTF file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file is not valid glTF, or a buffer it references cannot be read.
    #[error("{message}")]
    Invalid {
        /// What the glTF reader reported.
        message: String,
    },
    /// A primitive draws points or lines.
    #[error("mesh {mesh} primitive {primitive} has mode {mode}, expected triangles")]
    NonTriangle {
        /// Index of the mesh in the file's `meshes` array.
        mesh: usize,
        /// Primitive index within the mesh.
        primitive: usize,
        /// The glTF mode name (`LINES`, …).
        mode: &'static str,
    },
    /// The default scene holds no triangles.
    #[error("the default scene holds no triangles")]
    Empty,
}

/// Loads the triangles of the default scene (or of the first scene, if the file names no
/// default) of a `.gltf` or `.glb` file, with positions multiplied by `scale` (file units →
/// metres). Triangles are `SurfacePart::Solid`.
pub fn load_gltf_mesh(path: &Path, scale: f64) -> Result<Mesh, GltfMeshError> {
    load_gltf(path, scale).map(|g| g.mesh)
}

/// A glTF file's triangles and the materials they use.
#[derive(Clone, Debug)]
pub struct GltfMesh {
    /// The triangles, as [`load_gltf_mesh`] gives them.
    pub mesh: Mesh,
    /// The distinct materials of the triangle primitives, in the order first met
    /// (`the default material` for a primitive that names none).
    pub materials: Vec<FileMaterial>,
    /// For every triangle of `mesh`, the index of its material in `materials`.
    pub triangle_materials: Vec<usize>,
}

/// [`load_gltf_mesh`], with the materials its triangles use.
pub fn load_gltf(path: &Path, scale: f64) -> Result<GltfMesh, GltfMeshError> {
    let bytes = crate::shipped::read(path).map_err(|source| GltfMeshError::Open {
        path: path.to_owned(),
        source,
    })?;
    load_gltf_from_slice(path, &bytes, scale)
}

/// [`load_gltf_mesh`] of a file's bytes already in memory; external buffers (`.bin`) are
/// looked up next to `path`.
pub fn load_gltf_mesh_from_slice(
    path: &Path,
    bytes: &[u8],
    scale: f64,
) -> Result<Mesh, GltfMeshError> {
    load_gltf_from_slice(path, bytes, scale).map(|g| g.mesh)
}

/// [`load_gltf`] of a file's bytes already in memory.
pub fn load_gltf_from_slice(
    path: &Path,
    bytes: &[u8],
    scale: f64,
) -> Result<GltfMesh, GltfMeshError> {
    let invalid = |e: gltf::Error| GltfMeshError::Invalid {
        message: describe(&e, bytes),
    };
    check_glb_header(bytes).map_err(|message| GltfMeshError::Invalid { message })?;
    check_accessor_indices(bytes).map_err(|message| GltfMeshError::Invalid { message })?;
    check_required_extensions(bytes).map_err(|message| GltfMeshError::Invalid { message })?;
    let gltf = gltf::Gltf::from_slice(bytes).map_err(invalid)?;
    let base = path.parent().unwrap_or(Path::new("."));
    // The reader's own error for a missing external buffer names no file.
    for buffer in gltf.document.buffers() {
        if let gltf::buffer::Source::Uri(uri) = buffer.source() {
            if !uri.starts_with("data:") {
                let file = base.join(uri);
                if !file.is_file() {
                    return Err(GltfMeshError::Invalid {
                        message: format!(
                            "buffer {} refers to `{}`, which does not exist",
                            buffer.index(),
                            file.display()
                        ),
                    });
                }
            }
        }
    }
    let buffers =
        gltf::import_buffers(&gltf.document, Some(base), gltf.blob.clone()).map_err(invalid)?;
    let scene = gltf
        .document
        .default_scene()
        .or_else(|| gltf.document.scenes().next())
        .ok_or(GltfMeshError::Empty)?;

    let mut out = Mesh::default();
    let mut materials: Vec<(Option<usize>, FileMaterial)> = Vec::new();
    let mut triangle_materials: Vec<usize> = Vec::new();
    let parts = material_parts(bytes);
    let mut all_have_normals = true;
    let root = Matrix4::new_scaling(scale);
    // Depth-first over the node tree with the accumulated transform; glTF forbids cycles
    // (§3.5.1) and the reader validates that, but the depth bound keeps a bad file from
    // looping.
    let mut stack: Vec<(gltf::Node, Matrix4<f64>, usize)> =
        scene.nodes().map(|n| (n, root, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 1024 {
            return Err(GltfMeshError::Invalid {
                message: "node hierarchy deeper than 1024 levels".to_owned(),
            });
        }
        let m = node.transform().matrix();
        let local = Matrix4::from_fn(|r, c| f64::from(m[c][r]));
        let world = parent * local;
        if let Some(mesh) = node.mesh() {
            let (part, counts) = mesh_part(&mesh, &buffers, &world)?;
            for (prim, count) in mesh.primitives().zip(counts) {
                let m = prim.material();
                let k = match materials.iter().position(|(i, _)| *i == m.index()) {
                    Some(k) => k,
                    None => {
                        let mut fm = FileMaterial::read(&m, scale);
                        fm.part = m.index().and_then(|i| parts.get(i).cloned().flatten());
                        materials.push((m.index(), fm));
                        materials.len() - 1
                    }
                };
                triangle_materials.extend(std::iter::repeat_n(k, count));
            }
            all_have_normals &= part.normals.is_some();
            out.append(&part);
        }
        stack.extend(node.children().map(|c| (c, world, depth + 1)));
    }
    if !all_have_normals {
        out.normals = None;
    }
    if out.triangles.is_empty() {
        return Err(GltfMeshError::Empty);
    }
    out.check()
        .map_err(|message| GltfMeshError::Invalid { message })?;
    Ok(GltfMesh {
        mesh: out,
        materials: materials.into_iter().map(|(_, m)| m).collect(),
        triangle_materials,
    })
}

/// The file's JSON document, parsed without the reader's validation; `None` for input the
/// reader cannot even deserialise (its own message then reports it).
fn json_root(bytes: &[u8]) -> Option<gltf::json::Root> {
    let json: std::borrow::Cow<[u8]> = if bytes.starts_with(b"glTF") {
        gltf::Glb::from_slice(bytes).ok()?.json
    } else {
        bytes.into()
    };
    gltf::json::Root::from_slice(&json).ok()
}

/// Key of a material's `extras` (glTF 2.0's application-specific data on any object) that
/// names the part of a glass object it covers: `"edge"` marks a target's edge finish
/// (`scene::load`, `[target]`). Blender writes a material's custom properties there.
pub const PART_EXTRAS_KEY: &str = "glassscan_part";

/// Per material of the file, its `extras.glassscan_part` string, if any (read from the raw
/// JSON: the glTF reader keeps `extras` only with a feature glassscan does not build).
fn material_parts(bytes: &[u8]) -> Vec<Option<String>> {
    let json: Option<std::borrow::Cow<[u8]>> = if bytes.starts_with(b"glTF") {
        gltf::Glb::from_slice(bytes).ok().map(|g| g.json)
    } else {
        Some(bytes.into())
    };
    let Some(root) = json.and_then(|j| serde_json::from_slice::<serde_json::Value>(&j).ok()) else {
        return Vec::new();
    };
    let Some(materials) = root.get("materials").and_then(|m| m.as_array()) else {
        return Vec::new();
    };
    (materials.iter())
        .map(|m| {
            let part = m.get("extras").and_then(|e| e.get(PART_EXTRAS_KEY));
            part.and_then(|p| p.as_str()).map(str::to_owned)
        })
        .collect()
}

/// Refuses a file that requires an extension glassscan does not read
/// ([`HANDLED_EXTENSIONS`]) or that its reader refuses as required
/// ([`REQUIRABLE_EXTENSIONS`]), by name, before the glTF reader's own, terser refusal.
fn check_required_extensions(bytes: &[u8]) -> Result<(), String> {
    let Some(root) = json_root(bytes) else {
        return Ok(());
    };
    let required = root.extensions_required.iter().map(String::as_str);
    let unknown: Vec<&str> = required
        .clone()
        .filter(|e| !HANDLED_EXTENSIONS.contains(e))
        .collect();
    if !unknown.is_empty() {
        return Err(format!(
            "the file requires the glTF extension(s) {}, which glassscan does not read (it \
             reads {})",
            unknown.join(", "),
            HANDLED_EXTENSIONS.join(", ")
        ));
    }
    if let Some(e) = required
        .clone()
        .find(|e| !REQUIRABLE_EXTENSIONS.contains(e))
    {
        return Err(format!(
            "the file lists {e} in extensionsRequired; glassscan reads it, but its glTF reader \
             (gltf 1.4.1) refuses it there: list it in extensionsUsed only"
        ));
    }
    Ok(())
}

/// Refuses a GLB whose header states a total length below the header's own 12 bytes: the
/// glTF reader subtracts 12 from it unchecked (gltf 1.4.1, `Glb::from_slice`: an overflow;
/// found by the `gltf_mesh` fuzz target).
fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    if let (Some(b"glTF"), Some(length)) = (bytes.get(..4), bytes.get(8..12)) {
        let length = u32::from_le_bytes(length.try_into().expect("4 bytes"));
        if length < 12 {
            return Err(format!(
                "invalid GLB: its header states {length} bytes in all, less than the 12-byte \
                 header itself"
            ));
        }
    }
    Ok(())
}

/// Refuses a primitive whose attributes name an accessor the file does not have, before the
/// glTF reader's validation indexes its accessor list with it (gltf-json 1.4.1 panics there,
/// in its primitive validation hook; found by the `gltf_mesh` fuzz target). Input the reader
/// cannot even deserialise is left to it, so that its own message reports it.
fn check_accessor_indices(bytes: &[u8]) -> Result<(), String> {
    let Some(root) = json_root(bytes) else {
        return Ok(());
    };
    let n = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let targets = prim.targets.iter().flatten();
            let morph = targets.flat_map(|t| [&t.positions, &t.normals, &t.tangents]);
            let used = (prim.attributes.values().map(|i| i.value()))
                .chain(prim.indices.iter().map(|i| i.value()))
                .chain(morph.flatten().map(|i| i.value()));
            for index in used {
                if index >= n {
                    return Err(format!(
                        "mesh {m} primitive {p} refers to accessor {index}, but the file has \
                         {n} accessor(s)"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Refuses accessors of a type the glTF 2.0 core allows not for their role (§3.7.2.1):
/// POSITION and NORMAL must be float VEC3, indices unsigned-integer SCALAR. The glTF reader
/// assumes so and panics otherwise (gltf 1.4.1, `Reader::read_indices`: `unreachable!()` for
/// float indices; found by the `gltf_mesh` fuzz target).
fn check_accessor_types(mesh: usize, prim: &gltf::Primitive) -> Result<(), GltfMeshError> {
    use gltf::accessor::{DataType, Dimensions};
    use gltf::Semantic;
    let bad = |what: &str, expected: &str, a: &gltf::Accessor| GltfMeshError::Invalid {
        message: format!(
            "mesh {mesh} primitive {}: {what} accessor {} is {:?} {:?}, expected {expected}",
            prim.index(),
            a.index(),
            a.dimensions(),
            a.data_type()
        ),
    };
    for (semantic, a) in prim.attributes() {
        let what = match semantic {
            Semantic::Positions => "POSITION",
            Semantic::Normals => "NORMAL",
            _ => continue,
        };
        if a.dimensions() != Dimensions::Vec3 || a.data_type() != DataType::F32 {
            return Err(bad(what, "Vec3 F32", &a));
        }
    }
    if let Some(a) = prim.indices() {
        let unsigned = matches!(a.data_type(), DataType::U8 | DataType::U16 | DataType::U32);
        if a.dimensions() != Dimensions::Scalar || !unsigned {
            return Err(bad("the indices", "Scalar U8, U16 or U32", &a));
        }
    }
    Ok(())
}

/// Refuses a POSITION, NORMAL or index accessor whose stated layout does not fit the bytes
/// behind it, before the glTF reader computes its slice unchecked (gltf 1.4.1,
/// `accessor::util::Iter::new`: `stride * (count - 1)`, an overflow for `"count": 0`, found
/// by the `gltf_mesh` fuzz target in CI; a stride below the element size trips its debug
/// assertion). The glTF 2.0 schema requires `count` ≥ 1 (accessor and sparse), a
/// `byteStride` of at least the element size, each accessor inside its buffer view and each
/// buffer view inside its buffer (§3.6.2.4, Data Alignment, states the accessor bound as
/// `byteOffset + stride · (count − 1) + element size ≤ bufferView.byteLength`).
fn check_accessor_layouts(
    mesh: usize,
    prim: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
) -> Result<(), GltfMeshError> {
    use gltf::Semantic;
    let used = prim
        .attributes()
        .filter_map(|(semantic, a)| match semantic {
            Semantic::Positions => Some(("POSITION", a)),
            Semantic::Normals => Some(("NORMAL", a)),
            _ => None,
        })
        .chain(prim.indices().map(|a| ("indices", a)));
    for (what, a) in used {
        let element = a.size();
        let sparse = a.sparse();
        let mut parts = Vec::with_capacity(3);
        if let Some(view) = a.view() {
            parts.push(("", view, a.offset(), a.count(), element));
        }
        if let Some(s) = &sparse {
            let ix = s.indices();
            let values = s.values();
            parts.push((
                "its sparse indices: ",
                ix.view(),
                ix.offset(),
                s.count(),
                ix.index_type().size(),
            ));
            parts.push((
                "its sparse values: ",
                values.view(),
                values.offset(),
                s.count(),
                element,
            ));
        }
        let fail = |message: String| GltfMeshError::Invalid {
            message: format!(
                "mesh {mesh} primitive {}: {what} accessor {}: {message}",
                prim.index(),
                a.index()
            ),
        };
        if a.count() > crate::limits::MAX_ACCESSOR_COUNT {
            return Err(fail(format!(
                "count {} exceeds the limit of {} elements",
                a.count(),
                crate::limits::MAX_ACCESSOR_COUNT
            )));
        }
        for (role, view, offset, count, size) in parts {
            check_slice(view, offset, count, size, buffers)
                .map_err(|m| fail(format!("{role}{m}")))?;
        }
    }
    Ok(())
}

/// Whether `count` elements of `size` bytes from `offset` into `view` (at the view's stride,
/// or packed) lie inside the view, and the view inside its buffer; all in checked arithmetic,
/// since every number comes from the file.
fn check_slice(
    view: gltf::buffer::View,
    offset: usize,
    count: usize,
    size: usize,
    buffers: &[gltf::buffer::Data],
) -> Result<(), String> {
    let v = view.index();
    if count == 0 {
        return Err("count is 0, expected at least 1".to_owned());
    }
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "buffer view {v} has byteStride {stride}, less than the {size}-byte element"
        ));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|n| n.checked_add(offset))
        .and_then(|n| n.checked_add(size));
    match end {
        Some(end) if end <= view.length() => {}
        _ => {
            return Err(format!(
                "{count} elements of {size} bytes at offset {offset} and stride {stride} do \
                 not fit buffer view {v} of {} bytes",
                view.length()
            ))
        }
    }
    let buffer = view.buffer().index();
    let have = buffers.get(buffer).map_or(0, |d| d.0.len());
    match view.offset().checked_add(view.length()) {
        Some(end) if end <= have => Ok(()),
        _ => Err(format!(
            "buffer view {v} spans bytes {}..+{} of buffer {buffer}, which holds {have}",
            view.offset(),
            view.length()
        )),
    }
}

/// The glTF reader's error in words a user can act on: an empty or truncated file says so
/// (the reader's own message for both is "failed to fill whole buffer").
fn describe(error: &gltf::Error, bytes: &[u8]) -> String {
    use gltf::binary::Error as Glb;
    match error {
        _ if bytes.is_empty() => "the file is empty (expected glTF JSON or a GLB binary)".into(),
        gltf::Error::Binary(Glb::Io(e)) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            format!(
                "truncated GLB: the file ends after {} bytes, inside its 12-byte header or \
                 a chunk header",
                bytes.len()
            )
        }
        // The reader counts both lengths after the 12-byte header.
        gltf::Error::Binary(Glb::Length { length, .. }) => format!(
            "truncated GLB: its header states {} bytes, the file has {}",
            u64::from(*length) + 12,
            bytes.len()
        ),
        other => other.to_string(),
    }
}

/// The triangles of one glTF mesh, transformed by `world`, and how many each primitive gave.
fn mesh_part(
    mesh: &gltf::Mesh,
    buffers: &[gltf::buffer::Data],
    world: &Matrix4<f64>,
) -> Result<(Mesh, Vec<usize>), GltfMeshError> {
    let linear: Matrix3<f64> = world.fixed_view::<3, 3>(0, 0).into_owned();
    let mirrored = linear.determinant() < 0.0;
    let normal_matrix = linear.try_inverse().map(|m| m.transpose());
    // Mesh names need gltf's `names` feature, which the crate does not enable; the index
    // identifies the mesh in the file's `meshes` array.
    let name = mesh.index();
    let mut out = Mesh::default();
    let mut counts = Vec::new();
    let mut all_have_normals = true;
    for prim in mesh.primitives() {
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return Err(GltfMeshError::NonTriangle {
                mesh: name,
                primitive: prim.index(),
                mode: mode_name(mode),
            });
        }
        check_accessor_types(name, &prim)?;
        check_accessor_layouts(name, &prim, buffers)?;
        let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
        let positions: Vec<Point3<f64>> = reader
            .read_positions()
            .ok_or_else(|| GltfMeshError::Invalid {
                message: format!("mesh {name} primitive {} has no POSITION", prim.index()),
            })?
            .map(|p| {
                let p = Point3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
                world.transform_point(&p)
            })
            .collect();
        let n = positions.len() as u32;
        let indices: Vec<u32> = match reader.read_indices() {
            Some(ix) => ix.into_u32().collect(),
            None => (0..n).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i >= n) {
            return Err(GltfMeshError::Invalid {
                message: format!(
                    "mesh {name} primitive {} has index {bad} out of {n} vertices",
                    prim.index()
                ),
            });
        }
        let mut triangles = assemble(mode, &indices);
        if mirrored {
            for t in &mut triangles {
                t.swap(1, 2);
            }
        }
        let normals = match (reader.read_normals(), normal_matrix) {
            (Some(ns), Some(nm)) => {
                let ns: Vec<Vector3<f64>> = ns
                    .map(|v| nm * Vector3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2])))
                    .map(|v| v.try_normalize(1e-12).unwrap_or_else(Vector3::z))
                    .collect();
                (ns.len() == positions.len()).then_some(ns)
            }
            _ => None,
        };
        all_have_normals &= normals.is_some();
        let parts = vec![SurfacePart::Solid; triangles.len()];
        counts.push(triangles.len());
        out.append(&Mesh {
            positions,
            normals,
            triangles,
            parts,
        });
    }
    if !all_have_normals {
        out.normals = None;
    }
    Ok((out, counts))
}

/// Triangles from an index list in a triangle mode (glTF 2.0 §3.7.2.1, primitive topologies).
/// Degenerate triangles (repeated index) are dropped.
fn assemble(mode: Mode, ix: &[u32]) -> Vec<[u32; 3]> {
    let tris: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => (2..ix.len())
            .map(|i| {
                // Every second triangle of a strip is wound the other way round.
                if i % 2 == 0 {
                    [ix[i - 2], ix[i - 1], ix[i]]
                } else {
                    [ix[i - 1], ix[i - 2], ix[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..ix.len()).map(|i| [ix[0], ix[i - 1], ix[i]]).collect(),
        _ => ix.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    };
    tris.into_iter()
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .collect()
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes/meshes")
            .join(name)
    }

    #[test]
    fn cube_fixture_applies_node_transforms_and_scale() {
        // cube.gltf: a unit cube (±0.5) under a parent node translated by (0, 0, 2) whose
        // child is translated by (1, 0, 0): the cube's centre lands at (1, 0, 2) file units.
        let mesh = load_gltf_mesh(&fixture("cube.gltf"), 0.1).expect("cube loads");
        assert_eq!(mesh.triangle_count(), 12);
        let n = mesh.positions.len() as f64;
        let centre = mesh
            .positions
            .iter()
            .map(|p| p.coords)
            .sum::<Vector3<f64>>()
            / n;
        assert!(
            (centre - Vector3::new(0.1, 0.0, 0.2)).norm() < 1e-7,
            "{centre:?}"
        );
        for axis in 0..3 {
            let lo = mesh
                .positions
                .iter()
                .map(|p| p[axis])
                .fold(f64::MAX, f64::min);
            let hi = mesh
                .positions
                .iter()
                .map(|p| p[axis])
                .fold(f64::MIN, f64::max);
            assert!((hi - lo - 0.1).abs() < 1e-7, "axis {axis}: {lo}..{hi}");
        }
        // Outward winding survives: the signed volume is positive (0.1³).
        let volume: f64 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| mesh.positions[k as usize].coords);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum();
        assert!((volume - 1e-3).abs() < 1e-9, "volume {volume}");
        assert!(mesh.parts.iter().all(|&p| p == SurfacePart::Solid));
    }

    #[test]
    fn lines_primitive_is_rejected_with_its_mode() {
        let err = load_gltf_mesh(&fixture("lines.gltf"), 1.0).unwrap_err();
        let msg = err.to_string();
        assert!(
            matches!(err, GltfMeshError::NonTriangle { primitive: 0, .. }),
            "{msg}"
        );
        assert!(msg.contains("LINES") && msg.contains("mesh 0"), "{msg}");
    }

    #[test]
    fn missing_file_is_an_open_error() {
        let err = load_gltf_mesh(&fixture("no-such-file.gltf"), 1.0).unwrap_err();
        assert!(matches!(err, GltfMeshError::Open { .. }), "{err}");
    }

    #[test]
    fn empty_truncated_and_missing_buffer_files_say_what_is_wrong() {
        let dir = Path::new("/nonexistent-dir/part.glb");
        let msg = |bytes: &[u8]| {
            load_gltf_mesh_from_slice(dir, bytes, 1.0)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            msg(b""),
            "the file is empty (expected glTF JSON or a GLB binary)"
        );
        assert!(
            msg(b"glTF\x02\0\0").contains("truncated GLB"),
            "{}",
            msg(b"glTF\x02\0\0")
        );
        // A 20-byte file whose header claims 1000 bytes.
        let mut glb = b"glTF".to_vec();
        glb.extend(2u32.to_le_bytes());
        glb.extend(1000u32.to_le_bytes());
        glb.extend([0u8; 8]);
        assert!(
            msg(&glb).contains("header states 1000 bytes, the file has 20"),
            "{}",
            msg(&glb)
        );
        glb[8..12].copy_from_slice(&3u32.to_le_bytes());
        assert!(msg(&glb).contains("states 3 bytes in all"), "{}", msg(&glb));
        let json =
            br#"{"asset":{"version":"2.0"},"buffers":[{"uri":"missing.bin","byteLength":12}]}"#;
        assert_eq!(
            msg(json),
            "buffer 0 refers to `/nonexistent-dir/missing.bin`, which does not exist"
        );
    }

    #[test]
    fn an_accessor_index_out_of_range_is_an_error_not_a_panic() {
        // The fuzz target's first crash, reduced: POSITION names accessor 0 of none.
        let json = br#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
        let err = load_gltf_mesh_from_slice(Path::new("x.gltf"), json, 1.0).unwrap_err();
        assert_eq!(
            err.to_string(),
            "mesh 0 primitive 0 refers to accessor 0, but the file has 0 accessor(s)"
        );
    }

    #[test]
    fn float_indices_are_an_error_not_a_panic() {
        // One vertex (12 zero bytes in a data URI) and an index accessor of FLOAT (5126), which
        // the glTF reader meets with `unreachable!()`.
        let json = br#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
            "buffers":[{"byteLength":12,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}],
            "bufferViews":[{"buffer":0,"byteLength":12}],
            "accessors":[{"bufferView":0,"componentType":5126,"count":1,"type":"VEC3","min":[0,0,0],"max":[0,0,0]},
                         {"bufferView":0,"componentType":5126,"count":3,"type":"SCALAR"}],
            "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}]}"#;
        let err = load_gltf_mesh_from_slice(Path::new("x.gltf"), json, 1.0).unwrap_err();
        assert!(
            err.to_string()
                .contains("the indices accessor 1 is Scalar F32, expected Scalar U8, U16 or U32"),
            "{err}"
        );
    }

    /// A one-mesh file over a 36-byte buffer of zeros (three vertices), with the given buffer
    /// views and accessors; POSITION is accessor 0, `indices` (if any) accessor 1.
    fn three_vertex_file(views: &str, accessors: &str, indices: bool) -> Vec<u8> {
        let indices = if indices { r#","indices":1"# } else { "" };
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
            "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{zeros}"}}],
            "bufferViews":[{views}],"accessors":[{accessors}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}{indices}}}]}}]}}"#,
            zeros = "A".repeat(48)
        )
        .into_bytes()
    }

    #[test]
    fn accessor_layouts_that_do_not_fit_are_errors_not_panics() {
        // The CI fuzz run's crash, reduced: `"count": 0` made the glTF reader compute
        // `stride * (0 - 1)`. Each case must be refused with a message naming the accessor;
        // in a debug build (overflow checks on) a missed case panics instead.
        let msg = |views: &str, accessors: &str, indices: bool| {
            let file = three_vertex_file(views, accessors, indices);
            load_gltf_mesh_from_slice(Path::new("x.gltf"), &file, 1.0)
                .unwrap_err()
                .to_string()
        };
        let view = r#"{"buffer":0,"byteLength":36}"#;
        let position = |count: &str| {
            format!(
                r#"{{"bufferView":0,"componentType":5126,"count":{count},"type":"VEC3",
                "min":[0,0,0],"max":[0,0,0]}}"#
            )
        };
        let cases = [
            (
                view.to_owned(),
                position("0"),
                false,
                "POSITION accessor 0: count is 0",
            ),
            (
                view.to_owned(),
                position("4"),
                false,
                "4 elements of 12 bytes at offset 0 and stride 12 do not fit buffer view 0 of 36",
            ),
            (
                view.to_owned(),
                position("1099511627776"),
                false,
                "count 1099511627776 exceeds the limit",
            ),
            (
                r#"{"buffer":0,"byteLength":36,"byteStride":8}"#.to_owned(),
                position("3"),
                false,
                "byteStride 8, less than the 12-byte element",
            ),
            (
                r#"{"buffer":0,"byteOffset":12,"byteLength":36}"#.to_owned(),
                position("3"),
                false,
                "buffer view 0 spans bytes 12..+36 of buffer 0, which holds 36",
            ),
            (
                view.to_owned(),
                format!(
                    r#"{},{{"bufferView":0,"componentType":5123,"count":0,"type":"SCALAR"}}"#,
                    position("3")
                ),
                true,
                "indices accessor 1: count is 0",
            ),
            (
                view.to_owned(),
                r#"{"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[0,0,0],"sparse":{"count":0,
                    "indices":{"bufferView":0,"componentType":5123},"values":{"bufferView":0}}}"#
                    .to_owned(),
                false,
                "POSITION accessor 0: its sparse indices: count is 0",
            ),
            (
                view.to_owned(),
                r#"{"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[0,0,0],"sparse":{"count":3,
                    "indices":{"bufferView":0,"componentType":5123},
                    "values":{"bufferView":0,"byteOffset":12}}}"#
                    .to_owned(),
                false,
                "its sparse values: 3 elements of 12 bytes at offset 12",
            ),
        ];
        for (views, accessors, indices, expected) in cases {
            let m = msg(&views, &accessors, indices);
            assert!(m.contains(expected), "expected `{expected}` in: {m}");
        }
    }

    #[test]
    fn strips_and_fans_are_assembled_with_consistent_winding() {
        let strip = assemble(Mode::TriangleStrip, &[0, 1, 2, 3]);
        assert_eq!(strip, vec![[0, 1, 2], [2, 1, 3]]);
        let fan = assemble(Mode::TriangleFan, &[0, 1, 2, 3]);
        assert_eq!(fan, vec![[0, 1, 2], [0, 2, 3]]);
    }
}
