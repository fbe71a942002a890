//! OBJ text (no MTL file is found beside the made-up origin): import must never panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let origin = std::path::Path::new("/nonexistent/fuzz.obj");
        let _ = irradia_import::obj::parse_str(text, origin);
    }
});
