//! PLY (Turk, "The PLY Polygon File Format", 1994): ASCII, binary little-endian and
//! binary big-endian. Reads `vertex` (x, y, z; optional nx, ny, nz and u, v / s, t /
//! texture_u, texture_v), `face` (a list property `vertex_indices` or `vertex_index`;
//! polygons are fanned into triangles) and `tristrips` (the Stanford scans' triangle
//! strips, e.g. igea.ply: one list `vertex_indices` per element, -1 ending a strip;
//! the winding alternates along a strip, and triangles that repeat a vertex are the
//! strip's joins and dropped); other elements are skipped.
//! Counts in the header are checked against the bytes that are really there.
//!
//! The other scalar properties of `vertex` and `face` become mesh attributes
//! ([`crate::mesh::attributes`]) named as Mitsuba 3's `ply` plugin names them (its
//! documentation, "PLY (Stanford Triangle Format) mesh loader"):
//! - `r, g, b` or `red, green, blue` (also `diffuse_red, ...`), with no prefix, are the
//!   colour `vertex_color` / `face_color` (an alpha channel is dropped);
//! - consecutive properties `{prefix}_{x|y|z|w}`, `{prefix}_{r|g|b|a}`,
//!   `{prefix}_{0|1|2|3}` or `{prefix}_{1|2|3|4}` form one attribute
//!   `vertex_{prefix}` / `face_{prefix}` (`..._{prefix}_color` for the `r|g|b` series)
//!   when they are 1 or 3 of them: `color_0, color_1, color_2` is `vertex_color`,
//!   `weight_0` alone `face_weight`;
//! - anything else (no `_` suffix of one character, a series of 2 or 4, a prefix seen
//!   before) is skipped.
//!
//! Integer properties are read as Mitsuba reads them: divided by their type's maximum
//! and decoded from sRGB to linear (8-bit colours as viewers show them); floats as they
//! are (linear). A face attribute's row is repeated for each triangle the face is
//! fanned into (and is zero for triangles of `tristrips`).

use super::ply_attributes::{attribute, attribute_groups, eligible};
use super::{read_file, MeshFile, MeshFileError};
use crate::mesh::MeshAttribute;
use glam::{Vec2, Vec3};
use std::path::Path;

/// Vertex properties that are not attributes: position, normal, uv (all its names).
const VERTEX_RESERVED: &[&str] = &[
    "x",
    "y",
    "z",
    "nx",
    "ny",
    "nz",
    "u",
    "v",
    "s",
    "t",
    "texture_u",
    "texture_v",
    "texture_s",
    "texture_t",
];

#[derive(Clone, Copy, Debug, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
    /// A value as an attribute channel: integers divided by their type's maximum and
    /// decoded from sRGB (Mitsuba reads integer PLY properties so), floats unchanged.
    fn attribute_value(self, x: f64) -> f32 {
        let max = match self {
            Scalar::I8 => i8::MAX as f64,
            Scalar::U8 => u8::MAX as f64,
            Scalar::I16 => i16::MAX as f64,
            Scalar::U16 => u16::MAX as f64,
            Scalar::I32 => i32::MAX as f64,
            Scalar::U32 => u32::MAX as f64,
            Scalar::F32 | Scalar::F64 => return x as f32,
        };
        irradia_core::color::srgb_to_linear((x / max) as f32)
    }
}

#[derive(Clone, Debug)]
pub(super) struct Property {
    pub(super) name: String,
    /// `Some(count type)` for list properties.
    pub(super) list: Option<Scalar>,
    pub(super) ty: Scalar,
}

#[derive(Clone, Debug)]
pub(super) struct Element {
    pub(super) name: String,
    count: usize,
    pub(super) props: Vec<Property>,
    /// Header line that declared it.
    pub(super) line: usize,
}

impl Element {
    /// The fewest bytes one instance can take in a binary file.
    fn min_size(&self) -> usize {
        self.props
            .iter()
            .map(|p| p.list.map_or(p.ty.size(), |c| c.size()))
            .sum()
    }
}

pub fn read_ply(path: &Path) -> Result<MeshFile, MeshFileError> {
    let bytes = read_file(path)?;
    parse_ply(&bytes, path)
}

/// Parses a PLY file held in memory; `path` only names the file in errors.
pub fn parse_ply(bytes: &[u8], path: &Path) -> Result<MeshFile, MeshFileError> {
    let (format, elements, body_start, header_lines) = parse_header(bytes, path)?;
    let mut reader = Reader {
        path,
        format,
        bytes,
        pos: body_start,
        line: header_lines,
        tokens: Vec::new(),
        token_pos: 0,
    };
    let mut out = MeshFile::default();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let mut vertex_count = None;
    let mut face_attributes: Vec<MeshAttribute> = Vec::new();
    for el in &elements {
        // Refuse counts the file cannot hold before allocating anything for them.
        if format != Encoding::Ascii {
            let remaining = bytes.len() - reader.pos;
            if el.count.saturating_mul(el.min_size()) > remaining {
                return Err(MeshFileError::new(
                    path,
                    Some(el.line),
                    Some(format!("element {}", el.name)),
                    format!(
                        "the header declares {} {} elements ({} bytes at least) but only {} bytes follow",
                        el.count,
                        el.name,
                        el.count.saturating_mul(el.min_size()),
                        remaining
                    ),
                ));
            }
        }
        let find = |names: &[&str]| {
            el.props
                .iter()
                .position(|p| names.contains(&p.name.as_str()) && p.list.is_none())
        };
        let capacity = el.count.min(bytes.len());
        match el.name.as_str() {
            "vertex" => {
                let xyz = [find(&["x"]), find(&["y"]), find(&["z"])];
                if xyz.iter().any(|p| p.is_none()) {
                    return Err(MeshFileError::new(
                        path,
                        Some(el.line),
                        Some("element vertex".into()),
                        "vertices need scalar properties x, y and z",
                    ));
                }
                let nxyz = [find(&["nx"]), find(&["ny"]), find(&["nz"])];
                let has_n = nxyz.iter().all(|p| p.is_some());
                let uv = [
                    find(&["u", "s", "texture_u", "texture_s"]),
                    find(&["v", "t", "texture_v", "texture_t"]),
                ];
                let has_uv = uv.iter().all(|p| p.is_some());
                let groups = attribute_groups("vertex", &eligible(el, VERTEX_RESERVED));
                let mut attr_values: Vec<Vec<f32>> = vec![Vec::new(); groups.len()];
                out.positions.reserve(capacity);
                let mut vals = vec![0f64; el.props.len()];
                for i in 0..el.count {
                    reader.start_instance(el, i)?;
                    for (k, p) in el.props.iter().enumerate() {
                        if p.list.is_some() {
                            reader.skip_list(el, i, p)?;
                        } else {
                            vals[k] = reader.scalar(el, i, p, p.ty)?;
                        }
                    }
                    reader.end_instance(el, i)?;
                    let get = |k: Option<usize>| vals[k.unwrap()] as f32;
                    let p = Vec3::new(get(xyz[0]), get(xyz[1]), get(xyz[2]));
                    if !p.is_finite() {
                        return Err(reader.error(
                            el,
                            i,
                            "x, y, z",
                            format!("position {p} is not finite"),
                        ));
                    }
                    out.positions.push(p);
                    if has_n {
                        normals.push(Vec3::new(get(nxyz[0]), get(nxyz[1]), get(nxyz[2])));
                    }
                    if has_uv {
                        uvs.push(Vec2::new(get(uv[0]), get(uv[1])));
                    }
                    for (g, values) in groups.iter().zip(&mut attr_values) {
                        values.extend(
                            g.props
                                .iter()
                                .map(|&k| el.props[k].ty.attribute_value(vals[k])),
                        );
                    }
                }
                for (g, values) in groups.into_iter().zip(attr_values) {
                    let a = attribute(path, el, &g, values)?;
                    // A second element called `vertex` does not replace the first's.
                    let _ = out.attributes.insert(a);
                }
                if has_n {
                    out.normals = Some(std::mem::take(&mut normals));
                }
                if has_uv {
                    out.uvs = Some(std::mem::take(&mut uvs));
                }
                vertex_count = Some(el.count);
            }
            "face" | "tristrips" => {
                let strips = el.name == "tristrips";
                let Some(list) = el.props.iter().position(|p| {
                    (p.name == "vertex_indices" || p.name == "vertex_index") && p.list.is_some()
                }) else {
                    return Err(MeshFileError::new(
                        path,
                        Some(el.line),
                        Some(format!("element {}", el.name)),
                        format!("{} need a list property vertex_indices", el.name),
                    ));
                };
                let nv = vertex_count.unwrap_or(0);
                out.indices.reserve(capacity);
                let mut corners: Vec<u32> = Vec::new();
                // Face attributes (not of triangle strips), a row per triangle.
                let groups = if strips {
                    Vec::new()
                } else {
                    attribute_groups("face", &eligible(el, &[]))
                };
                let first_triangle = out.indices.len();
                let mut attr_values: Vec<Vec<f32>> = groups
                    .iter()
                    .map(|g| vec![0.0; first_triangle * g.props.len()])
                    .collect();
                let mut vals = vec![0f64; el.props.len()];
                for i in 0..el.count {
                    reader.start_instance(el, i)?;
                    let before = out.indices.len();
                    for (k, p) in el.props.iter().enumerate() {
                        if k != list {
                            match p.list {
                                Some(_) => reader.skip_list(el, i, p)?,
                                None => vals[k] = reader.scalar(el, i, p, p.ty)?,
                            }
                            continue;
                        }
                        let n = reader.list_len(el, i, p)?;
                        corners.clear();
                        for c in 0..n {
                            let x = reader.scalar(el, i, p, p.ty)?;
                            if strips && x == -1.0 && p.ty.is_integer() {
                                strip_triangles(&corners, &mut out.indices);
                                corners.clear();
                                continue;
                            }
                            if !p.ty.is_integer() || x < 0.0 || x >= nv as f64 || x.fract() != 0.0 {
                                return Err(reader.error(
                                    el,
                                    i,
                                    &format!("{} [{c}]", p.name),
                                    format!("vertex index {x} is out of range (the file has {nv} vertices)"),
                                ));
                            }
                            corners.push(x as u32);
                        }
                        if strips {
                            strip_triangles(&corners, &mut out.indices);
                            continue;
                        }
                        if n < 3 {
                            return Err(reader.error(
                                el,
                                i,
                                &p.name,
                                format!("a face needs at least 3 vertices, found {n}"),
                            ));
                        }
                        for c in 1..n - 1 {
                            out.indices.push([corners[0], corners[c], corners[c + 1]]);
                        }
                    }
                    reader.end_instance(el, i)?;
                    for (g, values) in groups.iter().zip(&mut attr_values) {
                        for _ in before..out.indices.len() {
                            values.extend(
                                g.props
                                    .iter()
                                    .map(|&k| el.props[k].ty.attribute_value(vals[k])),
                            );
                        }
                    }
                }
                for (g, values) in groups.into_iter().zip(attr_values) {
                    face_attributes.push(attribute(path, el, &g, values)?);
                }
            }
            // A binary element without properties takes no bytes: nothing to read (and
            // its count, which nothing bounds, must not be looped over).
            _ if format != Encoding::Ascii && el.props.is_empty() => {}
            _ => {
                for i in 0..el.count {
                    reader.start_instance(el, i)?;
                    for p in &el.props {
                        match p.list {
                            Some(_) => reader.skip_list(el, i, p)?,
                            None => {
                                reader.scalar(el, i, p, p.ty)?;
                            }
                        }
                    }
                    reader.end_instance(el, i)?;
                }
            }
        }
    }
    // Triangles read after a face element's (another element's) read its attributes
    // as zero.
    let triangles = out.indices.len();
    for a in face_attributes {
        let mut values = a.values().to_vec();
        values.resize(triangles * a.channels(), 0.0);
        let a = MeshAttribute::new(a.name(), a.channels(), values)
            .map_err(|e| MeshFileError::new(path, None, None, e.to_string()))?;
        // A second `face` element's attribute of the same name is not read.
        let _ = out.attributes.insert(a);
    }
    Ok(out)
}

/// The triangles of one strip `s0 s1 s2 s3 ...`: (s0 s1 s2), (s2 s1 s3), (s2 s3 s4), ...
/// (every second one reversed so that all keep the first one's winding); triangles that
/// repeat a vertex join strips and are dropped.
fn strip_triangles(strip: &[u32], out: &mut Vec<[u32; 3]>) {
    for (k, w) in strip.windows(3).enumerate() {
        let t = if k % 2 == 0 {
            [w[0], w[1], w[2]]
        } else {
            [w[1], w[0], w[2]]
        };
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            out.push(t);
        }
    }
}

/// Returns the format, the elements, the offset of the body and the header's line count.
fn parse_header(
    bytes: &[u8],
    path: &Path,
) -> Result<(Encoding, Vec<Element>, usize, usize), MeshFileError> {
    let err = |line: usize, field: Option<&str>, msg: String| {
        MeshFileError::new(path, Some(line), field.map(str::to_string), msg)
    };
    let mut pos = 0;
    let mut line = 0;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some(len) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            return Err(err(
                line + 1,
                Some("header"),
                "the file ends before end_header".into(),
            ));
        };
        line += 1;
        let text = String::from_utf8_lossy(&bytes[pos..pos + len]);
        let text = text.trim_end_matches('\r');
        pos += len + 1;
        let tok: Vec<&str> = text.split_whitespace().collect();
        if line == 1 {
            if text.trim() != "ply" {
                return Err(err(
                    1,
                    None,
                    "not a PLY file (the first line must be 'ply')".into(),
                ));
            }
            continue;
        }
        match tok.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("format") => {
                format = Some(match tok.get(1).copied() {
                    Some("ascii") => Encoding::Ascii,
                    Some("binary_little_endian") => Encoding::Little,
                    Some("binary_big_endian") => Encoding::Big,
                    other => {
                        return Err(err(
                            line,
                            Some("format"),
                            format!("unknown format {:?}", other.unwrap_or("")),
                        ))
                    }
                });
            }
            Some("element") => {
                let (Some(name), Some(count)) = (tok.get(1), tok.get(2)) else {
                    return Err(err(
                        line,
                        Some("element"),
                        "expected 'element NAME COUNT'".into(),
                    ));
                };
                let count: usize = count.parse().map_err(|_| {
                    err(
                        line,
                        Some(&format!("element {name}")),
                        format!("'{count}' is not a count"),
                    )
                })?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                    line,
                });
            }
            Some("property") => {
                let Some(el) = elements.last_mut() else {
                    return Err(err(
                        line,
                        Some("property"),
                        "a property before any element".into(),
                    ));
                };
                let bad_type = |t: &str| err(line, Some("property"), format!("unknown type '{t}'"));
                let prop = if tok.get(1) == Some(&"list") {
                    let (Some(ct), Some(ty), Some(name)) = (tok.get(2), tok.get(3), tok.get(4))
                    else {
                        return Err(err(
                            line,
                            Some("property"),
                            "expected 'property list COUNT_TYPE TYPE NAME'".into(),
                        ));
                    };
                    let c = Scalar::parse(ct).ok_or_else(|| bad_type(ct))?;
                    if !c.is_integer() {
                        return Err(err(
                            line,
                            Some("property"),
                            format!("list count type '{ct}' is not an integer type"),
                        ));
                    }
                    Property {
                        name: name.to_string(),
                        list: Some(c),
                        ty: Scalar::parse(ty).ok_or_else(|| bad_type(ty))?,
                    }
                } else {
                    let (Some(ty), Some(name)) = (tok.get(1), tok.get(2)) else {
                        return Err(err(
                            line,
                            Some("property"),
                            "expected 'property TYPE NAME'".into(),
                        ));
                    };
                    Property {
                        name: name.to_string(),
                        list: None,
                        ty: Scalar::parse(ty).ok_or_else(|| bad_type(ty))?,
                    }
                };
                el.props.push(prop);
            }
            Some("end_header") => break,
            Some(other) => {
                return Err(err(
                    line,
                    Some("header"),
                    format!("unknown header keyword '{other}'"),
                ))
            }
        }
    }
    let Some(format) = format else {
        return Err(err(
            line,
            Some("format"),
            "the header has no format line".into(),
        ));
    };
    Ok((format, elements, pos, line))
}

/// Reads values from the body in either encoding.
struct Reader<'a> {
    path: &'a Path,
    format: Encoding,
    bytes: &'a [u8],
    pos: usize,
    /// Current line (ASCII).
    line: usize,
    tokens: Vec<&'a str>,
    token_pos: usize,
}

impl<'a> Reader<'a> {
    fn error(&self, el: &Element, i: usize, field: &str, msg: String) -> MeshFileError {
        let line = (self.format == Encoding::Ascii).then_some(self.line);
        MeshFileError::new(
            self.path,
            line,
            Some(format!("{} {i}: {field}", el.name)),
            msg,
        )
    }

    fn ends_early(&self, el: &Element, i: usize, field: &str) -> MeshFileError {
        self.error(
            el,
            i,
            field,
            format!(
                "the file ends early: the header declares {} {} elements",
                el.count, el.name
            ),
        )
    }

    fn start_instance(&mut self, el: &Element, i: usize) -> Result<(), MeshFileError> {
        if self.format != Encoding::Ascii {
            return Ok(());
        }
        // One instance per line; blank lines are skipped.
        loop {
            if self.pos >= self.bytes.len() {
                return Err(self.ends_early(el, i, "line"));
            }
            let end = self.bytes[self.pos..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(self.bytes.len(), |p| self.pos + p);
            self.line += 1;
            let text = std::str::from_utf8(&self.bytes[self.pos..end])
                .map_err(|_| self.error(el, i, "line", "not text".into()))?;
            self.pos = (end + 1).min(self.bytes.len());
            self.tokens = text.split_whitespace().collect();
            self.token_pos = 0;
            if !self.tokens.is_empty() {
                return Ok(());
            }
        }
    }

    fn end_instance(&mut self, el: &Element, i: usize) -> Result<(), MeshFileError> {
        if self.format == Encoding::Ascii && self.token_pos < self.tokens.len() {
            return Err(self.error(
                el,
                i,
                "line",
                format!(
                    "{} values more than the header's properties",
                    self.tokens.len() - self.token_pos
                ),
            ));
        }
        Ok(())
    }

    fn scalar(
        &mut self,
        el: &Element,
        i: usize,
        p: &Property,
        ty: Scalar,
    ) -> Result<f64, MeshFileError> {
        match self.format {
            Encoding::Ascii => {
                let Some(tok) = self.tokens.get(self.token_pos).copied() else {
                    return Err(self.error(el, i, &p.name, "missing value".into()));
                };
                self.token_pos += 1;
                let x: f64 = if ty.is_integer() {
                    tok.parse::<i64>().map(|x| x as f64).map_err(|_| {
                        self.error(el, i, &p.name, format!("'{tok}' is not an integer"))
                    })?
                } else {
                    tok.parse::<f64>().map_err(|_| {
                        self.error(el, i, &p.name, format!("'{tok}' is not a number"))
                    })?
                };
                Ok(x)
            }
            Encoding::Little | Encoding::Big => {
                let n = ty.size();
                if self.pos + n > self.bytes.len() {
                    return Err(self.ends_early(el, i, &p.name));
                }
                let mut b = [0u8; 8];
                b[..n].copy_from_slice(&self.bytes[self.pos..self.pos + n]);
                self.pos += n;
                if self.format == Encoding::Big {
                    b[..n].reverse();
                }
                Ok(match ty {
                    Scalar::I8 => b[0] as i8 as f64,
                    Scalar::U8 => b[0] as f64,
                    Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
                    Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
                    Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::F64 => f64::from_le_bytes(b),
                })
            }
        }
    }

    fn list_len(&mut self, el: &Element, i: usize, p: &Property) -> Result<usize, MeshFileError> {
        let ct = p.list.expect("list property");
        let n = self.scalar(el, i, p, ct)?;
        if n < 0.0 || n > 1_000_000.0 {
            return Err(self.error(el, i, &p.name, format!("list length {n} is not valid")));
        }
        Ok(n as usize)
    }

    fn skip_list(&mut self, el: &Element, i: usize, p: &Property) -> Result<(), MeshFileError> {
        let n = self.list_len(el, i, p)?;
        for _ in 0..n {
            self.scalar(el, i, p, p.ty)?;
        }
        Ok(())
    }
}
