//! The profile CSV reader on arbitrary text: a profile or a `DatasetError`, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let path = std::path::Path::new("profile.csv");
        let _ = glassscan::io::profile_csv::parse_profile_csv(path, text);
    }
});
