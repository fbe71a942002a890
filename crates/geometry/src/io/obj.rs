//! Wavefront OBJ: `v`, `vt`, `vn` and `f` (polygons fanned into triangles; indices
//! 1-based or negative, relative to the end). Other statements (`o`, `g`, `s`,
//! `usemtl`, `mtllib`, `l`, ...) are ignored. A corner `v/vt/vn` that combines
//! attributes differently from another becomes its own vertex.

use super::{read_file, MeshFile, MeshFileError};
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::path::Path;

pub fn read_obj(path: &Path) -> Result<MeshFile, MeshFileError> {
    let bytes = read_file(path)?;
    parse_obj(&String::from_utf8_lossy(&bytes), path)
}

/// Parses OBJ text; `path` only names the file in errors.
pub fn parse_obj(text: &str, path: &Path) -> Result<MeshFile, MeshFileError> {
    let mut v: Vec<Vec3> = Vec::new();
    let mut vt: Vec<Vec2> = Vec::new();
    let mut vn: Vec<Vec3> = Vec::new();
    // Corners as (v, vt, vn) with -1 for absent.
    let mut faces: Vec<[(u32, i64, i64); 3]> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let err = |field: &str, msg: String| {
            MeshFileError::new(path, Some(line), Some(field.to_string()), msg)
        };
        let content = raw.split('#').next().unwrap_or("");
        let mut tok = content.split_whitespace();
        let Some(key) = tok.next() else { continue };
        let nums = |tok: std::str::SplitWhitespace, names: &[&str], min: usize| {
            let vals: Vec<&str> = tok.collect();
            if vals.len() < min {
                return Err(err(
                    key,
                    format!("expected {} numbers, found {}", min, vals.len()),
                ));
            }
            vals.iter()
                .take(names.len())
                .zip(names)
                .map(|(s, name)| {
                    let x: f32 = s.parse().map_err(|_| {
                        err(&format!("{key}: {name}"), format!("'{s}' is not a number"))
                    })?;
                    if !x.is_finite() {
                        return Err(err(&format!("{key}: {name}"), format!("{s} is not finite")));
                    }
                    Ok(x)
                })
                .collect::<Result<Vec<f32>, _>>()
        };
        match key {
            "v" => {
                let x = nums(tok, &["x", "y", "z"], 3)?;
                v.push(Vec3::new(x[0], x[1], x[2]));
            }
            "vn" => {
                let x = nums(tok, &["x", "y", "z"], 3)?;
                vn.push(Vec3::new(x[0], x[1], x[2]));
            }
            "vt" => {
                let x = nums(tok, &["u", "v"], 1)?;
                vt.push(Vec2::new(x[0], x.get(1).copied().unwrap_or(0.0)));
            }
            "f" => {
                let mut corners = Vec::new();
                for (k, c) in tok.enumerate() {
                    let field = format!("f: corner {}", k + 1);
                    let mut parts = c.split('/');
                    let resolve = |s: Option<&str>,
                                   count: usize,
                                   what: &str,
                                   required: bool|
                     -> Result<i64, MeshFileError> {
                        match s {
                            None | Some("") if !required => Ok(-1),
                            None | Some("") => {
                                Err(err(&field, format!("missing {what} index in '{c}'")))
                            }
                            Some(s) => {
                                let i: i64 = s.parse().map_err(|_| {
                                    err(&field, format!("'{s}' is not a {what} index"))
                                })?;
                                let resolved = if i > 0 { i - 1 } else { count as i64 + i };
                                if i == 0 || resolved < 0 || resolved >= count as i64 {
                                    return Err(err(
                                        &field,
                                        format!("{what} index {i} is out of range ({count} defined so far)"),
                                    ));
                                }
                                Ok(resolved)
                            }
                        }
                    };
                    let vi = resolve(parts.next(), v.len(), "vertex", true)?;
                    let ti = resolve(parts.next(), vt.len(), "texture", false)?;
                    let ni = resolve(parts.next(), vn.len(), "normal", false)?;
                    corners.push((vi as u32, ti, ni));
                }
                if corners.len() < 3 {
                    return Err(err(
                        "f",
                        format!("a face needs at least 3 corners, found {}", corners.len()),
                    ));
                }
                for k in 1..corners.len() - 1 {
                    faces.push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    let all_t = faces.iter().flatten().all(|c| c.1 >= 0);
    let all_n = faces.iter().flatten().all(|c| c.2 >= 0);
    let mut out = MeshFile::default();
    if !all_t && !all_n {
        out.positions = v;
        out.indices = faces.iter().map(|f| f.map(|c| c.0)).collect();
        return Ok(out);
    }
    // Unify the per-attribute indices into one index per distinct corner.
    let key = |c: &(u32, i64, i64)| {
        (
            c.0,
            if all_t { c.1 } else { -1 },
            if all_n { c.2 } else { -1 },
        )
    };
    let mut map: HashMap<(u32, i64, i64), u32> = HashMap::new();
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    for f in &faces {
        let mut tri = [0u32; 3];
        for (k, c) in f.iter().enumerate() {
            let kk = key(c);
            tri[k] = *map.entry(kk).or_insert_with(|| {
                out.positions.push(v[kk.0 as usize]);
                if all_t {
                    uvs.push(vt[kk.1 as usize]);
                }
                if all_n {
                    normals.push(vn[kk.2 as usize]);
                }
                (out.positions.len() - 1) as u32
            });
        }
        out.indices.push(tri);
    }
    out.normals = all_n.then_some(normals);
    out.uvs = all_t.then_some(uvs);
    Ok(out)
}
