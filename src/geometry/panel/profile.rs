//! The edge finishes a panel can have, as the user states them (SI units), with the sourced
//! defaults. `edge` turns each into its cross-section.
//!
//! Terms and sources (read, then stated in our own words):
//! - IGMA Thermal Stress Task Group / PPG Industries, "Edge Condition" sheet
//!   (<https://paperzz.com/doc/6937513/edge-condition>): a seamed edge is a cut edge whose two
//!   corners are ground off at about 45°, each seam (arris) about 0.8 mm (0.030″) wide.
//! - CGC Glass, "Edge Finishes" (<http://www.cgcglass.com/edge-finishes/>): the seamed edge is
//!   automotive edge No. 3; an arrissed edge carries a small bevel at about 45° to the surface,
//!   no wider than 1/16″; a pencil edge is ground to an arc of a circle of chosen radius; bevel
//!   widths are stated as measured on the face.
//! - B. Beranek, AGRR magazine (<https://beranek.agrrmag.com/tag/glass-cutters/>): automotive
//!   edge #4 is flat at 90°; edge #3 ("seamed") is made from #4 by seaming both sharp corners
//!   on a belt sander at 45°; edge #2 is rounded (pencil).
//! - Honda, US 6551673 B1 (<http://patentcut.com/6551673>): flush-glazing edges with a planar
//!   facet at 40–65° to the outer surface and an outer corner radius below t/2, which is why
//!   an arris angle between 30° and 65° is accepted.
//!
//! Section coordinates: an inset d ≥ 0 from the outline (the panel's outer extent) and a height
//! h ∈ [0, t] above the bottom face.

/// Default arris width (m): the IGMA/PPG sheet's seam width, about 0.8 mm (0.030″).
pub const DEFAULT_ARRIS_WIDTH_M: f64 = 0.8e-3;
/// Default arris angle to the face (rad): the IGMA/PPG sheet's and Beranek's 45°.
pub const DEFAULT_ARRIS_ANGLE_RAD: f64 = std::f64::consts::FRAC_PI_4;
/// Smallest arris angle accepted (rad): 30°.
pub const MIN_ARRIS_ANGLE_RAD: f64 = std::f64::consts::FRAC_PI_6;
/// Largest arris angle accepted (rad): 65°, the upper end of Honda US 6551673's facet angles.
pub const MAX_ARRIS_ANGLE_RAD: f64 = 65.0 * std::f64::consts::PI / 180.0;

/// Cross-section of the edge finish.
#[derive(Clone, Debug, PartialEq)]
pub enum EdgeProfile {
    /// Flat ground edge (automotive edge #4): a wall perpendicular to the faces, razor corners.
    FlatGround,
    /// Seamed edge (automotive edge #3, the default): a flat-ground wall whose corners carry
    /// ground arrisses, optionally with every junction rounded.
    Seamed(Seamed),
    /// Arrissed edge: sugar for [`EdgeProfile::Seamed`] with 45° arrisses of width `bevel_m`
    /// top and bottom and no fillet (the same section the earlier arrissed edge had).
    Arrissed {
        /// Width of the 45° bevel on the face (m), 0 < bevel < thickness/2.
        bevel_m: f64,
    },
    /// Pencil edge (automotive edge #2): one circular arc from face to face.
    Pencil {
        /// Arc radius (m), ≥ thickness/2; `None` is thickness/2, the half-round C edge.
        radius_m: Option<f64>,
    },
    /// Any polyline section, each segment a flat facet.
    Section {
        /// Points (inset, height) (m) from the top face boundary (height t) down to the bottom
        /// face boundary (height 0); the rules are in `custom`.
        points_m: Vec<[f64; 2]>,
    },
}

impl Default for EdgeProfile {
    /// The seamed edge with the IGMA/PPG arrisses: what a panel without an `edge` key gets.
    fn default() -> Self {
        EdgeProfile::Seamed(Seamed::default())
    }
}

/// A seamed edge: two arrisses and a vertical wall between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seamed {
    /// The arris at the top face's corner.
    pub top: Arris,
    /// The arris at the bottom face's corner.
    pub bottom: Arris,
    /// Radius (m, ≥ 0) of the circular fillets that round every junction of the section
    /// (face/arris, arris/wall, face/wall where an arris is absent); 0 = sharp junctions.
    pub fillet_radius_m: f64,
}

impl Default for Seamed {
    fn default() -> Self {
        Seamed {
            top: Arris::default(),
            bottom: Arris::default(),
            fillet_radius_m: 0.0,
        }
    }
}

/// One ground arris (seam): a flat facet across a corner of the edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arris {
    /// Extent across the face (m, ≥ 0), the horizontal leg, as bevel widths are specified
    /// (CGC); 0 = no arris (a sharp corner). The vertical leg is width·tan(angle).
    pub width_m: f64,
    /// Angle of the facet to the face plane (rad), in [30°, 65°].
    pub angle_rad: f64,
}

impl Arris {
    /// The vertical leg (m): how far down the wall the arris reaches.
    pub fn vertical_leg_m(&self) -> f64 {
        self.width_m * self.angle_rad.tan()
    }
}

impl Default for Arris {
    fn default() -> Self {
        Arris {
            width_m: DEFAULT_ARRIS_WIDTH_M,
            angle_rad: DEFAULT_ARRIS_ANGLE_RAD,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_igma_seam() {
        let EdgeProfile::Seamed(s) = EdgeProfile::default() else {
            panic!("the default edge is seamed");
        };
        for a in [s.top, s.bottom] {
            assert_eq!(a.width_m, 0.8e-3);
            assert!((a.angle_rad.to_degrees() - 45.0).abs() < 1e-12);
            assert!((a.vertical_leg_m() - 0.8e-3).abs() < 1e-15);
        }
        assert_eq!(s.fillet_radius_m, 0.0);
        assert!((MAX_ARRIS_ANGLE_RAD.to_degrees() - 65.0).abs() < 1e-12);
        assert!((MIN_ARRIS_ANGLE_RAD.to_degrees() - 30.0).abs() < 1e-12);
    }
}
