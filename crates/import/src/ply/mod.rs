//! PLY as a scene: the file is one mesh object `{ type = "mesh", path = "model.ply" }`
//! (read by the scene reader: ASCII and binary, faces fanned into triangles, triangle
//! strips, normals, uv, and the other properties as mesh attributes). A mesh with a
//! colour attribute gets a `diffuse` material whose reflectance is the
//! `mesh_attribute` texture `vertex_color` (or, without it, `face_color`). A PLY
//! file has no camera or light, so it always gets the framing camera and the
//! environment light of [`crate::model`].

use crate::model::{self, Bounds};
use crate::Imported;
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;
use std::path::Path;

/// Imports `path` (`.ply`, or `.ply.gz` compressed with gzip as pbrt-v4's scenes ship
/// their meshes).
pub fn import(path: &Path) -> Result<Imported, SceneError> {
    let bytes = crate::read_bytes(path)?;
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"))
    {
        let mut plain = Vec::new();
        std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&bytes[..]), &mut plain)
            .map_err(|e| {
                SceneError::input("", format!("cannot decompress (gzip): {e}")).with_file(path)
            })?;
        return parse_bytes(&plain, path);
    }
    parse_bytes(&bytes, path)
}

/// Imports PLY bytes as if read from `origin` (the object refers to `origin`).
pub fn parse_bytes(bytes: &[u8], origin: &Path) -> Result<Imported, SceneError> {
    let mesh = irradia_geometry::io::ply::parse_ply(bytes, origin).map_err(model::mesh_error)?;
    if mesh.indices.is_empty() {
        return Err(SceneError::input(
            "",
            "the file has no faces or triangle strips (no `face` or `tristrips` element with a vertex_indices list)",
        )
        .with_file(origin));
    }
    let mut bounds = Bounds::default();
    for p in &mesh.positions {
        bounds.add(*p);
    }
    let dir = origin.parent().unwrap_or(Path::new(""));
    let mut tree = Node::table(0);
    let mut obj = Node::table(0);
    obj.put("type", "mesh", 0)
        .put("path", model::rel_name(origin, dir), 0);
    // A colour attribute (vertex colours first, else face colours) as the reflectance.
    let color = ["vertex_color", "face_color"]
        .into_iter()
        .find(|n| mesh.attributes.get(n).is_some_and(|a| a.channels() == 3));
    if let Some(name) = color {
        let mut attr = Node::table(0);
        attr.put("type", "mesh_attribute", 0).put("name", name, 0);
        let mut m = Node::table(0);
        m.put("type", "diffuse", 0).set("reflectance", attr);
        let mut mats = Node::table(0);
        mats.set("vertex_colors", m);
        tree.set("materials", mats);
        obj.put("material", "vertex_colors", 0);
    }
    tree.push("objects", obj);
    let mut notes = Vec::new();
    model::complete_bare_model(&mut tree, bounds, false, &mut notes);
    Ok(Imported {
        tree,
        text: String::new(),
        origin: origin.to_path_buf(),
        warnings: Vec::new(),
        notes,
    })
}
