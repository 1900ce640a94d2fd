//! What a glTF file's material says about the light at the laser wavelength, and how it maps
//! to glassscan's materials (the scene loader merges it with the scene file's
//! `material_overrides` and records where each value came from).
//!
//! The mapping (glTF 2.0 §3.9 and the Khronos extensions' specifications):
//! - `KHR_materials_transmission.transmissionFactor` > 0 → glass. Its index is
//!   `KHR_materials_ior.ior`, 1.5 when absent (the extension's default, which is also what core
//!   glTF assumes for dielectrics). Its absorption is `KHR_materials_volume`'s: white light
//!   becomes `attenuationColor` after `attenuationDistance`, so Beer–Lambert gives
//!   σ = −ln(c)/d; at 658 nm glassscan takes the red channel c_r (linear, as glTF stores it:
//!   an approximation, the red primary spans ~600–700 nm). The distance is in file units, so it
//!   is multiplied by the mesh's `scale`. No volume extension: no absorption.
//! - Otherwise opaque → Lambertian with albedo = `baseColorFactor`'s red channel (linear; the
//!   laser is red). Textures are not read; a metallic material (`metallicFactor` > 0) is still
//!   taken as Lambertian, with a warning.
//!
//! glTF cannot say how the faces scatter (`face_imperfection`) or how rough a ground edge is
//! (`edge_roughness`): a glass material from a file needs both from the scene file.

/// A glTF material, read.
#[derive(Clone, Debug, PartialEq)]
pub struct FileMaterial {
    /// How messages name it: `material 2 "Glass"`, or `the default material`.
    pub label: String,
    /// Its `name`, if it has one.
    pub name: Option<String>,
    /// Its `extras.glassscan_part` (`gltf_mesh::PART_EXTRAS_KEY`), if any: `"edge"` marks a
    /// target's edge finish.
    pub part: Option<String>,
    /// `KHR_materials_transmission.transmissionFactor` (0 when absent).
    pub transmission: f64,
    /// `KHR_materials_ior.ior`, if the file gives it.
    pub ior: Option<f64>,
    /// `KHR_materials_volume`: (attenuation distance in m after `scale`, red channel of the
    /// attenuation colour), if the file gives a finite distance.
    pub attenuation: Option<(f64, f64)>,
    /// Red channel of `baseColorFactor` (linear).
    pub base_red: f64,
    /// `metallicFactor`.
    pub metallic: f64,
    /// `roughnessFactor` (1 when absent, the default of glTF 2.0's
    /// `material.pbrMetallicRoughness` schema); the microfacet α is its square (glTF 2.0,
    /// Appendix B: α = roughness²).
    pub roughness: f64,
}

/// `KHR_materials_ior`'s default index (and core glTF's assumption for dielectrics).
pub const GLTF_DEFAULT_IOR: f64 = 1.5;

/// The glTF extensions glassscan reads.
pub const HANDLED_EXTENSIONS: [&str; 3] = [
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_volume",
];

/// The ones a file may also list in `extensionsRequired`: the glTF reader (gltf-json 1.4.1)
/// reads `KHR_materials_volume` but refuses it as required, so a file must list it in
/// `extensionsUsed` only (which is what exporters such as Blender do).
pub const REQUIRABLE_EXTENSIONS: [&str; 2] = ["KHR_materials_transmission", "KHR_materials_ior"];

impl FileMaterial {
    /// Reads `material` of a file whose lengths are multiplied by `scale` to give metres.
    pub fn read(material: &gltf::Material, scale: f64) -> FileMaterial {
        let label = match (material.index(), material.name()) {
            (Some(i), Some(name)) => format!("material {i} \"{name}\""),
            (Some(i), None) => format!("material {i}"),
            (None, _) => "the default material".to_owned(),
        };
        let pbr = material.pbr_metallic_roughness();
        let attenuation = material.volume().and_then(|v| {
            let d = f64::from(v.attenuation_distance());
            (d.is_finite() && d > 0.0).then(|| (d * scale, f64::from(v.attenuation_color()[0])))
        });
        FileMaterial {
            label,
            name: material.name().map(str::to_owned),
            part: None, // from the raw JSON, `gltf_mesh`
            transmission: material
                .transmission()
                .map_or(0.0, |t| f64::from(t.transmission_factor())),
            ior: material.ior().map(f64::from),
            attenuation,
            base_red: f64::from(pbr.base_color_factor()[0]),
            metallic: f64::from(pbr.metallic_factor()),
            roughness: f64::from(pbr.roughness_factor()),
        }
    }

    /// Whether it is glass (transmits).
    pub fn is_glass(&self) -> bool {
        self.transmission > 0.0
    }

    /// The Beer–Lambert absorption coefficient (1/m) it gives: −ln(c_r)/d, 0 without a volume.
    /// `None` for a colour that is not in (0, 1] (a black colour would be infinitely opaque).
    pub fn absorption_per_m(&self) -> Option<f64> {
        match self.attenuation {
            None => Some(0.0),
            Some((d, c)) if c > 0.0 && c <= 1.0 => Some(-c.ln() / d),
            Some(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glass(attenuation: Option<(f64, f64)>) -> FileMaterial {
        FileMaterial {
            label: "m".into(),
            name: None,
            part: None,
            roughness: 1.0,
            transmission: 1.0,
            ior: None,
            attenuation,
            base_red: 1.0,
            metallic: 0.0,
        }
    }

    #[test]
    fn beer_lambert_from_the_attenuation_colour_and_distance() {
        // White light keeps c after d: exp(−σ d) = c.
        let m = glass(Some((0.01, 0.9)));
        let sigma = m.absorption_per_m().unwrap();
        assert!(((-sigma * 0.01).exp() - 0.9).abs() < 1e-15);
        // Clear float at 658 nm, 0.003 /mm (the shipped scenes' value): transmits e^−0.012 over 4 mm.
        let d: f64 = 0.004;
        let c = (-3.0 * d).exp();
        assert!((glass(Some((d, c))).absorption_per_m().unwrap() - 3.0).abs() < 1e-12);
        assert_eq!(glass(None).absorption_per_m(), Some(0.0));
        assert_eq!(glass(Some((0.01, 0.0))).absorption_per_m(), None);
        assert_eq!(glass(Some((0.01, 1.0))).absorption_per_m(), Some(0.0));
    }
}
