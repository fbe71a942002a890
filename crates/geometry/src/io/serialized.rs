//! Mitsuba's `.serialized` meshes: a file of zlib-compressed shapes, each with a
//! header (format 0x041C, version 3 or 4), flags, an optional name (version 4),
//! vertex and triangle counts, then positions, normals, texture coordinates and
//! colours in single or double precision, and 32- or 64-bit indices; an offset table
//! and the shape count close the file. Counts are checked against the decompressed
//! data before anything is allocated for them.

use super::{read_file, MeshFile, MeshFileError};
use flate2::read::ZlibDecoder;
use glam::{Vec2, Vec3};
use std::io::Read;
use std::path::Path;

const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const SINGLE: u32 = 0x1000;
const DOUBLE: u32 = 0x2000;

/// The shape at `index` of the file at `path`.
pub fn read_serialized(path: &Path, index: usize) -> Result<MeshFile, MeshFileError> {
    let bytes = read_file(path)?;
    parse_serialized(&bytes, index).map_err(|m| MeshFileError::new(path, None, None, m))
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(b.get(at..at + 2)?.try_into().ok()?))
}
fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
}
fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

/// Parses a whole `.serialized` file held in memory.
pub fn parse_serialized(b: &[u8], index: usize) -> Result<MeshFile, String> {
    let short = || "the file ends early".to_string();
    if b.len() < 8 {
        return Err(short());
    }
    let count = u32_at(b, b.len() - 4).ok_or_else(short)? as usize;
    if index >= count {
        return Err(format!(
            "shape_index {index} is out of range: the file holds {count} shape(s)"
        ));
    }
    let version = u16_at(b, 2).ok_or_else(short)?;
    if u16_at(b, 0) != Some(0x041C) {
        return Err("not a Mitsuba serialized mesh (the file does not begin with 0x041C)".into());
    }
    // The offset table: u64 per shape (version 4) or u32 (version 3).
    let wide = version >= 4;
    let entry = if wide { 8 } else { 4 };
    let table = (b.len() - 4)
        .checked_sub(entry * count)
        .ok_or_else(|| format!("the offset table of {count} shapes does not fit in the file"))?;
    let off_at = |i: usize| -> Option<usize> {
        let at = table + i * entry;
        let v = if wide {
            u64_at(b, at)?
        } else {
            u64::from(u32_at(b, at)?)
        };
        usize::try_from(v).ok()
    };
    let start = off_at(index).ok_or_else(short)?;
    let end = if index + 1 < count {
        off_at(index + 1).ok_or_else(short)?
    } else {
        table
    };
    if start + 4 > end || end > b.len() {
        return Err(format!(
            "shape {index}: its offsets ({start}..{end}) are not in the file"
        ));
    }
    if u16_at(b, start) != Some(0x041C) {
        return Err(format!("shape {index}: bad header (expected 0x041C)"));
    }
    let version = u16_at(b, start + 2).ok_or_else(short)?;
    if !(3..=4).contains(&version) {
        return Err(format!(
            "shape {index}: unsupported version {version} (3 or 4 are read)"
        ));
    }
    let mut data = Vec::new();
    ZlibDecoder::new(&b[start + 4..end])
        .take(1 << 32)
        .read_to_end(&mut data)
        .map_err(|e| format!("shape {index}: cannot decompress: {e}"))?;
    parse_shape(&data, version).map_err(|m| format!("shape {index}: {m}"))
}

struct Cursor<'a> {
    b: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&e| e <= self.b.len())
            .ok_or("the data ends early")?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    fn floats(&mut self, n: usize, double: bool) -> Result<Vec<f32>, String> {
        let size = if double { 8 } else { 4 };
        let bytes = self.take(n.checked_mul(size).ok_or("too many values")?)?;
        Ok(bytes
            .chunks_exact(size)
            .map(|c| {
                if double {
                    f64::from_le_bytes(c.try_into().unwrap()) as f32
                } else {
                    f32::from_le_bytes(c.try_into().unwrap())
                }
            })
            .collect())
    }
}

fn parse_shape(data: &[u8], version: u16) -> Result<MeshFile, String> {
    let mut c = Cursor { b: data, at: 0 };
    let flags = c.u32()?;
    let double = flags & DOUBLE != 0;
    if double == (flags & SINGLE != 0) {
        return Err("the flags give neither or both of single and double precision".into());
    }
    if version == 4 {
        // The shape's name, null-terminated.
        let rest = &data[c.at..];
        let n = rest
            .iter()
            .position(|&x| x == 0)
            .ok_or("the shape name is not terminated")?;
        c.at += n + 1;
    }
    let nv = c.u64()?;
    let nt = c.u64()?;
    let fsize: u64 = if double { 8 } else { 4 };
    let per_vertex = 3
        + if flags & HAS_NORMALS != 0 { 3 } else { 0 }
        + if flags & HAS_TEXCOORDS != 0 { 2 } else { 0 }
        + if flags & HAS_COLORS != 0 { 3 } else { 0 };
    let wide = nv > u64::from(u32::MAX);
    let need = nv
        .checked_mul(per_vertex * fsize)
        .and_then(|v| v.checked_add(nt.checked_mul(3 * if wide { 8 } else { 4 })?))
        .ok_or("the counts overflow")?;
    if need > (data.len() - c.at) as u64 {
        return Err(format!(
            "{nv} vertices and {nt} triangles need {need} bytes; the shape holds {}",
            data.len() - c.at
        ));
    }
    let (nv, nt) = (nv as usize, nt as usize);
    let vec3s = |v: Vec<f32>| -> Vec<Vec3> {
        v.chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect()
    };
    let positions = vec3s(c.floats(3 * nv, double)?);
    let normals = if flags & HAS_NORMALS != 0 {
        Some(vec3s(c.floats(3 * nv, double)?))
    } else {
        None
    };
    let uvs = if flags & HAS_TEXCOORDS != 0 {
        Some(
            c.floats(2 * nv, double)?
                .chunks_exact(2)
                .map(|p| Vec2::new(p[0], p[1]))
                .collect(),
        )
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        c.floats(3 * nv, double)?;
    }
    let mut indices = Vec::with_capacity(nt);
    for _ in 0..nt {
        let mut t = [0u32; 3];
        for k in &mut t {
            let i = if wide { c.u64()? } else { u64::from(c.u32()?) };
            *k = u32::try_from(i).map_err(|_| format!("vertex index {i} is out of range"))?;
        }
        indices.push(t);
    }
    Ok(MeshFile {
        positions,
        indices,
        normals,
        uvs,
        attributes: Default::default(),
    })
}
