//! PLY bytes: import must never panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let origin = std::path::Path::new("/nonexistent/fuzz.ply");
    let _ = irradia_import::ply::parse_bytes(data, origin);
});
