//! Path classes: what produced a contribution on the sensor. Every splat of the light transport
//! carries one, the irradiance is also written as one image per class ([`PathClass::ALL`]), and
//! each profile peak is labelled with the class that dominates it, or [`PathClass::SensorNoise`]
//! when no traced light reached its window (a peak made by the sensor's noise alone), so every
//! valid point has a class.

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
    /// A background surface (an object labelled `background`: wall, board), seen directly.
    Background,
    /// The target object itself when it is opaque (an opaque plate, the opaque copy of a glass
    /// target), seen directly.
    Target,
    /// Any other opaque surface (an object without a label: supports, fixtures), seen directly.
    Other,
    /// An opaque surface lit by laser light that a glass surface reflected onto it (the face's
    /// mirror image of the laser line, or the edge's back-scatter) without crossing glass: it
    /// lies off the laser plane, so the sensor puts it where no surface is.
    GlassReflected,
    /// A peak with no traced light in its window: the sensor's noise alone (a label only; it
    /// has no irradiance layer).
    SensorNoise,
}

impl PathClass {
    /// Every class of traced light, in layer order: one irradiance image each.
    pub const ALL: [PathClass; 11] = [
        PathClass::GlassFace,
        PathClass::GlassEdge,
        PathClass::ThroughGlass,
        PathClass::Glint,
        PathClass::InternalReflection,
        PathClass::Table,
        PathClass::TapeCover,
        PathClass::Background,
        PathClass::Target,
        PathClass::Other,
        PathClass::GlassReflected,
    ];

    /// Every class a profile point can be labelled with: [`PathClass::ALL`] and
    /// [`PathClass::SensorNoise`].
    pub const LABELS: [PathClass; 12] = [
        PathClass::GlassFace,
        PathClass::GlassEdge,
        PathClass::ThroughGlass,
        PathClass::Glint,
        PathClass::InternalReflection,
        PathClass::Table,
        PathClass::TapeCover,
        PathClass::Background,
        PathClass::Target,
        PathClass::Other,
        PathClass::GlassReflected,
        PathClass::SensorNoise,
    ];

    /// Position of the class's layer in [`PathClass::ALL`]. Panics for
    /// [`PathClass::SensorNoise`], which has no layer (a programming error: only traced light
    /// is splatted).
    pub fn index(self) -> usize {
        PathClass::ALL
            .iter()
            .position(|&c| c == self)
            .expect("only classes of traced light have a layer")
    }

    /// The class named `name` (as [`PathClass::name`] gives it), if any.
    pub fn from_name(name: &str) -> Option<PathClass> {
        PathClass::LABELS.into_iter().find(|c| c.name() == name)
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
            PathClass::Target => "target",
            PathClass::Other => "other",
            PathClass::GlassReflected => "glass_reflected",
            PathClass::SensorNoise => "sensor_noise",
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
        let mut names: Vec<_> = PathClass::LABELS.iter().map(|c| c.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), PathClass::LABELS.len());
        assert_eq!(PathClass::LABELS[..PathClass::ALL.len()], PathClass::ALL);
        for c in PathClass::LABELS {
            assert_eq!(PathClass::from_name(c.name()), Some(c));
        }
    }
}
