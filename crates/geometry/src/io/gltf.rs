//! glTF 2.0 (`.gltf` with external or data-URI buffers, and binary `.glb`), read by
//! the `gltf` crate: one primitive of one mesh as a [`MeshFile`] (positions; indices,
//! normals, `TEXCOORD_0` and `COLOR_0` when present; triangle lists, strips and fans),
//! and the encoded bytes of an embedded image. Every accessor read is checked against
//! its buffer first, so a file whose accessors point past their data is an error that
//! names the mesh, primitive and accessor, not a panic.

use super::{read_file, MeshFile, MeshFileError};
use crate::mesh::{MeshAttribute, MeshAttributes};
use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};

/// A glTF document with its buffers loaded.
pub struct GltfFile {
    pub path: PathBuf,
    pub document: gltf::Document,
    pub buffers: Vec<gltf::buffer::Data>,
}

impl std::fmt::Debug for GltfFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "GltfFile({})", self.path.display())
    }
}

impl GltfFile {
    /// Reads `path` (`.gltf` or `.glb`) and the buffers it references.
    pub fn open(path: &Path) -> Result<GltfFile, MeshFileError> {
        let bytes = read_file(path)?;
        Self::from_bytes(&bytes, path)
    }

    /// Parses a glTF or GLB held in memory; external buffers are resolved relative
    /// to `path`'s folder.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<GltfFile, MeshFileError> {
        let err = |msg: String| MeshFileError::new(path, None, None, msg);
        check_glb_container(bytes).map_err(err)?;
        let gltf = gltf::Gltf::from_slice_without_validation(bytes)
            .map_err(|e| err(format!("not a valid glTF file: {e}")))?;
        let gltf::Gltf { document, blob } = gltf;
        let root = document.into_json();
        // gltf-json 1.4.1's validation indexes a primitive's POSITION accessor before
        // checking that it exists (a panic on such a file): checked here first.
        for (m, mesh) in root.meshes.iter().enumerate() {
            for (p, prim) in mesh.primitives.iter().enumerate() {
                for (sem, a) in &prim.attributes {
                    if a.value() >= root.accessors.len() {
                        return Err(MeshFileError::new(
                            path,
                            None,
                            Some(format!("mesh {m}, primitive {p}: {sem:?}")),
                            format!(
                                "accessor {} does not exist (the file has {})",
                                a.value(),
                                root.accessors.len()
                            ),
                        ));
                    }
                }
            }
        }
        let document = gltf::Document::from_json(root)
            .map_err(|e| err(format!("not a valid glTF file: {e}")))?;
        // gltf 1.4.1 unwraps the percent-decoding of a relative buffer URI as UTF-8 (a
        // panic on `%AA`, found by fuzzing): such a URI is refused here first.
        for b in document.buffers() {
            if let gltf::buffer::Source::Uri(uri) = b.source() {
                if !uri.contains(':') && String::from_utf8(percent_decode_bytes(uri)).is_err() {
                    return Err(MeshFileError::new(
                        path,
                        None,
                        Some(format!("buffers[{}].uri", b.index())),
                        "its percent-encoded bytes are not UTF-8 text",
                    ));
                }
            }
        }
        let base = path.parent().unwrap_or(Path::new("."));
        let buffers = gltf::import_buffers(&document, Some(base), blob)
            .map_err(|e| err(format!("cannot load a buffer: {e}")))?;
        Ok(GltfFile {
            path: path.to_path_buf(),
            document,
            buffers,
        })
    }

    fn err(&self, field: String, msg: impl Into<String>) -> MeshFileError {
        MeshFileError::new(&self.path, None, Some(field), msg)
    }

    /// Checks that every element of `a` lies inside its buffer view and the view inside
    /// its buffer (the `gltf` crate's readers assume so).
    pub fn check_accessor(&self, a: &gltf::Accessor, field: &str) -> Result<(), MeshFileError> {
        let name = || format!("{field} (accessor {})", a.index());
        if a.sparse().is_some() {
            return Err(self.err(name(), "sparse accessors are not read"));
        }
        let Some(view) = a.view() else {
            return Err(self.err(name(), "the accessor has no buffer view"));
        };
        let buffer = self
            .buffers
            .get(view.buffer().index())
            .ok_or_else(|| self.err(name(), "the buffer view's buffer is missing"))?;
        let view_end = view.offset().checked_add(view.length());
        if !matches!(view_end, Some(e) if e <= buffer.len()) {
            return Err(self.err(
                name(),
                format!(
                    "buffer view {} ends past its buffer ({} bytes)",
                    view.index(),
                    buffer.len()
                ),
            ));
        }
        let elem = a.size();
        let stride = view.stride().unwrap_or(elem);
        if stride < elem && a.count() > 1 {
            return Err(self.err(
                name(),
                format!("stride {stride} is shorter than an element ({elem} bytes)"),
            ));
        }
        if a.count() == 0 {
            // gltf 1.4.1 computes `count - 1` when it reads one (a panic found by
            // fuzzing); the glTF specification requires at least one element.
            return Err(self.err(name(), "the accessor has no elements (count 0)"));
        }
        {
            let need = (a.count() - 1)
                .checked_mul(stride)
                .and_then(|x| x.checked_add(elem))
                .and_then(|x| x.checked_add(a.offset()));
            if !matches!(need, Some(n) if n <= view.length()) {
                return Err(self.err(
                    name(),
                    format!(
                        "{} elements do not fit in buffer view {} ({} bytes)",
                        a.count(),
                        view.index(),
                        view.length()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Checks the accessors of primitive `p` that are read (bounds, as
    /// [`GltfFile::check_accessor`], and the component type and dimensions the format
    /// allows for each: the `gltf` crate's readers assume both).
    pub fn check_primitive(&self, p: &gltf::Primitive, here: &str) -> Result<(), MeshFileError> {
        use gltf::accessor::{DataType as T, Dimensions as D};
        use gltf::Semantic as S;
        let check = |a: &gltf::Accessor, what: &str, types: &[T], dims: &[D]| {
            let field = format!("{here}: {what}");
            self.check_accessor(a, &field)?;
            if !types.contains(&a.data_type()) || !dims.contains(&a.dimensions()) {
                return Err(self.err(
                    format!("{field} (accessor {})", a.index()),
                    format!(
                        "{:?} {:?} is not a type this attribute may have",
                        a.data_type(),
                        a.dimensions()
                    ),
                ));
            }
            Ok(())
        };
        for (sem, a) in p.attributes() {
            let name = sem.to_string();
            match sem {
                S::Positions | S::Normals => check(&a, &name, &[T::F32], &[D::Vec3])?,
                S::TexCoords(0) => check(&a, &name, &[T::F32, T::U8, T::U16], &[D::Vec2])?,
                S::Colors(0) => check(&a, &name, &[T::F32, T::U8, T::U16], &[D::Vec3, D::Vec4])?,
                _ => {}
            }
        }
        if let Some(a) = p.indices() {
            check(&a, "indices", &[T::U8, T::U16, T::U32], &[D::Scalar])?;
        }
        Ok(())
    }

    /// Primitive `primitive` of mesh `mesh`.
    pub fn primitive(&self, mesh: usize, primitive: usize) -> Result<MeshFile, MeshFileError> {
        let meshes = self.document.meshes().len();
        let m = self.document.meshes().nth(mesh).ok_or_else(|| {
            self.err(
                "mesh".into(),
                format!("mesh {mesh} does not exist (the file has {meshes})"),
            )
        })?;
        let count = m.primitives().len();
        let p = m.primitives().nth(primitive).ok_or_else(|| {
            self.err(
                "primitive".into(),
                format!("mesh {mesh} has no primitive {primitive} (it has {count})"),
            )
        })?;
        let here = format!("mesh {mesh}, primitive {primitive}");
        use gltf::mesh::Mode;
        let mode = p.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return Err(self.err(
                here,
                format!("{mode:?} primitives are not surfaces (only triangles are read)"),
            ));
        }
        self.check_primitive(&p, &here)?;
        let reader = p.reader(|b| self.buffers.get(b.index()).map(|d| &d.0[..]));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| self.err(here.clone(), "the primitive has no POSITION attribute"))?
            .map(Vec3::from)
            .collect();
        let n = positions.len();
        let list: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..n as u32).collect(),
        };
        let indices: Vec<[u32; 3]> = match mode {
            Mode::Triangles => list.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
            Mode::TriangleStrip => list
                .windows(3)
                .enumerate()
                .map(|(k, w)| {
                    if k % 2 == 0 {
                        [w[0], w[1], w[2]]
                    } else {
                        [w[1], w[0], w[2]]
                    }
                })
                .collect(),
            _ => (1..list.len().saturating_sub(1))
                .map(|k| [list[0], list[k], list[k + 1]])
                .collect(),
        };
        if let Some(bad) = indices.iter().flatten().find(|&&i| i as usize >= n) {
            return Err(self.err(
                format!("{here}: indices"),
                format!("index {bad} is out of range ({n} vertices)"),
            ));
        }
        let same = |len: usize, what: &str| {
            if len == n {
                Ok(())
            } else {
                Err(self.err(
                    format!("{here}: {what}"),
                    format!("{len} values for {n} vertices"),
                ))
            }
        };
        let normals = match reader.read_normals() {
            Some(it) => {
                let v: Vec<Vec3> = it.map(Vec3::from).collect();
                same(v.len(), "NORMAL")?;
                Some(v)
            }
            None => None,
        };
        let uvs = match reader.read_tex_coords(0) {
            Some(it) => {
                let v: Vec<Vec2> = it.into_f32().map(Vec2::from).collect();
                same(v.len(), "TEXCOORD_0")?;
                Some(v)
            }
            None => None,
        };
        let mut attributes = MeshAttributes::default();
        if let Some(it) = reader.read_colors(0) {
            // COLOR_0 (linear RGB; alpha dropped) as the `vertex_color` attribute.
            let v: Vec<f32> = it.into_rgb_f32().flatten().collect();
            same(v.len() / 3, "COLOR_0")?;
            let c = MeshAttribute::new("vertex_color", 3, v)
                .map_err(|e| self.err(format!("{here}: COLOR_0"), e.to_string()))?;
            let _ = attributes.insert(c);
        }
        Ok(MeshFile {
            positions,
            indices,
            normals,
            uvs,
            attributes,
        })
    }

    /// The encoded bytes (PNG or JPEG) of image `index` when the file holds them (a
    /// buffer view or a `data:` URI); `Ok(None)` for an image in a file of its own
    /// (its URI, relative to the glTF file, is [`GltfFile::image_uri`]).
    pub fn embedded_image(&self, index: usize) -> Result<Option<Vec<u8>>, MeshFileError> {
        let count = self.document.images().len();
        let field = format!("image {index}");
        let img = self.document.images().nth(index).ok_or_else(|| {
            self.err(
                field.clone(),
                format!("image {index} does not exist (the file has {count})"),
            )
        })?;
        if !self.source_readable(index) {
            return Err(self.err(
                field,
                "an image needs a uri, or a bufferView with a mimeType",
            ));
        }
        match img.source() {
            gltf::image::Source::View { view, .. } => {
                let buffer = self
                    .buffers
                    .get(view.buffer().index())
                    .ok_or_else(|| self.err(field.clone(), "its buffer is missing"))?;
                let end = view.offset().checked_add(view.length());
                match end {
                    Some(end) if end <= buffer.len() => {
                        Ok(Some(buffer.0[view.offset()..end].to_vec()))
                    }
                    _ => Err(self.err(field, "its buffer view ends past the buffer")),
                }
            }
            gltf::image::Source::Uri { uri, .. } => match uri.strip_prefix("data:") {
                Some(rest) => {
                    let Some((_, data)) = rest.split_once(";base64,") else {
                        return Err(self.err(field, "a data URI must be base64-encoded"));
                    };
                    base64_decode(data)
                        .map(Some)
                        .ok_or_else(|| self.err(field, "the data URI is not valid base64"))
                }
                None => Ok(None),
            },
        }
    }

    /// Whether image `index` has what the `gltf` crate's `Image::source` unwraps.
    fn source_readable(&self, index: usize) -> bool {
        match self.document.as_json().images.get(index) {
            Some(i) if i.buffer_view.is_some() => i.mime_type.is_some(),
            Some(i) => i.uri.is_some(),
            None => false,
        }
    }

    /// The URI of image `index` when it is a file of its own (percent-decoded).
    pub fn image_uri(&self, index: usize) -> Option<String> {
        if !self.source_readable(index) {
            return None;
        }
        match self.document.images().nth(index)?.source() {
            gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => {
                Some(percent_decode(uri))
            }
            _ => None,
        }
    }
}

/// `%20` and friends in a URI.
fn percent_decode(s: &str) -> String {
    String::from_utf8_lossy(&percent_decode_bytes(s)).into_owned()
}

/// The bytes `%XX` escapes in `s` stand for (a `%` not followed by two hex digits is
/// kept as it is).
fn percent_decode_bytes(s: &str) -> Vec<u8> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            let hex = std::str::from_utf8(&b[i + 1..i + 3]).unwrap_or("");
            if let Ok(x) = u8::from_str_radix(hex, 16) {
                out.push(x);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    out
}

/// Standard base64 (padding optional, whitespace ignored).
pub fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        } as u32;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// The GLB container's lengths checked before the `gltf` crate reads them: gltf 1.4.1
/// subtracts a chunk's length from what is left without checking it (an overflow
/// panic on a truncated or forged file, found by fuzzing). A file that does not start
/// with `glTF` is left to the crate (JSON glTF).
fn check_glb_container(bytes: &[u8]) -> Result<(), String> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let word = |at: usize| -> Option<u64> {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64)
    };
    let total = word(8).ok_or("a GLB file shorter than its 12-byte header")?;
    if total != bytes.len() as u64 {
        return Err(format!(
            "the GLB header gives {total} bytes, the file has {}",
            bytes.len()
        ));
    }
    let mut at = 12u64;
    let mut chunks = 0;
    while at < total {
        let len = word(at as usize).ok_or("a GLB chunk header is cut off")?;
        word(at as usize + 4).ok_or("a GLB chunk header is cut off")?;
        let end = at + 8 + len;
        if end > total {
            return Err(format!(
                "GLB chunk {chunks} of {len} bytes runs past the end of the file"
            ));
        }
        at = end;
        chunks += 1;
    }
    if chunks == 0 {
        return Err("a GLB file without its JSON chunk".into());
    }
    Ok(())
}
