//! Studies that process engineers run before touching a robot: the paper's scan-angle (edge)
//! experiment and sweeps of scan angle × exposure × threshold × peak selection.
//!
//! Both plan their poses on the true border (nominal = true pose) and measure each profile
//! against the ground-truth edge point p_e: in the edge frame (`edge_frame`, millimetres) and by
//! the BIP error |BIP − p_e| under both BIP rules (`tally`). Tables are built here as text and
//! JSON values; the command line writes them (atomically, through `dataset`). Results depend
//! only on the scene, the settings and the seed, never on the thread count.

pub mod convergence;
pub mod edge_frame;
pub mod finding_map;
pub mod finding_map_report;
pub mod grid;
pub mod scan_angle;
pub mod scan_angle_report;
pub mod side_by_side;
pub mod sweep;
pub mod sweep_report;
pub mod tally;
pub mod wrong_surface;

/// A report object with the run's description (`run`, an object: scene, seed, files, …) merged
/// into it; a key of `run` replaces the report's key of the same name.
pub fn with_run(mut report: serde_json::Value, run: serde_json::Value) -> serde_json::Value {
    if let (serde_json::Value::Object(o), serde_json::Value::Object(r)) = (&mut report, run) {
        o.extend(r);
    }
    report
}

/// A setting converted back to the unit it was typed in (degrees from radians, milliseconds
/// from seconds), rounded to 1e-9 of that unit, so that 15° comes back as 15 and not as
/// 14.999999999999998 in tables, file names and plots. The simulation uses the unrounded value.
pub fn as_typed(v: f64) -> f64 {
    (v * 1e9).round() / 1e9
}

/// A CSV field of a number: Rust's shortest round-trip form, empty for NaN or a missing value
/// (what spreadsheets and pandas read as missing).
pub fn csv_number(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x}"),
        _ => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_come_back_as_typed() {
        assert_eq!(15f64.to_radians().to_degrees(), 14.999999999999998);
        assert_eq!(as_typed(15f64.to_radians().to_degrees()), 15.0);
        assert_eq!(as_typed(0.3e-3 * 1e3), 0.3);
        assert_eq!(as_typed(42.5), 42.5);
        assert_eq!(csv_number(Some(f64::NAN)), "");
        assert_eq!(csv_number(None), "");
    }
}
