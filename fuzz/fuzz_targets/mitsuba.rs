//! The Mitsuba 3 XML importer on arbitrary text: it must return a scene or an error,
//! never panic. Its in-memory entry point reads no file (includes are refused).
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let opts = irradia_import::Options::default();
        if let Ok(imported) = irradia_import::mitsuba::parse_str(text, Path::new("fuzz.xml"), &opts) {
            let _ = imported.scene();
        }
    }
});
