//! glTF JSON or GLB bytes: import (and reading every primitive) must never panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let origin = std::path::Path::new("/nonexistent/fuzz.glb");
    let _ = irradia_import::gltf::parse_bytes(data, origin);
    if let Ok(file) = irradia_geometry_gltf(data, origin) {
        for m in 0..file.document.meshes().len().min(4) {
            for p in 0..4 {
                let _ = file.primitive(m, p);
            }
        }
        for i in 0..file.document.images().len().min(4) {
            let _ = file.embedded_image(i);
        }
    }
});

fn irradia_geometry_gltf(
    data: &[u8],
    origin: &std::path::Path,
) -> Result<irradia_import::gltf::GltfFile, irradia_import::gltf::MeshFileError> {
    irradia_import::gltf::GltfFile::from_bytes(data, origin)
}
