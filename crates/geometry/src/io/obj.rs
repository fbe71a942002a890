//! Wavefront OBJ, read by the `tobj` crate: `v` (with optional vertex colours
//! `v x y z r g b`), `vt`, `vn` and `f` (polygons fanned into triangles; indices
//! 1-based or negative, relative to the end), split into groups by `usemtl`
//! ([`ObjData::groups`]); `mtllib` files are read by `tobj` as well. A corner
//! `v/vt/vn` that combines attributes differently from another becomes its own
//! vertex. Texture coordinates are kept as written (OBJ's `vt` origin is the image's
//! bottom-left corner, Irradia's bitmap uv the top-left: the scene schema's
//! `flip_tex_coords` turns them, as Mitsuba's OBJ loader does by default).
//!
//! `tobj` reports no positions, so a first pass over the text ([`check_obj`]) finds
//! the line and column of anything malformed (a number that does not parse or is not
//! finite, a face with fewer than 3 corners, an index out of range) before `tobj`
//! reads it.

use super::{read_file, MeshFile, MeshFileError};
use crate::mesh::{MeshAttribute, MeshAttributes};
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::path::Path;

/// Marks the stand-in materials that keep `usemtl` names (never in [`ObjData::materials`]).
const PLACEHOLDER: &str = "\u{0}irradia-placeholder";

/// One `usemtl` group of an OBJ file: its faces as one mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjGroup {
    /// The `usemtl` name; `None` for faces before any `usemtl`.
    pub material: Option<String>,
    pub mesh: MeshFile,
}

/// An OBJ file's faces by material, and the materials of its `mtllib` files.
#[derive(Clone, Debug, Default)]
pub struct ObjData {
    /// In the order the materials are first used.
    pub groups: Vec<ObjGroup>,
    /// The materials its MTL files define (a `usemtl` name may be missing here).
    pub materials: Vec<tobj::Material>,
    /// The `mtllib` files named (relative to the OBJ file's folder), in order.
    pub mtllibs: Vec<String>,
}

pub fn read_obj(path: &Path) -> Result<MeshFile, MeshFileError> {
    let bytes = read_file(path)?;
    parse_obj(&String::from_utf8_lossy(&bytes), path)
}

/// Parses OBJ text into one mesh of all its faces; `path` only names the file in
/// errors (no `mtllib` is read).
pub fn parse_obj(text: &str, path: &Path) -> Result<MeshFile, MeshFileError> {
    let data = parse_obj_groups(text, path, |_| Ok((Vec::new(), HashMap::new())))?;
    Ok(merge(data.groups.into_iter().map(|g| g.mesh)))
}

/// Reads the faces of `path` that use material `group` (`Some("")`: the faces before
/// any `usemtl`), or all of them (`None`).
pub fn read_obj_group(path: &Path, group: Option<&str>) -> Result<MeshFile, MeshFileError> {
    let bytes = read_file(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let Some(name) = group else {
        return parse_obj(&text, path);
    };
    let data = parse_obj_groups(&text, path, mtl_loader(path))?;
    let names: Vec<String> = data
        .groups
        .iter()
        .map(|g| g.material.clone().unwrap_or_default())
        .collect();
    let picked: Vec<MeshFile> = data
        .groups
        .into_iter()
        .filter(|g| g.material.as_deref().unwrap_or("") == name)
        .map(|g| g.mesh)
        .collect();
    if picked.is_empty() {
        let list: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
        return Err(MeshFileError::new(
            path,
            None,
            Some("group".into()),
            format!(
                "no faces use material \"{name}\" (the groups are {})",
                list.join(", ")
            ),
        ));
    }
    Ok(merge(picked.into_iter()))
}

/// The `tobj` material loader for an OBJ file at `obj_path`: `mtllib` names relative
/// to its folder; a missing or malformed MTL file gives no materials (importers check
/// MTL files themselves, with positions).
pub fn mtl_loader(obj_path: &Path) -> impl Fn(&Path) -> tobj::MTLLoadResult {
    let dir = obj_path.parent().map(Path::to_path_buf).unwrap_or_default();
    move |name: &Path| {
        let bytes = std::fs::read(dir.join(name)).map_err(|_| tobj::LoadError::OpenFileFailed)?;
        let text = String::from_utf8_lossy(&bytes);
        tobj::load_mtl_buf(&mut text.as_bytes())
    }
}

/// Parses OBJ text into its `usemtl` groups with `tobj`, after [`check_obj`] has
/// placed any error; `mtl` loads a `mtllib` file by name.
pub fn parse_obj_groups(
    text: &str,
    path: &Path,
    mtl: impl Fn(&Path) -> tobj::MTLLoadResult,
) -> Result<ObjData, MeshFileError> {
    let mtllibs = check_obj(text, path)?;
    let opts = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // tobj keeps a `usemtl` name only when an MTL file defines it; a first, made-up
    // `mtllib` defines every name used (as placeholders, which the real MTL files read
    // after it replace), so that groups keep their names without their MTL files.
    let used: Vec<String> = text
        .lines()
        .filter_map(|l| {
            let l = l.split('#').next().unwrap_or("").trim();
            l.strip_prefix("usemtl")
                .filter(|r| r.starts_with(char::is_whitespace))
                .map(|r| r.trim().to_string())
        })
        .filter(|n| !n.is_empty())
        .collect();
    let names_lib = "\u{0}irradia-usemtl-names";
    let source = format!("mtllib {names_lib}\n{text}");
    let loader = |name: &Path| {
        if name == Path::new(names_lib) {
            let mut mats = Vec::new();
            let mut map = HashMap::new();
            for n in &used {
                if !map.contains_key(n) {
                    map.insert(n.clone(), mats.len());
                    let mut m = tobj::Material {
                        name: n.clone(),
                        ..Default::default()
                    };
                    m.unknown_param.insert(PLACEHOLDER.into(), String::new());
                    mats.push(m);
                }
            }
            return Ok((mats, map));
        }
        mtl(name)
    };
    let (models, materials) = tobj::load_obj_buf(&mut source.as_bytes(), &opts, loader)
        .map_err(|e| MeshFileError::new(path, None, None, format!("tobj: {e}")))?;
    let materials = materials.unwrap_or_default();
    let mut groups: Vec<ObjGroup> = Vec::new();
    for m in models {
        let material = m
            .mesh
            .material_id
            .and_then(|i| materials.get(i))
            .map(|mat| mat.name.clone());
        let mesh = mesh_of(&m.mesh);
        if mesh.indices.is_empty() {
            continue;
        }
        match groups.iter_mut().find(|g| g.material == material) {
            Some(g) => g.mesh = merge([std::mem::take(&mut g.mesh), mesh].into_iter()),
            None => groups.push(ObjGroup { material, mesh }),
        }
    }
    // The materials MTL files define (the last definition of a name wins, as in tobj).
    let mut defined: Vec<tobj::Material> = Vec::new();
    for m in materials {
        if m.unknown_param.contains_key(PLACEHOLDER) {
            continue;
        }
        defined.retain(|d| d.name != m.name);
        defined.push(m);
    }
    Ok(ObjData {
        groups,
        materials: defined,
        mtllibs,
    })
}

/// A `tobj` mesh (single-indexed, triangulated) as a [`MeshFile`].
fn mesh_of(m: &tobj::Mesh) -> MeshFile {
    let n = m.positions.len() / 3;
    let v3 = |a: &[f32]| -> Vec<Vec3> { a.chunks_exact(3).map(Vec3::from_slice).collect() };
    let indices: Vec<[u32; 3]> = m
        .indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    MeshFile {
        positions: v3(&m.positions),
        indices,
        normals: (m.normals.len() == 3 * n && n > 0).then(|| v3(&m.normals)),
        uvs: (m.texcoords.len() == 2 * n && n > 0).then(|| {
            m.texcoords
                .chunks_exact(2)
                .map(|t| Vec2::new(t[0], t[1]))
                .collect()
        }),
        attributes: {
            let mut a = MeshAttributes::default();
            if m.vertex_color.len() == 3 * n && n > 0 {
                // `v x y z r g b`: linear RGB, one row per vertex (tobj's vertex order).
                if let Ok(c) = MeshAttribute::new("vertex_color", 3, m.vertex_color.clone()) {
                    let _ = a.insert(c);
                }
            }
            a
        },
    }
}

/// One mesh of several (indices offset; an attribute kept only when every part has it).
pub fn merge(parts: impl Iterator<Item = MeshFile>) -> MeshFile {
    let parts: Vec<MeshFile> = parts.collect();
    if parts.len() <= 1 {
        return parts.into_iter().next().unwrap_or_default();
    }
    let all_n = parts.iter().all(|p| p.normals.is_some());
    let all_t = parts.iter().all(|p| p.uvs.is_some());
    // Attributes every part has, with the same channels: concatenated in part order
    // (vertex rows follow the vertices, face rows the triangles).
    let shared: Vec<(String, usize)> = parts[0]
        .attributes
        .iter()
        .filter(|a| {
            parts[1..].iter().all(|p| {
                p.attributes
                    .get(a.name())
                    .is_some_and(|b| b.channels() == a.channels())
            })
        })
        .map(|a| (a.name().to_string(), a.channels()))
        .collect();
    let mut attr_values: Vec<Vec<f32>> = vec![Vec::new(); shared.len()];
    let mut out = MeshFile {
        normals: all_n.then(Vec::new),
        uvs: all_t.then(Vec::new),
        ..Default::default()
    };
    for p in parts {
        let base = out.positions.len() as u32;
        out.indices
            .extend(p.indices.iter().map(|t| t.map(|i| i + base)));
        out.positions.extend(p.positions);
        if let (Some(o), Some(n)) = (out.normals.as_mut(), p.normals) {
            o.extend(n);
        }
        if let (Some(o), Some(t)) = (out.uvs.as_mut(), p.uvs) {
            o.extend(t);
        }
        for ((name, _), values) in shared.iter().zip(&mut attr_values) {
            if let Some(a) = p.attributes.get(name) {
                values.extend_from_slice(a.values());
            }
        }
    }
    for ((name, channels), values) in shared.into_iter().zip(attr_values) {
        if let Ok(a) = MeshAttribute::new(name, channels, values) {
            let _ = out.attributes.insert(a);
        }
    }
    out
}

/// Checks OBJ text statement by statement: every number parses and is finite, every
/// face has 3 or more corners whose indices are in range. Returns the `mtllib` names.
pub fn check_obj(text: &str, path: &Path) -> Result<Vec<String>, MeshFileError> {
    let (mut nv, mut nt, mut nn) = (0usize, 0usize, 0usize);
    let mut mtllibs = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut tok = tokens(content);
        let Some((_, key)) = tok.next() else { continue };
        let err = |field: &str, col: usize, msg: String| {
            MeshFileError::new(path, Some(line), Some(field.to_string()), msg).at_column(col)
        };
        let nums = |tok: &mut dyn Iterator<Item = (usize, &str)>,
                    names: &[&str],
                    min: usize|
         -> Result<(), MeshFileError> {
            let vals: Vec<(usize, &str)> = tok.collect();
            if vals.len() < min {
                return Err(err(
                    key,
                    1 + raw.len() - raw.trim_start().len(),
                    format!("expected {} numbers, found {}", min, vals.len()),
                ));
            }
            for ((col, s), name) in vals.iter().zip(names) {
                let field = format!("{key}: {name}");
                let x: f32 = s
                    .parse()
                    .map_err(|_| err(&field, *col, format!("'{s}' is not a number")))?;
                if !x.is_finite() {
                    return Err(err(&field, *col, format!("{s} is not finite")));
                }
            }
            Ok(())
        };
        match key {
            "v" => {
                nums(&mut tok, &["x", "y", "z", "r", "g", "b"], 3)?;
                nv += 1;
            }
            "vn" => {
                nums(&mut tok, &["x", "y", "z"], 3)?;
                nn += 1;
            }
            "vt" => {
                nums(&mut tok, &["u", "v", "w"], 1)?;
                nt += 1;
            }
            "mtllib" => {
                let name = content.trim_start()[6..].trim();
                if !name.is_empty() {
                    mtllibs.push(name.to_string());
                }
            }
            "usemtl" if content.trim_start()[6..].trim().is_empty() => {
                return Err(err("usemtl", 1, "a material name is missing".into()));
            }
            "f" => {
                let mut count = 0;
                for (k, (col, c)) in tok.enumerate() {
                    count += 1;
                    let field = format!("f: corner {}", k + 1);
                    let mut parts = c.split('/');
                    let check = |s: Option<&str>, count: usize, what: &str, required: bool| match s
                    {
                        None | Some("") if !required => Ok(()),
                        None | Some("") => {
                            Err(err(&field, col, format!("missing {what} index in '{c}'")))
                        }
                        Some(s) => {
                            let i: i64 = s.parse().map_err(|_| {
                                err(&field, col, format!("'{s}' is not a {what} index"))
                            })?;
                            let resolved = if i > 0 { i - 1 } else { count as i64 + i };
                            if i == 0 || resolved < 0 || resolved >= count as i64 {
                                return Err(err(
                                    &field,
                                    col,
                                    format!(
                                        "{what} index {i} is out of range ({count} defined so far)"
                                    ),
                                ));
                            }
                            Ok(())
                        }
                    };
                    check(parts.next(), nv, "vertex", true)?;
                    check(parts.next(), nt, "texture", false)?;
                    check(parts.next(), nn, "normal", false)?;
                    if parts.next().is_some() {
                        return Err(err(&field, col, format!("'{c}' has more than 3 indices")));
                    }
                }
                if count < 3 {
                    return Err(err(
                        "f",
                        1 + raw.len() - raw.trim_start().len(),
                        format!("a face needs at least 3 corners, found {count}"),
                    ));
                }
            }
            _ => {}
        }
    }
    Ok(mtllibs)
}

/// The whitespace-separated words of `s` with their 1-based columns (in characters).
pub fn tokens(s: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut col = 0usize;
    let mut rest = s;
    std::iter::from_fn(move || {
        let skip = rest.len() - rest.trim_start().len();
        col += rest[..skip].chars().count();
        rest = &rest[skip..];
        if rest.is_empty() {
            return None;
        }
        let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
        let word = &rest[..end];
        let start = col + 1;
        col += word.chars().count();
        rest = &rest[end..];
        Some((start, word))
    })
}
