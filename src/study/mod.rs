//! Studies that process engineers run before touching a robot: the paper's scan-angle (edge)
//! experiment and sweeps of scan angle × exposure × threshold × peak selection.
//!
//! Both plan their poses on the true border (nominal = true pose) and measure each profile
//! against the ground-truth edge point p_e: in the edge frame (`edge_frame`, millimetres) and by
//! the BIP error |BIP − p_e| under both BIP rules (`tally`). Tables are built here as text and
//! JSON values; the command line writes them (atomically, through `dataset`). Results depend
//! only on the scene, the settings and the seed, never on the thread count.

pub mod edge_frame;
pub mod grid;
pub mod scan_angle;
pub mod scan_angle_report;
pub mod sweep;
pub mod sweep_report;
pub mod tally;
pub mod wrong_surface;

/// A CSV field of a number: Rust's shortest round-trip form, empty for NaN or a missing value
/// (what spreadsheets and pandas read as missing).
pub fn csv_number(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x}"),
        _ => String::new(),
    }
}
