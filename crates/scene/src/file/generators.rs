//! `type = "generator"`: a triangle mesh made by one of the lecture's benchmark
//! applications (crates/geometry/src/generators), so that every command that reads a
//! scene (`irradia render`, `irradia parallel --workload`, radiosity) can use them:
//!
//! - `generator = "random-triangles"`: `count`, `seed`, `size` (area distribution:
//!   `{ distribution = "constant", area }`, `"uniform"` with `min`/`max`,
//!   `"exponential"` with `mean`, `"lognormal"` with `median`/`sigma`), `bounds`
//!   (`{ min, max }` box of the triangle centres, default [-1, 1]³) and `facing`
//!   (one normal for every triangle; default random);
//! - `generator = "teapot"`: the Utah teapot's 32 patches tessellated at `level`;
//! - `generator = "gyroid"`: the gyroid by marching cubes on a `grid`³ lattice;
//! - `generator = "metaballs"`: `count` random balls (`seed`) or explicit `balls =
//!   [{ center, radius }]`, meshed on a `grid`³ lattice;
//! - `generator = "volume"`: the isosurface `iso` of a scalar volume from `path`: an NRRD
//!   file (`.nrrd`/`.nhdr`) or a raw file with `dims`, `voxel` (u8 ... f64), `endian`,
//!   `header_bytes` and `spacing`.
//!
//! Every number is checked against a limit that keeps memory bounded, and errors name
//! the file, line and field.

use super::reader::{unknown_name_message, Result, Table, Val};
use glam::{UVec3, Vec3};
use irradia_core::Aabb;
use irradia_geometry::generators::metaballs::{metaballs_mesh, random_balls, Ball};
use irradia_geometry::generators::random_triangles::{
    random_triangles, RandomTriangles, SizeDistribution,
};
use irradia_geometry::generators::{gyroid_mesh, volume_mesh, MeshData, ScalarGrid};
use irradia_geometry::io::volume::{read_nrrd, read_raw, Endian, RawSpec, VoxelType};
use irradia_geometry::shapes::bezier::{teapot_patches, tessellate};
use irradia_geometry::TriangleMesh;

/// The generators `generator = "..."` accepts.
pub const GENERATORS: &[&str] = &[
    "random-triangles",
    "teapot",
    "gyroid",
    "metaballs",
    "volume",
];

/// Most random triangles one object may ask for.
const MAX_RANDOM: u32 = 20_000_000;
/// Largest marching-cubes lattice side.
const MAX_GRID: u32 = 512;

/// Reads the generator object's fields and builds its mesh.
pub fn read_generator(t: &Table) -> Result<TriangleMesh> {
    let g_v = t.req("generator")?;
    let name = g_v.str()?;
    let mesh = match name {
        "random-triangles" => random(t)?,
        "teapot" => {
            let level = bounded(t.get("level"), 8, 1, 256)?;
            let p = tessellate(&teapot_patches(), level);
            return TriangleMesh::new(p.positions, p.indices, Some(p.normals), Some(p.uvs))
                .map_err(|e| g_v.err(format!("teapot: {e}")));
        }
        "gyroid" => gyroid_mesh(bounded(t.get("grid"), 64, 4, MAX_GRID)?),
        "metaballs" => metaballs(t)?,
        "volume" => volume(t)?,
        _ => {
            return Err(g_v.err(unknown_name_message("generator", name, GENERATORS)));
        }
    };
    let what = if name == "volume" { "iso" } else { "generator" };
    let at = t.get(what).unwrap_or(g_v);
    TriangleMesh::new(mesh.positions, mesh.indices, None, None)
        .map_err(|e| at.err(format!("the {name} generator made no usable mesh: {e}")))
}

/// An optional whole number in `lo..=hi`, `default` when absent.
fn bounded(v: Option<Val>, default: u32, lo: u32, hi: u32) -> Result<u32> {
    match v {
        None => Ok(default),
        Some(v) => {
            let n = v.u32()?;
            if !(lo..=hi).contains(&n) {
                return Err(v.err(format!("must be between {lo} and {hi} (got {n})")));
            }
            Ok(n)
        }
    }
}

fn seed(t: &Table) -> Result<u64> {
    Ok(t.get("seed").map(|s| s.u32()).transpose()?.unwrap_or(1) as u64)
}

fn random(t: &Table) -> Result<MeshData> {
    let count = bounded(t.get("count"), 1000, 1, MAX_RANDOM)? as usize;
    let area = match t.get("size") {
        None => SizeDistribution::Constant(0.002),
        Some(v) => size(&v)?,
    };
    let mut spec = RandomTriangles::new(count, area, seed(t)?);
    if let Some(b) = t.get("bounds") {
        spec.bounds = bounds_box(&b)?;
    }
    if let Some(f) = t.get("facing") {
        spec.facing = Some(f.direction()?);
    }
    Ok(random_triangles(&spec))
}

/// `{ distribution = "constant", area = 0.002 }` and the other distributions.
fn size(v: &Val) -> Result<SizeDistribution> {
    let s = v.table()?;
    let d_v = s.req("distribution")?;
    let d = d_v.choice(&["constant", "uniform", "exponential", "lognormal"])?;
    let out = match d {
        "constant" => SizeDistribution::Constant(s.req("area")?.positive()?),
        "uniform" => {
            let min = s.req("min")?.positive()?;
            let max_v = s.req("max")?;
            let max = max_v.positive()?;
            if max < min {
                return Err(max_v.err(format!("must be at least min ({min})")));
            }
            SizeDistribution::Uniform { min, max }
        }
        "exponential" => SizeDistribution::Exponential {
            mean: s.req("mean")?.positive()?,
        },
        _ => SizeDistribution::LogNormal {
            median: s.req("median")?.positive()?,
            sigma: s.req("sigma")?.in_range(0.0, 5.0)?,
        },
    };
    s.finish()?;
    Ok(out)
}

fn bounds_box(v: &Val) -> Result<Aabb> {
    let t = v.table()?;
    let lo = t.req("min")?.vec3()?;
    let hi_v = t.req("max")?;
    let hi = hi_v.vec3()?;
    t.finish()?;
    if lo.cmpgt(hi).any() {
        return Err(hi_v.err(format!(
            "no coordinate of max may be below min (min {lo}, max {hi})"
        )));
    }
    Ok(Aabb::new(lo, hi))
}

fn metaballs(t: &Table) -> Result<MeshData> {
    let grid = bounded(t.get("grid"), 64, 4, MAX_GRID)?;
    let balls = match (t.get("balls"), t.get("count")) {
        (Some(_), Some(c)) => return Err(c.err("give either balls or count, not both")),
        (Some(b), None) => {
            let mut balls = Vec::new();
            for item in b.array()? {
                let bt = item.table()?;
                balls.push(Ball {
                    center: bt.req("center")?.vec3()?,
                    radius: bt.req("radius")?.positive()?,
                });
                bt.finish()?;
            }
            if balls.is_empty() || balls.len() > 1000 {
                return Err(b.err(format!("expected 1 to 1000 balls (got {})", balls.len())));
            }
            let _ = t.get("seed").map(|s| s.u32()).transpose()?;
            balls
        }
        (None, c) => {
            let count = bounded(c, 8, 1, 1000)? as usize;
            random_balls(count, seed(t)?)
        }
    };
    Ok(metaballs_mesh(&balls, grid))
}

fn volume(t: &Table) -> Result<MeshData> {
    let iso_v = t.req("iso")?;
    let iso = iso_v.f32()?;
    let grid = read_volume(t)?;
    Ok(volume_mesh(&grid, iso))
}

/// The scalar volume of `path` (relative to the scene file): an NRRD file
/// (`.nrrd`/`.nhdr`, which describes itself), Mitsuba's grid volume (`.vol`, likewise)
/// or a raw one described by `dims`, `voxel`,
/// `endian`, `header_bytes` and `spacing`. Shared by the `volume` generator and the
/// `sdfgrid` shape.
pub(super) fn read_volume(t: &Table) -> Result<ScalarGrid> {
    let path_v = t.req("path")?;
    let path = path_v.doc.resolve(path_v.str()?);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let nrrd = ext == "nrrd" || ext == "nhdr";
    let mitsuba = ext == "vol";
    let raw_fields = ["dims", "voxel", "endian", "header_bytes", "spacing"];
    let grid = if nrrd || mitsuba {
        if let Some((k, v)) = raw_fields.iter().find_map(|k| t.get(k).map(|v| (k, v))) {
            let what = if nrrd {
                "an NRRD file"
            } else {
                "a Mitsuba .vol file"
            };
            return Err(v.err(format!(
                "{k} belongs to raw volumes; {what} describes itself"
            )));
        }
        if nrrd {
            read_nrrd(&path)
        } else {
            irradia_geometry::io::volume::read_mitsuba_vol(&path)
        }
    } else {
        let d_v = t.req("dims")?;
        let d = d_v.array()?;
        if d.len() != 3 {
            return Err(d_v.err("expected [nx, ny, nz]"));
        }
        let dims = UVec3::new(d[0].count()?, d[1].count()?, d[2].count()?);
        if dims.min_element() < 2 || dims.max_element() > 4096 {
            return Err(d_v.err(format!("each size must be 2 to 4096 (got {dims})")));
        }
        let vox_v = t.req("voxel")?;
        let voxel = VoxelType::parse(vox_v.str()?)
            .ok_or_else(|| vox_v.err("expected u8, i8, u16, i16, u32, i32, f32 or f64"))?;
        let mut spec = RawSpec::new(dims, voxel);
        if let Some(e) = t.get("endian") {
            spec.endian = match e.choice(&["little", "big"])? {
                "little" => Endian::Little,
                _ => Endian::Big,
            };
        }
        if let Some(h) = t.get("header_bytes") {
            spec.header_bytes = h.u32()? as usize;
        }
        if let Some(s) = t.get("spacing") {
            let v = s.vec3()?;
            if !(v.cmpgt(Vec3::ZERO).all() && v.is_finite()) {
                return Err(s.err("every spacing must be positive"));
            }
            spec.spacing = v;
        }
        read_raw(&path, &spec)
    };
    grid.map_err(|e| path_v.err(format!("cannot read the volume: {e}")))
}
