//! The x_mm,y_mm,z_mm points reader (register, score) on arbitrary text: points or a
//! `DatasetError`, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let path = std::path::Path::new("points.csv");
        let _ = glassscan::io::points_csv::parse_points_csv(path, text);
    }
});
