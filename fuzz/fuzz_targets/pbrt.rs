//! The pbrt-v4 importer on arbitrary text: it must return a tree or an error, never
//! panic (`cargo +nightly fuzz run pbrt fuzz/corpus/pbrt`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let origin = Path::new("fuzz.pbrt");
        if let Ok(imported) = irradia_import::pbrt::parse_str(text, origin) {
            // The tree must also survive the schema reader without panicking.
            let _ = imported.scene();
        }
        let _ = irradia_import::pbrt::coverage_str(text, origin);
    }
});
