//! One dataset manifest line on arbitrary text: a `ManifestLine` or a `DatasetError`, never a
//! panic; a line that parses encodes back to a line that parses to the same value.
#![no_main]

use libfuzzer_sys::fuzz_target;

use glassscan::dataset::manifest::{encode_line, parse_line};

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let path = std::path::Path::new("manifest.jsonl");
        if let Ok(line) = parse_line(path, 1, text) {
            let again = parse_line(path, 1, &encode_line(&line)).expect("an encoded line parses");
            // NaN never reaches a manifest (JSON has none), so equality is exact.
            assert_eq!(again, line);
        }
    }
});
