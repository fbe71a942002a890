//! Scalar volumes from files, for marching-cubes isosurfaces
//! ([`crate::generators::volume_mesh`]): a raw file of voxels
//! (dimensions, voxel type and byte order given by the caller) or an NRRD file
//! (Teem's "Nearly Raw Raster Data": a text header, then raw or ASCII data, inline
//! or in a detached file).
//!
//! Sizes are checked against the data before anything large is allocated, and every
//! error names the file (and for NRRD headers the line and field).

use crate::generators::marching_cubes::ScalarGrid;
use glam::{UVec3, Vec3};
use irradia_core::Aabb;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The type of one voxel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VoxelType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    F32,
    F64,
}

impl VoxelType {
    pub fn bytes(self) -> usize {
        match self {
            VoxelType::U8 | VoxelType::I8 => 1,
            VoxelType::U16 | VoxelType::I16 => 2,
            VoxelType::U32 | VoxelType::I32 | VoxelType::F32 => 4,
            VoxelType::F64 => 8,
        }
    }

    /// Parses a type name: `u8 i8 u16 i16 u32 i32 f32 f64` or an NRRD type name
    /// (`uchar`, `unsigned short`, `int16_t`, `float`, ...).
    pub fn parse(name: &str) -> Option<VoxelType> {
        let n = name.trim().to_ascii_lowercase();
        Some(match n.as_str() {
            "u8" | "uchar" | "unsigned char" | "uint8" | "uint8_t" => VoxelType::U8,
            "i8" | "signed char" | "int8" | "int8_t" => VoxelType::I8,
            "u16" | "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => {
                VoxelType::U16
            }
            "i16" | "short" | "short int" | "signed short" | "signed short int" | "int16"
            | "int16_t" => VoxelType::I16,
            "u32" | "uint" | "unsigned int" | "uint32" | "uint32_t" => VoxelType::U32,
            "i32" | "int" | "signed int" | "int32" | "int32_t" => VoxelType::I32,
            "f32" | "float" => VoxelType::F32,
            "f64" | "double" => VoxelType::F64,
            _ => return None,
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Endian {
    Little,
    Big,
}

/// How to read a raw volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawSpec {
    /// Voxels along x, y, z (x fastest in the file).
    pub dims: UVec3,
    pub voxel: VoxelType,
    pub endian: Endian,
    /// Bytes to skip at the start (a header).
    pub header_bytes: usize,
    /// Distance between voxel centres along each axis.
    pub spacing: Vec3,
}

impl RawSpec {
    pub fn new(dims: UVec3, voxel: VoxelType) -> Self {
        Self {
            dims,
            voxel,
            endian: Endian::Little,
            header_bytes: 0,
            spacing: Vec3::ONE,
        }
    }
}

#[derive(Debug, Error, PartialEq)]
pub enum VolumeError {
    #[error("{path}: {message}")]
    Io { path: String, message: String },
    #[error("{path}: expected {expected} bytes of voxel data ({dims} voxels of {voxel_bytes} bytes after {skip} skipped), found {found}")]
    Size {
        path: String,
        expected: u64,
        found: u64,
        dims: String,
        voxel_bytes: usize,
        skip: usize,
    },
    #[error("{path}: volume dimensions {dims} are invalid: each must be at least 2 and their product at most 2^31")]
    Dims { path: String, dims: String },
    #[error("{path}:{line}: field '{field}': {message}")]
    Header {
        path: String,
        line: usize,
        field: String,
        message: String,
    },
    #[error("{path}: {message}")]
    Data { path: String, message: String },
}

fn io_err(path: &Path, e: std::io::Error) -> VolumeError {
    VolumeError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

fn check_dims(path: &str, dims: UVec3) -> Result<usize, VolumeError> {
    let n = dims.x as u64 * dims.y as u64 * dims.z as u64;
    if dims.min_element() < 2 || n > (1 << 31) {
        return Err(VolumeError::Dims {
            path: path.into(),
            dims: format!("{}x{}x{}", dims.x, dims.y, dims.z),
        });
    }
    Ok(n as usize)
}

/// Decodes `count` voxels of `voxel` type to f32.
fn decode(data: &[u8], voxel: VoxelType, endian: Endian, count: usize) -> Vec<f32> {
    let b = voxel.bytes();
    data[..count * b]
        .chunks_exact(b)
        .map(|c| {
            let mut a = [0u8; 8];
            a[..b].copy_from_slice(c);
            if endian == Endian::Big {
                a[..b].reverse();
            }
            match voxel {
                VoxelType::U8 => a[0] as f32,
                VoxelType::I8 => a[0] as i8 as f32,
                VoxelType::U16 => u16::from_le_bytes([a[0], a[1]]) as f32,
                VoxelType::I16 => i16::from_le_bytes([a[0], a[1]]) as f32,
                VoxelType::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f32,
                VoxelType::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f32,
                VoxelType::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]),
                VoxelType::F64 => f64::from_le_bytes(a) as f32,
            }
        })
        .collect()
}

fn grid(dims: UVec3, spacing: Vec3, origin: Vec3, values: Vec<f32>) -> ScalarGrid {
    let extent = (dims - UVec3::ONE).as_vec3() * spacing;
    ScalarGrid {
        dims,
        bounds: Aabb::new(origin, origin + extent),
        values,
    }
}

/// Decodes raw voxel bytes (`path` only names the source in errors).
pub fn parse_raw(bytes: &[u8], spec: &RawSpec, path: &str) -> Result<ScalarGrid, VolumeError> {
    let n = check_dims(path, spec.dims)?;
    let expected = (n * spec.voxel.bytes()) as u64;
    let found = bytes.len().saturating_sub(spec.header_bytes) as u64;
    if found != expected {
        return Err(VolumeError::Size {
            path: path.into(),
            expected,
            found,
            dims: format!("{}x{}x{}", spec.dims.x, spec.dims.y, spec.dims.z),
            voxel_bytes: spec.voxel.bytes(),
            skip: spec.header_bytes,
        });
    }
    let values = decode(&bytes[spec.header_bytes..], spec.voxel, spec.endian, n);
    Ok(grid(spec.dims, spec.spacing, Vec3::ZERO, values))
}

/// Reads a raw volume file.
pub fn read_raw(path: &Path, spec: &RawSpec) -> Result<ScalarGrid, VolumeError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, e))?;
    parse_raw(&bytes, spec, &path.display().to_string())
}

/// Decodes Mitsuba's binary grid volume (`.vol`, the format of its `gridvolume` and
/// `sdfgrid` plugins, documented with `gridvolume`): the bytes `VOL`, version 3, the
/// encoding (1: float32), the resolution in x, y and z, the channel count (one is read;
/// a multi-channel grid is refused), the bounding box (six float32), then the values,
/// x fastest, all little-endian. The grid spans its bounding box.
pub fn parse_mitsuba_vol(bytes: &[u8], path: &str) -> Result<ScalarGrid, VolumeError> {
    let data = |message: String| VolumeError::Data {
        path: path.into(),
        message,
    };
    if bytes.len() < 48 || &bytes[..3] != b"VOL" {
        return Err(data(
            "not a Mitsuba volume: a .vol file starts with the bytes VOL and a 48-byte header"
                .into(),
        ));
    }
    if bytes[3] != 3 {
        return Err(data(format!(
            "Mitsuba volume version {} (only version 3 is defined)",
            bytes[3]
        )));
    }
    let int =
        |at: usize| i32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let float =
        |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let encoding = int(4);
    if encoding != 1 {
        return Err(data(format!(
            "Mitsuba volume encoding {encoding}: only 1 (float32) is read"
        )));
    }
    let res = [int(8), int(12), int(16)];
    if res.iter().any(|&r| r < 2) {
        return Err(VolumeError::Dims {
            path: path.into(),
            dims: format!("{}x{}x{}", res[0], res[1], res[2]),
        });
    }
    let dims = UVec3::new(res[0] as u32, res[1] as u32, res[2] as u32);
    let channels = int(20);
    if channels != 1 {
        return Err(data(format!(
            "{channels} channels: a signed distance grid has one"
        )));
    }
    let n = check_dims(path, dims)?;
    let (lo, hi) = (
        Vec3::new(float(24), float(28), float(32)),
        Vec3::new(float(36), float(40), float(44)),
    );
    let expected = (n * 4) as u64;
    let found = (bytes.len() - 48) as u64;
    if found != expected {
        return Err(VolumeError::Size {
            path: path.into(),
            expected,
            found,
            dims: format!("{}x{}x{}", dims.x, dims.y, dims.z),
            voxel_bytes: 4,
            skip: 48,
        });
    }
    let values = decode(&bytes[48..], VoxelType::F32, Endian::Little, n);
    // Some files (Mitsuba's own torus_sdfgrid.vol) hold integers where the box's
    // floats belong: a box that is not a sane float box is the unit cube.
    let bounds = if lo.is_finite() && hi.is_finite() && (hi - lo).min_element() > 1e-20 {
        Aabb::new(lo, hi)
    } else {
        Aabb::new(Vec3::ZERO, Vec3::ONE)
    };
    Ok(ScalarGrid {
        dims,
        bounds,
        values,
    })
}

/// Reads Mitsuba's binary grid volume ([`parse_mitsuba_vol`]).
pub fn read_mitsuba_vol(path: &Path) -> Result<ScalarGrid, VolumeError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, e))?;
    parse_mitsuba_vol(&bytes, &path.display().to_string())
}

/// Reads an NRRD file (header and inline data, or a header naming a detached data
/// file relative to the header's folder). Supported: 3 dimensions, the integer and
/// float types of [`VoxelType`], encodings `raw` and `ascii`, `byte skip`,
/// `spacings` or `space directions` (their lengths) and `space origin`.
pub fn read_nrrd(path: &Path) -> Result<ScalarGrid, VolumeError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, e))?;
    parse_nrrd(&bytes, path)
}

/// Parses NRRD bytes; `path` names the source in errors and locates detached data.
pub fn parse_nrrd(bytes: &[u8], path: &Path) -> Result<ScalarGrid, VolumeError> {
    let p = path.display().to_string();
    let header_err = |line: usize, field: &str, message: String| VolumeError::Header {
        path: p.clone(),
        line,
        field: field.into(),
        message,
    };
    // The header ends at the first empty line (or at the end for a detached header).
    let mut pos = 0;
    let mut lines = Vec::new();
    let mut data_start = bytes.len();
    while pos < bytes.len() {
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map(|i| pos + i)
            .unwrap_or(bytes.len());
        let line = String::from_utf8_lossy(&bytes[pos..end])
            .trim_end_matches('\r')
            .to_string();
        pos = (end + 1).min(bytes.len());
        if line.is_empty() {
            data_start = pos;
            break;
        }
        lines.push(line);
    }
    match lines.first() {
        Some(m) if m.starts_with("NRRD000") && m.len() == 8 => {}
        _ => {
            return Err(header_err(
                1,
                "magic",
                "not an NRRD file: the first line must be NRRD0001 .. NRRD0005".into(),
            ))
        }
    }
    let mut voxel = None;
    let mut dimension = None;
    let mut sizes: Option<Vec<u32>> = None;
    let mut encoding = None;
    let mut endian = None;
    let mut spacing = Vec3::ONE;
    let mut origin = Vec3::ZERO;
    let mut data_file: Option<PathBuf> = None;
    let mut byte_skip: i64 = 0;
    let mut line_skip: usize = 0;
    let floats = |n: usize, line: usize, field: &str, v: &str| -> Result<Vec<f32>, VolumeError> {
        let cleaned = v.replace(['(', ')', ','], " ");
        let xs: Result<Vec<f32>, _> = cleaned
            .split_whitespace()
            .map(|s| s.parse::<f32>())
            .collect();
        match xs {
            Ok(xs) if xs.len() == n => Ok(xs),
            _ => Err(header_err(
                line,
                field,
                format!("expected {n} numbers, found '{v}'"),
            )),
        }
    };
    for (k, l) in lines.iter().enumerate().skip(1) {
        let line = k + 1;
        if l.starts_with('#') || l.contains(":=") {
            continue; // comments and key/value pairs
        }
        let Some((field, value)) = l.split_once(':') else {
            return Err(header_err(line, l, "expected 'field: value'".into()));
        };
        let field = field.trim().to_ascii_lowercase();
        let value = value.trim();
        match field.as_str() {
            "type" => {
                voxel = Some(VoxelType::parse(value).ok_or_else(|| header_err(line, "type", format!("unsupported type '{value}' (use 8/16/32-bit integers, float or double)")))?)
            }
            "dimension" => {
                let d: u32 = value.parse().map_err(|_| header_err(line, "dimension", format!("not a number: '{value}'")))?;
                if d != 3 {
                    return Err(header_err(line, "dimension", format!("only 3-dimensional volumes are supported, not {d}")));
                }
                dimension = Some(d);
            }
            "sizes" => {
                let s: Result<Vec<u32>, _> = value.split_whitespace().map(str::parse).collect();
                match s {
                    Ok(s) if s.len() == 3 => sizes = Some(s),
                    _ => return Err(header_err(line, "sizes", format!("expected 3 positive integers, found '{value}'"))),
                }
            }
            "encoding" => {
                encoding = Some(match value.to_ascii_lowercase().as_str() {
                    "raw" => "raw",
                    "ascii" | "text" | "txt" => "ascii",
                    other => {
                        return Err(header_err(line, "encoding", format!("unsupported encoding '{other}' (use raw or ascii; decompress with e.g. `unu save -e raw`)")))
                    }
                })
            }
            "endian" => {
                endian = Some(match value {
                    "little" => Endian::Little,
                    "big" => Endian::Big,
                    _ => return Err(header_err(line, "endian", format!("expected little or big, found '{value}'"))),
                })
            }
            "spacings" => {
                let s = floats(3, line, "spacings", value)?;
                spacing = Vec3::new(s[0], s[1], s[2]);
            }
            "space directions" => {
                let s = floats(9, line, "space directions", value)?;
                spacing = Vec3::new(
                    Vec3::new(s[0], s[1], s[2]).length(),
                    Vec3::new(s[3], s[4], s[5]).length(),
                    Vec3::new(s[6], s[7], s[8]).length(),
                );
            }
            "space origin" => {
                let s = floats(3, line, "space origin", value)?;
                origin = Vec3::new(s[0], s[1], s[2]);
            }
            "data file" | "datafile" => {
                let dir = path.parent().unwrap_or(Path::new("."));
                data_file = Some(dir.join(value));
            }
            "byte skip" | "byteskip" => {
                byte_skip = value.parse().map_err(|_| header_err(line, "byte skip", format!("not an integer: '{value}'")))?;
                if byte_skip < -1 {
                    return Err(header_err(line, "byte skip", "must be -1 or at least 0".into()));
                }
            }
            "line skip" | "lineskip" => {
                line_skip = value.parse().map_err(|_| header_err(line, "line skip", format!("not a non-negative integer: '{value}'")))?;
            }
            // Fields that do not change the voxel values.
            _ => {}
        }
    }
    let last = lines.len();
    let voxel = voxel.ok_or_else(|| header_err(last, "type", "required field missing".into()))?;
    dimension.ok_or_else(|| header_err(last, "dimension", "required field missing".into()))?;
    let sizes = sizes.ok_or_else(|| header_err(last, "sizes", "required field missing".into()))?;
    let encoding =
        encoding.ok_or_else(|| header_err(last, "encoding", "required field missing".into()))?;
    let dims = UVec3::new(sizes[0], sizes[1], sizes[2]);
    let n = check_dims(&p, dims)?;
    let endian = match (endian, voxel.bytes(), encoding) {
        (Some(e), _, _) => e,
        (None, 1, _) | (None, _, "ascii") => Endian::Little,
        (None, _, _) => {
            return Err(header_err(
                last,
                "endian",
                "required for multi-byte raw data".into(),
            ))
        }
    };
    let (data_path, detached);
    let data: &[u8] = match &data_file {
        Some(f) => {
            detached = std::fs::read(f).map_err(|e| io_err(f, e))?;
            data_path = f.display().to_string();
            &detached
        }
        None => {
            data_path = p.clone();
            &bytes[data_start..]
        }
    };
    let mut data = data;
    for _ in 0..line_skip {
        match data.iter().position(|&b| b == b'\n') {
            Some(i) => data = &data[i + 1..],
            None => {
                return Err(VolumeError::Data {
                    path: data_path,
                    message: format!("fewer than {line_skip} lines to skip"),
                })
            }
        }
    }
    let values = if encoding == "ascii" {
        let text = String::from_utf8_lossy(data);
        let mut values = Vec::with_capacity(n);
        for (i, tok) in text
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .enumerate()
        {
            if i >= n {
                return Err(VolumeError::Data {
                    path: data_path,
                    message: format!("more than the {n} values the sizes call for"),
                });
            }
            values.push(tok.parse::<f32>().map_err(|_| VolumeError::Data {
                path: data_path.clone(),
                message: format!("value {} is not a number: '{tok}'", i + 1),
            })?);
        }
        if values.len() != n {
            return Err(VolumeError::Data {
                path: data_path,
                message: format!("found {} values, the sizes call for {n}", values.len()),
            });
        }
        values
    } else {
        let need = n * voxel.bytes();
        let skip = if byte_skip == -1 {
            data.len().saturating_sub(need)
        } else {
            byte_skip as usize
        };
        let found = data.len().saturating_sub(skip);
        if found < need || (byte_skip != -1 && found != need) {
            return Err(VolumeError::Size {
                path: data_path,
                expected: need as u64,
                found: found as u64,
                dims: format!("{}x{}x{}", dims.x, dims.y, dims.z),
                voxel_bytes: voxel.bytes(),
                skip,
            });
        }
        decode(&data[skip..], voxel, endian, n)
    };
    Ok(grid(dims, spacing, origin, values))
}

#[cfg(test)]
mod tests {
    /// A Mitsuba .vol file of `dims` with `values` (x fastest).
    fn vol(dims: [i32; 3], channels: i32, values: &[f32]) -> Vec<u8> {
        let mut b = b"VOL".to_vec();
        b.push(3);
        for v in [1, dims[0], dims[1], dims[2], channels] {
            b.extend(v.to_le_bytes());
        }
        for v in [0.0f32, 0.0, 0.0, 2.0, 1.0, 1.0] {
            b.extend(v.to_le_bytes());
        }
        for v in values {
            b.extend(v.to_le_bytes());
        }
        b
    }

    #[test]
    fn mitsuba_vol_reads_values_x_fastest_and_its_box() {
        let values: Vec<f32> = (0..12).map(|i| i as f32 - 5.5).collect();
        let g = super::parse_mitsuba_vol(&vol([3, 2, 2], 1, &values), "t.vol").unwrap();
        assert_eq!(g.dims, glam::UVec3::new(3, 2, 2));
        assert_eq!(g.values, values);
        assert_eq!(g.bounds.max, glam::Vec3::new(2.0, 1.0, 1.0));
    }

    #[test]
    fn mitsuba_vol_refuses_what_it_cannot_read() {
        let values = vec![0.0f32; 8];
        for (bytes, says) in [
            (b"NOPE".to_vec(), "not a Mitsuba volume"),
            (vol([2, 2, 2], 3, &values), "3 channels"),
            (vol([2, 2, 2], 1, &values[..7]), "2x2x2"),
            (vol([1, 2, 2], 1, &values[..4]), "1x2x2"),
        ] {
            let e = super::parse_mitsuba_vol(&bytes, "t.vol")
                .unwrap_err()
                .to_string();
            assert!(e.contains(says) && e.starts_with("t.vol"), "{e}");
        }
    }

    use super::*;
    use crate::generators::volume_mesh;

    fn nrrd(header: &str, data: &[u8]) -> Vec<u8> {
        let mut b = header.as_bytes().to_vec();
        b.extend_from_slice(b"\n");
        b.extend_from_slice(data);
        b
    }

    fn ball(n: u32) -> Vec<u8> {
        let mut out = Vec::new();
        let c = (n - 1) as f32 / 2.0;
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let d = Vec3::new(x as f32 - c, y as f32 - c, z as f32 - c).length();
                    out.extend_from_slice(&((d * 100.0) as u16).to_be_bytes());
                }
            }
        }
        out
    }

    #[test]
    fn nrrd_big_endian_u16_ball_meshes_to_a_sphere() {
        let n = 12;
        let header = format!("NRRD0004\n# a ball\ntype: unsigned short\ndimension: 3\nsizes: {n} {n} {n}\nendian: big\nencoding: raw\nspacings: 0.5 0.5 0.5\nspace origin: (1, 2, 3)\nunits:=mm\n");
        let g = parse_nrrd(&nrrd(&header, &ball(n)), Path::new("ball.nrrd")).unwrap();
        assert_eq!(g.dims, UVec3::splat(n));
        assert_eq!(g.bounds.min, Vec3::new(1.0, 2.0, 3.0));
        assert!((g.bounds.max - Vec3::new(6.5, 7.5, 8.5)).length() < 1e-6);
        let m = volume_mesh(&g, 400.0); // radius 4 voxels = 2 units
        assert!(m.indices.len() > 100);
        let centre = g.bounds.min + 0.5 * (g.bounds.max - g.bounds.min);
        for p in &m.positions {
            assert!(((*p - centre).length() - 2.0).abs() < 0.1, "{p}");
        }
        // The same voxels as a raw file.
        let mut spec = RawSpec::new(UVec3::splat(n), VoxelType::U16);
        spec.endian = Endian::Big;
        let raw = parse_raw(&ball(n), &spec, "ball.raw").unwrap();
        assert_eq!(raw.values, g.values);
    }

    #[test]
    fn nrrd_ascii_and_detached() {
        let dir = tempdir();
        let values: Vec<String> = (0..8).map(|i| format!("{}", i as f32 * 0.5)).collect();
        std::fs::write(dir.join("v.txt"), values.join(" ")).unwrap();
        let header = "NRRD0005\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\ndata file: v.txt\n";
        std::fs::write(dir.join("v.nhdr"), header).unwrap();
        let g = read_nrrd(&dir.join("v.nhdr")).unwrap();
        assert_eq!(g.values, (0..8).map(|i| i as f32 * 0.5).collect::<Vec<_>>());
    }

    fn tempdir() -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "irradia-volume-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn header_error(text: &str) -> (usize, String, String) {
        match parse_nrrd(&nrrd(text, &[0; 8]), Path::new("bad.nrrd")) {
            Err(VolumeError::Header {
                path,
                line,
                field,
                message,
            }) => {
                assert_eq!(path, "bad.nrrd");
                (line, field, message)
            }
            other => panic!("expected a header error for {text:?}, got {other:?}"),
        }
    }

    #[test]
    fn nrrd_header_errors_name_line_and_field() {
        assert_eq!(header_error("P5 not nrrd\n").1, "magic");
        let (line, field, msg) = header_error("NRRD0004\ntype: quaternion\n");
        assert_eq!((line, field.as_str()), (2, "type"));
        assert!(msg.contains("quaternion"));
        let (line, field, _) = header_error("NRRD0004\ntype: uchar\ndimension: 2\n");
        assert_eq!((line, field.as_str()), (3, "dimension"));
        let (line, field, _) = header_error("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2\n");
        assert_eq!((line, field.as_str()), (4, "sizes"));
        let (_, field, msg) =
            header_error("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\n");
        assert_eq!(field, "encoding");
        assert!(msg.contains("gzip"));
        let (_, field, _) =
            header_error("NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n");
        assert_eq!(field, "endian");
        let (_, field, _) = header_error("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n");
        assert_eq!(field, "encoding");
        let (line, _, msg) = header_error("NRRD0004\ntype: uchar\nthis line has no colon\n");
        assert_eq!(line, 3);
        assert!(msg.contains("field: value"));
        let (_, field, _) = header_error("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\nspacings: 1 nan-ish\n");
        assert_eq!(field, "spacings");
    }

    #[test]
    fn data_size_errors() {
        // Raw: too few bytes.
        let e = parse_raw(
            &[0u8; 15],
            &RawSpec::new(UVec3::new(2, 2, 2), VoxelType::U16),
            "v.raw",
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                VolumeError::Size {
                    expected: 16,
                    found: 15,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().starts_with("v.raw: expected 16 bytes"));
        // Raw: a dimension of 1 cannot be meshed.
        let e = parse_raw(
            &[0u8; 4],
            &RawSpec::new(UVec3::new(4, 1, 1), VoxelType::U8),
            "v.raw",
        )
        .unwrap_err();
        assert!(matches!(e, VolumeError::Dims { .. }));
        // NRRD: inline data shorter than the sizes say.
        let text = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 3 3 3\nencoding: raw\n";
        let e = parse_nrrd(&nrrd(text, &[1; 20]), Path::new("short.nrrd")).unwrap_err();
        assert!(
            matches!(
                e,
                VolumeError::Size {
                    expected: 27,
                    found: 20,
                    ..
                }
            ),
            "{e}"
        );
        // NRRD ASCII: a bad number names its position.
        let text = "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n";
        let e = parse_nrrd(&nrrd(text, b"1 2 3 x 5 6 7 8"), Path::new("a.nrrd")).unwrap_err();
        assert_eq!(e.to_string(), "a.nrrd: value 4 is not a number: 'x'");
        // A missing detached file names that file.
        let text = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: nowhere.raw\n";
        let e = parse_nrrd(text.as_bytes(), Path::new("/tmp/h.nhdr")).unwrap_err();
        assert!(e.to_string().starts_with("/tmp/nowhere.raw:"), "{e}");
    }
}
