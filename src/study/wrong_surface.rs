//! Which profile points come from the wrong surface: the rule behind the sweep's
//! `wrong_surface_fraction`.
//!
//! A laser-line sensor triangulates a peak as if the light had come straight from a diffuse
//! point in the laser plane. That is true for a surface seen directly (the ground glass edge, a
//! face imperfection on the top face, the table, tape, cover, background). It is false when the
//! light was refracted or mirrored between the scattering point and the camera, or between the
//! laser and it: the point then appears somewhere no surface is. From the per-point path label
//! (`sensor::path_class`), a point is from the wrong surface when its class is
//!
//! - `through_glass`: an opaque surface seen through the pane (the refracted, raised table of
//!   the paper's Fig. 5);
//! - `glint`: a purely specular chain into the aperture;
//! - `internal_reflection`: a face scatterer reached after a reflection inside the glass;
//! - `glass_reflected`: an opaque surface lit by light a glass surface reflected onto it, off
//!   the laser plane (the mirror image of the line in a pane);
//! - `sensor_noise`: a peak with no traced light at all.
//!
//! `glass_face` counts as right even though it also holds the bottom face's imperfections seen
//! through the top face (the label does not separate them); their return is the faint 0.2 %
//! that rarely passes the threshold. Invalid points are not counted; a valid point without a
//! label (no per-class images) counts as right, since nothing says it is wrong.

use crate::sensor::path_class::PathClass;
use crate::sensor::profile::Profile;

/// Whether a point labelled `label` appears where no surface scattered its light.
pub fn is_wrong_surface(label: Option<PathClass>) -> bool {
    matches!(
        label,
        Some(
            PathClass::ThroughGlass
                | PathClass::Glint
                | PathClass::InternalReflection
                | PathClass::GlassReflected
                | PathClass::SensorNoise
        )
    )
}

/// (valid points, valid points from the wrong surface) of a profile.
pub fn count_wrong_surface(profile: &Profile) -> (usize, usize) {
    profile
        .points
        .iter()
        .filter(|q| q.valid)
        .fold((0, 0), |(n, w), q| {
            (n + 1, w + is_wrong_surface(q.label) as usize)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refracted_and_mirrored_paths_are_wrong_and_direct_ones_right() {
        let wrong: Vec<&str> = PathClass::LABELS
            .iter()
            .filter(|c| is_wrong_surface(Some(**c)))
            .map(|c| c.name())
            .collect();
        assert_eq!(
            wrong,
            [
                "through_glass",
                "glint",
                "internal_reflection",
                "glass_reflected",
                "sensor_noise"
            ]
        );
        assert!(!is_wrong_surface(None));
    }
}
