//! Path classes: what produced a contribution on the sensor. Every splat of the light transport
//! carries one, the irradiance is also written as one image per class, and each profile peak
//! is labelled with the class that dominates it.

/// The class of a light path, decided at the vertex that connects to the camera (or at the
/// aperture, for a glint).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PathClass {
    /// Diffuse scattering by a glass face's imperfections (dust, micro-defects).
    GlassFace,
    /// Scattering by the rough (ground, seamed) glass edge.
    GlassEdge,
    /// An opaque surface whose light passed through glass on the way in or out (mixed pixels).
    ThroughGlass,
    /// A purely specular chain from the laser into the aperture: a glint.
    Glint,
    /// A glass-face scatterer reached after an internal reflection inside the glass.
    InternalReflection,
    /// The table, seen directly.
    Table,
    /// Tape or a cover block, seen directly.
    TapeCover,
    /// Any other opaque surface (background wall, supports), seen directly.
    Background,
}

impl PathClass {
    /// Every class, in layer order.
    pub const ALL: [PathClass; 8] = [
        PathClass::GlassFace,
        PathClass::GlassEdge,
        PathClass::ThroughGlass,
        PathClass::Glint,
        PathClass::InternalReflection,
        PathClass::Table,
        PathClass::TapeCover,
        PathClass::Background,
    ];

    /// Position in [`PathClass::ALL`].
    pub fn index(self) -> usize {
        PathClass::ALL
            .iter()
            .position(|&c| c == self)
            .expect("ALL lists every class")
    }

    /// The snake_case name used for EXR layers and reports.
    pub fn name(self) -> &'static str {
        match self {
            PathClass::GlassFace => "glass_face",
            PathClass::GlassEdge => "glass_edge",
            PathClass::ThroughGlass => "through_glass",
            PathClass::Glint => "glint",
            PathClass::InternalReflection => "internal_reflection",
            PathClass::Table => "table",
            PathClass::TapeCover => "tape_cover",
            PathClass::Background => "background",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_and_names_are_unique() {
        for (i, c) in PathClass::ALL.iter().enumerate() {
            assert_eq!(c.index(), i);
        }
        let mut names: Vec<_> = PathClass::ALL.iter().map(|c| c.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), PathClass::ALL.len());
    }
}
