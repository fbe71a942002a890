//! Mesh files: Wavefront OBJ (by `tobj`, split by `usemtl`), PLY (ASCII, binary little-
//! and big-endian; faces and triangle strips) and the primitives of glTF 2.0 files (by
//! the `gltf` crate) into a [`TriangleMesh`]; scalar volumes (raw and NRRD) in
//! `volume.rs`. Bad files give a [`MeshFileError`] naming the file, the line
//! (text formats) or element (binary PLY), and the field; nothing here panics on
//! malformed input, and sizes claimed by a header are checked against the file
//! before memory is allocated for them.

mod error;
pub mod gltf;
pub mod obj;
pub mod ply;
mod ply_attributes;
pub mod serialized;
pub mod volume;

pub use error::MeshFileError;

use crate::mesh::{MeshAttributes, MeshError, TriangleMesh};
use glam::{Vec2, Vec3};
use std::path::Path;

/// What a file holds, before it is checked and turned into a [`TriangleMesh`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshFile {
    pub positions: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    /// Named per-vertex and per-face values (Mitsuba's mesh attributes): vertex
    /// colours as `vertex_color` (linear RGB), PLY's other properties by Mitsuba's
    /// naming (`io::ply`). Face attributes have one row per triangle of `indices`.
    pub attributes: MeshAttributes,
}

/// Which part of a mesh file to read: everything (the default), one OBJ `usemtl` group,
/// or one primitive of one glTF mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshPart {
    /// OBJ: the faces that use this material (`""`: those before any `usemtl`).
    pub group: Option<String>,
    /// glTF: the mesh's index (required for glTF files).
    pub mesh: Option<usize>,
    /// glTF: the primitive's index in the mesh (default 0).
    pub primitive: Option<usize>,
    /// Mitsuba `.serialized`: the shape's index in the file.
    pub shape_index: usize,
}

impl MeshFile {
    /// Builds the mesh; mesh-level problems (no triangles, ...) are reported against
    /// `path`.
    pub fn into_mesh(self, path: &Path) -> Result<TriangleMesh, MeshFileError> {
        let attributes = self.attributes;
        let mesh = TriangleMesh::new(self.positions, self.indices, self.normals, self.uvs)
            .and_then(|m| m.with_attributes(attributes));
        mesh.map_err(|e| {
            let field = match &e {
                MeshError::IndexOutOfRange { triangle, .. } => Some(format!("triangle {triangle}")),
                MeshError::NonFinitePosition { vertex, .. }
                | MeshError::NonFiniteAttribute { vertex, .. } => Some(format!("vertex {vertex}")),
                _ => None,
            };
            MeshFileError::new(path, None, field, e.to_string())
        })
    }
}

/// Reads an OBJ, PLY or Mitsuba `.serialized` file (chosen by the extension) into a
/// mesh.
pub fn load_mesh(path: &Path) -> Result<TriangleMesh, MeshFileError> {
    read_mesh_file(path, 0)?.into_mesh(path)
}

/// Reads `part` of an OBJ, PLY, `.serialized`, glTF or GLB file (chosen by the
/// extension) into a mesh.
pub fn load_mesh_part(path: &Path, part: &MeshPart) -> Result<TriangleMesh, MeshFileError> {
    read_mesh_part(path, part)?.into_mesh(path)
}

/// Reads a mesh file's contents (chosen by the extension); `shape_index` picks the
/// shape of a `.serialized` file that holds several.
pub fn read_mesh_file(path: &Path, shape_index: usize) -> Result<MeshFile, MeshFileError> {
    read_mesh_part(
        path,
        &MeshPart {
            shape_index,
            ..Default::default()
        },
    )
}

/// [`load_mesh_part`] before the mesh is checked and built.
pub fn read_mesh_part(path: &Path, part: &MeshPart) -> Result<MeshFile, MeshFileError> {
    // A gzip-compressed PLY file (`.ply.gz`, as pbrt-v4's scenes ship them).
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .map(|n| n.to_ascii_lowercase())
        .unwrap_or_default();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let gltf = matches!(ext.as_deref(), Some("gltf" | "glb"));
    let misplaced = |what: &str| {
        MeshFileError::new(
            path,
            None,
            Some(what.to_string()),
            format!("a `{what}` selector needs a glTF file"),
        )
    };
    if !gltf {
        if part.mesh.is_some() {
            return Err(misplaced("mesh"));
        }
        if part.primitive.is_some() {
            return Err(misplaced("primitive"));
        }
    }
    if part.group.is_some() && ext.as_deref() != Some("obj") {
        return Err(MeshFileError::new(
            path,
            None,
            Some("group".into()),
            "a `group` selector needs an OBJ file",
        ));
    }
    if name.ends_with(".ply.gz") {
        let packed = read_file(path)?;
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&packed[..]), &mut bytes)
            .map_err(|e| {
                MeshFileError::new(path, None, None, format!("cannot decompress (gzip): {e}"))
            })?;
        return ply::parse_ply(&bytes, path);
    }
    match ext.as_deref() {
        Some("obj") => obj::read_obj_group(path, part.group.as_deref()),
        Some("ply") => ply::read_ply(path),
        Some("serialized") => serialized::read_serialized(path, part.shape_index),
        Some("gltf" | "glb") => {
            let Some(mesh) = part.mesh else {
                return Err(MeshFileError::new(
                    path,
                    None,
                    Some("mesh".into()),
                    "a glTF file holds several meshes: name one with `mesh = N` (and `primitive = N`)",
                ));
            };
            let file = gltf::GltfFile::open(path)?;
            file.primitive(mesh, part.primitive.unwrap_or(0))
        }
        _ => Err(MeshFileError::new(
            path,
            None,
            None,
            "unknown mesh format: the name must end in .obj or .ply (also .ply.gz), .serialized, .gltf or .glb",
        )),
    }
}

/// Reads a whole file, naming it in the error.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, MeshFileError> {
    std::fs::read(path).map_err(|e| {
        let what = match e.kind() {
            std::io::ErrorKind::NotFound => "no such file".to_string(),
            _ => format!("cannot read the file: {e}"),
        };
        MeshFileError::new(path, None, None, what)
    })
}
