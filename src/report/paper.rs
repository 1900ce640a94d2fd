//! The paper's numbers that a report sets beside the run's, each with the place it is quoted
//! from: Adrian & Pham, "Locating Transparent Objects to Millimetre Accuracy". Tables are named
//! by their caption, as the printed numbering and the source's labels differ.

/// A result quoted from the paper: mean (± std), max, and where it stands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quoted {
    /// What was measured, as the paper names it.
    pub what: &'static str,
    /// Mean.
    pub mean: f64,
    /// Standard deviation, where given.
    pub std: Option<f64>,
    /// Maximum, where given.
    pub max: Option<f64>,
    /// Unit of the three values.
    pub unit: &'static str,
    /// Section and table of the paper.
    pub source: &'static str,
}

impl Quoted {
    /// `mean ± std (max M) unit`.
    pub fn text(&self) -> String {
        let mut t = format!("{}", self.mean);
        if let Some(s) = self.std {
            t += &format!(" ± {s}");
        }
        if let Some(m) = self.max {
            t += &format!(" (max {m})");
        }
        format!("{t} {}", self.unit)
    }
}

/// Point localisation on the glass edge: |tooltip at BIP − marked point| over n locations.
pub const POINT_GLASS: Quoted = Quoted {
    what: "point localisation error, glass",
    mean: 0.94,
    std: Some(0.28),
    max: Some(1.35),
    unit: "mm",
    source: "Section V-B (Experiment 1: point localisation), table \"Point localisation error\", column Glass",
};

/// Point localisation on an opaque object's edge.
pub const POINT_OPAQUE: Quoted = Quoted {
    what: "point localisation error, opaque object",
    mean: 1.01,
    std: Some(0.14),
    max: Some(1.27),
    unit: "mm",
    source: "Section V-B (Experiment 1: point localisation), table \"Point localisation error\", column Opaque object",
};

/// The full pipeline (BIPs → ICP → touching the border), n = 12.
pub const FULL_PIPELINE: Quoted = Quoted {
    what: "full pipeline localisation error (n = 12)",
    mean: 0.88,
    std: Some(0.39),
    max: Some(1.65),
    unit: "mm",
    source:
        "Section VI-B (Experiment 2: full pipeline), table \"Full pipeline localisation error\"",
};

/// Average time of the scanning stage (robot motion included), n = 4.
pub const TIME_SCANNING: Quoted = Quoted {
    what: "scanning time (n = 4, robot motion)",
    mean: 14.845,
    std: None,
    max: None,
    unit: "s",
    source: "Section VI-B, table \"Average operation time\", row Scanning",
};

/// Average time of pose estimation (ICP), n = 4.
pub const TIME_POSE_ESTIMATION: Quoted = Quoted {
    what: "pose estimation time (n = 4)",
    mean: 0.023,
    std: None,
    max: None,
    unit: "s",
    source: "Section VI-B, table \"Average operation time\", row Pose estimation",
};

/// What the paper reports of one scan angle of its edge experiment: a finding in words (it
/// gives no error in millimetres for these angles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngleFinding {
    /// Scan angle above the surface (degrees).
    pub angle_deg: f64,
    /// The paper's statement.
    pub finding: &'static str,
    /// Where it is stated.
    pub source: &'static str,
}

/// The edge experiment's angles: 10° and 40° (Fig. 7), and the pipeline's 45°.
pub const ANGLE_FINDINGS: [AngleFinding; 3] = [
    AngleFinding {
        angle_deg: 10.0,
        finding: "laser readings further away from the border boundary (p_e)",
        source: "Section III-C, Fig. 7(a)",
    },
    AngleFinding {
        angle_deg: 40.0,
        finding: "laser points in closer proximity to the edge line than at 10°",
        source: "Section III-C, Fig. 7(b)",
    },
    AngleFinding {
        angle_deg: 45.0,
        finding: "the pipeline's scan angle: border points sampled looking at the surface from approximately 45°",
        source: "Section IV-A (and the abstract)",
    },
];

/// The paper's finding for `angle_deg`, if it reports one.
pub fn angle_finding(angle_deg: f64) -> Option<&'static AngleFinding> {
    ANGLE_FINDINGS
        .iter()
        .find(|f| (f.angle_deg - angle_deg).abs() < 1e-6)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_numbers_read_as_in_the_paper() {
        assert_eq!(POINT_GLASS.text(), "0.94 ± 0.28 (max 1.35) mm");
        assert_eq!(POINT_OPAQUE.text(), "1.01 ± 0.14 (max 1.27) mm");
        assert_eq!(FULL_PIPELINE.text(), "0.88 ± 0.39 (max 1.65) mm");
        assert_eq!(TIME_SCANNING.text(), "14.845 s");
        assert_eq!(
            angle_finding(40.0).unwrap().source,
            "Section III-C, Fig. 7(b)"
        );
        assert!(angle_finding(30.0).is_none());
    }
}
