//! The resolved scene: everything the simulation needs, validated, in SI units.

use std::path::PathBuf;

use crate::geometry::border::BorderCurve;
use crate::geometry::mesh::Mesh;
use crate::geometry::pose::Pose;
use crate::scan::ScanConfig;
use crate::sensor::SensorConfig;

/// Optical properties of a glass material, as parsed from the scene file. The glass light
/// transport (issue #3) consumes these; until then a scene that uses glass cannot be simulated.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GlassSpec {
    /// Refractive index at the laser wavelength (if given directly).
    pub ior: Option<f64>,
    /// Cauchy coefficients (A, B µm², C µm⁴…), n(λ) = A + B/λ² + C/λ⁴ (λ in µm), if given.
    pub cauchy: Option<Vec<f64>>,
    /// Sellmeier coefficients B1..3 and C1..3 (µm²), if given.
    pub sellmeier: Option<([f64; 3], [f64; 3])>,
    /// Beer–Lambert absorption coefficient (1/m).
    pub absorption_per_m: f64,
    /// Fraction of light scattered diffusely by the faces (dust, micro-defects), in [0, 1).
    pub face_imperfection: f64,
    /// RMS slope roughness α of the ground edge (microfacet parameter), ≥ 0.
    pub edge_roughness: f64,
}

impl GlassSpec {
    /// Refractive index at vacuum wavelength `wavelength_m`: the given `ior`, or the Cauchy law
    /// n = A + B/λ² + C/λ⁴ + … or the Sellmeier law n² = 1 + Σ Bᵢλ²/(λ² − Cᵢ), λ in µm
    /// (NaN where n² < 0; the scene loader checks that exactly one law is given and that it
    /// yields n ≥ 1).
    pub fn index_at(&self, wavelength_m: f64) -> f64 {
        let l2 = (wavelength_m * 1e6).powi(2);
        if let Some(n) = self.ior {
            n
        } else if let Some(c) = &self.cauchy {
            c.iter().zip(0..).map(|(a, k)| a / l2.powi(k)).sum()
        } else if let Some((b, c)) = &self.sellmeier {
            let n2 = 1.0 + (0..3).map(|k| b[k] * l2 / (l2 - c[k])).sum::<f64>();
            if n2 >= 0.0 {
                n2.sqrt()
            } else {
                f64::NAN
            }
        } else {
            f64::NAN
        }
    }
}

/// A material, by kind.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Material {
    /// An ideal diffuse reflector with the given albedo in [0, 1].
    Lambertian {
        /// Hemispherical reflectance in [0, 1].
        albedo: f64,
    },
    /// Glass (parsed, not yet simulated).
    Glass(GlassSpec),
}

/// A named material.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedMaterial {
    /// The name used by objects in the scene file.
    pub name: String,
    /// Its optical model.
    pub material: Material,
}

/// What an object is, for the path labels of the light it returns (glass objects are labelled
/// by their surface part instead).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ObjectLabel {
    /// The table the target lies on.
    Table,
    /// A background surface (wall, floor) seen beyond the target.
    Background,
    /// Tape laid over the glass border (the paper's edge experiment, step 1).
    Tape,
    /// A cover block on the glass surface (edge experiment, step 2).
    Cover,
    /// Anything else.
    #[default]
    Other,
}

/// One object of the scene.
#[derive(Clone, Debug)]
pub struct Object {
    /// Name from the scene file (unique).
    pub name: String,
    /// Mesh in the object's model frame (m).
    pub mesh: Mesh,
    /// True pose of the object in the base frame B (T_B_object).
    pub pose: Pose,
    /// Index into `World::materials`.
    pub material: usize,
    /// Role for path labels.
    pub label: ObjectLabel,
}

/// The object whose border is scanned and located (the glass panel or its opaque copy).
#[derive(Clone, Debug)]
pub struct Target {
    /// Index into `World::objects`.
    pub object: usize,
    /// The border edge curve in the model frame M.
    pub border: BorderCurve,
    /// The nominal (coarse) pose T_BM0 that localisation starts from.
    pub nominal_pose: Pose,
}

/// A validated scene, ready to simulate.
#[derive(Clone, Debug)]
pub struct World {
    /// The scene file it came from.
    pub source: PathBuf,
    /// All objects (at least one).
    pub objects: Vec<Object>,
    /// All materials referenced by objects.
    pub materials: Vec<NamedMaterial>,
    /// The scanned object, if the scene names one.
    pub target: Option<Target>,
    /// The sensor head (preset plus overrides).
    pub sensor: SensorConfig,
    /// Hand-eye mount T_FS: the sensor frame in the robot flange frame.
    pub mount: Pose,
    /// Scan settings (CLI flags may override them).
    pub scan: ScanConfig,
    /// Where the values of every material taken from a glTF file came from.
    pub material_sources: Vec<MaterialSource>,
    /// What the loader found suspicious but not wrong (e.g. a mesh of implausible size), each
    /// naming the field; the command line prints them and the manifests record them.
    pub warnings: Vec<String>,
}

/// A material taken from a mesh's glTF file: which one, and where each value came from.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MaterialSource {
    /// The object.
    pub object: String,
    /// The glTF file, as the scene file names it.
    pub file: String,
    /// The glTF material (`material 0 "Glass"`).
    pub gltf_material: String,
    /// `glass` or `lambertian`.
    pub kind: &'static str,
    /// Each value in the scene file's units, with its source.
    pub values: Vec<MaterialValue>,
}

/// One value of a [`MaterialSource`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MaterialValue {
    /// The scene file's key (`ior`, `absorption_per_mm`, …).
    pub key: &'static str,
    /// The value, in that key's unit.
    pub value: f64,
    /// `file` (the glTF material), `toml` (`material_overrides`) or `gltf default` (the
    /// extension's default for a value the file leaves out).
    pub source: &'static str,
}

/// Albedo of the opaque copy of a target (the paper's Table 3 compares the glass with an
/// opaque object of the same shape; its surface is not described, so a matte mid-grey is a
/// modelling choice, L).
pub const OPAQUE_COPY_ALBEDO: f64 = 0.5;

impl World {
    /// The target's border curve in the base frame, at the target's true pose (where p_e
    /// lies); `None` without a target.
    pub fn true_border_in_base(&self) -> Option<BorderCurve> {
        let target = self.target.as_ref()?;
        Some(target.border.transformed(&self.objects[target.object].pose))
    }

    /// The same scene with the target made of an opaque Lambertian material of `albedo`
    /// (same mesh, pose and border): the paper's opaque-object comparison. `None` without a
    /// target.
    pub fn with_opaque_target(&self, albedo: f64) -> Option<World> {
        let target = self.target.as_ref()?;
        let mut world = self.clone();
        world.materials.push(NamedMaterial {
            name: "opaque_copy".into(),
            material: Material::Lambertian { albedo },
        });
        world.objects[target.object].material = world.materials.len() - 1;
        Some(world)
    }
}
