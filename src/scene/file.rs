//! The scene file as written: serde structs that mirror the TOML one to one, in the file's
//! named units (`_mm`, `_deg`, `_ms`, `_nm`, `_mw`, `_um`). `scenes/README.md` is the
//! reference for every field; `load` validates these values and converts them to SI.
//!
//! Every struct denies unknown keys (a typo is an error, as in Mitsuba), and every value that
//! is validated later is `Spanned`, so that an error can point at its line and column.
//! Integers are read as `i64` so that a negative count gets a range message rather than a
//! type error. Tagged variants use TOML's native enum forms (`"pencil"` or
//! `{ arrissed = { bevel_mm = 0.5 } }`): serde's internally tagged and untagged enums buffer
//! their input and would lose the spans. The edge finish, which takes a kind either as a name
//! or as a table, has its own visitor (`edge_def`), which reads the table's value directly
//! from the TOML deserializer and so keeps the spans too.

use std::collections::BTreeMap;

use serde::Deserialize;
use serde_spanned::Spanned;

/// A number with its place in the file.
pub(crate) type Num = Spanned<f64>;
/// An integer with its place in the file.
pub(crate) type Int = Spanned<i64>;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    /// Named materials.
    #[serde(default)]
    pub materials: BTreeMap<Spanned<String>, Spanned<MaterialDef>>,
    /// The objects, in file order.
    #[serde(default)]
    pub objects: Vec<Spanned<ObjectDef>>,
    /// The scanned object, if any.
    pub target: Option<Spanned<TargetDef>>,
    /// The sensor head.
    pub sensor: Spanned<SensorDef>,
    /// Hand-eye mount T_FS; identity when absent.
    pub mount: Option<Spanned<PoseDef>>,
    /// Scan settings; defaults when absent.
    pub scan: Option<Spanned<ScanDef>>,
}

/// The kinds of material.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(crate) enum MaterialKind {
    Lambertian,
    Glass,
}

/// One material. The fields that belong to the other kind must be absent; `load` checks it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MaterialDef {
    pub kind: Spanned<MaterialKind>,
    /// Lambertian: hemispherical reflectance in [0, 1].
    pub albedo: Option<Num>,
    /// Glass: refractive index at the laser wavelength.
    pub ior: Option<Num>,
    /// Glass: Cauchy coefficients [A, B, C, …], n(λ) = A + B/λ² + C/λ⁴ + … (λ in µm).
    pub cauchy: Option<Spanned<Vec<Num>>>,
    /// Glass: Sellmeier coefficients (C in µm²).
    pub sellmeier: Option<Spanned<SellmeierDef>>,
    /// Glass: Beer–Lambert absorption coefficient (1/mm), ≥ 0.
    pub absorption_per_mm: Option<Num>,
    /// Glass: diffusely scattered fraction at the faces, in [0, 1).
    pub face_imperfection: Option<Num>,
    /// Glass: microfacet roughness α of the ground edge, ≥ 0.
    pub edge_roughness: Option<Num>,
}

/// `material_overrides` of a mesh object whose material comes from its glTF file: each value
/// replaces the file's (or gives what glTF cannot carry: `face_imperfection`, `edge_roughness`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MaterialOverridesDef {
    pub ior: Option<Num>,
    pub absorption_per_mm: Option<Num>,
    pub face_imperfection: Option<Num>,
    pub edge_roughness: Option<Num>,
    pub albedo: Option<Num>,
}

/// n²(λ) = 1 + Σ bᵢ·λ²/(λ² − cᵢ), λ in µm.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SellmeierDef {
    pub b: [Num; 3],
    /// µm².
    pub c: [Num; 3],
}

/// One `[[objects]]` entry: exactly one of `panel`, `box`, `mesh`, `tape`, `cover`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ObjectDef {
    pub name: Spanned<String>,
    /// A `[materials.NAME]`; absent only for a mesh, which then takes its glTF material.
    pub material: Option<Spanned<String>>,
    /// Values for (or instead of) the glTF material's, when `material` is absent.
    pub material_overrides: Option<Spanned<MaterialOverridesDef>>,
    /// True pose T_B_object; identity when absent.
    pub pose: Option<Spanned<PoseDef>>,
    pub panel: Option<Spanned<PanelDef>>,
    #[serde(rename = "box")]
    pub cuboid: Option<Spanned<BoxDef>>,
    pub mesh: Option<Spanned<MeshDef>>,
    /// A tape fitted to a panel object of the scene.
    pub tape: Option<Spanned<TapeDef>>,
    /// A cover fitted to a panel object of the scene.
    pub cover: Option<Spanned<CoverDef>>,
    /// Role of the object for path labels (`table`, `background`, `tape`, `cover`, `other`).
    pub label: Option<Spanned<LabelDef>>,
}

/// A pose: translation (mm) and fixed-axis x, y, z angles (deg), R = Rz·Ry·Rx.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PoseDef {
    pub translation_mm: Option<[Num; 3]>,
    pub rotation_deg: Option<[Num; 3]>,
}

/// A procedural glass panel (`geometry::panel`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PanelDef {
    pub outline: Spanned<OutlineDef>,
    pub thickness_mm: Num,
    /// Absent: flat.
    pub curvature: Option<Spanned<CurvatureDef>>,
    /// Absent: seamed, with the default arrisses.
    pub edge: Option<Spanned<EdgeDef>>,
    /// Absent: 5 mm.
    pub tessellation_mm: Option<Num>,
}

/// Either `width_mm` and `height_mm`, or `polygon_mm`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct OutlineDef {
    pub width_mm: Option<Num>,
    pub height_mm: Option<Num>,
    pub polygon_mm: Option<Spanned<Vec<[Num; 2]>>>,
    /// Absent: 0 (sharp corners).
    pub corner_radius_mm: Option<Num>,
}

/// A cylindrical bend.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CurvatureDef {
    /// Radius of the bottom face (mm), > 0.
    pub radius_mm: Num,
}

/// The edge finish: a kind's name (`"seamed"`, `"flat_ground"`, `"pencil"`) or a one-key
/// table naming a kind with its parameters (`{ seamed = { … } }`, `{ pencil = { … } }`,
/// `{ arrissed = { … } }`, `{ section = { … } }`). Read by `edge_def`, which accepts both
/// forms for one kind (serde's derived enums take a kind either as a name or as a table).
#[derive(Debug)]
pub(crate) enum EdgeDef {
    FlatGround,
    /// `None`: `"seamed"`, every parameter at its default.
    Seamed(Option<Spanned<SeamedDef>>),
    Pencil(Option<Spanned<PencilDef>>),
    Arrissed(Spanned<ArrissedDef>),
    Section(Spanned<SectionDef>),
}

/// `{ seamed = { top = { … }, bottom = { … }, fillet_radius_mm } }`; absent keys take the
/// IGMA/PPG defaults.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SeamedDef {
    pub top: Option<Spanned<ArrisDef>>,
    pub bottom: Option<Spanned<ArrisDef>>,
    /// Absent: 0 (sharp junctions).
    pub fillet_radius_mm: Option<Num>,
}

/// One arris: width across the face (mm, ≥ 0) and angle to the face (deg, 30–65).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ArrisDef {
    pub width_mm: Option<Num>,
    pub angle_deg: Option<Num>,
}

/// `{ pencil = { radius_mm } }`; absent: half the thickness.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PencilDef {
    pub radius_mm: Option<Num>,
}

/// `{ arrissed = { bevel_mm } }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ArrissedDef {
    pub bevel_mm: Num,
}

/// `{ section = { points_mm = [[inset, height], …] } }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SectionDef {
    pub points_mm: Spanned<Vec<Spanned<[Num; 2]>>>,
}

/// `tape = { on = "pane", … }`: the tape sheet over a panel object's edge.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TapeDef {
    /// The panel object the tape is laid on.
    pub on: Spanned<String>,
    pub thickness_mm: Option<Num>,
    pub gap_mm: Option<Num>,
    pub onto_face_mm: Option<Num>,
}

/// `cover = { on = "pane", … }`: the cover on a panel object's top face.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CoverDef {
    /// The panel object the cover sits on.
    pub on: Spanned<String>,
    pub width_mm: Option<Num>,
    pub height_mm: Option<Num>,
    pub gap_mm: Option<Num>,
}

/// A box centred on its pose.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BoxDef {
    pub size_mm: [Num; 3],
}

/// A glTF mesh file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MeshDef {
    /// Relative to the scene file's folder.
    pub file: Spanned<String>,
    /// File units to metres; absent: 1 (glTF is in metres).
    pub scale: Option<Num>,
    /// The file's up axis: `y` (absent; glTF's convention, turned to glassscan's +Z up) or
    /// `z` (taken as it is).
    pub up_axis: Option<Spanned<UpAxisDef>>,
}

/// `mesh.up_axis`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub(crate) enum UpAxisDef {
    /// +Y up (glTF 2.0 §3.4).
    #[serde(rename = "y")]
    Y,
    /// +Z up.
    #[serde(rename = "z")]
    Z,
}

/// `[target]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TargetDef {
    pub object: Spanned<String>,
    /// T_BM0 in the base frame; absent: the true pose.
    pub nominal_pose: Option<Spanned<PoseDef>>,
    /// How a mesh target's border is found; absent: by an edge material if the file has one
    /// named like "edge", else by the default dihedral threshold.
    pub border: Option<Spanned<BorderDef>>,
}

/// `target.border`: how the edge finish of a mesh target is told from its faces
/// (`geometry::mesh_border`). At most one key.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BorderDef {
    /// Creases of at least this angle (deg) separate the faces from the edge finish.
    pub dihedral_deg: Option<Num>,
    /// The glTF material (by name) of the edge finish's triangles.
    pub edge_material: Option<Spanned<String>>,
}

/// `[sensor]`: a preset and overrides.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SensorDef {
    pub preset: Spanned<String>,
    pub wavelength_nm: Option<Num>,
    pub laser_power_mw: Option<Num>,
    pub fan_angle_deg: Option<Num>,
    /// 1/e² full width of the line at the waist (mm).
    pub line_waist_mm: Option<Num>,
    pub waist_distance_mm: Option<Num>,
    pub m_squared: Option<Num>,
    pub line_profile: Option<Spanned<LineProfileDef>>,
    pub polarization: Option<Spanned<PolarizationDef>>,
    pub z_min_mm: Option<Num>,
    pub z_max_mm: Option<Num>,
    pub x_width_mm: Option<Num>,
    pub points_per_profile: Option<Int>,
    pub threshold_dn: Option<Int>,
    /// The firmware's automatic threshold instead of `threshold_dn`.
    pub auto_threshold: Option<Spanned<bool>>,
    /// Peak selection mode: all, first, last, largest_area, max_intensity, single.
    pub peak_select: Option<Spanned<String>>,
    /// Peak filter on the width (px): [min, max].
    pub peak_width_px: Option<Spanned<[Int; 2]>>,
    /// Peak filter on the maximum intensity (DN): [min, max].
    pub peak_intensity_dn: Option<Spanned<[Int; 2]>>,
    /// Laser speckle on rough returns (default true).
    pub speckle: Option<Spanned<bool>>,
    /// Speckle contrast C in (0, 1].
    pub speckle_contrast: Option<Num>,
    pub exposure_ms: Option<Num>,
    pub camera: Option<Spanned<CameraDef>>,
    pub imager: Option<Spanned<ImagerDef>>,
}

/// Intensity along the laser line.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub(crate) enum LineProfileDef {
    Uniform,
    Gaussian { half_angle_1e2_deg: Num },
}

/// Polarisation of the laser: `"unpolarized"` or `{ linear = { angle_deg = 90 } }`.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub(crate) enum PolarizationDef {
    Unpolarized,
    Linear { angle_deg: Num },
}

/// What an opaque object is, for the path labels of its returns.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(crate) enum LabelDef {
    Table,
    Background,
    Tape,
    Cover,
    Other,
}

/// `[sensor.camera]` overrides.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CameraDef {
    pub baseline_mm: Option<Num>,
    pub lens_z_mm: Option<Num>,
    pub aim_distance_mm: Option<Num>,
    pub focal_length_mm: Option<Num>,
    pub f_number: Option<Num>,
    pub pixel_pitch_um: Option<Num>,
    pub columns: Option<Int>,
    pub rows: Option<Int>,
}

/// `[sensor.imager]` overrides.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ImagerDef {
    pub quantum_efficiency: Option<Num>,
    pub full_well_e: Option<Num>,
    pub gain_dn_per_e: Option<Num>,
    pub adc_bits: Option<Int>,
    /// `"cmos"` (clip at the full well) or `"ccd"` (spill along the column).
    pub sensor_kind: Option<Spanned<SensorKindDef>>,
    pub dark_current_e_per_s: Option<Num>,
    pub read_noise_e: Option<Num>,
    pub dark_offset_dn: Option<Num>,
    pub prnu: Option<Num>,
    pub dsnu_e: Option<Num>,
    pub noise: Option<Spanned<bool>>,
}

/// The image sensor's technology, for what happens above the full well.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(crate) enum SensorKindDef {
    Cmos,
    Ccd,
}

/// `[scan]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ScanDef {
    pub scan_angle_deg: Option<Num>,
    pub poses: Option<Int>,
    pub standoff_mm: Option<Num>,
    pub start_fraction: Option<Num>,
}
